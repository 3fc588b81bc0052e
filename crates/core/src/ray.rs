//! Rays and ray differentials.

use glam::Vec3;

/// A ray `o + t d`, `t ∈ (0, t_max)`, at scene time `time`. `d` is normalised by every
/// producer in caustica.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub o: Vec3,
    pub d: Vec3,
    pub t_max: f32,
    /// Scene time (frames) at which the ray meets the geometry: moving meshes are
    /// interpolated to it. 0 for rays made by [`Ray::new`]; rays spawned from a surface hit
    /// inherit the hit's time.
    pub time: f32,
}

impl Ray {
    #[inline]
    pub fn new(o: Vec3, d: Vec3) -> Self {
        Self {
            o,
            d,
            t_max: f32::INFINITY,
            time: 0.0,
        }
    }
    #[inline]
    pub fn with_t_max(o: Vec3, d: Vec3, t_max: f32) -> Self {
        Self {
            o,
            d,
            t_max,
            time: 0.0,
        }
    }
    /// The same ray at scene time `time` (frames).
    #[inline]
    pub fn at_time(self, time: f32) -> Self {
        Self { time, ..self }
    }
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.o + self.d * t
    }
}

/// A ray with the first-order derivatives of its origin and direction with respect to the two
/// image-plane coordinates (x, y in pixels), after Igehy 1999 and seed 000 appendix B.1.
///
/// The `differentials` crate propagates these through transfer, reflection and refraction.
#[derive(Clone, Copy, Debug)]
pub struct RayDifferential {
    pub ray: Ray,
    /// ∂o/∂x, ∂o/∂y (m per pixel).
    pub dodx: Vec3,
    pub dody: Vec3,
    /// ∂d/∂x, ∂d/∂y (per pixel) of the *normalised* direction.
    pub dddx: Vec3,
    pub dddy: Vec3,
}

impl RayDifferential {
    /// A ray without meaningful differentials (all derivatives zero).
    pub fn without_differentials(ray: Ray) -> Self {
        Self {
            ray,
            dodx: Vec3::ZERO,
            dody: Vec3::ZERO,
            dddx: Vec3::ZERO,
            dddy: Vec3::ZERO,
        }
    }
}
