//! Differential algebra for ray and photon differentials (seed 000, appendix B: "Space and
//! time ray differentials"), and the emission and footprints of photon differentials (seed 002,
//! "Photon Differential Splatting for Rendering Caustics", eq. 1–12 and app. B).
//!
//! A [`RayDiff<N>`] is a ray — origin `P` (m) and unit direction `V` — together with its
//! first-order structure with respect to `N` scalar parameters θ = (θ₀ … θ_{N−1}):
//! `dp[i] = ∂P/∂θᵢ` (m per unit of θᵢ) and `dv[i] = ∂V/∂θᵢ` (per unit of θᵢ). The
//! parameters are whatever generated the ray: the two image-plane coordinates of a camera
//! ray differential (Igehy 1999; `N = 2`, see [`caustica_core::RayDifferential`]), two
//! positional and two directional parameters of a photon differential (seed 002; `N = 4`, or
//! `N = 2` with eq. 7's pairs, see below), plus time for moving scenes (seed 000 eq. B.12 and
//! ch. 7; `N = 5`). Scene geometry may depend on the same parameters through
//! [`TriangleMotion`].
//!
//! Following appendix B, a ray is propagated by alternating
//!
//! * **transfer** onto a surface, `Q = P + s V` ([`transfer`], eq. B.13–B.16 with the plane
//!   constraint eq. B.24–B.29),
//! * **reflection** `W = V − 2 (Vᵀ N) N` ([`reflection`], eq. B.17–B.18) or **refraction**
//!   `W = η V − μ N` ([`refraction`], eq. B.19–B.23),
//!
//! where the normal `N` and its differential `dN` come from a **surface model**
//! ([`surface`], B.3): a [`FlatTriangle`] (eq. B.24–B.34) or a [`PhongTriangle`] with
//! interpolated vertex normals (eq. B.35–B.55).
//!
//! Directions are unit vectors throughout, as in eq. B.1b: reflection and refraction of a
//! unit `V` about a unit `N` give a unit `W`, so every `dv` is the derivative of the
//! normalised direction (what [`caustica_core::RayDifferential`] stores) and is
//! perpendicular to `v`. Derivatives of an unnormalised direction are converted with
//! eq. B.5b ([`normalize_differential`], [`RayDiff::from_unnormalized`]).
//!
//! # Photon differentials (seed 002; seed 000 ch. 5)
//!
//! A photon differential is a [`RayDiff<2>`] whose parameter 0 pairs the light-surface
//! coordinate u with the direction coordinate θ and parameter 1 pairs v with φ: seed 002's
//! pairwise-parallel choice of the initial vectors (eq. 2–3) makes the transferred footprint
//! the parallelogram of `(D_u + D_θ) x′` and `(D_v + D_φ) x′` (eq. 7), so the algebra above
//! propagates it unchanged.
//!
//! * [`emission`] creates it for point, spot, directional, beam ("laser") and diffuse area
//!   lights (eq. 1–6: `|D_u x| = 2 s √(A_e/(π N_e))` m, `|D_θ ω| = 2 s √(ω_e/(π N_e))` rad, so
//!   that the `N_e` photons' footprints sum to `s² A_e` and their solid angles to `s² ω_e`),
//!   from an [`EmissionBudget`] (`N_e`, smoothing `s`).
//! * [`footprint`] turns it, at the non-specular surface where it lands, into a [`Footprint`]:
//!   the inscribed ellipse of area `A_p = π/4 |D_u x × D_v x|` (m², eq. 4), irradiance
//!   `E_p = Φ_p/A_p` (W/m²), the 2×3 filter matrix `M_p` of eq. 12, Silverman's kernel
//!   (eq. 11) and the photon's term `π K(|M_p (x − x_p)|) E_p` of the radiance estimate
//!   (eq. 10 = seed 000 eq. 5.14, W/m² before the BRDF), the gather radius and the anisotropy
//!   metric of app. B. Collapsed footprints are a typed error.
//!
//! ```
//! use caustica_core::Vec3;
//! use caustica_differentials::{EmissionBudget, Footprint, emit_point, transfer_to_plane};
//!
//! // 10⁴ photons from a 1 W/sr point light 2 m above the floor, smoothing s = 5.
//! let budget = EmissionBudget::new(10_000, 5.0).unwrap();
//! let photon = emit_point(Vec3::new(0.0, 0.0, 2.0), -Vec3::Z, &budget).unwrap();
//! let z = [Vec3::ZERO; 2];
//! let hit = transfer_to_plane(&photon, Vec3::ZERO, &z, Vec3::Z, &z).unwrap();
//! let fp = Footprint::from_ray(&hit.ray, Vec3::Z).unwrap();
//! let flux = budget.photon_flux(4.0 * std::f32::consts::PI); // Φ_p = Φ/N_e (W)
//! // E_p = I / (s² d²): the inverse-square law shared among the s² overlapping footprints
//! assert!((fp.irradiance(flux) - 1.0 / (25.0 * 4.0)).abs() < 1e-5);
//! assert!(fp.contains(Vec3::new(0.01, 0.0, 0.0)) && fp.irradiance_at(Vec3::ZERO, flux) > 0.0);
//! ```
//!
//! Every operation returns finite values or a [`DiffError`] (ray parallel to the plane,
//! degenerate triangle, vanishing interpolated normal, total internal reflection, overflow,
//! invalid emission parameters, collapsed footprint); none returns NaN.
//!
//! ```
//! use caustica_core::Vec3;
//! use caustica_differentials::{FlatTriangle, RayDiff};
//!
//! // A ray whose origin moves along x with θ₀ and whose direction turns towards y with θ₁.
//! let ray = RayDiff::<2>::new(Vec3::ZERO, Vec3::Z, [Vec3::X, Vec3::ZERO], [Vec3::ZERO, Vec3::Y]);
//! let tri = FlatTriangle { q: [Vec3::new(-1.0, -1.0, 2.0), Vec3::new(1.0, -1.0, 2.0), Vec3::new(0.0, 1.0, 2.0)] };
//! let hit = tri.hit(&ray).unwrap();
//! assert!((hit.ray.dp[1] - 2.0 * Vec3::Y).length() < 1e-6); // dQ = s dV on a facing plane
//! let out = hit.refract(1.0 / 1.5).unwrap();
//! assert!(out.v.dot(out.dv[1]).abs() < 1e-6);
//! ```

