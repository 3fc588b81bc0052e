//! The progressive methods as rules over the one-shot ones: each iteration is an independent
//! one-shot render (its own light paths and camera samples,
//! [`ProgressiveSettings::iteration_options`]) at the iteration's bandwidth from the one
//! schedule ([`BandwidthSchedule`], seed 001 eq. 3.27), and the image is the mean of the
//! iterations ([`run_iterations`]). Only the current iteration's photons are alive.
//!
//! * `pppm` — probabilistic progressive photon mapping (Knaus and Zwicker 2011; seed 001's
//!   "PPPM"): `pm` with a fixed-radius caustic estimate at the global radius
//!   `r²_{i+1} = r²_i (i + α)/(i + 1)` (`V(r) ∝ r²`), and the global map's fixed radius shrunk
//!   by the same rule, so direct light (NEE), caustics and the final gather's indirect light
//!   all converge. No per-pixel state.
//! * `ppds` — progressive photon differential splatting: `pds` whose smoothing shrinks by the
//!   same rule applied to the footprint area, `s²_{i+1} = s²_i (i + α)/(i + 1)` (a footprint's
//!   area is ∝ s², seed 002 eq. 4), each iteration a fresh batch of footprints splatted and
//!   dropped. Sharp from the first iteration (footprints adapt to the photon density) and
//!   consistent (the smoothing goes to 0 while the footprints' count grows).
//! * `ppdm` — the same schedule over `pdm` (footprints gathered instead of splatted).
//! * `pdpm` — the same schedule over `dpm`: its bandwidth h (the support of the diffused
//!   kernel, area ∝ h²) shrinks as `pppm`'s radius, q and the steepness stay, and the noise
//!   scale keeps its ratio to h (h/2 unless given). The diffused kernel lies inside the disc of
//!   radius h and integrates to 1, so its bias vanishes with h as the fixed kernel's does.
//!
//! Initial bandwidths: `pppm`'s radius (and `pdpm`'s h) is `--radius` or the median distance
//! from a caustic photon of the first iteration to its k-th nearest neighbour (`--k`, a pilot
//! over that iteration's own photons); the global map's, the same with `--global-k`; the
//! footprints' smoothing is `--smoothing`.

use super::IntegratorKind;
use super::photon_mapping::{self, PhotonMaps};
use super::photon_splatting;
use crate::control::Stage;
use crate::driver::iteration_state::{IterationState, resume_pooled};
use crate::driver::iterations::{run_iterations, shard_iterations};
use crate::error::OptionError;
use crate::film::Film;
use crate::filter::Filter;
use crate::options::{Bandwidth, CausticEstimator, NoiseScale, RenderOptions, Smoothing};
use crate::stats::RenderStats;
use caustica_density::estimator::median_knn_radius;
use caustica_density::{BandwidthSchedule, KernelVolume};
use caustica_scene::Scene;

/// The one-shot method a progressive one iterates.
pub fn one_shot(kind: IntegratorKind) -> Option<IntegratorKind> {
    // (SPPM is not iterations of a one-shot method: see `sppm.rs`.)
    match kind {
        IntegratorKind::ProgressivePhotonMapping => Some(IntegratorKind::PhotonMapping),
        IntegratorKind::ProgressiveSplatting => Some(IntegratorKind::PhotonDifferentialSplatting),
        IntegratorKind::ProgressiveDifferentialMapping => {
            Some(IntegratorKind::PhotonDifferentialMapping)
        }
        IntegratorKind::ProgressiveDiffusion => Some(IntegratorKind::DiffusionPhotonMapping),
        _ => None,
    }
}

/// True for the methods whose caustic bandwidth is a radius (`--radius` or the k-NN pilot).
fn radius_method(kind: IntegratorKind) -> bool {
    matches!(
        kind,
        IntegratorKind::ProgressivePhotonMapping | IntegratorKind::ProgressiveDiffusion
    )
}

/// The first iteration's bandwidths and their schedules.
struct Schedules {
    /// `pppm`'s caustic radius (m), `pdpm`'s bandwidth h (m), or the footprints' smoothing s.
    caustic: BandwidthSchedule,
    /// The global map's radius (m), when there is a global map.
    global: Option<BandwidthSchedule>,
}

impl Schedules {
    fn new(
        scene: &Scene,
        kind: IntegratorKind,
        opts: &RenderOptions,
        notes: &mut Vec<String>,
    ) -> Result<Self, OptionError> {
        let p = &opts.photons;
        let alpha = p.progressive.alpha;
        let first = p.progressive.iteration_options(opts, 1);
        // A pilot over the first iteration's own photons (the same paths it traces).
        let wants_radius = radius_method(kind) && p.progressive.radius.is_none();
        let wants_global = PhotonMaps::wants_global(&first);
        let (mut r_caustic, mut r_global) = (None, None);
        if wants_radius || wants_global {
            let mut pilot = first.clone();
            // The pilot only needs the photons: a plain k-NN map, whatever the method estimates.
            pilot.photons.caustic_estimator = None;
            if !wants_radius {
                pilot.photons.light_paths = Some(1);
            }
            if !wants_global {
                pilot.photons.global_light_paths = None;
                pilot.photons.global_photons = 0;
            }
            let maps = PhotonMaps::build(scene, &pilot);
            let points =
                |m: &crate::photon::map::PhotonMap, k| median_knn_radius(&m.points(&p.estimate), k);
            if wants_radius
                && let crate::photon::caustic::CausticEstimate::Density { map, .. } = &maps.caustic
            {
                r_caustic = points(map, p.estimate.k);
            }
            if wants_global {
                r_global = points(&maps.global, p.global_estimate().k);
            }
        }
        let fallback = || (scene.geometry.bounds().extent().length() * 1e-3).max(1e-6);
        let caustic_h1 = match kind {
            _ if radius_method(kind) => match (p.progressive.radius, r_caustic) {
                (Some(r), _) => r.get(),
                (None, Some(r)) => r,
                (None, None) => {
                    notes.push(format!(
                        "warning: no caustic photons in the first iteration to choose a radius from; using {:.4} m",
                        fallback()
                    ));
                    fallback()
                }
            },
            _ => p.footprints.smoothing.get(),
        };
        let schedule = |h1: f32| {
            BandwidthSchedule::new(h1 as f64, alpha, KernelVolume::AREA).map_err(|e| {
                OptionError::Invalid {
                    what: "the progressive schedule",
                    rule: "alpha in (0, 1] and a positive initial bandwidth",
                    got: e.to_string(),
                }
            })
        };
        let global = if wants_global {
            Some(schedule(r_global.unwrap_or_else(fallback))?)
        } else {
            None
        };
        Ok(Self {
            caustic: schedule(caustic_h1)?,
            global,
        })
    }

