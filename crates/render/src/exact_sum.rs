//! Exact, order-independent sums of floating-point values: what lets a render split over
//! threads, iterations or machines add up to the same bytes in any grouping.
//!
//! Floating-point addition is not associative, so `(a + b) + c` and `a + (b + c)` may differ in
//! the last bit; a film pooled from shards would then depend on how the work was cut. An
//! [`ExactSum`] is a fixed-point number with 64 fraction bits in an `i128` (the film's
//! accumulator type): every addend is rounded once, on its own, to a multiple of 2⁻⁶⁴ (a
//! deterministic function of that addend alone), and the sums of those integers are exact,
//! associative and commutative (two's-complement wrapping addition is, and the total of a
//! film's pixel never comes near 2¹²⁷). So the sum of any set of addends is one number whatever
//! the order or grouping of the additions, and partial sums computed anywhere merge exactly.
//!
//! Range and resolution, in the addend's unit (radiance W/m²/sr times a sample weight, or a
//! light path's splat): magnitudes up to 2⁶² ≈ 4.6·10¹⁸ (larger ones saturate), resolution
//! 2⁻⁶⁴ ≈ 5.4·10⁻²⁰ (an addend below half of it counts as 0). An f32 image cannot show either
//! limit for radiance in any physical range: a pixel sum of 10¹² samples of 10⁶ W/m²/sr fits, and
//! the rounding of 10⁹ addends moves a pixel by < 10⁻¹⁰ absolute.

/// Fraction bits of the fixed point.
const FRACTION_BITS: i32 = 64;
/// Largest magnitude an addend is rounded to (2¹²⁶, i.e. 2⁶² in value): a quarter of the
/// `i128` range, so sums of a few addends at the limit do not wrap.
const MAX_ADDEND: i128 = 1 << 126;
/// 2⁻⁶⁴, the value of one unit.
const UNIT: f64 = 1.0 / 18_446_744_073_709_551_616.0;

/// A sum of floating-point addends, each rounded to a multiple of 2⁻⁶⁴: exact and independent
/// of the order and grouping of the additions (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ExactSum(i128);

impl ExactSum {
    pub const ZERO: Self = Self(0);

    /// The addend `v` rounded to the nearest multiple of 2⁻⁶⁴ (ties away from zero), saturating
    /// at ±2⁶²; NaN is 0. A pure function of `v`'s bits.
    #[inline]
    pub fn from_f64(v: f64) -> Self {
        let bits = v.to_bits();
        let exp = ((bits >> 52) & 0x7ff) as i32;
        if exp == 0 {
            // Zero and subnormals (< 2⁻¹⁰²², far below the resolution).
            return Self::ZERO;
        }
        let negative = bits >> 63 == 1;
        let magnitude = if exp == 0x7ff {
            if bits & ((1 << 52) - 1) != 0 {
                return Self::ZERO; // NaN
            }
            MAX_ADDEND
        } else {
            // |v| = mant · 2^(exp − 1075), so |v| / 2⁻⁶⁴ = mant · 2^shift.
            let mant = ((bits & ((1 << 52) - 1)) | (1 << 52)) as i128;
            let shift = exp - 1075 + FRACTION_BITS;
            if shift >= 0 {
                if shift > 126 - 53 {
                    MAX_ADDEND
                } else {
                    (mant << shift).min(MAX_ADDEND)
                }
            } else if shift < -53 {
                0
            } else {
                // Round half away from zero: add half a unit, then drop the bits below it.
                let s = -shift;
                ((mant >> (s - 1)) + 1) >> 1
            }
        };
        Self(if negative { -magnitude } else { magnitude })
    }

    /// [`Self::from_f64`] of an f32 (exact widening first).
    #[inline]
    pub fn from_f32(v: f32) -> Self {
        Self::from_f64(v as f64)
    }

    /// Adds `v` (rounded on its own, see [`Self::from_f64`]).
    #[inline]
    pub fn add_f64(&mut self, v: f64) {
        *self += Self::from_f64(v);
    }

    /// The sum, rounded to the nearest f64.
    #[inline]
    pub fn to_f64(self) -> f64 {
        self.0 as f64 * UNIT
    }

