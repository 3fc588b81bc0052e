//! Shared checks for the BSDF unit tests (compiled only for tests).
//!
//! [`LobeDomain`] is a χ² binning of the whole sphere around an axis `center`: rings between
//! explicit θ edges (extra edges can be put on known discontinuities), by default `nt` equal
//! bins in t ∈ [0, 1] mapped to the polar angle θ by θ = (π/2)(2t)^power for t ≤ ½ and
//! θ = π − (π/2)(2 − 2t)^power above (the equator θ = π/2 is always a bin edge), and `np` equal
//! bins in φ. With power > 1 the cells near both poles are small, so narrow lobes (GGX
//! α = 0.05, Phong n = 2000, transmission at normal incidence) are resolved by many cells
//! instead of falling into one ring of the default (cos θ, φ) grid. Expected counts integrate
//! the density with the midpoint rule in (θ, φ) with the Jacobian sin θ; rejected samples form
//! an extra cell (as in `caustica_core::chi2`).

use super::{BxDF, TransportMode};
use caustica_core::chi2::{ChiSquareResult, chi_square};
use caustica_core::sampling::{Pcg32, warp};
use caustica_core::{Frame, Spectrum, Vec2, Vec3};
use std::f64::consts::PI;

pub struct LobeDomain {
    pub center: Vec3,
    /// Ring edges in θ (radians), increasing from 0 to π.
    pub edges: Vec<f64>,
    pub np: usize,
    pub res: usize,
}

/// θ(t) of the symmetric power mapping described in the module docs.
fn power_map(t: f64, power: f64) -> f64 {
    if t <= 0.5 {
        0.5 * PI * (2.0 * t).powf(power)
    } else {
        PI - 0.5 * PI * (2.0 - 2.0 * t).powf(power)
    }
}

impl LobeDomain {
    pub fn new(center: Vec3, power: f64) -> Self {
        Self::with_rings(center, power, 48, 64, 10)
    }

    pub fn with_rings(center: Vec3, power: f64, nt: usize, np: usize, res: usize) -> Self {
        let edges = (0..=nt)
            .map(|i| power_map(i as f64 / nt as f64, power))
            .collect();
        Self {
            center: center.normalize(),
            edges,
            np,
            res,
        }
    }

    /// Adds a ring edge at polar angle `theta` (radians), e.g. on a known discontinuity of the
    /// density, so that no cell straddles it.
    pub fn split_at(mut self, theta: f64) -> Self {
        if theta > 0.0 && theta < PI && !self.edges.iter().any(|&e| (e - theta).abs() < 1e-9) {
            self.edges.push(theta);
            self.edges.sort_by(f64::total_cmp);
        }
        self
    }

    fn nt(&self) -> usize {
        self.edges.len() - 1
    }

    fn frame(&self) -> Frame {
        Frame::from_normal(self.center)
    }

