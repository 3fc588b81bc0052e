//! Constant environment light.

use super::{EmissionSample, LightSample, LightSource};
use caustica_core::sampling::warp;
use caustica_core::{Frame, PI, Ray, Spectrum, Vec2, Vec3};

/// Radiance `radiance` (W/m²/sr) arriving from every direction at infinity.
#[derive(Clone, Debug)]
pub struct EnvironmentLight {
    pub radiance: Spectrum,
    /// Scene bounding sphere, set by `preprocess`.
    pub scene_center: Vec3,
    pub scene_radius: f32,
}

impl EnvironmentLight {
    pub fn constant(radiance: Spectrum) -> Self {
        Self {
            radiance,
            scene_center: Vec3::ZERO,
            scene_radius: 0.0,
        }
    }
}

impl LightSource for EnvironmentLight {
    fn preprocess(&mut self, center: Vec3, radius: f32) {
        self.scene_center = center;
        self.scene_radius = radius.max(0.0);
    }
    /// Uniform direction on the sphere (no cosine), `pdf` = 1/(4π), `weight` = 4π L,
    /// `dist` = ∞, `p` 2 r beyond `p` along `wi`.
    fn sample_li(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        let wi = warp::square_to_uniform_sphere(u);
        let pdf = warp::uniform_sphere_pdf();
        Some(LightSample {
            wi,
            dist: f32::INFINITY,
            p: p + wi * (2.0 * self.scene_radius.max(1.0)),
            weight: self.radiance / pdf,
            pdf,
            delta: false,
        })
    }
    fn pdf_li(&self, _p: Vec3, _wi: Vec3, _light_p: Vec3, _light_n: Vec3) -> f32 {
        warp::uniform_sphere_pdf()
    }
    /// L for every direction.
    fn le(&self, _n: Vec3, _w: Vec3) -> Spectrum {
        self.radiance
    }
    /// pbrt-v4 style: the travel direction `d` is uniform on the sphere (`pdf_dir` = 1/(4π)); the
    /// origin is uniform on the disk of the bounding radius r perpendicular to `d`, centred one
    /// radius upstream of the scene centre (`pdf_pos` = 1/(π r²)); `weight` = L/(pdf_pos·pdf_dir)
    /// = 4π² r² L (every photon crosses its disk at normal incidence, so there is no cosine).
    /// `normal` is the disk normal `d`.
    fn sample_emission(&self, u_pos: Vec2, u_dir: Vec2) -> EmissionSample {
        let d = warp::square_to_uniform_sphere(u_dir);
        let pdf_dir = warp::uniform_sphere_pdf();
        let r = self.scene_radius;
        let f = Frame::from_normal(d);
        let c = warp::square_to_disk_concentric(u_pos) * r;
        let o = self.scene_center + f.s * c.x + f.t * c.y - d * r;
        let area = PI * r * r;
        let (pdf_pos, weight) = if area > 0.0 {
            (1.0 / area, self.radiance / (pdf_dir / area))
        } else {
            (0.0, Spectrum::ZERO)
        };
        EmissionSample {
            ray: Ray::new(o, d),
            normal: Some(d),
            weight,
            pdf_pos,
            pdf_dir,
            delta_pos: false,
            delta_dir: false,
        }
    }
    /// Flux entering the scene's bounding sphere: for each direction ω the radiance L crosses
    /// the disk of area π r² perpendicular to ω, giving L π r² per steradian, so
    /// Φ = 4π · π r² · L. (Equivalently the sphere's area 4π r² times the irradiance π L that a
    /// uniform L produces on each surface element from the outside.)
    fn power(&self) -> Spectrum {
        self.radiance * (4.0 * PI * PI * self.scene_radius * self.scene_radius)
    }
    fn is_delta(&self) -> bool {
        false
    }
    fn is_infinite(&self) -> bool {
        true
    }
    /// (π r², 4π): the emission disk and all directions.
    fn emission_extent(&self) -> (f32, f32) {
        (PI * self.scene_radius * self.scene_radius, 4.0 * PI)
    }
}
