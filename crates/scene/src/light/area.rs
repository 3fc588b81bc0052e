//! STUB: to be implemented.

use super::{EmissionSample, LightSample, LightSource};
use caustica_core::{Spectrum, Vec2, Vec3};

#[derive(Clone, Debug)]
pub struct AreaLight {}

impl LightSource for AreaLight {
    fn sample_li(&self, _p: Vec3, _u: Vec2) -> Option<LightSample> {
        todo!()
    }
    fn pdf_li(&self, _p: Vec3, _wi: Vec3, _light_p: Vec3, _light_n: Vec3) -> f32 {
        todo!()
    }
    fn le(&self, _n: Vec3, _w: Vec3) -> Spectrum {
        todo!()
    }
    fn sample_emission(&self, _u_pos: Vec2, _u_dir: Vec2) -> EmissionSample {
        todo!()
    }
    fn power(&self) -> Spectrum {
        todo!()
    }
    fn is_delta(&self) -> bool {
        todo!()
    }
}

/// The surface an area light emits from (world space).
#[derive(Clone, Debug)]
pub enum AreaShape {
    Triangles(Vec<[Vec3; 3]>),
    Sphere(crate::shape::Sphere),
    Disk(crate::shape::Disk),
}

impl AreaLight {
    /// Diffuse emitter of radiance `radiance` (W/m²/sr) on `shape`, one-sided unless `two_sided`.
    pub fn new(shape: AreaShape, radiance: Spectrum, two_sided: bool) -> Self {
        let _ = (shape, radiance, two_sided);
        todo!()
    }
}
