//! The isotropic phase function, p = 1/(4π) sr⁻¹.

use super::{Phase, PhaseSample};
use caustica_core::sampling::warp::{square_to_uniform_sphere, uniform_sphere_pdf};
use caustica_core::{Vec2, Vec3};

/// Scatters equally into every direction.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Isotropic;

impl Phase for Isotropic {
    #[inline]
    fn eval(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        uniform_sphere_pdf()
    }
    #[inline]
    fn sample(&self, _wo: Vec3, u: Vec2) -> Option<PhaseSample> {
        Some(PhaseSample {
            wi: square_to_uniform_sphere(u),
            pdf: uniform_sphere_pdf(),
            weight: 1.0,
        })
    }
    #[inline]
    fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        uniform_sphere_pdf()
    }
}
