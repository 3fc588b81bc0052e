//! Stochastic progressive photon mapping (Hachisuka and Jensen 2009) as a rule over the
//! shared pieces: per iteration a camera pass (a new visible point per camera sample: the first
//! non-delta vertex through mirrors and glass, so anti-aliasing and depth of field converge)
//! that adds emission and direct light (next-event estimation) to its pixel, then a photon pass
//! whose photons are splatted onto the visible points by the eye-splat driver (the visible
//! points are the eye map; each sums its photons in path order, so the image is independent of
//! the thread count), then the per-pixel statistics updated (the standard update of the
//! original papers, spec notes sec. 1.7 [EXT], checked against HJ09 eq. 6–9 and HOJ08 eq. 8–10):
//!
//! ```text
//! N_{i+1} = N_i + α M_i,   R²_{i+1} = R²_i (N_i + α M_i)/(N_i + M_i),
//! τ_{i+1} = (τ_i + Φ_i) R²_{i+1}/R²_i,   L = τ/(π R² I) (+ the mean of the direct light),
//! ```
//!
//! with `M_i` the photons found within the pixel's radius in iteration `i`, `Φ_i = Σ β f φ`
//! their reflected flux (φ = path weight / light paths of the iteration, W, so τ is per
//! iteration and the radiance divides by the iteration count `I` rather than by all emitted
//! paths), both averaged over the pixel's camera samples of the iteration. Photons of direct
//! illumination (one edge from the light) are skipped: the camera pass has that light.

use crate::control::Stage;
use crate::driver::eye_splat::{SplatRule, eye_pass, splat_batches};
use crate::driver::iteration_state::{IterationState, fingerprint};
use crate::driver::iterations::run_iterations;
use crate::error::OptionError;
use crate::exact_sum::ExactSum;
use crate::film::Film;
use crate::filter::Filter;
use crate::integrator::IntegratorKind;
use crate::options::RenderOptions;
use crate::photon::caustic::CAUSTIC_STREAM;
use crate::photon::eye_map::EyeVertex;
use crate::photon::plan::{CHUNK, PathStream, run_chunk};
use crate::photon::tracer::{MapKind, Photon, trace_one};
use crate::stats::RenderStats;
use crate::transport::direct::sample_direct;
use crate::transport::eye_walk::{EyeEvent, Flow, walk_eye};
use caustica_core::{PI, Spectrum, Vec3};
use caustica_density::estimator::median_knn_radius;
use caustica_scene::Scene;
use caustica_scene::bsdf::TransportMode;
use caustica_scene::intersection::NONE;
use std::cell::RefCell;

/// Random-number stream of SPPM's photons (the caustic stream: with `--caustics-only` the
/// same light paths as the other caustic methods).
const SPPM_STREAM: u64 = CAUSTIC_STREAM;

/// f64 values per pixel in a state file: R², N, τ (3).
const STATS_PER_PIXEL: usize = 5;

/// The statistics of one pixel.
#[derive(Clone, Copy, Debug)]
struct PixelStats {
    /// Squared radius (m²).
    r2: f64,
    /// Accumulated photon count N.
    n: f64,
    /// Accumulated reflected flux τ (W/sr per iteration's normalisation).
    tau: [f64; 3],
}

/// The photon splat rule of one iteration: photons within a visible point's pixel radius.
struct SppmSplat<'a> {
    scene: &'a Scene,
    opts: &'a RenderOptions,
    stream: PathStream,
    first: u64,
    paths: u64,
    /// Radius per pixel of the film's window (m).
    radius: &'a [f32],
    max_radius: f32,
    kind: MapKind,
    /// Photons with fewer edges from the light are skipped (2: direct light is the camera
    /// pass's; 1 for PPM, whose photons carry it).
    min_depth: u16,
}

