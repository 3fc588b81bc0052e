//! The wavelengths a spectral path carries: hero wavelength sampling (Wilkie et al. 2014,
//! "Hero Wavelength Spectral Sampling", EGSR) with N = 3, one wavelength per lane of
//! [`Spectrum`].
//!
//! One uniform number u gives the hero λ₀ = F⁻¹(u) and its rotations
//! λ_j = F⁻¹((u + j/3) mod 1), j = 1, 2, where F is the CDF of a density p on [360, 830] nm.
//! Since (u + j/3) mod 1 is uniform whenever u is, every λ_j is marginally distributed by p, and
//! the film's estimator of a colour integral ∫ S(λ) c̄(λ) dλ is the average of the three
//! one-sample estimators, (1/3) Σ_j S(λ_j) c̄(λ_j) / p(λ_j) ([`SampledWavelengths::to_xyz`]).
//! The three are correlated (stratified in CDF space), which is the point: they cover the
//! spectrum evenly.
//!
//! The density is pbrt-v4's visible-wavelength density (Pharr, Jakob and Humphreys,
//! *Physically Based Rendering*, 4th ed., sec. 4.6.5): p(λ) ∝ 1 / cosh²(0.0072 (λ − 538)),
//! normalised on [360, 830] nm, with the closed-form inverse CDF
//! λ = 538 + atanh(t₀ + u (t₁ − t₀)) / 0.0072, t_{0,1} = tanh(0.0072 (360|830 − 538)).
//! It is concentrated where the matching functions are large and never vanishes on
//! [360, 830] nm, so the estimator stays bounded wherever the tables are non-zero. Measured
//! against uniform sampling by `measure_sampling_variance` (see the tests): the visible density
//! has the lower variance of the film's linear sRGB estimate for every spectrum tried.

use super::cie::{CIE_Y_INTEGRAL, LAMBDA_MAX, LAMBDA_MIN, cie_xyz, xyz_to_linear_srgb};
use crate::Spectrum;

/// Number of wavelengths per path (the lanes of [`Spectrum`]).
pub const N_WAVELENGTHS: usize = 3;

/// Rate a of the density 1/cosh²(a (λ − centre)), in 1/nm.
const VIS_A: f32 = 0.0072;
/// Centre of the density (nm).
const VIS_CENTRE: f32 = 538.0;
/// tanh(a (360 − 538)).
const VIS_T0: f32 = -0.856_910_6;
/// tanh(a (830 − 538)) − tanh(a (360 − 538)).
const VIS_DT: f32 = 1.827_502;
/// a / (t₁ − t₀): the normalisation of the density, in 1/nm.
const VIS_NORM: f32 = 0.003_939_804;

/// The largest f32 below 1.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// The visible-wavelength density p(λ) = 0.00394 / cosh²(0.0072 (λ − 538)) on [360, 830] nm,
/// in 1/nm; zero outside.
#[inline]
pub fn visible_pdf(lambda_nm: f32) -> f32 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda_nm) {
        return 0.0;
    }
    let c = (VIS_A * (lambda_nm - VIS_CENTRE)).cosh();
    VIS_NORM / (c * c)
}

/// The inverse CDF of [`visible_pdf`]: u ∈ [0, 1) ↦ λ ∈ [360, 830] nm.
#[inline]
pub fn sample_visible_wavelength(u: f32) -> f32 {
    inverse_cdf(u).0
}

/// λ = F⁻¹(u) and v = t₀ + u (t₁ − t₀), so that p(λ) = VIS_NORM (1 − v²).
#[inline]
fn inverse_cdf(u: f32) -> (f32, f32) {
    let v = VIS_T0 + u * VIS_DT;
    // atanh(v) = ½ ln((1 + v)/(1 − v)); |v| ≤ 0.971, so no overflow.
    let l = VIS_CENTRE + 0.5 * ((1.0 + v) / (1.0 - v)).ln() / VIS_A;
    (l.clamp(LAMBDA_MIN, LAMBDA_MAX), v)
}

