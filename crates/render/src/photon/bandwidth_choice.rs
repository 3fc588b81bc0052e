//! Automatic bandwidths: `pm`'s k, `dpm`'s bandwidth h and diffusivity q, the smoothing s of
//! `pdm` and `pds`, chosen from traced photons by least-squares cross-validation of the image
//! ([`caustica_density::bandwidth_selection`]).
//!
//! For a candidate bandwidth the caustic estimate L̂ of the photon method is evaluated at the
//! first vertices of [`RAYS_PER_PIXEL`] camera rays through each scored pixel (offsets drawn
//! from the pixel filter, as the render's samples are) and averaged, and scored as
//!
//! ```text
//! LSCV = Σ_pixels Σ_rgb [ L̂(x)² − 2 L̂(x) L̃(x) ]
//! ```
//!
//! where L̃ is a hold-out estimate of the same pixels: the light tracer's caustics-only image
//! (paths L S+ D E, the unbiased reference of the case studies) from light paths of their own
//! random stream ([`HOLDOUT_STREAM`]), independent of the photons, so E[L̂ L̃] = E[L̂] L and the
//! score estimates Σ (L̂ − L)² up to a constant (Rudemo 1982; Silverman 1986 eq. 3.39). Only
//! pixels whose camera ray meets a non-delta surface first are scored: the light tracer
//! cannot connect through a mirror or glass to the camera, so elsewhere L̃ would be 0 though L
//! is not.
//!
//! Cost: a map of more than [`PILOT_PHOTONS`] photons is represented by a pilot, the first
//! [`PILOT_PHOTONS`] of its own light paths (a prefix of the same stream), and the pilot's
//! choice is carried to the full count at the AMISE rate (k ∝ N^{2/3}, h ∝ N^{-1/6},
//! s ∝ N^{1/3} on surfaces; [`Smoother::rate`]); at most [`SCORED_PIXELS`] pixels (a regular
//! subgrid) are scored. The hold-out has [`HOLDOUT_FACTOR`] times the pilot's light paths, at
//! most [`HOLDOUT_MAX_PATHS`] (or the pilot's own count if that is larger).
//! The choice is deterministic: the pilot, the hold-out (fixed chunks merged in order) and the
//! scores (per-pixel values in parallel, summed in pixel order) do not depend on the thread
//! count.

use crate::film::{Film, SplatBuffer};
use crate::filter::Filter;
use crate::integrator::IntegratorKind;
use crate::integrator::light_tracer::trace_light_path;
use crate::options::{
    AutoBandwidth, Bandwidth, CausticEstimator, Diffusivity, PhotonOptions, RenderOptions,
    Smoothing,
};
use crate::photon::caustic::{CAUSTIC_STREAM, CausticEstimate};
use crate::photon::differential::{
    DiffPhoton, FootprintFilter, PdmMap, TracedDiffPhotons, trace_photon_differentials,
};
use crate::photon::plan::PhotonBudget;
use crate::stats::RenderStats;
use crate::transport::eye_walk::{EyeEvent, Flow, walk_eye};
use crate::transport::vertex::Vertex;
use caustica_core::sampling::Sampler;
use caustica_core::{Spectrum, Vec2};
use caustica_density::bandwidth_selection::{LscvScore, Smoother, amise_rescale, select_geometric};
use caustica_density::estimator::median_knn_radius;
use caustica_differentials::Footprint;
use caustica_scene::Scene;
use rayon::prelude::*;

