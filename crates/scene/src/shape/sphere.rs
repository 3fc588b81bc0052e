//! Analytic sphere.

use super::Aabb;
use crate::geometry::ShapeHit;
use caustica_core::{Frame, PI, Vec2, Vec3};

/// Sphere of `radius` (m) around `center`; its geometric normal points outward.
#[derive(Clone, Copy, Debug)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
}

impl Sphere {
    /// True if the sphere can be intersected (finite centre, positive finite radius).
    pub fn is_valid(&self) -> bool {
        self.center.is_finite() && self.radius.is_finite() && self.radius > 0.0
    }

    pub fn bounds(&self) -> Aabb {
        Aabb {
            min: self.center - Vec3::splat(self.radius),
            max: self.center + Vec3::splat(self.radius),
        }
    }

    /// Nearest ray parameter `t ∈ (0, t_max)` where `o + t d` meets the sphere, or `None`.
    ///
    /// Numerically stable: the discriminant is formed from the squared distance of the centre to
    /// the ray's line (Haines et al., Ray Tracing Gems ch. 7) and the roots via the
    /// cancellation-free `q` form. Works from inside (returns the far root).
    #[inline]
    pub fn intersect(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
        let oc = o - self.center;
        let a = d.length_squared();
        let b = oc.dot(d); // half the linear coefficient
        let c = oc.length_squared() - self.radius * self.radius;
        let f = oc - d * (b / a);
        let disc = a * (self.radius * self.radius - f.length_squared());
        if disc.is_nan() || disc < 0.0 {
            return None;
        }
        let q = -(b + disc.sqrt().copysign(b));
        let (mut t0, mut t1) = if q != 0.0 { (c / q, q / a) } else { (0.0, 0.0) };
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        if t0 > 0.0 && t0 < t_max {
            Some(t0)
        } else if t1 > 0.0 && t1 < t_max {
            Some(t1)
        } else {
            None
        }
    }

    /// Surface data at the hit point `p_hit` (re-projected onto the sphere).
    ///
    /// `uv = (φ/2π, θ/π)` with φ the azimuth around +z from +x in [0, 2π) and θ the polar
    /// angle from +z; `dpdu = 2π (−y, x, 0)`, `dpdv = π (z cos φ, z sin φ, −r sin θ)` in
    /// centre-relative coordinates (a tangent frame around `ng` at the poles).
    pub fn surface(&self, p_hit: Vec3) -> ShapeHit {
        let mut rel = p_hit - self.center;
        let len = rel.length();
        if len > 0.0 {
            rel *= self.radius / len;
        } else {
            rel = Vec3::Z * self.radius;
        }
        let p = self.center + rel;
        let ng = rel / self.radius;
        let mut phi = rel.y.atan2(rel.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let cos_theta = (rel.z / self.radius).clamp(-1.0, 1.0);
        let theta = cos_theta.acos();
        let uv = Vec2::new(phi / (2.0 * PI), theta / PI);
        let (sin_phi, cos_phi) = phi.sin_cos();
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let mut dpdu = Vec3::new(-rel.y, rel.x, 0.0) * (2.0 * PI);
        let mut dpdv = Vec3::new(rel.z * cos_phi, rel.z * sin_phi, -self.radius * sin_theta) * PI;
        if dpdu.cross(dpdv).length_squared() <= 1e-12 * self.radius.powi(4) {
            let f = Frame::from_normal(ng);
            dpdu = f.s * (2.0 * PI * self.radius);
            dpdv = f.t * (PI * self.radius);
        }
        ShapeHit {
            p,
            ng,
            ns: ng,
            uv,
            bary: uv,
            dpdu,
            dpdv,
        }
    }
}
