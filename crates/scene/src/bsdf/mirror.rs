//! Perfect specular reflector: ωi = (−ωo.x, −ωo.y, ωo.z), f = R δ(ωi − reflect(ωo)) / |cos θi|
//! (pbrt-v4 §9.3 specular reflection with F replaced by a constant reflectance). Two-sided.

use super::{BsdfFlags, BsdfSample, BxDF, TransportMode};
use caustica_core::{Spectrum, Vec2, Vec3};

/// Perfect mirror with per-channel reflectance `reflectance` ∈ [0, 1].
#[derive(Clone, Copy, Debug)]
pub struct Mirror {
    pub reflectance: Spectrum,
}

impl Mirror {
    pub fn new(reflectance: Spectrum) -> Self {
        Self { reflectance }
    }
}

impl BxDF for Mirror {
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
        Some(BsdfSample {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            weight: self.reflectance,
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
    fn reflects_exactly_on_both_sides() {
        let m = Mirror::new(Spectrum::new(0.9, 0.5, 0.1));
        for wo in [
            Vec3::new(0.3, -0.4, 0.866_025_4),
            Vec3::new(-0.6, 0.0, -0.8),
            Vec3::Z,
        ] {
            let s = m
                .sample(wo, 0.5, Vec2::new(0.3, 0.7), TransportMode::Radiance)
                .unwrap();
            // Angle of incidence equals angle of reflection and the plane is preserved:
            // wo + wi is parallel to the normal.
            let sum = wo + s.wi;
            assert!(sum.x.abs() < 1e-7 && sum.y.abs() < 1e-7, "{wo} {:?}", s.wi);
            assert_eq!(s.wi.z, wo.z);
            assert_eq!(s.weight, Spectrum::new(0.9, 0.5, 0.1));
            assert!(s.flags.is_delta() && s.flags.contains(BsdfFlags::REFLECTION));
            assert_eq!(s.eta, 1.0);
            assert_eq!(m.eval(wo, s.wi, TransportMode::Radiance), Spectrum::ZERO);
            assert_eq!(m.pdf(wo, s.wi, TransportMode::Radiance), 0.0);
        }
    }
}