/// Largest photon count chosen for directly; larger maps are represented by a pilot this big.
pub const PILOT_PHOTONS: usize = 32_768;
/// Most pixels scored (a regular subgrid of the image).
pub const SCORED_PIXELS: usize = 16_384;
/// Most pixels scored for the diffusion estimate, whose queries are the dearest.
pub const SCORED_PIXELS_DIFFUSION: usize = 4_096;
/// Hold-out light paths per pilot light path.
pub const HOLDOUT_FACTOR: u64 = 4;
/// Most hold-out light paths, unless the pilot itself needed more (a light that sends few of
/// its paths into caustics, like the gold ring's area light, would otherwise make the
/// hold-out dearer than the render).
pub const HOLDOUT_MAX_PATHS: u64 = 1 << 22;
/// Random-number stream of the hold-out light paths (the photons use
/// [`crate::photon::caustic::CAUSTIC_STREAM`] and the global map its own).
pub const HOLDOUT_STREAM: u64 = 0x401D;
/// Hold-out light paths per chunk (fixed, so the hold-out image is thread-count independent).
const HOLDOUT_CHUNK: u64 = 1 << 12;
/// Chunks traced concurrently before merging.
pub const HOLDOUT_WAVE: u64 = 8;
/// Diffusivities q tried by `dpm` (seed 000 eq. 4.15; the case studies' optima were 0.025–0.2).
const Q_CANDIDATES: [f32; 5] = [0.025, 0.05, 0.1, 0.2, 0.4];

/// The options a render runs with after the choice, and the line for the user.
pub struct Choice {
    /// `opts` with every automatic bandwidth replaced by its chosen (or fallback) value and
    /// [`PhotonOptions::auto`] cleared.
    pub opts: RenderOptions,
    /// "automatic bandwidth: …", or `None` when nothing was automatic for this integrator.
    pub note: Option<String>,
}

/// What is chosen for one integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Target {
    /// k of the k-NN or variable estimate (`pm`).
    K(CausticEstimator),
    /// The fixed bandwidth h (`pm --estimator fixed`).
    H,
    /// The diffusion estimate's h and/or q (`dpm`).
    Diffusion { h: bool, q: bool },
    /// The smoothing s (`pdm`, `pds`).
    S,
}

/// True when rendering with `kind` and `p` chooses a bandwidth automatically.
pub fn chooses(kind: IntegratorKind, p: &PhotonOptions) -> bool {
    target(kind, p).is_some()
}

/// Bytes of one scored camera vertex.
pub const CELL_BYTES: u64 = std::mem::size_of::<(Vertex, Spectrum)>() as u64;

fn target(kind: IntegratorKind, p: &PhotonOptions) -> Option<Target> {
    let a = p.auto;
    let diffusion = (a.bandwidth || a.q).then_some(Target::Diffusion {
        h: a.bandwidth,
        q: a.q,
    });
    match kind {
        IntegratorKind::PhotonMapping
        | IntegratorKind::VolumetricPhotonMapping
        | IntegratorKind::BeamRadianceEstimate => match p.caustic_estimator.unwrap_or_default() {
            e @ (CausticEstimator::Knn | CausticEstimator::Variable) => a.k.then_some(Target::K(e)),
            CausticEstimator::Fixed => a.bandwidth.then_some(Target::H),
            CausticEstimator::Diffusion => diffusion,
        },
        IntegratorKind::DiffusionPhotonMapping => diffusion,
        IntegratorKind::PhotonDifferentialMapping
        | IntegratorKind::PhotonDifferentialSplatting
        | IntegratorKind::VolumePhotonDifferentials => a.smoothing.then_some(Target::S),
        // The progressive methods start from the given bandwidth and shrink it.
        IntegratorKind::Path
        | IntegratorKind::LightTrace
        | IntegratorKind::Hybrid
        | IntegratorKind::ProgressivePhotonMapping
        | IntegratorKind::ProgressiveSplatting
        | IntegratorKind::ProgressiveDifferentialMapping
        | IntegratorKind::ProgressiveDiffusion
        | IntegratorKind::StochasticProgressivePhotonMapping
        | IntegratorKind::ProgressivePhotonMappingHitPoints
        | IntegratorKind::PhotonConeFocusing => None,
    }
}

