//! Smooth conductor: delta reflection weighted by the exact conductor Fresnel term
//! F(cos θo; η + iκ) (see [`super::fresnel::fresnel_conductor`]) times a specular tint
//! (pbrt-v4 §9.4 `ConductorBxDF`, smooth case; Mitsuba 3 `conductor`). Two-sided.

use super::fresnel::fresnel_conductor;
use super::{BsdfFlags, BsdfSample, BxDF, TransportMode};
use caustica_core::{Spectrum, Vec2, Vec3};

/// Smooth conductor with complex IOR `eta + i k` (per channel, relative to the outside medium).
#[derive(Clone, Copy, Debug)]
pub struct Conductor {
    pub eta: Spectrum,
    pub k: Spectrum,
    /// Multiplicative tint (1 for physically based metals).
    pub specular: Spectrum,
}

impl Conductor {
    pub fn new(eta: Spectrum, k: Spectrum, specular: Spectrum) -> Self {
        Self { eta, k, specular }
    }
}

impl BxDF for Conductor {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::DELTA
    }
    fn eval(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> Spectrum {
        Spectrum::ZERO
    }
    fn sample(&self, wo: Vec3, _uc: f32, _u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let f = fresnel_conductor(wo.z.abs(), self.eta, self.k);
        Some(BsdfSample {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            weight: f * self.specular,
            pdf: 1.0,
            flags: BsdfFlags::REFLECTION | BsdfFlags::DELTA,
            eta: 1.0,
        })
    }
    fn pdf(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> f32 {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weight_is_fresnel_times_tint_on_both_sides() {
        // Gold, normal incidence: ((η−1)² + κ²)/((η+1)² + κ²) per channel.
        let eta = Spectrum::new(0.143_118_96, 0.374_957_04, 1.442_478_6);
        let k = Spectrum::new(3.983_160_4, 2.385_720_7, 1.603_215_3);
        let c = Conductor::new(eta, k, Spectrum::new(1.0, 0.5, 1.0));
        for wo in [Vec3::Z, -Vec3::Z] {
            let s = c
                .sample(wo, 0.1, Vec2::ZERO, TransportMode::Radiance)
                .unwrap();
            assert_eq!(s.wi, wo);
            for ch in 0..3 {
                let (e, kk) = (eta[ch], k[ch]);
                let r = ((e - 1.0).powi(2) + kk * kk) / ((e + 1.0).powi(2) + kk * kk);
                let tint = [1.0, 0.5, 1.0][ch];
                assert!((s.weight[ch] - r * tint).abs() < 1e-5, "{ch}");
            }
        }
    }
}