/// The CDF of [`visible_pdf`] (for tests and stratification checks).
#[inline]
pub fn visible_cdf(lambda_nm: f32) -> f32 {
    let l = lambda_nm.clamp(LAMBDA_MIN, LAMBDA_MAX);
    (((VIS_A * (l - VIS_CENTRE)).tanh() - VIS_T0) / VIS_DT).clamp(0.0, 1.0)
}

/// (u + j/3) mod 1, kept in [0, 1).
#[inline]
fn rotate(u: f32, j: usize) -> f32 {
    let v = u + j as f32 / N_WAVELENGTHS as f32;
    let v = if v >= 1.0 { v - 1.0 } else { v };
    v.clamp(0.0, ONE_MINUS_EPSILON)
}

/// The three wavelengths (nm) of a spectral path and the marginal density (1/nm) each was drawn
/// with. Lane j of every [`Spectrum`] on the path is the value at `lambda[j]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampledWavelengths {
    /// Wavelengths in nm; `lambda[0]` is the hero.
    pub lambda: [f32; 3],
    /// Marginal densities in 1/nm; 0 marks a terminated lane.
    pub pdf: [f32; 3],
}

impl SampledWavelengths {
    /// Hero wavelength sampling from the visible density: λ_j = F⁻¹((u + j/3) mod 1), each with
    /// pdf [`visible_pdf`]`(λ_j)`. `u` ∈ [0, 1).
    ///
    /// The density comes without a transcendental function: with v = t₀ + u (t₁ − t₀),
    /// λ = 538 + atanh(v)/a and cosh²(atanh v) = 1/(1 − v²), so p(λ) = (a/(t₁ − t₀)) (1 − v²)
    /// (equal to `visible_pdf(λ)` up to rounding).
    #[inline]
    pub fn sample_visible(u: f32) -> Self {
        let u = u.clamp(0.0, ONE_MINUS_EPSILON);
        let mut lambda = [0.0; 3];
        let mut pdf = [0.0; 3];
        for j in 0..N_WAVELENGTHS {
            let (l, v) = inverse_cdf(rotate(u, j));
            lambda[j] = l;
            pdf[j] = VIS_NORM * (1.0 - v * v);
        }
        Self { lambda, pdf }
    }

    /// Hero wavelength sampling from the uniform density on [360, 830] nm: λ_j = 360 +
    /// 470 ((u + j/3) mod 1), each with pdf 1/470 nm⁻¹. `u` ∈ [0, 1).
    #[inline]
    pub fn sample_uniform(u: f32) -> Self {
        let u = u.clamp(0.0, ONE_MINUS_EPSILON);
        let span = LAMBDA_MAX - LAMBDA_MIN;
        let mut lambda = [0.0; 3];
        for (j, l) in lambda.iter_mut().enumerate() {
            *l = (LAMBDA_MIN + span * rotate(u, j)).min(LAMBDA_MAX);
        }
        Self {
            lambda,
            pdf: [1.0 / span; 3],
        }
    }

    /// The hero wavelength λ₀ (nm), the one that survives [`Self::terminate_secondary`].
    #[inline]
    pub fn hero(&self) -> f32 {
        self.lambda[0]
    }

    /// Keeps only the hero wavelength, for events whose outcome depends on λ (a dispersive
    /// refraction sends each wavelength in its own direction, so one path can carry only one).
    ///
    /// The film's estimator is (1/3) Σ_j S_j c̄(λ_j)/p_j over the lanes with p_j ≠ 0. After
    /// termination only lane 0 counts, and its density is divided by 3, so the estimator becomes
    /// (1/3) S_0 c̄(λ₀) / (p(λ₀)/3) = S_0 c̄(λ₀) / p(λ₀): the one-sample estimator of the hero
    /// alone, unbiased because λ₀ is marginally distributed by p. (The other lanes' values are
    /// ignored from here on; callers may keep computing them.) Idempotent.
    #[inline]
    pub fn terminate_secondary(&mut self) {
        if self.secondary_terminated() {
            return;
        }
        self.pdf[1] = 0.0;
        self.pdf[2] = 0.0;
        self.pdf[0] /= N_WAVELENGTHS as f32;
    }