    fn cell(&self, frame: &Frame, w: Vec3) -> Option<usize> {
        let l = frame.to_local(w).as_dvec3();
        let len = l.length();
        if !len.is_finite() || (len - 1.0).abs() > 1e-3 {
            return None;
        }
        let l = l / len;
        let theta = l.z.clamp(-1.0, 1.0).acos();
        let ti = self
            .edges
            .partition_point(|&e| e <= theta)
            .saturating_sub(1)
            .min(self.nt() - 1);
        let mut phi = l.y.atan2(l.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let pi = ((phi / (2.0 * PI) * self.np as f64) as usize).min(self.np - 1);
        Some(ti * self.np + pi)
    }

    /// ∫ pdf dω over each cell.
    pub fn integrate_cells(&self, pdf: &impl Fn(Vec3) -> f32) -> Vec<f64> {
        let frame = self.frame();
        let (nt, np, r) = (self.nt(), self.np, self.res);
        let dphi = 2.0 * PI / (np * r) as f64;
        let mut out = vec![0.0; nt * np];
        for ti in 0..nt {
            let dtheta = (self.edges[ti + 1] - self.edges[ti]) / r as f64;
            for a in 0..r {
                let theta = self.edges[ti] + (a as f64 + 0.5) * dtheta;
                let jac = theta.sin() * dtheta * dphi;
                for pi in 0..np {
                    let mut acc = 0.0;
                    for b in 0..r {
                        let phi = ((pi * r + b) as f64 + 0.5) * dphi;
                        let l = Vec3::new(
                            (theta.sin() * phi.cos()) as f32,
                            (theta.sin() * phi.sin()) as f32,
                            theta.cos() as f32,
                        );
                        let v = pdf(frame.to_world(l)) as f64;
                        if v.is_finite() {
                            acc += v;
                        }
                    }
                    out[ti * np + pi] += acc * jac;
                }
            }
        }
        out
    }

    pub fn integrate(&self, pdf: &impl Fn(Vec3) -> f32) -> f64 {
        self.integrate_cells(pdf).iter().sum()
    }

    pub fn run(
        &self,
        n: usize,
        mut sample: impl FnMut() -> Option<Vec3>,
        pdf: impl Fn(Vec3) -> f32,
    ) -> ChiSquareResult {
        let frame = self.frame();
        let ncell = self.nt() * self.np;
        let mut observed = vec![0.0f64; ncell + 1];
        for _ in 0..n {
            match sample().and_then(|w| self.cell(&frame, w)) {
                Some(c) => observed[c] += 1.0,
                None => observed[ncell] += 1.0,
            }
        }
        let mut expected: Vec<f64> = self
            .integrate_cells(&pdf)
            .iter()
            .map(|v| v * n as f64)
            .collect();
        let total: f64 = expected.iter().sum();
        expected.push((n as f64 - total).max(0.0));
        chi_square(&observed, &expected)
    }
}

/// Domain for testing a BSDF: 120 rings around +z (so the horizon, where most densities are
/// discontinuous, is a cell boundary and no cell straddles it) times 128 azimuth bins. `narrow`
/// lobes (α ≈ 0.05, high Phong exponents) get rings refined toward the poles and a finer
/// integration grid.
pub fn lobe_domain(narrow: bool) -> LobeDomain {
    if narrow {
        LobeDomain::with_rings(Vec3::Z, 2.0, 120, 128, 20)
    } else {
        LobeDomain::with_rings(Vec3::Z, 1.0, 120, 128, 8)
    }
}

/// Per-test significance for a group of `m` tests at family-wise level 1 % (Šidák).
pub fn sidak(m: usize) -> f64 {
    1.0 - (1.0 - 0.01f64).powf(1.0 / m as f64)
}

/// Unit direction at polar angle `deg` (degrees), azimuth chosen off the axes; `up = false`
/// mirrors it below the surface.
pub fn dir(deg: f32, up: bool) -> Vec3 {
    let t = deg.to_radians();
    let z = if up { t.cos() } else { -t.cos() };
    Vec3::new(t.sin() * 0.8, t.sin() * 0.6, z)
}

/// χ² test of the non-delta samples of `b` against `b.pdf` on a [`LobeDomain`].
pub fn chi2_bsdf(
    b: &impl BxDF,
    wo: Vec3,
    mode: TransportMode,
    domain: &LobeDomain,
    seed: u64,
    n: usize,
) -> ChiSquareResult {
    let mut rng = Pcg32::new(seed, 3);
    domain.run(
        n,
        || {
            let uc = rng.next_f32();
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let s = b.sample(wo, uc, u, mode)?;
            (!s.flags.is_delta()).then_some(s.wi)
        },
        |wi| b.pdf(wo, wi, mode),
    )
}

/// Every sample's `pdf` equals `b.pdf(wo, wi)` and its weight equals f |cos θi| / pdf.
pub fn check_sample_consistency(b: &impl BxDF, wo: Vec3, mode: TransportMode, seed: u64) {
    let mut rng = Pcg32::new(seed, 4);
    let mut accepted = 0;
    for _ in 0..20_000 {
        let uc = rng.next_f32();
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let Some(s) = b.sample(wo, uc, u, mode) else {
            continue;
        };
        accepted += 1;
        assert!(
            (s.wi.length() - 1.0).abs() < 1e-4,
            "wi not unit: {:?}",
            s.wi
        );
        assert!(s.weight.is_finite() && s.weight.min_component() >= 0.0);
        let pdf = b.pdf(wo, s.wi, mode);
        assert!(
            (pdf - s.pdf).abs() <= 2e-3 * s.pdf,
            "pdf mismatch wo={wo} wi={:?}: sample {} vs pdf() {pdf}",
            s.wi,
            s.pdf
        );
        let f = b.eval(wo, s.wi, mode);
        let w = f * (s.wi.z.abs() / s.pdf);
        for c in 0..3 {
            assert!(
                (w[c] - s.weight[c]).abs() <= 2e-3 * s.weight[c].max(1e-3),
                "weight mismatch wo={wo} wi={:?}: {:?} vs eval·cos/pdf {:?}",
                s.wi,
                s.weight,
                w
            );
        }
        // Sample eta is 1 for reflection, η′ otherwise.
        if s.wi.z * wo.z > 0.0 {
            assert_eq!(s.eta, 1.0);
        }
    }
    assert!(accepted > 1000, "only {accepted} samples accepted");
}

/// Directional albedo ∫ f |cos θi| dωi estimated from the sampler's weights: (mean, 5σ bound)
/// per channel.
pub fn albedo_sampled(
    b: &impl BxDF,
    wo: Vec3,
    mode: TransportMode,
    seed: u64,
    n: usize,
) -> ([f64; 3], [f64; 3]) {
    let mut rng = Pcg32::new(seed, 5);
    let (mut s1, mut s2) = ([0.0f64; 3], [0.0f64; 3]);
    for _ in 0..n {
        let uc = rng.next_f32();
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let w = b
            .sample(wo, uc, u, mode)
            .map(|s| s.weight)
            .unwrap_or(Spectrum::ZERO);
        for c in 0..3 {
            s1[c] += w[c] as f64;
            s2[c] += (w[c] as f64).powi(2);
        }
    }
    let mut mean = [0.0; 3];
    let mut tol = [0.0; 3];
    for c in 0..3 {
        mean[c] = s1[c] / n as f64;
        let var = (s2[c] / n as f64 - mean[c] * mean[c]).max(0.0);
        tol[c] = 5.0 * (var / n as f64).sqrt() + 1e-4;
    }
    (mean, tol)
}

/// Directional albedo from `eval` alone (uniform sphere sampling, independent of the BSDF's
/// sampler): (mean, 5σ bound) per channel.
pub fn albedo_uniform(
    b: &impl BxDF,
    wo: Vec3,
    mode: TransportMode,
    seed: u64,
    n: usize,
) -> ([f64; 3], [f64; 3]) {
    let mut rng = Pcg32::new(seed, 6);
    let (mut s1, mut s2) = ([0.0f64; 3], [0.0f64; 3]);
    for _ in 0..n {
        let wi = warp::square_to_uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
        let v = b.eval(wo, wi, mode) * (wi.z.abs() / warp::uniform_sphere_pdf());
        for c in 0..3 {
            s1[c] += v[c] as f64;
            s2[c] += (v[c] as f64).powi(2);
        }
    }
    let mut mean = [0.0; 3];
    let mut tol = [0.0; 3];
    for c in 0..3 {
        mean[c] = s1[c] / n as f64;
        let var = (s2[c] / n as f64 - mean[c] * mean[c]).max(0.0);
        tol[c] = 5.0 * (var / n as f64).sqrt() + 1e-4;
    }
    (mean, tol)
}

/// f(wo, wi) = f(wi, wo) for random pairs of directions on the same side (reflection lobes).
pub fn check_reflection_reciprocity(b: &impl BxDF, seed: u64) {
    let mut rng = Pcg32::new(seed, 7);
    let mut nonzero = 0;
    for _ in 0..5_000 {
        let wo = warp::square_to_uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
        let mut wi = warp::square_to_uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
        if wi.z * wo.z < 0.0 {
            wi.z = -wi.z;
        }
        let a = b.eval(wo, wi, TransportMode::Radiance);
        let c = b.eval(wi, wo, TransportMode::Radiance);
        for k in 0..3 {
            assert!(
                (a[k] - c[k]).abs() <= 1e-3 * a[k].abs().max(c[k].abs()) + 1e-7,
                "f({wo},{wi}) = {a:?} but f(wi,wo) = {c:?}"
            );
        }
        if !a.is_black() {
            nonzero += 1;
        }
    }
    assert!(nonzero > 100);
}
