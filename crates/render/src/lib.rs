//! Integrators and film of caustica. The folders are the layers, data flowing down:
//!
//! * [`transport`] — what every path walks: the medium hook ([`transport::trace_segment`]),
//!   vertices, path limits, next-event estimation, the light walker and the eye walker.
//! * [`photon`] — the photon family: numbered light paths and their plan, photon tracing and
//!   maps, the caustic estimate, the eye map, photon differentials.
//! * [`driver`] — how work is spread over threads, deterministically: pixels, light paths,
//!   and the eye-splat pipeline.
//! * [`integrator`] — the methods, each a rule over the above: the path tracer, the light
//!   tracer, photon mapping (`pm`, `dpm`, `pdm`) and photon differential splatting (`pds`).
//! * [`options`], [`control`], [`error`] — what a render is asked to do, how it reports and
//!   stops, and why it refuses.
//! * [`film`] and its [`crop`] window, [`filter`], [`stats`], [`photon_view`] — accumulation, reconstruction,
//!   counters, and photons drawn over an image.

#![forbid(unsafe_code)]

pub mod control;
pub mod crop;
pub mod driver;
pub mod error;
pub mod exact_sum;
pub mod film;
pub mod filter;
pub mod integrator;
pub mod memory;
pub mod options;
pub mod partial;
pub mod pcf;
pub mod photon;
pub mod photon_view;
pub mod shard;
pub mod stats;
pub mod transport;

pub use control::{Progress, RenderControl};
pub use crop::CropWindow;
pub use error::{OptionError, RenderError};
pub use exact_sum::ExactSum;
pub use film::Film;
pub use integrator::{IntegratorKind, RenderOutput, render};
pub use options::{
    AutoBandwidth, Bandwidth, CausticEstimator, DiffusionSettings, Diffusivity, EmissionStrategy,
    FootprintSettings, LightShare, NoiseScale, NormalDistance, PhotonOptions, ProgressiveSettings,
    Radius, RenderOptions, ShutterAlign, Smoothing, Steepness, SweepRule,
};
pub use photon::plan::PhotonBudget;
pub use shard::{RowSet, Shard, ShardUnit};
pub use stats::RenderStats;
pub use transport::PathLimits;
