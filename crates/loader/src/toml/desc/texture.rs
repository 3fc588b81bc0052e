//! Texture-valued parameters: a colour, an image file or a checkerboard.

use crate::toml::value::{Positive, Rgb};
use caustica_core::Spectrum;
use serde::Deserialize;
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};

/// A texture-valued parameter: a colour, `{ texture = "file" }` or `{ checker = {...} }`.
#[derive(Clone, Debug)]
pub(crate) enum TexDesc {
    Constant(Spectrum),
    File(String),
    Checker(Spectrum, Spectrum, f32),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct TexTable {
    pub(crate) texture: Option<String>,
    pub(crate) checker: Option<CheckerDesc>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CheckerDesc {
    pub(crate) a: Option<Rgb>,
    pub(crate) b: Option<Rgb>,
    pub(crate) scale: Option<Positive>,
}

impl<'de> Deserialize<'de> for TexDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        fn grey<E: de::Error>(v: f64) -> Result<TexDesc, E> {
            if v.is_finite() && v >= 0.0 {
                Ok(TexDesc::Constant(Spectrum::splat(v as f32)))
            } else {
                Err(E::custom(format!(
                    "colour must be non-negative and finite, got {v}"
                )))
            }
        }
        impl<'de> Visitor<'de> for V {
            type Value = TexDesc;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str(
                    "a colour [r, g, b], { texture = \"file\" } or { checker = { a, b, scale } }",
                )
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<TexDesc, E> {
                grey(v)
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<TexDesc, E> {
                grey(v as f64)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<TexDesc, E> {
                grey(v as f64)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<TexDesc, A::Error> {
                let rgb = Rgb::deserialize(de::value::SeqAccessDeserializer::new(seq))?;
                Ok(TexDesc::Constant(rgb.0))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<TexDesc, A::Error> {
                let t = TexTable::deserialize(de::value::MapAccessDeserializer::new(map))?;
                match (t.texture, t.checker) {
                    (Some(f), None) => Ok(TexDesc::File(f)),
                    (None, Some(c)) => Ok(TexDesc::Checker(
                        c.a.map_or(Spectrum::splat(0.4), |x| x.0),
                        c.b.map_or(Spectrum::splat(0.2), |x| x.0),
                        c.scale.map_or(4.0, |x| x.0),
                    )),
                    _ => Err(de::Error::custom(
                        "a texture table needs exactly one of 'texture' or 'checker'",
                    )),
                }
            }
        }
        d.deserialize_any(V)
    }
}
