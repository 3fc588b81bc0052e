//! STUB: to be implemented.

use super::{BsdfFlags, BsdfSample, BxDF, TransportMode};
use caustica_core::{Spectrum, Vec2, Vec3};

#[derive(Clone, Copy, Debug)]
pub struct Phong {}

impl BxDF for Phong {
    fn flags(&self) -> BsdfFlags {
        todo!()
    }
    fn eval(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> Spectrum {
        todo!()
    }
    fn sample(&self, _wo: Vec3, _uc: f32, _u: Vec2, _mode: TransportMode) -> Option<BsdfSample> {
        todo!()
    }
    fn pdf(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> f32 {
        todo!()
    }
}
