//! Photon footprints: the ellipse a photon differential covers on the surface where it lands,
//! its irradiance and the anisotropic kernel that spreads it (seed 002 sec. 3.1, 3.3, eq. 4,
//! 10–12 and app. B; seed 000 sec. 5.2.2–5.2.3, eq. 5.13–5.15).
//!
//! At a hit `x_p` with unit normal `n_p`, the positional differential vectors `D_u x_p`,
//! `D_v x_p` (m) span a parallelogram — the photon's ray footprint — and the photon footprint
//! is the largest ellipse inscribed in it, centred at `x_p`, whose conjugate semi-diameters are
//! the columns of `½ Dx` (seed 002 sec. 3.1). Then
//!
//! * area `A_p = π/4 |D_u x × D_v x|` (m², eq. 4 = eq. 5.15) — [`Footprint::area`];
//! * irradiance `E_p = Φ_p / A_p` (W/m², sec. 3.3 = eq. 5.5) — [`Footprint::irradiance`];
//! * filter matrix `M_p = 2 / (D_u x · (D_v x × n)) [D_v x × n ; n × D_u x]` (2×3, 1/m,
//!   eq. 12): the top two rows of the inverse of the change of basis `[½D_u x, ½D_v x, n]`, so
//!   the ellipse becomes the unit circle and the normal offset is dropped (locally flat
//!   surface) — [`Footprint::filter_matrix`], [`Footprint::to_filter`];
//! * the photon's share of the radiance estimate, eq. 10 without the BRDF:
//!   `π K(|M_p (x − x_p)|) E_p` (W/m²) with Silverman's second-order kernel
//!   `K(x) = 3/π (1 − x²)²` for `x < 1` (eq. 11) — [`Footprint::irradiance_at`]. It integrates
//!   to `Φ_p` over the plane: the map from filter space to the plane has Jacobian
//!   `|det ½[D_u x D_v x]| = A_p / π` and `∫_{unit disc} K = 1`, so
//!   `∫ π K E_p dA = π (A_p/π) Φ_p/A_p = Φ_p`.
//!
//! **Seed 000's form is the same estimate.** Eq. 5.14 weights `ΔE_pd` by
//! `K((x − x_pd)ᵀ M_pdᵀ M_pd (x − x_pd))` with Table 5.1's Silverman kernel `K(y) = 3(1 − |y|)²`
//! of the *squared* filter distance and no factor π; since
//! `3(1 − d²)² = π · 3/π (1 − d²)²`, eq. 5.14's summand is eq. 10's. Both are also
//! `caustica_density::Kernel::Silverman.eval(d², Dim::Two) · π` (that kernel takes `u² = d²`
//! and is normalised to 1 over the unit disc), which this crate cannot call: `differentials`
//! comes before `density` in the dependency order, so eq. 11 is implemented here as
//! [`silverman`].
//!
//! **Gather radius.** Seed 002 bounds the eye-vertex search by
//! `r_max = ½ max(|D_u x_p|, |D_v x_p|)` and seed 000 by "half the length of the longest
//! positional differential vector". That is the ellipse's largest semi-axis only when the two
//! vectors are orthogonal (as they are at emission); once transfers and refractions have skewed
//! them, ½D_u and ½D_v are conjugate semi-diameters, and the semi-major axis — the largest
//! singular value of `½[D_u x D_v x]` — can be longer (for `D_u = (1, 0)`, `D_v = (1, 0.1)`
//! it is 0.71 against `r_max = 0.50`), so a search within `r_max` would miss part of the
//! ellipse. [`Footprint::gather_radius`] is the semi-major axis (equal to `r_max` for
//! orthogonal vectors, never smaller); the printed formula is [`Footprint::seed_gather_radius`].
//!
//! **Collapsed footprints** (`|D_u x × D_v x| ≈ 0`: the area of eq. 4 vanishes and eq. 12 is
//! singular) are [`DiffError::CollapsedFootprint`]; seed 002 discards such photons (sec. 3.3),
//! and the typed error lets a caller count them.

use std::f32::consts::PI;

use caustica_core::{Vec2, Vec3};

use crate::ray_differential::{all_finite3, unit};
use crate::{DiffError, RayDiff, SurfaceHit};

/// A footprint has collapsed when `|D_u x × D_v x| ≤ COLLAPSED_SIN · |D_u x| |D_v x|` (the sine
/// of the angle between the projected positional differential vectors).
pub const COLLAPSED_SIN: f32 = 1e-6;

/// Area of the photon footprint, `A_p = π/4 |D_u x × D_v x|` (eq. 4 = eq. 5.15; m² for `du`, `dv`
/// in m): the maximum-area ellipse inscribed in the parallelogram of the two vectors.
#[inline]
pub fn footprint_area(du: Vec3, dv: Vec3) -> f32 {
    PI / 4.0 * du.cross(dv).length() // eq. 4
}

/// Solid angle of a photon, `ω_p = π/4 |D_θ ω × D_φ ω|` (sr, seed 002, the unnumbered equation
/// after eq. 4), for the directional differential vectors `dtheta`, `dphi` (rad).
#[inline]
pub fn photon_solid_angle(dtheta: Vec3, dphi: Vec3) -> f32 {
    PI / 4.0 * dtheta.cross(dphi).length()
}

