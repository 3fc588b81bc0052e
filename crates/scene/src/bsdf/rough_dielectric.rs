//! GGX rough dielectric (Walter, Marschner, Li & Torrance 2007, "Microfacet Models for
//! Refraction through Rough Surfaces", eqs. 16–21 and 38–41; implementation as in pbrt-v4 §9.7
//! `DielectricBxDF`, with visible-normal sampling from Heitz 2018).
//!
//! Oriented like [`super::Dielectric`]: `wo.z > 0` is outside and η = η_inside/η_outside.
//! With η′ = η(ωi side)/η(ωo side) (1 for reflection) and the generalised half vector
//! ωm = ±normalize(ωo + η′ ωi) facing +z:
//!
//! * reflection:   f = D(ωm) G2 F / (4 |cos θo cos θi|)
//! * transmission: f = D(ωm) G2 (1 − F) |ωi·ωm| |ωo·ωm| / (|cos θo cos θi| (ωi·ωm + ωo·ωm/η′)²),
//!   divided by η′² in radiance mode (Veach 1997 §5.2), not in importance mode,
//!
//! where F = Fr(ωo·ωm, η) exact. Sampling: ωm ~ D_ωo (visible normals), reflect with probability
//! F, otherwise refract through ωm; the Jacobians are dωm/dωi = 1/(4|ωi·ωm|) (reflection,
//! Walter eq. 14) and |ωi·ωm| / (ωi·ωm + ωo·ωm/η′)² (refraction, Walter eq. 17), so both sample
//! weights reduce to G2/G1(ωo) (× 1/η′² for radiance transmission). Single scattering only:
//! energy reflected among microfacets more than once is lost.

use super::fresnel::{fresnel_dielectric, reflect, refract};
use super::microfacet::TrowbridgeReitz;
use super::{BsdfFlags, BsdfSample, BxDF, TransportMode};
use caustica_core::{Spectrum, Vec2, Vec3};

/// Rough dielectric boundary with relative IOR `eta` = η_inside/η_outside.
#[derive(Clone, Copy, Debug)]
pub struct RoughDielectric {
    pub distrib: TrowbridgeReitz,
    pub eta: f32,
}

/// Geometry of a direction pair: generalised half vector and the crossing's η′.
struct HalfVector {
    wm: Vec3,
    reflect: bool,
    etap: f32,
}

impl RoughDielectric {
    /// Isotropic roughness `alpha`, relative IOR `eta` (≠ 1; use [`super::Dielectric`] for
    /// index-matched boundaries).
    pub fn new(alpha: f32, eta: f32) -> Self {
        Self {
            distrib: TrowbridgeReitz::isotropic(alpha),
            eta,
        }
    }

    fn half_vector(&self, wo: Vec3, wi: Vec3) -> Option<HalfVector> {
        let (co, ci) = (wo.z, wi.z);
        if co == 0.0 || ci == 0.0 {
            return None;
        }
        let reflect = co * ci > 0.0;
        let etap = if reflect {
            1.0
        } else if co > 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        };
        let wm = wi * etap + wo;
        if wm.length_squared() == 0.0 {
            return None;
        }
        let mut wm = wm.normalize();
        if wm.z < 0.0 {
            wm = -wm;
        }
        // Discard back-facing microfacets.
        if wm.dot(wi) * ci < 0.0 || wm.dot(wo) * co < 0.0 {
            return None;
        }
        Some(HalfVector { wm, reflect, etap })
    }

    fn radiance_scale(mode: TransportMode, etap: f32) -> f32 {
        match mode {
            TransportMode::Radiance => 1.0 / (etap * etap),
            TransportMode::Importance => 1.0,
        }
    }
}

