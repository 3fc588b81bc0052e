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
//! 3. The number `N` of light paths that yields `--photons` caustic landings, counted without
//!    differentials ([`count_caustic_paths`]): the footprints scale with `1/√N` (eq. 5–6), so
//!    `N` must be known before the first splat. These are the paths of `pdm`, so `pdm` and
//!    `pds` use the same photons. Up to [`RECORD_LANDING_PATHS`] photons the count also notes
//!    which paths landed (8 bytes each), and only those are traced again; most paths of a
//!    low-yield scene (the glass sphere: 0.4 %) never reach a specular surface.
//! 4. Paths `0..N` traced as photon differentials in batches of fixed chunks (in parallel);
//!    each batch's photons splatted in path order by the eye map's tiles in parallel, each tile
//!    adding to its own vertices' accumulators ([`crate::eye_map`]), so the image does not
//!    depend on the thread count.
//! 5. Each camera sample's pixel receives `β · Σ splats` of its vertex.

use super::photon_mapping::{self, CAUSTIC_STREAM, PhotonMaps, footprint_filter};
use crate::eye_map::{BoxedPhoton, EyeMap, EyeVertex};
use crate::film::Film;
use crate::filter::Filter;
use crate::image_loop::render_pixels_collect;
use crate::options::{Progress, RenderControl, RenderOptions};
use crate::photon_differential::{
    DiffPhoton, FootprintFilter, Landing, LandingTracer, RECORD_LANDING_PATHS, count_caustic_paths,
    photons_from_landings, unit_budget,
};
use crate::stats::RenderStats;
use caustica_core::Spectrum;
use caustica_core::sampling::Sampler;
use caustica_scene::Scene;
use rayon::prelude::*;
use std::sync::atomic::Ordering;
use std::time::Instant;

/// Light paths per chunk of the splatting pass (traced in parallel; photons kept in path order).
const CHUNK: u64 = 1 << 12;
/// Shares of the progress bar given to the camera pass and to counting the light paths (the
/// splatting pass has the rest).
const EYE_SHARE: f64 = 0.4;
const COUNT_SHARE: f64 = 0.1;

