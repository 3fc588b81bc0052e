//! Analytic sphere.

use caustica_core::Vec3;

/// Sphere of `radius` (m) around `center`; its geometric normal points outward.
#[derive(Clone, Copy, Debug)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
}
