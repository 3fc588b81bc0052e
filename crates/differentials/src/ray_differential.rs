//! The ray differential: a ray `(P, V)` and its first-order structure with respect to `N`
//! parameters θ = (θ₀ … θ_{N−1}) (seed 000 appendix B.1).

use caustica_core::{Ray, RayDifferential, Vec3};

use crate::DiffError;

/// A ray with origin `p` (m) and **unit** direction `v` (unitless), together with the partial
/// derivatives `dp[i] = ∂P/∂θᵢ` (m per unit of θᵢ) and `dv[i] = ∂V/∂θᵢ` (per unit of θᵢ).
///
/// `dv` is the derivative of the *normalised* direction, as in eq. B.1b/B.5, so `v · dv[i] = 0`
/// up to rounding; every operation in this crate preserves that. Build a differential from an
/// unnormalised direction with [`RayDiff::from_unnormalized`].
///
/// In the notation of appendix B, the column `i` of the Jacobian `DP` is `dp[i]`; a change
/// `Δθ` of the parameters moves the ray to first order by `Σᵢ dp[i] Δθᵢ` (eq. B.3–B.4, B.9).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayDiff<const N: usize> {
    /// Origin `P` (m).
    pub p: Vec3,
    /// Unit direction `V`.
    pub v: Vec3,
    /// `∂P/∂θᵢ` (m per unit of θᵢ).
    pub dp: [Vec3; N],
    /// `∂V/∂θᵢ` of the unit direction (per unit of θᵢ).
    pub dv: [Vec3; N],
}

/// True if every value is finite, without a branch per value: `x · 0` is `±0` for finite `x`
/// and NaN for `±∞` and NaN, and a sum of `±0` is `±0`, so the sum is zero exactly when every
/// value is finite. The hot paths check whole differentials this way.
#[inline]
pub(crate) fn all_finite(xs: impl IntoIterator<Item = f32>) -> bool {
    xs.into_iter().fold(0.0, |acc, x| acc + x * 0.0) == 0.0
}

/// [`all_finite`] for vectors.
#[inline]
pub(crate) fn all_finite3<'a>(vs: impl IntoIterator<Item = &'a Vec3>) -> bool {
    vs.into_iter()
        .fold(Vec3::ZERO, |acc, v| acc + *v * 0.0)
        .cmpeq(Vec3::ZERO)
        .all()
}

/// `v / |v|`, or `None` for a zero or non-finite vector. A vector already unit to within a
/// few ulps (the sampled directions and normals a renderer passes) is returned as it is.
#[inline]
pub(crate) fn unit(v: Vec3) -> Option<Vec3> {
    let len2 = v.length_squared();
    if (len2 - 1.0).abs() <= 4.0 * f32::EPSILON {
        return Some(v);
    }
    let len = len2.sqrt();
    (len > 0.0 && len.is_finite()).then(|| v / len)
}

/// Differential of a normalisation `V = v/‖v‖` (eq. B.5b, B.7):
/// `dV = (vᵀv I₃ − v vᵀ) / (vᵀv)^{3/2} dv`. Returns `dV` for a given `dv`; `v` must be non-zero.
///
/// The same matrix is the `J` of eq. B.31b, B.33, B.40c and B.45a.
#[inline]
pub fn normalize_differential(v: Vec3, dv: Vec3) -> Vec3 {
    let len2 = v.length_squared();
    let len = len2.sqrt();
    // eq. B.5b, written as (dv − V (Vᵀ dv)) / ‖v‖ to avoid forming the matrix.
    let unit = v / len;
    (dv - unit * unit.dot(dv)) / len
}

impl<const N: usize> RayDiff<N> {
    /// A ray differential from a unit direction `v` and derivatives of the unit direction.
    #[inline]
    pub fn new(p: Vec3, v: Vec3, dp: [Vec3; N], dv: [Vec3; N]) -> Self {
        Self { p, v, dp, dv }
    }

    /// A ray without parameter dependence (all derivatives zero).
    #[inline]
    pub fn constant(p: Vec3, v: Vec3) -> Self {
        Self::new(p, v, [Vec3::ZERO; N], [Vec3::ZERO; N])
    }

    /// A ray differential from an unnormalised direction `v_raw` and its derivatives
    /// `dv_raw[i] = ∂v/∂θᵢ`: normalises the direction (eq. B.1b) and maps the derivatives
    /// through eq. B.5b. This is how a photon differential's directional derivative, given as
    /// a perturbation of an unnormalised direction, enters the algebra.
    pub fn from_unnormalized(
        p: Vec3,
        v_raw: Vec3,
        dp: [Vec3; N],
        dv_raw: [Vec3; N],
    ) -> Result<Self, DiffError> {
        let len = v_raw.length();
        if !(len > 0.0 && len.is_finite()) {
            return Err(DiffError::ZeroDirection);
        }
        let dv = std::array::from_fn(|i| normalize_differential(v_raw, dv_raw[i])); // eq. B.5b
        let r = Self::new(p, v_raw / len, dp, dv); // eq. B.1b
        r.finite_or_err()
    }

