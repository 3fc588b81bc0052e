//! Photon differentials in participating media (seed 000 sec. 8.4): free flight, the rotation
//! of the differential vectors into a sampled direction, the area heuristics of eq. 8.23–8.26,
//! and the three differential vectors of a stored volume photon.
//!
//! # Free flight (sec. 8.4.1, eq. 8.19–8.22)
//!
//! A photon that travels the distance `s` to a scattering event moves to `x' = x + sω` with
//! `ω' = ω` (8.19). Neighbouring rays of the beam travel the same `s` (`ds → 0`, 8.21–8.22), so
//!
//! ```text
//! D x' = D x + s D ω,    D ω' = D ω                                             (8.21, 8.22)
//! ```
//!
//! without the projection onto a plane of a surface transfer (eq. B.13–B.16): there is no
//! surface. [`free_flight`] is this map; it ignores the density variation along the ray
//! (seed notes Q-M7: the distance is sampled by delta tracking in grids, the differential keeps
//! `ds → 0`).
//!
//! # Scattering (eq. 8.23–8.24) and importance-sampled reflection (eq. 8.25–8.26)
//!
//! At a scattering event the walker samples `ω'` from the phase function with density `p`
//! (sr⁻¹). The differential vectors are rotated by the quaternion taking `ω` to `ω'`
//! ([`Rotation`]) and multiplied by `√k`, so that the footprint's area is multiplied by `k`:
//!
//! ```text
//! k = 1/(4π p)              (8.23)     A' = (π/4) k |D_u x × D_v x|              (8.24)
//! k = 1/(2π p)              (8.26)     A' = A k                                  (8.25)
//! ```
//!
//! the first in a medium, the second at a surface reflection sampled by importance (diffuse
//! cosine sampling, `p = cos θ'/π`, or any BSDF). Densely sampled directions narrow the beam,
//! sparse ones widen it, and `E[k] = 1` under the sampling density (`∫ p/(4πp) dω' = 1`,
//! `∫_{H²} p/(2πp) dω' = 1`), so the expected area is preserved ([`phase_area_factor`],
//! [`surface_area_factor`]). **Decisions** (seed notes Q-M4, Q-M5): `√k` scales both the
//! positional and the directional vectors ("the differential vectors", sec. 8.4.1); at a
//! surface the positional vectors, which the transfer left in the tangent plane, are first
//! projected onto the plane ⊥ ω (the beam's cross-section there), then rotated and scaled
//! ([`reflect_sampled`]). An isotropic phase function has `k ≡ 1`: the scattering only rotates.
//!
//! # Storage (sec. 8.4, eq. 8.16–8.18)
//!
//! Only `D_u x` and `D_v x` are traced. A stored volume photon gets a third vector `D_w x`
//! along its direction with length `max(|D_u x|, |D_v x|)`, "so the kernel is between a sphere
//! and an oblate spheroid". That holds when `D_u x, D_v x ⊥ ω`; after a surface or a light
//! they lie in a tangent plane, so [`volume_axes`] first projects them onto the plane ⊥ ω
//! (seed notes Q-M3; [`AxesRule::PaperLiteral`] keeps them as traced). Eq. 8.16's volume and
//! the filter matrix `M = (½[D_u x D_v x D_w x])⁻¹` are `caustica_density::beam`'s.

use caustica_core::Vec3;
use glam::{DQuat, DVec3, Quat};

use crate::DiffError;
use crate::RayDiff;
use crate::ray_differential::{all_finite3, unit};

/// Eq. 8.19–8.22: the differential `ray` after a free flight of `s` metres along its direction:
/// origin `P + sV`, `dP + s dV`, `dV` unchanged. An error if `s` or the result is not finite.
pub fn free_flight<const N: usize>(ray: &RayDiff<N>, s: f32) -> Result<RayDiff<N>, DiffError> {
    if !s.is_finite() {
        return Err(DiffError::NonFinite);
    }
    // Plain loops over the vectors in this file: `[T; N]::map` closures are not inlined here
    // and cost a tenth of the volume tracer's time.
    let mut dp = ray.dp;
    for (d, dv) in dp.iter_mut().zip(&ray.dv) {
        *d += *dv * s; // (8.21)
    }
    RayDiff::new(ray.p + ray.v * s, ray.v, dp, ray.dv).finite_or_err() // (8.19), (8.22)
}

