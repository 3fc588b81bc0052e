//! Directional (distant) light.

use super::{EmissionSample, LightSample, LightSource};
use caustica_core::sampling::warp;
use caustica_core::{Frame, PI, Ray, Spectrum, Vec2, Vec3};

/// Light arriving from infinitely far away along `direction` with irradiance `irradiance`
/// (W/m²) on a plane perpendicular to it.
#[derive(Clone, Debug)]
pub struct DirectionalLight {
    /// Unit direction the light travels in.
    pub direction: Vec3,
    /// Irradiance on a plane perpendicular to `direction` (W/m²).
    pub irradiance: Spectrum,
    /// Scene bounding sphere, set by `preprocess`.
    pub scene_center: Vec3,
    pub scene_radius: f32,
}

impl DirectionalLight {
    pub fn new(direction: Vec3, irradiance: Spectrum) -> Self {
        Self {
            direction: direction.try_normalize().unwrap_or(-Vec3::Z),
            irradiance,
            scene_center: Vec3::ZERO,
            scene_radius: 0.0,
        }
    }
}

impl LightSource for DirectionalLight {
    fn preprocess(&mut self, center: Vec3, radius: f32) {
        self.scene_center = center;
        self.scene_radius = radius.max(0.0);
    }
    /// `wi = −direction`, `dist = ∞`, `weight` = E; `p` is a point 2 r beyond `p` toward the
    /// light (outside the scene).
    fn sample_li(&self, p: Vec3, _u: Vec2) -> Option<LightSample> {
        let wi = -self.direction;
        let far = p + wi * (2.0 * self.scene_radius.max(1.0));
        Some(LightSample::delta(wi, f32::INFINITY, far, self.irradiance))
    }
    /// Origin uniform on the disk of the bounding radius r perpendicular to `direction`,
    /// centred one radius upstream of the scene centre (outside the bounding sphere);
    /// `pdf_pos` = 1/(π r²), delta direction, `weight` = E π r². `normal` is the disk's normal
    /// (= `direction`), so photon differentials span the disk (seed 002 eq. 2–3).
    fn sample_emission(&self, u_pos: Vec2, _u_dir: Vec2) -> EmissionSample {
        let r = self.scene_radius;
        let f = Frame::from_normal(self.direction);
        let c = warp::square_to_disk_concentric(u_pos) * r;
        let o = self.scene_center + f.s * c.x + f.t * c.y - self.direction * r;
        let area = PI * r * r;
        let (pdf_pos, weight) = if area > 0.0 {
            (1.0 / area, self.irradiance * area)
        } else {
            (0.0, Spectrum::ZERO)
        };
        EmissionSample {
            ray: Ray::new(o, self.direction),
            normal: Some(self.direction),
            weight,
            pdf_pos,
            pdf_dir: 1.0,
            delta_pos: false,
            delta_dir: true,
        }
    }
    /// E π r² (W): the flux through the scene's bounding disk.
    fn power(&self) -> Spectrum {
        self.irradiance * (PI * self.scene_radius * self.scene_radius)
    }
    fn is_delta(&self) -> bool {
        true
    }
    fn is_infinite(&self) -> bool {
        true
    }
    /// (π r², 0).
    fn emission_extent(&self) -> (f32, f32) {
        (PI * self.scene_radius * self.scene_radius, 0.0)
    }
    /// Every photon leaves along self.direction, which is also the emitter normal.
    fn fixed_emission_direction(&self) -> Option<(Vec3, Option<Vec3>)> {
        Some((self.direction, Some(self.direction)))
    }
}
