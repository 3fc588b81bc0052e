//! `caustica render`.

use crate::eta::{EtaClock, TimeLeft};
use anyhow::{Context, Result, bail};
use caustica_core::image_io::Image;
use caustica_core::sampling::SamplerKind;
use caustica_loader as loader;
use caustica_render::driver::iteration_state::IterationState;
use caustica_render::{
    Film, IntegratorKind, PathLimits, Progress, RenderControl, RenderOptions, render,
};
use caustica_scene::Scene;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// The options that decide what a render computes: scene, integrator, sampling, photon mapping.
/// Shared by `render` and `sweep` (which varies one of them).
#[derive(Args, Clone, Debug)]
pub struct RenderSettings {
    /// Scene file (.toml) or built-in scene name (see `caustica scenes`). Default: the embedded
    /// Cornell box.
    pub scene: Option<String>,
    /// Integrator: path (path tracer with NEE and MIS), lighttrace (light tracer), pm (photon
    /// mapping), dpm (diffusion-based photon mapping), pdm (photon differential mapping), pds
    /// (photon differential splatting), vpm, beam, vpd (media); progressive: pppm, ppds, ppdm,
    /// pdpm (iterations of pm, pds, pdm, dpm at a shrinking bandwidth), sppm, ppm. Default: the scene's
    /// suggestion (Mitsuba `ptracer` maps to lighttrace), else path.
    #[arg(long)]
    pub integrator: Option<String>,
    /// Mitsuba scene parameter overriding a `<default>`: `-D name=value` (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    pub define: Vec<String>,
    /// Samples per pixel (path, the camera passes of pm, dpm, pdm, pds) or light paths per
    /// pixel (lighttrace); per iteration for the progressive methods (default 1), and ppm's
    /// fixed hit points per pixel. Default: the scene's suggestion, else 16. Not with --time,
    /// except for pds and the progressive methods.
    #[arg(long, allow_negative_numbers = true)]
    pub spp: Option<u32>,
    /// Render for this many seconds instead of a fixed sample count; the budget is shared by
    /// every pass (photon passes included). pds's camera pass keeps its --spp and the time goes
    /// to its light paths.
    #[arg(long, allow_negative_numbers = true)]
    pub time: Option<f64>,
    /// Worker threads (default: all cores). The image does not depend on it.
    #[arg(long, allow_negative_numbers = true)]
    pub threads: Option<usize>,
    /// Random seed; the same seed gives the same image bytes.
    #[arg(long, default_value_t = 0, allow_negative_numbers = true)]
    pub seed: u64,
    /// Sampler: sobol (Owen-scrambled) or independent.
    #[arg(long, default_value = "sobol")]
    pub sampler: String,
    /// Longest path in edges (Mitsuba's max_depth; -1 = unlimited).
    #[arg(long, allow_negative_numbers = true)]
    pub max_depth: Option<i64>,
    /// Render only caustics seen directly (paths L S+ D E), for comparing the caustics of the
    /// light tracer and photon mapping without the noise of other light (lighttrace, pm, dpm, pdm).
    #[arg(long)]
    pub caustics_only: bool,
    /// Render only light scattered by media straight toward the camera (paths ... M E along
    /// the camera ray's first segment), for comparing volume estimates with the light tracer
    /// without the noise of surface light (lighttrace, vpm, beam, vpd, and the other photon
    /// methods in media scenes).
    #[arg(long)]
    pub volume_only: bool,
    /// Spectral mode: every path samples three wavelengths (hero wavelength sampling), RGB
    /// inputs are upsampled to spectra (Jakob & Hanika 2019), named illuminants and blackbodies
    /// keep their spectra, dispersive glasses refract by wavelength, and the film integrates
    /// the CIE 1931 matching functions into linear sRGB. The photon methods trace their photons
    /// spectrally and store them in RGB (their camera side is RGB; docs/spectral.md).
    #[arg(long)]
    pub spectral: bool,
    /// Image width in pixels, overriding the scene's (any scene kind). Alone, the height
    /// follows to keep the aspect ratio; the field of view is kept along the scene's fov axis.
    #[arg(long, allow_negative_numbers = true)]
    pub width: Option<u32>,
    /// Image height in pixels, overriding the scene's (alone: the width follows).
    #[arg(long, allow_negative_numbers = true)]
    pub height: Option<u32>,
    /// Memory budget in GB (default: three quarters of the physical memory): a render whose
    /// estimated allocations exceed it is refused before it starts, with the figure and the
    /// option that lowers it (a positive finite number).
    #[arg(long, value_name = "GB", allow_negative_numbers = true)]
    pub memory: Option<f64>,
    /// Frame of an animated scene at which the shutter opens (frames may be fractional;
    /// default: the scene's, else 0). Static scenes ignore it.
    #[arg(long, allow_negative_numbers = true, value_parser = crate::values::finite_f32)]
    pub frame: Option<f32>,
    /// How long the shutter stays open, in frames (seed 003's exposure e; seconds = E / fps;
    /// ≥ 0, 0 = an instant; default: the scene's, else 0). Moving meshes are blurred over it by
    /// every integrator that samples time (path, lighttrace, and the photon methods' photons).
    #[arg(long, value_name = "E", allow_negative_numbers = true, value_parser = crate::values::finite_f32)]
    pub shutter: Option<f32>,
    #[command(flatten)]
    pub photon: crate::photon_args::PhotonArgs,
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub settings: RenderSettings,
    /// Output image (.exr, .pfm or .png; default out.exr). With --shard, the partial result: a
    /// .cpart file, or a directory to write shard-IIII-of-NNNN.cpart into.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Also write an sRGB PNG.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Exposure (stops) applied to PNG output.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = crate::values::finite_f32)]
    pub exposure: f32,
    /// Render only the W×H window whose top-left pixel is (X,Y) of the film (after
    /// --width/--height), like pbrt's --pixelbounds: the image is W×H and each pixel equals the
    /// uncropped render's with the same seed (every integrator; the light tracer and the photon
    /// methods still trace the whole film's light paths and photons). X,Y,W,H: four
    /// non-negative integers, W and H at least 1, the window inside the film.
    #[arg(long, value_name = "X,Y,W,H", allow_hyphen_values = true)]
    pub crop: Option<String>,
    /// Write the image accumulated so far every S seconds (the progressive methods also write
    /// their state file then, see --resume).
    #[arg(long)]
    pub checkpoint: Option<f64>,
    /// Continue a progressive render (pppm, ppds, ppdm, pdpm, sppm, ppm, pcf) from its state file, which every such
    /// render writes next to its image (OUTPUT.state: after the last complete iteration, at
    /// Ctrl-C, and with --checkpoint periodically). Give the same scene and options, and the
    /// total --iterations (or --time) wanted: the result has the bytes of an uninterrupted
    /// render.
    #[arg(long, value_name = "STATE")]
    pub resume: Option<PathBuf>,
    /// Progressive methods: also write the image after each of these iterations (positive
    /// integers, comma-separated, e.g. 1,10,100,1000) as OUTPUT with `-itN` before its
    /// extension (out-it100.exr), and a table of when each was reached (iteration, seconds
    /// since the render started, image) as OUTPUT.iterations.csv: one render gives a
    /// convergence curve.
    #[arg(long, value_name = "N1,N2,...", value_parser = parse_iteration_list)]
    pub save_iterations: Option<IterationList>,
    /// Render the frames A to B of an animated scene (both included; integers, e.g. 0..24),
    /// the shutter opening at each (its length from --shutter or the scene). -o (and --png)
    /// must then hold a frame field, %d or %0Nd (out_%04d.exr), and an animated PNG of the
    /// sequence is written (see --apng). Every frame uses the same --seed.
    #[arg(long, value_name = "A..B", allow_hyphen_values = true)]
    pub frames: Option<String>,
    /// The animated PNG of a --frames sequence (played at the scene's frame rate, else 25 fps,
    /// at --exposure). Default: -o with its frame field replaced by "preview", as .png.
    #[arg(long, value_name = "PATH")]
    pub apng: Option<PathBuf>,
    /// Live preview: serve a page on http://127.0.0.1:PORT/ (default 8080; 0: any free port)
    /// showing the image as it converges (refreshed every --preview-interval), with an exposure
    /// slider, the pass, progress, time left and rate, and the summary at the end. The port is
    /// bound before the render starts (in use: an error). With --frames it follows each frame.
    /// Put it after the scene, or write --preview=PORT (docs/preview.md).
    #[arg(long, value_name = "PORT", num_args = 0..=1, default_missing_value = "8080")]
    pub preview: Option<u16>,
    /// Stream the image to a running tev (https://github.com/Tom94/tev) at HOST:PORT (tev's
    /// default is 127.0.0.1:14158) with its TCP protocol, every --preview-interval and at the
    /// end; connected before the render starts (refused: an error).
    #[arg(long, value_name = "HOST:PORT")]
    pub tev: Option<String>,
    /// Seconds between the snapshots of the image that --preview and --tev show (default 1).
    /// A snapshot converts the film between passes (~55 ms per megapixel); snapshots are spaced
    /// further apart when needed to keep them under 1 % of the render's time.
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    pub preview_interval: Option<f64>,
    /// With --frames: keep the frames whose output file exists instead of rendering them again
    /// (to resume an interrupted sequence).
    #[arg(long)]
    pub skip_existing: bool,
    /// Render only shard I of N (0 <= I < N) of the work and write a partial result (see -o)
    /// for `caustica merge`, whose image is byte-identical to this render without --shard. Each
    /// method splits its own unit: pixel rows (path, pm, dpm, pdm, vpm, beam, vpd), light-path
    /// chunks (lighttrace), splat chunks (pds), iterations (pppm, ppds, ppdm, pdpm, pcf); sppm
    /// and ppm cannot be split. `/N` reads I from SLURM_ARRAY_TASK_ID (an array 0..N-1) or
    /// JOB_COMPLETION_INDEX (docs/distributed.md).
    #[arg(long, value_name = "I/N", allow_hyphen_values = true)]
    pub shard: Option<String>,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
}

