//! The one light-path walker shared by every light-side integrator: the light tracer connects
//! its vertices to the camera, the photon tracer stores them as photons.
//!
//! A path starts at a light chosen in proportion to power and an emission sample of that light
//! (origin, direction, and the frame at the origin); it then scatters by BSDF sampling in
//! importance mode, with Russian roulette, until it leaves the scene or reaches `max_depth`.

use crate::stats::RenderStats;
use crate::transport::emission::{Emission, Emitted, emit};
use crate::transport::limits::{PathLimits, russian_roulette};
use crate::transport::medium::{Segment, trace_segment};
use crate::transport::time::PathTime;
use crate::transport::vertex::{MediumVertex, Vertex, emission_ray};
use caustica_core::sampling::Sampler;
use caustica_core::{Channels, Ray, Spectrum, Vec3};
use caustica_scene::Scene;
use caustica_scene::bsdf::{BsdfSample, TransportMode};
use caustica_scene::intersection::NONE;
use caustica_scene::light::{EmissionDensity, EmissionSample};
use caustica_scene::phase::{Phase, PhaseSample};

/// The start of a light path.
pub struct LightStart<'a> {
    pub light: usize,
    /// Discrete probability of having chosen this light.
    pub pmf: f32,
    pub emission: &'a EmissionSample,
    /// The ray the walker traces first: the emission ray with its origin moved off the
    /// emitting surface ([`emission_ray`]).
    pub ray: Ray,
    /// The medium the light emits into (`Scene::light_media`), or `NONE`.
    pub medium: u32,
    /// The lanes of the path: RGB, or the wavelengths it sampled (spectral mode). Values of
    /// the path go to the film or a photon map through [`Channels::to_rgb`].
    pub channels: Channels,
    /// The emission's relative density against uniform emission (`emission.weight` is already
    /// divided by it): photon differentials shrink their initial vectors by it.
    pub density: EmissionDensity,
}

/// A surface vertex of a light path, as seen by the visitor.
pub struct LightVertex<'a> {
    pub v: &'a Vertex,
    /// Unit direction back toward where the light came from (world space), −ray direction.
    pub wo: Vec3,
    /// Path throughput up to (and including the transmittance before) this vertex: the flux in W
    /// this path carries into the vertex, before dividing by the number of emitted paths.
    pub beta: Spectrum,
    /// Edges from the light to this vertex (1: the light shines on it directly).
    pub depth: u32,
    /// True when every earlier scattering vertex of the path was delta (mirror or glass) and
    /// there was at least one: the vertex receives caustic light, L S+ x.
    pub after_specular_chain: bool,
    /// The medium of the ray that reached the vertex (`NONE` = vacuum).
    pub medium: u32,
}

/// A real scattering event of a light path inside a medium, as seen by the visitor.
pub struct LightMediumVertex<'a> {
    pub v: &'a MediumVertex,
    /// Path throughput into the vertex including the free flight's weight σ_s T / p: the flux
    /// (W) this path carries into the scattering, before dividing by the number of paths.
    pub beta: Spectrum,
    /// Edges from the light to this vertex.
    pub depth: u32,
    /// True when every earlier scattering vertex was delta and there was at least one: the
    /// vertex is lit by a volume caustic, L S+ M.
    pub after_specular_chain: bool,
}

impl LightVertex<'_> {
    /// True where a light path ends as a caustic: a non-delta surface reached through one or
    /// more delta vertices (L S+ D). The one rule of the caustic photon map, photon
    /// differentials, the light tracer's caustics-only mode and the pds counting pass.
    #[inline]
    pub fn is_caustic(&self) -> bool {
        self.after_specular_chain && self.v.bsdf.flags().is_smooth()
    }
}

impl LightScatter<'_> {
    /// True if a path that is still a caustic candidate stays one after this scattering: only
    /// delta scattering keeps it (after a non-delta bounce no later vertex receives caustic
    /// light, L S+ D). Caustic tracers end their paths where this is false.
    #[inline]
    pub fn keeps_caustic(&self) -> bool {
        self.sample.flags.is_delta()
    }
}

