//! Density estimators judged on the 2-D [`testbed`](crate::testbed): each estimator's density
//! image of a sampled [`Distribution`], its integrated squared error against the exact density,
//! SSIM, and how well it keeps the thin line's peak (seed 000 sec. 4.3, fig. 4.5).
//!
//! The suite ([`suite`]) follows the thesis' procedure: k-NN with k = 1200/600/300/150 (fig.
//! 4.5a–d) and more k to find its best; the fixed-bandwidth estimate over a range of h (this is
//! the diffusion estimate with a large q, the thesis' way of choosing the bandwidth); and the
//! anisotropic and isotropic diffusion estimates with q = 0.8/0.4/0.2/0.1 (fig. 4.5e–l) at every
//! h of that range, reported at the h that is best for each q. The diffusion pre-pass depends
//! on h alone, so it runs once per h and is shared by every q and by both variants.

use crate::ssim::mean_ssim;
use crate::testbed::{Distribution, ise, relative_ise};
use caustica_core::Vec3;
use caustica_density::diffusion::{DiffusionEstimator, DiffusionParams};
use caustica_density::estimator::{Estimator, EstimatorSpec, Query, Scratch, WeightedPoints};
use caustica_density::kernel::Kernel;
use rayon::prelude::*;
use std::time::Instant;

/// The estimate at the centres of a `size`×`size` image of the unit square (row 0 at the top,
/// the layout of [`Distribution::density_image`]); probability density (1/area).
pub fn estimate_image(est: &Estimator, points: &WeightedPoints, size: usize) -> Vec<f64> {
    (0..size)
        .into_par_iter()
        .flat_map_iter(|j| {
            let mut scratch = Scratch::default();
            let y = 1.0 - (j as f32 + 0.5) / size as f32;
            (0..size)
                .map(|i| {
                    let x = (i as f32 + 0.5) / size as f32;
                    let q = Query::new(Vec3::new(x, y, 0.0), Vec3::Z);
                    est.density(points, &q, &mut scratch) as f64
                })
                .collect::<Vec<_>>()
        })
        .collect()
}

/// Pixels of one-pixel-wide structures of the exact image: non-zero pixels whose left and right
/// neighbours are zero (the thin line).
pub fn line_pixels(exact: &[f64], size: usize) -> Vec<usize> {
    let mut out = Vec::new();
    for j in 0..size {
        for i in 1..size.saturating_sub(1) {
            let k = j * size + i;
            if exact[k] > 0.0 && exact[k - 1] == 0.0 && exact[k + 1] == 0.0 {
                out.push(k);
            }
        }
    }
    out
}

/// SSIM of an estimate against the exact density, both divided by the exact density's maximum
/// (so the display range of the ground truth is [0, 1], the range SSIM's constants assume).
pub fn density_ssim(estimate: &[f64], exact: &[f64], size: usize) -> f64 {
    let peak = exact.iter().copied().fold(0.0, f64::max).max(1e-300);
    let a: Vec<f64> = estimate.iter().map(|v| v / peak).collect();
    let b: Vec<f64> = exact.iter().map(|v| v / peak).collect();
    mean_ssim(&a, &b, size, size, |_, _| true).unwrap_or(f64::NAN)
}

/// One estimator's result on the testbed.
#[derive(Clone, Debug)]
pub struct Run {
    /// Estimator family: knn, fixed, variable, diffusion, isotropic-diffusion.
    pub estimator: &'static str,
    /// k for knn/variable, else q (NaN for fixed).
    pub parameter: f64,
    /// Bandwidth h (NaN for knn/variable).
    pub bandwidth: f64,
    /// Integrated squared error ∫(f̂ − f)², averaged over the realisations (the MISE).
    pub mise: f64,
    /// MISE / ∫f².
    pub relative_mise: f64,
    /// Mean SSIM against the exact density (first realisation).
    pub ssim: f64,
    /// ∫f̂ over the unit square (first realisation): 1 when the estimate keeps the total
    /// mass; kernels whose shape varies with the query (k-NN, diffusion) need not.
    pub mass: f64,
    /// Mean estimate over the thin line's pixels / its true density (1 = peak kept); `None`
    /// when the distribution has no thin line.
    pub line_ratio: Option<f64>,
    /// Seconds for the estimate image (excluding any pre-pass), first realisation.
    pub seconds: f64,
    /// Seconds of the pre-pass (pilot bandwidths or diffusion gradients), first realisation.
    pub prepass_seconds: f64,
    /// The image of the first realisation.
    pub image: Vec<f64>,
}

