//! Photon differential splatting (`pds`, seed 002 sec. 3.3): the estimate of photon
//! differential mapping (eq. 10–12) evaluated the other way round. `pdm` loops over the camera
//! samples and gathers the footprints around each; `pds` first records the camera samples'
//! first non-delta vertices in an eye-path map ([`EyeMap`]), then traces the caustic photons
//! in batches and splats each one's footprint onto the eye vertices it covers, then drops it.
//! Memory therefore does not grow with the photon count: the eye map has one vertex per camera
//! sample, a batch holds the photons of a fixed number of light paths.
//!
//! 1. The global map (if the render wants indirect light) as for `pm`.
//! 2. The camera pass: `pm`'s camera paths ([`photon_mapping::radiance_with`]) with direct and
//!    indirect light as there; where `pm` would add the caustic estimate, the vertex is
//!    recorded instead (several per pixel: one per camera sample, the anti-aliasing).
//! 3. The number `N` of light paths: `--light-paths N` (the seed's N_e), or the number that
//!    yields `--photons` caustic landings, counted without differentials
//!    ([`count_caustic_paths`]): the footprints scale with `1/√N` (eq. 5–6), so `N` must be
//!    known before the first splat. These are the paths of `pdm`, so `pdm` and
//!    `pds` use the same photons. Up to [`RECORD_LANDING_PATHS`] photons the count also notes
//!    which paths landed (8 bytes each), and only those are traced again; most paths of a
//!    low-yield scene (the glass sphere: 0.4 %) never reach a specular surface.
//! 4. Paths `0..N` traced as photon differentials in batches of fixed chunks (in parallel);
//!    each batch's photons splatted in path order by the eye map's tiles in parallel, each tile
//!    adding to its own vertices' accumulators, so the image does not depend on the thread
//!    count. Steps 2–5 are the eye-splat driver ([`crate::driver::eye_splat`]); this file is
//!    its rule for footprints ([`FootprintSplat`]).
//! 5. Each camera sample's pixel receives `β · Σ splats` of its vertex.
//!
//! Under a time budget `T` the camera pass still takes `spp` samples per pixel (it is not a
//! pass that runs on: more camera samples would only grow the eye map, its memory and the
//! splatting cost, not lower the caustic's noise), ending early if 0.4 T runs out first; the
//! count may use half of the time left after it, and the splatting ends by T; splatting stopped after `M < N` of the paths (time, Ctrl-C) scales the splats by
//! `N / M`, the estimate of the `M` paths splatted (their footprints keep the size of `N`).

use super::IntegratorKind;
use super::photon_mapping::{self, PhotonMaps};
use crate::control::Stage;
use crate::driver::eye_splat::{SplatRule, eye_pass, resolve, splat_batches};
use crate::exact_sum::ExactSum;
use crate::film::Film;
use crate::filter::Filter;
use crate::options::EmissionStrategy;
use crate::options::RenderOptions;
use crate::photon::adaptive::chain_steps;
use crate::photon::caustic::CAUSTIC_STREAM;
use crate::photon::differential::{
    DiffPhoton, EMISSION_PARAMS, FootprintFilter, Landing, LandingTracer, MadePhotons,
    RECORD_LANDING_PATHS, TEMPORAL_PARAMS, count_adaptive, count_caustic_paths,
    photons_from_landings, unit_budget, widened_note,
};
use crate::photon::eye_map::EyeVertex;
use crate::photon::plan::{CHUNK, PathSet, PathStream, PhotonBudget};
use crate::photon::tracer::NO_CAUSTIC_PATHS;
use crate::photon::visible_points::VisiblePoints;
use crate::stats::RenderStats;
use crate::transport::emission::caustic_emission_notes;
use caustica_core::sampling::Sampler;
use caustica_core::{Spectrum, Vec3};
use caustica_scene::Scene;
use caustica_scene::bsdf::TransportMode;
use std::time::Instant;