/// Silverman's second-order kernel in filter space, `K(x) = 3/π (1 − x²)²` for `x < 1`, else 0
/// (seed 002 eq. 11; 1 per unit filter area), of the filter distance `x = |M_p (x − x_p)|`. It
/// integrates to 1 over the unit disc. Returns 0 for a NaN argument.
#[inline]
pub fn silverman(x: f32) -> f32 {
    let x2 = x * x;
    if x2 < 1.0 {
        let a = 1.0 - x2;
        3.0 / PI * a * a // eq. 11
    } else {
        0.0
    }
}

/// The elliptic footprint of a photon differential at a surface hit (seed 002 eq. 4, 12).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    center: Vec3,
    normal: Vec3,
    du: Vec3,
    dv: Vec3,
    rows: [Vec3; 2],
    area: f32,
    /// Semi-major axis (m), cached: every splat and gather tests against it.
    gather_radius: f32,
}

/// The larger eigenvalue of the Gram matrix `[[p, r], [r, q]]` (`p = |a|²`, `q = |b|²`,
/// `r = a · b`).
#[inline]
fn gram_max_eigenvalue(p: f64, q: f64, r: f64) -> f64 {
    0.5 * (p + q) + (0.25 * (p - q) * (p - q) + r * r).sqrt()
}

impl Footprint {
    /// The footprint centred at `center` (`x_p`, m) on the surface with normal `normal` (`n_p`,
    /// any non-zero length) of the positional differential vectors `du` = `D_u x_p`,
    /// `dv` = `D_v x_p` (m).
    ///
    /// The vectors are projected orthogonally onto the tangent plane of `n_p` ("projected down
    /// onto the tangential surface", seed 000 sec. 5.1). For a photon differential transferred
    /// onto the plane of this normal (`transfer_to_plane`, a triangle hit) they already lie in
    /// it and nothing changes; otherwise (e.g. a shading normal) this keeps eq. 4's area equal to
    /// the ellipse that eq. 12 maps to the unit circle, which eq. 12 alone already ignores the
    /// normal components for (`D_v x × n` and `D_u x · (D_v x × n)` do not see them).
    ///
    /// Errors: [`DiffError::NonFinite`] for a non-finite input or an overflowing area or
    /// matrix, [`DiffError::DegenerateNormal`] for a zero normal,
    /// [`DiffError::CollapsedFootprint`] if a projected vector is zero or the two are
    /// (numerically) parallel (see [`COLLAPSED_SIN`]).
    pub fn new(center: Vec3, du: Vec3, dv: Vec3, normal: Vec3) -> Result<Self, DiffError> {
        if !all_finite3([&center, &du, &dv, &normal]) {
            return Err(DiffError::NonFinite);
        }
        let n = unit(normal).ok_or(DiffError::DegenerateNormal)?;
        let du = du - n * n.dot(du);
        let dv = dv - n * n.dot(dv);
        // |a × b| > sin · |a| |b|, in squares (f64: the squares of tiny vectors underflow f32).
        let (a, b) = (du.as_dvec3(), dv.as_dvec3());
        let (a2, b2) = (a.length_squared(), b.length_squared());
        let sin2 = COLLAPSED_SIN as f64 * COLLAPSED_SIN as f64;
        if !(a2 > 0.0 && b2 > 0.0 && a.cross(b).length_squared() > sin2 * a2 * b2) {
            return Err(DiffError::CollapsedFootprint);
        }
        let area = footprint_area(du, dv); // eq. 4
        // eq. 12: M_p = 2 / (D_u x · (D_v x × n)) [D_v x × n ; n × D_u x]
        let r0 = dv.cross(n);
        let r1 = n.cross(du);
        let scale = 2.0 / du.dot(r0);
        let rows = [scale * r0, scale * r1];
        if !(area > 0.0 && area.is_finite() && all_finite3(&rows)) {
            return Err(DiffError::NonFinite);
        }
        Ok(Self {
            center,
            normal: n,
            du,
            dv,
            rows,
            area,
            // The semi-major axis (semi_axis_lengths), from the Gram entries computed above.
            gather_radius: (0.5 * gram_max_eigenvalue(a2, b2, a.dot(b)).sqrt()) as f32,
        })
    }

    /// The footprint of `du`, `dv` (as [`Footprint::new`]) with each principal semi-axis raised
    /// to at least `min_semi_axis` (m), and whether it was raised. Near a caustic fold first-order
    /// differentials give footprints of almost no area, whose irradiance Φ/A is a firefly
    /// wherever they meet an eye point (seed 000 Q-M9 names the same degeneracy for volume
    /// kernels): the floor bounds it by Φ/(π r²) and keeps the footprint's orientation, flux
    /// and major axis. A footprint whose semi-axes are both at least `min_semi_axis` is exactly
    /// [`Footprint::new`]'s. Vectors too parallel for [`Footprint::new`] are rescued: the major
    /// axis along the longer vector, the minor one across it in the tangent plane (two zero
    /// vectors: a disc of radius `min_semi_axis`).
    ///
    /// The rule is [`crate::medium::widen_ellipse`], the one volume kernels use.
    ///
    /// Errors: those of [`Footprint::new`] (a collapsed footprint only if the floor is not
    /// positive).
    /// Without a floor (`None`) it is [`Footprint::new`].
    pub fn widened(
        center: Vec3,
        du: Vec3,
        dv: Vec3,
        normal: Vec3,
        min_semi_axis: Option<f32>,
    ) -> Result<(Self, bool), DiffError> {
        let Some(min_semi_axis) = min_semi_axis else {
            return Self::new(center, du, dv, normal).map(|f| (f, false));
        };
        if !all_finite3([&center, &du, &dv, &normal]) {
            return Err(DiffError::NonFinite);
        }
        let n = unit(normal).ok_or(DiffError::DegenerateNormal)?;
        let (pu, pv) = (du - n * n.dot(du), dv - n * n.dot(dv));
        match crate::medium::widen_ellipse(pu, pv, n, min_semi_axis) {
            None => Self::new(center, du, dv, normal).map(|f| (f, false)),
            Some([a, b]) => Self::new(center, a, b, n).map(|f| (f, true)),
        }
    }

