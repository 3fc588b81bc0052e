//! Differential algebra for ray and photon differentials (seed 000, appendix B: "Space and
//! time ray differentials").
//!
//! A [`RayDiff<N>`] is a ray — origin `P` (m) and unit direction `V` — together with its
//! first-order structure with respect to `N` scalar parameters θ = (θ₀ … θ_{N−1}):
//! `dp[i] = ∂P/∂θᵢ` (m per unit of θᵢ) and `dv[i] = ∂V/∂θᵢ` (per unit of θᵢ). The
//! parameters are whatever generated the ray: the two image-plane coordinates of a camera
//! ray differential (Igehy 1999; `N = 2`, see [`caustica_core::RayDifferential`]), two
//! positional and two directional parameters of a photon differential (seed 002; `N = 4`),
//! plus time for moving scenes (seed 000 eq. B.12 and ch. 7; `N = 5`). Scene geometry may
//! depend on the same parameters through [`TriangleMotion`].
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
//! Every operation returns finite values or a [`DiffError`] (ray parallel to the plane,
//! degenerate triangle, vanishing interpolated normal, total internal reflection, overflow);
//! none returns NaN.
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

// Comparisons are written `!(x > bound)` on purpose: they are also true for NaN, which is how
// every guard here turns garbage input into an error instead of propagating it.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

mod error;
pub mod ray_differential;
pub mod reflection;
pub mod refraction;
pub mod surface;
pub mod transfer;

pub use error::DiffError;
pub use ray_differential::{RayDiff, normalize_differential};
pub use reflection::{reflect, reflection_jacobians};
pub use refraction::{refract, refract_direction, refraction_jacobians};
pub use surface::{FlatTriangle, PhongTriangle, SurfaceHit, TriangleMotion};
pub use transfer::{Transferred, transfer_to_plane};