/// Shares of the render (progress bar and time budget) of the passes: the global map, the
/// camera pass, counting the light paths; the splatting pass has the rest.
const GLOBAL_END: f64 = 0.05;
const EYE_END: f64 = 0.4;
const COUNT_END: f64 = 0.5;
/// Under a time budget: the share of the time left after the camera pass that counting may use.
const COUNT_SHARE_OF_TIME_LEFT: f64 = 0.5;

/// What a `pds` render did, for its notes and for tests.
#[derive(Clone, Debug, Default)]
pub struct PdsReport {
    /// Eye vertices recorded by the camera pass, and their memory (bytes).
    pub eye_vertices: usize,
    pub eye_bytes: usize,
    /// Light paths of the pass (N) and the caustic landings in them.
    pub paths: u64,
    pub landings: usize,
    /// Light paths splatted (M ≤ N; fewer when stopped).
    pub paths_splatted: u64,
    pub photons: u64,
    pub collapsed: u64,
    pub failed: u64,
    /// Footprints widened by the minimum semi-axis.
    pub widened: u64,
    pub splats: u64,
    /// Photons in the global map.
    pub global_photons: usize,
    /// Seconds of the passes.
    pub global_secs: f64,
    pub eye_secs: f64,
    pub count_secs: f64,
    pub splat_secs: f64,
    /// Set when the render stopped before every path was splatted.
    pub stopped: Option<&'static str>,
    /// The adaptive sampler's note (`--emission adaptive`).
    pub adaptive: Option<String>,
}

/// Renders `scene` by photon differential splatting into `film`; returns the statistics and
/// appends the notes for the user.
pub fn render(
    scene: &Scene,
    opts: &RenderOptions,
    stage: &Stage,
    film: &mut Film,
    filter: &Filter,
    notes: &mut Vec<String>,
) -> RenderStats {
    let (stats, report, warnings) = render_report(scene, opts, stage, film, filter);
    notes.extend(report_notes(scene, &report, opts));
    notes.extend(warnings.iter().map(|w| format!("warning: {w}")));
    stats
}