#![forbid(unsafe_code)]
// Comparisons are written `!(x > bound)` on purpose: they are also true for NaN, which is how
// every guard here turns garbage input into an error instead of propagating it.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod camera;
pub mod emission;
mod error;
pub mod footprint;
pub mod medium;
pub mod ray_differential;
pub mod reflection;
pub mod refraction;
pub mod surface;
pub mod transfer;

pub use camera::camera_ray_diff;
pub use emission::{
    EmissionBasis, EmissionBudget, emission_basis, emit, emit_area, emit_beam, emit_directional,
    emit_point, emit_spot, emit_with_basis, emit_with_lengths,
};
pub use error::DiffError;
pub use footprint::{Footprint, footprint_area, photon_solid_angle, silverman};
pub use medium::{
    AxesRule, Rotation, free_flight, phase_area_factor, reflect_sampled, scatter,
    spread_collimated, surface_area_factor, volume_axes,
};
pub use ray_differential::{RayDiff, normalize_differential};
pub use reflection::{reflect, reflection_jacobians};
pub use refraction::{refract, refract_direction, refract_dispersive, refraction_jacobians};
pub use surface::{FlatTriangle, PhongTriangle, SurfaceHit, TriangleMotion};
pub use transfer::{Transferred, transfer_to_fixed_plane, transfer_to_plane};
