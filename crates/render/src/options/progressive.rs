//! Settings of the progressive methods (`pppm`, `ppds`, `ppdm`): how many iterations, the light
//! paths of each, and the bandwidth schedule (seed 001 eq. 3.27).

use super::{Radius, RenderOptions};
use crate::error::OptionError;

/// Iterations when neither `iterations` nor a time budget is given.
pub const DEFAULT_ITERATIONS: u64 = 16;

/// How a progressive render runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProgressiveSettings {
    /// Iterations to run (`--iterations`); `None`: until the time budget is spent, or
    /// [`DEFAULT_ITERATIONS`] without one.
    pub iterations: Option<u64>,
    /// Light paths each iteration traces for each photon map (`--photons-per-iteration`, as
    /// pbrt-v4's SPPM counts them); ≥ 1.
    pub paths_per_iteration: u64,
    /// The schedule's α in (0, 1] (`--alpha`; 2/3 minimises the MSE of PPPM, Knaus and
    /// Zwicker 2011; 1 keeps the bandwidth fixed).
    pub alpha: f64,
    /// The first iteration's gather radius (m) of `pppm` (`--radius`); `None`: the median
    /// distance from a caustic photon of the first iteration to its k-th nearest neighbour.
    pub radius: Option<Radius>,
}

impl Default for ProgressiveSettings {
    fn default() -> Self {
        Self {
            iterations: None,
            paths_per_iteration: 100_000,
            alpha: 2.0 / 3.0,
            radius: None,
        }
    }
}

impl ProgressiveSettings {
    /// Checks the values; the message names the option.
    pub fn validate(&self) -> Result<(), OptionError> {
        if !(self.alpha > 0.0 && self.alpha <= 1.0) {
            return Err(OptionError::Invalid {
                what: "--ppm-alpha",
                rule: "a number in (0, 1] (at 0 the variance never vanishes, above 1 the radius grows; seed 001 sec. 3.5.3)",
                got: self.alpha.to_string(),
            });
        }
        if self.paths_per_iteration == 0 {
            return Err(OptionError::Invalid {
                what: "--photons-per-iteration",
                rule: "at least 1 light path",
                got: "0".into(),
            });
        }
        if self.iterations == Some(0) {
            return Err(OptionError::Invalid {
                what: "--iterations",
                rule: "at least 1",
                got: "0".into(),
            });
        }
        Ok(())
    }

    /// The most iterations a render with `opts` runs: `iterations`, or without it unbounded
    /// under a time budget and [`DEFAULT_ITERATIONS`] otherwise.
    pub fn max_iterations(&self, opts: &RenderOptions) -> Option<u64> {
        match (self.iterations, opts.time_limit) {
            (Some(n), _) => Some(n),
            (None, Some(_)) => None,
            (None, None) => Some(DEFAULT_ITERATIONS),
        }
    }

    /// The options of iteration `i ≥ 1` of a render with `opts`: a one-shot render of its own
    /// window of light paths (paths `(i − 1) M … i M − 1` of every photon stream, `M` =
    /// `paths_per_iteration`) and camera samples (`(i − 1) spp … i spp − 1` of every pixel),
    /// without time budget, checkpoints, shard or automatic bandwidths (the progressive driver
    /// owns those). Iterations are therefore independent, and iteration `i` is the same whenever
    /// and wherever it runs.
    pub fn iteration_options(&self, opts: &RenderOptions, i: u64) -> RenderOptions {
        let mut o = opts.clone();
        let k = i.max(1) - 1;
        o.time_limit = None;
        o.checkpoint_interval = None;
        // A sharded render splits iterations; each iteration is whole.
        o.shard = None;
        o.first_sample = (k.saturating_mul(opts.spp as u64)).min(u32::MAX as u64) as u32;
        let p = &mut o.photons;
        p.first_path = k.saturating_mul(self.paths_per_iteration);
        p.light_paths = Some(self.paths_per_iteration);
        p.global_light_paths = Some(self.paths_per_iteration);
        p.auto = Default::default();
        o
    }
}
