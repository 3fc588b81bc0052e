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
use super::{BsdfFlags, BsdfSample, BxDF, TransportMode, sample_two_sided, to_upper_side};
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
        sample_two_sided(wo, |wo_u| self.sample_upper(wo_u, u))
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

impl RoughConductor {
    /// Samples a visible microfacet normal and reflects `wo_u` (above the surface) about it.
    fn sample_upper(&self, wo_u: Vec3, u: Vec2) -> Option<BsdfSample> {
        let wm = self.distrib.sample_wm(wo_u, u);
        let wi = reflect(wo_u, wm);
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
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            flags: BsdfFlags::REFLECTION | BsdfFlags::GLOSSY,
            eta: 1.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::testutil::*;
    use caustica_core::sampling::Pcg32;

    const MODE: TransportMode = TransportMode::Radiance;

    fn gold(alpha: f32) -> RoughConductor {
        RoughConductor::new(
            alpha,
            Spectrum::new(0.143_118_96, 0.374_957_04, 1.442_478_6),
            Spectrum::new(3.983_160_4, 2.385_720_7, 1.603_215_3),
            Spectrum::ONE,
        )
    }

    fn domain(alpha: f32) -> LobeDomain {
        lobe_domain(alpha < 0.1)
    }

    #[test]
    fn chi2_sampling_matches_pdf() {
        let alphas = [0.05f32, 0.2, 0.6];
        let angles = [(0.0f32, true), (30.0, true), (60.0, false), (85.0, true)];
        let level = sidak(alphas.len() * angles.len());
        for (i, &alpha) in alphas.iter().enumerate() {
            let b = gold(alpha);
            for (j, &(deg, up)) in angles.iter().enumerate() {
                let wo = dir(deg, up);
                let seed = (10 * i + j) as u64;
                let r = chi2_bsdf(&b, wo, MODE, &domain(alpha), seed, 200_000);
                assert!(r.passed_at(level), "α={alpha} θ={deg} up={up}: {r}");
            }
        }
    }

    #[test]
    fn pdf_integrates_to_acceptance_rate() {
        for alpha in [0.2f32, 0.6] {
            let b = gold(alpha);
            for deg in [0.0f32, 60.0, 85.0] {
                let wo = dir(deg, true);
                let integral = domain(alpha).integrate(&|wi| b.pdf(wo, wi, MODE));
                let mut rng = Pcg32::new(17, 0);
                let n = 100_000;
                let acc = (0..n)
                    .filter(|_| {
                        let u = Vec2::new(rng.next_f32(), rng.next_f32());
                        b.sample(wo, 0.5, u, MODE).is_some()
                    })
                    .count() as f64
                    / n as f64;
                let tol = 5.0 * (acc * (1.0 - acc) / n as f64).sqrt() + 2e-3;
                assert!(integral <= 1.0 + 2e-3, "∫pdf = {integral}");
                assert!(
                    (integral - acc).abs() < tol,
                    "α={alpha} θ={deg}: ∫pdf = {integral}, accepted {acc}"
                );
            }
        }
    }

    #[test]
    fn weights_reciprocity_and_energy() {
        // A (nearly) perfect reflector: F ≈ 1 for κ ≫ 1.
        let perfect =
            |alpha| RoughConductor::new(alpha, Spectrum::ONE, Spectrum::splat(1e4), Spectrum::ONE);
        for alpha in [0.05f32, 0.2, 0.6] {
            for (deg, up) in [(0.0f32, true), (30.0, false), (60.0, true), (85.0, true)] {
                let wo = dir(deg, up);
                check_sample_consistency(&gold(alpha), wo, MODE, 1);
                let (m, tol) = albedo_sampled(&perfect(alpha), wo, MODE, 2, 100_000);
                assert!(m[0] <= 1.0 + tol[0], "α={alpha} θ={deg}: albedo {m:?}");
                // Single scattering at normal incidence loses at least the facets steeper than
                // 45° (visible-normal fraction α²/(1+α²)), and little more for small α.
                if deg == 0.0 {
                    let lost = alpha * alpha / (1.0 + alpha * alpha);
                    let m0 = m[0] as f32;
                    assert!(m0 < 1.0 - lost + 1e-3, "α={alpha}: albedo {m0}");
                    assert!(m0 > 1.0 - 2.0 * lost - 0.01, "α={alpha}: albedo {m0}");
                }
            }
            check_reflection_reciprocity(&gold(alpha.max(0.2)), 3);
        }
        // The sampler-based albedo agrees with a sampler-independent estimate from eval alone.
        let b = gold(0.6);
        let wo = dir(40.0, true);
        let (ms, ts) = albedo_sampled(&b, wo, MODE, 5, 200_000);
        let (mu, tu) = albedo_uniform(&b, wo, MODE, 6, 400_000);
        for c in 0..3 {
            assert!((ms[c] - mu[c]).abs() < ts[c] + tu[c], "{ms:?} vs {mu:?}");
        }
    }
}