/// What [`suite`] computes.
#[derive(Clone, Debug)]
pub struct SuiteConfig {
    pub distribution: Distribution,
    /// Samples per realisation (48 000 in the thesis).
    pub samples: usize,
    /// Image side (pixels).
    pub size: usize,
    pub seed: u64,
    /// Independent sample sets the errors are averaged over.
    pub realisations: usize,
    pub knn_k: Vec<usize>,
    pub variable_k: Vec<usize>,
    pub bandwidths: Vec<f32>,
    pub q: Vec<f32>,
    /// Steepness of eq. 4.15 (1 in the thesis).
    pub alpha: f32,
}

impl SuiteConfig {
    /// The fig. 4.5 suite on `distribution` with the thesis' sample count.
    pub fn fig45(distribution: Distribution) -> Self {
        Self {
            distribution,
            samples: crate::testbed::PAPER_SAMPLES,
            size: crate::testbed::DEFAULT_RESOLUTION,
            seed: 1,
            realisations: 2,
            knn_k: vec![25, 50, 100, 150, 200, 300, 600, 1200],
            variable_k: vec![25, 50, 100, 200, 400],
            bandwidths: vec![0.006, 0.008, 0.011, 0.016, 0.022, 0.032, 0.045, 0.064, 0.09],
            q: vec![0.8, 0.4, 0.2, 0.1, 0.05],
            alpha: 1.0,
        }
    }
}

/// Runs every estimator of `cfg` (see the [module docs](self)); `progress` receives a line per
/// finished estimator.
pub fn suite(cfg: &SuiteConfig, progress: &(dyn Fn(&Run) + Sync)) -> Vec<Run> {
    let exact = cfg.distribution.density_image(cfg.size, cfg.size);
    let line = line_pixels(&exact, cfg.size);
    let line_truth =
        (!line.is_empty()).then(|| line.iter().map(|&k| exact[k]).sum::<f64>() / line.len() as f64);
    let sets: Vec<WeightedPoints> = (0..cfg.realisations.max(1))
        .map(|r| {
            WeightedPoints::planar(
                &cfg.distribution
                    .sample(cfg.samples, cfg.seed.wrapping_add(r as u64)),
            )
        })
        .collect();
    let kernel = Kernel::Epanechnikov;
    let mut runs = Vec::new();
    // Evaluates prepared estimators (one per realisation) into a Run.
    let mut finish = |estimator: &'static str,
                      parameter: f64,
                      bandwidth: f64,
                      ests: &[Estimator],
                      prepass_seconds: f64| {
        let mut mise = 0.0;
        let mut rel = 0.0;
        let mut first = None;
        let mut seconds = 0.0;
        for (r, (est, pts)) in ests.iter().zip(&sets).enumerate() {
            let t = Instant::now();
            let img = estimate_image(est, pts, cfg.size);
            if r == 0 {
                seconds = t.elapsed().as_secs_f64();
            }
            mise += ise(&img, &exact) / ests.len() as f64;
            rel += relative_ise(&img, &exact) / ests.len() as f64;
            if first.is_none() {
                first = Some(img);
            }
        }
        let image = first.unwrap_or_default();
        let run = Run {
            estimator,
            parameter,
            bandwidth,
            mise,
            relative_mise: rel,
            ssim: density_ssim(&image, &exact, cfg.size),
            mass: image.iter().sum::<f64>() / image.len().max(1) as f64,
            line_ratio: line_truth
                .map(|t| line.iter().map(|&k| image[k]).sum::<f64>() / line.len() as f64 / t),
            seconds,
            prepass_seconds,
            image,
        };
        progress(&run);
        runs.push(run);
    };
    let timed = |f: &dyn Fn(&WeightedPoints) -> Estimator| {
        let mut secs = 0.0;
        let ests: Vec<Estimator> = sets
            .iter()
            .enumerate()
            .map(|(r, p)| {
                let t = Instant::now();
                let e = f(p);
                if r == 0 {
                    secs = t.elapsed().as_secs_f64();
                }
                e
            })
            .collect();
        (ests, secs)
    };
    for &k in &cfg.knn_k {
        let spec = EstimatorSpec::Knn {
            k,
            max_radius: None,
            kernel,
        };
        let (ests, s) = timed(&|p| Estimator::prepare(&spec, p));
        finish("knn", k as f64, f64::NAN, &ests, s);
    }
    for &k in &cfg.variable_k {
        let spec = EstimatorSpec::Variable {
            k,
            max_radius: None,
            kernel,
        };
        let (ests, s) = timed(&|p| Estimator::prepare(&spec, p));
        finish("variable", k as f64, f64::NAN, &ests, s);
    }
    for &h in &cfg.bandwidths {
        let spec = EstimatorSpec::Fixed { h, kernel };
        let (ests, s) = timed(&|p| Estimator::prepare(&spec, p));
        finish("fixed", f64::NAN, h as f64, &ests, s);
        // One diffusion pre-pass per h, shared by every q and both variants.
        let mut params = DiffusionParams::new(h);
        params.alpha = cfg.alpha;
        let (base, s) = timed(&|p| Estimator::Diffusion(DiffusionEstimator::new(p, params)));
        for isotropic in [false, true] {
            for &q in &cfg.q {
                let ests: Vec<Estimator> = base
                    .iter()
                    .map(|e| match e {
                        Estimator::Diffusion(d) => {
                            Estimator::Diffusion(d.with_diffusivity(q, cfg.alpha, isotropic))
                        }
                        other => other.clone(),
                    })
                    .collect();
                let name = if isotropic {
                    "isotropic-diffusion"
                } else {
                    "diffusion"
                };
                finish(name, q as f64, h as f64, &ests, s);
            }
        }
    }
    runs
}

