//! Bidirectional scattering distribution functions.
//!
//! Conventions (shared by every BSDF):
//! * Directions are unit vectors in the local shading frame (+z = shading normal), both pointing
//!   *away* from the surface: `wo` toward the viewer (or previous vertex), `wi` toward the light
//!   (or next vertex).
//! * [`Bsdf::eval`] returns f(wo, wi) in sr⁻¹ *without* the cosine; it is zero for delta lobes.
//! * [`Bsdf::sample`] returns `weight = f·|cos θi| / pdf` (for delta lobes the lobe's Fresnel
//!   weight divided by the probability of choosing it) and `pdf` in sr⁻¹ (for delta lobes the
//!   discrete probability of the chosen lobe, flagged by [`BsdfFlags::DELTA`]).
//! * [`TransportMode`] selects radiance or importance transport: refraction scales radiance by
//!   η² (non-symmetric, Veach 1997 §5.2); importance is not scaled.
//! * Two-sidedness and orientation: see the crate docs.

pub mod conductor;
pub mod dielectric;
pub mod fresnel;
pub mod lambertian;
pub mod microfacet;
pub mod mirror;
pub mod phong;
pub mod rough_conductor;
pub mod rough_dielectric;
#[cfg(test)]
pub(crate) mod testutil;

pub use conductor::Conductor;
pub use dielectric::Dielectric;
pub use lambertian::Lambertian;
pub use mirror::Mirror;
pub use phong::Phong;
pub use rough_conductor::RoughConductor;
pub use rough_dielectric::RoughDielectric;

use caustica_core::{Spectrum, Vec2, Vec3};

/// Two-sided opaque BSDFs: mirrors `wo` and `wi` through the tangent plane when `wo` is below
/// the surface, so the model only ever sees `wo.z ≥ 0` (crate docs, "two-sidedness").
#[inline]
pub fn to_upper_side(wo: Vec3, wi: Vec3) -> (Vec3, Vec3) {
    if wo.z < 0.0 {
        (Vec3::new(wo.x, wo.y, -wo.z), Vec3::new(wi.x, wi.y, -wi.z))
    } else {
        (wo, wi)
    }
}

/// Sampling of a two-sided opaque BSDF: mirrors `wo` to the upper side when it is below the
/// surface, samples there with `sample_upper` (which may assume `wo.z > 0`) and mirrors the
/// sampled direction back. Grazing `wo` (z = 0) gives no sample.
#[inline]
pub fn sample_two_sided(
    wo: Vec3,
    sample_upper: impl FnOnce(Vec3) -> Option<BsdfSample>,
) -> Option<BsdfSample> {
    if wo.z == 0.0 {
        return None;
    }
    let flip = wo.z < 0.0;
    let mut s = sample_upper(if flip {
        Vec3::new(wo.x, wo.y, -wo.z)
    } else {
        wo
    })?;
    if flip {
        s.wi.z = -s.wi.z;
    }
    Some(s)
}

/// Lobe classification bits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct BsdfFlags(pub u8);

impl BsdfFlags {
    pub const NONE: BsdfFlags = BsdfFlags(0);
    pub const REFLECTION: BsdfFlags = BsdfFlags(1);
    pub const TRANSMISSION: BsdfFlags = BsdfFlags(2);
    pub const DIFFUSE: BsdfFlags = BsdfFlags(4);
    pub const GLOSSY: BsdfFlags = BsdfFlags(8);
    pub const DELTA: BsdfFlags = BsdfFlags(16);

    #[inline]
    pub const fn contains(self, o: BsdfFlags) -> bool {
        self.0 & o.0 == o.0
    }
    #[inline]
    pub const fn intersects(self, o: BsdfFlags) -> bool {
        self.0 & o.0 != 0
    }
    #[inline]
    pub const fn is_delta(self) -> bool {
        self.0 & Self::DELTA.0 != 0
    }
    /// Has a non-delta (diffuse or glossy) lobe, i.e. can be evaluated for given directions.
    #[inline]
    pub const fn is_smooth(self) -> bool {
        self.0 & (Self::DIFFUSE.0 | Self::GLOSSY.0) != 0
    }
}

impl std::ops::BitOr for BsdfFlags {
    type Output = BsdfFlags;
    fn bitor(self, o: BsdfFlags) -> BsdfFlags {
        BsdfFlags(self.0 | o.0)
    }
}

/// Whether radiance (camera paths) or importance (light paths, photons) is transported.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    Radiance,
    Importance,
}

/// Result of sampling a BSDF.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// Sampled direction, local frame.
    pub wi: Vec3,
    /// f·|cos θi| / pdf.
    pub weight: Spectrum,
    /// Solid-angle density (sr⁻¹), or the discrete lobe probability for delta lobes.
    pub pdf: f32,
    /// The lobe that was sampled.
    pub flags: BsdfFlags,
    /// Relative IOR η_t/η_i crossed by the sampled direction (1 for reflection).
    pub eta: f32,
}

/// Interface of one scattering model; [`Bsdf`] dispatches over the concrete models.
pub trait BxDF {
    /// Union of the lobes of this model.
    fn flags(&self) -> BsdfFlags;
    /// f(wo, wi) in sr⁻¹, zero for delta lobes.
    fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Spectrum;
    /// Samples `wi` given `wo`, with `uc` choosing a lobe and `u` the direction.
    fn sample(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample>;
    /// Solid-angle density of [`BxDF::sample`] returning `wi` (non-delta lobes only).
    fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32;
}

/// A BSDF instantiated at a surface point (parameters already looked up from textures).
#[derive(Clone, Copy, Debug)]
pub enum Bsdf {
    Lambertian(Lambertian),
    Mirror(Mirror),
    Dielectric(Dielectric),
    Conductor(Conductor),
    RoughConductor(RoughConductor),
    RoughDielectric(RoughDielectric),
    Phong(Phong),
}

macro_rules! dispatch {
    ($self:ident, $b:ident => $e:expr) => {
        match $self {
            Bsdf::Lambertian($b) => $e,
            Bsdf::Mirror($b) => $e,
            Bsdf::Dielectric($b) => $e,
            Bsdf::Conductor($b) => $e,
            Bsdf::RoughConductor($b) => $e,
            Bsdf::RoughDielectric($b) => $e,
            Bsdf::Phong($b) => $e,
        }
    };
}

impl Bsdf {
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        dispatch!(self, b => b.flags())
    }
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Spectrum {
        #[cfg(feature = "eval-counter")]
        instrument::count();
        dispatch!(self, b => b.eval(wo, wi, mode))
    }
    #[inline]
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        #[cfg(feature = "eval-counter")]
        instrument::count();
        dispatch!(self, b => b.sample(wo, uc, u, mode))
    }
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        #[cfg(feature = "eval-counter")]
        instrument::count();
        dispatch!(self, b => b.pdf(wo, wi, mode))
    }
}

/// Per-thread counts of BSDF calls (`eval`, `sample`, `pdf`), with the `eval-counter` feature.
#[cfg(feature = "eval-counter")]
pub mod instrument {
    use std::cell::Cell;

    thread_local! {
        static CALLS: Cell<u64> = const { Cell::new(0) };
    }

    pub(super) fn count() {
        CALLS.with(|c| c.set(c.get() + 1));
    }

    /// BSDF calls made on this thread so far.
    pub fn calls() -> u64 {
        CALLS.with(|c| c.get())
    }
}
