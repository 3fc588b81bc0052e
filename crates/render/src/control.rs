//! How a render reports back and when it stops: the caller's callbacks and stop flag
//! ([`RenderControl`]), and the one clock all passes of a render share ([`Clock`], seen by each
//! pass through its [`Stage`]).
//!
//! A render is a sequence of passes (photon tracing, a camera pass, splatting…). Each pass owns
//! a share `[lo, hi]` of the render: of the progress bar, and under a time budget `T` of the
//! time, so that the pass must end by `hi · T` after the render started. The time budget is
//! therefore one budget for the whole render, not one per pass.

use crate::driver::iteration_state::IterationState;
use crate::film::Film;
use crate::options::RenderOptions;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Progress of a render.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Fraction done in [0, 1] (by work, or by time under a time budget).
    pub fraction: f64,
    /// Samples (or light paths) done so far in the current pass.
    pub samples: u64,
    /// What the render is doing ("tracing photons", "camera pass", "splatting", …).
    pub pass: &'static str,
    /// Fraction of the current pass's work done, in [0, 1] (by work even under a time budget):
    /// what an estimate of the pass's remaining time extrapolates.
    pub pass_fraction: f64,
}

/// Callbacks and the stop flag of a render.
pub struct RenderControl<'a> {
    /// Set (e.g. by Ctrl-C) to stop after the current pass; the film keeps what was rendered.
    pub stop: &'a AtomicBool,
    pub on_progress: &'a (dyn Fn(Progress) + Sync),
    pub on_checkpoint: &'a (dyn Fn(&Film) + Sync),
    /// After each complete iteration of a progressive render (see [`IterationDone`]).
    pub on_iteration: &'a (dyn Fn(&IterationDone) + Sync),
}

/// What a progressive render hands its caller after each complete iteration: the iterations
/// pooled so far, and on request the render's state (what a state file for `--resume` holds)
/// and the image so far (the pooled film, or for SPPM and PPM the pool with the per-pixel
/// photon statistics added). Both are made only when asked for.
pub struct IterationDone<'a> {
    /// Complete iterations pooled, resumed ones included.
    pub iteration: u64,
    state: &'a dyn Fn() -> IterationState,
    image: &'a dyn Fn() -> Film,
}

impl<'a> IterationDone<'a> {
    pub fn new(
        iteration: u64,
        state: &'a dyn Fn() -> IterationState,
        image: &'a dyn Fn() -> Film,
    ) -> Self {
        Self {
            iteration,
            state,
            image,
        }
    }
    /// The render's state after this iteration.
    pub fn state(&self) -> IterationState {
        (self.state)()
    }
    /// The image after this iteration (radiance, W/m²/sr, as the render's final film).
    pub fn image(&self) -> Film {
        (self.image)()
    }
}

impl RenderControl<'_> {
    /// A control that never stops and reports nothing.
    pub fn silent() -> RenderControl<'static> {
        static NEVER: AtomicBool = AtomicBool::new(false);
        RenderControl {
            stop: &NEVER,
            on_progress: &|_| {},
            on_checkpoint: &|_| {},
            on_iteration: &|_| {},
        }
    }
}

/// The clock of one render: when it started, its time budget and when the last checkpoint was
/// written.
pub struct Clock {
    start: Instant,
    limit: Option<Duration>,
    checkpoint_interval: Option<Duration>,
    /// Milliseconds after `start` of the last checkpoint.
    last_checkpoint_ms: AtomicU64,
}

impl Clock {
    /// Starts the clock of a render with `opts`'s time budget and checkpoint interval.
    pub fn start(opts: &RenderOptions) -> Self {
        Self {
            start: Instant::now(),
            limit: opts.time_limit,
            checkpoint_interval: opts.checkpoint_interval,
            last_checkpoint_ms: AtomicU64::new(0),
        }
    }

    /// A clock without time budget or checkpoints (a progressive iteration's: the driver
    /// around it owns those).
    pub fn untimed() -> Self {
        Self {
            start: Instant::now(),
            limit: None,
            checkpoint_interval: None,
            last_checkpoint_ms: AtomicU64::new(0),
        }
    }

    /// Time since the render started.
    pub fn elapsed(&self) -> Duration {
        self.start.elapsed()
    }

    /// The whole render as one stage.
    pub fn stage<'a>(&'a self, ctl: &'a RenderControl<'a>) -> Stage<'a> {
        Stage {
            ctl,
            clock: self,
            lo: 0.0,
            hi: 1.0,
            label: "rendering",
        }
    }
}

