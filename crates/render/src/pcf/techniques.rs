//! The cone-direction samplers of seed 001 sec. 4.2 and their multi-sample MIS (sec. 4.3).
//!
//! At a non-delta light vertex each enabled technique draws one direction ω_t (multi-sample
//! MIS with n_t = 1, spec notes Q6) and the cone's value is weighted by the power heuristic
//! (eq. 4.4, β = 2) over the enabled techniques' densities at ω_t:
//!
//! ```text
//! w_t(ω) = p_t(ω)^β / Σ_u p_u(ω)^β,      cone value  β_path · w_t(ω_t) f(ω_i → ω_t) / p_t(ω_t)
//! ```
//!
//! so eq. 4.3's Σ_t w_t = 1 holds wherever any density is positive. The densities are in
//! solid angle (sr⁻¹) over the whole sphere of directions.
//!
//! * [`CameraLobe`]: camera next-event, a normalised Blinn–Phong lobe (eq. 4.1) around the
//!   direction V to the camera, `(n + 1)/(2π) cosⁿ θ_V` on V's hemisphere. Sec. 4.2.2
//!   mirrors samples that fall below the surface; we read "mirrored" as a reflection in the
//!   tangent plane (ω·n < 0 is sent to ω − 2(ω·n)n, which keeps it near V's reflection instead
//!   of throwing it away as ω → −ω would; spec notes Q8) and give the folded density
//!   p(ω) + p(reflect(ω)), so the sampler is unbiased. Only for BSDFs without transmission.
//! * [`ImportonMixture`]: a mixture of uniform caps of half-angle θ_imp around the nearby
//!   importons' directions, weighted by their importance (spec notes sec. 2.9, Q9).
//! * Uniform directions over the sphere (pdf 1/4π): "no guiding" (Q22).
//! * The BSDF's own sampler (in `tracer.rs`, through `Bsdf::sample` and `Bsdf::pdf`).

use caustica_core::sampling::warp;
use caustica_core::{Frame, Vec2, Vec3};
use std::f32::consts::PI;

/// The power heuristic weight (β = 2) of technique `t` among the densities `pdfs` at one
/// direction: p_t² / Σ p_u² (eq. 4.4). 0 where every density is 0.
pub fn power_weight(pdfs: &[f32], t: usize) -> f32 {
    let sum: f32 = pdfs.iter().map(|p| p * p).sum();
    if sum > 0.0 && sum.is_finite() {
        pdfs[t] * pdfs[t] / sum
    } else {
        0.0
    }
}

/// Reflection of `w` in the plane with unit normal `n`.
#[inline]
fn reflect_in_plane(w: Vec3, n: Vec3) -> Vec3 {
    w - 2.0 * w.dot(n) * n
}

/// Camera next-event: a Blinn–Phong lobe around the unit direction `axis` to the camera.
#[derive(Clone, Copy, Debug)]
pub struct CameraLobe {
    pub axis: Vec3,
    /// The exponent n ≥ 0.
    pub exponent: f32,
    /// The unit normal of the side to keep: samples below it are reflected to it, and the
    /// density is the folded one (None: no folding, e.g. at glass).
    pub fold: Option<Vec3>,
}

impl CameraLobe {
    /// The exponent that puts half the lobe's mass inside a cap of half-angle `t`:
    /// cos^{n+1} t = 1/2 (spec notes Q8), 0 for t ≥ 60°.
    pub fn exponent_for_cap(t: f32) -> f32 {
        let c = t.cos();
        if c <= 0.5 {
            return 0.0;
        }
        let n = 0.5f32.ln() / c.ln() - 1.0;
        n.clamp(0.0, 1e6)
    }

    fn lobe(&self, w: Vec3) -> f32 {
        let c = w.dot(self.axis);
        if c <= 0.0 {
            return 0.0;
        }
        (self.exponent + 1.0) * 0.5 / PI * c.powf(self.exponent)
    }

    /// A direction: cos θ_V = ξ₁^{1/(n+1)}, φ = 2πξ₂ (eq. 4.2, with φ from ξ₂: the seed
    /// prints ξ₁, a misprint), folded if asked.
    pub fn sample(&self, u: Vec2) -> Vec3 {
        let cos_t = u.x.powf(1.0 / (self.exponent + 1.0));
        let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let local = Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
        let w = Frame::from_normal(self.axis).to_world(local).normalize();
        match self.fold {
            Some(n) if w.dot(n) < 0.0 => reflect_in_plane(w, n),
            _ => w,
        }
    }

    /// The density (sr⁻¹) of [`CameraLobe::sample`] at `w`.
    pub fn pdf(&self, w: Vec3) -> f32 {
        match self.fold {
            None => self.lobe(w),
            Some(n) => {
                if w.dot(n) < 0.0 {
                    0.0
                } else {
                    self.lobe(w) + self.lobe(reflect_in_plane(w, n))
                }
            }
        }
    }
}

/// A mixture of uniform caps around importon directions, weighted by importance.
#[derive(Clone, Debug, Default)]
pub struct ImportonMixture {
    /// (unit direction, importance > 0).
    pub lobes: Vec<(Vec3, f32)>,
    pub cos_cap: f32,
    total: f32,
}

impl ImportonMixture {
    /// The mixture over `lobes` with caps of half-angle whose cosine is `cos_cap`.
    pub fn new(lobes: Vec<(Vec3, f32)>, cos_cap: f32) -> Self {
        let total = lobes.iter().map(|l| l.1).sum();
        Self {
            lobes,
            cos_cap,
            total,
        }
    }

