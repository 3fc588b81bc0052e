//! Unidirectional volumetric path tracer with next-event estimation, MIS (power heuristic)
//! and Russian roulette. Radiance estimate of one camera ray (W/m²/sr). Its own loop (MIS needs
//! the previous vertex's pdf at every emitter hit), over the shared segment and vertex code of
//! [`crate::transport`]. The path's terms are summed by a [`PathSum`] of a [`DirectBatch`], which
//! lets the next-event estimates its lanes cover wait and computes them four at a time across
//! consecutive paths, the bits unchanged. In RGB scenes without media lit by lights the lanes'
//! kernel covers ([`super::path_lanes::covers`]: triangle area, point and directional lights)
//! the `path` integrator runs [`super::path_lanes`] instead: this estimator with eight paths in
//! SIMD lanes while they meet diffuse surfaces, each finished by this loop ([`continue_path`])
//! from its first other surface on, the same image bit for bit.
//!
//! In media, [`trace_segment`] samples free flights (delta tracking with spectral MIS); at a
//! medium vertex direct light comes from NEE through the media (phase function against the
//! light's pdf, MIS with phase sampling) and the path continues by sampling the phase function
//! — the radiative transfer equation (seed 000 eq. 8.1) estimated as Mitsuba 3's `volpath`
//! and pbrt-v4's `VolPathIntegrator` do. Medium vertices count as path vertices for
//! `max_depth` and roulette.

use crate::options::RenderOptions;
use crate::stats::RenderStats;
use crate::transport::direct::{direct_with, sample_direct, sample_direct_at};
use crate::transport::direct_lanes::DirectBatch;
use crate::transport::limits::russian_roulette;
use crate::transport::medium::{Segment, trace_segment};
use crate::transport::vertex::{MediumVertex, Scatterer, Vertex};
use caustica_core::sampling::Sampler;
use caustica_core::sampling::warp::power_heuristic;
use caustica_core::{Channels, Ray, Spectrum, Vec2, Vec3};
use caustica_scene::Scene;
use caustica_scene::bsdf::TransportMode;
use caustica_scene::intersection::NONE;
use caustica_scene::phase::Phase;

/// What a camera path does at its surface vertices beyond path tracing: photon cone focusing
/// ends the path at a lookup vertex with its cone-map estimate (seed 001 eq. 3.14) and, nested,
/// replaces next-event estimation before it by direct-light cones (sec. 3.6). The plain path
/// tracer is [`PathOnly`].
pub trait CameraRule {
    /// At surface vertex `depth` (1 = the first hit), after the emission found there was
    /// counted: `Some` ends the path there with the [`Lookup`]'s radiance.
    fn lookup(&self, v: &Vertex, depth: u32, stats: &mut RenderStats) -> Option<Lookup> {
        let _ = (v, depth, stats);
        None
    }
    /// Sees every surface vertex the camera path reaches (`depth` from 1) with the path
    /// throughput `beta` up to it, before anything else happens there (pcf's importons are
    /// recorded here).
    fn visit(&self, v: &Vertex, depth: u32, beta: Spectrum) {
        let _ = (v, depth, beta);
    }
    /// Direct light at a vertex that does not look up ([`Direct`]).
    fn direct(&self, v: &Vertex, depth: u32, stats: &mut RenderStats) -> Direct {
        let _ = (v, depth, stats);
        Direct::Nee
    }
    /// True when a light tracer beside the path tracer counts the paths E D … S L (the camera
    /// path's first vertex scattered by a non-delta lobe, the last before the light by a delta
    /// lobe): the light tracer's L S … D E ([`crate::integrator::light_tracer::Connect::SpecularFirst`])
    /// read from the other end, whose emission the path tracer then drops. The `hybrid`
    /// integrator.
    fn light_tracer_beside(&self) -> bool {
        false
    }
}

/// What a camera path ends with at its lookup vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lookup {
    /// Radiance (W/m²/sr) the vertex scatters toward the previous one, from the rule.
    pub radiance: Spectrum,
    /// Add next-event estimation without MIS (all direct light, the bounce that would find
    /// emission is not taken): the rule's radiance then excludes direct light.
    pub nee: bool,
}

