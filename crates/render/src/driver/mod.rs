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
//! * [`iterations`] — iterations of a one-shot render pooled into one image, one alive at a
//!   time (the progressive methods), with the time budget, Ctrl-C and checkpoints between them.

pub mod eye_splat;
pub mod iteration_state;
pub mod iterations;
pub mod light_paths;
pub mod pixels;
