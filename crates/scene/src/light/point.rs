//! Isotropic point light.

use super::{EmissionSample, LightSample, LightSource};
use caustica_core::sampling::warp;
use caustica_core::{PI, Ray, Spectrum, Vec2, Vec3};

/// Isotropic point light of radiant intensity `intensity` (W/sr) at `position`.
#[derive(Clone, Debug)]
pub struct PointLight {
    pub position: Vec3,
    /// Radiant intensity (W/sr).
    pub intensity: Spectrum,
}

impl PointLight {
    pub fn new(position: Vec3, intensity: Spectrum) -> Self {
        Self {
            position,
            intensity,
        }
    }
}

impl LightSource for PointLight {
    /// `weight` = I / d² (W/m² per unit projected area, i.e. the irradiance at normal incidence).
    fn sample_li(&self, p: Vec3, _u: Vec2) -> Option<LightSample> {
        let (wi, dist, d2) = super::toward(p, self.position)?;
        Some(LightSample::delta(
            wi,
            dist,
            self.position,
            self.intensity / d2,
        ))
    }
    /// Uniform direction on the sphere: `weight` = 4π I (W), `pdf_dir` = 1/(4π).
    fn sample_emission(&self, _u_pos: Vec2, u_dir: Vec2) -> EmissionSample {
        let d = warp::square_to_uniform_sphere(u_dir);
        let pdf_dir = warp::uniform_sphere_pdf();
        EmissionSample {
            ray: Ray::new(self.position, d),
            normal: None,
            weight: self.intensity / pdf_dir,
            pdf_pos: 1.0,
            pdf_dir,
            delta_pos: true,
            delta_dir: false,
        }
    }
    /// 4π I (W).
    fn power(&self) -> Spectrum {
        self.intensity * (4.0 * PI)
    }
    fn is_delta(&self) -> bool {
        true
    }
    /// (0, 4π).
    fn emission_extent(&self) -> (f32, f32) {
        (0.0, 4.0 * PI)
    }
}
