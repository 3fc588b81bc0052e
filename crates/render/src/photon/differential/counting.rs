//! The light paths that yield a number of caustic landings, counted without differentials:
//! photon differential splatting must know their number `N` before the first splat, since the
//! footprints scale with `1/√N` (eq. 5–6).

use super::trace::{LandingTracer, is_caustic_landing};
use crate::photon::adaptive::{AdaptiveRun, run_chains};
use crate::photon::plan::{PathStream, trace_paths};
use crate::photon::visible_points::VisiblePoints;
use crate::stats::RenderStats;
use crate::transport::light_walk::{
    LightEvent, LightMediumVertex, LightScatter, LightVertex, LightVisitor, walk_light_path_at,
};
use crate::transport::limits::PathLimits;
use caustica_core::Vec3;
use caustica_core::sampling::Sampler;

/// The light paths [`trace_photon_differentials`] emits to find `target` caustic landings
/// with a given stream, found without differentials (see [`count_caustic_paths`]).
pub struct CausticPaths {
    /// `N`: the paths emitted (the N of Φ = β/N and of eq. 5–6).
    pub paths: u64,
    /// Caustic landings in them (`target` unless the scene yields fewer).
    pub landings: usize,
    /// The indices (ascending) of the paths with at least one landing, when recorded.
    pub landing_paths: Option<Vec<u64>>,
    pub stats: RenderStats,
}

/// Photon counts up to which photon differential splatting records the landing paths (8 bytes
/// per landing: ≤ 16 MB) so as to re-trace only those; above it, memory stays bounded and
/// every path is traced twice.
pub const RECORD_LANDING_PATHS: usize = 1 << 21;

/// The light paths [`trace_photon_differentials`] emits to find `target` caustic landings in
/// `stream`, traced without differentials and without storing photons: photon differential
/// splatting must know their number `N` before the first splat, since the footprints scale
/// with `1/√N` (eq. 5–6). With `record` it also returns which paths landed, so that only those
/// need tracing again (8 bytes per landing). `progress` receives the fraction of `target` found
/// so far after each wave of paths and returns false to stop counting there (then `N` is the
/// paths counted so far). The paths are `tracer`'s: its scene, time rule and emission.
pub fn count_caustic_paths(
    tracer: &LandingTracer,
    target: usize,
    stream: &PathStream,
    limits: &PathLimits,
    record: bool,
    progress: &mut dyn FnMut(f64) -> bool,
) -> CausticPaths {
    let mut progress = |found: usize| progress(found as f64 / target.max(1) as f64);
    if record {
        let (mut found, paths, stats) =
            landings(tracer, target, stream, limits, &mut progress, |path| path);
        let landings = found.len();
        found.dedup();
        return CausticPaths {
            paths,
            landings,
            landing_paths: Some(found),
            stats,
        };
    }
    // Too many to record: count only (a zero-sized record per landing).
    let (found, paths, stats) = landings(tracer, target, stream, limits, &mut progress, |_| ());
    CausticPaths {
        paths,
        landings: found.len(),
        landing_paths: None,
        stats,
    }
}

/// `record(path)` once per caustic landing, in path order, until `target` of them.
fn landings<P: Copy + Send>(
    tracer: &LandingTracer,
    target: usize,
    stream: &PathStream,
    limits: &PathLimits,
    progress: &mut dyn FnMut(usize) -> bool,
    record: impl Fn(u64) -> P + Sync,
) -> (Vec<P>, u64, RenderStats) {
    trace_paths(target, stream, 0, progress, |path, sampler, out, st| {
        let r = record(path);
        let mut count = Count {
            out,
            record: move |_: &LightVertex| r,
        };
        walk_light_path_at(
            tracer.scene,
            sampler,
            limits,
            st,
            &mut count,
            tracer.time,
            tracer.emission,
        )
    })
}

/// Adaptive photon tracing's counting pass ([`crate::photon::adaptive`]): `steps` chain steps
/// over `tracer`'s light paths from `first` on, a path visible when one of its caustic landings
/// lies near a visible point; each state keeps its landings' positions. The splatting pass
/// replays the states ([`crate::photon::plan::PathSet::States`]).
pub fn count_adaptive(
    tracer: &LandingTracer,
    steps: u64,
    stream: &PathStream,
    first: u64,
    limits: &PathLimits,
    visible: &VisiblePoints,
) -> AdaptiveRun<Vec3> {
    run_chains(
        stream,
        first,
        steps,
        true,
        &|points: &[Vec3]| points.iter().any(|&p| visible.near(p)),
        &|sampler, out, st| {
            walk_light_path_at(
                tracer.scene,
                sampler,
                limits,
                st,
                &mut Count {
                    out,
                    record: |lv: &LightVertex| lv.v.si.p,
                },
                tracer.time,
                tracer.emission,
            )
        },
    )
}

/// Pushes `record(landing)` once per caustic landing of the path.
struct Count<'a, P, F> {
    out: &'a mut Vec<P>,
    record: F,
}

impl<P, F: Fn(&LightVertex) -> P> LightVisitor for Count<'_, P, F> {
    fn event(&mut self, event: LightEvent, _: &mut Sampler, _: &mut RenderStats) {
        if let LightEvent::Vertex(lv) = event
            && is_caustic_landing(lv)
        {
            self.out.push((self.record)(lv));
        }
    }
    fn scatter(&mut self, sc: &LightScatter, _: &mut RenderStats) -> bool {
        sc.keeps_caustic() // as the photon-differential tracer
    }
    fn scatter_in_medium(
        &mut self,
        _: &LightMediumVertex,
        _: &caustica_scene::phase::PhaseSample,
    ) -> bool {
        false
    }
}