/// How a vertex before the lookup gets its direct light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Direct {
    /// Next-event estimation (at non-delta vertices), MIS-combined with the emission the next
    /// bounce finds: the path tracer.
    Nee,
    /// `L` (W/m²/sr) is all the direct light the vertex scatters, in place of NEE, and the
    /// emission the next bounce finds is not counted (it is in `L`).
    Replace(Spectrum),
    /// `L` (W/m²/sr) is added to what the path tracer does there: light it cannot find (a delta
    /// light seen through a delta vertex).
    Add(Spectrum),
}

/// The path tracer's rule: no lookups, NEE everywhere.
pub struct PathOnly;

impl CameraRule for PathOnly {}

/// The radiance (W/m²/sr, linear sRGB) of one camera sample at `raster` under `rule` (the path
/// tracer's is [`PathOnly`]): the lens sample, the time, the path's wavelengths in spectral mode,
/// then the path, in that sampler order. `None` when the radiance waits in `batch` (see
/// [`radiance_deferred`]). `ext` is the camera's
/// [`caustica_scene::camera::PerspectiveCamera::screen_half_extent`], computed once by the
/// caller (a tangent per sample otherwise).
#[allow(clippy::too_many_arguments)]
pub fn camera_radiance<'s>(
    scene: &'s Scene,
    raster: Vec2,
    ext: Vec2,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    stats: &mut RenderStats,
    rule: &impl CameraRule,
    batch: &mut DirectBatch<'s>,
) -> Option<Spectrum> {
    let (ray, ch) = camera_ray(scene, raster, ext, sampler);
    radiance_deferred(scene, ray, sampler, opts, stats, rule, ch, batch)
}

/// The camera ray of a sample at `raster` and its path's lanes: the lens sample, the time, then
/// the wavelengths in spectral mode, in that sampler order. `ext` is the camera's
/// [`caustica_scene::camera::PerspectiveCamera::screen_half_extent`].
#[inline]
pub fn camera_ray(
    scene: &Scene,
    raster: Vec2,
    ext: Vec2,
    sampler: &mut Sampler,
) -> (Ray, Channels) {
    let u_lens = sampler.next_2d();
    let time = scene.sample_time(|| sampler.next_1d());
    let ray = scene.camera.ray(raster, u_lens, ext).at_time(time);
    (ray, scene.sample_channels(|| sampler.next_1d()))
}

/// The MIS weight (power heuristic, Veach 1997) of the emission of light `li` found at `p`
/// (normal `n`; both zero for an environment light) in direction `d`, sampled at the previous
/// vertex `prev_p` with density `prev_pdf`, against next-event estimation's light sampling there.
#[inline]
pub fn emission_mis(
    scene: &Scene,
    li: u32,
    prev_pdf: f32,
    prev_p: Vec3,
    d: Vec3,
    p: Vec3,
    n: Vec3,
) -> f32 {
    let light = &scene.lights[li as usize];
    power_heuristic(
        prev_pdf,
        scene.light_pmf(li) * light.pdf_li(prev_p, d, p, n),
    )
}

/// [`radiance_deferred`] computed at once: every next-event estimate where the path finds it.
pub fn radiance_with(
    scene: &Scene,
    ray: Ray,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    stats: &mut RenderStats,
    rule: &impl CameraRule,
    ch: Channels,
) -> Spectrum {
    let mut batch = DirectBatch::one_by_one();
    let l = radiance_deferred(scene, ray, sampler, opts, stats, rule, ch, &mut batch);
    debug_assert!(
        l.is_some(),
        "a batch that computes one by one holds nothing back"
    );
    l.unwrap_or(Spectrum::ZERO)
}

