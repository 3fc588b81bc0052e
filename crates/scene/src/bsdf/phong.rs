//! Normalised Blinn–Phong glossy lobe plus Lambertian diffuse.
//!
//! Half-vector density (seed 001 eq. 4.1, Blinn 1977 lobe): p_h(ωh) = (n+1)/(2π) cosⁿθh, sampled
//! by cos θh = ξ₁^{1/(n+1)}, φh = 2πξ₂; the reflected direction ωi = reflect(ωo, ωh) then has
//! density p(ωi) = p_h(ωh) / (4 ωo·ωh) (Walter et al. 2007 eq. 14).
//!
//! BRDF (Ashikhmin & Shirley 2000, "An Anisotropic Phong BRDF Model", eq. 4, isotropic, without
//! its Fresnel factor):
//!
//! f = kd/π + ks (n+1)/(8π) cosⁿθh / ((ωh·ωo) max(cos θo, cos θi)).
//!
//! It is symmetric, and because f_s cos θi / p(ωi) = ks cos θi / max(cos θo, cos θi) ≤ ks, the
//! glossy albedo never exceeds ks at any angle, so kd + ks ≤ 1 guarantees energy conservation.
//! (The popular (n+8)/(8π) cosⁿθh normalisation does not: its normal-incidence albedo is
//! ≈ n(n+8)/((n+2)(n+4)) > 1 for n > 4.) Lobes are chosen with probability proportional to the
//! mean of kd and ks; the returned pdf is the mixture density. Two-sided.

use super::fresnel::reflect;
use super::{BsdfFlags, BsdfSample, BxDF, TransportMode, sample_two_sided, to_upper_side};
use caustica_core::sampling::warp;
use caustica_core::{INV_PI, PI, Spectrum, Vec2, Vec3};

/// Blinn–Phong glossy lobe (`specular` ks, `exponent` n ≥ 0) plus Lambertian `diffuse` kd,
/// with kd + ks ≤ 1 per channel.
#[derive(Clone, Copy, Debug)]
pub struct Phong {
    pub diffuse: Spectrum,
    pub specular: Spectrum,
    pub exponent: f32,
}

impl Phong {
    pub fn new(diffuse: Spectrum, specular: Spectrum, exponent: f32) -> Self {
        Self {
            diffuse,
            specular,
            exponent,
        }
    }

    /// Probability of sampling the glossy lobe.
    fn spec_prob(&self) -> f32 {
        let d = self.diffuse.average().max(0.0);
        let s = self.specular.average().max(0.0);
        if d + s <= 0.0 { 0.0 } else { s / (d + s) }
    }

    /// Half-vector density (n+1)/(2π) cosⁿθh (sr⁻¹), seed 001 eq. 4.1.
    pub fn half_vector_pdf(&self, cos_h: f32) -> f32 {
        if cos_h <= 0.0 {
            return 0.0;
        }
        (self.exponent + 1.0) * 0.5 * std::f32::consts::FRAC_1_PI * cos_h.powf(self.exponent)
    }

    /// Glossy part of f for upper-side directions.
    fn glossy(&self, wo: Vec3, wi: Vec3) -> f32 {
        let wh = (wo + wi).normalize();
        let dot = wo.dot(wh);
        if dot <= 0.0 || wh.z <= 0.0 {
            return 0.0;
        }
        let v =
            (self.exponent + 1.0) / (8.0 * PI) * wh.z.powf(self.exponent) / (dot * wo.z.max(wi.z));
        if v.is_finite() { v } else { 0.0 }
    }

    /// Solid-angle density of the glossy sampler for upper-side directions.
    fn glossy_pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let wh = (wo + wi).normalize();
        let dot = wo.dot(wh);
        if dot <= 0.0 {
            return 0.0;
        }
        let p = self.half_vector_pdf(wh.z) / (4.0 * dot);
        if p.is_finite() { p } else { 0.0 }
    }

    fn eval_upper(&self, wo: Vec3, wi: Vec3) -> Spectrum {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Spectrum::ZERO;
        }
        self.diffuse * INV_PI + self.specular * self.glossy(wo, wi)
    }

    fn pdf_upper(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let ps = self.spec_prob();
        ps * self.glossy_pdf(wo, wi) + (1.0 - ps) * wi.z * INV_PI
    }
}

impl BxDF for Phong {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE | BsdfFlags::GLOSSY
    }
    fn eval(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Spectrum {
        let (wo, wi) = to_upper_side(wo, wi);
        self.eval_upper(wo, wi)
    }
    fn sample(&self, wo: Vec3, uc: f32, u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        sample_two_sided(wo, |wo_u| self.sample_upper(wo_u, uc, u))
    }
    fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        let (wo, wi) = to_upper_side(wo, wi);
        self.pdf_upper(wo, wi)
    }
}

