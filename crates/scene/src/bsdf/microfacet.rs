//! Trowbridge–Reitz (GGX) microfacet distribution.
//!
//! Formulas (local shading frame, +z = macro-normal):
//! * D(ωm) = 1 / (π αx αy cos⁴θm (1 + tan²θm (cos²φm/αx² + sin²φm/αy²))²)
//!   (Trowbridge & Reitz 1975; Walter et al. 2007 eq. 33; anisotropic form as in pbrt-v4 §9.6.1).
//! * Smith Λ(ω) = (√(1 + α(φ)² tan²θ) − 1)/2 with α(φ)² = cos²φ αx² + sin²φ αy²
//!   (Heitz 2014, "Understanding the Masking-Shadowing Function", eq. 72/86).
//! * G1(ω) = 1/(1 + Λ(ω)); height-correlated G2(ωo, ωi) = 1/(1 + Λ(ωo) + Λ(ωi)) (Heitz 2014 eq. 99).
//! * Visible normals D_ωo(ωm) = G1(ωo) max(0, ωo·ωm) D(ωm) / cos θo (Heitz 2014 eq. 38), sampled
//!   exactly with Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4).
//!
//! D is normalised so that ∫ D(ωm) cos θm dωm = 1 over the upper hemisphere.

use caustica_core::{PI, Vec2, Vec3};

/// Anisotropic GGX distribution with roughness `alpha_x`, `alpha_y` along the shading tangents.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrowbridgeReitz {
    pub alpha_x: f32,
    pub alpha_y: f32,
}

#[inline]
fn cos2_theta(w: Vec3) -> f32 {
    w.z * w.z
}
#[inline]
fn sin2_theta(w: Vec3) -> f32 {
    (1.0 - cos2_theta(w)).max(0.0)
}
#[inline]
fn tan2_theta(w: Vec3) -> f32 {
    sin2_theta(w) / cos2_theta(w)
}
/// (cos²φ, sin²φ) of a direction (φ = 0 at the pole).
#[inline]
fn cos2_sin2_phi(w: Vec3) -> (f32, f32) {
    let s2 = w.x * w.x + w.y * w.y;
    if s2 <= 0.0 {
        (1.0, 0.0)
    } else {
        (w.x * w.x / s2, w.y * w.y / s2)
    }
}

impl TrowbridgeReitz {
    /// Isotropic distribution with roughness `alpha`.
    pub fn isotropic(alpha: f32) -> Self {
        Self {
            alpha_x: alpha,
            alpha_y: alpha,
        }
    }

    /// Microfacet normal density D(ωm) (sr⁻¹ with respect to projected solid angle).
    pub fn d(&self, wm: Vec3) -> f32 {
        let t2 = tan2_theta(wm);
        if !t2.is_finite() {
            return 0.0;
        }
        let c4 = cos2_theta(wm) * cos2_theta(wm);
        if c4 < 1e-16 {
            return 0.0;
        }
        let (c2p, s2p) = cos2_sin2_phi(wm);
        let e = t2 * (c2p / (self.alpha_x * self.alpha_x) + s2p / (self.alpha_y * self.alpha_y));
        1.0 / (PI * self.alpha_x * self.alpha_y * c4 * (1.0 + e) * (1.0 + e))
    }

    /// Smith Λ(ω) (even in ω).
    pub fn lambda(&self, w: Vec3) -> f32 {
        let t2 = tan2_theta(w);
        if !t2.is_finite() {
            return 0.0;
        }
        let (c2p, s2p) = cos2_sin2_phi(w);
        let a2 = c2p * self.alpha_x * self.alpha_x + s2p * self.alpha_y * self.alpha_y;
        ((1.0 + a2 * t2).sqrt() - 1.0) * 0.5
    }