impl RenderArgs {
    /// The output image (`-o`, default out.exr).
    fn output(&self) -> PathBuf {
        self.output
            .clone()
            .unwrap_or_else(|| PathBuf::from("out.exr"))
    }
}

/// What [`RenderSettings::resolve`] selects for a loaded scene.
#[derive(Clone, Debug)]
pub struct Resolved {
    pub kind: IntegratorKind,
    pub opts: RenderOptions,
    /// Warnings for the user (options that have no effect, an unknown suggested integrator).
    pub warnings: Vec<String>,
}

impl RenderSettings {
    /// Starts the worker threads (`--threads`, else one per core). Call once, before rendering.
    pub fn start_threads(&self) -> Result<()> {
        if let Some(t) = self.threads {
            if t == 0 {
                bail!("--threads must be at least 1");
            }
            rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build_global()
                .context("cannot start the worker threads")?;
        }
        Ok(())
    }

    /// Loads the scene (with the `-D` definitions) and prints its warnings.
    pub fn load_scene(&self) -> Result<Scene> {
        let defines = parse_defines(&self.define)?;
        let size = Resolution {
            width: self.width,
            height: self.height,
        };
        let shutter = ShutterOverride {
            frame: self.frame,
            length: self.shutter,
        };
        let mut scene = load_at(self.scene.as_deref(), &defines, size, shutter)?;
        scene.set_spectral(self.spectral).context("--spectral")?;
        for w in &scene.warnings {
            eprintln!("warning: {w}");
        }
        Ok(scene)
    }

