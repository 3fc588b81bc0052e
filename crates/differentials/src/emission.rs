//! Emission of photon differentials from arbitrary lights (seed 002 sec. 3.1, eq. 1–6; seed 000
//! sec. 5.2.1, eq. 5.2–5.7).
//!
//! An emitted photon is the ray `r(u, v; θ, φ) = x(u, v) + t′ ω(θ, φ)` of eq. 1: its origin is
//! parameterised by the light's surface (u, v), its direction by the emission solid angle
//! (θ, φ). Seed 002 chooses the four initial differential vectors *pairwise parallel*:
//!
//! * `D_u x / |D_u x| = D_θ ω / |D_θ ω| = (n × ω) / |n × ω|` (eq. 2),
//! * `D_v x / |D_v x| = (D_u x / |D_u x|) × n`, `D_φ ω / |D_φ ω| = (D_θ ω / |D_θ ω|) × ω`
//!   (eq. 3),
//!
//! so that after the first transfer `D_θ x′ ∥ D_u x′` and `D_φ x′ ∥ D_v x′` (seed 002 app. A)
//! and the Minkowski sum of the positional and directional footprints is the parallelogram
//! spanned by `(D_u + D_θ) x′` and `(D_v + D_φ) x′` (eq. 7). That is why a photon differential
//! is a [`RayDiff<2>`] here: parameter 0 is the pair (u, θ) with `dp[0] = D_u x`,
//! `dv[0] = D_θ ω`; parameter 1 is the pair (v, φ) with `dp[1] = D_v x`, `dv[1] = D_φ ω`.
//! Transferring it with [`crate::transfer_to_plane`] (or a [`crate::FlatTriangle`] hit) gives
//! eq. 8 + eq. 9 summed, i.e. eq. 7. The parameters are dimensionless offsets measured in
//! differential vectors: the vectors are Suykens' "differential vectors" (seed 000 sec. 5.1),
//! `dp` in m and `dv` in rad (unit direction change), not per-steradian densities.
//!
//! # Lengths (eq. 4–6)
//!
//! The photon footprint is the ellipse inscribed in the parallelogram of the positional vectors,
//! of area `A_p = π/4 |D_u x × D_v x|` (eq. 4); by analogy the photon solid angle is
//! `ω_p = π/4 |D_θ ω × D_φ ω|` (unnumbered, after eq. 4). Seed 002 asks that the `N_e` emitted
//! photons' initial footprints sum to `s² A_e` and their solid angles to `s² ω_e`. Since the
//! vectors start orthogonal and of equal length `L`, `N_e π L² / 4 = s² A_e`, hence
//!
//! * `|D_u x| = |D_v x| = 2 s √(A_e / (π N_e))` (eq. 5, m),
//! * `|D_θ ω| = |D_φ ω| = 2 s √(ω_e / (π N_e))` (eq. 6, rad),
//!
//! which the tests check as `N_e A_p = s² A_e` and `N_e ω_p = s² ω_e`. A point light has
//! `A_e = 0` (zero positional vectors), a directional or collimated light `ω_e = 0` (zero
//! directional vectors). The extents per light (what `LightSource::emission_extent` in
//! `caustica-scene` reports): point `ω_e = 4π`; spot `ω_e = 2π(1 − cos θ_cutoff)`;
//! directional `A_e` = the emission disk over the scene; beam `A_e = π r²`; diffuse area light
//! `A_e` = its area, `ω_e = 2π` (one-sided) or `4π` (two-sided).
//!
//! # Orientation of the normal
//!
//! Eq. 2–3 give the same *lines* for either sign of `n`, but eq. 7 needs the paired vectors to
//! point the same way after transfer, not opposite ways (else the sum of eq. 7 would shrink the
//! footprint to `||D_v x′| − |D_φ x′||`). Writing `n = cos α ω + sin α b` with `b ⟂ ω` gives
//! `D_v x′ = −|D_v x| cos α P(b)` and `D_φ x′ = −t′ |D_φ ω| P(b)` (P: the transfer projection of
//! eq. 8), so they agree in sign exactly when `n · ω > 0`. The normal is therefore turned
//! towards the emitted direction (this matters for two-sided emitters); the test
//! `pairs_are_parallel_after_first_transfer` checks it on both sides.
//!
//! The photon's flux is `Φ_p = Φ_l / N_e` for every light type (eq. 5.4, 5.7), see
//! [`EmissionBudget::photon_flux`]; its irradiance on a receiver is `Φ_p / A_p′`
//! (eq. 5.5, [`crate::Footprint::irradiance`]).

