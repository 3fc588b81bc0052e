//! Free-flight sampling and transmittance, the estimators every walker uses inside a medium.
//!
//! # Free flights: delta tracking with spectral MIS
//!
//! Along a ray the transmittance per channel c is T_c(t) = exp(−∫₀ᵗ σ_t,c) (seed 000 eq. 8.2,
//! with the minus sign the print lacks). A free flight either scatters at t, with density
//! T_c(t) σ_t,c(t), or passes the segment's end t_max, with probability T_c(t_max). With RGB
//! coefficients the three channels want different distances; one channel (the *hero*, chosen
//! uniformly per segment) is tracked and the result weighted by the balance heuristic over the
//! three choices — Mitsuba 3's `volpath` and pbrt-v4's `VolPathIntegrator` do the same.
//!
//! The "channels" are the path's lanes: RGB, or three wavelengths in spectral mode, whose
//! coefficients the caller evaluates once per span ([`Medium::coefficients`]); the estimators
//! here are the same arithmetic either way. After a dispersive interface a spectral path keeps
//! only its hero wavelength (`Channels::terminate_secondary`) but its secondary lanes still hold
//! coefficients: the MIS stays over all three lanes, which is still unbiased for the surviving
//! lane (the balance-heuristic estimator f_c / ⅓Σ_k p_k is unbiased for every lane c whose own
//! density p_c is positive wherever f_c is), only a little noisier than tracking lane 0 alone.
//! Kept that way for simplicity.
//!
//! In a grid the flight is tracked against majorants σ̄_c = d̄ σ_t,c ≥ σ_t,c(t) (one per
//! majorant cell, [`super::grid::MajorantSegments`]): tentative collisions at rate σ̄_h of the
//! hero, each real with probability σ_t,h/σ̄_h, null otherwise (delta tracking, Woodcock et al.
//! 1965). For a sampled sequence of null collisions t₁ … t_{n−1} and a real one tₙ, every
//! channel's path density and the integrand share the product
//!
//! ```text
//! A_c = Π_{i<n} e^{−σ̄_c Δᵢ} σ_n,c(tᵢ) · e^{−σ̄_c Δₙ},   σ_n = σ̄ − σ_t (null coefficient)
//! ```
//!
//! so a scattering at tₙ gets the weight f_c/p̄ = A_c σ_s,c(tₙ) / ⅓Σ_k A_k σ_t,k(tₙ), a pass
//! A_c / ⅓Σ_k A_k — the throughput factor of σ_s T / p with absorption folded in (no
//! absorption event is sampled). In a homogeneous medium σ̄ = σ_t, no null collision happens
//! and this is the familiar `σ_s e^{−σ_t t} / ⅓Σ_k σ_t,k e^{−σ_t,k t}`.
//!
//! # Transmittance
//!
//! Closed form in homogeneous media; in grids ratio tracking (Novák et al. 2014) with the
//! largest channel's majorant, T_c = Π (1 − σ_t,c(tᵢ)/σ̄), unbiased for every channel, with
//! Russian roulette once the estimate is small (as pbrt-v4).
//!
//! # Random numbers and bounded loops
//!
//! A [`TrackingSampler`] gives the first two numbers of a segment from the path's sampler
//! (stratified: a homogeneous flight uses exactly these two) and the rest from a PCG32 stream
//! seeded by them, so the sampler's dimension layout stays fixed and renders stay a pure
//! function of the seed. Every loop is capped at [`MAX_TRACKING_STEPS`] collisions; scenes whose
//! media could need more are refused when built (`Medium::validate`).

use super::{Coefficients, Medium, MediumKind};
use caustica_core::sampling::{Pcg32, mix_seed};
use caustica_core::{Ray, Spectrum};

/// Largest number of tentative collisions one tracking call takes.
pub const MAX_TRACKING_STEPS: u32 = 1 << 20;

/// Random numbers of one tracking call: two from the path's sampler, then a PCG32 stream
/// seeded by them.
#[derive(Clone, Debug)]
pub struct TrackingSampler {
    first: [f32; 2],
    used: u8,
    rng: Option<Pcg32>,
}

impl TrackingSampler {
    pub fn new(u0: f32, u1: f32) -> Self {
        Self {
            first: [u0, u1],
            used: 0,
            rng: None,
        }
    }
    /// Next uniform number in [0, 1).
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        if (self.used as usize) < self.first.len() {
            self.used += 1;
            return self.first[self.used as usize - 1];
        }
        let [a, b] = self.first;
        self.rng
            .get_or_insert_with(|| {
                Pcg32::new(
                    mix_seed(
                        ((a.to_bits() as u64) << 32) | b.to_bits() as u64,
                        &[0x0074_726b],
                    ),
                    0x6d65_6469,
                )
            })
            .next_f32()
    }
}