/// A pass's view of the render: its share `[lo, hi]` of the progress bar and of the time
/// budget, the callbacks, the stop flag.
#[derive(Clone, Copy)]
pub struct Stage<'a> {
    pub ctl: &'a RenderControl<'a>,
    clock: &'a Clock,
    lo: f64,
    hi: f64,
    label: &'static str,
}

impl<'a> Stage<'a> {
    /// This stage, reporting its progress as `label` (what the user sees the render doing).
    pub fn labelled(self, label: &'static str) -> Stage<'a> {
        Stage { label, ..self }
    }

    /// The part `[a, b]` (fractions of this stage) of this stage.
    pub fn part(&self, a: f64, b: f64) -> Stage<'a> {
        let w = self.hi - self.lo;
        Stage {
            lo: self.lo + w * a,
            hi: self.lo + w * b,
            ..*self
        }
    }

    /// True under a time budget.
    pub fn timed(&self) -> bool {
        self.clock.limit.is_some()
    }

    /// Reports that the fraction `done` of this stage's work is done (`samples` units of it):
    /// the progress bar shows the time spent under a time budget, else the work done.
    pub fn report(&self, done: f64, samples: u64) {
        let fraction = match self.clock.limit {
            Some(t) => self.clock.elapsed().as_secs_f64() / t.as_secs_f64(),
            None => self.lo + (self.hi - self.lo) * done.clamp(0.0, 1.0),
        };
        (self.ctl.on_progress)(Progress {
            fraction: fraction.min(1.0),
            samples,
            pass: self.label,
            pass_fraction: done.clamp(0.0, 1.0),
        });
    }

    /// [`Stage::report`] for a pass that reports after each wave of work (no sample count):
    /// returns whether it may go on (neither interrupted nor out of its share of the time).
    pub fn report_and_go_on(&self, done: f64) -> bool {
        self.report(done, 0);
        !(self.interrupted() || self.out_of_time())
    }

    /// True once the caller asked the render to stop (Ctrl-C).
    pub fn interrupted(&self) -> bool {
        self.ctl.stop.load(Ordering::Relaxed)
    }

    /// The fraction of this stage's share of the budget used so far, 0 at its start and 1 at
    /// its end (`None` without a budget).
    pub fn time_used(&self) -> Option<f64> {
        self.clock.limit.map(|t| {
            let f = self.clock.elapsed().as_secs_f64() / t.as_secs_f64();
            ((f - self.lo) / (self.hi - self.lo).max(1e-12)).max(0.0)
        })
    }

    /// Time left in this stage's share of the budget (`None` without a budget).
    pub fn time_left(&self) -> Option<Duration> {
        self.clock
            .limit
            .map(|t| t.mul_f64(self.hi).saturating_sub(self.clock.elapsed()))
    }

    /// True once this stage's share of the time budget is spent (never without a budget).
    pub fn out_of_time(&self) -> bool {
        self.clock
            .limit
            .is_some_and(|t| self.clock.elapsed() >= t.mul_f64(self.hi))
    }

    /// Called after each pass of work: true when the stage must end now (interrupted, or out of
    /// time); otherwise hands `film` to the checkpoint callback when a checkpoint is due.
    pub fn end_of_pass(&self, film: &Film) -> bool {
        self.stop_or_checkpoint(|| (self.ctl.on_checkpoint)(film))
    }

    /// [`Stage::end_of_pass`] for a film made only when a checkpoint is due (e.g. the eye
    /// vertices' splats resolved into a copy of the film).
    pub fn end_of_pass_with(&self, film: impl FnOnce() -> Film) -> bool {
        self.stop_or_checkpoint(|| (self.ctl.on_checkpoint)(&film()))
    }

    fn stop_or_checkpoint(&self, write: impl FnOnce()) -> bool {
        if self.interrupted() || self.out_of_time() {
            return true;
        }
        if self.checkpoint_due() {
            write();
        }
        false
    }

    /// True (and the timer restarted) when a checkpoint is due.
    fn checkpoint_due(&self) -> bool {
        let Some(iv) = self.clock.checkpoint_interval else {
            return false;
        };
        let now = self.clock.elapsed().as_millis() as u64;
        let last = self.clock.last_checkpoint_ms.load(Ordering::Relaxed);
        if now.saturating_sub(last) >= iv.as_millis() as u64 {
            self.clock.last_checkpoint_ms.store(now, Ordering::Relaxed);
            true
        } else {
            false
        }
    }
}
