//! `caustica sweep SCENE --param NAME --values A,B,C --reference REF`: the scene rendered once
//! per value of one render option, each image compared with a reference (the metrics of
//! `caustica compare`), written as a CSV table, the images and a plot of RMSE and SSIM against
//! the value (seed 000 figs. 6.6–6.7).

use crate::compare_cmd::{self, MetricArgs};
use crate::render_cmd::{RenderSettings, Resolved};
use anyhow::{Context, Result, bail};
use caustica_eval::metrics::CompareOptions;
use caustica_eval::plot::{self, SweepPlot, SweepPoint, format_number};
use caustica_eval::{EvalError, compare};
use caustica_render::{Film, Progress, RenderControl, render};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::fmt::{Display, Write as _};
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

#[derive(Args)]
pub struct SweepArgs {
    #[command(flatten)]
    pub render: RenderSettings,
    /// The render option to vary, by its long name: spp, seed, max-depth, sampler, time,
    /// integrator, photons, global-photons, k, global-k, max-radius, kernel, final-gather,
    /// tangent-projection, disc-test, caustics-only, estimator, bandwidth, q, alpha,
    /// noise-scale, isotropic, smoothing, normal-distance, min-footprint, no-auto-bandwidth, volume-only,
    /// volume-photons, volume-k, volume-radius, march-step, volume-smoothing, min-semi-axis, volume-boundary or
    /// spread-collimated.
    #[arg(long, value_name = "NAME")]
    pub param: String,
    /// The values of the parameter, comma-separated (e.g. 10,50,200 or uniform,cone:1.1);
    /// one render each, in this order.
    #[arg(long, value_name = "A,B,C", allow_hyphen_values = true)]
    pub values: String,
    /// Reference image (.exr, .pfm or .png) of the scene's size.
    #[arg(long, value_name = "REF")]
    pub reference: PathBuf,
    #[command(flatten)]
    pub metric: MetricArgs,
    /// Output directory, created if missing (default: sweep-NAME). Receives sweep.csv,
    /// NAME-VALUE.exr per value (and .png with --png), sweep.svg and sweep.png.
    #[arg(short, long, value_name = "OUTDIR")]
    pub output: Option<PathBuf>,
    /// Also write NAME-VALUE.png beside each EXR (sRGB, at the metrics' --exposure).
    #[arg(long)]
    pub png: bool,
    /// No progress bar and no per-render notes.
    #[arg(long, short)]
    pub quiet: bool,
}

/// A render option a sweep sets from the text of a value.
trait Slot {
    /// Sets the option to `text` parsed; the error says why it does not parse.
    fn set(&mut self, text: &str) -> Result<(), String>;
    /// Whether the command line gave the option already (plain values with a default, such as
    /// the seed, cannot tell and say no).
    fn given(&self) -> bool;
}

impl<T: FromStr> Slot for Option<T>
where
    T::Err: Display,
{
    fn set(&mut self, text: &str) -> Result<(), String> {
        *self = Some(text.parse().map_err(|e: T::Err| e.to_string())?);
        Ok(())
    }
    fn given(&self) -> bool {
        self.is_some()
    }
}

impl Slot for u64 {
    fn set(&mut self, text: &str) -> Result<(), String> {
        *self = text.parse().map_err(|e| format!("{e}"))?;
        Ok(())
    }
    fn given(&self) -> bool {
        false
    }
}

impl Slot for String {
    fn set(&mut self, text: &str) -> Result<(), String> {
        text.clone_into(self);
        Ok(())
    }
    fn given(&self) -> bool {
        false
    }
}

impl Slot for bool {
    fn set(&mut self, text: &str) -> Result<(), String> {
        *self = match text {
            "true" | "on" | "yes" => true,
            "false" | "off" | "no" => false,
            _ => return Err("expected true or false".into()),
        };
        Ok(())
    }
    fn given(&self) -> bool {
        *self
    }
}

/// Where a parameter lives in the render settings.
type Field = for<'a> fn(&'a mut RenderSettings) -> &'a mut dyn Slot;