    /// The footprint of a photon differential `ray` (parameters as in [`crate::emission`]:
    /// `dp[0] = D_u x`, `dp[1] = D_v x`) that has been transferred onto the surface with normal
    /// `normal`: centre `ray.p`, vectors `ray.dp`. See [`Footprint::new`].
    pub fn from_ray(ray: &RayDiff<2>, normal: Vec3) -> Result<Self, DiffError> {
        Self::new(ray.p, ray.dp[0], ray.dp[1], normal)
    }

    /// The footprint at a triangle hit, on the triangle's plane (its geometric normal, in which
    /// the transferred `dp` lie).
    pub fn from_hit(hit: &SurfaceHit<2>) -> Result<Self, DiffError> {
        Self::from_ray(&hit.ray, hit.geometric_normal)
    }

    /// Centre `x_p` (m).
    pub fn center(&self) -> Vec3 {
        self.center
    }

    /// Unit normal `n_p`.
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// The positional differential vectors `[D_u x_p, D_v x_p]` (m), in the tangent plane.
    pub fn differentials(&self) -> [Vec3; 2] {
        [self.du, self.dv]
    }

    /// `½ D_u x_p`, `½ D_v x_p` (m): what seed 002 calls the ellipse's semi-axes (sec. 3.1). They
    /// are conjugate semi-diameters — `x_p + ½(cos t D_u x + sin t D_v x)` traces the ellipse —
    /// and its principal semi-axes only when orthogonal; see [`Footprint::principal_semi_axes`].
    pub fn conjugate_semi_diameters(&self) -> [Vec3; 2] {
        [0.5 * self.du, 0.5 * self.dv]
    }

    /// The ellipse's principal semi-axes `[major, minor]` as vectors (m), orthogonal, in the
    /// tangent plane: the singular vectors of `½[D_u x D_v x]` scaled by its singular values.
    pub fn principal_semi_axes(&self) -> [Vec3; 2] {
        let (a, b) = (self.du.as_dvec3(), self.dv.as_dvec3());
        let (p, q, r) = (a.dot(a), b.dot(b), a.dot(b));
        let (l1, _) = self.gram_eigenvalues();
        // eigenvector of [[p, r], [r, q]] for λ₁: the better conditioned of two equivalent forms
        let (e1, e2) = ((r, l1 - p), (l1 - q, r));
        let e = if e1.0.hypot(e1.1) >= e2.0.hypot(e2.1) {
            e1
        } else {
            e2
        };
        let len = e.0.hypot(e.1);
        let e = if len > 0.0 {
            (e.0 / len, e.1 / len)
        } else {
            (1.0, 0.0)
        };
        let major = (a * e.0 + b * e.1) * 0.5;
        let minor = (a * -e.1 + b * e.0) * 0.5;
        [major.as_vec3(), minor.as_vec3()]
    }

    /// Lengths of the principal semi-axes `(major, minor)` (m); `π · major · minor = A_p`.
    pub fn semi_axis_lengths(&self) -> (f32, f32) {
        let (l1, l2) = self.gram_eigenvalues();
        ((0.5 * l1.sqrt()) as f32, (0.5 * l2.sqrt()) as f32)
    }

    /// Eigenvalues `λ₁ ≥ λ₂ ≥ 0` of the Gram matrix of `D_u x`, `D_v x` (m², in f64).
    fn gram_eigenvalues(&self) -> (f64, f64) {
        let (a, b) = (self.du.as_dvec3(), self.dv.as_dvec3());
        let l1 = gram_max_eigenvalue(a.dot(a), b.dot(b), a.dot(b));
        let det = a.cross(b).length_squared(); // p q − r², without cancellation
        (l1, det / l1)
    }

    /// Footprint area `A_p = π/4 |D_u x × D_v x|` (m², eq. 4).
    pub fn area(&self) -> f32 {
        self.area
    }

    /// Irradiance of the photon, `E_p = Φ_p / A_p` (W/m², seed 002 sec. 3.3, seed 000 eq. 5.5),
    /// for its flux `flux` = `Φ_p` (W). Multiply a spectral flux by `irradiance(1.0)` (1/m²).
    pub fn irradiance(&self, flux: f32) -> f32 {
        flux / self.area
    }

    /// The 2×3 filter matrix `M_p` of eq. 12 as its two rows (1/m): `M_p (x − x_p)` are the
    /// filter-space coordinates in which the footprint is the unit circle; `M_p n_p = 0`.
    pub fn filter_matrix(&self) -> [Vec3; 2] {
        self.rows
    }

    /// Filter-space coordinates `M_p (x − x_p)` of a world point `x` (m) (eq. 12), unitless:
    /// `x_p + ½ D_u x ↦ (1, 0)`, `x_p + ½ D_v x ↦ (0, 1)`, offsets along `n_p` ignored.
    pub fn to_filter(&self, x: Vec3) -> Vec2 {
        let d = x - self.center;
        Vec2::new(self.rows[0].dot(d), self.rows[1].dot(d))
    }