/// Chooses the automatic bandwidths of `opts` for integrator `kind` on `scene`. `progress`
/// sees the fraction done and returns false to stop: the render then goes on with the fixed
/// defaults (and the note says so).
pub fn choose(
    scene: &Scene,
    kind: IntegratorKind,
    opts: &RenderOptions,
    progress: &mut dyn FnMut(f64) -> bool,
) -> Choice {
    let mut out = opts.clone();
    out.photons.auto = AutoBandwidth::default();
    let Some(target) = target(kind, &opts.photons) else {
        return Choice {
            opts: out,
            note: None,
        };
    };
    let t = std::time::Instant::now();
    let chosen = run(scene, target, opts, progress);
    let secs = t.elapsed().as_secs_f64();
    let note = match chosen {
        Ok((values, how)) => {
            values.apply(&mut out.photons);
            format!(
                "automatic bandwidth: {} ({how}; {secs:.2} s)",
                values.describe()
            )
        }
        Err(why) => {
            let fixed = Values::fallback(target, &opts.photons);
            fixed.apply(&mut out.photons);
            format!(
                "automatic bandwidth: {why}; using the fixed default {}",
                fixed.describe()
            )
        }
    };
    Choice {
        opts: out,
        note: Some(note),
    }
}

/// Chosen values (only those of the target are `Some`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Values {
    k: Option<usize>,
    h: Option<f32>,
    q: Option<f32>,
    s: Option<f32>,
}

impl Values {
    /// The fixed defaults the automatic choice replaces.
    fn fallback(target: Target, p: &PhotonOptions) -> Values {
        match target {
            Target::K(_) => Values {
                k: Some(p.estimate.k),
                ..Values::default()
            },
            // The median-k-NN-radius default is computed later, from the full map.
            Target::H => Values::default(),
            Target::Diffusion { q, .. } => Values {
                q: q.then_some(p.diffusion.q.get()),
                ..Values::default()
            },
            Target::S => Values {
                s: Some(p.footprints.smoothing.get()),
                ..Values::default()
            },
        }
    }

    fn apply(self, p: &mut PhotonOptions) {
        if let Some(k) = self.k {
            // The global map keeps the fixed k: only the caustic map's is chosen.
            p.global_k.get_or_insert(p.estimate.k);
            p.estimate.k = k.max(1);
        }
        if let Some(h) = self.h.and_then(|h| Bandwidth::new(h).ok()) {
            p.bandwidth = Some(h);
        }
        if let Some(q) = self.q.and_then(|q| Diffusivity::new(q).ok()) {
            p.diffusion.q = q;
        }
        if let Some(s) = self.s.and_then(|s| Smoothing::new(s).ok()) {
            p.footprints.smoothing = s;
        }
    }

    fn describe(self) -> String {
        let mut parts = Vec::new();
        if let Some(k) = self.k {
            parts.push(format!("k = {k}"));
        }
        if let Some(h) = self.h {
            parts.push(format!("h = {h:.4}"));
        }
        if let Some(q) = self.q {
            parts.push(format!("q = {q}"));
        }
        if let Some(s) = self.s {
            parts.push(format!("s = {s:.2}"));
        }
        if parts.is_empty() {
            "h = the median k-NN radius".to_string()
        } else {
            parts.join(", ")
        }
    }
}

/// A scored pixel: the first vertices of those of its camera rays that meet a non-delta
/// surface first (at least one).
struct ScoredPixel {
    /// Pixel index (row-major).
    pixel: usize,
    /// Each vertex with the throughput of its camera ray (transmittance).
    rays: Vec<(Vertex, Spectrum)>,
}

/// Camera rays per scored pixel, their offsets drawn from the pixel filter as the render's are:
/// a pixel's score compares the estimate averaged over the filter, as the render computes it,
/// with the hold-out's filtered pixel. Evaluated at the pixel centre alone, an estimate varying
/// within the pixel counts that variation as error and the choice drifts to wider bandwidths.
pub const RAYS_PER_PIXEL: usize = 4;