/// [`render`] returning what it did instead of notes: the statistics, the report, the warnings.
pub fn render_report(
    scene: &Scene,
    opts: &RenderOptions,
    stage: &Stage,
    film: &mut Film,
    filter: &Filter,
) -> (RenderStats, PdsReport, Vec<String>) {
    let mut report = PdsReport::default();
    let t = Instant::now();
    let global_stage = stage
        .part(0.0, GLOBAL_END)
        .labelled("tracing global photons");
    let maps = PhotonMaps::for_integrator(
        scene,
        IntegratorKind::PhotonDifferentialSplatting,
        opts,
        &mut |f| global_stage.report_and_go_on(f),
    );
    report.global_secs = t.elapsed().as_secs_f64();
    report.global_photons = maps.global.len();
    let mut stats = maps.stats;
    let mut warnings = Vec::new();

    // 2. Camera pass and eye map.
    let t = Instant::now();
    let cam = &scene.camera;
    // The camera pass has a fixed size whatever the budget (see the module docs).
    let eye_opts = RenderOptions {
        time_limit: None,
        ..opts.clone()
    };
    let (eye, st) = eye_pass(
        film,
        filter,
        &eye_opts,
        &stage.part(GLOBAL_END, EYE_END).labelled("camera pass"),
        |sampler, raster, pixel, out: &mut Vec<EyeVertex>, st| {
            let u_lens = sampler.next_2d();
            let time = scene.sample_time(|| sampler.next_1d());
            let ray = cam.generate_ray(raster, u_lens).ray.at_time(time);
            photon_mapping::radiance_with(scene, &maps, ray, sampler, opts, st, &mut |v, beta| {
                out.push(EyeVertex::new(v, beta, pixel));
                Spectrum::ZERO
            })
        },
    );
    stats += st;
    report.eye_vertices = eye.len();
    report.eye_bytes = eye.memory_bytes();
    report.eye_secs = t.elapsed().as_secs_f64();
    warnings.extend(maps.warnings.iter().cloned());
    // Stopped (Ctrl-C) from here on, the count and the splatting each still do one wave, so the
    // image written has a caustic, scaled by N/M like any stopped splatting.

    // 3. How many light paths: the budget N_e, or as many as make the requested photons.
    // Under a time budget the camera pass took what its fixed size needed; the count may use
    // half of what is left, the splatting the rest.
    let (count_start, count_end) = match stage.time_used() {
        Some(used) if used < 1.0 => (used, used + (1.0 - used) * COUNT_SHARE_OF_TIME_LEFT),
        Some(_) => (1.0, 1.0),
        None => (EYE_END, COUNT_END),
    };
    let t = Instant::now();
    let stream = PathStream::new(opts, CAUSTIC_STREAM);
    let tracer = LandingTracer::new(scene, &unit_budget(opts.photons.footprints.smoothing))
        .with_time(&opts.photons.footprints, scene)
        .with_wavelength(&opts.photons.footprints, scene)
        .with_emission(opts.photons.emission.caustic_rule());
    let counted;
    let chains;
    let work = match opts.photons.caustic_budget() {
        // Visibility-driven adaptive photon tracing: chains toward landings near the camera's
        // visible points; the splatting replays their states.
        budget if opts.photons.emission == EmissionStrategy::Adaptive => {
            let visible = VisiblePoints::from_camera(scene, opts);
            chains = count_adaptive(
                &tracer,
                chain_steps(budget),
                &stream,
                opts.photons.first_path,
                &opts.limits,
                &visible,
            );
            stats.rays += chains.stats.rays;
            report.paths = chains.paths();
            report.landings = chains
                .states
                .iter()
                .map(|s| s.records.len() * s.count as usize)
                .sum();
            report.adaptive = Some(chains.note(&visible));
            if chains.visible == 0 {
                warnings.push(format!(
                    "adaptive photon tracing: none of {} light paths landed near a visible point through glass or mirrors",
                    chains.uniform
                ));
            }
            PathSet::States {
                states: &chains.states,
                n: report.paths,
            }
        }
        PhotonBudget::Paths(n) => {
            report.paths = n;
            PathSet::Range {
                first: opts.photons.first_path,
                n,
            }
        }
        PhotonBudget::Records(target) => {
            let count_stage = stage
                .part(count_start, count_end)
                .labelled("counting light paths");
            counted = count_caustic_paths(
                &tracer,
                target,
                &stream,
                &opts.limits,
                target <= RECORD_LANDING_PATHS,
                &mut |f| count_stage.report_and_go_on(f),
            );
            stats.rays += counted.stats.rays;
            report.paths = counted.paths;
            report.landings = counted.landings;
            if counted.landings < target {
                warnings.push(format!(
                    "only {} caustic photons found after {} light paths (requested {target}){}",
                    counted.landings,
                    counted.paths,
                    if counted.landings == 0 {
                        format!(": {NO_CAUSTIC_PATHS}")
                    } else {
                        String::new()
                    }
                ));
            }
            // The paths to trace with differentials: those that landed when they were recorded
            // (most paths of a low-yield scene never reach a specular surface), else all.
            match &counted.landing_paths {
                Some(list) => PathSet::Listed {
                    list,
                    first: 0,
                    n: counted.paths,
                },
                None => PathSet::Range {
                    first: 0,
                    n: counted.paths,
                },
            }
        }
    };
    report.count_secs = t.elapsed().as_secs_f64();

    // 4. Trace and splat; 5. into the pixels.
    let t = Instant::now();
    let rule = FootprintSplat {
        opts,
        stream,
        work,
        filter: FootprintFilter::new(&opts.photons.footprints),
        tracer,
    };
    let done = splat_batches(
        film,
        &eye,
        &rule,
        &stage.part(count_end, 1.0).labelled("splatting"),
        opts.shard,
    );
    resolve(film, &eye, &rule, &done.acc, done.chunks_done);
    stats.rays += done.stats.rays;
    stats.nonfinite += done.stats.nonfinite;
    report.splat_secs = t.elapsed().as_secs_f64();
    report.paths_splatted = rule.work.covered(done.chunks_done);
    report.photons = done.totals.photons;
    report.collapsed = done.totals.collapsed;
    report.failed = done.totals.failed;
    report.widened = done.totals.widened;
    report.splats = done.splats;
    if let PhotonBudget::Paths(_) = opts.photons.caustic_budget() {
        report.landings =
            (done.totals.photons + done.totals.collapsed + done.totals.failed) as usize;
        if report.landings == 0 && done.chunks_done == rule.work.chunks() {
            warnings.push(format!(
                "no caustic photons in {} light paths: {NO_CAUSTIC_PATHS}",
                report.paths
            ));
        }
    }
    if done.chunks_done < rule.work.chunks() {
        report.stopped = Some(if stage.interrupted() {
            "interrupted"
        } else {
            "out of time"
        });
    }
    (stats, report, warnings)
}

