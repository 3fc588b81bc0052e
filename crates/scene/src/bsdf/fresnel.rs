//! Fresnel equations and the reflection/refraction helpers shared by the specular and
//! microfacet models.
//!
//! * [`fresnel_dielectric`]: exact unpolarised Fresnel reflectance of a dielectric interface,
//!   the average of the s- and p-polarised terms (Born & Wolf, *Principles of Optics* §1.5.2;
//!   written as in pbrt-v4 `FrDielectric`, Pharr, Jakob & Humphreys 2023 §9.3). Handles
//!   η < 1, η > 1 and total internal reflection. No Schlick approximation anywhere.
//! * [`fresnel_conductor`]: exact unpolarised Fresnel reflectance of an interface with a complex
//!   relative IOR η + iκ (pbrt-v4 `FrComplex`, §9.3.6), evaluated per RGB channel.
//! * [`reflect`], [`refract`]: mirror and Snell directions (pbrt-v4 §9.3.1–9.3.2).

use caustica_core::{Spectrum, Vec3};

/// Unpolarised Fresnel reflectance of a dielectric interface.
///
/// `cos_theta_i` is the cosine between the incident direction and the normal on the side the
/// relative IOR `eta` = η_t/η_i refers to (η of the side *opposite* to the normal divided by η of
/// the normal's side). A negative cosine means the direction is on the other side; η is then
/// inverted. Returns 1 for total internal reflection.
pub fn fresnel_dielectric(cos_theta_i: f32, eta: f32) -> f32 {
    let mut cos_i = cos_theta_i.clamp(-1.0, 1.0);
    let mut eta = eta;
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
    }
    // Snell: sin θt = sin θi / η.
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (r_parl * r_parl + r_perp * r_perp)
}

/// Minimal complex number for the conductor Fresnel term.
#[derive(Clone, Copy, Debug)]
struct Complex {
    re: f32,
    im: f32,
}