/// The radiance arriving at the camera along `ray` under a [`CameraRule`], for a path with lanes `ch` (the rules of the photon
/// family run in RGB, their estimates being RGB); the result is in linear sRGB. Same sampler
/// use whatever the rule does. `None` when a next-event estimate waits in `batch`'s lanes: its
/// [`DirectBatch::finish`] gives the radiance then (only paths in RGB wait, so it needs no
/// conversion).
#[allow(clippy::too_many_arguments)]
pub fn radiance_deferred<'s>(
    scene: &'s Scene,
    ray: Ray,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    stats: &mut RenderStats,
    rule: &impl CameraRule,
    ch: Channels,
    batch: &mut DirectBatch<'s>,
) -> Option<Spectrum> {
    let start = PathState::camera(scene, ray, ch);
    continue_path(scene, start, None, None, sampler, opts, stats, rule, batch)
}

/// What the path loop carries from one vertex to the next: where a camera path stands before
/// its next segment. [`super::path_lanes`] hands a path over to the loop in this form.
#[derive(Clone, Copy, Debug)]
pub struct PathState {
    /// The ray of the next segment, and the medium it starts in.
    pub ray: Ray,
    pub medium: u32,
    /// Throughput (dimensionless, per lane of `ch`).
    pub beta: Spectrum,
    /// Edges traced so far.
    pub depth: u32,
    /// The previous vertex, for MIS of emission found by BSDF or phase sampling: delta lobe,
    /// density of the sampled direction, position.
    pub prev_delta: bool,
    pub prev_pdf: f32,
    pub prev_p: Vec3,
    /// The previous vertex's direct light came from the rule: emission found next is in it.
    pub prev_direct_by_rule: bool,
    /// Whether the first scattering on a surface was non-delta (`None` before it): emission
    /// found after a delta bounce on such a path is the light tracer's when one runs beside
    /// (`CameraRule::light_tracer_beside`).
    pub first_diffuse: Option<bool>,
    /// What the lanes of the path's values mean.
    pub ch: Channels,
}

impl PathState {
    /// A path about to trace its camera ray `ray`, with lanes `ch`.
    pub fn camera(scene: &Scene, ray: Ray, ch: Channels) -> Self {
        Self {
            ray,
            medium: scene.camera_medium,
            beta: Spectrum::ONE,
            depth: 0,
            prev_delta: true,
            prev_pdf: 0.0,
            prev_p: Vec3::ZERO,
            prev_direct_by_rule: false,
            first_diffuse: None,
            ch,
        }
    }
}