    /// True once [`Self::terminate_secondary`] has run.
    #[inline]
    pub fn secondary_terminated(&self) -> bool {
        self.pdf[1] == 0.0 && self.pdf[2] == 0.0
    }

    /// CIE XYZ of a path's spectral value `s` (lane j at `lambda[j]`): the Monte Carlo estimate
    /// (1/3) Σ_j s_j (x̄, ȳ, z̄)(λ_j) / p_j / CIE_Y_INTEGRAL over the lanes with p_j ≠ 0. Its
    /// expectation is ∫ S(λ) (x̄, ȳ, z̄) dλ / ∫ ȳ dλ, so a constant spectrum 1 gives Y = 1.
    #[inline]
    pub fn to_xyz(&self, s: Spectrum) -> [f32; 3] {
        let mut xyz = [0.0f32; 3];
        for j in 0..N_WAVELENGTHS {
            if self.pdf[j] == 0.0 {
                continue;
            }
            let w = s.c[j] / self.pdf[j];
            let c = cie_xyz(self.lambda[j]);
            xyz[0] += w * c[0];
            xyz[1] += w * c[1];
            xyz[2] += w * c[2];
        }
        let k = 1.0 / (N_WAVELENGTHS as f32 * CIE_Y_INTEGRAL);
        xyz.map(|v| v * k)
    }