/// The render options a sweep can vary, by long option name. Adding one is one line here (and
/// its name in the `--param` help above).
const PARAMETERS: &[(&str, Field)] = &[
    ("spp", |s| &mut s.spp),
    ("seed", |s| &mut s.seed),
    ("max-depth", |s| &mut s.max_depth),
    ("sampler", |s| &mut s.sampler),
    ("time", |s| &mut s.time),
    ("integrator", |s| &mut s.integrator),
    ("photons", |s| &mut s.photon.photons),
    ("global-photons", |s| &mut s.photon.global_photons),
    ("k", |s| &mut s.photon.k),
    ("global-k", |s| &mut s.photon.global_k),
    ("max-radius", |s| &mut s.photon.max_radius),
    ("kernel", |s| &mut s.photon.kernel),
    ("final-gather", |s| &mut s.photon.final_gather),
    ("tangent-projection", |s| &mut s.photon.tangent_projection),
    ("disc-test", |s| &mut s.photon.disc_test),
    ("caustics-only", |s| &mut s.caustics_only),
    ("estimator", |s| &mut s.photon.estimator),
    ("bandwidth", |s| &mut s.photon.bandwidth),
    ("q", |s| &mut s.photon.q),
    ("alpha", |s| &mut s.photon.alpha),
    ("noise-scale", |s| &mut s.photon.noise_scale),
    ("isotropic", |s| &mut s.photon.isotropic),
    ("smoothing", |s| &mut s.photon.smoothing),
    ("normal-distance", |s| &mut s.photon.normal_distance),
    ("min-footprint", |s| &mut s.photon.min_footprint),
    ("no-auto-bandwidth", |s| &mut s.photon.no_auto_bandwidth),
    ("volume-only", |s| &mut s.volume_only),
    ("volume-photons", |s| &mut s.photon.volume_photons),
    ("volume-k", |s| &mut s.photon.volume_k),
    ("volume-radius", |s| &mut s.photon.volume_radius),
    ("march-step", |s| &mut s.photon.march_step),
    ("volume-smoothing", |s| &mut s.photon.volume_smoothing),
    ("min-semi-axis", |s| &mut s.photon.min_semi_axis),
    ("volume-boundary", |s| &mut s.photon.volume_boundary),
    ("spread-collimated", |s| &mut s.photon.spread_collimated),
];

/// The setter of parameter `name` (a long option name, with or without the leading `--`).
fn parameter(name: &str) -> Result<(&'static str, Field)> {
    let bare = name.strip_prefix("--").unwrap_or(name);
    PARAMETERS
        .iter()
        .find(|(n, _)| *n == bare)
        .copied()
        .with_context(|| {
            let names: Vec<&str> = PARAMETERS.iter().map(|(n, _)| *n).collect();
            format!(
                "--param {name:?} is not a parameter a sweep can vary; valid: {}",
                names.join(", ")
            )
        })
}

/// Splits `--values` into its items: none empty, no repeats.
fn parse_values(text: &str) -> Result<Vec<String>> {
    if text.trim().is_empty() {
        bail!("--values is empty: give a comma-separated list, e.g. --values 1,4,16");
    }
    let values: Vec<String> = text.split(',').map(|v| v.trim().to_string()).collect();
    for (i, v) in values.iter().enumerate() {
        if v.is_empty() {
            bail!(
                "--values {text:?}: value {} of {} is empty",
                i + 1,
                values.len()
            );
        }
        if values[..i].contains(v) {
            bail!("--values {text:?}: '{v}' is given twice");
        }
    }
    Ok(values)
}

/// File name stem of the image of one value: `NAME-VALUE`, with characters other than
/// letters, digits and `.+-` replaced by `_` (`kernel-cone_1.1`).
pub fn image_stem(param: &str, value: &str) -> String {
    let clean: String = value
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "._+-".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("{param}-{clean}")
}

/// The measurements of one render.
struct Row {
    value: String,
    rmse: f64,
    rel_mse: f64,
    mise: f64,
    ssim: Option<f64>,
    /// Wall-clock time of the render call (s).
    seconds: f64,
}

/// A CSV field, quoted when it must be.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn write_csv(path: &Path, rows: &[Row]) -> Result<()> {
    let mut text = String::from("value,rmse,rel_mse,mise,ssim,seconds\n");
    for r in rows {
        let ssim = r.ssim.map_or(String::new(), |s| s.to_string());
        let _ = writeln!(
            text,
            "{},{},{},{},{ssim},{:.4}",
            csv_field(&r.value),
            r.rmse,
            r.rel_mse,
            r.mise,
            r.seconds
        );
    }
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