/// The pixels scored: a regular subgrid of at most `max` pixels, [`RAYS_PER_PIXEL`] camera rays
/// each; a ray counts if it meets a non-delta surface first (its first vertex, as in the
/// caustics-only light tracer), a pixel if one of its rays does.
fn scored_pixels(scene: &Scene, opts: &RenderOptions, max: usize) -> Vec<ScoredPixel> {
    let cam = &scene.camera;
    let filter = Filter::new(scene.settings.filter);
    let (w, h) = (cam.width as usize, cam.height as usize);
    let stride = ((w * h) as f64 / max as f64).sqrt().ceil().max(1.0) as usize;
    let pixels: Vec<(usize, usize)> = (stride / 2..h)
        .step_by(stride)
        .flat_map(|y| (stride / 2..w).step_by(stride).map(move |x| (x, y)))
        .collect();
    pixels
        .par_iter()
        .filter_map(|&(x, y)| {
            let mut sampler = Sampler::new(opts.sampler, opts.seed);
            let rays: Vec<(Vertex, Spectrum)> = (0..RAYS_PER_PIXEL)
                .filter_map(|k| {
                    sampler.start_pixel_sample(x as u32, y as u32, k as u32);
                    let offset = filter.sample(sampler.next_2d());
                    let raster = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset;
                    let ray = cam.generate_ray(raster, Vec2::splat(0.5)).ray;
                    let mut found = None;
                    walk_eye(
                        scene,
                        ray,
                        scene.camera_medium,
                        &mut sampler,
                        1,
                        &mut RenderStats::default(),
                        |event, _, _| {
                            if let EyeEvent::Vertex { v, beta, .. } = event
                                && v.bsdf.flags().is_smooth()
                            {
                                found = Some((v.clone(), beta));
                            }
                            Flow::Stop
                        },
                    );
                    found
                })
                .collect();
            (!rays.is_empty()).then_some(ScoredPixel {
                pixel: y * w + x,
                rays,
            })
        })
        .collect()
}

/// The hold-out image: `paths` caustics-only light-tracer paths of [`HOLDOUT_STREAM`], or
/// `None` if `progress` says stop.
fn holdout(
    scene: &Scene,
    opts: &RenderOptions,
    paths: u64,
    progress: &mut dyn FnMut(f64) -> bool,
) -> Option<Film> {
    let cam = &scene.camera;
    let (w, h) = (cam.width as usize, cam.height as usize);
    let mut lt = opts.clone();
    lt.caustics_only = true;
    let filter = Filter::new(scene.settings.filter);
    // The full film, whatever the render's crop window: the choice is the full render's.
    let mut film = Film::new(w, h);
    let empty = SplatBuffer::for_film(&film);
    let chunks = paths.div_ceil(HOLDOUT_CHUNK);
    let mut c0 = 0;
    while c0 < chunks {
        let c1 = (c0 + HOLDOUT_WAVE).min(chunks);
        let bufs: Vec<(SplatBuffer, u64)> = (c0..c1)
            .into_par_iter()
            .map(|c| {
                let mut buf = empty.clone();
                let mut st = RenderStats::default();
                let mut sampler = Sampler::new(opts.sampler, opts.seed);
                let (first, last) = (c * HOLDOUT_CHUNK, ((c + 1) * HOLDOUT_CHUNK).min(paths));
                for path in first..last {
                    sampler.start_path(HOLDOUT_STREAM, path);
                    trace_light_path(scene, &mut sampler, &lt, &filter, &mut buf, &mut st);
                }
                (buf, last - first)
            })
            .collect();
        for (buf, n) in &bufs {
            buf.merge_into(&mut film, *n);
        }
        c0 = c1;
        if !progress(c0 as f64 / chunks as f64) {
            return None;
        }
    }
    Some(film)
}