    /// Linear sRGB (Rec. 709, D65) of a path's spectral value: [`Self::to_xyz`] through
    /// [`xyz_to_linear_srgb`], returned as an RGB [`Spectrum`] for the film.
    #[inline]
    pub fn to_linear_srgb(&self, s: Spectrum) -> Spectrum {
        Spectrum::from_rgb(xyz_to_linear_srgb(self.to_xyz(s)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chi2::chi_square;
    use crate::sampling::Pcg32;

    #[test]
    fn constants_match_their_definitions() {
        let a = VIS_A as f64;
        let t0 = (a * (360.0 - 538.0)).tanh();
        let t1 = (a * (830.0 - 538.0)).tanh();
        assert!((VIS_T0 as f64 - t0).abs() < 1e-6);
        assert!((VIS_DT as f64 - (t1 - t0)).abs() < 1e-6);
        assert!((VIS_NORM as f64 / (a / (t1 - t0)) - 1.0).abs() < 1e-6);
        // The density integrates to 1 (midpoint rule at 0.1 nm) and is the CDF's derivative.
        let s: f64 = (0..4700)
            .map(|i| visible_pdf(360.0 + (i as f32 + 0.5) * 0.1) as f64 * 0.1)
            .sum();
        assert!((s - 1.0).abs() < 1e-4, "{s}");
        for l in [380.0f32, 450.0, 538.0, 600.0, 700.0, 800.0] {
            let d = (visible_cdf(l + 0.5) - visible_cdf(l - 0.5)) / 1.0;
            assert!((d / visible_pdf(l) - 1.0).abs() < 2e-3, "{l}");
            // And the sampler inverts the CDF.
            let u = visible_cdf(l);
            assert!((sample_visible_wavelength(u) - l).abs() < 0.05, "{l}");
        }
        assert_eq!(sample_visible_wavelength(0.0), 360.0);
        assert!((sample_visible_wavelength(ONE_MINUS_EPSILON) - 830.0).abs() < 0.1);
    }

    /// Counts of `lambda` in 5 nm bins over [360, 830] against the density's mass in each bin.
    fn chi2_of(lambdas: &[f32], cdf: impl Fn(f32) -> f64) -> crate::chi2::ChiSquareResult {
        let bins = 94;
        let mut obs = vec![0.0f64; bins];
        for &l in lambdas {
            assert!((360.0..=830.0).contains(&l), "{l}");
            obs[(((l - 360.0) / 5.0) as usize).min(bins - 1)] += 1.0;
        }
        let n = lambdas.len() as f64;
        let exp: Vec<f64> = (0..bins)
            .map(|b| {
                let (a, c) = (360.0 + 5.0 * b as f32, 365.0 + 5.0 * b as f32);
                n * (cdf(c) - cdf(a))
            })
            .collect();
        chi_square(&obs, &exp)
    }

    fn pdf_cdf(l: f32) -> f64 {
        // The CDF by numerical integration of visible_pdf, independent of visible_cdf.
        let steps = 64;
        let h = (l - 360.0) as f64 / steps as f64;
        (0..steps)
            .map(|i| visible_pdf(360.0 + ((i as f64 + 0.5) * h) as f32) as f64 * h)
            .sum()
    }

    #[test]
    fn chi2_every_lane_follows_visible_pdf() {
        let mut rng = Pcg32::new(22, 1);
        let n = 100_000;
        let wls: Vec<_> = (0..n)
            .map(|_| SampledWavelengths::sample_visible(rng.next_f32()))
            .collect();
        for j in 0..3 {
            let lam: Vec<f32> = wls.iter().map(|w| w.lambda[j]).collect();
            let r = chi2_of(&lam, pdf_cdf);
            assert!(r.passed_at(0.01 / 3.0), "lane {j}: {r}");
            for w in &wls {
                let p = visible_pdf(w.lambda[j]);
                assert!((w.pdf[j] / p - 1.0).abs() < 1e-5, "{w:?}: {p}");
            }
        }
        // The test can fail: uniform wavelengths are not visible_pdf-distributed.
        let lam: Vec<f32> = (0..n)
            .map(|_| SampledWavelengths::sample_uniform(rng.next_f32()).lambda[1])
            .collect();
        assert!(!chi2_of(&lam, pdf_cdf).passed());
        // And the uniform sampler's lanes are uniform.
        let r = chi2_of(&lam, |l| (l - 360.0) as f64 / 470.0);
        assert!(r.passed(), "{r}");
    }

    #[test]
    fn lanes_are_rotations_of_the_hero_in_cdf_space() {
        let mut rng = Pcg32::new(22, 2);
        for _ in 0..1000 {
            let u = rng.next_f32();
            let w = SampledWavelengths::sample_visible(u);
            assert_eq!(w.hero(), w.lambda[0]);
            for j in 0..3 {
                let want = (u + j as f32 / 3.0).fract();
                let got = visible_cdf(w.lambda[j]);
                // Distance on the circle [0, 1).
                let d = (got - want).abs();
                assert!(d.min(1.0 - d) < 2e-4, "u {u} lane {j}: {got} vs {want}");
            }
            let wu = SampledWavelengths::sample_uniform(u);
            for j in 0..3 {
                let want = 360.0 + 470.0 * (u + j as f32 / 3.0).fract();
                let d = (wu.lambda[j] - want).abs();
                assert!(d.min(470.0 - d) < 1e-3, "{wu:?}");
                assert_eq!(wu.pdf[j], 1.0 / 470.0);
            }
        }
        // Lane pairs are not independent: they are always a third of the CDF apart, so pairs
        // (λ₀, λ₁) never both fall below the median.
        let med = sample_visible_wavelength(0.5);
        for i in 0..999 {
            let w = SampledWavelengths::sample_visible((i as f32 + 0.5) / 999.0);
            assert!(!(w.lambda[0] < med && w.lambda[1] < med && w.lambda[2] < med));
        }
    }

    /// ∫ over [a, b] (integers, nm) of the linearly interpolated CMFs (trapezoid = exact).
    fn cmf_integral(a: u32, b: u32) -> [f64; 3] {
        let mut s = [0.0f64; 3];
        for l in a..b {
            let (c0, c1) = (cie_xyz(l as f32), cie_xyz(l as f32 + 1.0));
            for k in 0..3 {
                s[k] += 0.5 * (c0[k] + c1[k]) as f64;
            }
        }
        s
    }

    #[test]
    fn spectral_white_furnace_per_bin() {
        // Jittered u (what a stratified sampler gives), constant spectrum 1: the estimator
        // restricted to 20 nm bins equals ∫_bin c̄ dλ / ∫ ȳ dλ within 1 % in every bin and
        // every channel that has mass there, for both samplers.
        let n = 200_000;
        let mut rng = Pcg32::new(22, 3);
        let edges: Vec<u32> = (360..=820).step_by(20).chain([830]).collect();
        for sampler in [
            SampledWavelengths::sample_visible as fn(f32) -> SampledWavelengths,
            SampledWavelengths::sample_uniform,
        ] {
            let mut est = vec![[0.0f64; 3]; edges.len() - 1];
            let mut total = [0.0f64; 3];
            for i in 0..n {
                let w = sampler((i as f32 + rng.next_f32()) / n as f32);
                for j in 0..3 {
                    // Lane j alone: the estimator of a spectrum that is 1 in lane j only.
                    let mut s = Spectrum::ZERO;
                    s.c[j] = 1.0;
                    let xyz = w.to_xyz(s);
                    let b = edges.partition_point(|&e| e as f32 <= w.lambda[j]) - 1;
                    let b = b.min(est.len() - 1);
                    for k in 0..3 {
                        est[b][k] += xyz[k] as f64 / n as f64;
                        total[k] += xyz[k] as f64 / n as f64;
                    }
                }
            }
            let y = CIE_Y_INTEGRAL as f64;
            for (b, e) in est.iter().enumerate() {
                let want = cmf_integral(edges[b], edges[b + 1]).map(|v| v / y);
                for k in 0..3 {
                    if want[k] < 1e-7 {
                        assert!(e[k].abs() < 1e-6, "bin {b} ch {k}: {} vs 0", e[k]);
                        continue;
                    }
                    let r = e[k] / want[k];
                    assert!(
                        (r - 1.0).abs() < 0.01,
                        "bin {}..{} ch {k}: {} vs {} (ratio {r})",
                        edges[b],
                        edges[b + 1],
                        e[k],
                        want[k]
                    );
                }
            }
            // The whole: illuminant E, XYZ = (∫x̄, ∫ȳ, ∫z̄)/∫ȳ ≈ (1.0000, 1, 1.0000).
            let want = cmf_integral(360, 830).map(|v| v / y);
            for k in 0..3 {
                assert!(
                    (total[k] / want[k] - 1.0).abs() < 1e-3,
                    "{total:?} vs {want:?}"
                );
            }
        }
    }

    /// Mean and standard error of `to_xyz(1)` over `n` independent hero draws.
    fn furnace(n: usize, seed: u64, terminate: bool) -> ([f64; 3], [f64; 3]) {
        let mut rng = Pcg32::new(seed, 4);
        let (mut s, mut s2) = ([0.0f64; 3], [0.0f64; 3]);
        for _ in 0..n {
            let mut w = SampledWavelengths::sample_visible(rng.next_f32());
            if terminate {
                w.terminate_secondary();
                assert!(w.secondary_terminated());
            }
            let xyz = w.to_xyz(Spectrum::ONE);
            for k in 0..3 {
                s[k] += xyz[k] as f64;
                s2[k] += (xyz[k] as f64).powi(2);
            }
        }
        let n = n as f64;
        let mean = s.map(|v| v / n);
        let se = [0, 1, 2].map(|k| ((s2[k] / n - mean[k] * mean[k]) / n).sqrt());
        (mean, se)
    }

    #[test]
    fn white_furnace_and_termination_keep_the_mean() {
        let want = cmf_integral(360, 830).map(|v| v / CIE_Y_INTEGRAL as f64);
        for terminate in [false, true] {
            let (mean, se) = furnace(200_000, 7, terminate);
            for k in 0..3 {
                let err = mean[k] - want[k];
                assert!(
                    (err / want[k]).abs() < 0.01 && err.abs() < 4.0 * se[k],
                    "terminate {terminate} ch {k}: {mean:?} ± {se:?} vs {want:?}"
                );
            }
        }
        // Termination: lane 0 keeps a third of its density, the others are skipped.
        let mut w = SampledWavelengths::sample_visible(0.3);
        let p0 = w.pdf[0];
        assert!(!w.secondary_terminated());
        w.terminate_secondary();
        w.terminate_secondary(); // idempotent
        assert_eq!(w.pdf, [p0 / 3.0, 0.0, 0.0]);
        // Values in terminated lanes are ignored.
        let a = w.to_xyz(Spectrum::new(1.0, 5.0, 7.0));
        let b = w.to_xyz(Spectrum::new(1.0, 0.0, 0.0));
        assert_eq!(a, b);
        // The 1/3 matters: dividing pdf[0] by anything else biases the mean by that factor,
        // so a wrong factor is caught by the 1 % bound above (3 vs 2 is a 50 % error).
        assert!(w.to_xyz(Spectrum::ONE)[1] > 0.0);
    }

    #[test]
    fn srgb_of_white_is_the_colour_of_illuminant_e() {
        // Constant spectrum 1 (illuminant E) through the film conversion: linear sRGB of E's
        // XYZ, averaged over jittered hero draws.
        let n = 50_000;
        let mut acc = [0.0f64; 3];
        for i in 0..n {
            let w = SampledWavelengths::sample_visible((i as f32 + 0.5) / n as f32);
            let rgb = w.to_linear_srgb(Spectrum::ONE);
            for k in 0..3 {
                acc[k] += rgb[k] as f64 / n as f64;
            }
        }
        let e = cmf_integral(360, 830).map(|v| (v / CIE_Y_INTEGRAL as f64) as f32);
        let want = xyz_to_linear_srgb(e);
        for k in 0..3 {
            assert!(
                (acc[k] as f32 - want[k]).abs() < 2e-3,
                "{acc:?} vs {want:?}"
            );
        }
        // E (correlated colour temperature ~5450 K) is warmer than D65: R > G > B.
        assert!(want[0] > want[1] && want[1] > want[2], "{want:?}");
    }

    /// Per-sample variance of the film's estimate (linear sRGB, summed over channels) for a few
    /// spectra, visible density against uniform (run with `--ignored --nocapture`).
    #[test]
    #[ignore]
    fn measure_sampling_variance() {
        use crate::spectral::upsample::RgbReflectance;
        let red = RgbReflectance::new([0.8, 0.1, 0.05]);
        let blue = RgbReflectance::new([0.05, 0.1, 0.8]);
        let d65n = crate::spectral::cie::d65_n;
        let spectra: [(&str, &dyn Fn(f32) -> f32); 4] = [
            ("E (constant 1)", &|_| 1.0),
            ("D65_n", &d65n),
            ("red reflectance x D65_n", &|l| red.eval(l) * d65n(l)),
            ("blue reflectance x D65_n", &|l| blue.eval(l) * d65n(l)),
        ];
        let n = 400_000;
        for (name, f) in spectra {
            let mut out = vec![];
            for sampler in [
                SampledWavelengths::sample_visible as fn(f32) -> SampledWavelengths,
                SampledWavelengths::sample_uniform,
            ] {
                let mut rng = Pcg32::new(22, 5);
                let (mut s, mut s2) = ([0.0f64; 3], [0.0f64; 3]);
                for _ in 0..n {
                    let w = sampler(rng.next_f32());
                    let v = w.to_linear_srgb(Spectrum::from_rgb(w.lambda.map(f)));
                    for k in 0..3 {
                        s[k] += v[k] as f64;
                        s2[k] += (v[k] as f64).powi(2);
                    }
                }
                let var: f64 = (0..3)
                    .map(|k| s2[k] / n as f64 - (s[k] / n as f64).powi(2))
                    .sum();
                out.push(var);
            }
            eprintln!(
                "{name}: variance per sample, visible {:.4}, uniform {:.4} (ratio {:.2})",
                out[0],
                out[1],
                out[1] / out[0]
            );
        }
    }

    #[test]
    fn deterministic_bits() {
        for u in [0.0, 0.1, 0.5, 0.999, ONE_MINUS_EPSILON, 1.0] {
            let a = SampledWavelengths::sample_visible(u);
            let b = SampledWavelengths::sample_visible(u);
            assert_eq!(a.lambda.map(f32::to_bits), b.lambda.map(f32::to_bits));
            assert!(a.lambda.iter().all(|l| (360.0..=830.0).contains(l)));
            assert!(a.pdf.iter().all(|&p| p > 0.0));
        }
    }
}