impl Phong {
    /// Samples the glossy or the diffuse lobe (chosen by `uc`) for `wo` above the surface.
    fn sample_upper(&self, wo_u: Vec3, uc: f32, u: Vec2) -> Option<BsdfSample> {
        let ps = self.spec_prob();
        if ps <= 0.0 && self.diffuse.is_black() {
            return None;
        }
        let (wi, flags) = if uc < ps {
            let cos_h = u.x.powf(1.0 / (self.exponent + 1.0));
            let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
            let phi = 2.0 * PI * u.y;
            let wh = Vec3::new(sin_h * phi.cos(), sin_h * phi.sin(), cos_h);
            (reflect(wo_u, wh), BsdfFlags::REFLECTION | BsdfFlags::GLOSSY)
        } else {
            (
                warp::square_to_cosine_hemisphere(u),
                BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE,
            )
        };
        if wi.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf_upper(wo_u, wi);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let weight = self.eval_upper(wo_u, wi) * (wi.z / pdf);
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            flags,
            eta: 1.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::testutil::*;

    const MODE: TransportMode = TransportMode::Radiance;

    fn cases() -> Vec<Phong> {
        vec![
            Phong::new(Spectrum::splat(0.5), Spectrum::splat(0.5), 1.0),
            Phong::new(Spectrum::splat(0.2), Spectrum::new(0.7, 0.6, 0.5), 30.0),
            Phong::new(Spectrum::splat(0.1), Spectrum::splat(0.9), 300.0),
            Phong::new(Spectrum::ZERO, Spectrum::ONE, 500.0),
        ]
    }

    #[test]
    fn chi2_sampling_matches_pdf() {
        let angles = [(0.0f32, true), (30.0, true), (60.0, false), (85.0, true)];
        let cs = cases();
        let level = sidak(cs.len() * angles.len());
        for (i, b) in cs.iter().enumerate() {
            for (j, &(deg, up)) in angles.iter().enumerate() {
                let wo = dir(deg, up);
                let narrow = b.exponent > 100.0;
                let seed = (10 * i + j) as u64;
                let r = chi2_bsdf(b, wo, MODE, &lobe_domain(narrow), seed, 150_000);
                assert!(r.passed_at(level), "n={} θ={deg} up={up}: {r}", b.exponent);
            }
        }
    }

    #[test]
    fn half_vector_density_is_normalised() {
        // ∫ (n+1)/(2π) cosⁿθh dωh = 1 over the hemisphere (seed 001 eq. 4.1).
        for n in [0.0f32, 1.0, 30.0, 300.0] {
            let b = Phong::new(Spectrum::ZERO, Spectrum::ONE, n);
            let i = lobe_domain(true).integrate(&|w| b.half_vector_pdf(w.z));
            assert!((i - 1.0).abs() < 2e-3, "n={n}: {i}");
        }
    }

    #[test]
    fn weights_reciprocity_energy() {
        for b in cases() {
            for (deg, up) in [(0.0f32, true), (45.0, false), (80.0, true)] {
                let wo = dir(deg, up);
                check_sample_consistency(&b, wo, MODE, 1);
                // Albedo ≤ kd + ks ≤ 1 (sampled, and from eval with uniform sampling when the
                // lobe is broad enough for that estimator to be precise).
                let bound = (b.diffuse + b.specular).max_component() as f64;
                let (m, tol) = albedo_sampled(&b, wo, MODE, 2, 100_000);
                for c in 0..3 {
                    assert!(m[c] <= bound + tol[c], "n={} θ={deg}: {m:?}", b.exponent);
                }
                if b.exponent <= 30.0 {
                    let (mu, tu) = albedo_uniform(&b, wo, MODE, 3, 300_000);
                    assert!((m[0] - mu[0]).abs() < tol[0] + tu[0], "{m:?} vs {mu:?}");
                }
            }
            check_reflection_reciprocity(&b, 4);
        }
        // Pure glossy white lobe at normal incidence: weight = cos θi / max(cos θo, cos θi) =
        // cos θi ≤ 1, and ≈ 1 for a sharp lobe (all mass near the mirror direction).
        let b = Phong::new(Spectrum::ZERO, Spectrum::ONE, 2000.0);
        let (m, _) = albedo_sampled(&b, Vec3::Z, MODE, 5, 50_000);
        assert!(m[0] > 0.99 && m[0] <= 1.0, "{m:?}");
    }
}