/// Scores caustic estimate `est` (radiance at a vertex) over `pixels` against `tilde`: a
/// pixel's estimate is the mean over its [`RAYS_PER_PIXEL`] rays (those that met no surface
/// add 0), computed in parallel and summed in pixel order.
fn score(
    pixels: &[ScoredPixel],
    tilde: &[[f64; 3]],
    est: impl Fn(&Vertex) -> Spectrum + Sync,
) -> f64 {
    let values: Vec<[f64; 3]> = pixels
        .par_iter()
        .map(|p| {
            let mut sum = [0.0; 3];
            for (v, beta) in &p.rays {
                for (a, c) in sum.iter_mut().zip((*beta * est(v)).c) {
                    *a += f64::from(c);
                }
            }
            sum.map(|a| a / RAYS_PER_PIXEL as f64)
        })
        .collect();
    let mut s = LscvScore::default();
    for (p, l) in pixels.iter().zip(&values) {
        for (e, h) in l.iter().zip(&tilde[p.pixel]) {
            s.add(*e, *h);
        }
    }
    s.value()
}

/// The pilot's budget for a full budget `full`, and how many times larger the full map is
/// (in photons for a record budget, in light paths for a path budget: the same ratio in
/// expectation). `pilot_paths` is what a record pilot needed, for the path case.
fn pilot_budget(full: PhotonBudget) -> PhotonBudget {
    match full {
        PhotonBudget::Records(n) => PhotonBudget::Records(n.min(PILOT_PHOTONS)),
        PhotonBudget::Paths(_) => PhotonBudget::Records(PILOT_PHOTONS),
    }
}

/// The full map's size over the pilot's (≥ 1 photon or path each), in the budget's unit.
fn full_over_pilot(full: PhotonBudget, pilot_records: usize, pilot_paths: u64) -> (u64, u64) {
    match full {
        PhotonBudget::Records(n) => (pilot_records.max(1) as u64, n.max(1) as u64),
        PhotonBudget::Paths(n) => (pilot_paths.max(1), n.max(pilot_paths).max(1)),
    }
}