use std::f64::consts::PI;

use caustica_core::{Frame, Vec3};

use crate::ray_differential::unit;
use crate::transfer::PARALLEL_COS;
use crate::{DiffError, RayDiff};

/// `|n × ω|` at or below which the emitted direction counts as (almost) along the normal, so
/// that eq. 2's `n × ω / |n × ω|` is numerically unreliable; seed 002 then builds the bases from
/// an orthonormal frame (sec. 3.1, after eq. 3). Within this angle (~0.06°) the fallback's
/// positional and directional vectors are parallel to `O(10⁻³)`.
pub const NORMAL_ALIGNED_SIN: f32 = 1e-3;

/// The photon count `N_e` and smoothing parameter `s` of seed 002 eq. 5–6, validated
/// (`N_e > 0`, `s` finite and `> 0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmissionBudget {
    photons: u64,
    smoothing: f32,
}

impl EmissionBudget {
    /// `photons` = `N_e`, the number of photons emitted from the light (for this map);
    /// `smoothing` = `s` (unitless; seed 002 found 5–40 to work well, sec. 3.3).
    ///
    /// Errors: [`DiffError::NoPhotons`] if `photons == 0`, [`DiffError::InvalidSmoothing`] if
    /// `s` is not finite or `s ≤ 0`.
    pub fn new(photons: u64, smoothing: f32) -> Result<Self, DiffError> {
        if photons == 0 {
            return Err(DiffError::NoPhotons);
        }
        if !(smoothing > 0.0 && smoothing.is_finite()) {
            return Err(DiffError::InvalidSmoothing);
        }
        Ok(Self { photons, smoothing })
    }

    /// `N_e`.
    pub fn photons(&self) -> u64 {
        self.photons
    }

    /// `s`.
    pub fn smoothing(&self) -> f32 {
        self.smoothing
    }

    /// Initial length `2 s √(extent / (π N_e))` of a differential vector: eq. 5 for an area
    /// `extent = A_e` (m² → m), eq. 6 for a solid angle `extent = ω_e` (sr → rad). Zero for a
    /// zero extent (point lights have no positional, collimated lights no directional vectors).
    ///
    /// Errors: [`DiffError::InvalidExtent`] if `extent` is negative or not finite.
    pub fn differential_length(&self, extent: f32) -> Result<f32, DiffError> {
        if !(extent >= 0.0 && extent.is_finite()) {
            return Err(DiffError::InvalidExtent);
        }
        // eq. 5 / eq. 6, in f64 so that large N_e lose nothing.
        let len = 2.0 * self.smoothing as f64 * (extent as f64 / (PI * self.photons as f64)).sqrt();
        Ok(len as f32)
    }

    /// The lengths `(|D_u x|, |D_θ ω|)` of eq. 5 and eq. 6 for a light whose photon origins
    /// cover area `area` (`A_e`, m²) and whose directions cover `solid_angle` (`ω_e`, sr).
    ///
    /// Errors: [`DiffError::InvalidExtent`] if an extent is negative or not finite,
    /// `solid_angle > 4π`, or both are zero (the photon would have no footprint at any
    /// distance).
    pub fn emission_lengths(&self, area: f32, solid_angle: f32) -> Result<(f32, f32), DiffError> {
        if solid_angle > 4.0 * std::f32::consts::PI * (1.0 + 1e-6) {
            return Err(DiffError::InvalidExtent);
        }
        let lx = self.differential_length(area)?; // eq. 5
        let lw = self.differential_length(solid_angle)?; // eq. 6
        if !(lx > 0.0 || lw > 0.0) {
            return Err(DiffError::InvalidExtent);
        }
        Ok((lx, lw))
    }

    /// Flux of one photon, `Φ_p = Φ_l / N_e` (W), for a light of power `power` (W): eq. 5.4 for
    /// a point light (`Φ_pd = A_pd M_total` with `A_pd = 4π/n_pd`, `M_total = Φ_l/4π`,
    /// eq. 5.2–5.3) and eq. 5.7 for an area light (`A_pd = A_l/n_pd`, `M_total = Φ_l/A_l`,
    /// eq. 5.6). It does not depend on `s` (seed 002 sec. 3.3: the kernels are normalised, so
    /// `s` trades variance for bias without changing the energy).
    pub fn photon_flux(&self, power: f32) -> f32 {
        (power as f64 / self.photons as f64) as f32
    }
}