/// Tag of the stream positioning the sampler while it replays an adaptive chain's state (its
/// numbers all come from the state; the tag only keeps the positioning distinct).
const REPLAY_STREAM_TAG: u64 = 0x5E9A_11ED;

/// The notes of a `pds` render.
fn report_notes(scene: &Scene, r: &PdsReport, opts: &RenderOptions) -> Vec<String> {
    let splat_secs = r.splat_secs.max(1e-9);
    let mut notes = vec![format!(
        "photon differential splatting: eye map {} vertices ({:.1} MB) in {:.2} s; {} caustic photons from {} light paths (counted in {:.2} s){}; global map {} photons in {:.2} s",
        r.eye_vertices,
        r.eye_bytes as f64 / 1e6,
        r.eye_secs,
        r.landings,
        r.paths,
        r.count_secs,
        match r.stopped {
            Some(why) => format!(
                ", stopped {why} after {} paths (splats scaled by N/M)",
                r.paths_splatted
            ),
            None => String::new(),
        },
        r.global_photons,
        r.global_secs,
    )];
    notes.push(format!(
        "splatting: smoothing s = {}, {} photons splatted, {} dropped with a collapsed footprint, {} dropped where the differential could not be propagated{}; {} splats in {splat_secs:.2} s ({:.2} M photons/s, {:.2} M splats/s), {:.1} splats per photon",
        opts.photons.footprints.smoothing,
        r.photons,
        r.collapsed,
        r.failed,
        widened_note(r.widened, opts.photons.footprints.min_semi_axis),
        r.splats,
        r.photons as f64 / splat_secs / 1e6,
        r.splats as f64 / splat_secs / 1e6,
        r.splats as f64 / r.photons.max(1) as f64,
    ));
    notes.extend(r.adaptive.clone());
    if r.paths > 0 {
        notes.extend(caustic_emission_notes(
            scene,
            opts.photons.emission.caustic_rule(),
            r.landings,
            r.paths,
        ));
    }
    notes
}

/// A vertex's splat sum (W/m²/sr times the sample's count of 1): the contributions of the
/// current chunk of light paths summed in f64, in path order, and folded into an exact total
/// ([`ExactSum`]) when a photon of a later chunk arrives (and when read). Each chunk's partial sum
/// is a pure function of that chunk's photons and the total is exact, so the vertex's sum does
/// not depend on how chunks are grouped into batches, threads or shards, while the hot path stays
/// one f64 addition per channel (an exact sum per splat cost pds's splatting pass 60 %:
/// docs/performance.md).
#[derive(Clone, Copy, Debug, Default)]
pub struct ChunkedSum {
    partial: [f64; 3],
    /// The chunk `partial` belongs to.
    chunk: u32,
    total: [ExactSum; 3],
}

impl ChunkedSum {
    /// Adds `c`, a contribution from a photon of chunk `chunk` (chunks arrive in increasing
    /// order).
    #[inline]
    pub fn add(&mut self, chunk: u32, c: [f64; 3]) {
        if chunk != self.chunk {
            self.fold();
            self.chunk = chunk;
        }
        for (p, c) in self.partial.iter_mut().zip(c) {
            *p += c;
        }
    }

