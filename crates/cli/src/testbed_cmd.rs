//! `caustica testbed`: every density estimator on 2-D photon distributions with a closed-form
//! density (Schjøth 2009 fig. 4.4–4.5). Writes per distribution the exact density image, the
//! estimate images of fig. 4.5's rows, `results.csv` (every run) and `README.md` (the fig. 4.5
//! MISE table and each estimator's best).

use anyhow::{Context, Result, bail};
use caustica_core::image_io::Image;
use caustica_eval::density_study::{Run, SuiteConfig, best, suite};
use caustica_eval::testbed::Distribution;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct TestbedArgs {
    /// Distribution: rectangle, disc, ring, line, ridges, gradient, edge, composite (fig. 4.4),
    /// or all.
    #[arg(long, default_value = "composite")]
    pub distribution: String,
    /// Samples (photons) per realisation.
    #[arg(long, default_value_t = caustica_eval::testbed::PAPER_SAMPLES)]
    pub samples: usize,
    /// Image side in pixels (the thin line is one pixel wide at 256).
    #[arg(long, default_value_t = caustica_eval::testbed::DEFAULT_RESOLUTION)]
    pub size: usize,
    /// Seed of the first realisation (realisation r uses seed + r).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Independent sample sets the MISE is averaged over.
    #[arg(long, default_value_t = 2)]
    pub realisations: usize,
    /// Output directory (created if missing).
    #[arg(short, long, default_value = "testbed")]
    pub output: PathBuf,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// Fig. 4.5's rows: k-NN k, and the diffusivity q of both diffusion variants.
const FIG45_K: [usize; 4] = [1200, 600, 300, 150];
const FIG45_Q: [f64; 4] = [0.8, 0.4, 0.2, 0.1];

pub fn run(args: TestbedArgs) -> Result<()> {
    let dists: Vec<Distribution> = if args.distribution == "all" {
        Distribution::ALL.to_vec()
    } else {
        vec![
            Distribution::from_name(&args.distribution).with_context(|| {
                let names: Vec<&str> = Distribution::ALL.iter().map(|d| d.name()).collect();
                format!(
                    "unknown distribution '{}': expected one of {} or all",
                    args.distribution,
                    names.join(", ")
                )
            })?,
        ]
    };
    if args.samples == 0 {
        bail!("--samples must be at least 1");
    }
    if !(16..=4096).contains(&args.size) {
        bail!(
            "--size must be between 16 and 4096 pixels, got {}",
            args.size
        );
    }
    if args.realisations == 0 {
        bail!("--realisations must be at least 1");
    }
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("creating {}", args.output.display()))?;
    let mut csv = String::from(
        "distribution,estimator,parameter,bandwidth,mise,relative_mise,ssim,mass,line_ratio,seconds,prepass_seconds\n",
    );
    let mut readme = String::new();
    let _ = writeln!(
        readme,
        "# Density estimators on the 2-D testbed (Schjøth 2009 fig. 4.4–4.5)\n\n\
         Regenerate: `caustica testbed --distribution {} --samples {} --size {} --seed {} --realisations {} -o DIR` \
         (release build). MISE = ∫(f̂ − f)² over the unit square (densities in 1/area, f integrates to 1), \
         averaged over {} realisations; SSIM on densities divided by the true peak; line = mean estimate \
         on the one-pixel line / its true density. Epanechnikov kernel throughout; diffusion: noise \
         scale h/2, α = 1, λ₁ normalised by its maximum over the photons.\n",
        args.distribution, args.samples, args.size, args.seed, args.realisations, args.realisations
    );
    for dist in dists {
        let mut cfg = SuiteConfig::fig45(dist);
        cfg.samples = args.samples;
        cfg.size = args.size;
        cfg.seed = args.seed;
        cfg.realisations = args.realisations;
        for k in FIG45_K {
            if !cfg.knn_k.contains(&k) {
                cfg.knn_k.push(k);
            }
        }
        let total =
            cfg.knn_k.len() + cfg.variable_k.len() + cfg.bandwidths.len() * (1 + 2 * cfg.q.len());
        let bar = if args.quiet {
            ProgressBar::hidden()
        } else {
            ProgressBar::new(total as u64)
        };
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} ETA {eta} {msg}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar.set_message(dist.name());
        let runs = suite(&cfg, &|r: &Run| {
            bar.set_message(format!("{} {}", dist.name(), label(r)));
            bar.inc(1);
        });
        bar.finish_and_clear();
        let dir = args.output.join(dist.name());
        std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        let exact = dist.density_image(cfg.size, cfg.size);
        let peak = exact.iter().copied().fold(0.0, f64::max);
        write_density_png(&exact, cfg.size, peak, &dir.join("exact.png"))?;
        for r in &runs {
            let _ = writeln!(
                csv,
                "{},{},{},{},{:.6e},{:.6e},{:.6},{:.5},{},{:.4},{:.4}",
                dist.name(),
                r.estimator,
                num(r.parameter),
                num(r.bandwidth),
                r.mise,
                r.relative_mise,
                r.ssim,
                r.mass,
                r.line_ratio.map_or(String::new(), |l| format!("{l:.4}")),
                r.seconds,
                r.prepass_seconds
            );
        }
        let _ = write!(readme, "{}", report(dist, &runs, &dir, peak, cfg.size)?);
        let knn = best(&runs, "knn", None);
        let dpm = best(&runs, "diffusion", None);
        if let (Some(k), Some(d)) = (knn, dpm) {
            println!(
                "{}: best knn {} MISE {:.4e}; best dpm {} MISE {:.4e} ({:.2}x); line peak knn {} dpm {}",
                dist.name(),
                label(k),
                k.mise,
                label(d),
                d.mise,
                d.mise / k.mise,
                k.line_ratio.map_or("-".into(), |l| format!("{l:.3}")),
                d.line_ratio.map_or("-".into(), |l| format!("{l:.3}")),
            );
        }
    }
    let csv_path = args.output.join("results.csv");
    std::fs::write(&csv_path, csv).with_context(|| format!("writing {}", csv_path.display()))?;
    let md = args.output.join("README.md");
    std::fs::write(&md, readme).with_context(|| format!("writing {}", md.display()))?;
    println!("testbed: wrote {} and {}", csv_path.display(), md.display());
    Ok(())
}