/// What a free flight found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FreeFlight {
    /// A real scattering at ray parameter `t` (m); multiply the path throughput by `weight`
    /// (σ_s T / p, dimensionless per channel) and scatter with the phase function there.
    Scatter { t: f32, weight: Spectrum },
    /// No scattering before `t_max`; multiply the throughput by `weight` (T / P, per channel).
    Pass { weight: Spectrum },
}

/// Majorant segments of a medium along a ray: one segment for homogeneous media, the DDA
/// cells for grids. Items `(t_start, t_end, majorant density)`.
enum Segments<'a> {
    One(Option<(f32, f32, f32)>),
    Grid(super::grid::MajorantSegments<'a>),
}

impl Iterator for Segments<'_> {
    type Item = (f32, f32, f32);
    #[inline]
    fn next(&mut self) -> Option<(f32, f32, f32)> {
        match self {
            Segments::One(s) => s.take(),
            Segments::Grid(g) => g.next(),
        }
    }
}

fn segments<'a>(m: &'a Medium, ray: &Ray, t_max: f32) -> Segments<'a> {
    match &m.kind {
        MediumKind::Homogeneous(_) => Segments::One(Some((0.0, t_max, 1.0))),
        MediumKind::Grid(g) => Segments::Grid(g.majorant_segments(ray, 0.0, t_max)),
    }
}

#[inline]
fn mean(s: Spectrum) -> f32 {
    (s[0] + s[1] + s[2]) / 3.0
}

/// Delta tracking with spectral MIS (module docs): samples the next real scattering along `ray`
/// (unit direction) before `t_max` (may be infinite: then a medium with σ_t > 0 always
/// scatters), with `c` the medium's coefficients in the path's lanes.
pub fn sample_free_flight(
    m: &Medium,
    c: &Coefficients,
    ray: &Ray,
    t_max: f32,
    ts: &mut TrackingSampler,
) -> FreeFlight {
    let sigma_t = c.sigma_t;
    let hero = ((ts.next_1d() * 3.0) as usize).min(2);
    let mut a = Spectrum::ONE;
    let mut steps = 0u32;
    for (t0, t1, dmax) in segments(m, ray, t_max) {
        let maj = sigma_t * dmax;
        if maj[hero] <= 0.0 {
            if t1.is_finite() {
                a *= (maj * -(t1 - t0)).exp();
            }
            continue;
        }
        let mut t = t0;
        loop {
            let dt = -(1.0 - ts.next_1d()).ln() / maj[hero];
            if t + dt >= t1 || steps >= MAX_TRACKING_STEPS {
                a *= (maj * -(t1 - t)).exp();
                break;
            }
            steps += 1;
            t += dt;
            a *= (maj * -dt).exp();
            let d = match &m.kind {
                MediumKind::Homogeneous(_) => 1.0,
                MediumKind::Grid(g) => g.density(ray.at(t)),
            };
            let st = sigma_t * d;
            let null = (maj - st).map(|v| v.max(0.0));
            // Real with probability σ_t,h/σ̄_h (no number drawn when that is 1).
            let real = null[hero] <= 0.0 || ts.next_1d() * maj[hero] < st[hero];
            if real {
                let p = mean(a * st);
                if p <= 0.0 {
                    return FreeFlight::Pass {
                        weight: Spectrum::ZERO,
                    };
                }
                return FreeFlight::Scatter {
                    t,
                    weight: a * (c.sigma_s * d) / p,
                };
            }
            a *= null;
            let s = a.max_component();
            if s <= 0.0 {
                return FreeFlight::Pass {
                    weight: Spectrum::ZERO,
                };
            }
            a /= s;
        }
    }
    let p = mean(a);
    FreeFlight::Pass {
        weight: if p > 0.0 { a / p } else { Spectrum::ZERO },
    }
}

