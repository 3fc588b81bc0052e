//! Photon mapping (Jensen 1996; seed 000 ch. 3): two photon maps, then camera paths that follow
//! specular chains to the first non-delta surface x, where the reflected radiance is
//!
//!   L(x → ω) = L_direct (next-event estimation, light sampling only)
//!            + L_caustic (radiance estimate, eq. 3.2, in the caustic map: L S+ D photons)
//!            + L_indirect (final gathering: BSDF-sampled rays, through specular chains, to
//!              the first non-delta surface y, where the global map's estimate gives the
//!              radiance leaving y toward x).
//!
//! Every light path is counted once: emission reached after a non-delta bounce only by NEE,
//! L S+ x only by the caustic map, and paths through another diffuse vertex only by the gather.
//! With `final_gather = 0` the global map is visualised directly: L(x) is the global estimate at
//! x (direct, caustic and indirect light together; fast and blotchy).

use super::IntegratorKind;
use crate::control::Stage;
use crate::options::{CausticEstimator, RenderOptions};
use crate::photon::caustic::{CausticEstimate, global_radiance};
use crate::photon::differential::volume_trace::{KernelRule, trace_volume_differentials};
use crate::photon::kernel_boundary::KernelBoundary;
use crate::photon::map::PhotonMap;
use crate::photon::tracer::{MapKind, TracedPhotons, trace_photons};
use crate::photon::volume_map::{VolumeEstimate, VolumeMap};
use crate::stats::RenderStats;
use crate::transport::direct::sample_direct;
use crate::transport::emission::caustic_emission_notes;
use crate::transport::eye_walk::{EyeEvent, Flow, walk_eye};
use crate::transport::vertex::Vertex;
use caustica_core::sampling::Sampler;
use caustica_core::{Ray, Spectrum, Vec3};
use caustica_scene::Scene;
use caustica_scene::bsdf::TransportMode;
use caustica_scene::intersection::NONE;

/// Random-number stream of the global map (the caustic map's is
/// [`crate::photon::caustic::CAUSTIC_STREAM`]; the camera pass uses pixel streams).
const GLOBAL_STREAM: u64 = 0x610B;
/// Random-number stream of the volume map.
const VOLUME_STREAM: u64 = 0x7601;
/// Longest specular chain a final-gather ray follows.
const MAX_GATHER_CHAIN: u32 = 16;

/// The photon maps of a render: the caustic estimate and the global map.
pub struct PhotonMaps {
    pub caustic: CausticEstimate,
    pub global: PhotonMap,
    /// Volume photons, in scenes with scattering media: in-scattered light along camera and
    /// final-gather rays (seed 000 eq. 8.3 or 8.4).
    pub volume: Option<VolumeMap>,
    /// Photon-tracing work.
    pub stats: RenderStats,
    /// Messages for the user (e.g. fewer photons than requested).
    pub warnings: Vec<String>,
    /// Facts about the maps for the render's notes (e.g. dropped photon differentials).
    pub notes: Vec<String>,
}

impl PhotonMaps {
    /// The maps of photon integrator `kind`: `pm`'s caustic map with
    /// `opts.photons.caustic_estimator` (k-NN by default), `dpm`'s with the diffusion estimate,
    /// `pdm`'s footprints (the same light paths, traced as photon differentials), or none for
    /// `pds` (it splats them); and the global map. `progress` sees the fraction done.
    pub fn for_integrator(
        scene: &Scene,
        kind: IntegratorKind,
        opts: &RenderOptions,
        progress: &mut dyn FnMut(f64) -> bool,
    ) -> Self {
        let density = |estimator, progress: &mut dyn FnMut(f64) -> bool| {
            let (caustic, traced) = CausticEstimate::density(scene, estimator, opts, progress);
            (caustic, traced.warning, traced.note, traced.stats)
        };
        Self::with_caustic(scene, opts, progress, |progress| match kind {
            // Only the volume estimate is wanted: no surface is shaded.
            _ if opts.volume_only => (CausticEstimate::None, None, None, RenderStats::default()),
            IntegratorKind::DiffusionPhotonMapping => match opts.time_limit {
                // The diffusion pre-passes cost several times the tracing per photon and the
                // clock does not cut them: under a time budget the caustic pass stores at most
                // what the pre-passes get through in most of the photon pass's share.
                Some(limit) => {
                    let secs = limit.as_secs_f64() * PHOTON_SHARE * DIFFUSION_PREPASS_SHARE;
                    let cap = ((secs * DIFFUSION_PHOTONS_PER_SECOND) as usize).max(1000);
                    let mut capped = opts.clone();
                    capped.photons.caustic_photons = opts.photons.caustic_photons.min(cap);
                    let (caustic, traced) = CausticEstimate::density(
                        scene,
                        CausticEstimator::Diffusion,
                        &capped,
                        progress,
                    );
                    (caustic, traced.warning, traced.note, traced.stats)
                }
                None => density(CausticEstimator::Diffusion, progress),
            },
            IntegratorKind::PhotonDifferentialMapping
            | IntegratorKind::VolumePhotonDifferentials => {
                CausticEstimate::footprints(scene, opts, progress)
            }
            IntegratorKind::PhotonDifferentialSplatting => (
                CausticEstimate::Splatted,
                None,
                None,
                RenderStats::default(),
            ),
            _ => density(opts.photons.caustic_estimator.unwrap_or_default(), progress),
        })
    }