    /// The hash tying a sharded render's parts to this scene: its source and the settings that
    /// change it ([`crate::shard_args::scene_hash`]).
    pub fn scene_hash(&self) -> Result<String> {
        let changes = format!(
            "defines {:?} width {:?} height {:?} frame {:?} shutter {:?} spectral {}",
            self.define, self.width, self.height, self.frame, self.shutter, self.spectral
        );
        crate::shard_args::scene_hash(self.scene.as_deref(), &changes)
    }

    /// The integrator and render options these settings select for `scene` (whose suggestions
    /// fill in what is not given), validated; no checkpoints.
    pub fn resolve(&self, scene: &Scene) -> Result<Resolved> {
        let mut warnings = Vec::new();
        let sampler: SamplerKind = self.sampler.parse().map_err(anyhow::Error::msg)?;
        if let Some(t) = self.time
            && !(t.is_finite() && t > 0.0)
        {
            bail!("--time must be a positive number of seconds, got {t}");
        }
        let kind: IntegratorKind = match (&self.integrator, &scene.settings.integrator) {
            (Some(name), _) => name.parse().map_err(anyhow::Error::msg)?,
            (None, Some(suggested)) => suggested.parse().unwrap_or_else(|_| {
                warnings.push(format!("the scene asks for integrator '{suggested}', which caustica does not have; using path"));
                IntegratorKind::Path
            }),
            (None, None) => IntegratorKind::Path,
        };
        kind.check_scene(scene)?;
        warnings.extend(kind.blind_spot(scene));
        if self.time.is_some()
            && self.spp.is_some()
            && kind != IntegratorKind::PhotonDifferentialSplatting
            && !kind.is_progressive()
        {
            bail!(
                "--spp and --time exclude each other for --integrator {} (only pds and the progressive methods take both: pds its camera samples and a budget for its light paths, pppm, ppds and ppdm the samples of each iteration)",
                kind.name()
            );
        }
        if self.photon.pcf.any_given() && kind != IntegratorKind::PhotonConeFocusing {
            bail!(
                "the --cone-*, --importon*, --camera-exponent, --no-mis, --no-camera-mirror and --nested options are for --integrator pcf, not {}",
                kind.name()
            );
        }
        if self.photon.wavelength_spread.is_some() {
            if !scene.spectral {
                bail!("--wavelength-spread needs --spectral (photons carry wavelengths only then)");
            }
            if !matches!(
                kind,
                IntegratorKind::PhotonDifferentialSplatting
                    | IntegratorKind::PhotonDifferentialMapping
            ) {
                bail!(
                    "--wavelength-spread is for --integrator pds and pdm, not {}",
                    kind.name()
                );
            }
        }
        if self.photon.progressive_given() && !kind.is_progressive() {
            bail!(
                "--iterations, --photons-per-iteration, --ppm-alpha and --radius are for the progressive methods (--integrator pppm, ppds, ppdm, pdpm, sppm, ppm or pcf), not {}",
                kind.name()
            );
        }
        // The progressive methods take a few camera samples per iteration.
        let spp = if kind.is_progressive() {
            self.spp.unwrap_or(1)
        } else {
            self.spp.or(scene.settings.spp).unwrap_or(16)
        };
        if spp == 0 {
            bail!("--spp must be at least 1");
        }
        let max_depth = match self.max_depth.or(scene.settings.max_depth.map(i64::from)) {
            None | Some(-1) => u32::MAX,
            Some(d) if d >= 1 => d.min(u32::MAX as i64) as u32,
            Some(d) => bail!("--max-depth must be -1 (unlimited) or at least 1, got {d}"),
        };
        let opts = RenderOptions {
            spp,
            time_limit: self.time.map(Duration::from_secs_f64),
            seed: self.seed,
            sampler,
            first_sample: 0,
            limits: PathLimits {
                max_depth,
                rr_depth: 5,
            },
            checkpoint_interval: None,
            memory_limit: match self.memory {
                Some(gb) if gb.is_finite() && gb > 0.0 => Some((gb * 1e9) as u64),
                Some(gb) => bail!("--memory must be a positive finite number of GB, got {gb}"),
                None => physical_memory().map(|b| b / 4 * 3),
            },
            photons: self.photon.options()?,
            caustics_only: self.caustics_only,
            volume_only: self.volume_only,
            crop: None,
            resume: None,
            shard: None,
        };
        let mut opts = opts;
        // The scene's [integrator] suggestions, where the command line is silent.
        if self.photon.photons.is_none()
            && self.photon.light_paths.is_none()
            && let Some(n) = scene.settings.photons
        {
            opts.photons.caustic_photons = n as usize;
        }
        if self.photon.smoothing.is_none()
            && let Some(s) = scene.settings.smoothing
        {
            opts.photons.footprints.smoothing = caustica_render::Smoothing::new(s)?;
            opts.photons.auto.smoothing = false;
        }
        if self.photon.volume_smoothing.is_none()
            && let Some(s) = scene.settings.volume_smoothing
        {
            opts.photons.volume.smoothing = Some(caustica_render::Smoothing::new(s)?);
        }
        if self.photon.volume_photons.is_none()
            && let Some(n) = scene.settings.volume_photons
        {
            opts.photons.volume.photons = n as usize;
        }
        if self.photon.final_gather.is_none()
            && let Some(g) = scene.settings.final_gather
        {
            opts.photons.final_gather = g;
        }
        kind.check(&opts)?;
        if (self.photon.smoothing.is_some()
            || self.photon.normal_distance.is_some()
            || self.photon.min_footprint.is_some())
            && !kind.uses_photon_differentials()
        {
            warnings.push(format!(
                "--smoothing, --normal-distance and --min-footprint only affect --integrator pdm, pds, vpd, ppds and ppdm, not '{}'",
                kind.name()
            ));
        }
        if self.photon.spread_collimated.is_some()
            && kind != IntegratorKind::VolumePhotonDifferentials
        {
            warnings.push(format!(
                "--spread-collimated only affects --integrator vpd, not '{}'",
                kind.name()
            ));
        }
        if self.photon.volume_boundary.is_some() && kind == IntegratorKind::VolumetricPhotonMapping
        {
            warnings.push(
                "--volume-boundary has no effect on --integrator vpm: its ray march gathers k-NN balls around the ray, not photon kernels (use beam or vpd)".to_string(),
            );
        }
        if self.photon.final_gather.is_some()
            && matches!(
                kind,
                IntegratorKind::StochasticProgressivePhotonMapping
                    | IntegratorKind::ProgressivePhotonMappingHitPoints
            )
        {
            warnings.push(format!(
                "--final-gather has no effect on --integrator {}: its visible points gather photons directly",
                kind.name()
            ));
        }
        if self.photon.light_share.is_some()
            && kind == IntegratorKind::Hybrid
            && self.time.is_none()
        {
            warnings.push(
                "--light-share splits a time budget (--time); without one the hybrid traces --light-paths light paths (default: one per two camera samples) and --spp camera samples".to_string(),
            );
        }
        if self.photon.light_share.is_some() && kind != IntegratorKind::Hybrid {
            warnings.push(format!(
                "--light-share only affects --integrator hybrid, not '{}'",
                kind.name()
            ));
        }
        if self.photon.any_given()
            && !kind.uses_photons()
            && !(kind == IntegratorKind::Hybrid && self.photon.only_hybrid_given())
        {
            warnings.push(format!(
                "photon-mapping options have no effect on integrator '{}'",
                kind.name()
            ));
        }
        Ok(Resolved {
            kind,
            opts,
            warnings,
        })
    }
}