/// [`radiance_deferred`] from `state` on: the path's first segment is `first` when it is
/// already traced (else the loop traces it), and `sum` (W/m²/sr), when given, is the sum of the
/// terms the path found before, added as its first term (the same bits as adding them one by
/// one: 0 + sum is sum).
#[allow(clippy::too_many_arguments)]
pub fn continue_path<'s>(
    scene: &'s Scene,
    state: PathState,
    mut first: Option<Segment>,
    sum: Option<Spectrum>,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    stats: &mut RenderStats,
    rule: &impl CameraRule,
    batch: &mut DirectBatch<'s>,
) -> Option<Spectrum> {
    let mut l = batch.path(scene);
    if let Some(sum) = sum {
        l.add(sum);
    }
    let PathState {
        mut ray,
        mut medium,
        mut beta,
        mut depth,
        mut prev_delta,
        mut prev_pdf,
        mut prev_p,
        mut prev_direct_by_rule,
        mut first_diffuse,
        mut ch,
    } = state;
    let beside = rule.light_tracer_beside();
    loop {
        let segment = match first.take() {
            Some(segment) => segment,
            None => trace_segment(scene, &ray, &mut medium, sampler, stats, &ch),
        };
        let (si, transmittance) = match segment {
            Segment::Surface { si, transmittance } => (si, transmittance),
            Segment::Escaped { transmittance } => {
                beta *= transmittance;
                for &li in &scene.infinite_lights {
                    let light = &scene.lights[li as usize];
                    let le = scene.light_emission(li as usize, light.le(Vec3::ZERO, -ray.d), &ch);
                    let w = if prev_direct_by_rule
                        || (beside && prev_delta && first_diffuse == Some(true))
                    {
                        0.0
                    } else if prev_delta {
                        1.0
                    } else {
                        emission_mis(scene, li, prev_pdf, prev_p, ray.d, Vec3::ZERO, Vec3::ZERO)
                    };
                    l.add(beta * le * w);
                }
                break;
            }
            Segment::Medium {
                p,
                medium: m,
                weight,
            } => {
                depth += 1;
                beta *= weight;
                first_diffuse.get_or_insert(false);
                if depth >= opts.limits.max_depth || beta.is_black() {
                    break;
                }
                let mv = MediumVertex::new(scene, p, &ray, m, &ch);
                l.add(beta * sample_direct_at(scene, Scatterer::Medium(&mv), sampler, stats, true));
                prev_direct_by_rule = false;
                let u = sampler.next_2d();
                let u_rr = sampler.next_1d();
                let Some(ps) = mv.phase.sample(mv.wo, u) else {
                    break;
                };
                beta *= ps.weight;
                prev_delta = false;
                prev_pdf = ps.pdf;
                prev_p = p;
                if !russian_roulette(&mut beta, depth, opts.limits.rr_depth, u_rr) {
                    break;
                }
                ray = Ray::new(p, ps.wi).at_time(ray.time);
                continue;
            }
        };
        depth += 1;
        beta *= transmittance;
        if si.light != NONE {
            let light = &scene.lights[si.light as usize];
            let le = scene.light_emission(si.light as usize, light.le(si.ng, -ray.d), &ch);
            if !le.is_black() {
                let w = if prev_direct_by_rule
                    || (beside && prev_delta && first_diffuse == Some(true))
                {
                    0.0
                } else if prev_delta {
                    1.0
                } else {
                    emission_mis(scene, si.light, prev_pdf, prev_p, ray.d, si.p, si.ng)
                };
                l.add(beta * le * w);
            }
        }
        if depth >= opts.limits.max_depth {
            break;
        }
        let v = Vertex::new(scene, si, &ray, &mut ch);
        rule.visit(&v, depth, beta);
        if let Some(lo) = rule.lookup(&v, depth, stats) {
            l.add(beta * lo.radiance);
            if lo.nee {
                l.add(beta * sample_direct(scene, &v, medium, sampler, stats, false));
            }
            break;
        }
        let flags = v.bsdf.flags();
        // Fixed dimension layout per bounce: 3 for NEE (+2 for its shadow ray in scenes with
        // media), 3 for the BSDF, 1 for roulette.
        let by_rule = rule.direct(&v, depth, stats);
        prev_direct_by_rule = matches!(by_rule, Direct::Replace(_));
        if let Direct::Add(ld) | Direct::Replace(ld) = by_rule {
            l.add(beta * ld);
        }
        if flags.is_smooth() && !prev_direct_by_rule {
            // Estimates the lanes cover wait for them (`direct_lanes`); the same numbers, the
            // same bits.
            let u_light = sampler.next_1d();
            let u = sampler.next_2d();
            if !l.defer_direct(beta, &v, u_light, u) {
                let at = Scatterer::Surface { v: &v, medium };
                l.add(beta * direct_with(scene, at, u_light, u, sampler, stats, true));
            }
        } else {
            sampler.next_1d();
            sampler.next_2d();
            if scene.has_media {
                sampler.next_2d();
            }
        }
        let uc = sampler.next_1d();
        let u = sampler.next_2d();
        let u_rr = sampler.next_1d();
        let Some(bs) = v.bsdf.sample(v.wo, uc, u, TransportMode::Radiance) else {
            break;
        };
        let wi = v.frame.to_world(bs.wi);
        if !v.same_side_consistent(-ray.d, wi, bs.wi) {
            break;
        }
        beta *= bs.weight;
        prev_delta = bs.flags.is_delta();
        first_diffuse.get_or_insert(!prev_delta);
        prev_pdf = bs.pdf;
        prev_p = v.si.p;
        if beta.is_black() {
            break;
        }
        if !russian_roulette(&mut beta, depth, opts.limits.rr_depth, u_rr) {
            break;
        }
        medium = v.si.medium_toward(wi, medium);
        ray = v.si.spawn_ray(wi);
    }
    l.total().map(|l| ch.to_rgb(l))
}
