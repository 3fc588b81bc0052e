//! Density estimation for caustica's photon maps.
//!
//! Specification: A. Schjøth, *Anisotropic Density Estimation in Global Illumination* (PhD thesis,
//! 2009): Table 2.1 (univariate kernels), eq. 3.2 (the general radiance estimate), Table 5.1
//! (the photon-mapping kernels) and appendix A, eq. A.1–A.2 (projection onto the tangent plane).
//!
//! * [`kernel`] — [`Kernel`]: kernels with support on the unit ball, normalised to integrate to 1
//!   over the d-dimensional unit ball ([`Dim`]).
//! * [`kdtree`] — [`KdTree`]: a static k-d tree over 3-D points (the photon map) with k-nearest
//!   ([`KdTree::knn`]) and fixed-radius ([`KdTree::range`]) queries.
//! * [`estimate`] — helpers for the radiance estimate: [`project_to_tangent_plane`] (eq. A.1–A.2)
//!   and [`disc_test`] (rejection of photons off the tangent plane or with a disagreeing normal).
//! * [`estimator`] — [`Estimator`]: every density estimator behind one interface (fixed
//!   bandwidth eq. 2.15, k-NN eq. 2.12/3.2, variable bandwidth eq. 2.13, diffusion eq. 4.19)
//!   over any [`PointSet`] (the testbed's samples, a photon map).
//! * [`radius_buckets`] — [`RadiusBuckets`]: points with their own support radius, searched by
//!   "whose ball contains x" (variable bandwidths, photon-differential footprints).
//! * [`beam`] — the beam radiance estimate's geometry (seed 000 sec. 8.3, eq. 8.4–8.16, with
//!   8.5's factor 2 and 8.13's `y` for `y_s` corrected): a [`beam::BeamKernel`]'s weight along
//!   an eye-ray segment for a ball or a filter-matrix ellipsoid, clipped to the segment or the
//!   whole chord, the closest point where `T_r` and the phase function are evaluated, the
//!   kernels' volumes and bounding radii.
//! * [`sphere_bvh`] — [`SphereBvh`]: a BVH over spheres with their own radii, calling back for
//!   every sphere a ray segment crosses, in a fixed order (the beam estimate's photon gather).
//! * [`bandwidth_selection`] — automatic bandwidths: least-squares cross-validation with a
//!   hold-out cross term ([`bandwidth_selection::LscvScore`]) over a geometric grid, and the
//!   AMISE rate that carries a pilot sample's choice to the full sample.
//! * [`schedule`] — [`BandwidthSchedule`]: the progressive methods' shrinking bandwidth
//!   (seed 001 eq. 3.27) from the closed-form Γ product, for any kernel volume `V(h)`.
//! * [`diffusion`] — diffusion-based estimation (ch. 4, eq. 4.11–4.19): gradient pre-pass,
//!   structure tensor, diffusion tensor.
//!
//! # Units
//!
//! [`Kernel::eval`] takes the dimensionless squared normalised distance `u² = |x − xᵢ|²/h²` and
//! returns a dimensionless weight whose integral over the unit ball of `R^d` is 1. A kernel
//! density estimate with bandwidth `h` (m) is `Σᵢ wᵢ K(|x − xᵢ|²/h²) / h^d`, which has the unit
//! of the weights `wᵢ` per m^d: with photon flux `Φᵢ` (W) and `d = 2` this is irradiance (W/m²);
//! multiplied by a BRDF (sr⁻¹) it is radiance (W/m²/sr), eq. 3.2:
//!
//! ```text
//! L̂_r(x, ω) = 1/(π h²) Σᵢ K₅.₁(dᵢ²/h²) f_r(x, ωᵢ, ω) Φᵢ = 1/h² Σᵢ eval(dᵢ²/h², Dim::Two) f_r Φᵢ
//! ```
//!
//! since `eval(u², Dim::Two) = K₅.₁(u²)/π` for the kernels of Table 5.1 (see [`kernel`]).
//!
//! A [`Query`] knows its [`Domain`]: a surface query (`Query::new(p, n)`, with a tangent frame)
//! estimates densities per m² with kernels normalised in 2-D, a volume query
//! (`Query::volume(p)`, participating media) densities per m³ with kernels normalised in 3-D:
//! with photon flux `Φᵢ` (W) and `d = 3` the estimate is W/m³, and with a phase function
//! (sr⁻¹) in the sum it is the in-scattered radiance of seed 000 eq. 8.3 (W/m³/sr; times the
//! scattering coefficient σ_s (1/m) it becomes the W/m²/sr/m source term along a ray).
//!
//! # Example
//!
//! ```
//! use caustica_core::Vec3;
//! use caustica_density::{Dim, KdTree, Kernel};
//!
//! let photons = vec![Vec3::ZERO, Vec3::new(0.1, 0.0, 0.0), Vec3::new(5.0, 0.0, 0.0)];
//! let tree = KdTree::build(&photons);
//! let mut nn = Vec::new();
//! tree.knn(Vec3::ZERO, 2, f32::INFINITY, &mut nn);
//! let h2 = 0.2f32 * 0.2;
//! let k = Kernel::from_name("epanechnikov").unwrap();
//! // Photon count per m² around the origin (unit weights).
//! let density: f32 = nn.iter().map(|n| k.eval(n.dist2 / h2, Dim::Two)).sum::<f32>() / h2;
//! assert!(density > 0.0);
//! ```

#![forbid(unsafe_code)]

pub mod bandwidth_selection;
pub mod beam;
pub mod diffusion;
pub mod estimate;
pub mod estimator;
pub mod kdtree;
pub mod kernel;
pub mod radius_buckets;
pub mod schedule;
pub mod sphere_bvh;

pub use diffusion::{DiffusionEstimator, DiffusionParams, DiffusionTensor};
pub use estimate::{disc_test, project_to_tangent_plane};
pub use estimator::{
    Domain, Estimator, EstimatorSpec, PointSet, Query, Scratch, WeightedPoints, median_knn_radius,
};
pub use kdtree::{KdTree, Neighbor};
pub use kernel::{Dim, Kernel};
pub use radius_buckets::RadiusBuckets;
pub use schedule::{BandwidthSchedule, KernelVolume, ScheduleError};
pub use sphere_bvh::SphereBvh;

/// Errors of the density crate.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum DensityError {
    /// An unknown kernel name (or a malformed cone parameter).
    #[error(
        "unknown kernel '{0}': expected one of uniform, epanechnikov, biweight, gaussian, cone, cone:G (G >= 1), silverman, cubic"
    )]
    UnknownKernel(String),
    /// The cone kernel's slope parameter `g` must be a finite number >= 1 (Table 5.1).
    #[error("invalid cone kernel parameter '{0}': g must be a finite number >= 1, e.g. 'cone:1.1'")]
    InvalidConeParameter(String),
    /// An estimator (or helper) defined only in a surface's tangent plane was given a volume
    /// query ([`estimator::Domain::Volume`]); the diffusion estimator is the one such estimator.
    #[error(
        "the {0} estimator is defined in a surface's tangent plane (seed 000 ch. 4) and cannot answer a volume query; use fixed, knn or variable for volume photons"
    )]
    SurfaceOnly(&'static str),
    /// The beam radiance estimate integrates its kernel along the eye ray in closed form
    /// (seed 000 eq. 8.11, 8.13, 8.15), which [`beam`] does for two kernels only.
    #[error(
        "the beam radiance estimate integrates the uniform and epanechnikov kernels only, not '{0}'"
    )]
    UnsupportedBeamKernel(String),
}