impl Complex {
    fn new(re: f32, im: f32) -> Self {
        Self { re, im }
    }
    fn add(self, o: Self) -> Self {
        Self::new(self.re + o.re, self.im + o.im)
    }
    fn sub(self, o: Self) -> Self {
        Self::new(self.re - o.re, self.im - o.im)
    }
    fn mul(self, o: Self) -> Self {
        Self::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
    fn div(self, o: Self) -> Self {
        let d = o.re * o.re + o.im * o.im;
        Self::new(
            (self.re * o.re + self.im * o.im) / d,
            (self.im * o.re - self.re * o.im) / d,
        )
    }
    fn norm(self) -> f32 {
        self.re * self.re + self.im * self.im
    }
    /// Principal square root (non-negative real part).
    fn sqrt(self) -> Self {
        let n = self.norm().sqrt();
        if n == 0.0 {
            return Self::new(0.0, 0.0);
        }
        let t1 = (0.5 * (n + self.re.abs())).sqrt();
        let t2 = 0.5 * self.im / t1;
        if self.re >= 0.0 {
            Self::new(t1, t2)
        } else {
            Self::new(t2.abs(), t1.copysign(self.im))
        }
    }
}

/// Fresnel reflectance of one channel with complex relative IOR `eta + i k`.
///
/// `r_s = (cos θi − η cos θt)/(cos θi + η cos θt)`, `r_p = (η cos θi − cos θt)/(η cos θi + cos θt)`
/// with complex η and `cos θt = sqrt(1 − sin²θi / η²)`; result `(|r_s|² + |r_p|²)/2`.
pub fn fresnel_complex(cos_theta_i: f32, eta: f32, k: f32) -> f32 {
    let cos_i = cos_theta_i.abs().clamp(0.0, 1.0);
    let eta_c = Complex::new(eta, k);
    let sin2_i = Complex::new((1.0 - cos_i * cos_i).max(0.0), 0.0);
    let sin2_t = sin2_i.div(eta_c.mul(eta_c));
    let cos_t = Complex::new(1.0, 0.0).sub(sin2_t).sqrt();
    let ci = Complex::new(cos_i, 0.0);
    let r_parl = eta_c.mul(ci).sub(cos_t).div(eta_c.mul(ci).add(cos_t));
    let r_perp = ci.sub(eta_c.mul(cos_t)).div(ci.add(eta_c.mul(cos_t)));
    let f = 0.5 * (r_parl.norm() + r_perp.norm());
    if f.is_finite() {
        f.clamp(0.0, 1.0)
    } else {
        1.0
    }
}

/// Conductor Fresnel reflectance per channel (sign of `cos_theta_i` ignored: conductors are
/// opaque and two-sided).
pub fn fresnel_conductor(cos_theta_i: f32, eta: Spectrum, k: Spectrum) -> Spectrum {
    Spectrum::new(
        fresnel_complex(cos_theta_i, eta[0], k[0]),
        fresnel_complex(cos_theta_i, eta[1], k[1]),
        fresnel_complex(cos_theta_i, eta[2], k[2]),
    )
}

/// Mirror reflection of `wo` about the unit normal `n` (both pointing away from the surface).
#[inline]
pub fn reflect(wo: Vec3, n: Vec3) -> Vec3 {
    -wo + 2.0 * wo.dot(n) * n
}

/// Refracts `wi` (pointing away from the surface) through the interface with unit normal `n`
/// and relative IOR `eta` = η(side opposite `n`)/η(side of `n`). If `wi` lies on the other side
/// of `n`, the interface is flipped (η → 1/η). Returns the transmitted direction (pointing away
/// from the surface, on the other side) and the relative IOR η_t/η_i actually crossed, or `None`
/// for total internal reflection.
pub fn refract(wi: Vec3, n: Vec3, eta: f32) -> Option<(Vec3, f32)> {
    let mut cos_i = n.dot(wi);
    let mut eta = eta;
    let mut n = n;
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = -n;
    }
    let sin2_i = (1.0 - cos_i * cos_i).max(0.0);
    let sin2_t = sin2_i / (eta * eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
    let wt = -wi / eta + (cos_i / eta - cos_t) * n;
    Some((wt, eta))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_matches_closed_form() {
        for eta in [1.5f32, 1.0 / 1.5, 1.33, 2.4, 0.5] {
            let want = ((eta - 1.0) / (eta + 1.0)).powi(2);
            let f = fresnel_dielectric(1.0, eta);
            assert!((f - want).abs() < 1e-6, "eta {eta}: {f} vs {want}");
            // Same from the other side with the inverted ratio.
            let g = fresnel_dielectric(-1.0, 1.0 / eta);
            assert!((g - want).abs() < 1e-6, "eta {eta}: {g} vs {want}");
        }
    }

    #[test]
    fn total_internal_reflection() {
        // Leaving glass (η = 1/1.5 seen from inside): critical angle asin(1/1.5) = 41.81°.
        let crit = (1.0f32 / 1.5).asin();
        let beyond = (crit + 0.01).cos();
        let before = (crit - 0.01).cos();
        assert_eq!(fresnel_dielectric(beyond, 1.0 / 1.5), 1.0);
        assert!(fresnel_dielectric(before, 1.0 / 1.5) < 1.0);
        // Same through the sign convention: inside is the negative side of the normal.
        assert_eq!(fresnel_dielectric(-beyond, 1.5), 1.0);
        assert!(refract(Vec3::new((crit + 0.01).sin(), 0.0, -beyond), Vec3::Z, 1.5).is_none());
        // Brewster angle: p-polarised reflectance vanishes, so F = r_s²/2 there.
        let tb = 1.5f32.atan();
        let (ci, ct) = (tb.cos(), (tb.sin() / 1.5).asin().cos());
        let rs = (ci - 1.5 * ct) / (ci + 1.5 * ct);
        let f = fresnel_dielectric(ci, 1.5);
        assert!((f - 0.5 * rs * rs).abs() < 1e-6, "{f}");
    }

    #[test]
    fn dielectric_at_45_degrees_matches_hand_value() {
        // θi = 45°, η = 1.5: F = 0.0502399 (computed with Python's cmath from the s/p amplitude
        // formulas, independently of this code).
        let f = fresnel_dielectric(std::f32::consts::FRAC_1_SQRT_2, 1.5);
        assert!((f - 0.050_239_9).abs() < 2e-6, "{f}");
    }

    #[test]
    fn conductor_matches_independent_values() {
        // Reference values computed with Python's cmath using the s/p amplitude formulas
        // (Born & Wolf), not with this code: gold red channel η = 0.1431189557, κ = 3.9831604247.
        let r0 = fresnel_complex(1.0, 0.143_118_96, 3.983_160_4);
        // Normal incidence: ((η−1)² + κ²)/((η+1)² + κ²).
        let (e, k) = (0.143_118_96f64, 3.983_160_4f64);
        let want0 = ((e - 1.0).powi(2) + k * k) / ((e + 1.0).powi(2) + k * k);
        assert!((r0 as f64 - want0).abs() < 1e-5, "{r0} vs {want0}");
        let r60 = fresnel_complex(0.5, 0.143_118_96, 3.983_160_4);
        assert!((r60 - CONDUCTOR_60).abs() < 1e-4, "{r60} vs {CONDUCTOR_60}");
        let r85 = fresnel_complex(85f32.to_radians().cos(), 0.143_118_96, 3.983_160_4);
        assert!((r85 - CONDUCTOR_85).abs() < 1e-4, "{r85} vs {CONDUCTOR_85}");
        // Grazing incidence reflects everything; k = 0 reduces to the dielectric formula.
        assert!((fresnel_complex(0.0, 0.2, 3.0) - 1.0).abs() < 1e-5);
        for c in [0.1f32, 0.5, 0.9] {
            let a = fresnel_complex(c, 1.5, 0.0);
            let b = fresnel_dielectric(c, 1.5);
            assert!((a - b).abs() < 1e-5, "{a} vs {b}");
        }
    }

    /// Gold (red) at θi = 60° and 85°, from Python cmath (pbrt-v4 form) and cross-checked with
    /// Mitsuba 3's real-valued `fresnel_conductor` formula (both give these digits).
    const CONDUCTOR_60: f32 = 0.962_191_8;
    const CONDUCTOR_85: f32 = 0.976_074_2;

    #[test]
    fn refraction_obeys_snell() {
        let eta = 1.5f32;
        for deg in [0.0f32, 10.0, 30.0, 60.0, 89.0] {
            let t = deg.to_radians();
            let wi = Vec3::new(t.sin(), 0.0, t.cos());
            let (wt, etap) = refract(wi, Vec3::Z, eta).unwrap();
            assert_eq!(etap, eta);
            assert!((wt.length() - 1.0).abs() < 1e-5);
            assert!(wt.z < 0.0 || deg == 90.0);
            let sin_t = (wt.x * wt.x + wt.y * wt.y).sqrt();
            assert!((t.sin() - eta * sin_t).abs() < 1e-5, "{deg}");
            // Opposite tangential direction (the ray continues through the surface).
            assert!(wt.x <= 0.0);
            // Reversibility.
            let (back, e2) = refract(wt, Vec3::Z, eta).unwrap();
            assert!((back - wi).length() < 1e-5);
            assert!((e2 - 1.0 / eta).abs() < 1e-6);
        }
        let wo = Vec3::new(0.3, -0.4, 0.866_025_4).normalize();
        let r = reflect(wo, Vec3::Z);
        assert_eq!(r, Vec3::new(-wo.x, -wo.y, wo.z));
    }
}