/// Renders `scene` by photon differential splatting into `film`; returns the statistics and
/// appends the notes for the user.
pub fn render(
    scene: &Scene,
    opts: &RenderOptions,
    ctl: &RenderControl,
    film: &mut Film,
    filter: &Filter,
    notes: &mut Vec<String>,
) -> RenderStats {
    let t0 = Instant::now();
    let maps = PhotonMaps::global_only(scene, opts);
    let global_secs = t0.elapsed().as_secs_f64();
    let mut stats = maps.stats;

    // 2. Camera pass and eye map.
    let t = Instant::now();
    let cam = &scene.camera;
    let eye_progress = |p: Progress| {
        (ctl.on_progress)(Progress {
            fraction: p.fraction * EYE_SHARE,
            ..p
        })
    };
    let eye_ctl = RenderControl {
        stop: ctl.stop,
        on_progress: &eye_progress,
        on_checkpoint: ctl.on_checkpoint,
    };
    let (st, vertices) = render_pixels_collect(
        film,
        filter,
        opts,
        &eye_ctl,
        |sampler, raster, pixel, out: &mut Vec<EyeVertex>, st| {
            let u_lens = sampler.next_2d();
            let ray = cam.generate_ray(raster, u_lens).ray;
            photon_mapping::radiance_with(scene, &maps, ray, sampler, opts, st, &mut |v, beta| {
                out.push(EyeVertex::new(v, beta, pixel));
                Spectrum::ZERO
            })
        },
    );
    stats += st;
    let eye = EyeMap::new(vertices);
    let eye_secs = t.elapsed().as_secs_f64();
    if ctl.stop.load(Ordering::Relaxed) {
        notes.push(
            "photon differential splatting: stopped during the camera pass; no caustics splatted"
                .into(),
        );
        return stats;
    }

    // 3. How many light paths make the requested caustic photons.
    let t = Instant::now();
    let target = opts.photons.caustic_photons;
    let record = target <= RECORD_LANDING_PATHS;
    let counted = count_caustic_paths(scene, target, CAUSTIC_STREAM, opts, record, &mut |f| {
        (ctl.on_progress)(Progress {
            fraction: EYE_SHARE + COUNT_SHARE * f.clamp(0.0, 1.0),
            samples: 0,
        })
    });
    let (paths, landings) = (counted.paths, counted.landings);
    stats.rays += counted.stats.rays;
    // The paths to trace with differentials: those that landed when they were recorded (most
    // paths of a low-yield scene never reach a specular surface), else all of them.
    let work = match &counted.landing_paths {
        Some(list) => Work::Listed(list),
        None => Work::All(paths),
    };
    let count_secs = t.elapsed().as_secs_f64();

    // 4. Trace and splat.
    let t = Instant::now();
    let splat = SplatPass {
        opts,
        eye: &eye,
        filter: footprint_filter(&opts.photons),
        tracer: unit_budget(opts.photons.smoothing).map(|b| LandingTracer::new(scene, &b)),
        paths,
    };
    // One accumulator per eye vertex, per tile (W/m²/sr before the throughput β).
    let mut acc: Vec<Vec<[f64; 3]>> = eye.tiles.iter().map(|t| vec![[0.0; 3]; t.len()]).collect();
    let mut totals = ChunkTotals::default();
    let chunks = work.chunks();
    // Chunks traced concurrently per batch (any number gives the same image: each vertex sums
    // its photons in path order).
    let wave = (4 * rayon::current_num_threads()).max(1) as u64;
    let mut last_checkpoint = Instant::now();
    let mut stopped = false;
    let mut c = 0u64;
    while c < chunks {
        let end = (c + wave).min(chunks);
        let parts: Vec<(Vec<DiffPhoton>, ChunkTotals, RenderStats)> = (c..end)
            .into_par_iter()
            .map(|i| splat.trace(&work, i))
            .collect();
        let mut batch = Vec::new();
        for (photons, tot, st) in parts {
            batch.extend(photons);
            totals += tot;
            stats.rays += st.rays;
            stats.nonfinite += st.nonfinite;
        }
        totals.splats += splat.splat(&batch, &mut acc);
        c = end;
        (ctl.on_progress)(Progress {
            fraction: EYE_SHARE
                + COUNT_SHARE
                + (1.0 - EYE_SHARE - COUNT_SHARE) * c as f64 / chunks.max(1) as f64,
            samples: work.done(c),
        });
        if ctl.stop.load(Ordering::Relaxed) {
            stopped = c < chunks;
            break;
        }
        if let Some(iv) = opts.checkpoint_interval
            && last_checkpoint.elapsed() >= iv
        {
            let mut partial = film.clone();
            resolve(&mut partial, &eye, &acc);
            (ctl.on_checkpoint)(&partial);
            last_checkpoint = Instant::now();
        }
    }
    let splat_secs = t.elapsed().as_secs_f64().max(1e-9);

    // 5. Into the pixels.
    resolve(film, &eye, &acc);

    notes.push(format!(
        "photon differential splatting: eye map {} vertices ({:.1} MB) in {eye_secs:.2} s; {landings} caustic photons from {paths} light paths (counted in {count_secs:.2} s){}; global map {} photons in {global_secs:.2} s",
        eye.len(),
        eye.memory_bytes() as f64 / 1e6,
        if stopped {
            format!(", stopped after {} paths", work.done(c))
        } else {
            String::new()
        },
        maps.global.len(),
    ));
    notes.push(format!(
        "splatting: smoothing s = {}, {} photons splatted, {} dropped with a collapsed footprint, {} dropped where the differential could not be propagated; {} splats in {splat_secs:.2} s ({:.2} M photons/s, {:.2} M splats/s), {:.1} splats per photon",
        opts.photons.smoothing,
        totals.photons,
        totals.collapsed,
        totals.failed,
        totals.splats,
        totals.photons as f64 / splat_secs / 1e6,
        totals.splats as f64 / splat_secs / 1e6,
        totals.splats as f64 / totals.photons.max(1) as f64,
    ));
    if landings < target {
        notes.push(format!(
            "warning: only {landings} caustic photons found after {paths} light paths (requested {target}){}",
            if landings == 0 {
                ": no light reaches a diffuse surface through glass or mirrors"
            } else {
                ""
            }
        ));
    }
    if splat.tracer.is_none() {
        notes.push(format!(
            "warning: smoothing s = {} is not a positive number; nothing splatted",
            opts.photons.smoothing
        ));
    }
    notes.extend(maps.warnings.iter().map(|w| format!("warning: {w}")));
    stats
}