    /// The maps of `pm` ([`PhotonMaps::for_integrator`] without progress).
    pub fn build(scene: &Scene, opts: &RenderOptions) -> Self {
        Self::for_integrator(scene, IntegratorKind::PhotonMapping, opts, &mut |_| true)
    }

    /// The maps of `pdm` ([`PhotonMaps::for_integrator`] without progress).
    pub fn build_differential(scene: &Scene, opts: &RenderOptions) -> Self {
        Self::for_integrator(
            scene,
            IntegratorKind::PhotonDifferentialMapping,
            opts,
            &mut |_| true,
        )
    }

    /// The maps of a photon integrator whose caustic estimate `caustic(progress)` makes (with
    /// its warning, a note and statistics); `progress` sees the fraction of both passes done.
    pub fn with_caustic(
        scene: &Scene,
        opts: &RenderOptions,
        progress: &mut dyn FnMut(f64) -> bool,
        caustic: impl FnOnce(
            &mut dyn FnMut(f64) -> bool,
        ) -> (CausticEstimate, Option<String>, Option<String>, RenderStats),
    ) -> Self {
        let has_global = Self::wants_global(opts);
        let has_volume = Self::wants_volume(scene, opts);
        let share = 1.0 / (1 + has_global as u32 + has_volume as u32) as f64;
        let (caustic, warning, note, mut stats) = caustic(&mut |f| progress(share * f));
        let g = Self::trace_global(scene, opts, &mut |f| progress(share + share * f));
        stats += g.stats;
        let mut warnings: Vec<String> = warning.into_iter().chain(g.warning).collect();
        let start = if has_global { 2.0 * share } else { share };
        let mut notes: Vec<String> = note.into_iter().collect();
        let volume = has_volume.then(|| {
            let settings = opts.photons.volume;
            let budget = crate::photon::plan::PhotonBudget::Records(settings.photons);
            let progress = &mut |f| progress(start + share * f);
            if settings.estimate == VolumeEstimate::Differentials {
                let rule = KernelRule {
                    axes: settings.axes,
                    min_semi_axis: settings.min_semi_axis,
                    spread_collimated: settings.spread_collimated,
                };
                let smoothing = settings
                    .smoothing
                    .unwrap_or(opts.photons.footprints.smoothing);
                let v = trace_volume_differentials(
                    scene,
                    budget,
                    smoothing,
                    rule,
                    VOLUME_STREAM,
                    opts,
                    progress,
                );
                stats += v.stats;
                warnings.extend(v.warning);
                notes.push(format!(
                    "volume photon differentials: smoothing s = {smoothing}, {} scattering events, {} stored, {} dropped with a flat kernel, {} dropped where the differential could not be propagated{}",
                    v.events,
                    v.photons.len(),
                    v.collapsed,
                    v.failed,
                    match settings.min_semi_axis {
                        Some(r) => format!(", {} widened to the minimum semi-axis {r} m", v.widened),
                        None => String::new(),
                    }
                ));
                let map = VolumeMap::from_ellipsoids(v.photons, v.kernels, v.paths, settings);
                return Self::cut_kernels(map, scene, opts, &mut notes);
            }
            let v = trace_photons(scene, budget, MapKind::Volume, VOLUME_STREAM, opts, progress);
            stats += v.stats;
            warnings.extend(v.warning);
            let map = VolumeMap::new(v.photons, v.paths, settings);
            Self::cut_kernels(map, scene, opts, &mut notes)
        });
        Self {
            caustic,
            global: PhotonMap::new(g.photons, g.paths),
            volume,
            stats,
            warnings,
            notes,
        }
    }

