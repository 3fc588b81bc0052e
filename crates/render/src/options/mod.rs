//! What a render is asked to do: the options every integrator shares ([`RenderOptions`]) and the
//! settings of each family ([`photon`]), whose values validate themselves ([`value`]).

pub mod pcf;
pub mod photon;
pub mod progressive;
pub mod value;

pub use pcf::{ConeSurfaces, ConeTechniques, DiffuseAperture, LookupRule, Nesting, PcfSettings};
pub use photon::{
    AutoBandwidth, CausticEstimator, DiffusionSettings, EmissionStrategy, FootprintSettings,
    PhotonOptions, ShutterAlign, SweepRule,
};
pub use progressive::ProgressiveSettings;
pub use value::{
    Bandwidth, Diffusivity, LightShare, NoiseScale, NormalDistance, Radius, Smoothing, Steepness,
};

use crate::crop::CropWindow;
use crate::error::OptionError;
use crate::transport::limits::PathLimits;
use caustica_core::sampling::SamplerKind;
use caustica_scene::camera::PerspectiveCamera;
use std::time::Duration;

/// Parameters shared by all integrators.
#[derive(Clone, Debug)]
pub struct RenderOptions {
    /// Samples per pixel (path tracer, the camera passes of the photon methods) or light paths
    /// per pixel (light tracer: the number of light paths is `spp × width × height`, as
    /// Mitsuba's `ptracer` counts them).
    pub spp: u32,
    /// A time budget for the whole render, shared by all its passes (`spp` is then ignored by
    /// the passes that can run on). Such a render is not reproducible bit for bit, since the
    /// work done depends on the machine.
    pub time_limit: Option<Duration>,
    pub seed: u64,
    pub sampler: SamplerKind,
    /// Index of the first camera sample of every pixel (0 for a one-shot render): pixel
    /// samples `first_sample, first_sample + 1, …` are drawn, so a progressive iteration's
    /// camera pass is independent of the others'.
    pub first_sample: u32,
    /// Path length limits (maximum depth, Russian roulette) of camera and light paths.
    pub limits: PathLimits,
    /// Interval at which `RenderControl::on_checkpoint` receives the film.
    pub checkpoint_interval: Option<Duration>,
    /// The most memory (bytes) the render may allocate by [`crate::memory::estimate`]; a render
    /// above it is refused before allocating. `None`: no limit.
    pub memory_limit: Option<u64>,
    /// Settings of the photon-mapping integrators.
    pub photons: PhotonOptions,
    /// Render only caustic light seen directly, paths L S+ D E: light that reached the first
    /// surface the camera sees, a non-delta one, through one or more delta (mirror, glass)
    /// bounces. Pixels that see a delta surface first are black. The light tracer and the photon
    /// methods honour it (the light tracer connects only such vertices to the camera; the photon
    /// methods return the caustic estimate alone), so their caustics can be compared without
    /// the noise of the other light (seed 000 ch. 6 compares caustics alone). The path tracer
    /// cannot isolate these paths and refuses it.
    pub caustics_only: bool,
    /// Render only the light that media scatter toward the camera along the camera ray's first
    /// segment (to the first surface that is not an index-matched boundary): paths … M E, the
    /// in-scattered radiance of seed 000 eq. 8.1 seen directly. The light tracer connects only
    /// medium vertices to the camera; the photon methods return only their volume estimate
    /// along that segment (seed notes Q-M11: media-only images isolate the ch. 8 estimators).
    /// The path tracer refuses it.
    pub volume_only: bool,
    /// Render only this window of the camera's film ([`CropWindow`]); `None`: the whole film.
    /// The image is the window's size and each pixel equals the uncropped render's; the
    /// light-side work (light paths, photons) is that of the whole film.
    pub crop: Option<CropWindow>,
    /// A progressive render to continue (`--resume`): its pooled film and iteration count;
    /// the render goes on from the next iteration to the bytes an uninterrupted one gives.
    pub resume: Option<std::sync::Arc<crate::driver::iteration_state::IterationState>>,
    /// Render only this shard's part of the work (`--shard I/N`, [`crate::shard`]): the films
    /// of shards `0..N` merge into exactly this render's film without a shard.
    pub shard: Option<crate::shard::Shard>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            spp: 16,
            time_limit: None,
            seed: 0,
            sampler: SamplerKind::Sobol,
            first_sample: 0,
            limits: PathLimits::default(),
            checkpoint_interval: None,
            memory_limit: None,
            photons: PhotonOptions::default(),
            caustics_only: false,
            volume_only: false,
            crop: None,
            resume: None,
            shard: None,
        }
    }
}

impl RenderOptions {
    /// The window of `camera`'s film this render computes (the whole film without a crop),
    /// checked to lie inside it.
    pub fn window(&self, camera: &PerspectiveCamera) -> Result<CropWindow, OptionError> {
        match self.crop {
            None => Ok(CropWindow::full(camera.width, camera.height)),
            Some(c) => c.check(camera.width, camera.height),
        }
    }
}