/// A parameter for tables: the suite's values are f32, printed as such (0.016, not
/// 0.01600000075995922); empty for NaN.
fn num(v: f64) -> String {
    if v.is_nan() {
        String::new()
    } else {
        format!("{}", v as f32)
    }
}

fn label(r: &Run) -> String {
    match r.estimator {
        "knn" | "variable" => format!("{} k={}", r.estimator, num(r.parameter)),
        "fixed" => format!("fixed h={}", num(r.bandwidth)),
        _ => format!(
            "{} h={} q={}",
            r.estimator,
            num(r.bandwidth),
            num(r.parameter)
        ),
    }
}

/// The density image as grey PNG: linear value = density / `peak`, clipped to [0, 1].
fn write_density_png(img: &[f64], size: usize, peak: f64, path: &Path) -> Result<()> {
    let mut out = Image::new(size, size);
    for j in 0..size {
        for i in 0..size {
            let v = (img[j * size + i] / peak.max(1e-300)).clamp(0.0, 1.0) as f32;
            out.set(i, j, [v; 3]);
        }
    }
    out.write_png(path, 0.0)
        .with_context(|| format!("writing {}", path.display()))
}

/// The distribution's section of README.md: fig. 4.5 as a table with images, and the best run
/// of every estimator.
fn report(dist: Distribution, runs: &[Run], dir: &Path, peak: f64, size: usize) -> Result<String> {
    let name = dist.name();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\n## {name}\n\n![exact]({name}/exact.png) exact density\n"
    );
    let _ = writeln!(
        s,
        "| fig. 4.5 row | setting | MISE | rel. MISE | SSIM | line | image |\n|---|---|---|---|---|---|---|"
    );
    let mut row = |title: &str, r: &Run, file: String| -> Result<()> {
        write_density_png(&r.image, size, peak, &dir.join(&file))?;
        let _ = writeln!(
            s,
            "| {title} | {} | {:.4e} | {:.4} | {:.4} | {} | ![]({name}/{file}) |",
            label(r),
            r.mise,
            r.relative_mise,
            r.ssim,
            r.line_ratio.map_or("–".into(), |l| format!("{l:.3}")),
        );
        Ok(())
    };
    for k in FIG45_K {
        if let Some(r) = best(runs, "knn", Some(k as f64)) {
            row("k-NN (a–d)", r, format!("knn-k{k}.png"))?;
        }
    }
    for (title, est) in [
        ("anisotropic DPM (e–h)", "diffusion"),
        ("isotropic DPM (i–l)", "isotropic-diffusion"),
    ] {
        for q in FIG45_Q {
            // The thesis' q values are stored as f32 in the suite.
            if let Some(r) = best(runs, est, Some(q as f32 as f64)) {
                row(title, r, format!("{est}-q{q}.png"))?;
            }
        }
    }
    let _ = writeln!(
        s,
        "\nBest of each estimator (smallest MISE over its parameters; diffusion over h and q):\n\n\
         | estimator | setting | MISE | SSIM | line | estimate s | pre-pass s |\n|---|---|---|---|---|---|---|"
    );
    for est in [
        "knn",
        "fixed",
        "variable",
        "diffusion",
        "isotropic-diffusion",
    ] {
        if let Some(r) = best(runs, est, None) {
            let _ = writeln!(
                s,
                "| {est} | {} | {:.4e} | {:.4} | {} | {:.2} | {:.2} |",
                label(r),
                r.mise,
                r.ssim,
                r.line_ratio.map_or("–".into(), |l| format!("{l:.3}")),
                r.seconds,
                r.prepass_seconds
            );
        }
    }
    if let (Some(k), Some(d)) = (best(runs, "knn", None), best(runs, "diffusion", None)) {
        let _ = writeln!(
            s,
            "\nAnisotropic DPM at its best ({}) has {:.2}× the MISE of the best k-NN ({}).",
            label(d),
            d.mise / k.mise,
            label(k)
        );
        if let (Some(lk), Some(ld)) = (k.line_ratio, d.line_ratio) {
            let _ = writeln!(
                s,
                "Thin-line peak kept: {:.1} % (DPM) vs {:.1} % (k-NN), ratio {:.2}.",
                100.0 * ld,
                100.0 * lk,
                ld / lk
            );
        }
    }
    Ok(s)
}