    /// The volume map with its kernels renormalised where surfaces cut them, if the settings
    /// ask for it and the estimate uses photon kernels (not the march), noted.
    fn cut_kernels(
        mut map: VolumeMap,
        scene: &Scene,
        opts: &RenderOptions,
        notes: &mut Vec<String>,
    ) -> VolumeMap {
        let s = map.settings();
        if s.boundary == KernelBoundary::Renormalised && s.estimate != VolumeEstimate::March {
            let r = map.renormalise_at_boundaries(scene, opts.seed);
            notes.push(format!(
                "volume kernels renormalised at surfaces: {} of {} cut, keeping {:.1} % of their mass on average",
                r.cut,
                r.kernels,
                100.0 * r.mean_kept
            ));
        }
        map
    }

    /// True when the render needs volume photons: the scene has a scattering medium.
    fn wants_volume(scene: &Scene, opts: &RenderOptions) -> bool {
        !opts.caustics_only && scene.media.iter().any(|m| !m.sigma_s.is_black())
    }

    /// True when the render needs the global map (indirect light; caustics alone need none).
    pub(crate) fn wants_global(opts: &RenderOptions) -> bool {
        (opts.photons.global_photons > 0 || opts.photons.global_light_paths.is_some())
            && !opts.caustics_only
            && !opts.volume_only
    }

    /// The global map, or none when it is not needed.
    fn trace_global(
        scene: &Scene,
        opts: &RenderOptions,
        progress: &mut dyn FnMut(f64) -> bool,
    ) -> TracedPhotons {
        if !Self::wants_global(opts) {
            return TracedPhotons {
                photons: Vec::new(),
                paths: 0,
                stats: RenderStats::default(),
                warning: None,
                note: None,
            };
        }
        trace_photons(
            scene,
            opts.photons.global_budget(),
            MapKind::Global,
            GLOBAL_STREAM,
            opts,
            progress,
        )
    }

    /// The line for the user about the photon pass that took `secs` seconds.
    pub fn summary(&self, secs: f64) -> String {
        let secs = secs.max(1e-9);
        format!(
            "photons: caustic {} from {} paths, global {} from {} paths, in {secs:.2} s ({:.2} M paths/s), {:.1} MB",
            self.caustic.len(),
            self.caustic.paths(),
            self.global.len(),
            self.global.paths,
            (self.caustic.paths() + self.global.paths + self.volume.as_ref().map_or(0, |v| v.paths))
                as f64
                / secs
                / 1e6,
            (self.caustic.memory_bytes()
                + self.global.memory_bytes()
                + self.volume.as_ref().map_or(0, |v| v.memory_bytes())) as f64
                / 1e6,
        ) + &self.volume.as_ref().map_or(String::new(), |v| {
            format!(
                "; volume {} from {} paths ({} estimate, median radius {:.4} m{})",
                v.len(),
                v.paths,
                v.settings().estimate.name(),
                v.median_radius(),
                if v.settings().estimate == VolumeEstimate::March {
                    format!(", step {:.4} m", v.step())
                } else {
                    String::new()
                }
            )
        })
    }
}

/// Radiance (W/m²/sr) arriving at the camera along `ray`.
pub fn radiance(
    scene: &Scene,
    maps: &PhotonMaps,
    ray: Ray,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    stats: &mut RenderStats,
) -> Spectrum {
    radiance_with(scene, maps, ray, sampler, opts, stats, &mut |v, beta| {
        beta * maps.caustic.radiance(v, &opts.photons)
    })
}