impl SplatRule for SppmSplat<'_> {
    type Photon = Photon;
    /// Σ β f φ (W/sr) and the photon count.
    type Acc = ([f64; 3], u32);
    type Totals = u64;

    fn empty(&self) -> Self::Acc {
        ([0.0; 3], 0)
    }
    fn chunks(&self) -> u64 {
        self.paths.div_ceil(CHUNK)
    }
    fn trace_chunk(&self, c: u64, stats: &mut RenderStats) -> (Vec<Photon>, u64) {
        let lo = self.first + c * CHUNK;
        let hi = (lo + CHUNK).min(self.first + self.paths);
        let run = run_chunk(lo..hi, &self.stream, &|_, sampler, out, st| {
            trace_one(self.scene, sampler, self.opts, self.kind, out, st)
        });
        *stats += run.stats;
        let inv = 1.0 / self.paths.max(1) as f32;
        let mut photons: Vec<Photon> = run
            .records
            .into_iter()
            .filter(|p| p.depth >= self.min_depth)
            .collect();
        for p in &mut photons {
            p.flux *= inv;
        }
        let n = photons.len() as u64;
        (photons, n)
    }
    fn bounds(&self, ph: &Photon) -> Option<(Vec3, Vec3)> {
        let r = Vec3::splat(self.max_radius);
        Some((ph.p - r, ph.p + r))
    }
    fn splat(&self, ph: &Photon, v: &EyeVertex, acc: &mut Self::Acc) -> bool {
        let r = self.radius[v.pixel as usize];
        if (ph.p - v.p).length_squared() >= r * r || ph.n.dot(v.n) <= 0.0 {
            return false;
        }
        let f = v
            .bsdf
            .eval(v.wo, v.frame.to_local(ph.wi), TransportMode::Radiance);
        let c = v.beta * f * ph.flux;
        for k in 0..3 {
            acc.0[k] += c.c[k] as f64;
        }
        acc.1 += 1;
        true
    }
    fn resolve(&self, _: &EyeVertex, _: &Self::Acc, _: u64) -> [ExactSum; 3] {
        [ExactSum::ZERO; 3] // the statistics are updated per pixel instead
    }
}

/// Which of the two methods.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Visible {
    /// SPPM: new visible points every iteration, direct light by next-event estimation there.
    PerIteration,
    /// PPM (Hachisuka et al. 2008): the hit points of the first camera pass kept for the whole
    /// render, `--spp` of them per pixel (one by default; more anti-alias a fixed amount at
    /// the cost of their memory, the limitation HJ09 removed), every light (direct included)
    /// from the photons. (HOJ08 computes direct light by ray tracing at the hit points;
    /// carrying it by photons needs no sampler per hit point and converges to the same image.)
    /// The statistics are per pixel over its hit points, as SPPM's: with one hit point per
    /// pixel that is HOJ08's per-hit-point update; with several, the pixel's mean of them.
    Fixed,
}

