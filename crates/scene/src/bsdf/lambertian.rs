//! Lambertian (ideal diffuse) reflection: f = ρ/π (Lambert 1760; pbrt-v4 §9.2), sampled with
//! the cosine-weighted hemisphere (Malley's method), whose density cos θi/π makes the sample
//! weight exactly ρ. Two-sided.

use super::{BsdfFlags, BsdfSample, BxDF, TransportMode, sample_two_sided, to_upper_side};
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
        sample_two_sided(wo, |_| {
            let wi = warp::square_to_cosine_hemisphere(u);
            if wi.z <= 0.0 {
                return None;
            }
            let pdf = wi.z * INV_PI;
            Some(BsdfSample {
                wi,
                weight: self.albedo,
                pdf,
                flags: BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE,
                eta: 1.0,
            })
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::testutil::*;

    const MODE: TransportMode = TransportMode::Radiance;

    #[test]
    fn chi2_sampling_matches_pdf() {
        let b = Lambertian::new(Spectrum::new(0.8, 0.5, 0.2));
        let angles = [(0.0f32, true), (30.0, true), (60.0, false), (85.0, true)];
        for (i, &(deg, up)) in angles.iter().enumerate() {
            let wo = dir(deg, up);
            let center = if up { Vec3::Z } else { -Vec3::Z };
            let r = chi2_bsdf(
                &b,
                wo,
                MODE,
                &LobeDomain::new(center, 1.0),
                10 + i as u64,
                100_000,
            );
            assert!(r.passed_at(sidak(angles.len())), "θ={deg} up={up}: {r}");
        }
    }

    #[test]
    fn pdf_integrates_to_one_and_white_albedo_is_one() {
        let b = Lambertian::new(Spectrum::ONE);
        for (deg, up) in [(0.0f32, true), (70.0, false)] {
            let wo = dir(deg, up);
            let i = LobeDomain::new(Vec3::Z, 1.0).integrate(&|wi| b.pdf(wo, wi, MODE));
            assert!((i - 1.0).abs() < 1e-3, "{i}");
            // Independent of the sampler: uniform sphere estimate of ∫ f |cos| = 1.
            let (m, tol) = albedo_uniform(&b, wo, MODE, 3, 200_000);
            assert!((m[0] - 1.0).abs() < tol[0], "{m:?} ± {tol:?}");
            check_sample_consistency(&b, wo, MODE, 4);
        }
        check_reflection_reciprocity(&Lambertian::new(Spectrum::new(0.3, 0.6, 0.9)), 9);
    }

    #[test]
    fn two_sided_and_no_transmission() {
        let b = Lambertian::new(Spectrum::splat(0.5));
        let (a, c) = (dir(30.0, true), dir(50.0, true));
        let (a2, c2) = (dir(30.0, false), dir(50.0, false));
        assert_eq!(b.eval(a, c, MODE), b.eval(a2, c2, MODE));
        assert_eq!(b.eval(a, c2, MODE), Spectrum::ZERO);
        let s = b.sample(a2, 0.5, Vec2::new(0.2, 0.9), MODE).unwrap();
        assert!(s.wi.z < 0.0);
    }
}