/// The rotation taking the unit direction `from` to the unit direction `to` (sec. 8.4.1): about
/// `from × to` by the angle between them. `to = from` is the identity; `to = −from` (where the
/// axis is undefined) is the half turn about an axis ⊥ `from` chosen from `from` alone (the
/// same for every call), so no NaN arises.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rotation(Quat);

/// `|from + to|²` at or below which the two directions count as opposite and the half turn
/// about a fixed perpendicular axis is used: only exactly opposite f32 vectors (the smallest
/// non-zero `|from + to|` of unit f32 vectors is ~6e-8).
const OPPOSITE: f64 = 1e-30;

/// `|from + to|²` above which [`Rotation::between`] works in f32.
const FAST_SUM2: f32 = 2e-3;

impl Rotation {
    /// The rotation `from → to` (both unit; see the type's docs). An error if either is zero or
    /// not finite.
    pub fn between(from: Vec3, to: Vec3) -> Result<Self, DiffError> {
        let (Some(a), Some(b)) = (unit(from), unit(to)) else {
            return Err(DiffError::ZeroDirection);
        };
        // Directions at least ~2.6° from opposite: the half-vector in f32 is accurate to a
        // few ulps (|a + b| > 0.045), the common case.
        let sum = a + b;
        if sum.length_squared() > FAST_SUM2 {
            let h = sum.normalize();
            let axis = a.cross(h);
            // Unit up to rounding: |a × h|² + (a·h)² = |a|²|h|² = 1.
            let q = Quat::from_xyzw(axis.x, axis.y, axis.z, a.dot(h));
            return if q.is_finite() {
                Ok(Self(q))
            } else {
                Err(DiffError::NonFinite)
            };
        }
        // Normalised again in f64: near-opposite directions make the half-vector sensitive to
        // the f32 lengths' rounding.
        let (a, b) = (a.as_dvec3().normalize(), b.as_dvec3().normalize());
        // q = (a × h, a·h) with h the unit half-vector of a and b is the rotation by the angle
        // between them about a × b (half-angle form: |a × h| = sin(θ/2), a·h = cos(θ/2)).
        let sum = a + b;
        let q = if sum.length_squared() > OPPOSITE {
            let h = sum.normalize();
            let axis = a.cross(h);
            DQuat::from_xyzw(axis.x, axis.y, axis.z, a.dot(h)).normalize()
        } else {
            // Opposite directions: a half turn about any axis ⊥ a.
            let helper = if a.x.abs() < 0.6 { DVec3::X } else { DVec3::Y };
            let axis = a.cross(helper).normalize();
            DQuat::from_xyzw(axis.x, axis.y, axis.z, 0.0)
        };
        let q = q.as_quat();
        if q.is_finite() {
            Ok(Self(q))
        } else {
            Err(DiffError::NonFinite)
        }
    }

    /// `R v`.
    #[inline]
    pub fn apply(&self, v: Vec3) -> Vec3 {
        self.0 * v
    }
}

/// Eq. 8.23: the area factor `k = 1/(4π p)` of a direction sampled from a phase function with
/// density `pdf` (sr⁻¹). An error for a density that is not positive and finite (a zero pdf:
/// the direction could not have been sampled).
pub fn phase_area_factor(pdf: f32) -> Result<f32, DiffError> {
    area_factor(pdf, 4.0 * std::f32::consts::PI)
}

/// Eq. 8.26: the area factor `k = 1/(2π p)` of a reflected direction sampled with density `pdf`
/// (sr⁻¹) over the hemisphere (cosine sampling: `k = 1/(2 cos θ')`). Errors as
/// [`phase_area_factor`].
pub fn surface_area_factor(pdf: f32) -> Result<f32, DiffError> {
    area_factor(pdf, 2.0 * std::f32::consts::PI)
}

fn area_factor(pdf: f32, solid_angle: f32) -> Result<f32, DiffError> {
    let k = 1.0 / (solid_angle * pdf);
    if pdf > 0.0 && k.is_finite() && k > 0.0 {
        Ok(k)
    } else {
        Err(DiffError::NonFinite)
    }
}

