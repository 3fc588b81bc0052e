//! Analytic disk.

use super::Aabb;
use crate::geometry::ShapeHit;
use caustica_core::{Frame, PI, Vec2, Vec3};

/// Disk of `radius` (m) around `center`, facing `normal` (unit).
#[derive(Clone, Copy, Debug)]
pub struct Disk {
    pub center: Vec3,
    pub normal: Vec3,
    pub radius: f32,
}

impl Disk {
    /// True if the disk can be intersected (finite, positive radius, nonzero normal).
    pub fn is_valid(&self) -> bool {
        self.center.is_finite()
            && self.normal.is_finite()
            && self.normal.length_squared() > 0.0
            && self.radius.is_finite()
            && self.radius > 0.0
    }

    /// Tight bounds of the (tilted) disk.
    pub fn bounds(&self) -> Aabb {
        let n = self.normal.normalize_or_zero();
        // Half-extent along axis i is r·sqrt(1 − n_i²).
        let e = (Vec3::ONE - n * n).max(Vec3::ZERO).map(f32::sqrt) * self.radius;
        Aabb {
            min: self.center - e,
            max: self.center + e,
        }
    }

    /// Ray parameter `t ∈ (0, t_max)` where `o + t d` meets the disk, or `None` (also for rays
    /// parallel to its plane). `normal` need not be unit here.
    #[inline]
    pub fn intersect(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
        let denom = d.dot(self.normal);
        if denom == 0.0 {
            return None;
        }
        let t = (self.center - o).dot(self.normal) / denom;
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        let p = o + d * t;
        let r = p - self.center;
        // Distance in the plane (remove the tiny out-of-plane component).
        let n2 = self.normal.length_squared();
        let in_plane = r - self.normal * (r.dot(self.normal) / n2);
        (in_plane.length_squared() <= self.radius * self.radius).then_some(t)
    }

    /// Surface data at `p_hit`: polar `uv = (ρ/R, φ/2π)` with φ measured from the first tangent
    /// of `Frame::from_normal(normal)`; `dpdu = R (cos φ s + sin φ t)`,
    /// `dpdv = 2π ρ (−sin φ s + cos φ t)` (so `dpdu × dpdv` points along `normal`).
    pub fn surface(&self, p_hit: Vec3) -> ShapeHit {
        let n = self.normal.normalize();
        let f = Frame::from_normal(n);
        let r = p_hit - self.center;
        let (x, y) = (r.dot(f.s), r.dot(f.t));
        let p = self.center + f.s * x + f.t * y;
        let rho = (x * x + y * y).sqrt();
        let mut phi = y.atan2(x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let (sin_phi, cos_phi) = phi.sin_cos();
        let uv = Vec2::new(rho / self.radius, phi / (2.0 * PI));
        let dpdu = (f.s * cos_phi + f.t * sin_phi) * self.radius;
        let mut dpdv = (f.t * cos_phi - f.s * sin_phi) * (2.0 * PI * rho);
        if dpdv.length_squared() <= 1e-12 * self.radius * self.radius {
            // At the centre the angular tangent vanishes; keep a frame around ng.
            dpdv = n.cross(dpdu) * (2.0 * PI * self.radius);
        }
        ShapeHit {
            p,
            ng: n,
            ns: n,
            uv,
            bary: uv,
            dpdu,
            dpdv,
        }
    }
}
