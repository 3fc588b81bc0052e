//! Spot light with Mitsuba 3 semantics.

use super::{EmissionSample, LightSample, LightSource};
use caustica_core::sampling::warp;
use caustica_core::{Frame, Ray, Spectrum, Vec2, Vec3};

/// Spot light at `position` shining along `frame.n`. The intensity is `intensity` (W/sr) inside
/// the cone of half-angle `beam_width`, falls linearly in angle to 0 at `cutoff_angle`, and is 0
/// beyond (Mitsuba 3's `spot`).
#[derive(Clone, Debug)]
pub struct SpotLight {
    pub position: Vec3,
    /// Emission frame; `frame.n` is the spot axis.
    pub frame: Frame,
    /// On-axis radiant intensity (W/sr).
    pub intensity: Spectrum,
    /// Half-angle (radians) where the intensity reaches 0.
    pub cutoff_angle: f32,
    /// Half-angle (radians) of the full-intensity cone (≤ `cutoff_angle`).
    pub beam_width: f32,
    cos_cutoff: f32,
    cos_beam: f32,
}

impl SpotLight {
    /// Angles in degrees (half-angles measured from the axis). `beam_width_deg` is clamped to
    /// `[0, cutoff_angle_deg]`, `cutoff_angle_deg` to `[0, 180]`.
    pub fn new(
        position: Vec3,
        direction: Vec3,
        intensity: Spectrum,
        cutoff_angle_deg: f32,
        beam_width_deg: f32,
    ) -> Self {
        let dir = direction.try_normalize().unwrap_or(Vec3::Z);
        let cutoff = cutoff_angle_deg.clamp(0.0, 180.0).to_radians();
        let beam = beam_width_deg
            .clamp(0.0, cutoff_angle_deg.clamp(0.0, 180.0))
            .to_radians();
        Self {
            position,
            frame: Frame::from_normal(dir),
            intensity,
            cutoff_angle: cutoff,
            beam_width: beam,
            cos_cutoff: cutoff.cos(),
            cos_beam: beam.cos(),
        }
    }

    /// Falloff factor in [0, 1] for a unit emission direction `w` (world space).
    pub fn falloff(&self, w: Vec3) -> f32 {
        let c = self.frame.n.dot(w);
        if c <= self.cos_cutoff {
            0.0
        } else if c >= self.cos_beam {
            1.0
        } else {
            let width = self.cutoff_angle - self.beam_width;
            if width <= 0.0 {
                1.0
            } else {
                ((self.cutoff_angle - c.clamp(-1.0, 1.0).acos()) / width).clamp(0.0, 1.0)
            }
        }
    }

    /// Radiant intensity (W/sr) emitted in unit direction `w`.
    pub fn intensity_toward(&self, w: Vec3) -> Spectrum {
        self.intensity * self.falloff(w)
    }

    /// ∫ falloff dω (sr), analytically: with b = beam width and c = cutoff,
    /// 2π [(1 − cos b) + ∫_b^c (c − θ)/(c − b) sin θ dθ] = 2π [1 − (sin c − sin b)/(c − b)].
    pub fn falloff_solid_angle(&self) -> f32 {
        let (b, c) = (self.beam_width as f64, self.cutoff_angle as f64);
        let v = if c - b < 1e-6 {
            1.0 - b.cos()
        } else {
            1.0 - (c.sin() - b.sin()) / (c - b)
        };
        (2.0 * std::f64::consts::PI * v) as f32
    }
}

impl LightSource for SpotLight {
    /// `weight` = I(θ) / d².
    fn sample_li(&self, p: Vec3, _u: Vec2) -> Option<LightSample> {
        let (wi, dist, d2) = super::toward(p, self.position)?;
        let i = self.intensity_toward(-wi);
        if i.is_black() {
            return None;
        }
        Some(LightSample::delta(wi, dist, self.position, i / d2))
    }
    /// Direction uniform in the cutoff cone: `pdf_dir` = 1/(2π(1 − cos cutoff)),
    /// `weight` = I(θ)/pdf_dir.
    fn sample_emission(&self, _u_pos: Vec2, u_dir: Vec2) -> EmissionSample {
        let local = warp::square_to_uniform_cone(u_dir, self.cos_cutoff);
        let d = self.frame.to_world(local).normalize();
        let pdf_dir = if self.cos_cutoff < 1.0 {
            warp::uniform_cone_pdf(self.cos_cutoff)
        } else {
            1.0
        };
        let weight = if self.cos_cutoff < 1.0 {
            self.intensity_toward(d) / pdf_dir
        } else {
            Spectrum::ZERO
        };
        EmissionSample {
            ray: Ray::new(self.position, d),
            normal: None,
            weight,
            pdf_pos: 1.0,
            pdf_dir,
            delta_pos: true,
            delta_dir: false,
        }
    }
    /// I · ∫ falloff dω (W), see [`SpotLight::falloff_solid_angle`].
    fn power(&self) -> Spectrum {
        self.intensity * self.falloff_solid_angle()
    }
    fn is_delta(&self) -> bool {
        true
    }
    /// (0, 2π (1 − cos cutoff)): the sampled cone.
    fn emission_extent(&self) -> (f32, f32) {
        (0.0, 2.0 * std::f32::consts::PI * (1.0 - self.cos_cutoff))
    }
}