    /// `|M_p (x − x_p)|`: 1 on the ellipse boundary.
    pub fn filter_distance(&self, x: Vec3) -> f32 {
        self.to_filter(x).length()
    }

    /// Whether `x` is inside the footprint: seed 002 discards a point if
    /// `|M_p (x − x_p)| ≥ 1` (sec. 3.3). False for NaN.
    pub fn contains(&self, x: Vec3) -> bool {
        self.filter_distance(x) < 1.0
    }

    /// Silverman's kernel (eq. 11) at `x` in filter space, `K(|M_p (x − x_p)|)` (per unit
    /// filter-space area).
    pub fn kernel(&self, x: Vec3) -> f32 {
        silverman(self.filter_distance(x))
    }

    /// The photon's contribution to the irradiance at `x` (W/m²), `π K(|M_p (x − x_p)|) E_p`
    /// with Silverman's kernel (eq. 11): the summand of eq. 10 without the BRDF (= seed 000
    /// eq. 5.14's summand, see the module docs). Integrates to `Φ_p` = `flux` over the plane.
    pub fn irradiance_at(&self, x: Vec3, flux: f32) -> f32 {
        self.irradiance_at_with(x, flux, silverman)
    }

    /// As [`Footprint::irradiance_at`] with another radial kernel `kernel(x)` of the filter
    /// distance, normalised to 1 over the unit disc (e.g. Epanechnikov `2/π (1 − x²)`).
    pub fn irradiance_at_with(&self, x: Vec3, flux: f32, kernel: impl Fn(f32) -> f32) -> f32 {
        PI * kernel(self.filter_distance(x)) * self.irradiance(flux) // eq. 10
    }

    /// Range of the neighbour search around `x_p` that finds every point of the footprint (m):
    /// the semi-major axis of the ellipse. Equals seed 002's `r_max = ½ max(|D_u x|, |D_v x|)`
    /// ([`Footprint::seed_gather_radius`]) when the vectors are orthogonal and exceeds it when
    /// they are skewed (see the module docs).
    pub fn gather_radius(&self) -> f32 {
        self.gather_radius
    }

    /// `r_max = ½ max(|D_u x_p|, |D_v x_p|)` as printed in seed 002 sec. 3.3 (and seed 000
    /// sec. 5.2.2's "half the length of the longest positional differential vector", m). Only
    /// a bound on the footprint for orthogonal vectors; prefer [`Footprint::gather_radius`].
    pub fn seed_gather_radius(&self) -> f32 {
        0.5 * self.du.length().max(self.dv.length())
    }

    /// The anisotropy metric of seed 002 app. B,
    /// `m_a = |D_min x − (D_max x · D_min x)/|D_max x|² D_max x| / |D_max x|`, with `D_max x`,
    /// `D_min x` the longer and the shorter positional differential vector: the ellipse
    /// "un-skewed" (the component of the shorter vector perpendicular to the longer one) and the
    /// ratio of its minor to its major radius. In `(0, 1]`, 1 for an isotropic footprint; the
    /// seed marks `m_a < 0.1` as highly anisotropic. It is `|D_u x × D_v x| / |D_max x|²`, not
    /// the ratio of the principal semi-axes ([`Footprint::axis_ratio`]), for skewed vectors.
    pub fn anisotropy(&self) -> f32 {
        let (dmax, dmin) = if self.du.length_squared() >= self.dv.length_squared() {
            (self.du, self.dv)
        } else {
            (self.dv, self.du)
        };
        let l2 = dmax.length_squared();
        (dmin - dmax.dot(dmin) / l2 * dmax).length() / l2.sqrt() // app. B
    }