/// The unit directions of the four initial differential vectors (eq. 2–3): `u` and `v` span the
/// emitter's tangent plane, `theta` and `phi` the plane perpendicular to the direction, with
/// `u ∥ theta` (eq. 2), `v = u × n`, `phi = theta × ω` (eq. 3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmissionBasis {
    /// `D_u x / |D_u x|`.
    pub u: Vec3,
    /// `D_v x / |D_v x|`.
    pub v: Vec3,
    /// `D_θ ω / |D_θ ω|`.
    pub theta: Vec3,
    /// `D_φ ω / |D_φ ω|`.
    pub phi: Vec3,
    /// The emitter normal used, unit and turned towards the direction (`n · ω > 0`); the
    /// direction itself for a source without a normal.
    pub normal: Vec3,
    /// The unit direction ω.
    pub direction: Vec3,
}

/// The bases of eq. 2–3 for unit direction `direction` (ω) leaving an emitter with normal
/// `normal` (`None` for a source without a surface: point and spot lights, and the beam or
/// directional aperture perpendicular to ω, for which `n = ω` is used).
///
/// * `|n × ω| > NORMAL_ALIGNED_SIN`: `u = theta = n × ω / |n × ω|` (eq. 2), `v = u × n`,
///   `phi = theta × ω` (eq. 3).
/// * Otherwise (ω ≈ n, or no normal): `u` is the first tangent of the orthonormal frame of `n`
///   ([`Frame::from_normal`], Duff et al. 2017, the revision of seed 002's ref. Fri12a), `theta`
///   is `u` made perpendicular to ω, and eq. 3 gives `v` and `phi`.
///
/// `normal` is normalised and turned towards ω (see the module docs). Errors:
/// [`DiffError::ZeroDirection`] (zero or non-finite ω), [`DiffError::DegenerateNormal`] (zero
/// or non-finite normal), [`DiffError::Parallel`] if `|n · ω| ≤ PARALLEL_COS` (tangential
/// emission, no cross-section).
pub fn emission_basis(direction: Vec3, normal: Option<Vec3>) -> Result<EmissionBasis, DiffError> {
    let w = unit(direction).ok_or(DiffError::ZeroDirection)?;
    let n = match normal {
        None => w,
        Some(n) => unit(n).ok_or(DiffError::DegenerateNormal)?,
    };
    let cos = n.dot(w);
    if !(cos.abs() > PARALLEL_COS) {
        return Err(DiffError::Parallel);
    }
    let n = if cos < 0.0 { -n } else { n };
    let c = n.cross(w);
    let len = c.length();
    let (u, theta) = if len > NORMAL_ALIGNED_SIN {
        let a = c / len; // eq. 2
        (a, a)
    } else {
        // ω ≈ n or no normal: an orthonormal basis from a 3-D vector (seed 002 after eq. 3).
        let u = Frame::from_normal(n).s;
        let theta = (u - w * w.dot(u)).normalize();
        (u, theta)
    };
    Ok(EmissionBasis {
        u,
        v: u.cross(n), // eq. 3, left
        theta,
        phi: theta.cross(w), // eq. 3, right
        normal: n,
        direction: w,
    })
}

/// The initial photon differential of a photon leaving `origin` (m) in direction `direction`
/// (normalised here) from a light whose photon origins are spread over area `area` (`A_e`, m²)
/// and whose directions around each origin cover solid angle `solid_angle` (`ω_e`, sr), with
/// emitter normal `normal` (`None` for a source without a surface):
///
/// `dp = [|D_u x| u, |D_v x| v]`, `dv = [|D_θ ω| θ̂, |D_φ ω| φ̂]` with the directions of
/// [`emission_basis`] (eq. 2–3) and the lengths of [`EmissionBudget::differential_length`]
/// (eq. 5–6).
///
/// Errors: those of [`emission_basis`]; [`DiffError::InvalidExtent`] if an extent is negative,
/// not finite, `solid_angle > 4π`, or both are zero (the photon would have no footprint at any
/// distance); [`DiffError::NonFinite`] for a non-finite origin.
pub fn emit(
    origin: Vec3,
    direction: Vec3,
    normal: Option<Vec3>,
    area: f32,
    solid_angle: f32,
    budget: &EmissionBudget,
) -> Result<RayDiff<2>, DiffError> {
    if !origin.is_finite() {
        return Err(DiffError::NonFinite);
    }
    let lengths = budget.emission_lengths(area, solid_angle)?;
    emit_with_lengths(origin, direction, normal, lengths)
}