pub fn run(args: SweepArgs) -> Result<()> {
    let (name, field) = parameter(&args.param)?;
    if field(&mut args.render.clone()).given() {
        bail!(
            "--{name} is the swept parameter (--param {name}): give its values with --values only"
        );
    }
    let values = parse_values(&args.values)?;
    let stems: Vec<String> = values.iter().map(|v| image_stem(name, v)).collect();
    for (i, s) in stems.iter().enumerate() {
        if let Some(j) = stems[..i].iter().position(|t| t == s) {
            bail!(
                "--values '{}' and '{}' would both be written to {s}.exr",
                values[j],
                values[i]
            );
        }
    }
    let outdir = args
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("sweep-{name}")));

    args.render.start_threads()?;
    let reference = compare_cmd::read(&args.reference, "reference")?;
    let scene = args.render.load_scene()?;
    let (w, h) = (scene.camera.width as usize, scene.camera.height as usize);
    if (reference.width, reference.height) != (w, h) {
        return Err(anyhow::Error::new(EvalError::SizeMismatch {
            iw: w,
            ih: h,
            rw: reference.width,
            rh: reference.height,
        }))
        .with_context(|| {
            format!(
                "reference {} does not fit scene '{}', which renders {w}x{h} images",
                args.reference.display(),
                scene.name
            )
        });
    }
    let region = args.metric.region(w, h)?;

    // Every value is applied and checked before the first render, so a bad one fails at once.
    let mut runs: Vec<(String, Resolved)> = Vec::with_capacity(values.len());
    let mut warnings: Vec<String> = Vec::new();
    for v in &values {
        let mut settings = args.render.clone();
        field(&mut settings)
            .set(v)
            .map_err(|e| anyhow::anyhow!("--values: '{v}' is not a valid --param {name}: {e}"))?;
        if settings.spp.is_some() && settings.time.is_some() {
            bail!("--spp and --time exclude each other (--param {name}, value '{v}')");
        }
        let resolved = settings
            .resolve(&scene)
            .with_context(|| format!("--param {name} = '{v}'"))?;
        for w in &resolved.warnings {
            if !warnings.contains(w) {
                warnings.push(w.clone());
            }
        }
        runs.push((v.clone(), resolved));
    }
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    std::fs::create_dir_all(&outdir)
        .with_context(|| format!("cannot create the output directory {}", outdir.display()))?;
    let csv_path = outdir.join("sweep.csv");
    let options = CompareOptions {
        exposure: args.metric.exposure,
        ..CompareOptions::default()
    };

    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(runs.len() as u64 * 1000)
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% ETA {eta} {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let value_width = values.iter().map(|v| v.len()).chain([name.len()]).max();
    let vw = value_width.unwrap_or(8);
    println!(
        "{name:>vw$}  {:>11}  {:>11}  {:>11}  {:>8}  {:>9}",
        "RMSE", "rel. MSE", "MISE", "SSIM", "seconds"
    );
    static NEVER: AtomicBool = AtomicBool::new(false);
    let mut rows: Vec<Row> = Vec::with_capacity(runs.len());
    for (i, ((v, r), stem)) in runs.iter().zip(&stems).enumerate() {
        bar.set_message(format!("{name} = {v} ({} of {})", i + 1, runs.len()));
        let base = i as u64 * 1000;
        let progress = |p: Progress| {
            bar.set_position(base + (p.fraction.clamp(0.0, 1.0) * 1000.0) as u64);
        };
        let ctl = RenderControl {
            stop: &NEVER,
            on_progress: &progress,
            on_checkpoint: &|_: &Film| {},
            on_iteration: &|_| {},
        };
        let start = Instant::now();
        let out = render(&scene, r.kind, &r.opts, &ctl)?;
        let seconds = start.elapsed().as_secs_f64();
        for note in &out.notes {
            if !args.quiet || note.starts_with("warning") {
                bar.suspend(|| eprintln!("[{name} = {v}] {note}"));
            }
        }
        let img = out.film.to_image();
        let path = outdir.join(format!("{stem}.exr"));
        img.write(&path)
            .with_context(|| format!("cannot write {}", path.display()))?;
        if args.png {
            let png = path.with_extension("png");
            img.write_png(&png, args.metric.exposure)
                .with_context(|| format!("cannot write {}", png.display()))?;
        }
        let pixels = args.metric.region_for(&region, &img, &reference);
        let c = compare(&img, &reference, &pixels, options).with_context(|| {
            format!(
                "comparing {} with reference {}",
                path.display(),
                args.reference.display()
            )
        })?;
        let row = Row {
            value: v.clone(),
            rmse: c.rmse,
            rel_mse: c.relative_mse,
            mise: c.mise,
            ssim: c.ssim,
            seconds,
        };
        let ssim = row.ssim.map_or("n/a".to_string(), |s| format!("{s:.5}"));
        bar.suspend(|| {
            println!(
                "{v:>vw$}  {:>11.4e}  {:>11.4e}  {:>11.4e}  {ssim:>8}  {seconds:>9.3}",
                row.rmse, row.rel_mse, row.mise
            )
        });
        rows.push(row);
        // Rewritten after every render, so an interrupted sweep keeps what it measured.
        write_csv(&csv_path, &rows)?;
    }
    bar.finish_and_clear();

    let points: Vec<SweepPoint> = rows
        .iter()
        .map(|r| SweepPoint {
            value: r.value.clone(),
            rmse: r.rmse,
            ssim: r.ssim,
        })
        .collect();
    let (svg, png) = (outdir.join("sweep.svg"), outdir.join("sweep.png"));
    let title = format!("{}: RMSE and SSIM against {name}", scene.name);
    let sweep_plot = SweepPlot {
        title: Some(&title),
        ..SweepPlot::new(name, &points)
    };
    plot::plot_sweep(&sweep_plot, &svg, &png).context("cannot plot the sweep")?;
    println!(
        "wrote {} ({} images, sweep.csv, sweep.svg, sweep.png)",
        outdir.display(),
        rows.len()
    );

    let rmse: Vec<f64> = rows.iter().map(|r| r.rmse).collect();
    let ssim: Vec<Option<f64>> = rows.iter().map(|r| r.ssim).collect();
    let best_rmse = plot::argmin(&rmse).map_or("RMSE-optimal: n/a".to_string(), |i| {
        format!(
            "RMSE-optimal {name} = {} (RMSE {})",
            rows[i].value,
            format_number(rows[i].rmse)
        )
    });
    let best_ssim = plot::argmax(&ssim).map_or(
        "SSIM-optimal: n/a (region narrower than 11 px)".to_string(),
        |i| {
            format!(
                "SSIM-optimal {name} = {} (SSIM {})",
                rows[i].value,
                format_number(ssim[i].unwrap_or(f64::NAN))
            )
        },
    );
    println!("{best_rmse}; {best_ssim}");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Command;

    #[test]
    fn every_parameter_is_a_render_option_named_in_the_help() {
        let cmd = SweepArgs::augment_args(Command::new("sweep"));
        let longs: Vec<&str> = cmd.get_arguments().filter_map(|a| a.get_long()).collect();
        let help = cmd
            .get_arguments()
            .find(|a| a.get_id() == "param")
            .and_then(|a| a.get_help())
            .map(|h| h.to_string())
            .unwrap_or_default();
        for (name, _) in PARAMETERS {
            assert!(longs.contains(name), "--{name} is not a render option");
            assert!(help.contains(name), "the --param help does not list {name}");
        }
    }

    #[test]
    fn parameters_set_their_option() {
        let cmd = SweepArgs::augment_args(Command::new("sweep"));
        let m = cmd
            .try_get_matches_from(["sweep", "--param", "k", "--values", "1", "--reference", "r"])
            .unwrap();
        let base = <SweepArgs as clap::FromArgMatches>::from_arg_matches(&m)
            .unwrap()
            .render;
        let set = |name: &str, v: &str| {
            let (_, f) = parameter(name).unwrap();
            let mut s = base.clone();
            f(&mut s).set(v).map(|_| s)
        };
        assert_eq!(set("k", "50").unwrap().photon.k, Some(50));
        assert_eq!(set("--spp", "4").unwrap().spp, Some(4));
        assert_eq!(set("seed", "7").unwrap().seed, 7);
        assert_eq!(set("max-depth", "-1").unwrap().max_depth, Some(-1));
        assert_eq!(
            set("max-radius", "0.5").unwrap().photon.max_radius,
            Some(0.5)
        );
        assert_eq!(
            set("kernel", "cone:1.1").unwrap().photon.kernel,
            Some(caustica_density::kernel::Kernel::Cone { g: 1.1 })
        );
        assert!(set("disc-test", "true").unwrap().photon.disc_test);
        assert!(set("k", "ten").is_err());
        assert!(set("spp", "-3").is_err());
        assert!(set("disc-test", "maybe").is_err());
        let err = parameter("smoothness").unwrap_err().to_string();
        assert!(
            err.contains("smoothness") && err.contains("global-photons, k"),
            "{err}"
        );
    }

    #[test]
    fn values_and_file_names() {
        assert_eq!(parse_values(" 1, 4 ,16").unwrap(), ["1", "4", "16"]);
        assert!(parse_values("").is_err());
        assert!(parse_values("1,,2").is_err());
        assert!(parse_values("1,2,1").is_err());
        assert_eq!(image_stem("kernel", "cone:1.1"), "kernel-cone_1.1");
        assert_eq!(image_stem("max-depth", "-1"), "max-depth--1");
        assert_eq!(csv_field("a\"b"), "\"a\"\"b\"");
        assert_eq!(csv_field("cone:1.1"), "cone:1.1");
    }
}