    fn fold(&mut self) {
        for (t, p) in self.total.iter_mut().zip(self.partial) {
            *t += ExactSum::from_f64(p);
        }
        self.partial = [0.0; 3];
    }

    /// The sum of every contribution.
    pub fn sum(&self) -> [ExactSum; 3] {
        let mut s = *self;
        s.fold();
        s.total
    }
}

/// Adds the reflected radiance of footprint `ph` (from a light path of chunk `chunk`) at eye
/// vertex `v` times the vertex's throughput, `β f_r π K(|M_p (x − x_p)|) Φ_p / A_p` (W/m²/sr,
/// seed 002 eq. 10–12 with `filter`), to `acc`; true if it reached the vertex with a finite,
/// non-zero value.
#[inline]
pub fn splat_footprint(
    filter: &FootprintFilter,
    ph: &DiffPhoton,
    chunk: u32,
    v: &EyeVertex,
    acc: &mut ChunkedSum,
) -> bool {
    let Some(w) = filter.weight(ph, v.p, v.n) else {
        return false;
    };
    let f = v
        .bsdf
        .eval(v.wo, v.frame.to_local(ph.wi), TransportMode::Radiance);
    let l = f * ph.flux * w;
    if l.is_finite() && !l.is_black() {
        // β times the f32 radiance is exact in f64.
        acc.add(
            chunk,
            std::array::from_fn(|k| v.beta.c[k] as f64 * l.c[k] as f64),
        );
        true
    } else {
        false
    }
}

/// A photon of the splatting pass with the chunk of light paths it came from.
pub struct ChunkPhoton {
    pub chunk: u32,
    pub photon: DiffPhoton,
}

/// Counts of one chunk of the splatting pass.
#[derive(Clone, Copy, Debug, Default)]
pub struct ChunkTotals {
    pub photons: u64,
    pub collapsed: u64,
    pub failed: u64,
    pub widened: u64,
}

impl std::ops::AddAssign for ChunkTotals {
    fn add_assign(&mut self, o: Self) {
        self.photons += o.photons;
        self.collapsed += o.collapsed;
        self.failed += o.failed;
        self.widened += o.widened;
    }
}

/// The splat rule of photon differential splatting: photons are footprints (seed 002 eq. 4,
/// 12), a vertex accumulates `β f_r π K(|M_p (x − x_p)|) Φ_p / A_p` (W/m²/sr, eq. 10 times the
/// throughput β) for every footprint that reaches it ([`FootprintFilter::weight`], the rule
/// `pdm` gathers with) into a [`ChunkedSum`], and resolves to that sum unrounded.
pub struct FootprintSplat<'a> {
    pub opts: &'a RenderOptions,
    pub stream: PathStream,
    /// The light paths, `N` of them (the N of Φ = β/N and of eq. 5–6).
    pub work: PathSet<'a>,
    pub filter: FootprintFilter,
    /// The light-path tracer for the unit budget (built once for all chunks).
    pub tracer: LandingTracer<'a>,
}

impl FootprintSplat<'_> {
    /// The photons of chunk `c`'s paths with `N` differential parameters, and the counts of
    /// collapsed, failed and widened landings.
    fn trace_landings<const N: usize>(&self, c: u64, st: &mut RenderStats) -> MadePhotons {
        let mut landings: Vec<Landing<N>> = Vec::new();
        let mut sampler = Sampler::new(self.stream.sampler, self.stream.seed);
        self.work.for_each_path(c, |path| {
            sampler.start_path(self.stream.stream, path);
            self.tracer
                .trace::<N>(&mut sampler, &self.opts.limits, &mut landings, st);
        });
        // Adaptive photon tracing's states: each replayed once, its landings weighted by how
        // many chain steps it stood for.
        for (i, s) in self.work.states_of_chunk(c).iter().enumerate() {
            sampler.start_path(self.stream.stream ^ REPLAY_STREAM_TAG, c * CHUNK + i as u64);
            sampler.replay_primary(s.primary.clone());
            let before = landings.len();
            self.tracer
                .trace::<N>(&mut sampler, &self.opts.limits, &mut landings, st);
            sampler.take_primary();
            for l in &mut landings[before..] {
                l.beta *= s.count as f32;
            }
        }
        photons_from_landings(
            &landings,
            self.work.len(),
            self.tracer.sweep_column(),
            self.opts.photons.footprints.min_semi_axis,
        )
    }
}

