//! What a render is asked to do and how it reports back.

use crate::film::Film;
use crate::photon_map::EstimateOptions;
use caustica_core::sampling::SamplerKind;
use std::sync::atomic::AtomicBool;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

/// Parameters shared by all integrators.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Samples per pixel (path tracer) or light paths per pixel (light tracer: the number of
    /// light paths is `spp × width × height`, as Mitsuba's `ptracer` counts them).
    pub spp: u32,
    /// With a time budget, passes continue until it is spent (`spp` is then ignored). Such a
    /// render is not reproducible bit for bit, since the sample count depends on the machine.
    pub time_limit: Option<Duration>,
    pub seed: u64,
    pub sampler: SamplerKind,
    /// Longest path in edges, Mitsuba's convention: 1 = emitters seen directly, 2 = direct
    /// lighting, … `u32::MAX` = unlimited (Russian roulette ends paths).
    pub max_depth: u32,
    /// Russian roulette starts after this many edges.
    pub rr_depth: u32,
    /// Interval at which `RenderControl::on_checkpoint` receives the film.
    pub checkpoint_interval: Option<Duration>,
    /// Settings of the photon-mapping integrators.
    pub photons: PhotonOptions,
    /// Render only caustic light seen directly, paths L S+ D E: light that reached the first
    /// surface the camera sees, a non-delta one, through one or more delta (mirror, glass)
    /// bounces. Pixels that see a delta surface first are black. The light tracer and `pm`
    /// honour it (the light tracer connects only such vertices to the camera; `pm` returns the
    /// caustic-map estimate alone), so their caustics can be compared without the noise of the
    /// other light (seed 000 ch. 6 compares caustics alone). The path tracer cannot isolate
    /// these paths and rejects it.
    pub caustics_only: bool,
}

/// Settings of the photon-mapping integrators.
#[derive(Clone, Debug, PartialEq)]
pub struct PhotonOptions {
    /// Photons stored in the caustic map (L S+ D); light paths are emitted until it holds this
    /// many.
    pub caustic_photons: usize,
    /// Photons stored in the global map (every non-delta hit); 0 = no indirect light.
    pub global_photons: usize,
    /// The radiance estimate (k, maximum radius, kernel, bias controls), used for both maps.
    pub estimate: EstimateOptions,
    /// Photons per estimate in the global map, when it should differ from `estimate.k` (the
    /// caustic map's); `None` = the same k.
    pub global_k: Option<usize>,
    /// Final-gather rays per camera sample; 0 = visualise the global map directly.
    pub final_gather: u32,
    /// The density estimator of the caustic map (the global map always uses k-NN).
    pub caustic_estimator: CausticEstimator,
    /// Fixed bandwidth h (m) of the `fixed` and diffusion estimators; `None` = the median
    /// distance from a caustic photon to its k-th nearest neighbour (k = `estimate.k`).
    pub bandwidth: Option<f32>,
    /// Parameters of the diffusion estimator (`dpm`).
    pub diffusion: DiffusionSettings,
    /// Radial kernel of photon-differential footprints (`pdm`, `pds`); seed 002 eq. 11's
    /// Silverman kernel by default.
    pub footprint_kernel: caustica_density::kernel::Kernel,
    /// Smoothing parameter s of photon differentials (`pdm`, `pds`; seed 002 eq. 5–6): the
    /// emitted footprints tile the light's area and solid angle s² times; > 0.
    pub smoothing: f32,
    /// Normal-distance threshold against topological bias (seed 002 sec. 3.3), as a fraction of
    /// a footprint's gather radius: a footprint does not reach a point farther than this from
    /// its tangent plane, `|n_p · (x − x_p)| > t · r_max`. `f32::INFINITY` disables the test;
    /// ≥ 0.
    pub normal_distance: f32,
}

/// Density estimators the caustic map can use (all behind `caustica_density::Estimator`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CausticEstimator {
    /// k-th nearest neighbour, eq. 3.2 (`pm`).
    #[default]
    Knn,
    /// Fixed bandwidth, eq. 2.15.
    Fixed,
    /// Variable bandwidth with a k-NN pilot (k = `estimate.k`), eq. 2.13.
    Variable,
    /// Diffusion-based photon mapping, eq. 4.19 (`dpm`).
    Diffusion,
}

impl CausticEstimator {
    pub const NAMES: &'static [&'static str] = &["knn", "fixed", "variable", "diffusion"];
}

impl std::str::FromStr for CausticEstimator {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "knn" => Ok(Self::Knn),
            "fixed" => Ok(Self::Fixed),
            "variable" => Ok(Self::Variable),
            "diffusion" | "dpm" => Ok(Self::Diffusion),
            _ => Err(format!(
                "unknown estimator '{s}' (expected one of: {})",
                Self::NAMES.join(", ")
            )),
        }
    }
}

/// Settings of diffusion-based photon mapping (seed 000 ch. 4); the bandwidth is
/// [`PhotonOptions::bandwidth`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffusionSettings {
    /// Noise scale σ (m) of the gradient pre-pass; `None` = half the bandwidth.
    pub noise_scale: Option<f32>,
    /// Diffusivity coefficient q (eq. 4.15).
    pub q: f32,
    /// Steepness α (eq. 4.15).
    pub alpha: f32,
    /// Isotropic diffusion (sec. 4.3.3).
    pub isotropic: bool,
}