    /// Ratio of the principal semi-axes, minor / major, in `(0, 1]`.
    pub fn axis_ratio(&self) -> f32 {
        let (a, b) = self.semi_axis_lengths();
        b / a
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::emission::{EmissionBudget, emit_point};
    use crate::{FlatTriangle, transfer_to_plane};
    use caustica_core::Mat3;

    fn close(a: f32, b: f32, rel: f32) -> bool {
        (a - b).abs() <= rel * b.abs().max(1e-30)
    }

    /// Footprints of various shapes on a tilted plane, as (centre, D_u x, D_v x, normal).
    fn cases() -> Vec<(Vec3, Vec3, Vec3, Vec3)> {
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        let t1 = n.any_orthonormal_vector();
        let t2 = n.cross(t1);
        let c = Vec3::new(1.0, -2.0, 0.5);
        vec![
            (c, 0.2 * t1, 0.2 * t2, n),                        // circle
            (c, 0.4 * t1, 0.05 * t2, n),                       // orthogonal, anisotropic
            (c, 0.3 * t1, 0.3 * t1 + 0.03 * t2, n),            // strongly skewed
            (c, 0.1 * t1 - 0.2 * t2, 0.25 * t1 + 0.1 * t2, n), // skewed, general
            (c, 0.1 * t2, 0.3 * t1, n),                        // left-handed about n
            (Vec3::ZERO, 2e-4 * t1, 1e-4 * (t1 + t2), -n),     // tiny, normal flipped
        ]
    }

    fn boundary(f: &Footprint, k: usize, count: usize) -> Vec3 {
        let t = 2.0 * PI * k as f32 / count as f32;
        let [a, b] = f.conjugate_semi_diameters();
        f.center() + t.cos() * a + t.sin() * b
    }

    /// The minimum semi-axis: footprints already wider are [`Footprint::new`]'s to the bit; others
    /// get both principal semi-axes at least the floor, keep their major axis and its direction
    /// (the ellipse contains the original); parallel vectors are rescued along the longer one.
    #[test]
    fn widening_raises_only_the_short_semi_axes() {
        for (c, du, dv, n) in cases() {
            let f = Footprint::new(c, du, dv, n).unwrap();
            let (a, b) = f.semi_axis_lengths();
            // A floor below the minor axis changes nothing.
            let (g, w) = Footprint::widened(c, du, dv, n, Some(0.5 * b)).unwrap();
            assert!(!w && g == f);
            // A floor above both axes: a disc of that radius.
            let (g, _) = Footprint::widened(c, du, dv, n, Some(2.0 * a)).unwrap();
            let (ga, gb) = g.semi_axis_lengths();
            assert!(close(ga, 2.0 * a, 1e-4) && close(gb, 2.0 * a, 1e-4));
            // A floor between the axes: the minor axis raised, the major kept.
            if a < 1.01 * b {
                continue; // a circle: nothing between its axes
            }
            let r = 0.5 * (a + b);
            let (g, w) = Footprint::widened(c, du, dv, n, Some(r)).unwrap();
            let (ga, gb) = g.semi_axis_lengths();
            assert!(w && close(ga.max(gb), a.max(r), 1e-4) && close(ga.min(gb), r, 1e-4));
            let [m0, _] = f.principal_semi_axes();
            let [g0, _] = g.principal_semi_axes();
            assert!(
                m0.normalize().dot(g0.normalize()).abs() > 0.999,
                "{m0} {g0}"
            );
            // The widened ellipse contains the original one.
            for k in 0..16 {
                let x = boundary(&f, k, 16) - g.center();
                let l = Vec2::new(g.rows[0].dot(x), g.rows[1].dot(x));
                assert!(l.length() <= 1.0 + 1e-4, "{l}");
            }
        }
        // Parallel vectors (collapsed for Footprint::new) keep the longer one as the major axis.
        let n = Vec3::Z;
        let (du, dv) = (Vec3::new(0.4, 0.0, 0.0), Vec3::new(-0.2, 0.0, 0.0));
        assert_eq!(
            Footprint::new(Vec3::ZERO, du, dv, n).unwrap_err(),
            DiffError::CollapsedFootprint
        );
        let (g, w) = Footprint::widened(Vec3::ZERO, du, dv, n, Some(0.01)).unwrap();
        let (ga, gb) = g.semi_axis_lengths();
        assert!(
            w && close(ga, 0.2, 1e-4) && close(gb, 0.01, 1e-4),
            "{ga} {gb}"
        );
        // Two zero vectors: a disc of the floor's radius.
        let (g, w) = Footprint::widened(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, n, Some(0.01)).unwrap();
        let (ga, gb) = g.semi_axis_lengths();
        assert!(w && close(ga, 0.01, 1e-4) && close(gb, 0.01, 1e-4));
    }

    #[test]
    fn area_is_eq_4_and_the_principal_axes_agree() {
        for (c, du, dv, n) in cases() {
            let f = Footprint::new(c, du, dv, n).unwrap();
            assert!(close(f.area(), PI / 4.0 * du.cross(dv).length(), 1e-6));
            let (a, b) = f.semi_axis_lengths();
            assert!(close(PI * a * b, f.area(), 1e-4), "{a} {b} {}", f.area());
            let [ma, mi] = f.principal_semi_axes();
            assert!(close(ma.length(), a, 1e-4) && close(mi.length(), b, 1e-3));
            assert!(ma.dot(mi).abs() < 1e-4 * a * a);
            assert!(ma.dot(f.normal()).abs() < 1e-5 * a && mi.dot(f.normal()).abs() < 1e-5 * a);
            // the principal axes' end points are on the ellipse (filter distance 1)
            for x in [ma, mi, -ma] {
                assert!((f.filter_distance(c + x) - 1.0).abs() < 1e-3);
            }
            // and the major axis is the farthest the boundary gets from the centre
            let far = (0..3600)
                .map(|k| (boundary(&f, k, 3600) - c).length())
                .fold(0.0f32, f32::max);
            assert!(close(far, a, 1e-4), "{far} {a}");
            assert!((0.0..=1.0 + 1e-6).contains(&f.axis_ratio()));
        }
    }

    /// Point light of intensity I at distance d above a plane, normal incidence. With
    /// `|D_θ ω| = |D_φ ω| = 4 s / √N` (eq. 6, ω_e = 4π) and a transfer over `t′ = d` along which
    /// the directional vectors are already parallel to the plane, `D x′ = d D ω`: a circle of
    /// radius `ρ = 2 s d / √N`, `A_p = π ρ² = 4π s² d² / N = d² ω_p`, and with
    /// `Φ_p = 4π I / N` (eq. 5.4) `E_p = Φ_p / A_p = I / (s² d²)`: the inverse-square
    /// irradiance divided by s², the mean number of footprints covering a point
    /// (`N / (4π d²)` photons per m² times `A_p`).
    #[test]
    fn point_light_footprint_at_normal_incidence_is_the_analytic_circle() {
        let (intensity, d) = (3.0f32, 2.5f32);
        for (n, s) in [(10_000u64, 1.0f32), (50_000, 8.0), (100, 0.5)] {
            let b = EmissionBudget::new(n, s).unwrap();
            let light = Vec3::new(0.3, -0.1, d);
            let r = emit_point(light, -Vec3::Z, &b).unwrap();
            let z = [Vec3::ZERO; 2];
            let t = transfer_to_plane(&r, Vec3::ZERO, &z, Vec3::Z, &z).unwrap();
            let f = Footprint::from_ray(&t.ray, Vec3::Z).unwrap();
            let rho = 2.0 * s * d / (n as f32).sqrt();
            let (a, bb) = f.semi_axis_lengths();
            assert!(
                close(a, rho, 1e-5) && close(bb, rho, 1e-5),
                "{a} {bb} {rho}"
            );
            assert!((f.center() - Vec3::new(0.3, -0.1, 0.0)).length() < 1e-6);
            assert!(close(f.area(), 4.0 * PI * s * s * d * d / n as f32, 1e-5));
            assert!(close(f.anisotropy(), 1.0, 1e-5) && close(f.axis_ratio(), 1.0, 1e-5));
            assert!(close(f.gather_radius(), rho, 1e-5));
            assert!(close(f.seed_gather_radius(), rho, 1e-5));
            let flux = b.photon_flux(4.0 * PI * intensity);
            let e = f.irradiance(flux);
            assert!(close(e, intensity / (s * s * d * d), 1e-5), "{e}");
        }
    }

    /// End to end (emission, transfer, eq. 4, 10–12): N photons from a point light in
    /// quasi-uniform (Fibonacci-sphere) directions, transferred to the plane z = 0 at distance
    /// d; Σ π K E_p at a point is the inverse-square (cosine) law `E = I d / (d² + r²)^{3/2}`,
    /// at the foot (circular footprints) and at 45° (elliptic ones).
    #[test]
    fn point_light_estimate_is_the_inverse_square_law() {
        // s ≥ 4: ≥ 16 footprints overlap each point, so the lattice's own unevenness stays
        // below 1 % (it is ~5 % at s = 2).
        for (n, s) in [(40_000u64, 4.0f32), (40_000, 8.0)] {
            let (intensity, d) = (2.0f32, 1.5f32);
            let b = EmissionBudget::new(n, s).unwrap();
            let light = Vec3::new(0.0, 0.0, d);
            let flux = b.photon_flux(4.0 * PI * intensity);
            let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
            let z = [Vec3::ZERO; 2];
            let feet: Vec<Footprint> = (0..n)
                .filter_map(|i| {
                    // in f64: the golden-angle phase reaches 10⁵ rad
                    let zc = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
                    let r = (1.0 - zc * zc).sqrt();
                    let phi = (golden * i as f64).rem_euclid(2.0 * std::f64::consts::PI);
                    let w = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, zc as f32);
                    let ray = emit_point(light, w, &b).ok()?;
                    let t = transfer_to_plane(&ray, Vec3::ZERO, &z, Vec3::Z, &z).ok()?;
                    Footprint::from_ray(&t.ray, Vec3::Z).ok()
                })
                .collect();
            assert!(feet.len() > (n as usize) / 2 - 10);
            for x in [
                Vec3::ZERO,
                Vec3::new(0.2, -0.1, 0.0),
                Vec3::new(d, 0.0, 0.0),
            ] {
                let est: f32 = feet.iter().map(|f| f.irradiance_at(x, flux)).sum();
                let r2 = x.length_squared();
                let exact = intensity * d / (d * d + r2).powf(1.5);
                assert!(close(est, exact, 0.015), "{n} {s} {x}: {est} vs {exact}");
            }
        }
    }