    /// Iteration `i`'s options: `opts` over its window with its bandwidths.
    fn options(&self, kind: IntegratorKind, opts: &RenderOptions, i: u64) -> RenderOptions {
        let mut o = opts.photons.progressive.iteration_options(opts, i);
        let h = self.caustic.bandwidth(i) as f32;
        // How far the bandwidth has shrunk: lengths tied to it shrink alike.
        let ratio = h / self.caustic.bandwidth(1) as f32;
        match kind {
            IntegratorKind::ProgressivePhotonMapping => {
                o.photons.caustic_estimator = Some(CausticEstimator::Fixed);
                o.photons.bandwidth = Bandwidth::new(h).ok();
            }
            IntegratorKind::ProgressiveDiffusion => {
                // (The iterations are dpm renders: the estimator is the diffusion one.)
                o.photons.bandwidth = Bandwidth::new(h).ok();
                // An explicit noise scale keeps its ratio to the bandwidth (the default, h/2,
                // follows it by itself).
                let d = &mut o.photons.diffusion;
                d.noise_scale = d
                    .noise_scale
                    .and_then(|n| NoiseScale::new(n.get() * ratio).ok());
            }
            _ => {
                if let Ok(s) = Smoothing::new(h) {
                    o.photons.footprints.smoothing = s;
                }
                // Footprints scale with the smoothing (seed 002 eq. 5–6): so does their floor,
                // which therefore vanishes with it (consistency).
                let f = &mut o.photons.footprints;
                f.min_semi_axis = f.min_semi_axis.map(|r| r * ratio);
            }
        }
        o.photons.global_bandwidth = self
            .global
            .as_ref()
            .and_then(|g| Bandwidth::new(g.bandwidth(i) as f32).ok());
        o
    }
}

/// Renders with progressive method `kind` into `film`.
pub(crate) fn render(
    scene: &Scene,
    kind: IntegratorKind,
    opts: &RenderOptions,
    stage: &Stage,
    film: &mut Film,
    filter: &Filter,
    notes: &mut Vec<String>,
) -> Result<(RenderStats, Option<IterationState>), OptionError> {
    let p = &opts.photons.progressive;
    let schedules = Schedules::new(scene, kind, opts, notes)?;
    let max = p.max_iterations(opts);
    // Resuming: the pooled film of the iterations done, then on from the next one.
    let (first, fp) = resume_pooled(scene, kind, opts, film, notes)?;
    let (first, max) = shard_iterations(opts, first, max);
    let mut first_notes = Vec::new();
    let snapshot = |f: &Film, i: u64| IterationState::pooled(&fp, i, f);
    let run = run_iterations(film, stage, first, max, None, &snapshot, |i, st, f| {
        let o = schedules.options(kind, opts, i);
        let mut n = Vec::new();
        let stats = match kind {
            IntegratorKind::ProgressiveSplatting => {
                photon_splatting::render(scene, &o, st, f, filter, &mut n)
            }
            _ => {
                let inner = one_shot(kind).unwrap_or(IntegratorKind::PhotonMapping);
                photon_mapping::render(scene, &o, st, f, filter, &mut n, |pr| {
                    PhotonMaps::for_integrator(scene, inner, &o, pr)
                })
            }
        };
        if i == first {
            first_notes = n;
        }
        stats
    });
    notes.extend(
        first_notes
            .into_iter()
            .map(|n| format!("iteration {first}: {n}")),
    );
    let done = if run.iterations > 0 {
        run.last
    } else {
        first - 1
    };
    // Complete iterations in the film (an interrupted first iteration kept alone is not one).
    let complete = done;
    let name = match kind {
        IntegratorKind::ProgressivePhotonMapping => "radius",
        IntegratorKind::ProgressiveDiffusion => "bandwidth h",
        _ => "smoothing s",
    };
    notes.push(format!(
        "progressive: {done} iterations of {} light paths per map, alpha {:.4}; {name} {:.5} -> {:.5}{}{}{}",
        p.paths_per_iteration,
        p.alpha,
        schedules.caustic.bandwidth(1),
        schedules.caustic.bandwidth(done.max(1)),
        schedules.global.as_ref().map_or(String::new(), |g| format!(
            ", global radius {:.5} -> {:.5} m",
            g.bandwidth(1),
            g.bandwidth(done.max(1))
        )),
        match run.stopped {
            Some(why) => format!(", stopped {why}"),
            None => String::new(),
        },
        if run.dropped_partial {
            " (the interrupted iteration dropped)"
        } else if run.kept_partial {
            " (the interrupted first iteration kept, partly rendered)"
        } else {
            ""
        },
    ));
    let state = (complete > 0).then(|| snapshot(film, complete));
    Ok((run.stats, state))
}