/// The machine's physical memory (bytes), from `/proc/meminfo` where there is one.
fn physical_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Image size overrides (`--width`, `--height`).
#[derive(Clone, Copy, Debug, Default)]
pub struct Resolution {
    pub width: Option<u32>,
    pub height: Option<u32>,
}

impl Resolution {
    /// The size of a `w` × `h` image with these overrides: one given, the other follows the
    /// aspect ratio (rounded, at least 1); checked against the loaders' film limit.
    pub fn apply(self, w: u32, h: u32) -> Result<(u32, u32)> {
        let follow = |given: u32, from: u32, to: u32| {
            ((given as f64 * to as f64 / from.max(1) as f64).round() as u32).max(1)
        };
        let (nw, nh) = match (self.width, self.height) {
            (None, None) => return Ok((w, h)),
            (Some(nw), None) => (nw, follow(nw, w, h)),
            (None, Some(nh)) => (follow(nh, h, w), nh),
            (Some(nw), Some(nh)) => (nw, nh),
        };
        if nw == 0 || nh == 0 {
            bail!("--width and --height must be at least 1, got {nw}x{nh}");
        }
        if u64::from(nw) * u64::from(nh) > loader::MAX_FILM_PIXELS {
            bail!(
                "an image of {nw}x{nh} pixels is too large (at most {} pixels, e.g. 16384x16384)",
                loader::MAX_FILM_PIXELS
            );
        }
        Ok((nw, nh))
    }
}

/// Loads a scene given as a path or built-in name; `defines` override Mitsuba `<default>`s,
/// `size` the image size.
pub fn load(scene: Option<&str>, defines: &[(String, String)], size: Resolution) -> Result<Scene> {
    load_at(scene, defines, size, ShutterOverride::default())
}

/// `--frame` and `--shutter`: the shutter's opening and length (frames) replacing the scene's.
#[derive(Clone, Copy, Debug, Default)]
pub struct ShutterOverride {
    pub frame: Option<f32>,
    pub length: Option<f32>,
}

/// [`load`] with the shutter of `shutter`.
pub fn load_at(
    scene: Option<&str>,
    defines: &[(String, String)],
    size: Resolution,
    shutter: ShutterOverride,
) -> Result<Scene> {
    let name = scene.unwrap_or(loader::DEFAULT_SCENE);
    let path = Path::new(name);
    let builder = if path.extension().is_some() || path.exists() {
        loader::parse_scene_file_with_defines(path, defines)
            .with_context(|| format!("cannot load scene {}", path.display()))?
    } else {
        if let Some((d, _)) = defines.first() {
            bail!(
                "-D {d}: the built-in scene '{name}' has no parameters (-D sets a Mitsuba scene's <default> parameters)"
            );
        }
        loader::builtin_scene(name).with_context(|| {
            format!(
                "'{name}' is neither a scene file nor a built-in scene ({})",
                loader::builtin_names().join(", ")
            )
        })?
    };
    let mut builder = builder;
    if let Some(camera) = builder.camera() {
        let (w, h) = size.apply(camera.width, camera.height)?;
        if (w, h) != (camera.width, camera.height) {
            let mut camera = camera.clone();
            (camera.width, camera.height) = (w, h);
            builder.set_camera(camera);
        }
    }
    if shutter.frame.is_some() || shutter.length.is_some() {
        let s = builder.shutter();
        let s = caustica_scene::Shutter::new(
            shutter.frame.unwrap_or(s.open),
            shutter.length.unwrap_or(s.length),
        )
        .context("--frame/--shutter")?;
        builder.set_shutter(s);
    }
    builder
        .build()
        .with_context(|| format!("cannot build scene '{name}'"))
}

/// Parses `-D NAME=VALUE` arguments.
pub fn parse_defines(defs: &[String]) -> Result<Vec<(String, String)>> {
    defs.iter()
        .map(|d| match d.split_once('=') {
            Some((k, v)) if !k.is_empty() => Ok((k.to_string(), v.to_string())),
            _ => bail!("-D expects NAME=VALUE, got '{d}'"),
        })
        .collect()
}

/// Where one render writes: the image, and the optional PNG at an exposure.
#[derive(Clone, Debug)]
struct Outputs {
    /// The image, or a shard's partial result.
    image: PathBuf,
    png: Option<PathBuf>,
    exposure: f32,
    /// The shard rendered (`image` is then its `.cpart` file).
    shard: Option<caustica_render::Shard>,
}