/// Adds `β · Σ splats` of every eye vertex to its pixel's camera-sample sum.
fn resolve(film: &mut Film, eye: &EyeMap, acc: &[Vec<[f64; 3]>]) {
    for (tile, acc) in eye.tiles.iter().zip(acc) {
        for (v, a) in tile.vertices.iter().zip(acc) {
            let px = &mut film.sum[v.pixel as usize];
            for k in 0..3 {
                px[k] += v.beta.c[k] as f64 * a[k];
            }
        }
    }
}

/// The light paths of the splatting pass, in chunks of [`CHUNK`] paths.
enum Work<'a> {
    /// Paths `0..N`.
    All(u64),
    /// These paths (ascending).
    Listed(&'a [u64]),
}

impl Work<'_> {
    fn chunks(&self) -> u64 {
        match self {
            Work::All(n) => n.div_ceil(CHUNK),
            Work::Listed(l) => (l.len() as u64).div_ceil(CHUNK),
        }
    }

    /// Calls `f(path)` for the paths of chunk `c`, in order.
    fn for_each_path(&self, c: u64, mut f: impl FnMut(u64)) {
        match self {
            Work::All(n) => (c * CHUNK..((c + 1) * CHUNK).min(*n)).for_each(f),
            Work::Listed(l) => {
                let lo = (c * CHUNK) as usize;
                let hi = ((c + 1) * CHUNK).min(l.len() as u64) as usize;
                l[lo..hi].iter().for_each(|&p| f(p));
            }
        }
    }

    /// Paths traced after the first `c` chunks.
    fn done(&self, c: u64) -> u64 {
        match self {
            Work::All(n) => (c * CHUNK).min(*n),
            Work::Listed(l) => (c * CHUNK).min(l.len() as u64),
        }
    }
}

/// Counts of one chunk of the splatting pass.
#[derive(Clone, Copy, Debug, Default)]
struct ChunkTotals {
    photons: u64,
    collapsed: u64,
    failed: u64,
    splats: u64,
}

impl std::ops::AddAssign for ChunkTotals {
    fn add_assign(&mut self, o: Self) {
        self.photons += o.photons;
        self.collapsed += o.collapsed;
        self.failed += o.failed;
        self.splats += o.splats;
    }
}

/// What every chunk of the splatting pass needs.
struct SplatPass<'a> {
    opts: &'a RenderOptions,
    eye: &'a EyeMap,
    filter: FootprintFilter,
    /// The light-path tracer for the unit budget (built once for all chunks); `None` for an
    /// invalid smoothing parameter (nothing is splatted).
    tracer: Option<LandingTracer<'a>>,
    /// Light paths `N` of the whole pass (the N of Φ = β/N and of eq. 5–6).
    paths: u64,
}

impl SplatPass<'_> {
    /// Traces the paths of chunk `c` of `work` as photon differentials; returns their caustic
    /// photons in path order.
    fn trace(&self, work: &Work, c: u64) -> (Vec<DiffPhoton>, ChunkTotals, RenderStats) {
        let mut st = RenderStats::default();
        let mut totals = ChunkTotals::default();
        let Some(tracer) = &self.tracer else {
            return (Vec::new(), totals, st);
        };
        let mut landings: Vec<Landing> = Vec::new();
        let mut sampler = Sampler::new(self.opts.sampler, self.opts.seed);
        work.for_each_path(c, |path| {
            sampler.start_path(CAUSTIC_STREAM, path);
            tracer.trace(&mut sampler, self.opts, &mut landings, &mut st);
        });
        let (photons, collapsed, failed) = photons_from_landings(&landings, self.paths);
        totals.photons = photons.len() as u64;
        totals.collapsed = collapsed;
        totals.failed = failed;
        (photons, totals, st)
    }

    /// Splats `photons` in order onto every tile (tiles in parallel, each into its own
    /// accumulators `acc[tile]`); returns the number of splats.
    fn splat(&self, photons: &[DiffPhoton], acc: &mut [Vec<[f64; 3]>]) -> u64 {
        let photons: Vec<BoxedPhoton> = photons
            .par_iter()
            .filter_map(|ph| BoxedPhoton::new(ph, &self.filter))
            .collect();
        self.eye
            .tiles
            .par_iter()
            .zip(acc.par_iter_mut())
            .map(|(tile, acc)| {
                let mut n = 0u64;
                for ph in &photons {
                    n += tile.splat(ph, &self.filter, |i, l| {
                        for (a, v) in acc[i].iter_mut().zip(l.c) {
                            *a += v as f64;
                        }
                    }) as u64;
                }
                n
            })
            .sum()
    }
}