/// Transmittance along `ray` (unit direction) over `[0, t_max]`: exp(−σ_t t_max) in homogeneous
/// media, ratio tracking with Russian roulette in grids (module docs); `c` the medium's
/// coefficients in the path's lanes.
pub fn transmittance(
    m: &Medium,
    c: &Coefficients,
    ray: &Ray,
    t_max: f32,
    ts: &mut TrackingSampler,
) -> Spectrum {
    let sigma_t = c.sigma_t;
    let g = match &m.kind {
        MediumKind::Homogeneous(_) => return (sigma_t * -t_max).exp(),
        MediumKind::Grid(g) => g,
    };
    let mut tr = Spectrum::ONE;
    let mut steps = 0u32;
    let max_sigma = sigma_t.max_component();
    for (t0, t1, dmax) in g.majorant_segments(ray, 0.0, t_max) {
        let maj = max_sigma * dmax;
        if maj <= 0.0 {
            continue;
        }
        let mut t = t0;
        loop {
            t += -(1.0 - ts.next_1d()).ln() / maj;
            if t >= t1 || steps >= MAX_TRACKING_STEPS {
                break;
            }
            steps += 1;
            let st = sigma_t * g.density(ray.at(t));
            tr *= (Spectrum::ONE - st / maj).map(|v| v.max(0.0));
            if tr.max_component() < 0.05 {
                if ts.next_1d() < 0.75 {
                    return Spectrum::ZERO;
                }
                tr /= 0.25;
            }
        }
    }
    tr
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::medium::DensityGrid;
    use crate::phase::PhaseFunction;
    use caustica_core::{Affine3A, Channels, Vec3};

    /// The medium's RGB coefficients (RGB mode).
    fn rgb(m: &Medium) -> Coefficients {
        m.coefficients(&Channels::Rgb)
    }

    fn homogeneous(st: Spectrum, albedo: f32) -> Medium {
        Medium::homogeneous(st * (1.0 - albedo), st * albedo, PhaseFunction::default())
    }

    /// Kolmogorov–Smirnov statistic of `xs` against the CDF `cdf`.
    fn ks(mut xs: Vec<f64>, cdf: impl Fn(f64) -> f64) -> f64 {
        xs.sort_by(f64::total_cmp);
        let n = xs.len() as f64;
        xs.iter()
            .enumerate()
            .map(|(i, &x)| {
                let f = cdf(x);
                (f - i as f64 / n).abs().max((f - (i + 1) as f64 / n).abs())
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn free_flights_are_exponential_ks() {
        // Grey medium: one channel law σ_t e^{−σ_t s} (seed 000 eq. 8.20), tested by KS at
        // α = 0.001 (critical value 1.95/√n).
        let sigma = 1.7f32;
        let m = homogeneous(Spectrum::splat(sigma), 1.0);
        let ray = Ray::new(Vec3::ZERO, Vec3::X);
        let mut rng = Pcg32::new(7, 1);
        let n = 20_000;
        let xs: Vec<f64> = (0..n)
            .map(|_| {
                let mut ts = TrackingSampler::new(rng.next_f32(), rng.next_f32());
                match sample_free_flight(&m, &rgb(&m), &ray, f32::INFINITY, &mut ts) {
                    FreeFlight::Scatter { t, weight } => {
                        assert!((weight - Spectrum::ONE).max_component().abs() < 1e-5);
                        t as f64
                    }
                    FreeFlight::Pass { .. } => panic!("an infinite medium always scatters"),
                }
            })
            .collect();
        let d = ks(xs, |s| 1.0 - (-(sigma as f64) * s).exp());
        assert!(d < 1.95 / (n as f64).sqrt(), "KS D = {d}");
    }

    #[test]
    fn grid_free_flights_follow_the_density_ks() {
        // A constant grid of density 0.5 inside a box with majorant cells: delta tracking must
        // give the same exponential law as the closed form, with null collisions in between
        // (the voxels are 0.5 and the majorant 0.5, so we add a denser corner far away to make
        // the global maximum 1 but keep the ray's cells at 0.5).
        let res = [8u32, 8, 8];
        let mut data = vec![0.5f32; 512];
        data[511] = 1.0;
        let g = DensityGrid::new(res, data, Affine3A::from_scale(Vec3::splat(10.0))).unwrap();
        let sigma = 0.8f32;
        let m = Medium::grid(
            g,
            Spectrum::ZERO,
            Spectrum::splat(sigma),
            PhaseFunction::default(),
        );
        let ray = Ray::new(Vec3::new(0.0, 1.0, 1.0), Vec3::X);
        let mut rng = Pcg32::new(9, 2);
        let n = 20_000;
        let mut xs = Vec::new();
        let mut passed = 0;
        for _ in 0..n {
            let mut ts = TrackingSampler::new(rng.next_f32(), rng.next_f32());
            match sample_free_flight(&m, &rgb(&m), &ray, 10.0, &mut ts) {
                FreeFlight::Scatter { t, .. } => xs.push(t as f64),
                FreeFlight::Pass { .. } => passed += 1,
            }
        }
        let rate = (sigma * 0.5) as f64;
        let p_pass = (-rate * 10.0).exp();
        let z = (passed as f64 - n as f64 * p_pass) / (n as f64 * p_pass * (1.0 - p_pass)).sqrt();
        assert!(
            z.abs() < 4.0,
            "passes {passed}, expected {}",
            n as f64 * p_pass
        );
        let k = xs.len() as f64;
        let d = ks(xs, |s| (1.0 - (-rate * s).exp()) / (1.0 - p_pass));
        assert!(d < 1.95 / k.sqrt(), "KS D = {d}");
    }

    #[test]
    fn chromatic_flights_estimate_each_channel_without_bias() {
        // E[weight of a pass] = T_c/P·P and E[Σ scatter weights] reproduce, per channel, the
        // probability of passing T_c(t_max) and the scattered fraction α_c (1 − T_c).
        let st = Spectrum::new(0.3, 1.0, 2.5);
        let albedo = 0.8f32;
        let m = homogeneous(st, albedo);
        let ray = Ray::new(Vec3::ZERO, Vec3::Y);
        let t_max = 1.3f32;
        let mut rng = Pcg32::new(11, 3);
        let n = 200_000;
        let (mut pass, mut scat) = ([0.0f64; 3], [0.0f64; 3]);
        let (mut pass2, mut scat2) = ([0.0f64; 3], [0.0f64; 3]);
        for _ in 0..n {
            let mut ts = TrackingSampler::new(rng.next_f32(), rng.next_f32());
            match sample_free_flight(&m, &rgb(&m), &ray, t_max, &mut ts) {
                FreeFlight::Pass { weight } => {
                    for c in 0..3 {
                        pass[c] += weight[c] as f64;
                        pass2[c] += (weight[c] as f64).powi(2);
                    }
                }
                FreeFlight::Scatter { weight, .. } => {
                    for c in 0..3 {
                        scat[c] += weight[c] as f64;
                        scat2[c] += (weight[c] as f64).powi(2);
                    }
                }
            }
        }
        for c in 0..3 {
            let tr = (-(st[c] as f64) * t_max as f64).exp();
            for (sum, sum2, want) in [
                (pass[c], pass2[c], tr),
                (scat[c], scat2[c], albedo as f64 * (1.0 - tr)),
            ] {
                let mean = sum / n as f64;
                let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
                assert!(
                    (mean - want).abs() < 4.0 * se + 1e-6,
                    "channel {c}: {mean} vs {want}"
                );
            }
        }
    }

    #[test]
    fn ratio_tracking_matches_the_analytic_transmittance_on_a_linear_ramp() {
        // Density x along x over a unit box scaled to 2 m: ∫ σ_t d along the x axis from the
        // first to the last voxel centre is σ_t (b² − a²)/(2·2) in world metres.
        let res = 32u32;
        let g = DensityGrid::from_fn([res, 4, 4], Affine3A::from_scale(Vec3::splat(2.0)), |u| u.x)
            .unwrap();
        let st = Spectrum::new(0.5, 1.5, 3.0);
        let m = Medium::grid(g, st * 0.5, st * 0.5, PhaseFunction::default());
        let a = 2.0 / (2.0 * res as f32);
        let ray = Ray::new(Vec3::new(a, 1.0, 1.0), Vec3::X);
        let len = 2.0 - 2.0 * a;
        let mut rng = Pcg32::new(13, 4);
        let n = 100_000;
        let (mut s, mut s2) = ([0.0f64; 3], [0.0f64; 3]);
        for _ in 0..n {
            let mut ts = TrackingSampler::new(rng.next_f32(), rng.next_f32());
            let t = transmittance(&m, &rgb(&m), &ray, len, &mut ts);
            for c in 0..3 {
                s[c] += t[c] as f64;
                s2[c] += (t[c] as f64).powi(2);
            }
        }
        // World x = 2u; density u = x/2; ∫_a^{a+len} x/2 dx.
        let (x0, x1) = (a as f64, (a + len) as f64);
        let integral = (x1 * x1 - x0 * x0) / 4.0;
        for c in 0..3 {
            let want = (-(st[c] as f64) * integral).exp();
            let mean = s[c] / n as f64;
            let se = ((s2[c] / n as f64 - mean * mean) / n as f64).sqrt();
            assert!(
                (mean - want).abs() < 4.0 * se + 1e-5,
                "channel {c}: {mean} vs {want}"
            );
            // The deterministic quadrature agrees too.
            let od = m.optical_depth(&ray, 0.0, len)[c] as f64;
            assert!((od - st[c] as f64 * integral).abs() < 1e-3, "{od}");
        }
    }

    #[test]
    fn homogeneous_transmittance_has_the_minus_sign() {
        // Seed 000 eq. 8.2 prints e^{+∫σ_t}; transmittance must fall with distance.
        let m = homogeneous(Spectrum::new(1.0, 2.0, 0.0), 0.5);
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        let t = transmittance(&m, &rgb(&m), &ray, 0.7, &mut TrackingSampler::new(0.5, 0.5));
        assert!((t[0] - (-0.7f32).exp()).abs() < 1e-6);
        assert!((t[1] - (-1.4f32).exp()).abs() < 1e-6);
        assert_eq!(t[2], 1.0);
    }

    #[test]
    fn very_dense_grids_end_and_are_refused_when_built() {
        let g = DensityGrid::new([2, 2, 2], vec![1.0; 8], Affine3A::IDENTITY).unwrap();
        let m = Medium::grid(
            g,
            Spectrum::ZERO,
            Spectrum::splat(1e9),
            PhaseFunction::default(),
        );
        let e = m.validate().unwrap_err();
        assert!(e.contains("tracking would not end"), "{e}");
        // Even unvalidated, tracking ends (capped).
        let ray = Ray::new(Vec3::new(-1.0, 0.5, 0.5), Vec3::X);
        let mut ts = TrackingSampler::new(0.3, 0.6);
        let _ = transmittance(&m, &rgb(&m), &ray, 3.0, &mut ts);
        let _ = sample_free_flight(&m, &rgb(&m), &ray, 3.0, &mut ts);
    }
}

#[cfg(test)]
mod grid_consistency {
    use super::*;
    use crate::medium::DensityGrid;
    use crate::phase::PhaseFunction;
    use caustica_core::{Affine3A, Channels, Vec3};

    fn rgb(m: &Medium) -> Coefficients {
        m.coefficients(&Channels::Rgb)
    }

    #[test]
    fn delta_and_ratio_tracking_match_the_optical_depth_in_a_random_grid() {
        let mut rng = Pcg32::new(21, 5);
        let data: Vec<f32> = (0..13 * 11 * 9)
            .map(|_| rng.next_f32().powi(3) * 2.0)
            .collect();
        let to_world = Affine3A::from_scale_rotation_translation(
            Vec3::new(1.2, 1.6, 1.2),
            glam::Quat::from_rotation_z(0.3),
            Vec3::new(-0.6, -1.0, -0.6),
        );
        let g = DensityGrid::new([13, 11, 9], data, to_world).unwrap();
        let m = Medium::grid(
            g,
            Spectrum::ZERO,
            Spectrum::splat(1.5),
            PhaseFunction::default(),
        );
        for r in 0..12 {
            let o = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 3.0 - 1.5;
            let target = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5;
            let d = (target - o).normalize();
            let ray = Ray::new(o, d);
            let t_max = 3.0;
            let want = (-(m.optical_depth(&ray, 0.0, t_max)[0] as f64)).exp();
            let n = 40_000;
            let (mut pass, mut ratio, mut ratio2) = (0.0f64, 0.0f64, 0.0f64);
            for _ in 0..n {
                let mut ts = TrackingSampler::new(rng.next_f32(), rng.next_f32());
                if let FreeFlight::Pass { weight } =
                    sample_free_flight(&m, &rgb(&m), &ray, t_max, &mut ts)
                {
                    pass += weight[0] as f64;
                }
                let mut ts = TrackingSampler::new(rng.next_f32(), rng.next_f32());
                let t = transmittance(&m, &rgb(&m), &ray, t_max, &mut ts)[0] as f64;
                ratio += t;
                ratio2 += t * t;
            }
            let p = pass / n as f64;
            let se = (want * (1.0 - want) / n as f64).sqrt();
            assert!(
                (p - want).abs() < 4.5 * se + 1e-4,
                "ray {r}: delta {p} vs {want}"
            );
            let rm = ratio / n as f64;
            let rse = ((ratio2 / n as f64 - rm * rm) / n as f64).sqrt();
            assert!(
                (rm - want).abs() < 4.5 * rse + 1e-4,
                "ray {r}: ratio {rm} vs {want}"
            );
        }
    }
}
