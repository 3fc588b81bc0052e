//! The iteration driver of the progressive methods: iteration after iteration of a one-shot
//! render, each into a fresh film that is then pooled into the image, so only one iteration's
//! photons (or footprints) are alive at a time.
//!
//! The driver owns what spans iterations: the progress bar (an iteration's share of it, or the
//! time), the time budget (the render stops after the iteration that crosses it), the stop flag
//! (Ctrl-C ends the render with the iterations completed; an interrupted first iteration is
//! kept so the image is never empty) and the checkpoints (the pooled image, after an iteration).
//! Each iteration runs under a clock of its own, without budget or checkpoints, so it is a pure
//! function of its options whatever the machine does: the render's bytes depend on the number
//! of iterations, never on when they ran.

use crate::control::{Clock, IterationDone, Progress, RenderControl, Stage};
use crate::driver::iteration_state::IterationState;
use crate::film::Film;
use crate::stats::RenderStats;

/// The iterations a render runs, `first ..= max`, narrowed to its shard's (`opts.shard`, a
/// range of the `max` iterations of the whole render: [`crate::shard`]); a sharded render has a
/// count of iterations, since it refuses time budgets.
pub fn shard_iterations(
    opts: &crate::options::RenderOptions,
    first: u64,
    max: Option<u64>,
) -> (u64, Option<u64>) {
    match (opts.shard, max) {
        (Some(s), Some(total)) => {
            let r = s.range(total);
            (r.start + 1, Some(r.end))
        }
        _ => (first, max),
    }
}

/// The image of a pooled film after iteration `i` (see [`run_iterations`]).
pub type Present<'a> = dyn Fn(&Film, u64) -> Film + 'a;

/// The state of a render whose pooled film is `film` after iteration `i`.
pub type Snapshot<'a> = dyn Fn(&Film, u64) -> IterationState + 'a;

/// What the iterations did.
#[derive(Debug, Default)]
pub struct IterationsRun {
    pub stats: RenderStats,
    /// Iterations pooled into the film by this run (after those it started from).
    pub iterations: u64,
    /// The last iteration pooled (the count of the whole render, resumed ones included).
    pub last: u64,
    /// An iteration was stopped (Ctrl-C) before it completed and dropped.
    pub dropped_partial: bool,
    /// The first iteration was stopped before it completed and kept (the image is never
    /// empty); it is not counted in `iterations`.
    pub kept_partial: bool,
    /// Why the render ended before `max` iterations: "interrupted" or "out of time".
    pub stopped: Option<&'static str>,
}

/// Runs iterations `first, first + 1, …` (numbered from 1) up to `max` (or until the time
/// budget or the stop flag ends them), `iteration(i, stage, film)` rendering iteration `i` into
/// the empty film `film` under its own untimed stage; pools each into `film`. Checkpoints show
/// the pooled film, or `present(film, i)` for a method whose image is more than the pool (SPPM's
/// per-pixel photon statistics after iteration `i`); `snapshot(film, i)` is the render's state
/// after iteration `i`; both are handed to [`crate::RenderControl::on_iteration`] (made only
/// if asked).
pub fn run_iterations(
    film: &mut Film,
    stage: &Stage,
    first: u64,
    max: Option<u64>,
    present: Option<&Present<'_>>,
    snapshot: &Snapshot<'_>,
    mut iteration: impl FnMut(u64, &Stage, &mut Film) -> RenderStats,
) -> IterationsRun {
    let mut run = IterationsRun::default();
    let (w, h) = film.full_size();
    let mut i = first.max(1);
    loop {
        if max.is_some_and(|m| i > m) {
            break;
        }
        // The iteration's share of the progress bar (without a time budget and a count the bar
        // shows iterations as they complete).
        let part = match max {
            Some(m) => {
                let n = (m - first.max(1) + 1) as f64;
                let k = (i - first.max(1)) as f64;
                stage.part(k / n, (k + 1.0) / n)
            }
            None => *stage,
        };
        let forward = move |p: Progress| part.labelled(p.pass).report(p.fraction, p.samples);
        let ctl = RenderControl {
            stop: stage.ctl.stop,
            on_progress: &forward,
            on_checkpoint: &|_| {},
            on_iteration: &|_| {},
        };
        let clock = Clock::untimed();
        let mut f = Film::cropped(film.window(), w, h);
        let st = iteration(i, &clock.stage(&ctl), &mut f);
        run.stats += st;
        if stage.interrupted() {
            run.stopped = Some("interrupted");
            if i > 1 {
                // A partial iteration would weigh its few samples like a whole one.
                run.dropped_partial = true;
            } else {
                // Nothing else to show: keep it, but not as a complete iteration.
                film.merge(&f);
                run.kept_partial = true;
            }
            break;
        }
        film.merge(&f);
        run.iterations += 1;
        run.last = i;
        // The image after iteration `i` (`present` takes the count of iterations pooled), for
        // the caller and for a checkpoint.
        let pooled: &Film = film;
        let image = || match present {
            Some(show) => show(pooled, i),
            None => pooled.clone(),
        };
        (stage.ctl.on_iteration)(&IterationDone::new(i, &|| snapshot(pooled, i), &image));
        let stop = stage.end_of_pass_with(image);
        i += 1;
        if stop {
            run.stopped = Some(if stage.interrupted() {
                "interrupted"
            } else {
                "out of time"
            });
            break;
        }
    }
    if max.is_some_and(|m| i > m) {
        run.stopped = None;
    }
    run
}
