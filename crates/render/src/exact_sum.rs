//! Exact, order-independent sums of floating-point values: what lets a render split over
//! threads, iterations or machines add up to the same bytes in any grouping.
//!
//! Floating-point addition is not associative, so `(a + b) + c` and `a + (b + c)` may differ in
//! the last bit; a film pooled from shards would then depend on how the work was cut. An
//! [`ExactSum`] is a fixed-point number with 63 fraction bits in an `i128` (the film's
//! accumulator type): every addend is truncated once, on its own, to a multiple of 2⁻⁶³ (a
//! deterministic function of that addend alone), and the sums of those integers are exact,
//! associative and commutative (two's-complement wrapping addition is, and the total of a
//! film's pixel never comes near 2¹²⁷). So the sum of any set of addends is one number whatever
//! the order or grouping of the additions, and partial sums computed anywhere merge exactly.
//!
//! Range and resolution, in the addend's unit (radiance W/m²/sr times a sample weight, or a
//! light path's splat): addends below 2⁶³ ≈ 9.2·10¹⁸ in magnitude (larger ones saturate), sums
//! below 2⁶⁴ (beyond, they wrap), resolution 2⁻⁶³ ≈ 1.1·10⁻¹⁹ (an addend's bits below it are
//! dropped). An f32 image cannot show either limit for radiance in any physical range: a pixel
//! sum of 10¹² samples of 10⁶ W/m²/sr fits, and the truncation of 10⁹ addends moves a pixel by
//! < 10⁻¹⁰ absolute. The conversion is branch-free (two float-to-integer instructions; a
//! correctly rounded one with branches, or `f64::trunc`, which is a libm call on the x86-64
//! baseline, cost pds's splatting twice as much: docs/performance.md).

/// 2⁶³ and its inverse, the value of one unit.
const SCALE: f64 = 9_223_372_036_854_775_808.0;
const UNIT: f64 = 1.0 / SCALE;

/// A sum of floating-point addends, each truncated to a multiple of 2⁻⁶³: exact and independent
/// of the order and grouping of the additions (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ExactSum(i128);

impl ExactSum {
    pub const ZERO: Self = Self(0);

    /// The addend `v` truncated toward zero to a multiple of 2⁻⁶³ (magnitudes of 2⁶³ and more
    /// saturate to some value beyond 2⁶³; NaN is 0). A pure function of `v`'s bits, without
    /// branches or calls: the integer part and the fraction each convert with one instruction.
    #[inline]
    pub fn from_f64(v: f64) -> Self {
        // Truncation toward zero (saturating); exact back in f64 below 2⁶³.
        let whole = v as i64;
        // Exact: v minus its integer part is an f64, and scaling by 2⁶³ is exact.
        let frac = ((v - whole as f64) * SCALE) as i64;
        Self(((whole as i128) << 63) + frac as i128)
    }

    /// [`Self::from_f64`] of an f32 (exact widening first).
    #[inline]
    pub fn from_f32(v: f32) -> Self {
        Self::from_f64(v as f64)
    }

    /// Adds `v` (truncated on its own, see [`Self::from_f64`]).
    #[inline]
    pub fn add_f64(&mut self, v: f64) {
        *self += Self::from_f64(v);
    }

    /// The sum, rounded to the nearest f64.
    #[inline]
    pub fn to_f64(self) -> f64 {
        self.0 as f64 * UNIT
    }

    /// The fixed-point integer (units of 2⁻⁶³), for files.
    pub fn to_bits(self) -> i128 {
        self.0
    }

    /// The sum whose fixed-point integer is `bits` (units of 2⁻⁶³).
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

    /// The truncation by exact arithmetic: v · 2⁶³ is exact in f64 (a power-of-two scaling), and
    /// so is its integer part.
    fn reference(v: f64) -> i128 {
        (v * SCALE).trunc() as i128
    }

    #[test]
    fn truncation_matches_exact_scaling() {
        for v in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            1.5,
            1e-3,
            -7.25e5,
            3.0 * UNIT,
            2.5 * UNIT,  // → 2
            -2.5 * UNIT, // → −2
            0.99 * UNIT, // → 0
            1e15,
            -1e18,
            std::f64::consts::PI,
        ] {
            assert_eq!(ExactSum::from_f64(v).to_bits(), reference(v), "{v:e}");
        }
        let mut rng = Pcg32::new(7, 1);
        for _ in 0..100_000 {
            let e = (rng.next_f32() * 120.0) as i32 - 80;
            let v = (rng.next_f32() as f64 - 0.3) * 2f64.powi(e);
            assert_eq!(ExactSum::from_f64(v).to_bits(), reference(v), "{v:e}");
        }
    }

    #[test]
    fn limits_saturate_and_nan_is_zero() {
        assert_eq!(ExactSum::from_f64(f64::NAN), ExactSum::ZERO);
        // Saturated: beyond 2⁶³ (in value), whatever the addend.
        assert!(ExactSum::from_f64(f64::INFINITY).to_f64() >= 2f64.powi(63));
        assert!(ExactSum::from_f64(-1e30).to_f64() <= -(2f64.powi(63)));
        assert_eq!(ExactSum::from_f64(1e30), ExactSum::from_f64(f64::INFINITY));
        assert_eq!(ExactSum::from_f64(1e-300), ExactSum::ZERO);
        assert_eq!(ExactSum::from_f64(2f64.powi(61)).to_f64(), 2f64.powi(61));
        assert_eq!(ExactSum::from_f64(-0.75).to_f64(), -0.75);
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