    /// Smith masking G1(ω).
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking–shadowing G2(ωo, ωi).
    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(wo) + self.lambda(wi))
    }

    /// Distribution of visible normals D_w(ωm) = G1(w) |w·ωm| D(ωm) / |cos θw| (sr⁻¹); this is
    /// the density of [`TrowbridgeReitz::sample_wm`] (for ωm on the side facing `w`).
    pub fn d_visible(&self, w: Vec3, wm: Vec3) -> f32 {
        let c = w.z.abs();
        if c == 0.0 {
            return 0.0;
        }
        self.g1(w) / c * self.d(wm) * w.dot(wm).abs()
    }

    /// Samples a visible microfacet normal (upper hemisphere) for direction `w` (Heitz 2018,
    /// listing 1). A direction below the surface is treated as its mirror image through the
    /// origin, so the returned normal always has `z > 0`.
    pub fn sample_wm(&self, w: Vec3, u: Vec2) -> Vec3 {
        // Stretch to the hemisphere configuration (α = 1).
        let mut wh = Vec3::new(self.alpha_x * w.x, self.alpha_y * w.y, w.z).normalize();
        if wh.z < 0.0 {
            wh = -wh;
        }
        // Orthonormal basis around wh.
        let t1 = if wh.z < 0.99999 {
            Vec3::Z.cross(wh).normalize()
        } else {
            Vec3::X
        };
        let t2 = wh.cross(t1);
        // Uniform point on the unit disk (polar mapping), warped to the visible half-disk.
        let r = u.x.sqrt();
        let phi = 2.0 * PI * u.y;
        let px = r * phi.cos();
        let mut py = r * phi.sin();
        let h = (1.0 - px * px).max(0.0).sqrt();
        let s = 0.5 * (1.0 + wh.z);
        py = (1.0 - s) * h + s * py;
        let pz = (1.0 - px * px - py * py).max(0.0).sqrt();
        let nh = px * t1 + py * t2 + pz * wh;
        // Unstretch.
        Vec3::new(self.alpha_x * nh.x, self.alpha_y * nh.y, nh.z.max(1e-6)).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::testutil::{LobeDomain, sidak};
    use caustica_core::chi2::SphericalDomain;
    use caustica_core::sampling::Pcg32;

    #[test]
    fn d_is_normalised_in_projected_solid_angle() {
        let dom = SphericalDomain {
            cos_bins: 400,
            phi_bins: 64,
            integration_res: 4,
        };
        for (ax, ay) in [(0.2f32, 0.2f32), (0.6, 0.6), (0.1, 0.4)] {
            let m = TrowbridgeReitz {
                alpha_x: ax,
                alpha_y: ay,
            };
            let i = dom.integrate(&|w| if w.z > 0.0 { m.d(w) * w.z } else { 0.0 });
            assert!((i - 1.0).abs() < 1e-2, "α=({ax},{ay}): {i}");
        }
    }

    #[test]
    fn isotropic_lambda_matches_closed_form_g1() {
        // Closed form G1 = 2 / (1 + sqrt(1 + α² tan²θ)) (Walter et al. 2007 eq. 34).
        let m = TrowbridgeReitz::isotropic(0.35);
        for deg in [0.0f32, 20.0, 45.0, 70.0, 88.0] {
            let t = deg.to_radians();
            let w = Vec3::new(t.sin(), 0.0, t.cos());
            let want = 2.0 / (1.0 + (1.0 + 0.35f32 * 0.35 * t.tan() * t.tan()).sqrt());
            assert!((m.g1(w) - want).abs() < 1e-5, "{deg}");
        }
    }

    #[test]
    fn visible_normal_projection_identity() {
        // ∫ D_w(ωm) dωm = 1, i.e. G1(w) cos θ = ∫ max(0, w·ωm) D(ωm) dωm (Heitz 2014 eq. 18).
        let dom = SphericalDomain {
            cos_bins: 400,
            phi_bins: 128,
            integration_res: 4,
        };
        let m = TrowbridgeReitz::isotropic(0.3);
        for deg in [0.0f32, 45.0, 80.0] {
            let t = deg.to_radians();
            let w = Vec3::new(t.sin(), 0.0, t.cos());
            let i = dom.integrate(&|wm| {
                if wm.z > 0.0 && wm.dot(w) > 0.0 {
                    m.d_visible(w, wm)
                } else {
                    0.0
                }
            });
            assert!((i - 1.0).abs() < 1e-2, "{deg}: {i}");
        }
    }

    #[test]
    fn chi2_visible_normals() {
        let cases = [
            (0.05f32, 0.05f32, 0.0f32),
            (0.05, 0.05, 60.0),
            (0.2, 0.2, 0.0),
            (0.2, 0.2, 60.0),
            (0.6, 0.6, 30.0),
            (0.6, 0.6, 85.0),
            (0.1, 0.5, 45.0),
        ];
        let alpha = sidak(cases.len());
        for (i, &(ax, ay, deg)) in cases.iter().enumerate() {
            let m = TrowbridgeReitz {
                alpha_x: ax,
                alpha_y: ay,
            };
            let t = deg.to_radians();
            let w = Vec3::new(t.sin() * 0.8, t.sin() * 0.6, t.cos());
            let mut rng = Pcg32::new(100 + i as u64, 0);
            // Bins centred on the normal, refined toward it (narrow lobes at small α).
            let r = LobeDomain::new(Vec3::Z, 3.0).run(
                200_000,
                || Some(m.sample_wm(w, Vec2::new(rng.next_f32(), rng.next_f32()))),
                |wm| {
                    if wm.z > 0.0 && wm.dot(w) > 0.0 {
                        m.d_visible(w, wm)
                    } else {
                        0.0
                    }
                },
            );
            assert!(r.passed_at(alpha), "α=({ax},{ay}) θ={deg}: {r}");
        }
    }
}