/// [`radiance`] with the caustic term left to `caustic(v, β)`, called at the first non-delta
/// vertex `v` of the camera path (throughput β) when caustic light is wanted there; it returns
/// the contribution to add (`β · L_caustic` for the photon maps, zero for photon differential
/// splatting, which records the vertex and splats onto it later). It draws no random numbers.
pub(crate) fn radiance_with(
    scene: &Scene,
    maps: &PhotonMaps,
    ray: Ray,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    stats: &mut RenderStats,
    caustic: &mut dyn FnMut(&Vertex, Spectrum) -> Spectrum,
) -> Spectrum {
    let mut l = Spectrum::ZERO;
    walk_eye(
        scene,
        ray,
        scene.camera_medium,
        sampler,
        u32::MAX,
        stats,
        |event, sampler, stats| {
            let (v, medium, wo, beta, depth) = match event {
                EyeEvent::Medium { span, beta } => {
                    if let Some(vm) = &maps.volume {
                        let u = sampler.next_1d();
                        l += beta * vm.radiance(scene, &span, u);
                    }
                    return Flow::Continue;
                }
                // Every earlier vertex was delta: the environment is seen through them.
                EyeEvent::Escaped { ray, beta } => {
                    for &li in &scene.infinite_lights {
                        l += beta * scene.lights[li as usize].le(Vec3::ZERO, -ray.d);
                    }
                    return Flow::Stop;
                }
                EyeEvent::Vertex {
                    v,
                    medium,
                    wo,
                    beta,
                    depth,
                } => (v, medium, wo, beta, depth),
            };
            if opts.volume_only {
                // Only the in-scattering along the first segment (the spans before this vertex).
                return Flow::Stop;
            }
            let smooth = v.bsdf.flags().is_smooth();
            if opts.caustics_only {
                // L S+ D E only: the caustic estimate at the first surface, if it is non-delta.
                if smooth {
                    l += caustic(v, beta);
                }
                return Flow::Stop;
            }
            if v.si.light != NONE {
                l += beta * scene.lights[v.si.light as usize].le(v.si.ng, wo);
            }
            if depth >= opts.limits.max_depth {
                return Flow::Stop;
            }
            if smooth {
                l += beta * shade(scene, maps, v, medium, sampler, opts, stats);
                if opts.photons.final_gather > 0 {
                    l += caustic(v, beta);
                }
                return Flow::Stop;
            }
            Flow::Continue
        },
    );
    l
}

/// Reflected radiance at the first non-delta vertex `v` of a camera path, without the caustic
/// term (added by the caller) unless the global map is visualised directly.
fn shade(
    scene: &Scene,
    maps: &PhotonMaps,
    v: &Vertex,
    medium: u32,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    stats: &mut RenderStats,
) -> Spectrum {
    let gather_rays = opts.photons.final_gather;
    if gather_rays == 0 {
        return global_radiance(&maps.global, v, &opts.photons);
    }
    let direct = sample_direct(scene, v, medium, sampler, stats, false);
    let mut indirect = Spectrum::ZERO;
    if !maps.global.is_empty() {
        let wo_world = v.frame.to_world(v.wo);
        for _ in 0..gather_rays {
            let uc = sampler.next_1d();
            let u = sampler.next_2d();
            let Some(bs) = v.bsdf.sample(v.wo, uc, u, TransportMode::Radiance) else {
                continue;
            };
            let wi = v.frame.to_world(bs.wi);
            if !v.same_side_consistent(wo_world, wi, bs.wi) {
                continue;
            }
            let gather_ray = v.si.spawn_ray(wi);
            let m = v.si.medium_toward(wi, medium);
            indirect += bs.weight * gather(scene, maps, gather_ray, m, sampler, opts, stats);
        }
        indirect /= gather_rays as f32;
    }
    direct + indirect
}

