//! A photon cone (seed 001 eq. 3.11): a sample of the radiance leaving a surface point, made
//! at a light-path vertex with the BSDF already applied, so a lookup evaluates no material.

use caustica_core::{Spectrum, Vec3};

/// A photon cone `(X_j, ω_j, P_{Λ,j})` with its light-path length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhotonCone {
    /// Position X_j (m).
    pub p: Vec3,
    /// Unit direction ω_j the radiance leaves in (world space).
    pub dir: Vec3,
    /// P_{Λ,j} = β · f(ω_i → ω_j) / p(ω_j), times its MIS weight (W: flux β in W times the
    /// dimensionless f/p; divided by the number of light paths and the kernel volume C_σ in
    /// m² sr, radiance W/m²/sr). No cosine at the cone (it carries radiance).
    pub value: Spectrum,
    /// Edges from the light to X_j (1: direct light), saturated at 255: nested PCF's direct
    /// estimate uses the length-1 cones only (spec notes sec. 2.10).
    pub length: u8,
    /// Emitted by a delta light (point, spot, directional, beam): one path tracing cannot hit.
    pub delta_light: bool,
    /// The shape the cone lies on (`SurfaceInteraction::shape`).
    pub shape: u32,
    /// Its geometric normal (unit, as the shape orients it, never flipped).
    pub ng: Vec3,
}
