//! Collimated beam of finite radius ("laser", seed 000 fig. 8.6).

use super::{EmissionSample, LightSample, LightSource};
use caustica_core::sampling::warp;
use caustica_core::{Frame, PI, Ray, Spectrum, Vec2, Vec3};

/// A collimated beam: light leaves the aperture disk of `radius` centred at `center`
/// (perpendicular to `frame.n`) along `frame.n`, with irradiance `irradiance` (W/m²) on any plane
/// perpendicular to the beam.
#[derive(Clone, Debug)]
pub struct BeamLight {
    pub center: Vec3,
    /// `frame.n` is the beam direction.
    pub frame: Frame,
    pub radius: f32,
    /// Irradiance across the beam (W/m²).
    pub irradiance: Spectrum,
}

impl BeamLight {
    pub fn new(center: Vec3, direction: Vec3, radius: f32, irradiance: Spectrum) -> Self {
        let d = direction.try_normalize().unwrap_or(-Vec3::Z);
        Self {
            center,
            frame: Frame::from_normal(d),
            radius: radius.max(0.0),
            irradiance,
        }
    }
    /// Unit beam direction.
    pub fn direction(&self) -> Vec3 {
        self.frame.n
    }
}

impl LightSource for BeamLight {
    /// A point downstream of the aperture and inside the beam cylinder receives
    /// `wi = −direction`, `weight` = E, `dist` = distance back to the aperture plane; `None`
    /// outside the cylinder or upstream of the aperture.
    fn sample_li(&self, p: Vec3, _u: Vec2) -> Option<LightSample> {
        let d = self.frame.n;
        let v = p - self.center;
        let along = v.dot(d);
        if along <= 0.0 || along.is_nan() {
            return None;
        }
        let perp = v - d * along;
        if perp.length_squared() > self.radius * self.radius {
            return None;
        }
        Some(LightSample::delta(
            -d,
            along,
            self.center + perp,
            self.irradiance,
        ))
    }
    /// Origin uniform on the aperture disk (`pdf_pos` = 1/(π r²)), delta direction, `weight` =
    /// E π r², `normal` = beam direction.
    fn sample_emission(&self, u_pos: Vec2, _u_dir: Vec2) -> EmissionSample {
        let c = warp::square_to_disk_concentric(u_pos) * self.radius;
        let o = self.center + self.frame.s * c.x + self.frame.t * c.y;
        let area = PI * self.radius * self.radius;
        let (pdf_pos, weight) = if area > 0.0 {
            (1.0 / area, self.irradiance * area)
        } else {
            (0.0, Spectrum::ZERO)
        };
        EmissionSample {
            ray: Ray::new(o, self.frame.n),
            normal: Some(self.frame.n),
            weight,
            pdf_pos,
            pdf_dir: 1.0,
            delta_pos: false,
            delta_dir: true,
        }
    }
    /// E π r² (W).
    fn power(&self) -> Spectrum {
        self.irradiance * (PI * self.radius * self.radius)
    }
    fn is_delta(&self) -> bool {
        true
    }
    /// (π r², 0).
    fn emission_extent(&self) -> (f32, f32) {
        (PI * self.radius * self.radius, 0.0)
    }
    /// Every photon leaves along self.frame.n, which is also the emitter normal.
    fn fixed_emission_direction(&self) -> Option<(Vec3, Option<Vec3>)> {
        Some((self.frame.n, Some(self.frame.n)))
    }
}
