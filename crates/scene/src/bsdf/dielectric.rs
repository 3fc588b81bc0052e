//! Smooth dielectric interface (pbrt-v4 §9.5 `DielectricBxDF`, smooth case; Veach 1997 §5.2).
//!
//! Oriented (crate docs): `wo.z > 0` is outside, and η = η_inside/η_outside. Reflection
//! (ωi = (−ωo.x, −ωo.y, ωo.z)) is chosen with probability F = Fr(cos θo, η) (exact Fresnel), and
//! refraction (Snell) otherwise, so the delta weight of either choice is 1. In radiance mode the
//! transmitted weight is divided by η′² where η′ = η(ωi side)/η(ωo side) is the relative IOR
//! crossed (radiance is compressed/expanded by the change of solid angle, Veach 1997 eq. 5.13);
//! importance is not scaled. Interior absorption is applied by the integrators.

use super::fresnel::{fresnel_dielectric, refract};
use super::{BsdfFlags, BsdfSample, BxDF, TransportMode};
use caustica_core::{Spectrum, Vec2, Vec3};

/// Smooth dielectric boundary with relative IOR `eta` = η_inside/η_outside.
#[derive(Clone, Copy, Debug)]
pub struct Dielectric {
    pub eta: f32,
}

impl Dielectric {
    pub fn new(eta: f32) -> Self {
        Self { eta }
    }
}

impl BxDF for Dielectric {
    fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::TRANSMISSION | BsdfFlags::DELTA
    }
    fn eval(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> Spectrum {
        Spectrum::ZERO
    }
    fn sample(&self, wo: Vec3, uc: f32, _u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let r = fresnel_dielectric(wo.z, self.eta);
        let reflection = BsdfSample {
            wi: Vec3::new(-wo.x, -wo.y, wo.z),
            weight: Spectrum::ONE,
            pdf: r,
            flags: BsdfFlags::REFLECTION | BsdfFlags::DELTA,
            eta: 1.0,
        };
        if uc < r {
            return Some(reflection);
        }
        let Some((wi, etap)) = refract(wo, Vec3::Z, self.eta) else {
            // Only reachable through rounding (F = 1 under total internal reflection).
            return Some(BsdfSample {
                pdf: 1.0,
                ..reflection
            });
        };
        let scale = match mode {
            TransportMode::Radiance => 1.0 / (etap * etap),
            TransportMode::Importance => 1.0,
        };
        Some(BsdfSample {
            wi,
            weight: Spectrum::splat(scale),
            pdf: 1.0 - r,
            flags: BsdfFlags::TRANSMISSION | BsdfFlags::DELTA,
            eta: etap,
        })
    }
    fn pdf(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> f32 {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::Pcg32;

    fn dir(deg: f32, up: bool) -> Vec3 {
        let t = deg.to_radians();
        Vec3::new(
            t.sin() * 0.6,
            t.sin() * 0.8,
            if up { t.cos() } else { -t.cos() },
        )
    }

    #[test]
    fn refraction_obeys_snell_from_both_sides() {
        for eta in [1.5f32, 1.0 / 1.5] {
            let d = Dielectric::new(eta);
            for (deg, up) in [
                (0.0f32, true),
                (30.0, true),
                (60.0, true),
                (60.0, false),
                (20.0, false),
            ] {
                let wo = dir(deg, up);
                // uc just below 1 forces transmission whenever F < 1.
                let s = d
                    .sample(wo, 0.999_999, Vec2::ZERO, TransportMode::Importance)
                    .unwrap();
                // η on each side: outside 1, inside eta.
                let (n_o, n_i) = if up { (1.0, eta) } else { (eta, 1.0) };
                if n_o * deg.to_radians().sin() > n_i {
                    assert!(
                        s.flags.contains(BsdfFlags::REFLECTION),
                        "TIR {eta} {deg} {up}"
                    );
                    continue;
                }
                assert!(
                    s.flags.contains(BsdfFlags::TRANSMISSION),
                    "{eta} {deg} {up}"
                );
                assert!(s.wi.z * wo.z < 0.0);
                assert!((s.eta - n_i / n_o).abs() < 1e-6);
                let sin_o = (wo.x * wo.x + wo.y * wo.y).sqrt();
                let sin_i = (s.wi.x * s.wi.x + s.wi.y * s.wi.y).sqrt();
                assert!(
                    (n_o * sin_o - n_i * sin_i).abs() < 1e-5,
                    "Snell {eta} {deg}"
                );
                // Same plane of incidence, opposite tangential direction.
                assert!(wo.truncate().perp_dot(s.wi.truncate()).abs() < 1e-6);
                assert!(wo.truncate().dot(s.wi.truncate()) <= 1e-7);
                assert!((s.weight[0] - 1.0).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn total_internal_reflection_always_reflects() {
        // Inside glass (wo.z < 0) beyond the 41.8° critical angle.
        let d = Dielectric::new(1.5);
        let wo = dir(50.0, false);
        for uc in [0.0f32, 0.5, 0.999_999] {
            let s = d
                .sample(wo, uc, Vec2::ZERO, TransportMode::Radiance)
                .unwrap();
            assert!(s.flags.contains(BsdfFlags::REFLECTION));
            assert_eq!(s.pdf, 1.0);
            assert_eq!(s.weight, Spectrum::ONE);
        }
    }

    #[test]
    fn white_furnace_and_radiance_scaling() {
        // Importance mode: every weight is 1, so the mean is exactly 1 (energy conserved).
        // Radiance mode: the mean weight is F + (1 − F)/η′², with F from the closed-form
        // normal-incidence value ((η−1)/(η+1))² = 0.04 for η = 1.5.
        let d = Dielectric::new(1.5);
        let n = 200_000;
        for (up, etap) in [(true, 1.5f32), (false, 1.0 / 1.5)] {
            let wo = if up { Vec3::Z } else { -Vec3::Z };
            let mut rng = Pcg32::new(7, 1);
            let (mut mi, mut mr, mut refl) = (0.0f64, 0.0f64, 0usize);
            for _ in 0..n {
                let uc = rng.next_f32();
                let si = d
                    .sample(wo, uc, Vec2::ZERO, TransportMode::Importance)
                    .unwrap();
                let sr = d
                    .sample(wo, uc, Vec2::ZERO, TransportMode::Radiance)
                    .unwrap();
                mi += si.weight[0] as f64 / n as f64;
                mr += sr.weight[0] as f64 / n as f64;
                if si.flags.contains(BsdfFlags::REFLECTION) {
                    refl += 1;
                }
            }
            assert!((mi - 1.0).abs() < 1e-6, "{mi}");
            let f = 0.04f64;
            // Binomial 5σ bound on the reflected fraction.
            let sigma = (f * (1.0 - f) / n as f64).sqrt();
            let frac = refl as f64 / n as f64;
            assert!((frac - f).abs() < 5.0 * sigma, "{frac}");
            let want = frac + (1.0 - frac) / (etap as f64 * etap as f64);
            assert!((mr - want).abs() < 1e-4, "{mr} vs {want}");
        }
    }
}