/// Eq. 8.23–8.24: the differential of a photon scattered at `ray.p` (the event, reached by
/// [`free_flight`]) into the unit direction `to` with area factor `k`: every differential
/// vector rotated by `R(ray.v → to)` ([`Rotation`]) and multiplied by `√k`.
pub fn scatter<const N: usize>(
    ray: &RayDiff<N>,
    to: Vec3,
    k: f32,
) -> Result<RayDiff<N>, DiffError> {
    if !(k > 0.0 && k.is_finite()) {
        return Err(DiffError::NonFinite);
    }
    let Some(to) = unit(to) else {
        return Err(DiffError::ZeroDirection);
    };
    let r = Rotation::between(ray.v, to)?;
    let sk = k.sqrt();
    let (mut dp, mut dv) = (ray.dp, ray.dv);
    for d in &mut dp {
        *d = r.apply(*d) * sk;
    }
    for d in &mut dv {
        let e = r.apply(*d) * sk;
        *d = e - to * to.dot(e); // exactly ⊥ `to` again after rounding (eq. B.1b)
    }
    RayDiff::new(ray.p, to, dp, dv).finite_or_err()
}

/// Eq. 8.25–8.26 with seed notes Q-M5: a photon whose differential `ray` arrived at a surface
/// (transferred onto its tangent plane, or moved there by [`free_flight`]: origin the hit, `V`
/// the incident direction; the two differ only along `V`) and is reflected into the unit
/// direction `to`, sampled by importance with area factor `k` ([`surface_area_factor`]): `dP`
/// projected onto the plane ⊥ `V`, then rotated and scaled as [`scatter`] does. The surface's
/// curvature is ignored, as in the thesis.
pub fn reflect_sampled<const N: usize>(
    ray: &RayDiff<N>,
    to: Vec3,
    k: f32,
) -> Result<RayDiff<N>, DiffError> {
    let v = ray.v;
    let mut dp = ray.dp;
    for d in &mut dp {
        *d -= v * v.dot(*d);
    }
    scatter(&RayDiff::new(ray.p, v, dp, ray.dv), to, k)
}

/// The photon solid angle (sr) below which, relative to a fresh one's, [`spread_collimated`]
/// counts a photon as collimated.
const COLLIMATED_RATIO: f32 = 1e-6;

/// **Extension** (not in the thesis, seed notes §2.4 [INF]): a *collimated* photon (its
/// directional vectors span no solid angle: a beam or directional light, only delta events
/// since) given the directional vectors of a point-light photon, so that the scattering that
/// follows ([`scatter`], [`reflect_sampled`]) spreads it. Under eq. 8.23–8.26 alone such a
/// photon keeps `D ω = 0` through every scattering event (`√k · R · 0 = 0`), so light scattered
/// out of a laser keeps the laser's cross-section forever (a few millimetres) and the smoke
/// around the beam is rendered as speckle. A point light's photons carry eq. 6's vectors,
/// orthogonal and of length `2 s √(4π/(π N_e))` = `point_length`; after an isotropic scattering
/// (`k = 1`) a photon that arrived with them spreads as if the event were a point light, which is
/// the reading given here to the collimated photon's scattering. Photons with any directional
/// spread are returned unchanged (the thesis's rule holds for them), as are the positional
/// vectors. The new vectors are `point_length` times an orthonormal basis ⊥ `V` (rad) whose
/// first vector is along `D_u x` (projected ⊥ `V`) and whose second is on `D_v x`'s side.
pub fn spread_collimated<const N: usize>(ray: &RayDiff<N>, point_length: f32) -> RayDiff<N> {
    if N < 2 || !(point_length > 0.0 && point_length.is_finite()) {
        return *ray;
    }
    let fresh = point_length * point_length;
    if ray.dv[0].cross(ray.dv[1]).length() > COLLIMATED_RATIO * fresh {
        return *ray;
    }
    // Paired with the positional vectors as eq. 2–3 pair a light's (D_θ ω ∥ D_u x, and D_φ ω on
    // D_v x's side), so that the footprint only grows over the next flight: an arbitrary basis
    // could point against D x and shrink it to nothing at some distance.
    let v = ray.v;
    let e0 = (ray.dp[0] - v * v.dot(ray.dp[0]))
        .try_normalize()
        .unwrap_or_else(|| caustica_core::Frame::from_normal(v).s);
    let mut e1 = v.cross(e0);
    if e1.dot(ray.dp[1]) < 0.0 {
        e1 = -e1;
    }
    let mut out = *ray;
    out.dv[0] = e0 * point_length;
    out.dv[1] = e1 * point_length;
    out
}

/// How [`volume_axes`] forms a stored photon's three vectors.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AxesRule {
    /// `D_u x`, `D_v x` projected onto the plane ⊥ ω first (seed notes Q-M3; default): the
    /// kernel is then between a sphere and an oblate spheroid, as sec. 8.4 says.
    #[default]
    Projected,
    /// The vectors as traced (sec. 8.4 literally).
    PaperLiteral,
}