/// Radiance arriving along a final-gather ray from the global map at the first non-delta
/// surface it reaches (through up to [`MAX_GATHER_CHAIN`] delta vertices). Emission is not
/// counted: NEE and the caustic estimate already hold it.
fn gather(
    scene: &Scene,
    maps: &PhotonMaps,
    ray: Ray,
    medium: u32,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    stats: &mut RenderStats,
) -> Spectrum {
    let mut l = Spectrum::ZERO;
    walk_eye(
        scene,
        ray,
        medium,
        sampler,
        MAX_GATHER_CHAIN,
        stats,
        |event, sampler, _| {
            match event {
                EyeEvent::Vertex { v, beta, .. } if v.bsdf.flags().is_smooth() => {
                    l += beta * global_radiance(&maps.global, v, &opts.photons);
                }
                EyeEvent::Medium { span, beta } => {
                    if let Some(vm) = &maps.volume {
                        let u = sampler.next_1d();
                        l += beta * vm.radiance(scene, &span, u);
                    }
                }
                _ => {}
            }
            Flow::Continue
        },
    );
    l
}

/// Renders with a photon method whose maps `build(progress)` makes: the photon pass (the first
/// [`PHOTON_SHARE`] of the progress bar), then the camera pass with the pixel driver.
pub(crate) fn render(
    scene: &Scene,
    opts: &RenderOptions,
    stage: &Stage,
    film: &mut crate::film::Film,
    filter: &crate::filter::Filter,
    notes: &mut Vec<String>,
    build: impl FnOnce(&mut dyn FnMut(f64) -> bool) -> PhotonMaps,
) -> RenderStats {
    let t = std::time::Instant::now();
    let photon_stage = stage.part(0.0, PHOTON_SHARE).labelled("tracing photons");
    let maps = build(&mut |f| photon_stage.report_and_go_on(f));
    notes.push(maps.summary(t.elapsed().as_secs_f64()));
    if maps.caustic.paths() > 0 {
        notes.extend(caustic_emission_notes(
            scene,
            opts.photons.emission.caustic_rule(),
            maps.caustic.len(),
            maps.caustic.paths(),
        ));
    }
    match &maps.caustic {
        CausticEstimate::Footprints(d) => notes.push(format!(
            "photon differentials: smoothing s = {}, {} caustic landings, {} stored, {} dropped with a collapsed footprint, {} dropped where the differential could not be propagated{}; gather radius median {:.4} m, max {:.4} m",
            opts.photons.footprints.smoothing,
            d.landings,
            d.len(),
            d.collapsed,
            d.failed,
            crate::photon::differential::widened_note(
                d.widened,
                opts.photons.footprints.min_semi_axis
            ),
            d.median_gather_radius(),
            d.max_gather_radius(),
        )),
        CausticEstimate::Density {
            estimator: caustica_density::estimator::Estimator::Diffusion(d),
            prepare_secs,
            ..
        } => {
            let p = d.params();
            notes.push(format!(
                "diffusion estimate: bandwidth {:.4}, noise scale {:.4}, q {}, alpha {}{}; pre-passes {prepare_secs:.2} s (included above)",
                p.bandwidth,
                p.noise_scale,
                p.q,
                p.alpha,
                if p.isotropic { ", isotropic" } else { "" },
            ));
        }
        _ => {}
    }
    notes.extend(maps.notes.iter().cloned());
    notes.extend(maps.warnings.iter().map(|w| format!("warning: {w}")));
    let cam = &scene.camera;
    let mut st = crate::driver::pixels::render_pixels(
        film,
        filter,
        opts,
        &stage.part(PHOTON_SHARE, 1.0).labelled("camera pass"),
        |sampler, raster, st| {
            let u_lens = sampler.next_2d();
            let time = scene.sample_time(|| sampler.next_1d());
            let ray = cam.generate_ray(raster, u_lens).ray.at_time(time);
            radiance(scene, &maps, ray, sampler, opts, st)
        },
    );
    st.rays += maps.stats.rays;
    st
}

/// Share of the progress bar (and of a time budget) given to the photon pass of `pm`, `dpm`
/// and `pdm`.
const PHOTON_SHARE: f64 = 0.2;
/// The share of the photon pass's time `dpm`'s diffusion pre-passes may take under a time budget.
const DIFFUSION_PREPASS_SHARE: f64 = 0.7;
/// Caustic photons the diffusion pre-passes process per second, on the order of this machine's
/// (2 cores: 0.29 M/s measured on the glass sphere); it caps `dpm`'s caustic photons under a
/// time budget, where guided emission would otherwise store more than the pre-passes can take.
const DIFFUSION_PHOTONS_PER_SECOND: f64 = 250_000.0;