impl Default for DiffusionSettings {
    /// q = 0.2, α = 1 as in seed 000 fig. 4.6.
    fn default() -> Self {
        Self {
            noise_scale: None,
            q: 0.2,
            alpha: 1.0,
            isotropic: false,
        }
    }
}

impl Default for PhotonOptions {
    fn default() -> Self {
        Self {
            caustic_photons: 200_000,
            global_photons: 100_000,
            estimate: EstimateOptions::default(),
            global_k: None,
            final_gather: 16,
            caustic_estimator: CausticEstimator::Knn,
            bandwidth: None,
            diffusion: DiffusionSettings::default(),
            smoothing: 1.0,
            footprint_kernel: caustica_density::kernel::Kernel::Silverman,
            normal_distance: 0.25,
        }
    }
}

impl PhotonOptions {
    /// Checks the values a user can set; the message names the offending option.
    pub fn validate(&self) -> Result<(), String> {
        if self.caustic_photons == 0 {
            return Err("the number of caustic photons must be at least 1".into());
        }
        if self.estimate.k == 0 {
            return Err("k (photons per estimate) must be at least 1".into());
        }
        if self.global_k == Some(0) {
            return Err("the global map's k (photons per estimate) must be at least 1".into());
        }
        if let Some(r) = self.estimate.max_radius
            && !(r.is_finite() && r > 0.0)
        {
            return Err(format!(
                "the maximum radius must be a positive length, got {r}"
            ));
        }
        let positive = |name: &str, v: f32| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!("{name} must be a positive finite number, got {v}"))
            }
        };
        if let Some(h) = self.bandwidth {
            positive("the bandwidth", h)?;
        }
        if let Some(s) = self.diffusion.noise_scale {
            positive("the noise scale", s)?;
        }
        positive("the diffusivity coefficient q", self.diffusion.q)?;
        positive("alpha", self.diffusion.alpha)?;
        positive("the smoothing parameter s", self.smoothing)?;
        if self.normal_distance.is_nan() || self.normal_distance < 0.0 {
            return Err(format!(
                "the normal-distance threshold must be ≥ 0 (a fraction of the footprint's gather radius; inf disables it), got {}",
                self.normal_distance
            ));
        }
        Ok(())
    }
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            spp: 16,
            time_limit: None,
            seed: 0,
            sampler: SamplerKind::Sobol,
            max_depth: u32::MAX,
            rr_depth: 5,
            checkpoint_interval: None,
            photons: PhotonOptions::default(),
            caustics_only: false,
        }
    }
}

/// Progress of a render.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Fraction done in [0, 1] (by samples, or by time under a time budget).
    pub fraction: f64,
    /// Samples (or light paths) done so far.
    pub samples: u64,
}

/// Callbacks and the stop flag of a render.
pub struct RenderControl<'a> {
    /// Set (e.g. by Ctrl-C) to stop after the current pass; the film keeps what was rendered.
    pub stop: &'a AtomicBool,
    pub on_progress: &'a (dyn Fn(Progress) + Sync),
    pub on_checkpoint: &'a (dyn Fn(&Film) + Sync),
}

impl RenderControl<'_> {
    /// A control that never stops and reports nothing.
    pub fn silent() -> RenderControl<'static> {
        static NEVER: AtomicBool = AtomicBool::new(false);
        RenderControl {
            stop: &NEVER,
            on_progress: &|_| {},
            on_checkpoint: &|_| {},
        }
    }
}

/// Between-pass bookkeeping shared by the render drivers: progress fraction, checkpoints, and
/// whether to stop (Ctrl-C flag or time budget).
pub(crate) struct PassClock {
    start: Instant,
    last_checkpoint: Instant,
}

impl PassClock {
    pub(crate) fn new() -> Self {
        Self {
            start: Instant::now(),
            last_checkpoint: Instant::now(),
        }
    }

    /// Fraction done: by time under a budget, else `done / total` work units.
    pub(crate) fn fraction(&self, opts: &RenderOptions, done: f64, total: f64) -> f64 {
        let f = match opts.time_limit {
            Some(t) => self.start.elapsed().as_secs_f64() / t.as_secs_f64(),
            None => done / total.max(1.0),
        };
        f.min(1.0)
    }

    /// Called after each pass: writes a checkpoint when one is due and tells whether the render
    /// must stop now.
    pub(crate) fn end_of_pass(
        &mut self,
        opts: &RenderOptions,
        ctl: &RenderControl,
        film: &Film,
    ) -> bool {
        if ctl.stop.load(Ordering::Relaxed) {
            return true;
        }
        if let Some(t) = opts.time_limit
            && self.start.elapsed() >= t
        {
            return true;
        }
        if let Some(iv) = opts.checkpoint_interval
            && self.last_checkpoint.elapsed() >= iv
        {
            (ctl.on_checkpoint)(film);
            self.last_checkpoint = Instant::now();
        }
        false
    }
}