/// The differential vectors `[D_u x, D_v x, D_w x]` (m) of a volume photon with traced
/// positional vectors `du`, `dv` (m) and unit direction `w` (sec. 8.4): `D_w x` along `w` with
/// length `max(|D_u x|, |D_v x|)` after the projection of [`AxesRule`]. An error if a vector
/// is not finite; a flat kernel (coplanar vectors) is left to the filter matrix to refuse.
pub fn volume_axes(du: Vec3, dv: Vec3, w: Vec3, rule: AxesRule) -> Result<[Vec3; 3], DiffError> {
    let Some(w) = unit(w) else {
        return Err(DiffError::ZeroDirection);
    };
    let (du, dv) = match rule {
        AxesRule::Projected => (du - w * w.dot(du), dv - w * w.dot(dv)),
        AxesRule::PaperLiteral => (du, dv),
    };
    let dw = w * du.length().max(dv.length());
    let axes = [du, dv, dw];
    if all_finite3(&axes) {
        Ok(axes)
    } else {
        Err(DiffError::NonFinite)
    }
}

/// The minimum semi-axis shared by volume kernels (seed 000 Q-M9) and surface footprints: the
/// conjugate diameters `du`, `dv` (m, in the plane ⊥ unit `normal`) of an ellipse whose minor
/// principal semi-axis is below `min_semi_axis` (m), replaced by its principal diameters with
/// each semi-axis raised to at least `min_semi_axis` (the principal directions and the major
/// semi-axis kept, so the new ellipse contains the old one); `None` when the minor semi-axis is
/// already that long (keep `du`, `dv` as they are). Parallel vectors keep the longer one as the
/// major axis, the minor across it; two zero vectors give a disc of radius `min_semi_axis`.
pub fn widen_ellipse(du: Vec3, dv: Vec3, normal: Vec3, min_semi_axis: f32) -> Option<[Vec3; 2]> {
    let (axes, dirs) = ellipse_principal_axes(du * 0.5, dv * 0.5).unwrap_or_else(|| {
        let long = if du.length_squared() >= dv.length_squared() {
            du
        } else {
            dv
        };
        match long.try_normalize() {
            Some(d0) => (
                [0.5 * long.length(), 0.0],
                [
                    d0,
                    normal
                        .cross(d0)
                        .try_normalize()
                        .unwrap_or(d0.any_orthonormal_vector()),
                ],
            ),
            None => {
                let f = caustica_core::Frame::from_normal(normal);
                ([0.0; 2], [f.s, f.t])
            }
        }
    });
    (axes[1] < min_semi_axis).then(|| {
        [
            dirs[0] * (2.0 * axes[0].max(min_semi_axis)),
            dirs[1] * (2.0 * axes[1].max(min_semi_axis)),
        ]
    })
}