    #[test]
    fn filter_matrix_maps_the_boundary_to_the_unit_circle() {
        for (c, du, dv, n) in cases() {
            let f = Footprint::new(c, du, dv, n).unwrap();
            for k in 0..64 {
                let x = boundary(&f, k, 64);
                let d = f.filter_distance(x);
                assert!((d - 1.0).abs() < 1e-4, "{k}: {d}");
                // just inside / just outside
                assert!(f.contains(c + 0.999 * (x - c)) && !f.contains(c + 1.001 * (x - c)));
                // offsets along the normal are ignored (locally flat surface)
                let off = 0.3 * f.gather_radius() * n;
                assert!((f.filter_distance(x + off) - d).abs() < 1e-4);
            }
            let [m0, m1] = f.filter_matrix();
            let nn = f.normal();
            assert!(m0.dot(nn).abs() < 1e-3 * m0.length() && m1.dot(nn).abs() < 1e-3 * m1.length());
            // ½D_u ↦ (1, 0), ½D_v ↦ (0, 1)
            let u = f.to_filter(c + 0.5 * du);
            let v = f.to_filter(c + 0.5 * dv);
            assert!((u - Vec2::X).length() < 1e-4 && (v - Vec2::Y).length() < 1e-4);
            // eq. 12 is the top two rows of the inverse of [½D_u, ½D_v, n]
            let inv = Mat3::from_cols(0.5 * du, 0.5 * dv, nn)
                .inverse()
                .transpose();
            for (row, m) in [(inv.x_axis, m0), (inv.y_axis, m1)] {
                assert!((row - m).length() < 1e-3 * m.length(), "{row} {m}");
            }
        }
    }