/// The iterations of `--save-iterations`, ascending, without repeats.
#[derive(Clone, Debug)]
pub struct IterationList(Vec<u64>);

fn parse_iteration_list(text: &str) -> Result<IterationList, String> {
    let mut v = text
        .split(',')
        .map(|t| match t.trim().parse::<u64>() {
            Ok(n) if n >= 1 => Ok(n),
            _ => Err(format!(
                "expected positive iteration counts separated by commas (e.g. 1,10,100), got {t:?}"
            )),
        })
        .collect::<Result<Vec<_>, _>>()?;
    v.sort_unstable();
    v.dedup();
    Ok(IterationList(v))
}

/// The image `--save-iterations` writes after iteration `i`: `image` with `-it{i}` before its
/// extension.
fn iteration_path(image: &Path, i: u64) -> PathBuf {
    let stem = image.file_stem().and_then(|s| s.to_str()).unwrap_or("out");
    let name = match image.extension().and_then(|e| e.to_str()) {
        Some(ext) => format!("{stem}-it{i}.{ext}"),
        None => format!("{stem}-it{i}"),
    };
    image.with_file_name(name)
}

/// The state file of a progressive render written to `image`: `image` + `.state`.
fn state_path(image: &Path) -> PathBuf {
    let mut s = image.as_os_str().to_owned();
    s.push(".state");
    PathBuf::from(s)
}

fn write_outputs(img: &Image, out: &Outputs) -> Result<()> {
    write_atomically(&out.image, |p| img.write(p))?;
    if let Some(png) = &out.png {
        write_atomically(png, |p| img.write_png(p, out.exposure))?;
    }
    Ok(())
}

/// The temporary file an image is written to before it is renamed to `path`.
fn partial_path(path: &Path) -> PathBuf {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    path.with_extension(format!("partial.{ext}"))
}

/// Checks, before any work, that an image can be written to `path`: creates its directory if
/// missing and creates (then removes) the temporary file [`write_atomically`] will use.
pub fn check_writable(path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| {
            anyhow::anyhow!(
                "cannot write {}: cannot create the directory {}: {e}",
                path.display(),
                dir.display()
            )
        })?;
    }
    let tmp = partial_path(path);
    std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(true)
        .open(&tmp)
        .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))?;
    let _ = std::fs::remove_file(&tmp);
    Ok(())
}

/// Writes through a temporary file and renames, so an interrupted write never leaves a
/// truncated image where a good one was. The error names `path` (not the temporary file) once.
pub(crate) fn write_atomically<E: std::error::Error + Send + Sync + 'static>(
    path: &Path,
    write: impl Fn(&Path) -> Result<(), E>,
) -> Result<()> {
    let tmp = partial_path(path);
    write(&tmp).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        // The image writer names the file it wrote, the temporary one: say `path` instead.
        let why = e.to_string().replace(&format!("{}: ", tmp.display()), "");
        anyhow::anyhow!("cannot write {}: {why}", path.display())
    })?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        anyhow::anyhow!("cannot write {}: {e}", path.display())
    })?;
    Ok(())
}

/// Set by Ctrl-C: the render stops after its current pass and writes what it has.
static STOP: AtomicBool = AtomicBool::new(false);

pub fn run(args: RenderArgs) -> Result<()> {
    args.settings.start_threads()?;
    if let Some(c) = args.checkpoint
        && !(c.is_finite() && c > 0.0)
    {
        bail!("--checkpoint must be a positive number of seconds, got {c}");
    }
    let shard = args
        .shard
        .as_deref()
        .map(|t| crate::shard_args::parse_shard(t, |v| std::env::var(v).ok()))
        .transpose()?;
    let part = match shard {
        Some(s) => {
            for (given, what) in [
                (args.frames.is_some(), "--frames"),
                (args.resume.is_some(), "--resume"),
                (args.checkpoint.is_some(), "--checkpoint"),
                (args.save_iterations.is_some(), "--save-iterations"),
                (args.png.is_some(), "--png"),
            ] {
                if given {
                    bail!(
                        "--shard {s} writes a partial result, not an image, so {what} does not apply; merge the shards with `caustica merge PARTS -o IMAGE` (a failed shard is rendered again: shards are idempotent)"
                    );
                }
            }
            Some(crate::shard_args::part_path(args.output.as_deref(), s)?)
        }
        None => {
            check_image_extension(&args.output())?;
            None
        }
    };
    let sequence = args.frames.as_deref().map(parse_frames).transpose()?;
    if sequence.is_none() && (args.apng.is_some() || args.skip_existing) {
        bail!("--apng and --skip-existing go with --frames A..B");
    }
    let preview_interval = match args.preview_interval {
        None => Duration::from_secs(1),
        Some(_) if args.preview.is_none() && args.tev.is_none() => {
            bail!("--preview-interval goes with --preview or --tev")
        }
        Some(s) if s.is_finite() && s > 0.0 && s <= 1e6 => Duration::from_secs_f64(s),
        Some(s) => bail!("--preview-interval must be a positive number of seconds, got {s}"),
    };
    if sequence.is_some() && args.resume.is_some() {
        bail!(
            "--resume continues one render, not a --frames sequence (each frame writes its own state file)"
        );
    }
    ctrlc::set_handler(|| {
        if STOP.swap(true, Ordering::SeqCst) {
            eprintln!("\ninterrupted twice: exiting without writing");
            std::process::exit(130);
        }
        eprintln!("\ninterrupted: finishing the current pass and writing the image (Ctrl-C again to abort)");
    })
    .context("cannot install the Ctrl-C handler")?;
    // The preview's port is bound and tev connected before any work, so that a port in use or
    // an absent tev stops the command before anything is rendered or written.
    let live = crate::preview::Live::start(args.preview, args.tev.as_deref(), preview_interval)?;
    let result = render_all(&args, part, shard, sequence, live.as_ref());
    if let Some(l) = live {
        l.end(result.as_ref().err().map(|e| format!("{e:#}")));
    }
    result?;
    if STOP.load(Ordering::SeqCst) {
        // The image so far is written; the exit status tells scripts the render is incomplete.
        std::process::exit(130);
    }
    Ok(())
}