impl SplatRule for FootprintSplat<'_> {
    type Photon = ChunkPhoton;
    type Acc = ChunkedSum;
    type Totals = ChunkTotals;

    fn empty(&self) -> ChunkedSum {
        ChunkedSum::default()
    }

    fn chunks(&self) -> u64 {
        self.work.chunks()
    }

    fn trace_chunk(&self, c: u64, st: &mut RenderStats) -> (Vec<ChunkPhoton>, ChunkTotals) {
        let made = if self.tracer.has_third_column() {
            self.trace_landings::<TEMPORAL_PARAMS>(c, st)
        } else {
            self.trace_landings::<EMISSION_PARAMS>(c, st)
        };
        let totals = ChunkTotals {
            photons: made.photons.len() as u64,
            collapsed: made.collapsed,
            failed: made.failed,
            widened: made.widened,
        };
        let chunk = c as u32;
        let photons = made
            .photons
            .into_iter()
            .map(|photon| ChunkPhoton { chunk, photon })
            .collect();
        (photons, totals)
    }

    fn bounds(&self, p: &ChunkPhoton) -> Option<(Vec3, Vec3)> {
        self.filter.bounds(&p.photon)
    }

    #[inline]
    fn splat(&self, p: &ChunkPhoton, v: &EyeVertex, acc: &mut ChunkedSum) -> bool {
        splat_footprint(&self.filter, &p.photon, p.chunk, v, acc)
    }

    fn resolve(&self, _: &EyeVertex, acc: &ChunkedSum, chunks_done: u64) -> [ExactSum; 3] {
        // Stopped after M < N paths: the estimate of the M paths splatted (flux β/M).
        let covered = self.work.covered(chunks_done);
        let acc = acc.sum();
        if covered == 0 || covered >= self.work.len() {
            acc
        } else {
            let scale = self.work.len() as f64 / covered as f64;
            acc.map(|a| ExactSum::from_f64(a.to_f64() * scale))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::photon::eye_map::EyeMap;
    use caustica_core::Frame;
    use caustica_density::kernel::Kernel;
    use caustica_differentials::Footprint;
    use caustica_scene::bsdf::{Bsdf, Lambertian};
    use std::f32::consts::PI;

    const ALBEDO: f32 = 0.5;

    /// A vertex on the floor y = 0 (normal +y) seen from straight above.
    fn vertex(p: Vec3, n: Vec3, pixel: u32) -> EyeVertex {
        let frame = Frame::from_normal(n);
        EyeVertex {
            p,
            n,
            wo: frame.to_local(n),
            frame,
            bsdf: Bsdf::Lambertian(Lambertian::new(Spectrum::splat(ALBEDO))),
            beta: Spectrum::ONE,
            pixel,
        }
    }

    /// A photon of flux 2 W landing at the origin from straight above, footprint semi-axes
    /// 0.2 m along x and 0.05 m along z (D x = twice the semi-axes).
    fn photon() -> DiffPhoton {
        DiffPhoton {
            footprint: Footprint::new(
                Vec3::ZERO,
                Vec3::new(0.4, 0.0, 0.0),
                Vec3::new(0.0, 0.0, 0.1),
                Vec3::Y,
            )
            .unwrap(),
            wi: Vec3::Y,
            n: Vec3::Y,
            flux: Spectrum::splat(2.0),
            dt: Vec3::ZERO,
            depth: 2,
        }
    }

    /// (pixel, radiance) of every vertex `photon()` reaches, by pixel; tiles of two vertices so
    /// that the tile culling is exercised too.
    fn splats(map: &EyeMap, filter: &FootprintFilter) -> Vec<(u32, Spectrum)> {
        let mut out = Vec::new();
        let ph = photon();
        let (lo, hi) = filter.bounds(&ph).expect("a finite footprint");
        for t in &map.tiles {
            t.for_each_in_box(lo, hi, |_, v| {
                let mut acc = ChunkedSum::default();
                if splat_footprint(filter, &ph, 0, v, &mut acc) {
                    let [r, g, b] = acc.sum().map(|a| a.to_f64() as f32);
                    let l = Spectrum::new(r, g, b);
                    out.push((v.pixel, l));
                }
            });
        }
        out.sort_by_key(|s| s.0);
        out
    }

    fn tiled(vertices: Vec<EyeVertex>) -> EyeMap {
        EyeMap::with_tile_size(vertices, 2)
    }

    #[test]
    fn a_splat_reaches_exactly_the_vertices_inside_the_ellipse() {
        let map = tiled(vec![
            vertex(Vec3::ZERO, Vec3::Y, 0),                   // centre
            vertex(Vec3::new(0.15, 0.0, 0.0), Vec3::Y, 1),    // inside, along the long axis
            vertex(Vec3::new(0.0, 0.0, 0.06), Vec3::Y, 2),    // outside, across
            vertex(Vec3::new(0.21, 0.0, 0.0), Vec3::Y, 3),    // outside, along
            vertex(Vec3::new(0.0, 0.0, 0.0), Vec3::NEG_Y, 4), // the underside
        ]);
        let f = FootprintFilter::default();
        let s = splats(&map, &f);
        let ids: Vec<u32> = s.iter().map(|s| s.0).collect();
        assert_eq!(ids, vec![0, 1]);
        // Eq. 10–12 at the centre: f_r Φ π K(0) / A, K(0) = 3/π (eq. 11), A = π · 0.2 · 0.05.
        let area = PI * 0.2 * 0.05;
        let expected = ALBEDO / PI * 2.0 * 3.0 / area;
        let got = s[0].1.c[0];
        assert!((got / expected - 1.0).abs() < 1e-5, "{got} vs {expected}");
        // At 3/4 of the long semi-axis: K ∝ (1 − 0.75²)².
        let ratio = s[1].1.c[0] / got;
        let k = (1.0f32 - 0.75 * 0.75).powi(2);
        assert!((ratio / k - 1.0).abs() < 1e-4, "{ratio} vs {k}");
        // The Epanechnikov kernel: 2/π at the centre.
        let e = splats(
            &map,
            &FootprintFilter {
                kernel: Kernel::Epanechnikov,
                ..f
            },
        );
        let r = e[0].1.c[0] / got;
        assert!((r - 2.0 / 3.0).abs() < 1e-5, "{r}");
    }

    #[test]
    fn the_normal_distance_threshold_keeps_splats_off_nearby_surfaces() {
        // A vertex 0.04 m above the floor (a step), inside the footprint's projection: the gather
        // radius is 0.2 m, so it is reached with the threshold off, not with 0.1 · 0.2 = 0.02 m.
        let map = tiled(vec![vertex(Vec3::new(0.05, 0.04, 0.0), Vec3::Y, 0)]);
        let off = FootprintFilter {
            normal_distance: f32::INFINITY,
            ..Default::default()
        };
        let on = FootprintFilter {
            normal_distance: 0.1,
            ..Default::default()
        };
        assert_eq!(splats(&map, &off).len(), 1);
        assert_eq!(splats(&map, &on).len(), 0);
        // A wall (normal +x) at the centre: rejected by the normal test whatever the threshold.
        let wall = tiled(vec![vertex(Vec3::ZERO, Vec3::X, 0)]);
        assert_eq!(splats(&wall, &off).len(), 0);
    }

    #[test]
    fn an_empty_map_splats_nothing() {
        let empty = tiled(Vec::new());
        assert_eq!(splats(&empty, &FootprintFilter::default()).len(), 0);
        assert!(empty.is_empty());
    }
}