/// The run with the smallest MISE among those with `estimator` (and, if given, `parameter`).
pub fn best<'a>(runs: &'a [Run], estimator: &str, parameter: Option<f64>) -> Option<&'a Run> {
    runs.iter()
        .filter(|r| r.estimator == estimator && parameter.is_none_or(|p| r.parameter == p))
        .min_by(|a, b| a.mise.total_cmp(&b.mise))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_pixels_find_the_thin_line() {
        let d = Distribution::Line;
        let exact = d.density_image(256, 256);
        let line = line_pixels(&exact, 256);
        assert!(!line.is_empty());
        assert!(line.iter().all(|k| k % 256 == 140));
        assert!(line_pixels(&Distribution::Disc.density_image(256, 256), 256).is_empty());
    }

    #[test]
    fn exact_image_has_zero_error_and_ssim_one() {
        let exact = Distribution::Composite.density_image(64, 64);
        assert_eq!(ise(&exact, &exact), 0.0);
        assert!((density_ssim(&exact, &exact, 64) - 1.0).abs() < 1e-12);
    }

    /// The acceptance test of issue 6 on a reduced suite (fewer parameters, one realisation):
    /// anisotropic diffusion at its best q beats the best k-NN in MISE, and keeps the thin
    /// line's peak better than the k-NN estimate of the same MISE rank.
    #[test]
    fn diffusion_beats_knn_on_the_composite() {
        let mut cfg = SuiteConfig::fig45(Distribution::Composite);
        cfg.realisations = 1;
        cfg.knn_k = vec![50, 100, 150, 300];
        cfg.variable_k = vec![];
        cfg.bandwidths = vec![0.011, 0.016, 0.022];
        cfg.q = vec![0.4, 0.2, 0.1];
        let runs = suite(&cfg, &|_| {});
        let knn = best(&runs, "knn", None).unwrap();
        let dpm = best(&runs, "diffusion", None).unwrap();
        assert!(
            dpm.mise < knn.mise,
            "dpm {} (h {}, q {}) vs knn {} (k {})",
            dpm.mise,
            dpm.bandwidth,
            dpm.parameter,
            knn.mise,
            knn.parameter
        );
        let (l_dpm, l_knn) = (dpm.line_ratio.unwrap(), knn.line_ratio.unwrap());
        assert!(l_dpm > l_knn, "line ratio dpm {l_dpm} vs knn {l_knn}");
    }
}
