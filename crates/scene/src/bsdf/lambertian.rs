//! Lambertian (ideal diffuse) reflection: f = ρ/π (Lambert 1760; pbrt-v4 §9.2), sampled with
//! the cosine-weighted hemisphere (Malley's method), whose density cos θi/π makes the sample
//! weight exactly ρ. Two-sided.

use super::{BsdfFlags, BsdfSample, BxDF, TransportMode, to_upper_side};
use caustica_core::sampling::warp;
use caustica_core::{INV_PI, Spectrum, Vec2, Vec3};

/// Ideal diffuse reflector with albedo `albedo` ∈ [0, 1] per channel.
#[derive(Clone, Copy, Debug)]
pub struct Lambertian {
    pub albedo: Spectrum,
}

impl Lambertian {
    pub fn new(albedo: Spectrum) -> Self {
        Self { albedo }
    }
}

impl BxDF for Lambertian {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE
    }
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Spectrum {
        let (wo, wi) = to_upper_side(wo, wi);
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Spectrum::ZERO;
        }
        self.albedo * INV_PI
    }
    fn sample(&self, wo: Vec3, _uc: f32, u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let mut wi = warp::square_to_cosine_hemisphere(u);
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = wi.z * INV_PI;
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        Some(BsdfSample {
            wi,
            weight: self.albedo,
            pdf,
            flags: BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE,
            eta: 1.0,
        })
    }
    fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        let (wo, wi) = to_upper_side(wo, wi);
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        wi.z * INV_PI
    }
}