/// [`emit`] with the vector lengths `(|D_u x|, |D_θ ω|)` of
/// [`EmissionBudget::emission_lengths`] computed once per light (they do not depend on the
/// photon): what a photon tracer calls per photon.
///
/// Errors: those of [`emission_basis`]; [`DiffError::NonFinite`] for a non-finite origin.
pub fn emit_with_lengths(
    origin: Vec3,
    direction: Vec3,
    normal: Option<Vec3>,
    (lx, lw): (f32, f32),
) -> Result<RayDiff<2>, DiffError> {
    if !origin.is_finite() {
        return Err(DiffError::NonFinite);
    }
    emit_with_basis(origin, &emission_basis(direction, normal)?, (lx, lw)) // eq. 2–3
}

/// [`emit_with_lengths`] with the basis of eq. 2–3 already computed ([`emission_basis`]): for
/// collimated lights, whose photons all share one direction and normal, and so one basis.
pub fn emit_with_basis(
    origin: Vec3,
    b: &EmissionBasis,
    (lx, lw): (f32, f32),
) -> Result<RayDiff<2>, DiffError> {
    RayDiff::new(
        origin,
        b.direction,
        [lx * b.u, lx * b.v],
        [lw * b.theta, lw * b.phi],
    )
    .finite_or_err()
}

/// Isotropic point light at `origin` (m): no positional differentials (`A_e = 0`, eq. 5),
/// directional ones from `ω_e = 4π` sr (eq. 6), `|D_θ ω| = 4 s / √N_e`.
pub fn emit_point(
    origin: Vec3,
    direction: Vec3,
    budget: &EmissionBudget,
) -> Result<RayDiff<2>, DiffError> {
    emit(
        origin,
        direction,
        None,
        0.0,
        4.0 * std::f32::consts::PI,
        budget,
    )
}

/// Spot light at `origin` (m) whose photons are emitted within the cone of half-angle
/// `θ_cutoff` (`cos_cutoff = cos θ_cutoff ∈ [−1, 1)`): like [`emit_point`] with
/// `ω_e = 2π (1 − cos θ_cutoff)` sr (eq. 6). `direction` is the sampled direction inside the
/// cone; only the cone's solid angle enters.
///
/// Errors: [`DiffError::InvalidExtent`] if `cos_cutoff ∉ [−1, 1)`; those of [`emit`].
pub fn emit_spot(
    origin: Vec3,
    direction: Vec3,
    cos_cutoff: f32,
    budget: &EmissionBudget,
) -> Result<RayDiff<2>, DiffError> {
    if !((-1.0..1.0).contains(&cos_cutoff)) {
        return Err(DiffError::InvalidExtent);
    }
    let omega = 2.0 * std::f32::consts::PI * (1.0 - cos_cutoff);
    emit(origin, direction, None, 0.0, omega, budget)
}

/// Directional (collimated, infinitely distant) light whose photons start at `origin` (m) on an
/// emission disk of area `area` (m², e.g. `π r²` of the scene's bounding disk) perpendicular to
/// `direction`: positional differentials only (eq. 5 with `A_e = area`, `ω_e = 0`), spanning
/// the disk's plane.
pub fn emit_directional(
    origin: Vec3,
    direction: Vec3,
    area: f32,
    budget: &EmissionBudget,
) -> Result<RayDiff<2>, DiffError> {
    emit(origin, direction, None, area, 0.0, budget)
}

/// Collimated beam ("laser") of radius `radius` (m): positional differentials from the
/// aperture's area `A_e = π r²` (eq. 5), `|D_u x| = 2 s r / √N_e`; no directional ones.
///
/// Errors: [`DiffError::InvalidExtent`] if `radius` is not finite and `> 0`.
pub fn emit_beam(
    origin: Vec3,
    direction: Vec3,
    radius: f32,
    budget: &EmissionBudget,
) -> Result<RayDiff<2>, DiffError> {
    if !(radius > 0.0 && radius.is_finite()) {
        return Err(DiffError::InvalidExtent);
    }
    emit_directional(
        origin,
        direction,
        std::f32::consts::PI * radius * radius,
        budget,
    )
}