/// Renders with SPPM (or PPM) into `film`; returns the statistics and the state after the last
/// complete iteration (none if there is none).
pub(crate) fn render(
    scene: &Scene,
    visible: Visible,
    opts: &RenderOptions,
    stage: &Stage,
    film: &mut Film,
    filter: &Filter,
    notes: &mut Vec<String>,
) -> Result<(RenderStats, Option<IterationState>), OptionError> {
    let p = &opts.photons.progressive;
    let ppm = visible == Visible::Fixed;
    let min_depth = if ppm { 1 } else { 2 };
    let integrator = if ppm {
        IntegratorKind::ProgressivePhotonMappingHitPoints
    } else {
        IntegratorKind::StochasticProgressivePhotonMapping
    };
    let fp = fingerprint(scene, integrator, opts);
    let kind = if opts.caustics_only {
        MapKind::Caustic
    } else {
        MapKind::Global
    };
    let m = p.paths_per_iteration;
    let stream = PathStream::new(opts, SPPM_STREAM);
    // The first radius: --radius, or the median k-NN distance among the first iteration's
    // photons.
    let r1 = match p.radius {
        Some(r) => r.get() as f64,
        None => {
            let run = run_chunk(0..m.min(16 * CHUNK), &stream, &|_, sampler, out, st| {
                trace_one(scene, sampler, opts, kind, out, st)
            });
            let photons: Vec<Photon> = run
                .records
                .into_iter()
                .filter(|p| p.depth >= min_depth)
                .collect();
            let map = crate::photon::map::PhotonMap::new(photons, m);
            median_knn_radius(&map.points(&opts.photons.estimate), opts.photons.estimate.k)
                .map(|r| r as f64)
                .unwrap_or_else(|| {
                    let r = (scene.geometry.bounds().extent().length() as f64 * 1e-3).max(1e-6);
                    notes.push(format!(
                        "warning: no indirect photons in the first iteration to choose a radius from; using {r:.4} m"
                    ));
                    r
                })
        }
    };
    let pixels = film.width * film.height;
    let stats = RefCell::new(vec![
        PixelStats {
            r2: r1 * r1,
            n: 0.0,
            tau: [0.0; 3],
        };
        pixels
    ]);
    let alpha = p.alpha;
    let spp = opts.spp.max(1) as f64;
    let cam = &scene.camera;
    // The photon term L = τ/(π R² I) after `iterations`, added to every camera sample of each
    // pixel of `film` (the pooled emission and direct light).
    let add_photons = |film: &mut Film, iterations: u64| {
        let i = iterations.max(1) as f64;
        for (px, s) in stats.borrow().iter().enumerate() {
            let c = film.count[px] as f64;
            for k in 0..3 {
                film.sum[px][k].add_f64(c * s.tau[k] / (PI as f64 * s.r2 * i));
            }
        }
    };
    // Resuming: the pooled film (emission and direct light) and the statistics.
    let first = match &opts.resume {
        Some(state) => {
            let next = state.restore_into(film, &fp, pixels * STATS_PER_PIXEL)?;
            for (s, x) in stats
                .borrow_mut()
                .iter_mut()
                .zip(state.extra.chunks_exact(STATS_PER_PIXEL))
            {
                *s = PixelStats {
                    r2: x[0],
                    n: x[1],
                    tau: [x[2], x[3], x[4]],
                };
            }
            notes.push(format!("resumed after iteration {}", state.iterations));
            next
        }
        None => 1,
    };
    let visible_points = RefCell::new(None);
    let present = |pooled: &Film, i: u64| {
        let mut f = pooled.clone();
        add_photons(&mut f, i);
        f
    };
    let snapshot = |pooled: &Film, i: u64| IterationState {
        fingerprint: fp.clone(),
        iterations: i,
        film: pooled.clone(),
        extra: stats
            .borrow()
            .iter()
            .flat_map(|s| [s.r2, s.n, s.tau[0], s.tau[1], s.tau[2]])
            .collect(),
    };
    let run = run_iterations(
        film,
        stage,
        first,
        p.max_iterations(opts),
        Some(&present),
        &snapshot,
        |i, st, f| {
            let o = p.iteration_options(opts, i);
            // 1. Camera pass: emission and direct light into the film, visible points recorded.
            // (PPM: its first iteration's only; a resumed PPM render makes them again, into a
            // film of its own, since the pooled film already holds their light.)
            let mut rs = RenderStats::default();
            let need = !ppm || visible_points.borrow().is_none();
            let cam_opts = if ppm {
                p.iteration_options(opts, 1)
            } else {
                o.clone()
            };
            let mut scratch = (ppm && i > 1).then(|| Film::cropped(f.window(), f.full.0, f.full.1));
            let target: &mut Film = match scratch.as_mut() {
                Some(s) => s,
                None => f,
            };
            let new_eye = need.then(|| {
                eye_pass(
                    target,
                    filter,
                    &cam_opts,
                    &st.part(0.0, 0.3).labelled("camera pass"),
                    |sampler, raster, pixel, out: &mut Vec<EyeVertex>, rst| {
                        let u_lens = sampler.next_2d();
                        let time = scene.sample_time(|| sampler.next_1d());
                        let ray = cam.generate_ray(raster, u_lens).ray.at_time(time);
                        let mut l = Spectrum::ZERO;
                        walk_eye(
                            scene,
                            ray,
                            scene.camera_medium,
                            sampler,
                            u32::MAX,
                            rst,
                            |event, sampler, rst| match event {
                                EyeEvent::Escaped { ray, beta } => {
                                    if !o.caustics_only {
                                        for &li in &scene.infinite_lights {
                                            l += beta
                                                * scene.lights[li as usize].le(Vec3::ZERO, -ray.d);
                                        }
                                    }
                                    Flow::Stop
                                }
                                EyeEvent::Medium { .. } => Flow::Continue,
                                EyeEvent::Vertex {
                                    v,
                                    medium,
                                    wo,
                                    beta,
                                    depth,
                                } => {
                                    if !o.caustics_only && v.si.light != NONE {
                                        l += beta
                                            * scene.lights[v.si.light as usize].le(v.si.ng, wo);
                                    }
                                    if depth >= o.limits.max_depth {
                                        return Flow::Stop;
                                    }
                                    let smooth = v.bsdf.flags().is_smooth();
                                    if o.caustics_only && !smooth {
                                        // L S+ D E only (as pm and the light tracer): a
                                        // caustic seen through glass or in a mirror is not one.
                                        return Flow::Stop;
                                    }
                                    if smooth {
                                        if !o.caustics_only && !ppm {
                                            l += beta
                                                * sample_direct(
                                                    scene, v, medium, sampler, rst, false,
                                                );
                                        }
                                        out.push(EyeVertex::new(v, beta, pixel));
                                        return Flow::Stop;
                                    }
                                    Flow::Continue
                                }
                            },
                        );
                        l
                    },
                )
            });
            if let Some((eye, r)) = new_eye {
                rs = r;
                *visible_points.borrow_mut() = Some(eye);
            }
            let held = visible_points.borrow();
            let Some(eye) = held.as_ref() else {
                return rs;
            };
            // 2. Photons splatted onto the visible points at each pixel's radius.
            let radius: Vec<f32> = stats.borrow().iter().map(|s| s.r2.sqrt() as f32).collect();
            let max_radius = radius.iter().copied().fold(0.0f32, f32::max);
            let rule = SppmSplat {
                scene,
                opts: &o,
                stream,
                first: o.photons.first_path,
                paths: m,
                radius: &radius,
                max_radius,
                kind,
                min_depth,
            };
            let done = splat_batches(f, eye, &rule, &st.part(0.3, 1.0).labelled("photons"), None);
            rs.rays += done.stats.rays;
            if done.chunks_done < rule.chunks() {
                // Stopped inside the photon pass: the driver drops (or, the first, keeps as partial)
                // this iteration; its photons do not enter the statistics.
                return rs;
            }
            // 3. The per-pixel update, from the means over each pixel's samples.
            let mut phi = vec![([0.0f64; 3], 0.0f64); pixels];
            for (tile, acc) in eye.tiles.iter().zip(&done.acc) {
                for (v, a) in tile.vertices.iter().zip(acc) {
                    let e = &mut phi[v.pixel as usize];
                    for k in 0..3 {
                        e.0[k] += a.0[k] / spp;
                    }
                    e.1 += a.1 as f64 / spp;
                }
            }
            for (s, (phi, mi)) in stats.borrow_mut().iter_mut().zip(phi) {
                if mi > 0.0 {
                    let n_new = s.n + alpha * mi;
                    let ratio = n_new / (s.n + mi);
                    for (t, f) in s.tau.iter_mut().zip(phi) {
                        *t = (*t + f) * ratio;
                    }
                    s.n = n_new;
                    s.r2 *= ratio;
                }
            }
            rs
        },
    );
    let done = run.last.max(first - 1);
    let state = (done > 0).then(|| snapshot(film, done));
    add_photons(film, done);
    let r = stats.borrow();
    let mut radii: Vec<f64> = r.iter().map(|s| s.r2.sqrt()).collect();
    radii.sort_by(f64::total_cmp);
    notes.push(format!(
        "{}: {} iterations of {m} light paths, alpha {:.4}; radius {r1:.5} -> median {:.5} m (min {:.5}, max {:.5}){}",
        if ppm { "ppm" } else { "sppm" },
        run.last,
        alpha,
        radii.get(radii.len() / 2).copied().unwrap_or(0.0),
        radii.first().copied().unwrap_or(0.0),
        radii.last().copied().unwrap_or(0.0),
        match run.stopped {
            Some(why) => format!(", stopped {why}"),
            None => String::new(),
        }
    ));
    Ok((run.stats, state))
}