    #[test]
    fn silverman_kernel_is_eq_11_and_normalised() {
        assert!(close(silverman(0.0), 3.0 / PI, 1e-7));
        assert!(close(silverman(0.5), 3.0 / PI * 0.5625, 1e-6));
        assert_eq!(silverman(1.0), 0.0);
        assert_eq!(silverman(1.5), 0.0);
        assert_eq!(silverman(f32::NAN), 0.0);
        assert_eq!(silverman(f32::INFINITY), 0.0);
        // ∫_disc K dA = ∫₀¹ K(r) 2π r dr = 1 (midpoint rule)
        let m = 100_000;
        let h = 1.0 / m as f64;
        let total: f64 = (0..m)
            .map(|i| {
                let r = (i as f64 + 0.5) * h;
                silverman(r as f32) as f64 * 2.0 * std::f64::consts::PI * r * h
            })
            .sum();
        assert!((total - 1.0).abs() < 1e-6, "{total}");
    }

    /// ∫ π K(|M_p (x − x_p)|) E_p dA = Φ_p over the plane (midpoint rule on a grid in the
    /// tangent plane covering the gather radius), for every footprint shape.
    #[test]
    fn kernel_integrates_to_the_flux_over_the_plane() {
        let flux = 0.37f32;
        for (c, du, dv, n) in cases() {
            let f = Footprint::new(c, du, dv, n).unwrap();
            let nn = f.normal();
            let t1 = nn.any_orthonormal_vector();
            let t2 = nn.cross(t1);
            let r = f.gather_radius() as f64 * 1.01;
            let m = 600;
            let h = 2.0 * r / m as f64;
            // Midpoint rule over the square [-r, r]² of the tangent plane.
            let integrate = |g: &dyn Fn(Vec3) -> f32| {
                let mut total = 0.0f64;
                for i in 0..m {
                    for j in 0..m {
                        let a = -r + (i as f64 + 0.5) * h;
                        let b = -r + (j as f64 + 0.5) * h;
                        total += g(c + t1 * a as f32 + t2 * b as f32) as f64 * h * h;
                    }
                }
                total
            };
            let total = integrate(&|x| f.irradiance_at(x, flux));
            assert!(
                (total / flux as f64 - 1.0).abs() < 2e-3,
                "{du} {dv}: {total}"
            );
            // another kernel normalised on the unit disc: Epanechnikov 2/π (1 − x²)
            let epa = |x: f32| {
                if x < 1.0 {
                    2.0 / PI * (1.0 - x * x)
                } else {
                    0.0
                }
            };
            let total = integrate(&|x| f.irradiance_at_with(x, flux, epa));
            assert!(
                (total / flux as f64 - 1.0).abs() < 5e-3,
                "epa {du} {dv}: {total}"
            );
        }
    }