/// What [`walk_light_path`] shows its visitor.
pub enum LightEvent<'a> {
    /// Once, first: the emission sample.
    Start(&'a LightStart<'a>),
    /// At every surface hit, delta or not (the visitor decides what to do with it).
    Vertex(&'a LightVertex<'a>),
    /// At every real scattering event in a medium.
    Medium(&'a LightMediumVertex<'a>),
}

/// The scattering the walker sampled at a vertex, shown to [`LightVisitor::scatter`] before the
/// path continues: photon differentials (`photon_differential`) need to know whether the sampled
/// delta lobe reflected or refracted, and with which relative IOR.
pub struct LightScatter<'a> {
    pub v: &'a Vertex,
    /// Unit direction back toward where the light came from (world space).
    pub wo: Vec3,
    /// Unit direction the path continues in (world space).
    pub wi: Vec3,
    /// The BSDF sample (local `wi`, lobe flags, relative IOR `eta` = η_t/η_i, 1 for
    /// reflection).
    pub sample: &'a BsdfSample,
}

/// A visitor of [`walk_light_path_with`]: `event` at the start and at every surface hit (as
/// the closure of [`walk_light_path`]), and `scatter` after each successful BSDF sample, before
/// throughput update and roulette. `scatter` returns false to end the path there (e.g. a caustic
/// tracer after the first non-delta bounce); the default continues and draws nothing.
pub trait LightVisitor {
    fn event(&mut self, event: LightEvent, sampler: &mut Sampler, stats: &mut RenderStats);
    fn scatter(&mut self, scatter: &LightScatter, stats: &mut RenderStats) -> bool {
        let _ = (scatter, stats);
        true
    }
    /// After the phase function was sampled at a medium vertex (the sample's new direction
    /// `wi` and its density): false ends the path there. A scattering in a medium is not delta,
    /// so caustic tracers end here.
    fn scatter_in_medium(&mut self, v: &LightMediumVertex, sample: &PhaseSample) -> bool {
        let _ = (v, sample);
        true
    }
}

/// A closure as a [`LightVisitor`] that only sees events.
pub struct EventsOnly<F>(pub F);

impl<F: FnMut(LightEvent, &mut Sampler, &mut RenderStats)> LightVisitor for EventsOnly<F> {
    fn event(&mut self, event: LightEvent, sampler: &mut Sampler, stats: &mut RenderStats) {
        (self.0)(event, sampler, stats)
    }
}

/// Walks one light path, calling `visit` once with [`LightEvent::Start`] and then with
/// [`LightEvent::Vertex`] at every surface hit. Sampler use: 5 dimensions to start (6 in
/// spectral mode: the wavelengths), then
/// whatever the visitor draws at each event, and 4 per vertex for scattering and roulette.
pub fn walk_light_path(
    scene: &Scene,
    sampler: &mut Sampler,
    limits: &PathLimits,
    stats: &mut RenderStats,
    visit: impl FnMut(LightEvent, &mut Sampler, &mut RenderStats),
) {
    walk_light_path_with(scene, sampler, limits, stats, &mut EventsOnly(visit))
}

/// [`walk_light_path`] with a [`LightVisitor`] that also sees each sampled scattering (and may
/// end the path there). Same sampler use as [`walk_light_path`]: a visitor that never ends a
/// path sees the same path.
pub fn walk_light_path_with(
    scene: &Scene,
    sampler: &mut Sampler,
    limits: &PathLimits,
    stats: &mut RenderStats,
    visitor: &mut impl LightVisitor,
) {
    walk_light_path_at(
        scene,
        sampler,
        limits,
        stats,
        visitor,
        PathTime::Shutter,
        Emission::Uniform,
    )
}

