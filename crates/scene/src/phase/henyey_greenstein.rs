//! The Henyey–Greenstein phase function (Henyey and Greenstein 1941):
//!
//! ```text
//! p(θ) = (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2}),   cos θ = −wo·wi
//! ```
//!
//! with mean cosine `g` ∈ (−1, 1): g > 0 scatters forward, g < 0 backward, g = 0 is isotropic.
//! Sampled exactly by inverting its CDF in cos θ (pbrt-v4 §11.3.1 derives the same inverse).

use super::{Phase, PhaseSample};
use caustica_core::sampling::warp::{square_to_uniform_sphere, uniform_sphere_pdf};
use caustica_core::{Frame, INV_4PI, PI, Vec2, Vec3};

/// Below this |g| the lobe is sampled as isotropic (the CDF inverse divides by g).
const NEARLY_ISOTROPIC: f32 = 1e-3;

/// Henyey–Greenstein lobe with mean cosine `g`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HenyeyGreenstein {
    pub g: f32,
}

impl HenyeyGreenstein {
    /// `g` must lie strictly inside (−1, 1): at ±1 the lobe is a delta.
    pub fn new(g: f32) -> Result<Self, String> {
        if g.is_finite() && g > -1.0 && g < 1.0 {
            Ok(Self { g })
        } else {
            Err(format!("Henyey–Greenstein g must lie in (-1, 1), got {g}"))
        }
    }

    /// p as a function of cos θ = −wo·wi (sr⁻¹).
    #[inline]
    pub fn eval_cos(&self, cos_theta: f32) -> f32 {
        let g = self.g;
        let denom = (1.0 + g * g - 2.0 * g * cos_theta).max(1e-12);
        INV_4PI * (1.0 - g * g) / (denom * denom.sqrt())
    }
}

impl Phase for HenyeyGreenstein {
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.eval_cos(-wo.dot(wi))
    }

    fn sample(&self, wo: Vec3, u: Vec2) -> Option<PhaseSample> {
        let g = self.g;
        if g.abs() < NEARLY_ISOTROPIC {
            let wi = square_to_uniform_sphere(u);
            return Some(PhaseSample {
                wi,
                pdf: uniform_sphere_pdf(),
                weight: self.eval(wo, wi) / uniform_sphere_pdf(),
            });
        }
        // Inverse CDF of cos θ (θ measured from the propagation direction).
        let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);
        let cos_theta = ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0);
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        // The outgoing propagation direction makes angle θ with the incoming one; in the
        // caller's convention the light arrived along −wi and leaves along wo, so −wi lies at
        // angle θ from wo.
        let local = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
        let wi = -Frame::from_normal(wo).to_world(local).normalize();
        let pdf = self.eval_cos(cos_theta);
        Some(PhaseSample {
            wi,
            pdf,
            weight: 1.0,
        })
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if self.g.abs() < NEARLY_ISOTROPIC {
            return uniform_sphere_pdf();
        }
        self.eval(wo, wi)
    }
}
