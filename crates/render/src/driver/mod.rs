//! The drivers: how work is spread over threads so that the image is a pure function of scene,
//! options and seed, whatever the thread count.
//!
//! * [`pixels`] — camera samples, pixel-parallel (path tracer, the camera passes of the photon
//!   methods).
//! * [`light_paths`] — light paths splatting into the film, path-parallel (light tracer).
//! * [`eye_splat`] — an eye pass recording eye vertices, then batches of light paths whose
//!   photons each eye-map tile splats in path order, then the vertices resolved into their
//!   pixels (`pds`; progressive photon mapping and photon cone focusing are further
//!   [`eye_splat::SplatRule`]s).

pub mod eye_splat;
pub mod light_paths;
pub mod pixels;