impl BxDF for RoughDielectric {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::TRANSMISSION | BsdfFlags::GLOSSY
    }
    fn eval(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Spectrum {
        let Some(h) = self.half_vector(wo, wi) else {
            return Spectrum::ZERO;
        };
        let (co, ci) = (wo.z, wi.z);
        let wm = h.wm;
        let f = fresnel_dielectric(wo.dot(wm), self.eta);
        let d = self.distrib.d(wm);
        let g = self.distrib.g(wo, wi);
        let v = if h.reflect {
            d * g * f / (4.0 * (ci * co).abs())
        } else {
            let denom = {
                let s = wi.dot(wm) + wo.dot(wm) / h.etap;
                s * s * ci * co
            };
            d * (1.0 - f)
                * g
                * (wi.dot(wm) * wo.dot(wm) / denom).abs()
                * Self::radiance_scale(mode, h.etap)
        };
        if v.is_finite() {
            Spectrum::splat(v)
        } else {
            Spectrum::ZERO
        }
    }
    fn sample(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let wm = self.distrib.sample_wm(wo, u);
        let dot_o = wo.dot(wm);
        // Facets sampled from D_ωo face ωo; guard against rounding.
        if dot_o * wo.z <= 0.0 {
            return None;
        }
        let r = fresnel_dielectric(dot_o, self.eta);
        let d_vis = self.distrib.d_visible(wo, wm);
        let g_over_g1 = |wi: Vec3| self.distrib.g(wo, wi) / self.distrib.g1(wo);
        if uc < r {
            let wi = reflect(wo, wm);
            if wi.z * wo.z <= 0.0 {
                return None;
            }
            let pdf = d_vis / (4.0 * dot_o.abs()) * r;
            if !(pdf > 0.0 && pdf.is_finite()) {
                return None;
            }
            Some(BsdfSample {
                wi,
                weight: Spectrum::splat(g_over_g1(wi)),
                pdf,
                flags: BsdfFlags::REFLECTION | BsdfFlags::GLOSSY,
                eta: 1.0,
            })
        } else {
            let (wi, etap) = refract(wo, wm, self.eta)?;
            if wi.z * wo.z >= 0.0 {
                return None;
            }
            let s = wi.dot(wm) + dot_o / etap;
            let dwm_dwi = wi.dot(wm).abs() / (s * s);
            let pdf = d_vis * dwm_dwi * (1.0 - r);
            if !(pdf > 0.0 && pdf.is_finite()) {
                return None;
            }
            Some(BsdfSample {
                wi,
                weight: Spectrum::splat(g_over_g1(wi) * Self::radiance_scale(mode, etap)),
                pdf,
                flags: BsdfFlags::TRANSMISSION | BsdfFlags::GLOSSY,
                eta: etap,
            })
        }
    }
    fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        let Some(h) = self.half_vector(wo, wi) else {
            return 0.0;
        };
        let wm = h.wm;
        let dot_o = wo.dot(wm);
        let r = fresnel_dielectric(dot_o, self.eta);
        let d_vis = self.distrib.d_visible(wo, wm);
        let p = if h.reflect {
            d_vis / (4.0 * dot_o.abs()) * r
        } else {
            let s = wi.dot(wm) + dot_o / h.etap;
            d_vis * wi.dot(wm).abs() / (s * s) * (1.0 - r)
        };
        if p.is_finite() { p } else { 0.0 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::testutil::*;
    use caustica_core::sampling::{Pcg32, warp};

    const R: TransportMode = TransportMode::Radiance;
    const I: TransportMode = TransportMode::Importance;

    /// χ² of reflection + transmission for one η at α ∈ {0.05, 0.2, 0.6} and four incident
    /// directions (both sides); Šidák-corrected over the 24 tests of both η.
    fn chi2_for_eta(eta: f32, seed0: u64) {
        let alphas = [0.05f32, 0.2, 0.6];
        let angles = [(0.0f32, true), (30.0, false), (60.0, true), (85.0, false)];
        let level = sidak(2 * alphas.len() * angles.len());
        let mut seed = seed0;
        for &alpha in &alphas {
            let b = RoughDielectric::new(alpha, eta);
            for &(deg, up) in &angles {
                seed += 1;
                let wo = dir(deg, up);
                let n = if alpha < 0.1 { 100_000 } else { 150_000 };
                // The density jumps to zero where the generalised half vector crosses the
                // horizon, (ωo + η′ωi).z = 0: put a ring edge there.
                let etap = if up { eta } else { 1.0 / eta };
                let zb = (-wo.z / etap) as f64;
                let mut dom = lobe_domain(alpha < 0.1);
                if zb.abs() < 1.0 {
                    dom = dom.split_at(zb.acos());
                }
                let r = chi2_bsdf(&b, wo, R, &dom, seed, n);
                assert!(r.passed_at(level), "α={alpha} η={eta} θ={deg} up={up}: {r}");
            }
        }
    }

    /// Importance mode (light paths and photon cones, which sample the cone direction given
    /// the incident one): the sampler matches its density there too.
    #[test]
    fn chi2_importance_mode() {
        let level = sidak(4);
        let mut seed = 500;
        for eta in [1.5f32, 1.0 / 1.5] {
            let b = RoughDielectric::new(0.2, eta);
            for (deg, up) in [(30.0f32, false), (60.0, true)] {
                seed += 1;
                let wo = dir(deg, up);
                let etap = if up { eta } else { 1.0 / eta };
                let zb = (-wo.z / etap) as f64;
                let mut dom = lobe_domain(false);
                if zb.abs() < 1.0 {
                    dom = dom.split_at(zb.acos());
                }
                let r = chi2_bsdf(&b, wo, TransportMode::Importance, &dom, seed, 150_000);
                assert!(r.passed_at(level), "η={eta} θ={deg} up={up}: {r}");
            }
        }
    }

    #[test]
    fn chi2_reflection_and_transmission_eta_1_5() {
        chi2_for_eta(1.5, 0);
    }

    #[test]
    fn chi2_reflection_and_transmission_eta_1_over_1_5() {
        chi2_for_eta(1.0 / 1.5, 100);
    }

    #[test]
    fn weights_match_eval_and_pdf() {
        for alpha in [0.05f32, 0.2, 0.6] {
            for eta in [1.5f32, 1.0 / 1.5] {
                let b = RoughDielectric::new(alpha, eta);
                for (deg, up) in [(0.0f32, true), (30.0, false), (60.0, true), (85.0, false)] {
                    check_sample_consistency(&b, dir(deg, up), R, 1);
                    check_sample_consistency(&b, dir(deg, up), I, 2);
                }
            }
        }
    }

    #[test]
    fn reciprocity_and_eta_squared_rule() {
        for eta in [1.5f32, 1.0 / 1.5] {
            let b = RoughDielectric::new(0.3, eta);
            let mut rng = Pcg32::new(21, 0);
            let (mut nr, mut nt) = (0, 0);
            for _ in 0..20_000 {
                let wo = warp::square_to_uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                let wi = warp::square_to_uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                // Skip pairs whose facet is seen at grazing angles, where 1 − F and the
                // Jacobian lose most of their f32 precision.
                let etap = if wo.z * wi.z > 0.0 {
                    1.0
                } else if wo.z > 0.0 {
                    eta
                } else {
                    1.0 / eta
                };
                let wm = (wo + etap * wi).normalize();
                if wm.dot(wo).abs() < 0.05 || wm.dot(wi).abs() < 0.05 {
                    continue;
                }
                let a = b.eval(wo, wi, R)[0];
                let c = b.eval(wi, wo, R)[0];
                // η of the side of a direction: outside (z > 0) 1, inside eta.
                let n = |w: Vec3| if w.z > 0.0 { 1.0 } else { eta };
                // Veach 1997 eq. 5.14: f(ωo, ωi) / η(ωo)² = f(ωi, ωo) / η(ωi)².
                let lhs = a / (n(wo) * n(wo));
                let rhs = c / (n(wi) * n(wi));
                assert!(
                    (lhs - rhs).abs() <= 5e-3 * lhs.max(rhs) + 1e-7,
                    "{wo} {wi}: {a} {c}"
                );
                // The importance-mode BSDF is the adjoint: f*(ωo, ωi) = f(ωi, ωo).
                let adj = b.eval(wo, wi, I)[0];
                assert!((adj - c).abs() <= 5e-3 * adj.max(c) + 1e-7, "{adj} vs {c}");
                if a > 0.0 {
                    if wo.z * wi.z > 0.0 {
                        nr += 1;
                    } else {
                        nt += 1;
                    }
                }
            }
            assert!(nr > 100 && nt > 100, "{nr} {nt}");
        }
    }

    #[test]
    fn energy_is_conserved_in_importance_mode() {
        // Importance-mode weights measure the fraction of incident power scattered: ≤ 1, and
        // close to 1 for small α (single scattering loses little).
        for alpha in [0.05f32, 0.2, 0.6] {
            for eta in [1.5f32, 1.0 / 1.5] {
                let b = RoughDielectric::new(alpha, eta);
                for (deg, up) in [(0.0f32, true), (30.0, false), (60.0, true), (85.0, false)] {
                    let (m, tol) = albedo_sampled(&b, dir(deg, up), I, 3, 100_000);
                    assert!(m[0] <= 1.0 + tol[0], "α={alpha} η={eta} θ={deg}: {m:?}");
                    if alpha == 0.05 && deg <= 60.0 {
                        assert!(m[0] > 0.97, "α={alpha} η={eta} θ={deg}: {m:?}");
                    }
                }
            }
        }
        // Sampler-independent estimate from eval agrees with the sampled one (broad lobe).
        let b = RoughDielectric::new(0.6, 1.5);
        let wo = dir(40.0, true);
        let (ms, ts) = albedo_sampled(&b, wo, R, 5, 200_000);
        let (mu, tu) = albedo_uniform(&b, wo, R, 6, 400_000);
        assert!((ms[0] - mu[0]).abs() < ts[0] + tu[0], "{ms:?} vs {mu:?}");
    }

    #[test]
    fn pdf_integral_is_at_most_one() {
        for (alpha, eta, deg, up) in [
            (0.2f32, 1.5f32, 0.0f32, true),
            (0.6, 1.0 / 1.5, 60.0, false),
        ] {
            let b = RoughDielectric::new(alpha, eta);
            let wo = dir(deg, up);
            let i = lobe_domain(false).integrate(&|wi| b.pdf(wo, wi, R));
            assert!(i <= 1.0 + 2e-3 && i > 0.9, "{i}");
        }
    }
}
