//! STUB: to be implemented.

use super::{EmissionSample, LightSample, LightSource};
use caustica_core::{Spectrum, Vec2, Vec3};

#[derive(Clone, Debug)]
pub struct PointLight {}

impl LightSource for PointLight {
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

// TEMPORARY (io helper): stub constructor with the COMMON.md signature so the loaders compile;
// the lead drops this at merge in favour of the lights helper's implementation.
impl PointLight {
    pub fn new(position: Vec3, intensity: Spectrum) -> Self {
        let _ = (position, intensity);
        Self {}
    }
}
