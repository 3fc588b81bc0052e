//! GGX rough conductor (Cook & Torrance 1982 microfacet BRDF with the GGX distribution of
//! Walter et al. 2007; pbrt-v4 §9.6 `ConductorBxDF`):
//!
//! f(ωo, ωi) = D(ωm) G2(ωo, ωi) F(ωo·ωm) / (4 cos θo cos θi), ωm = normalize(ωo + ωi),
//!
//! with the exact conductor Fresnel term times a specular tint. Sampled with visible normals
//! (Heitz 2018): ωm ~ D_ωo, ωi = reflect(ωo, ωm), pdf(ωi) = D_ωo(ωm) / (4 |ωo·ωm|), so the
//! sample weight is F G2/G1(ωo). Samples below the horizon are rejected (`None`). Two-sided.

use super::fresnel::{fresnel_conductor, reflect};
use super::microfacet::TrowbridgeReitz;
use super::{BsdfFlags, BsdfSample, BxDF, TransportMode, to_upper_side};
use caustica_core::{Spectrum, Vec2, Vec3};

/// Rough conductor with GGX roughness `distrib` and complex IOR `eta + i k`.
#[derive(Clone, Copy, Debug)]
pub struct RoughConductor {
    pub distrib: TrowbridgeReitz,
    pub eta: Spectrum,
    pub k: Spectrum,
    pub specular: Spectrum,
}

impl RoughConductor {
    /// Isotropic roughness `alpha`.
    pub fn new(alpha: f32, eta: Spectrum, k: Spectrum, specular: Spectrum) -> Self {
        Self {
            distrib: TrowbridgeReitz::isotropic(alpha),
            eta,
            k,
            specular,
        }
    }
}

impl BxDF for RoughConductor {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::GLOSSY
    }
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Spectrum {
        let (wo, wi) = to_upper_side(wo, wi);
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Spectrum::ZERO;
        }
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return Spectrum::ZERO;
        }
        let wm = wm.normalize();
        let f = fresnel_conductor(wo.dot(wm), self.eta, self.k);
        let v = self.distrib.d(wm) * self.distrib.g(wo, wi) / (4.0 * wo.z * wi.z);
        f * self.specular * v
    }
    fn sample(&self, wo: Vec3, _uc: f32, u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let flip = wo.z < 0.0;
        let wo_u = if flip {
            Vec3::new(wo.x, wo.y, -wo.z)
        } else {
            wo
        };
        let wm = self.distrib.sample_wm(wo_u, u);
        let mut wi = reflect(wo_u, wm);
        if wi.z <= 0.0 {
            return None;
        }
        let dot = wo_u.dot(wm);
        if dot <= 0.0 {
            return None;
        }
        let pdf = self.distrib.d_visible(wo_u, wm) / (4.0 * dot);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        // f cos θi / pdf = F G2 / G1(ωo).
        let f = fresnel_conductor(dot, self.eta, self.k);
        let weight = f * self.specular * (self.distrib.g(wo_u, wi) / self.distrib.g1(wo_u));
        if flip {
            wi.z = -wi.z;
        }
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            flags: BsdfFlags::REFLECTION | BsdfFlags::GLOSSY,
            eta: 1.0,
        })
    }
    fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        let (wo, wi) = to_upper_side(wo, wi);
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return 0.0;
        }
        let wm = wm.normalize();
        let dot = wo.dot(wm);
        if dot <= 0.0 {
            return 0.0;
        }
        self.distrib.d_visible(wo, wm) / (4.0 * dot)
    }
}