/// [`walk_light_path_with`] at the time `time` chooses (in a moving scene one more number is
/// drawn first, unless `time` is the instant), emitted by `emission` (the same numbers are
/// drawn whatever the rule).
pub fn walk_light_path_at(
    scene: &Scene,
    sampler: &mut Sampler,
    limits: &PathLimits,
    stats: &mut RenderStats,
    visitor: &mut impl LightVisitor,
    time: PathTime,
    emission: Emission,
) {
    let time = time.sample(scene, sampler);
    let u_light = sampler.next_1d();
    let u_pos = sampler.next_2d();
    let u_dir = sampler.next_2d();
    if scene.light_distribution.is_none() {
        return;
    }
    let mut ch = scene.sample_channels(|| sampler.next_1d());
    let Some(Emitted {
        light: li,
        pmf,
        mut es,
        density,
    }) = emit(scene, emission, u_light, u_pos, u_dir)
    else {
        return;
    };
    es.weight = scene.light_emission(li, es.weight, &ch);
    let mut ray = emission_ray(&es).at_time(time);
    let mut medium = scene.light_media.get(li).copied().unwrap_or(NONE);
    visitor.event(
        LightEvent::Start(&LightStart {
            light: li,
            pmf,
            emission: &es,
            ray,
            medium,
            channels: ch,
            density,
        }),
        sampler,
        stats,
    );
    let mut beta = es.weight / pmf;
    let mut depth = 1u32; // edges of the path including the one being traced
    let mut all_delta = true; // every scattering vertex so far was delta
    loop {
        let (si, transmittance) = match trace_segment(scene, &ray, &mut medium, sampler, stats, &ch)
        {
            Segment::Surface { si, transmittance } => (si, transmittance),
            Segment::Escaped { .. } => break,
            Segment::Medium {
                p,
                medium: m,
                weight,
            } => {
                beta *= weight;
                if beta.is_black() {
                    break;
                }
                let mv = MediumVertex::new(scene, p, &ray, m, &ch);
                let lmv = LightMediumVertex {
                    v: &mv,
                    beta,
                    depth,
                    after_specular_chain: all_delta && depth >= 2,
                };
                visitor.event(LightEvent::Medium(&lmv), sampler, stats);
                let u = sampler.next_2d();
                let u_rr = sampler.next_1d();
                if depth + 1 >= limits.max_depth {
                    break;
                }
                let Some(ps) = mv.phase.sample(mv.wo, u) else {
                    break;
                };
                if !visitor.scatter_in_medium(&lmv, &ps) {
                    break;
                }
                beta *= ps.weight;
                all_delta = false;
                depth += 1;
                if !russian_roulette(&mut beta, depth, limits.rr_depth, u_rr) {
                    break;
                }
                ray = Ray::new(p, ps.wi).at_time(ray.time);
                continue;
            }
        };
        beta *= transmittance;
        let v = Vertex::new(scene, si, &ray, &mut ch);
        let wo = -ray.d;
        visitor.event(
            LightEvent::Vertex(&LightVertex {
                v: &v,
                wo,
                beta,
                depth,
                after_specular_chain: all_delta && depth >= 2,
                medium,
            }),
            sampler,
            stats,
        );
        let uc = sampler.next_1d();
        let u = sampler.next_2d();
        let u_rr = sampler.next_1d();
        if depth + 1 >= limits.max_depth {
            break;
        }
        let Some(bs) = v.bsdf.sample(v.wo, uc, u, TransportMode::Importance) else {
            break;
        };
        let wi = v.frame.to_world(bs.wi);
        if !v.same_side_consistent(wo, wi, bs.wi) {
            break;
        }
        let scatter = LightScatter {
            v: &v,
            wo,
            wi,
            sample: &bs,
        };
        if !visitor.scatter(&scatter, stats) {
            break;
        }
        beta *= bs.weight * v.shading_normal_correction(wo, wi, TransportMode::Importance);
        if beta.is_black() {
            break;
        }
        all_delta &= bs.flags.is_delta();
        depth += 1;
        if !russian_roulette(&mut beta, depth, limits.rr_depth, u_rr) {
            break;
        }
        medium = v.si.medium_toward(wi, medium);
        ray = v.si.spawn_ray(wi);
    }
}