/// The render, or the `--frames` sequence, of `run`.
fn render_all(
    args: &RenderArgs,
    part: Option<PathBuf>,
    shard: Option<caustica_render::Shard>,
    sequence: Option<(i64, i64)>,
    live: Option<&crate::preview::Live>,
) -> Result<()> {
    match sequence {
        None => {
            let out = Outputs {
                image: part.clone().unwrap_or_else(|| args.output()),
                png: args.png.clone(),
                exposure: args.exposure,
                shard,
            };
            // Nothing rendered may be lost to an unwritable path: check them before any work.
            check_writable(&out.image)?;
            if let Some(png) = &out.png {
                check_writable(png)?;
            }
            render_one(args, &args.settings, &out, "", &STOP, live)?;
        }
        Some((first, last)) => run_sequence(args, first, last, &STOP, live)?,
    }
    Ok(())
}

pub(crate) fn check_image_extension(path: &Path) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if !["exr", "pfm", "png"].contains(&ext.as_str()) {
        bail!("output {} must end in .exr, .pfm or .png", path.display());
    }
    Ok(())
}

/// `--frames A..B`: two integers, A ≤ B, both included.
fn parse_frames(text: &str) -> Result<(i64, i64)> {
    let parsed = text
        .split_once("..")
        .and_then(|(a, b)| Some((a.trim().parse::<i64>().ok()?, b.trim().parse::<i64>().ok()?)));
    match parsed {
        Some((a, b)) if a <= b && b - a < 1_000_000 => Ok((a, b)),
        Some((a, b)) => bail!(
            "--frames {text}: the first frame must not be after the last (and at most a million frames), got {a} and {b}"
        ),
        None => bail!(
            "--frames expects A..B with two integer frames, both included (e.g. 0..24), got '{text}'"
        ),
    }
}

/// `-o` (or `--png`) of a sequence as a frame pattern; the error says what is expected.
fn sequence_pattern(path: &Path, option: &str) -> Result<loader::frame_pattern::FramePattern> {
    let text = path.to_string_lossy();
    if !loader::frame_pattern::FramePattern::is_pattern(&text) {
        bail!(
            "with --frames, {option} {} must hold a frame field, %d or %0Nd (e.g. out_%04d.exr)",
            path.display()
        );
    }
    loader::frame_pattern::FramePattern::parse(&text).map_err(|e| anyhow::anyhow!("{option}: {e}"))
}

/// `--frames A..B`: one render per frame (the shutter opening at it), each written as soon as
/// it is done, then the animated PNG preview of the frames rendered (also after Ctrl-C).
fn run_sequence(
    args: &RenderArgs,
    first: i64,
    last: i64,
    stop: &'static AtomicBool,
    live: Option<&crate::preview::Live>,
) -> Result<()> {
    if args.settings.frame.is_some() {
        bail!("--frame and --frames exclude each other (--frames sets the frame of each render)");
    }
    let output = args.output();
    let image = sequence_pattern(&output, "-o")?;
    let png = args
        .png
        .as_deref()
        .map(|p| sequence_pattern(p, "--png"))
        .transpose()?;
    let preview = match &args.apng {
        Some(p) => p.clone(),
        None => {
            let text = output.to_string_lossy().into_owned();
            let named = PathBuf::from(
                loader::frame_pattern::FramePattern::parse(&text)
                    .map_err(anyhow::Error::msg)?
                    .replace_field("preview"),
            );
            named.with_extension("png")
        }
    };
    let outputs = |f: i64| Outputs {
        image: PathBuf::from(image.name(f)),
        png: png.as_ref().map(|p| PathBuf::from(p.name(f))),
        exposure: args.exposure,
        shard: None,
    };
    for f in [first, last] {
        let o = outputs(f);
        check_writable(&o.image)?;
        if let Some(p) = &o.png {
            check_writable(p)?;
        }
    }
    check_writable(&preview)?;
    let count = (last - first + 1) as usize;
    let started = Instant::now();
    let mut frames = Vec::with_capacity(count);
    let mut fps = None;
    let mut rendered = 0usize;
    for (i, f) in (first..=last).enumerate() {
        let out = outputs(f);
        if args.skip_existing && out.image.exists() {
            let img = Image::read(&out.image)
                .with_context(|| format!("--skip-existing: cannot read {}", out.image.display()))?;
            eprintln!("frame {f}: kept {}", out.image.display());
            frames.push(img);
            continue;
        }
        let mut settings = args.settings.clone();
        settings.frame = Some(f as f32);
        let done = i as f64 / count as f64;
        let label = if rendered == 0 {
            format!("frame {f} ({}/{count}) ", i + 1)
        } else {
            let per = started.elapsed().as_secs_f64() / rendered as f64;
            format!(
                "frame {f} ({}/{count}, sequence {:.0}%, {} left) ",
                i + 1,
                100.0 * done,
                crate::eta::duration(per * (count - i) as f64)
            )
        };
        let (img, scene_fps) = render_one(args, &settings, &out, &label, stop, live)?;
        fps = fps.or(scene_fps);
        rendered += 1;
        frames.push(img);
        if stop.load(Ordering::SeqCst) {
            break;
        }
    }
    let fps = fps.unwrap_or(25.0);
    caustica_core::apng::write_apng(&preview, &frames, fps, args.exposure)
        .with_context(|| format!("cannot write the preview {}", preview.display()))?;
    println!(
        "sequence: frames {first}..{last} ({} rendered, {} kept) in {:.2} s -> {}, preview ({} frames at {fps} fps) -> {}",
        rendered,
        frames.len() - rendered,
        started.elapsed().as_secs_f64(),
        output.display(),
        frames.len(),
        preview.display()
    );
    Ok(())
}