/// Diffuse area light of total area `area` (m²) with surface normal `normal` at the photon's
/// origin `origin` (m): positional (eq. 5) and directional (eq. 6) differentials, with
/// `solid_angle` = `ω_e` = 2π sr for a one-sided emitter (the hemisphere) or 4π sr for a
/// two-sided one — what `LightSource::emission_extent` reports. The paper's ω_e is the extent
/// of the emitted directions, not weighted by the cosine of the diffuse emission profile.
pub fn emit_area(
    origin: Vec3,
    direction: Vec3,
    normal: Vec3,
    area: f32,
    solid_angle: f32,
    budget: &EmissionBudget,
) -> Result<RayDiff<2>, DiffError> {
    emit(origin, direction, Some(normal), area, solid_angle, budget)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::footprint::{footprint_area, photon_solid_angle};
    use crate::transfer_to_plane;
    use std::f32::consts::PI;

    fn close(a: f32, b: f32, rel: f32) -> bool {
        (a - b).abs() <= rel * b.abs().max(1e-30)
    }

    fn budget(n: u64, s: f32) -> EmissionBudget {
        EmissionBudget::new(n, s).unwrap()
    }

    /// Deterministic, well-spread directions (a tiny LCG; no dependency on the samplers).
    fn dirs(count: usize, seed: u64) -> Vec<Vec3> {
        let mut x = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let mut next = || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((x >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
        };
        (0..count)
            .map(|_| {
                loop {
                    let v = Vec3::new(next(), next(), next());
                    if v.length() > 0.2 && v.length() < 1.0 {
                        break v.normalize();
                    }
                }
            })
            .collect()
    }

    #[test]
    fn lengths_follow_eq_5_and_6() {
        let b = budget(10_000, 8.0);
        // eq. 5: 2 s √(A / (π N)); eq. 6 the same with ω_e.
        let area = 0.3;
        let want = 2.0 * 8.0 * (area / (PI * 10_000.0)).sqrt();
        assert!(close(b.differential_length(area).unwrap(), want, 1e-6));
        assert_eq!(b.differential_length(0.0).unwrap(), 0.0);
        // point light: 2 s √(4π/(πN)) = 4 s / √N
        let r = emit_point(Vec3::ZERO, Vec3::new(0.3, -0.2, 0.9), &b).unwrap();
        let l = 4.0 * 8.0 / 100.0;
        assert!(close(r.dv[0].length(), l, 1e-5) && close(r.dv[1].length(), l, 1e-5));
        assert_eq!(r.dp, [Vec3::ZERO; 2]);
        // beam: 2 s r / √N
        let r = emit_beam(Vec3::ONE, Vec3::Y, 0.05, &b).unwrap();
        let l = 2.0 * 8.0 * 0.05 / 100.0;
        assert!(close(r.dp[0].length(), l, 1e-5) && close(r.dp[1].length(), l, 1e-5));
        assert_eq!(r.dv, [Vec3::ZERO; 2]);
        // the flux of eq. 5.4 / 5.7 does not depend on s
        assert_eq!(b.photon_flux(50.0), budget(10_000, 1.0).photon_flux(50.0));
        assert!(close(b.photon_flux(50.0), 5e-3, 1e-6));
    }

    /// N_e ω_p = s² ω_e (eq. 6 with the photon solid angle after eq. 4): the photons' solid
    /// angles tile the sphere s² times, for every direction.
    #[test]
    fn point_light_photons_tile_the_sphere() {
        for (n, s) in [
            (1_000u64, 1.0f32),
            (20_000, 5.0),
            (7, 0.3),
            (1_000_000, 40.0),
        ] {
            let b = budget(n, s);
            for w in dirs(50, n) {
                let r = emit_point(Vec3::new(1.0, 2.0, 3.0), w, &b).unwrap();
                let omega_p = photon_solid_angle(r.dv[0], r.dv[1]);
                let total = n as f32 * omega_p;
                assert!(close(total, 4.0 * PI * s * s, 1e-5), "{n} {s}: {total}");
            }
        }
    }

    #[test]
    fn spot_light_photons_tile_the_cone() {
        let (n, s) = (5_000u64, 3.0f32);
        for cos_cutoff in [-1.0f32, -0.3, 0.0, 0.7, 0.999] {
            let r = emit_spot(
                Vec3::ZERO,
                Vec3::new(0.1, 0.0, -1.0),
                cos_cutoff,
                &budget(n, s),
            )
            .unwrap();
            let total = n as f32 * photon_solid_angle(r.dv[0], r.dv[1]);
            assert!(close(total, s * s * 2.0 * PI * (1.0 - cos_cutoff), 1e-5));
            assert_eq!(r.dp, [Vec3::ZERO; 2]);
        }
    }

    /// N_e A_p = s² A_e (eq. 4–5): directional, beam and area lights tile their emission area.
    #[test]
    fn collimated_and_area_photons_tile_the_area() {
        let (n, s) = (40_000u64, 6.0f32);
        let b = budget(n, s);
        for w in dirs(30, 7) {
            let r = emit_directional(Vec3::ZERO, w, 12.5, &b).unwrap();
            assert!(close(
                n as f32 * footprint_area(r.dp[0], r.dp[1]),
                s * s * 12.5,
                1e-5
            ));
            // the emission disk is perpendicular to the beam
            assert!(r.dp[0].dot(w).abs() < 1e-6 && r.dp[1].dot(w).abs() < 1e-6);
            let r = emit_beam(Vec3::ZERO, w, 0.01, &b).unwrap();
            let a = PI * 1e-4;
            assert!(close(
                n as f32 * footprint_area(r.dp[0], r.dp[1]),
                s * s * a,
                1e-5
            ));
        }
        let normal = Vec3::new(0.2, -0.4, 1.0).normalize();
        for w in dirs(60, 9) {
            let r = emit_area(Vec3::ONE, w, normal, 0.25, 2.0 * PI, &b);
            if w.dot(normal).abs() <= PARALLEL_COS {
                continue;
            }
            let r = r.unwrap();
            assert!(close(
                n as f32 * footprint_area(r.dp[0], r.dp[1]),
                s * s * 0.25,
                1e-5
            ));
            let total = n as f32 * photon_solid_angle(r.dv[0], r.dv[1]);
            assert!(close(total, s * s * 2.0 * PI, 1e-5));
            // positional vectors in the emitter's tangent plane, directional ⟂ ω
            for i in 0..2 {
                assert!(r.dp[i].dot(normal).abs() < 1e-6 * r.dp[i].length());
                assert!(r.dv[i].dot(r.v).abs() < 1e-6 * r.dv[i].length());
            }
        }
    }

    /// The directions of eq. 2–3, including the ω ≈ n fallback and the back side.
    #[test]
    fn bases_follow_eq_2_and_3() {
        let normals = dirs(20, 3);
        for (k, w) in dirs(40, 4).into_iter().enumerate() {
            let n = normals[k % normals.len()];
            let b = emission_basis(w, Some(n)).unwrap();
            let n_used = if n.dot(w) < 0.0 { -n } else { n };
            assert!((b.normal - n_used).length() < 1e-6);
            let a = n_used.cross(w).normalize();
            assert!((b.u - a).length() < 1e-5 && (b.theta - a).length() < 1e-5); // eq. 2
            assert!((b.v - a.cross(n_used)).length() < 1e-5); // eq. 3
            assert!((b.phi - a.cross(w)).length() < 1e-5);
            for x in [b.u, b.v, b.theta, b.phi] {
                assert!((x.length() - 1.0).abs() < 1e-5);
            }
            assert!(b.u.dot(b.v).abs() < 1e-5 && b.theta.dot(b.phi).abs() < 1e-5);
        }
        // ω = n, ω ≈ n and no normal: a valid orthonormal basis in each plane
        let n = Vec3::new(0.0, 0.6, 0.8);
        let tilt = (n + 1e-4 * Vec3::X).normalize();
        for (w, nn) in [(n, Some(n)), (tilt, Some(n)), (-n, Some(n)), (n, None)] {
            let b = emission_basis(w, nn).unwrap();
            let nu = b.normal;
            assert!(b.u.dot(nu).abs() < 1e-6 && b.v.dot(nu).abs() < 1e-6);
            assert!(b.theta.dot(w).abs() < 1e-6 && b.phi.dot(w).abs() < 1e-6);
            assert!(b.u.dot(b.theta) > 1.0 - 1e-6); // parallel to O(angle²)
            assert!(b.v.dot(b.phi) > 1.0 - 1e-6);
            assert!(b.u.dot(b.v).abs() < 1e-6 && (b.v.length() - 1.0).abs() < 1e-6);
        }
    }

    /// Seed 002 app. A: with eq. 2–3, `D_θ x′ ∥ D_u x′` and `D_φ x′ ∥ D_v x′` after the first
    /// transfer — and, with the normal turned towards ω, pointing the same way, so that the
    /// combined vectors of eq. 7 are their sums in length too.
    #[test]
    fn pairs_are_parallel_after_first_transfer() {
        let b = budget(1_000, 2.0);
        let normals = dirs(10, 11);
        let planes = dirs(10, 12);
        let mut checked = 0;
        for (k, w) in dirs(60, 13).into_iter().enumerate() {
            let n = normals[k % normals.len()];
            let pn = planes[k % planes.len()];
            let Ok(r2) = emit_area(Vec3::ZERO, w, n, 0.5, 2.0 * PI, &b) else {
                continue;
            };
            // separate the four vectors: parameters u, v, θ, φ
            let r4 = RayDiff::<4>::new(
                r2.p,
                r2.v,
                [r2.dp[0], r2.dp[1], Vec3::ZERO, Vec3::ZERO],
                [Vec3::ZERO, Vec3::ZERO, r2.dv[0], r2.dv[1]],
            );
            let q0 = r2.p + 3.0 * w;
            let Ok(t4) = transfer_to_plane(&r4, q0, &[Vec3::ZERO; 4], pn, &[Vec3::ZERO; 4]) else {
                continue;
            };
            if pn.dot(w).abs() < 0.2 {
                continue; // keep the transfer well conditioned
            }
            let t2 = transfer_to_plane(&r2, q0, &[Vec3::ZERO; 2], pn, &[Vec3::ZERO; 2]).unwrap();
            let d = t4.ray.dp;
            for (a, c) in [(d[0], d[2]), (d[1], d[3])] {
                let sin = a.cross(c).length() / (a.length() * c.length());
                assert!(sin < 1e-4, "not parallel: {a} {c}");
                assert!(a.dot(c) > 0.0, "antiparallel: {a} {c}");
            }
            // eq. 7: the RayDiff<2> carries the sums, whose lengths add
            for (i, (a, c)) in [(d[0], d[2]), (d[1], d[3])].into_iter().enumerate() {
                assert!((t2.ray.dp[i] - (a + c)).length() < 1e-5 * (a + c).length());
                assert!(close(t2.ray.dp[i].length(), a.length() + c.length(), 1e-4));
            }
            checked += 1;
        }
        assert!(checked > 20, "{checked}");
    }

    /// A photon emitted with parameter offset ε lands where `p′ + ε dp′` predicts after one
    /// transfer, to O(ε²): the error halves twice when ε halves. The neighbouring photon is
    /// built independently of the differential: origin moved along the emitter's plane, direction
    /// *rotated* by the angle `ε |D_θ ω|`, traced exactly (f64) to the plane.
    #[test]
    fn neighbouring_photon_lands_where_the_differential_predicts() {
        let b = budget(10_000, 1.0);
        let n = Vec3::new(0.1, -0.2, 1.0).normalize();
        let w = Vec3::new(0.5, 0.3, 0.8).normalize();
        let origin = Vec3::new(0.2, 0.1, 0.0);
        let (q0, pn) = (
            Vec3::new(0.0, 0.0, 3.0),
            Vec3::new(0.3, -0.4, -1.0).normalize(),
        );
        let lights: [(&str, RayDiff<2>); 3] = [
            ("area", emit_area(origin, w, n, 0.5, 2.0 * PI, &b).unwrap()),
            ("point", emit_point(origin, w, &b).unwrap()),
            ("beam", emit_beam(origin, w, 0.5, &b).unwrap()),
        ];
        for (name, r) in lights {
            let t = transfer_to_plane(&r, q0, &[Vec3::ZERO; 2], pn, &[Vec3::ZERO; 2]).unwrap();
            for delta in [[1.0f32, 0.0], [0.0, 1.0], [0.6, -0.8]] {
                let err = |eps: f64| {
                    let d = [delta[0] as f64 * eps, delta[1] as f64 * eps];
                    let dv = |i: usize| r.dv[i].as_dvec3();
                    let (p, v) = (r.p.as_dvec3(), r.v.as_dvec3());
                    let origin = p + r.dp[0].as_dvec3() * d[0] + r.dp[1].as_dvec3() * d[1];
                    // rotate v towards the combined directional vector by its length
                    let turn = dv(0) * d[0] + dv(1) * d[1];
                    let ang = turn.length();
                    let dir = if ang > 0.0 {
                        v * ang.cos() + turn / ang * ang.sin()
                    } else {
                        v
                    };
                    let (q0, pn) = (q0.as_dvec3(), pn.as_dvec3());
                    let hit = origin + dir * ((q0 - origin).dot(pn) / dir.dot(pn));
                    let pred = t.ray.p.as_dvec3()
                        + t.ray.dp[0].as_dvec3() * d[0]
                        + t.ray.dp[1].as_dvec3() * d[1];
                    (hit - pred).length()
                };
                let (e1, e2) = (err(1.0), err(0.5));
                if name == "beam" {
                    // the origin moves linearly in a fixed direction: exact to rounding
                    assert!(e1 < 1e-6, "{name}: {e1}");
                    continue;
                }
                let ratio = e1 / e2;
                assert!(e1 > 1e-5 && e1 < 1e-2, "{name} {delta:?}: {e1}");
                assert!(
                    (3.6..4.4).contains(&ratio),
                    "{name} {delta:?}: {e1} {e2} {ratio}"
                );
            }
        }
    }

    #[test]
    fn invalid_input_is_an_error() {
        assert_eq!(EmissionBudget::new(0, 1.0), Err(DiffError::NoPhotons));
        for s in [0.0, -1.0, f32::NAN, f32::INFINITY, -0.0] {
            assert_eq!(EmissionBudget::new(10, s), Err(DiffError::InvalidSmoothing));
        }
        let b = budget(100, 2.0);
        assert_eq!(b.differential_length(-1.0), Err(DiffError::InvalidExtent));
        assert_eq!(
            b.differential_length(f32::NAN),
            Err(DiffError::InvalidExtent)
        );
        assert_eq!(
            b.differential_length(f32::INFINITY),
            Err(DiffError::InvalidExtent)
        );
        let (o, w, n) = (Vec3::ZERO, Vec3::Z, Vec3::Z);
        assert_eq!(
            emit(o, w, Some(n), 0.0, 0.0, &b),
            Err(DiffError::InvalidExtent)
        );
        assert_eq!(
            emit(o, w, None, 0.0, 13.0, &b),
            Err(DiffError::InvalidExtent)
        );
        assert_eq!(
            emit_area(o, w, n, -1.0, 2.0 * PI, &b),
            Err(DiffError::InvalidExtent)
        );
        assert_eq!(emit_spot(o, w, 1.0, &b), Err(DiffError::InvalidExtent));
        assert_eq!(emit_spot(o, w, -1.5, &b), Err(DiffError::InvalidExtent));
        assert_eq!(emit_spot(o, w, f32::NAN, &b), Err(DiffError::InvalidExtent));
        assert_eq!(emit_beam(o, w, 0.0, &b), Err(DiffError::InvalidExtent));
        assert_eq!(emit_beam(o, w, f32::NAN, &b), Err(DiffError::InvalidExtent));
        assert_eq!(emit_point(o, Vec3::ZERO, &b), Err(DiffError::ZeroDirection));
        assert_eq!(
            emit_point(o, Vec3::splat(f32::NAN), &b),
            Err(DiffError::ZeroDirection)
        );
        assert_eq!(
            emit_point(Vec3::splat(f32::NAN), w, &b),
            Err(DiffError::NonFinite)
        );
        assert_eq!(
            emit_area(o, w, Vec3::ZERO, 1.0, PI, &b),
            Err(DiffError::DegenerateNormal)
        );
        // grazing emission: n · ω = 0
        assert_eq!(
            emit_area(o, Vec3::X, n, 1.0, PI, &b),
            Err(DiffError::Parallel)
        );
        assert_eq!(
            emit_area(o, Vec3::new(1.0, 0.0, 1e-8), n, 1.0, PI, &b),
            Err(DiffError::Parallel)
        );
        // nearly grazing is still a (thin) photon, finite
        let r = emit_area(o, Vec3::new(1.0, 0.0, 1e-4), n, 1.0, PI, &b).unwrap();
        assert!(r.is_finite());
    }
}
