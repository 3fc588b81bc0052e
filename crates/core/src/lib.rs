//! Foundation of caustica: the types every other crate speaks.
//!
//! * [`Spectrum`] — the one colour type: RGB, or three sampled wavelengths in spectral mode
//!   ([`Channels`] says which; [`spectral`] holds the colour science).
//! * [`Ray`], [`RayDifferential`] — rays and their per-pixel differentials (Igehy 1999).
//! * [`Frame`] — orthonormal shading frames.
//! * [`sampling`] — random number generators, the Sobol/independent samplers and warps.
//! * [`image_io`] — reading and writing EXR, PFM and PNG; [`apng`] — animated PNG previews.
//! * [`chi2`] — chi-square goodness-of-fit tests used by every sampler's tests.

#![forbid(unsafe_code)]

pub mod apng;
pub mod channels;
pub mod chi2;
pub mod frame;
pub mod image_io;
pub mod ray;
pub mod sampling;
pub mod spectral;
pub mod spectrum;

pub use channels::Channels;
pub use frame::Frame;
pub use glam::{Affine3A, Mat3, Mat4, Vec2, Vec3, Vec3A};
pub use ray::{Ray, RayDifferential};
pub use spectrum::Spectrum;

/// Small offset used to move ray origins off surfaces, relative to the scene scale of 1.
pub const RAY_EPSILON: f32 = 1e-4;

/// π as `f32`.
pub const PI: f32 = std::f32::consts::PI;
/// 1/π.
pub const INV_PI: f32 = std::f32::consts::FRAC_1_PI;
/// 1/(2π).
pub const INV_2PI: f32 = 0.5 * std::f32::consts::FRAC_1_PI;
/// 1/(4π).
pub const INV_4PI: f32 = 0.25 * std::f32::consts::FRAC_1_PI;