    /// Every point of the ellipse is within [`Footprint::gather_radius`]; seed 002's printed
    /// `r_max` equals it for orthogonal vectors and falls short for skewed ones.
    #[test]
    fn gather_radius_covers_the_footprint() {
        for (c, du, dv, n) in cases() {
            let f = Footprint::new(c, du, dv, n).unwrap();
            let r = f.gather_radius();
            for k in 0..720 {
                assert!((boundary(&f, k, 720) - c).length() <= r * (1.0 + 1e-5));
            }
            assert!(f.seed_gather_radius() <= r * (1.0 + 1e-5));
            let orthogonal = du.dot(dv).abs() < 1e-6 * du.length() * dv.length();
            if orthogonal {
                assert!(close(f.seed_gather_radius(), r, 1e-5));
            }
        }
        // the example of the module docs: D_u = (1, 0), D_v = (1, 0.1)
        let f = Footprint::new(Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.1, 0.0), Vec3::Z).unwrap();
        assert!(close(f.seed_gather_radius(), 0.5 * 1.01f32.sqrt(), 1e-6));
        assert!(f.gather_radius() > 0.7, "{}", f.gather_radius());
    }

    #[test]
    fn anisotropy_metric_of_appendix_b() {
        let z = Vec3::Z;
        let m = |du: Vec3, dv: Vec3| Footprint::new(Vec3::ZERO, du, dv, z).unwrap().anisotropy();
        assert!(close(m(Vec3::X, Vec3::Y), 1.0, 1e-6));
        assert!(close(m(3.0 * Vec3::X, -3.0 * Vec3::Y), 1.0, 1e-6));
        assert!(close(m(Vec3::X, 0.05 * Vec3::Y), 0.05, 1e-5));
        // D_max = (2, 0), D_min = (1, 1): un-skewed minor (0, 1), ratio 1/2 — in either order
        let (a, b) = (2.0 * Vec3::X, Vec3::new(1.0, 1.0, 0.0));
        assert!(close(m(a, b), 0.5, 1e-6) && close(m(b, a), 0.5, 1e-6));
        // scale-invariant; = |D_u × D_v| / |D_max|²; the principal-axis ratio differs when skewed
        assert!(close(m(7.0 * a, 7.0 * b), 0.5, 1e-5));
        let f = Footprint::new(Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), z).unwrap();
        assert!(close(f.anisotropy(), 0.5, 1e-6));
        assert!(close(f.axis_ratio(), (3.0 - 5f32.sqrt()) / 2.0, 1e-4));
        for (c, du, dv, n) in cases() {
            let f = Footprint::new(c, du, dv, n).unwrap();
            let ma = f.anisotropy();
            assert!(ma > 0.0 && ma <= 1.0 + 1e-6, "{ma}");
            let dmax2 = du.length_squared().max(dv.length_squared());
            assert!(close(ma, du.cross(dv).length() / dmax2, 1e-4));
        }
    }

    /// Degenerate input gives the documented error, never NaN.
    #[test]
    fn degenerate_footprints_are_errors_never_nan() {
        let (c, z) = (Vec3::ZERO, Vec3::Z);
        let collapsed = Err(DiffError::CollapsedFootprint);
        assert_eq!(Footprint::new(c, Vec3::X, 2.0 * Vec3::X, z), collapsed);
        assert_eq!(Footprint::new(c, Vec3::X, -Vec3::X, z), collapsed);
        assert_eq!(
            Footprint::new(c, Vec3::X, Vec3::new(1.0, 1e-8, 0.0), z),
            collapsed
        );
        assert_eq!(Footprint::new(c, Vec3::ZERO, Vec3::Y, z), collapsed);
        assert_eq!(Footprint::new(c, Vec3::ZERO, Vec3::ZERO, z), collapsed);
        // dv along the normal: nothing left in the tangent plane
        assert_eq!(Footprint::new(c, Vec3::X, Vec3::Z, z), collapsed);
        // a point light's photon at emission has zero positional vectors
        let b = EmissionBudget::new(100, 1.0).unwrap();
        let r = emit_point(c, Vec3::Z, &b).unwrap();
        assert_eq!(Footprint::from_ray(&r, Vec3::Z), collapsed);
        let nan = Vec3::new(f32::NAN, 0.0, 0.0);
        let inf = Vec3::new(f32::INFINITY, 0.0, 0.0);
        for (x, du, dv, n) in [
            (nan, Vec3::X, Vec3::Y, z),
            (c, nan, Vec3::Y, z),
            (c, Vec3::X, inf, z),
            (c, Vec3::X, Vec3::Y, nan),
        ] {
            assert_eq!(Footprint::new(x, du, dv, n), Err(DiffError::NonFinite));
        }
        assert_eq!(
            Footprint::new(c, Vec3::X, Vec3::Y, Vec3::ZERO),
            Err(DiffError::DegenerateNormal)
        );
        // overflow of the area
        let big = Vec3::new(1e30, 0.0, 0.0);
        assert_eq!(
            Footprint::new(c, big, Vec3::new(0.0, 1e30, 0.0), z),
            Err(DiffError::NonFinite)
        );
        // grazing arrival: n · ω = 0 is the transfer's Parallel error ...
        let zz = [Vec3::ZERO; 2];
        let r = emit_point(Vec3::new(0.0, 0.0, 1.0), Vec3::X, &b).unwrap();
        assert_eq!(
            transfer_to_plane(&r, c, &zz, z, &zz),
            Err(DiffError::Parallel)
        );
        // ... and nearly grazing a long, thin, finite footprint: at height 1 and cos = n · ω,
        // t′ = 1/cos and the in-plane vector is stretched by 1/cos, so A_p = ω_p / cos³ and
        // m_a = cos.
        for cos in [0.3f32, 1e-2, 1e-3] {
            let w = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, -cos);
            let r = emit_point(Vec3::new(0.0, 0.0, 1.0), w, &b).unwrap();
            let t = transfer_to_plane(&r, c, &zz, z, &zz).unwrap();
            let f = Footprint::from_ray(&t.ray, z).unwrap();
            let omega_p = crate::footprint::photon_solid_angle(r.dv[0], r.dv[1]);
            assert!(
                close(f.area() * cos.powi(3), omega_p, 1e-2),
                "{cos}: {}",
                f.area()
            );
            assert!(
                close(f.anisotropy(), cos, 1e-2),
                "{cos}: {}",
                f.anisotropy()
            );
            for x in [c, t.ray.p, Vec3::splat(1e3)] {
                assert!(f.irradiance_at(x, 1.0).is_finite() && f.kernel(x).is_finite());
            }
        }
        // a query at NaN gets kernel 0, not NaN
        let f = Footprint::new(c, Vec3::X, Vec3::Y, z).unwrap();
        assert_eq!(f.kernel(nan), 0.0);
        assert_eq!(f.irradiance_at(nan, 1.0), 0.0);
        assert!(!f.contains(nan));
    }

    #[test]
    fn footprint_from_a_triangle_hit() {
        let b = EmissionBudget::new(500, 2.0).unwrap();
        let r = emit_point(Vec3::ZERO, Vec3::new(0.1, 0.2, 1.0), &b).unwrap();
        let tri = FlatTriangle {
            q: [
                Vec3::new(-2.0, -2.0, 2.0),
                Vec3::new(2.0, -2.0, 2.5),
                Vec3::new(0.0, 2.0, 1.8),
            ],
        };
        let hit = tri.hit(&r).unwrap();
        let f = Footprint::from_hit(&hit).unwrap();
        let n = (tri.q[1] - tri.q[0]).cross(tri.q[2] - tri.q[0]);
        let z = [Vec3::ZERO; 2];
        let t = transfer_to_plane(&r, tri.q[0], &z, n, &z).unwrap();
        let g = Footprint::from_ray(&t.ray, n).unwrap();
        assert!((f.center() - g.center()).length() < 1e-5);
        assert!(close(f.area(), g.area(), 1e-4));
        // the transferred vectors already lie in the plane: the projection changes nothing
        for (a, b) in f.differentials().into_iter().zip(t.ray.dp) {
            assert!((a - b).length() < 1e-5 * b.length());
        }
    }
}
