//! Integrators and film of caustica.
//!
//! * [`film`], [`filter`] — accumulation of camera samples and light-path splats.
//! * [`image_loop`] — the pixel-parallel driver: every pixel sample is a pure function of
//!   (seed, pixel, sample index), so images are identical for any thread count.
//! * [`splat_loop`] — the light-path-parallel driver: paths are grouped in fixed chunks whose
//!   splat buffers are merged in chunk order, again independent of the thread count.
//! * [`surface`] and [`direct`] — shared per-vertex work (BSDF at a hit, shading-normal
//!   correction, Beer–Lambert absorption, next-event estimation) used by every integrator.
//! * [`light_path`] — the one light-path walker shared by the light tracer and the photon
//!   tracer.
//! * [`photon_tracer`], [`photon_map`] — the photon tracer shared by every photon method, and
//!   photon maps with the radiance estimate of seed 000 eq. 3.2.
//! * [`photon_differential`] — caustic photons carrying photon differentials, their footprints
//!   and the estimate of seed 002 eq. 10 (`pdm`).
//! * [`eye_map`] — the eye-path map that photon differential splatting (`pds`) splats onto.
//! * [`integrator`] — the path tracer, the light tracer, photon mapping (`pm`, `dpm`, `pdm`) and
//!   photon differential splatting (`pds`).

pub mod direct;
pub mod eye_map;
pub mod film;
pub mod filter;
pub mod image_loop;
pub mod integrator;
pub mod light_path;
pub mod options;
pub mod photon_differential;
pub mod photon_map;
pub mod photon_tracer;
pub mod photon_view;
pub mod splat_loop;
pub mod stats;
pub mod surface;

pub use film::Film;
pub use integrator::{IntegratorKind, RenderOutput, render};
pub use options::{
    CausticEstimator, DiffusionSettings, PhotonOptions, Progress, RenderControl, RenderOptions,
};
pub use stats::RenderStats;