    /// The fixed-point integer (units of 2⁻⁶⁴), for files.
    pub fn to_bits(self) -> i128 {
        self.0
    }

    /// The sum whose fixed-point integer is `bits` (units of 2⁻⁶⁴).
    pub fn from_bits(bits: i128) -> Self {
        Self(bits)
    }
}

impl std::ops::AddAssign for ExactSum {
    /// Exact: two's-complement addition is associative and commutative.
    #[inline]
    fn add_assign(&mut self, o: Self) {
        self.0 = self.0.wrapping_add(o.0);
    }
}

impl std::ops::Add for ExactSum {
    type Output = Self;
    #[inline]
    fn add(mut self, o: Self) -> Self {
        self += o;
        self
    }
}

impl std::iter::Sum for ExactSum {
    fn sum<I: Iterator<Item = Self>>(iter: I) -> Self {
        iter.fold(Self::ZERO, |a, b| a + b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::Pcg32;

    /// The rounding by exact rational arithmetic: v · 2⁶⁴ for values whose product is exact in
    /// f64 (a power-of-two scaling), rounded half away from zero.
    fn reference(v: f64) -> i128 {
        let scaled = v * 18_446_744_073_709_551_616.0; // exact: a power of two
        let r = scaled.abs().floor();
        let frac = scaled.abs() - r; // exact for |scaled| < 2⁵³ … and 0 above
        let m = r as i128 + (frac >= 0.5) as i128;
        if v < 0.0 { -m } else { m }
    }

    #[test]
    fn rounding_matches_exact_scaling() {
        for v in [
            0.0,
            1.0,
            -1.0,
            0.5,
            1.5,
            1e-3,
            -7.25e5,
            3.0 * UNIT,
            2.5 * UNIT,  // a tie: away from zero → 3
            -2.5 * UNIT, // → −3
            0.49 * UNIT, // → 0
            1e15,
            std::f64::consts::PI,
        ] {
            assert_eq!(ExactSum::from_f64(v).to_bits(), reference(v), "{v:e}");
        }
        let mut rng = Pcg32::new(7, 1);
        for _ in 0..10_000 {
            let e = (rng.next_f32() * 80.0) as i32 - 60;
            let v = (rng.next_f32() as f64 - 0.3) * 2f64.powi(e);
            assert_eq!(ExactSum::from_f64(v).to_bits(), reference(v), "{v:e}");
        }
    }

    #[test]
    fn limits_saturate_and_nan_is_zero() {
        assert_eq!(ExactSum::from_f64(f64::NAN), ExactSum::ZERO);
        assert_eq!(ExactSum::from_f64(f64::INFINITY).to_bits(), MAX_ADDEND);
        assert_eq!(ExactSum::from_f64(-1e30).to_bits(), -MAX_ADDEND);
        assert_eq!(ExactSum::from_f64(1e-300), ExactSum::ZERO);
        assert_eq!(ExactSum::from_f64(2f64.powi(61)).to_f64(), 2f64.powi(61));
    }

    #[test]
    fn sums_do_not_depend_on_order_or_grouping() {
        // Values of very different magnitudes, where f64 sums differ with the order.
        let mut rng = Pcg32::new(3, 9);
        let xs: Vec<f64> = (0..5000)
            .map(|i| (rng.next_f32() as f64 - 0.2) * 10f64.powi(i % 13 - 6))
            .collect();
        let forward: ExactSum = xs.iter().map(|&x| ExactSum::from_f64(x)).sum();
        let backward: ExactSum = xs.iter().rev().map(|&x| ExactSum::from_f64(x)).sum();
        let grouped: ExactSum = xs
            .chunks(7)
            .map(|c| c.iter().map(|&x| ExactSum::from_f64(x)).sum::<ExactSum>())
            .collect::<Vec<_>>()
            .into_iter()
            .rev()
            .sum();
        assert_eq!(forward, backward);
        assert_eq!(forward, grouped);
        // The f64 sums in those orders differ (so the test would see a non-exact accumulator).
        let f: f64 = xs.iter().sum();
        let b: f64 = xs.iter().rev().sum();
        assert_ne!(f, b);
        // And the exact sum is as accurate as the f64 one.
        assert!((forward.to_f64() - f).abs() <= 1e-9 * f.abs().max(1.0));
    }
}