/// One render of `settings` written to `out`, with the progress bar (its message prefixed by
/// `label`) and the one-line summary. Returns the image and the scene's frame rate.
fn render_one(
    args: &RenderArgs,
    settings: &RenderSettings,
    out: &Outputs,
    label: &str,
    stop: &'static AtomicBool,
    live: Option<&crate::preview::Live>,
) -> Result<(Image, Option<f32>)> {
    let scene = settings.load_scene()?;
    let Resolved {
        kind,
        mut opts,
        warnings,
    } = settings.resolve(&scene)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    // The film reaches the CLI at checkpoints (`on_checkpoint`); a live preview takes its
    // snapshots there too, so it lowers the interval to its own and the files are then written
    // only when --checkpoint's interval has passed (`gated`). The interval changes when the
    // film is looked at, never what is added to it: the image is the same bytes.
    let file_interval = args.checkpoint.map(Duration::from_secs_f64);
    opts.checkpoint_interval = match (file_interval, live) {
        (Some(f), Some(l)) => Some(f.min(l.interval)),
        (None, Some(l)) => Some(l.interval),
        (f, None) => f,
    };
    let gated = live.is_some() && file_interval.is_some();
    if let Some(l) = live {
        l.hub.start_render(&out.image.display().to_string(), label);
    }
    opts.shard = out.shard;
    let cam = &scene.camera;
    opts.crop = args
        .crop
        .as_deref()
        .map(|c| caustica_render::CropWindow::parse(c, cam.width, cam.height))
        .transpose()?;
    let fingerprint = (kind.resumable() && out.shard.is_none())
        .then(|| caustica_render::driver::iteration_state::fingerprint(&scene, kind, &opts));
    if let Some(path) = &args.resume {
        let Some(fp) = &fingerprint else {
            bail!(
                "--resume continues a progressive render (--integrator pppm, ppds, ppdm, pdpm, sppm, ppm or pcf), not {}",
                kind.name()
            );
        };
        let bytes = std::fs::read(path)
            .map_err(|e| anyhow::anyhow!("cannot read the state file {}: {e}", path.display()))?;
        let state = IterationState::decode(&bytes, fp)
            .map_err(|e| anyhow::anyhow!("cannot resume from {}: {e}", path.display()))?;
        if opts
            .photons
            .progressive
            .iterations
            .is_some_and(|n| n <= state.iterations)
        {
            bail!(
                "cannot resume from {}: it already holds {} iterations; ask for more with --iterations",
                path.display(),
                state.iterations
            );
        }
        eprintln!(
            "resuming after iteration {} from {}",
            state.iterations,
            path.display()
        );
        opts.resume = Some(std::sync::Arc::new(state));
    }
    if args.save_iterations.is_some() && !kind.is_progressive() {
        bail!(
            "--save-iterations writes the images of a progressive render's iterations (--integrator pppm, ppds, ppdm, pdpm, sppm, ppm or pcf), not of {}",
            kind.name()
        );
    }
    let state_path = fingerprint.as_ref().map(|_| state_path(&out.image));
    if kind.uses_photons() && !args.quiet {
        eprintln!(
            "memory: {}",
            caustica_render::memory::estimate(kind, &scene, &opts)
        );
    }
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(1000)
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    // The bar shows the whole render; the message the pass, its own progress and the time left
    // (of the render under --time, else of the pass: see eta.rs).
    let started = Instant::now();
    let eta = Mutex::new(EtaClock::new(opts.time_limit));
    let progress = |p: Progress| {
        bar.set_position((p.fraction * 1000.0) as u64);
        let left = match eta.lock() {
            Ok(mut c) => c.update(started.elapsed().as_secs_f64(), p.pass, p.pass_fraction),
            Err(_) => TimeLeft::Unknown,
        };
        let msg = match left {
            TimeLeft::Unknown => format!("{label}{} {:.0}%", p.pass, 100.0 * p.pass_fraction),
            _ => format!("{label}{} {:.0}%, {left}", p.pass, 100.0 * p.pass_fraction),
        };
        bar.set_message(msg);
        if let Some(l) = live {
            let eta = left.to_string();
            l.hub
                .progress(p.pass, p.pass_fraction, p.fraction, &eta, p.samples);
        }
    };
    // A failing checkpoint is reported at once (each distinct failure once); the render goes on.
    let checkpoint_err = std::sync::Mutex::new(None::<String>);
    let last_file = Mutex::new(Instant::now());
    let checkpoint = |film: &Film| {
        let file_due = match file_interval {
            None => false,
            Some(_) if !gated => true,
            Some(iv) => last_file.lock().is_ok_and(|mut last| {
                let due = last.elapsed() >= iv;
                if due {
                    *last = Instant::now();
                }
                due
            }),
        };
        // A snapshot is skipped while the last one's cost is more than the preview's share of
        // the time since (`Live::snapshot_due`): the conversion runs between passes.
        let snapshot = live.filter(|l| file_due || l.snapshot_due());
        if !file_due && snapshot.is_none() {
            return;
        }
        let t = Instant::now();
        let img = film.to_image();
        let cost = t.elapsed();
        let written = if file_due {
            write_outputs(&img, out)
        } else {
            Ok(())
        };
        if let Some(l) = snapshot {
            l.hub.publish(img);
            l.snapshot_taken(cost);
        }
        if let Err(e) = written
            && let Ok(mut slot) = checkpoint_err.lock()
        {
            let msg = format!("{e:#}");
            if slot.as_deref() != Some(msg.as_str()) {
                bar.suspend(|| eprintln!("warning: checkpoint not written, rendering on: {msg}"));
                *slot = Some(msg);
            }
        }
    };
    // The progressive methods' state file: with --checkpoint at its interval, and at the end.
    let last_state = Mutex::new(Instant::now());
    let write_state = |state: &IterationState| {
        if let Some(path) = &state_path {
            let bytes = state.to_bytes();
            if let Err(e) = write_atomically(path, |p| std::fs::write(p, &bytes)) {
                bar.suspend(|| eprintln!("warning: state file not written: {e:#}"));
            }
        }
    };
    // --save-iterations: the image after each listed iteration, and when it was reached.
    let saved = Mutex::new(String::from("iteration,seconds,image\n"));
    let table = {
        let mut s = out.image.as_os_str().to_owned();
        s.push(".iterations.csv");
        PathBuf::from(s)
    };
    let on_iteration = |done: &caustica_render::control::IterationDone| {
        if let Some(list) = &args.save_iterations
            && list.0.binary_search(&done.iteration).is_ok()
        {
            let secs = started.elapsed().as_secs_f64();
            let path = iteration_path(&out.image, done.iteration);
            let written =
                write_atomically(&path, |p| done.image().to_image().write(p)).and_then(|()| {
                    let mut t = saved
                        .lock()
                        .map_err(|_| anyhow::anyhow!("the iteration table is poisoned"))?;
                    t.push_str(&format!(
                        "{},{secs:.4},{}\n",
                        done.iteration,
                        path.display()
                    ));
                    write_atomically(&table, |p| std::fs::write(p, t.as_bytes()))
                });
            if let Err(e) = written {
                bar.suspend(|| eprintln!("warning: --save-iterations: {e:#}"));
            }
        }
        let Some(iv) = file_interval else {
            return;
        };
        if let Ok(mut last) = last_state.lock()
            && last.elapsed() >= iv
        {
            write_state(&done.state());
            *last = Instant::now();
        }
    };
    let ctl = RenderControl {
        stop,
        on_progress: &progress,
        on_checkpoint: &checkpoint,
        on_iteration: &on_iteration,
    };
    let rendered = render(&scene, kind, &opts, &ctl)?;
    if let (Some(state), Some(path)) = (&rendered.state, &state_path) {
        write_state(state);
        eprintln!(
            "state after iteration {}: {} (continue with --resume)",
            state.iterations,
            path.display()
        );
    }
    bar.finish_and_clear();
    for note in &rendered.notes {
        eprintln!("{note}");
    }
    let img = rendered.film.to_image();
    let shard_note = match out.shard {
        None => {
            write_outputs(&img, out)?;
            String::new()
        }
        Some(shard) => {
            if stop.load(Ordering::SeqCst) {
                bail!(
                    "shard {shard} was interrupted: no partial result written (render it again; a shard's result depends only on its index)"
                );
            }
            let manifest = caustica_render::partial::Manifest::of_shard(
                shard,
                rendered.shard.clone().unwrap_or_default(),
                settings.scene_hash()?,
                caustica_render::driver::iteration_state::fingerprint(&scene, kind, &opts),
            );
            let bytes = caustica_render::partial::Part::encode(&manifest, &rendered.film);
            write_atomically(&out.image, |p| std::fs::write(p, &bytes))?;
            format!(
                "shard {shard} ({}, {:.1} MB)",
                rendered.shard.as_deref().unwrap_or(""),
                bytes.len() as f64 / 1e6
            )
        }
    };
    let secs = rendered.elapsed.as_secs_f64().max(1e-9);
    let what = match kind {
        _ if out.shard.is_some() => String::new(),
        IntegratorKind::Path
        | IntegratorKind::PhotonMapping
        | IntegratorKind::DiffusionPhotonMapping
        | IntegratorKind::PhotonDifferentialMapping
        | IntegratorKind::PhotonDifferentialSplatting
        | IntegratorKind::VolumetricPhotonMapping
        | IntegratorKind::BeamRadianceEstimate
        | IntegratorKind::VolumePhotonDifferentials => {
            format!("{:.1} spp", rendered.film.mean_samples())
        }
        IntegratorKind::ProgressivePhotonMapping
        | IntegratorKind::ProgressiveSplatting
        | IntegratorKind::ProgressiveDifferentialMapping
        | IntegratorKind::ProgressiveDiffusion
        | IntegratorKind::StochasticProgressivePhotonMapping
        | IntegratorKind::ProgressivePhotonMappingHitPoints
        | IntegratorKind::PhotonConeFocusing => format!(
            "{} iterations, {:.1} spp",
            rendered.iterations.unwrap_or(0),
            rendered.film.mean_samples()
        ),
        IntegratorKind::LightTrace => format!("{} light paths", rendered.film.light_paths()),
        IntegratorKind::Hybrid => format!(
            "{} light paths, {:.1} spp",
            rendered.film.light_paths(),
            rendered.film.mean_samples()
        ),
    } + &shard_note;
    let stopped = if stop.load(Ordering::SeqCst) {
        " (interrupted)"
    } else {
        ""
    };
    let crop = opts
        .crop
        .map(|c| format!(" (crop {c} of {}x{})", cam.width, cam.height))
        .unwrap_or_default();
    let summary = format!(
        "{}: {}{} {}x{}{crop}, {what} in {secs:.2} s{stopped}: {:.2} M samples/s, {:.2} M rays/s, {} NaN/Inf samples discarded -> {}",
        scene.name,
        kind.name(),
        if scene.spectral { " (spectral)" } else { "" },
        rendered.film.width,
        rendered.film.height,
        rendered.stats.samples as f64 / secs / 1e6,
        rendered.stats.rays as f64 / secs / 1e6,
        rendered.stats.nonfinite,
        out.image.display()
    );
    println!("{summary}");
    if let Some(l) = live {
        l.hub.summary(&summary, stopped.is_empty());
        l.hub.publish(img.clone());
    }
    Ok((img, scene.settings.fps))
}