/// The semi-axes `(a, b)` (m, `a ≥ b`) and unit principal directions of the ellipse spanned by
/// the conjugate semi-diameters `u`, `v` (m): the square roots of the eigenvalues of
/// `u uᵀ + v vᵀ` restricted to their plane. `None` if they are parallel or zero.
pub fn ellipse_principal_axes(u: Vec3, v: Vec3) -> Option<([f32; 2], [Vec3; 2])> {
    let (u, v) = (u.as_dvec3(), v.as_dvec3());
    let e1 = u.try_normalize().or_else(|| v.try_normalize())?;
    let e2 = (v - e1 * e1.dot(v))
        .try_normalize()
        .or_else(|| (u - e1 * e1.dot(u)).try_normalize())?;
    // S = u uᵀ + v vᵀ in the basis (e1, e2).
    let (u1, u2, v1, v2) = (u.dot(e1), u.dot(e2), v.dot(e1), v.dot(e2));
    let (a, b, c) = (u1 * u1 + v1 * v1, u1 * u2 + v1 * v2, u2 * u2 + v2 * v2);
    let mean = 0.5 * (a + c);
    let rad = (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let (l1, l2) = (mean + rad, (mean - rad).max(0.0));
    // Eigenvector of the larger eigenvalue in (e1, e2) coordinates.
    let (x, y) = if b.abs() > 1e-300 {
        (l1 - c, b)
    } else if a >= c {
        (1.0, 0.0)
    } else {
        (0.0, 1.0)
    };
    let d1 = (e1 * x + e2 * y).try_normalize()?;
    let d2 = e1.cross(e2).cross(d1).normalize();
    let axes = [l1.sqrt() as f32, l2.sqrt() as f32];
    (axes[1] > 0.0 && axes[0].is_finite()).then_some((axes, [d1.as_vec3(), d2.as_vec3()]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::{Pcg32, warp};
    use caustica_scene::phase::{Phase, PhaseFunction};

    fn rand_unit(rng: &mut Pcg32) -> Vec3 {
        warp::square_to_uniform_sphere(caustica_core::Vec2::new(rng.next_f32(), rng.next_f32()))
    }

    fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
        (a - b).length() <= tol * (1.0 + a.length().max(b.length()))
    }

    #[test]
    fn rotation_maps_the_direction_and_keeps_lengths_and_angles() {
        // TM8: R ω = ω', |R x| = |x|, x ⊥ ω ⇒ R x ⊥ ω', and the degenerate cases.
        let mut rng = Pcg32::new(7, 1);
        for i in 0..2000 {
            let a = rand_unit(&mut rng);
            let b = match i % 4 {
                0 => a,
                1 => -a,
                2 => (-a + Vec3::splat(1e-5)).normalize(), // nearly opposite
                _ => rand_unit(&mut rng),
            };
            let r = Rotation::between(a, b).unwrap();
            assert!(close(r.apply(a), b, 2e-6), "{a} → {b}: {}", r.apply(a));
            let x = rand_unit(&mut rng) * 3.0;
            let rx = r.apply(x);
            assert!(rx.is_finite());
            assert!((rx.length() - 3.0).abs() < 1e-5);
            let perp = x - a * a.dot(x);
            assert!(r.apply(perp).dot(b).abs() < 1e-5 * (1.0 + perp.length()));
            if i % 4 == 0 {
                assert!(close(rx, x, 1e-6), "identity");
            }
        }
        assert!(Rotation::between(Vec3::ZERO, Vec3::X).is_err());
        assert!(Rotation::between(Vec3::X, Vec3::NAN).is_err());
    }

    #[test]
    fn free_flight_matches_finite_differences_of_neighbouring_rays() {
        // TM9: two neighbouring rays θ ± ε propagated the same distance s; the central
        // difference is exact for a straight line (the error is rounding only, O(ε²) in
        // general).
        let mut rng = Pcg32::new(3, 9);
        for _ in 0..200 {
            let p = rand_unit(&mut rng);
            let v = rand_unit(&mut rng);
            let dp = [rand_unit(&mut rng) * 0.3, rand_unit(&mut rng) * 0.2];
            let dv = dp.map(|_| {
                let d = rand_unit(&mut rng);
                (d - v * v.dot(d)) * 0.5
            });
            let ray = RayDiff::new(p, v, dp, dv);
            let s = 4.0 * rng.next_f32();
            let out = free_flight(&ray, s).unwrap();
            let eps = 1e-3f32;
            for i in 0..2 {
                let at = |sign: f32| {
                    let p = ray.p + ray.dp[i] * (sign * eps);
                    let d = (ray.v + ray.dv[i] * (sign * eps)).normalize();
                    (p + d * s, d)
                };
                let (p1, d1) = at(1.0);
                let (p0, d0) = at(-1.0);
                let fd_p = (p1 - p0) / (2.0 * eps);
                let fd_v = (d1 - d0) / (2.0 * eps);
                assert!(close(out.dp[i], fd_p, 2e-3), "{} vs {fd_p}", out.dp[i]);
                assert!(close(out.dv[i], fd_v, 2e-3), "{} vs {fd_v}", out.dv[i]);
            }
            assert!(close(out.p, p + v * s, 1e-6));
        }
        assert!(free_flight(&RayDiff::<2>::constant(Vec3::ZERO, Vec3::X), f32::NAN).is_err());
    }

    #[test]
    fn refraction_into_a_medium_then_free_flight_matches_finite_differences() {
        // The acceptance test of a photon entering a medium: neighbours offset by ±ε in u and v
        // are traced exactly (in f64: the plane z = 0, Snell's law, then the same flight s from
        // their own hit points, eq. 8.21's ds → 0), and their central difference matches the
        // propagated differential to O(ε²): halving ε divides the error by about 4 until the
        // f32 floor.
        use crate::FlatTriangle;
        use glam::DVec3;
        let tri = FlatTriangle {
            q: [
                Vec3::new(-5.0, -5.0, 0.0),
                Vec3::new(5.0, -5.0, 0.0),
                Vec3::new(0.0, 5.0, 0.0),
            ],
        };
        let eta = 1.0 / 1.33f64; // n_incident / n_transmitted
        let p = Vec3::new(0.1, -0.2, 1.5);
        let v = Vec3::new(0.35, 0.2, -1.0).normalize();
        let perp = |d: Vec3| (d - v * v.dot(d)).normalize();
        // Diverging from a point 0.5 m behind the origin, so refraction and flight both matter.
        let dv = [perp(Vec3::X) * 0.4, perp(Vec3::Y) * 0.3];
        let dp = [dv[0] * 0.5 + perp(Vec3::Y) * 0.05, dv[1] * 0.5];
        let ray = RayDiff::new(p, v, dp, dv);
        let s = 0.8f32;
        let hit = tri.hit(&ray).unwrap();
        let inside = free_flight(&hit.refract(eta as f32).unwrap(), s).unwrap();
        // The exact path of a neighbour: origin and direction perturbed by e along parameter i.
        let exact = |i: usize, e: f64| -> (DVec3, DVec3) {
            let o = p.as_dvec3() + dp[i].as_dvec3() * e;
            let d = (v.as_dvec3() + dv[i].as_dvec3() * e).normalize();
            let q = o + d * (-o.z / d.z); // the plane z = 0
            let n = DVec3::Z; // facing the incident ray: V·N < 0
            let c = -d.dot(n);
            let k = 1.0 - eta * eta * (1.0 - c * c);
            let w = d * eta + n * (eta * c - k.sqrt());
            (q + w * s as f64, w)
        };
        for i in 0..2 {
            let err = |e: f64| {
                let ((p1, w1), (p0, w0)) = (exact(i, e), exact(i, -e));
                let fd_p = (p1 - p0) / (2.0 * e);
                let fd_w = (w1 - w0) / (2.0 * e);
                (fd_p - inside.dp[i].as_dvec3())
                    .length()
                    .max((fd_w - inside.dv[i].as_dvec3()).length())
            };
            let (e1, e2, e3) = (err(0.04), err(0.02), err(0.01));
            assert!(e3 < 2e-3, "parameter {i}: error {e3} at ε = 0.01");
            // Second order: the error falls by ~4 per halving (well above the f32 floor here).
            assert!(
                e2 < 0.35 * e1 + 2e-5 && e3 < 0.35 * e2 + 2e-5,
                "{i}: {e1} {e2} {e3}"
            );
        }
    }

    #[test]
    fn area_factors_have_expectation_one() {
        // TM7: E[k] = 1 for eq. 8.23 under the phase function's own sampling (isotropic and
        // HG at several g) and for eq. 8.26 under cosine sampling, by Monte Carlo.
        let n = 400_000;
        for g in [-0.5f32, 0.0, 0.3, 0.8] {
            let phase = if g == 0.0 {
                PhaseFunction::default()
            } else {
                PhaseFunction::henyey_greenstein(g).unwrap()
            };
            let mut rng = Pcg32::new(11, g.to_bits() as u64);
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let u = caustica_core::Vec2::new(rng.next_f32(), rng.next_f32());
                let ps = phase.sample(Vec3::Z, u).unwrap();
                let k = phase_area_factor(ps.pdf).unwrap() as f64;
                sum += k;
                sum2 += k * k;
            }
            let mean = sum / n as f64;
            let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
            // The HG factor is bounded ((1+|g|)³/(1−g²) at most), so the mean is normal.
            assert!(
                (mean - 1.0).abs() < 5.0 * se + 1e-9,
                "g = {g}: E[k] = {mean} ± {se}"
            );
            if g == 0.0 {
                assert!((mean - 1.0).abs() < 1e-6, "isotropic: k ≡ 1");
            }
        }
        // Cosine sampling: k = 1/(2 cos θ) has a finite mean and an infinite variance
        // (P(k > K) = 1/(4K²)), so the tolerance is not a standard error: the truncated tail
        // beyond K_max = √n contributes ≤ 1/(2√n), and the rest has variance ≤ ln(K_max)/2.
        let mut rng = Pcg32::new(5, 5);
        let n = 1_000_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let w = warp::square_to_cosine_hemisphere(caustica_core::Vec2::new(
                rng.next_f32(),
                rng.next_f32(),
            ));
            let pdf = warp::cosine_hemisphere_pdf(w);
            sum += surface_area_factor(pdf).map_or(0.0, f64::from);
        }
        let mean = sum / n as f64;
        let tol = 0.5 / (n as f64).sqrt() + 5.0 * ((n as f64).sqrt().ln() / 2.0 / n as f64).sqrt();
        assert!((mean - 1.0).abs() < tol, "cosine: E[k] = {mean}, tol {tol}");
        assert!(phase_area_factor(0.0).is_err() && surface_area_factor(f32::NAN).is_err());
    }

    #[test]
    fn scattering_rotates_into_the_new_direction_and_scales_the_area_by_k() {
        // TM7's per-sample part and eq. 8.24: |D_u x' × D_v x'| = k |D_u x × D_v x|.
        let mut rng = Pcg32::new(21, 2);
        for i in 0..500 {
            let v = rand_unit(&mut rng);
            let perp = |rng: &mut Pcg32| {
                let d = rand_unit(rng);
                d - v * v.dot(d)
            };
            let ray = RayDiff::new(
                Vec3::ONE,
                v,
                [perp(&mut rng), perp(&mut rng)],
                [perp(&mut rng) * 0.1, perp(&mut rng) * 0.1],
            );
            let to = if i % 10 == 0 { -v } else { rand_unit(&mut rng) };
            let k = 0.1 + 3.0 * rng.next_f32();
            let out = scatter(&ray, to, k).unwrap();
            assert!(close(out.v, to, 1e-6));
            let a0 = ray.dp[0].cross(ray.dp[1]).length();
            let a1 = out.dp[0].cross(out.dp[1]).length();
            // Rounding of the rotation relative to the vectors' lengths (the cross product of
            // nearly parallel vectors cancels).
            let scale = k * ray.dp[0].length() * ray.dp[1].length();
            assert!((a1 - k * a0).abs() <= 1e-5 * scale, "{a1} vs {}", k * a0);
            // Vectors ⊥ the old direction end ⊥ the new one.
            for d in out.dp.iter().chain(&out.dv) {
                assert!(d.dot(to).abs() < 1e-5 * (1.0 + d.length()));
            }
            assert!(out.p == ray.p);
        }
        let ray = RayDiff::<2>::constant(Vec3::ZERO, Vec3::X);
        assert!(scatter(&ray, Vec3::Y, 0.0).is_err());
        assert!(scatter(&ray, Vec3::ZERO, 1.0).is_err());
    }

    #[test]
    fn collimated_photons_spread_like_a_point_lights_and_others_are_left_alone() {
        // A collimated photon (D ω = 0) gets eq. 6's point-light vectors: photon solid angle
        // (π/4)|D_θ ω × D_φ ω| = s² 4π / N_e (here N_e = 1, s = 3), ⊥ V, paired with D x so
        // that its footprint grows monotonically over any flight, and after an isotropic
        // scattering (k = 1) the same solid angle. A photon with spread is unchanged.
        use crate::EmissionBudget;
        let s = 3.0f32;
        let len = EmissionBudget::new(1, s)
            .unwrap()
            .differential_length(4.0 * std::f32::consts::PI)
            .unwrap();
        let mut rng = Pcg32::new(4, 4);
        for _ in 0..200 {
            let v = rand_unit(&mut rng);
            let f = caustica_core::Frame::from_normal(v);
            let a = rng.next_f32() * std::f32::consts::TAU;
            let (c, sn) = (a.cos(), a.sin());
            // The beam's cross-section vectors (orthogonal, 2 mm), turned by a random angle.
            let dp = [
                (f.s * c + f.t * sn) * 0.002,
                (f.t * c - f.s * sn) * 0.002 * if rng.next_f32() < 0.5 { 1.0 } else { -1.0 },
            ];
            let ray = RayDiff::new(Vec3::ZERO, v, dp, [Vec3::ZERO; 2]);
            let out = spread_collimated(&ray, len);
            let omega = std::f32::consts::FRAC_PI_4 * out.dv[0].cross(out.dv[1]).length();
            let want = s * s * 4.0 * std::f32::consts::PI;
            assert!((omega - want).abs() < 1e-4 * want, "{omega} vs {want}");
            assert_eq!(out.dp, ray.dp);
            for d in out.dv {
                assert!(d.dot(v).abs() < 1e-5 * len);
            }
            // The footprint area grows with the flight distance, never through zero.
            let area = |t: f32| {
                let r = free_flight(&out, t).unwrap();
                r.dp[0].cross(r.dp[1]).length()
            };
            let mut last = area(0.0);
            for t in [1e-4f32, 1e-3, 1e-2, 0.1, 1.0] {
                let a = area(t);
                assert!(a > last, "area {a} after {t} m, {last} before");
                last = a;
            }
            // Scattering isotropically (k = 1) keeps that solid angle.
            let sc = scatter(&out, rand_unit(&mut rng), 1.0).unwrap();
            let omega = std::f32::consts::FRAC_PI_4 * sc.dv[0].cross(sc.dv[1]).length();
            assert!((omega - want).abs() < 1e-3 * want, "{omega} vs {want}");
            // A photon that already spreads (any light but a collimated one) is left alone.
            let spread = RayDiff::new(Vec3::ZERO, v, dp, [f.s * 0.1 * len, f.t * 0.1 * len]);
            assert_eq!(spread_collimated(&spread, len), spread);
        }
    }

    #[test]
    fn sampled_reflection_projects_the_tangent_footprint_onto_the_beam() {
        // A beam falling at 60° onto the plane z = 0: its tangent-plane vectors are the
        // cross-section stretched by 1/cos; projected ⊥ V they are the cross-section again.
        let v = Vec3::new(3f32.sqrt() / 2.0, 0.0, -0.5); // 60° from the normal
        let cross_section = [Vec3::new(0.5, 0.0, 3f32.sqrt() / 2.0) * 0.1, Vec3::Y * 0.1];
        // On the plane: along v's tangent direction, length 0.1/cos 60°.
        let tangent = [Vec3::X * 0.2, Vec3::Y * 0.1];
        let ray = RayDiff::new(Vec3::ZERO, v, tangent, [Vec3::ZERO; 2]);
        let out = reflect_sampled(&ray, Vec3::Z, 1.0).unwrap();
        let a = out.dp[0].cross(out.dp[1]).length();
        let want = cross_section[0].cross(cross_section[1]).length();
        assert!((a - want).abs() < 1e-6, "{a} vs {want}");
        assert!(out.dp.iter().all(|d| d.dot(Vec3::Z).abs() < 1e-6));
    }

    #[test]
    fn volume_axes_follow_sec_8_4() {
        // TM10: D_w x along ω with length max(|D_u|, |D_v|); equal orthogonal D_u, D_v ⊥ ω
        // give a sphere (three orthogonal equal vectors).
        let w = Vec3::new(0.0, 0.6, 0.8);
        let du = Vec3::X * 0.3;
        let dv = w.cross(du);
        let [a, b, c] = volume_axes(du, dv, w, AxesRule::Projected).unwrap();
        assert!(close(c, w * 0.3, 1e-6));
        for (x, y) in [(a, b), (a, c), (b, c)] {
            assert!(x.dot(y).abs() < 1e-6);
        }
        assert!((a.length() - 0.3).abs() < 1e-6 && (b.length() - 0.3).abs() < 1e-6);
        // Vectors with a component along ω: projected by default, kept as traced literally.
        let tilted = du + w * 0.2;
        let p = volume_axes(tilted, dv * 2.0, w, AxesRule::Projected).unwrap();
        assert!(p[0].dot(w).abs() < 1e-6 && close(p[2], w * 0.6, 1e-6));
        let l = volume_axes(tilted, dv, w, AxesRule::PaperLiteral).unwrap();
        assert!(close(l[0], tilted, 0.0) && close(l[2], w * tilted.length(), 1e-6));
        assert!(volume_axes(Vec3::NAN, dv, w, AxesRule::Projected).is_err());
        assert!(volume_axes(du, dv, Vec3::ZERO, AxesRule::Projected).is_err());
    }

    #[test]
    fn principal_axes_of_conjugate_semi_diameters() {
        let mut rng = Pcg32::new(1, 4);
        for _ in 0..500 {
            let u = rand_unit(&mut rng) * (0.1 + rng.next_f32());
            let v = rand_unit(&mut rng) * (0.1 + rng.next_f32());
            let ([a, b], [d1, d2]) = ellipse_principal_axes(u, v).unwrap();
            // Same area (π a b = π |u × v|) and the same sum of squares (a² + b² = |u|² + |v|²).
            assert!((a * b - u.cross(v).length()).abs() < 1e-4 * (a * b).max(1e-3));
            assert!((a * a + b * b - u.length_squared() - v.length_squared()).abs() < 1e-4);
            assert!(a >= b && d1.dot(d2).abs() < 1e-5);
            // The principal directions lie in the plane of u and v.
            let n = u.cross(v).normalize();
            assert!(d1.dot(n).abs() < 1e-4 && d2.dot(n).abs() < 1e-4);
        }
        assert!(ellipse_principal_axes(Vec3::X, Vec3::X * 2.0).is_none());
    }
}