    /// The same ray with `M ≥ N` parameters: the first `N` derivatives as they are, the others
    /// zero — a parameter this ray does not depend on yet (e.g. time at the emission from a
    /// static light, before a moving surface adds its motion terms).
    ///
    /// # Panics
    /// If `M < N` (a programming error).
    pub fn widen<const M: usize>(&self) -> RayDiff<M> {
        assert!(
            M >= N,
            "cannot widen a differential of {N} parameters to {M}"
        );
        let mut dp = [Vec3::ZERO; M];
        let mut dv = [Vec3::ZERO; M];
        dp[..N].copy_from_slice(&self.dp);
        dv[..N].copy_from_slice(&self.dv);
        RayDiff {
            p: self.p,
            v: self.v,
            dp,
            dv,
        }
    }

    /// First-order estimate of the ray at parameters θ + Δθ (eq. B.3–B.4 with `dθ = Δθ`,
    /// as in eq. B.9). The direction estimate is not renormalised.
    pub fn first_order(&self, delta: [f32; N]) -> (Vec3, Vec3) {
        let mut p = self.p;
        let mut v = self.v;
        for ((dp, dv), d) in self.dp.iter().zip(&self.dv).zip(delta) {
            p += *dp * d;
            v += *dv * d;
        }
        (p, v)
    }

    /// The ray itself, with infinite extent.
    #[inline]
    pub fn ray(&self) -> Ray {
        Ray::new(self.p, self.v)
    }

    /// Whether every component is finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        // The sum of `x · 0` over every component (see [`all_finite`]), written as a plain loop:
        // this check runs at every vertex of every photon differential.
        let mut acc = self.p * 0.0 + self.v * 0.0;
        for i in 0..N {
            acc += self.dp[i] * 0.0 + self.dv[i] * 0.0;
        }
        acc.cmpeq(Vec3::ZERO).all()
    }

    /// `Ok(self)` if finite, `Err(NonFinite)` otherwise.
    pub(crate) fn finite_or_err(self) -> Result<Self, DiffError> {
        if self.is_finite() {
            Ok(self)
        } else {
            Err(DiffError::NonFinite)
        }
    }
}

impl From<&RayDifferential> for RayDiff<2> {
    /// caustica's camera differential: θ = (x, y) in pixels; its `dddx`, `dddy` are already
    /// derivatives of the normalised direction.
    fn from(r: &RayDifferential) -> Self {
        Self::new(r.ray.o, r.ray.d, [r.dodx, r.dody], [r.dddx, r.dddy])
    }
}

impl RayDiff<2> {
    /// Back to caustica's [`RayDifferential`] (θ = (x, y)), with ray extent `t_max`.
    pub fn to_core(&self, t_max: f32) -> RayDifferential {
        RayDifferential {
            ray: Ray::with_t_max(self.p, self.v, t_max),
            dodx: self.dp[0],
            dody: self.dp[1],
            dddx: self.dv[0],
            dddy: self.dv[1],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn widening_keeps_the_derivatives_and_adds_zero_ones() {
        let r = RayDiff::<2>::new(
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::Y,
            [Vec3::X, Vec3::new(0.0, 0.0, -2.0)],
            [Vec3::Z, Vec3::new(0.5, 0.0, 0.0)],
        );
        let w = r.widen::<3>();
        assert_eq!((w.p, w.v), (r.p, r.v));
        assert_eq!(&w.dp[..2], &r.dp[..]);
        assert_eq!(&w.dv[..2], &r.dv[..]);
        assert_eq!((w.dp[2], w.dv[2]), (Vec3::ZERO, Vec3::ZERO));
        assert_eq!(r.widen::<2>(), r);
    }

    #[test]
    fn finiteness_checks_catch_every_non_finite_component() {
        let good = RayDiff::<2>::new(
            Vec3::new(1.0, -0.0, 3.0e38),
            Vec3::Z,
            [Vec3::new(-1e-38, 0.0, 2.0), Vec3::splat(-0.0)],
            [Vec3::X, Vec3::new(0.5, -2.0, f32::MIN_POSITIVE)],
        );
        assert!(good.is_finite());
        assert!(all_finite([0.0, -0.0, f32::MAX, f32::MIN, 1e-45]));
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            assert!(!all_finite([1.0, bad, 2.0]));
            for k in 0..18 {
                let mut r = good;
                let v = match k / 3 {
                    0 => &mut r.p,
                    1 => &mut r.v,
                    2 => &mut r.dp[0],
                    3 => &mut r.dp[1],
                    4 => &mut r.dv[0],
                    _ => &mut r.dv[1],
                };
                v[k % 3] = bad;
                assert!(!r.is_finite(), "component {k} = {bad} not caught");
                assert_eq!(r.finite_or_err(), Err(DiffError::NonFinite));
            }
        }
    }
}