/// The choice itself: the chosen values and how they were found, or why there is none.
fn run(
    scene: &Scene,
    target: Target,
    opts: &RenderOptions,
    progress: &mut dyn FnMut(f64) -> bool,
) -> Result<(Values, String), String> {
    const INTERRUPTED: &str = "interrupted";
    let p = &opts.photons;
    let full = p.caustic_budget();
    // Progress: pilot 0–0.3, hold-out 0.3–0.5, scoring 0.5–1.
    let pilot_opts = {
        let mut o = opts.clone();
        o.photons.light_paths = None;
        if let PhotonBudget::Records(n) = pilot_budget(full) {
            o.photons.caustic_photons = n;
        }
        // The minimum footprint is absolute: applied after scaling to each candidate s.
        o.photons.footprints.min_semi_axis = None;
        o
    };
    enum Pilot {
        Density(CausticEstimate),
        Footprints(TracedDiffPhotons),
    }
    let mut stop = false;
    let mut pilot_progress = |f: f64| {
        let go = progress(0.3 * f);
        stop |= !go;
        go
    };
    let (pilot, records, paths) = match target {
        Target::S => {
            let d = trace_photon_differentials(
                scene,
                pilot_opts.photons.caustic_budget(),
                Smoothing::ONE,
                CAUSTIC_STREAM,
                &pilot_opts,
                &mut pilot_progress,
            );
            let (r, n) = (d.photons.len(), d.paths);
            (Pilot::Footprints(d), r, n)
        }
        _ => {
            let (c, traced) = CausticEstimate::density(
                scene,
                CausticEstimator::Knn,
                &pilot_opts,
                &mut pilot_progress,
            );
            let (r, n) = (c.len(), traced.paths);
            (Pilot::Density(c), r, n)
        }
    };
    if stop {
        return Err(INTERRUPTED.into());
    }
    if records == 0 {
        return Err("no caustic photons to choose from".into());
    }
    let (pilot_n, full_n) = full_over_pilot(full, records, paths);
    let max_cells = match target {
        Target::Diffusion { .. } => SCORED_PIXELS_DIFFUSION,
        _ => SCORED_PIXELS,
    };
    let pixels = scored_pixels(scene, opts, max_cells);
    let holdout_paths = paths
        .saturating_mul(HOLDOUT_FACTOR)
        .min(HOLDOUT_MAX_PATHS.max(paths))
        .max(1);
    let film = holdout(scene, opts, holdout_paths, &mut |f| progress(0.3 + 0.2 * f))
        .ok_or_else(|| INTERRUPTED.to_string())?;
    let tilde: Vec<[f64; 3]> = film
        .to_image()
        .data
        .iter()
        .map(|px| px.map(f64::from))
        .collect();
    let seen: f64 = pixels
        .iter()
        .map(|c| tilde[c.pixel].iter().sum::<f64>())
        .sum();
    if pixels.is_empty() || seen <= 0.0 {
        return Err("no caustic the camera sees directly to score against".into());
    }
    let rays: usize = pixels.iter().map(|p| p.rays.len()).sum();
    let how = |n: usize| {
        let pilot = if pilot_n < full_n {
            format!(" on a {records}-photon pilot, scaled to the full map at the AMISE rate")
        } else {
            String::new()
        };
        format!(
            "least-squares cross-validation over {n} candidates{pilot}, {} pixels ({rays} camera rays), {holdout_paths} hold-out light paths",
            pixels.len()
        )
    };
    // Scoring progress: a rough count of candidates.
    let mut done = 0.0;
    let mut tick = |expected: f64| {
        done += 1.0;
        progress(0.5 + 0.5 * (done / expected).min(1.0))
    };
    match (target, pilot) {
        (Target::K(estimator), Pilot::Density(mut caustic)) => {
            let hi = (records as f64).clamp(4.0, 512.0);
            let sel = select_geometric(4.0, hi, 2.0, f64::round, |k| {
                let mut po = p.clone();
                po.estimate.k = k as usize;
                caustic.set_estimator(estimator, &po);
                let s = score(&pixels, &tilde, |v| caustic.radiance(v, &po));
                tick(9.0).then_some(s)
            })
            .ok_or_else(|| INTERRUPTED.to_string())?;
            let k = amise_rescale(sel.value, Smoother::NearestNeighbours, pilot_n, full_n, 2);
            Ok((
                Values {
                    k: Some(k.round().max(1.0) as usize),
                    ..Values::default()
                },
                how(sel.scored.len()),
            ))
        }
        (Target::H | Target::Diffusion { .. }, Pilot::Density(mut caustic)) => {
            let (estimator, q_list): (CausticEstimator, Vec<Option<f32>>) = match target {
                Target::Diffusion { q: true, .. } => (
                    CausticEstimator::Diffusion,
                    Q_CANDIDATES.iter().map(|&q| Some(q)).collect(),
                ),
                Target::Diffusion { q: false, .. } => (CausticEstimator::Diffusion, vec![None]),
                _ => (CausticEstimator::Fixed, vec![None]),
            };
            let auto_h = !matches!(target, Target::Diffusion { h: false, .. });
            // The default's scale: the median distance to the 50th neighbour in the pilot.
            let h0 = match (auto_h, p.bandwidth) {
                (false, Some(h)) => f64::from(h.get()),
                _ => {
                    let CausticEstimate::Density { map, .. } = &caustic else {
                        unreachable!("a density pilot")
                    };
                    f64::from(
                        median_knn_radius(&map.points(&p.estimate), p.estimate.k).unwrap_or(1.0),
                    )
                }
            };
            let expected = (q_list.len() * if auto_h { 7 } else { 1 }) as f64;
            let mut best: Option<(f64, f64, Option<f32>)> = None;
            let mut scored = 0;
            for q in q_list {
                let mut eval = |h: f64| {
                    let mut po = p.clone();
                    po.bandwidth = Bandwidth::new(h as f32).ok();
                    if let Some(q) = q.and_then(|q| Diffusivity::new(q).ok()) {
                        po.diffusion.q = q;
                    }
                    caustic.set_estimator(estimator, &po);
                    let s = score(&pixels, &tilde, |v| caustic.radiance(v, &po));
                    tick(expected).then_some(s)
                };
                let (h, s) = if auto_h {
                    let sel = select_geometric(h0 / 8.0, h0 * 4.0, 2.0, |h| h, &mut eval)
                        .ok_or_else(|| INTERRUPTED.to_string())?;
                    scored += sel.scored.len();
                    let s = sel
                        .scored
                        .iter()
                        .find(|(c, _)| *c == sel.value)
                        .map_or(f64::INFINITY, |&(_, s)| s);
                    (sel.value, s)
                } else {
                    scored += 1;
                    (h0, eval(h0).ok_or_else(|| INTERRUPTED.to_string())?)
                };
                if s.is_finite() && best.is_none_or(|(_, b, _)| s < b) {
                    best = Some((h, s, q));
                }
            }
            let (h, _, q) = best.ok_or("no finite score")?;
            let h = amise_rescale(h, Smoother::Bandwidth, pilot_n, full_n, 2);
            Ok((
                Values {
                    h: auto_h.then_some(h as f32),
                    q,
                    ..Values::default()
                },
                how(scored),
            ))
        }
        (Target::S, Pilot::Footprints(traced)) => {
            let filter = FootprintFilter::new(&p.footprints);
            let sel = select_geometric(
                0.5,
                16.0,
                2.0,
                |s| s,
                |s| {
                    let map = CausticEstimate::Footprints(PdmMap::with_filter(
                        scaled(&traced, s as f32, p.footprints.min_semi_axis),
                        filter,
                    ));
                    let sc = score(&pixels, &tilde, |v| map.radiance(v, p));
                    tick(8.0).then_some(sc)
                },
            )
            .ok_or_else(|| INTERRUPTED.to_string())?;
            let s = amise_rescale(sel.value, Smoother::FootprintScale, pilot_n, full_n, 2);
            Ok((
                Values {
                    s: Some(s as f32),
                    ..Values::default()
                },
                how(sel.scored.len()),
            ))
        }
        _ => unreachable!("the pilot matches the target"),
    }
}

/// `traced`'s photons with footprints of smoothing `s` instead of 1: the differential vectors
/// are linear in the initial lengths 2 s √(A/(π N_e)) (seed 002 eq. 5–6; first-order transfer,
/// seed 000 app. B), so they scale by s; then the minimum semi-axis, if any, as the render
/// applies it. Footprints that collapse are dropped.
fn scaled(traced: &TracedDiffPhotons, s: f32, min_semi_axis: Option<f32>) -> TracedDiffPhotons {
    let mut widened = 0;
    let photons: Vec<DiffPhoton> = traced
        .photons
        .iter()
        .filter_map(|ph| {
            let [du, dv] = ph.footprint.differentials();
            let (c, n) = (ph.footprint.center(), ph.footprint.normal());
            let fp = Footprint::widened(c, du * s, dv * s, n, min_semi_axis).map(|(f, w)| {
                widened += u64::from(w);
                f
            });
            fp.ok().map(|footprint| DiffPhoton { footprint, ..*ph })
        })
        .collect();
    TracedDiffPhotons {
        photons,
        paths: traced.paths,
        landings: traced.landings,
        collapsed: traced.collapsed,
        failed: traced.failed,
        widened,
        stats: RenderStats::default(),
        warning: None,
        note: None,
    }
}