    /// Replaces the lobes with `lobes` and the caps with `cos_cap`, reusing the allocation (one
    /// mixture per light vertex in the cone tracer's hot loop).
    pub fn refill(&mut self, lobes: impl Iterator<Item = (Vec3, f32)>, cos_cap: f32) {
        self.lobes.clear();
        self.lobes.extend(lobes);
        self.cos_cap = cos_cap;
        self.total = self.lobes.iter().map(|l| l.1).sum();
    }

    /// True if the mixture can draw a direction.
    pub fn is_empty(&self) -> bool {
        self.total.is_nan() || self.total <= 0.0
    }

    /// Picks a lobe with `uc` in proportion to importance, then a direction uniform in its cap.
    pub fn sample(&self, uc: f32, u: Vec2) -> Option<Vec3> {
        if self.is_empty() {
            return None;
        }
        let target = uc * self.total;
        let mut acc = 0.0;
        let mut pick = self.lobes.len() - 1;
        for (i, l) in self.lobes.iter().enumerate() {
            acc += l.1;
            if target < acc {
                pick = i;
                break;
            }
        }
        let local = warp::square_to_uniform_cone(u, self.cos_cap);
        Some(
            Frame::from_normal(self.lobes[pick].0)
                .to_world(local)
                .normalize(),
        )
    }

    /// The mixture's density (sr⁻¹) at `w`.
    pub fn pdf(&self, w: Vec3) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let cap = warp::uniform_cone_pdf(self.cos_cap);
        let inside: f32 = self
            .lobes
            .iter()
            .filter(|l| w.dot(l.0) > self.cos_cap)
            .map(|l| l.1)
            .sum();
        inside / self.total * cap
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::chi2;
    use caustica_core::sampling::rng::Pcg32;

    /// χ² of a sphere sampler against its density (Mitsuba-style, the shared harness).
    fn check_sphere(
        name: &str,
        seed: u64,
        integration_res: usize,
        sample: impl Fn(Vec2, f32) -> Option<Vec3>,
        pdf: impl Fn(Vec3) -> f32,
    ) {
        let mut rng = Pcg32::new(0x5eed, seed);
        let dom = chi2::SphericalDomain {
            cos_bins: 100,
            phi_bins: 60,
            integration_res,
        };
        let r = chi2::ChiSquareTest::new(dom, 300_000).run(
            || {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                sample(u, rng.next_f32())
            },
            pdf,
        );
        assert!(r.passed_at(1e-3), "{name}: {r}");
    }

    #[test]
    fn camera_lobe_chi2_with_and_without_folding() {
        // A tilted axis with folding in the z = 0 plane (a bin edge), and at n = 0 (a density
        // discontinuous at the lobe's horizon) axes the binning resolves.
        let tilted = Vec3::new(0.3, 0.5, 0.8).normalize();
        let cases = [
            (0.0f32, Vec3::Z, None),
            (0.0, Vec3::new(0.0, 0.6, 0.8), Some(Vec3::Z)),
            (1.0, tilted, None),
            (3.0, tilted, Some(Vec3::Z)),
            (30.0, tilted, None),
            (30.0, Vec3::new(0.0, 0.6, -0.8), Some(Vec3::Z)),
        ];
        for (n, axis, fold) in cases {
            let lobe = CameraLobe {
                axis,
                exponent: n,
                fold,
            };
            check_sphere(
                &format!("camera lobe n={n} axis={axis} fold={fold:?}"),
                n as u64,
                if n == 0.0 { 32 } else { 12 },
                |u, _| Some(lobe.sample(u)),
                |w| lobe.pdf(w),
            );
        }
    }

    #[test]
    fn importon_mixture_chi2() {
        let mix = ImportonMixture::new(
            vec![
                (Vec3::Z, 1.0),
                (Vec3::new(0.0, 0.6, 0.8), 3.0),
                (Vec3::new(-1.0, 0.0, 0.0), 0.5),
            ],
            (25f32).to_radians().cos(),
        );
        check_sphere(
            "importon mixture",
            1,
            32,
            |u, uc| mix.sample(uc, u),
            |w| mix.pdf(w),
        );
    }

    #[test]
    fn power_weights_sum_to_one_where_any_pdf_is_positive() {
        // T-4.
        let mut rng = Pcg32::new(3, 4);
        for _ in 0..10_000 {
            let n = 2 + (rng.next_u32() % 2) as usize;
            let pdfs: Vec<f32> = (0..n)
                .map(|_| {
                    if rng.next_f32() < 0.3 {
                        0.0
                    } else {
                        rng.next_f32() * 10.0
                    }
                })
                .collect();
            let sum: f32 = (0..n).map(|t| power_weight(&pdfs, t)).sum();
            if pdfs.iter().any(|&p| p > 0.0) {
                assert!((sum - 1.0).abs() < 1e-5, "{pdfs:?}: {sum}");
            } else {
                assert_eq!(sum, 0.0);
            }
            for t in 0..n {
                if pdfs[t] == 0.0 {
                    assert_eq!(power_weight(&pdfs, t), 0.0);
                }
            }
        }
    }

    #[test]
    fn exponent_puts_half_the_mass_in_the_cap() {
        for deg in [2.0f32, 10.0, 18.0, 45.0] {
            let t = deg.to_radians();
            let n = CameraLobe::exponent_for_cap(t);
            // Mass inside the cap: 1 − cos^{n+1} t.
            let mass = 1.0 - t.cos().powf(n + 1.0);
            assert!((mass - 0.5).abs() < 1e-3, "{deg}: {mass}");
        }
        assert_eq!(CameraLobe::exponent_for_cap(70f32.to_radians()), 0.0);
    }
}
