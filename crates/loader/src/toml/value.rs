//! Typed field readers: numbers, vectors, colours, counts and matrices that check their range
//! while being deserialised, so that a bad value's error carries its span.

use caustica_core::{Mat4, Spectrum, Vec3};
use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};

/// One number or an array of numbers (integers are accepted as floats).
pub(crate) struct Nums(pub(crate) Vec<f64>);

impl<'de> Deserialize<'de> for Nums {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Nums;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number or an array of numbers")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Nums, E> {
                Ok(Nums(vec![v]))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Nums, E> {
                Ok(Nums(vec![v as f64]))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Nums, E> {
                Ok(Nums(vec![v as f64]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Nums, A::Error> {
                let mut out = Vec::new();
                while let Some(v) = seq.next_element::<f64>()? {
                    out.push(v);
                }
                Ok(Nums(out))
            }
        }
        d.deserialize_any(V)
    }
}

pub(crate) fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Converts `Nums` to three finite values; `splat` allows a single number.
pub(crate) fn three<E: de::Error>(n: Nums, splat: bool, what: &str) -> Result<[f32; 3], E> {
    let v = match n.0.len() {
        3 => [n.0[0], n.0[1], n.0[2]],
        1 if splat => [n.0[0]; 3],
        k => {
            return Err(E::custom(format!(
                "expected {what} ({}3 numbers), got {k} numbers",
                if splat { "a number or " } else { "" }
            )));
        }
    };
    if !all_finite(&v) {
        return Err(E::custom(format!("{what} must be finite, got {v:?}")));
    }
    Ok(v.map(|x| x as f32))
}

/// A finite 3-vector `[x, y, z]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct V3(pub(crate) Vec3);
impl<'de> Deserialize<'de> for V3 {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        three(Nums::deserialize(d)?, false, "a vector [x, y, z]").map(|v| V3(Vec3::from(v)))
    }
}

/// A non-negative finite colour `[r, g, b]` or a single grey value.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Rgb(pub(crate) Spectrum);
impl<'de> Deserialize<'de> for Rgb {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = three(Nums::deserialize(d)?, true, "a colour [r, g, b]")?;
        if v.iter().any(|&c| c < 0.0) {
            return Err(de::Error::custom(format!(
                "colour must be non-negative, got {v:?}"
            )));
        }
        Ok(Rgb(Spectrum::from_rgb(v)))
    }
}

macro_rules! checked_float {
    ($name:ident, $ok:expr, $msg:literal) => {
        #[derive(Clone, Copy, Debug)]
        pub(crate) struct $name(pub(crate) f32);
        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let v = f64::deserialize(d)?;
                let ok: fn(f64) -> bool = $ok;
                if v.is_finite() && ok(v) {
                    Ok($name(v as f32))
                } else {
                    Err(de::Error::custom(format!(concat!($msg, ", got {}"), v)))
                }
            }
        }
    };
}
checked_float!(Finite, |_| true, "must be a finite number");
checked_float!(Positive, |v| v > 0.0, "must be positive and finite");
checked_float!(NonNeg, |v| v >= 0.0, "must be non-negative and finite");

/// An integer ≥ 1.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Count(pub(crate) u32);
impl<'de> Deserialize<'de> for Count {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = i64::deserialize(d)?;
        match u32::try_from(v) {
            Ok(n) if n >= 1 => Ok(Count(n)),
            _ => Err(de::Error::custom(format!(
                "must be an integer from 1 to {}, got {v}",
                u32::MAX
            ))),
        }
    }
}

/// A finite 4×4 matrix given as four rows.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Matrix(pub(crate) Mat4);
impl<'de> Deserialize<'de> for Matrix {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let rows = <[[f64; 4]; 4]>::deserialize(d)?;
        if !rows.iter().all(|r| all_finite(r)) {
            return Err(de::Error::custom("matrix entries must be finite"));
        }
        let r = rows.map(|r| r.map(|x| x as f32));
        Ok(Matrix(Mat4::from_cols_array_2d(&r).transpose()))
    }
}
