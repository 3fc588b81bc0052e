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

use crate::direct::sample_direct;
use crate::options::RenderOptions;
use crate::options::{CausticEstimator, PhotonOptions};
use crate::photon_differential::{FootprintFilter, PdmMap, trace_photon_differentials};
use crate::photon_map::PhotonMap;
use crate::photon_tracer::{MapKind, trace_photons};
use crate::stats::RenderStats;
use crate::surface::{Vertex, interior_transmittance};
use caustica_core::sampling::Sampler;
use caustica_core::{Ray, Spectrum, Vec3};
use caustica_density::diffusion::DiffusionParams;
use caustica_density::estimator::{Estimator, EstimatorSpec, Scratch, median_knn_radius};
use caustica_scene::Scene;
use caustica_scene::bsdf::TransportMode;
use caustica_scene::intersection::NONE;
use std::cell::RefCell;

/// Random-number streams of the two maps (the camera pass uses pixel streams).
pub(crate) const CAUSTIC_STREAM: u64 = 0xCA05;
const GLOBAL_STREAM: u64 = 0x610B;
/// Longest specular chain a final-gather ray follows.
const MAX_GATHER_CHAIN: u32 = 16;

/// The caustic and global photon maps of a scene, with the caustic map's density estimator.
pub struct PhotonMaps {
    pub caustic: PhotonMap,
    pub global: PhotonMap,
    /// The caustic map's estimator, prepared for it (k-NN for `pm`, diffusion for `dpm`).
    pub caustic_estimator: Estimator,
    /// Seconds spent preparing the caustic estimator (the diffusion pre-passes).
    pub prepare_secs: f64,
    /// `pdm`: the caustic photons as photon differentials, whose footprint estimate (seed 002
    /// eq. 10) replaces the caustic map's (`caustic` is then empty).
    pub differential: Option<PdmMap>,
    /// Photon-tracing work.
    pub stats: RenderStats,
    /// Messages for the user (e.g. fewer photons than requested).
    pub warnings: Vec<String>,
}

impl PhotonMaps {
    /// Traces both maps with the sizes in `opts.photons` and prepares the caustic map's
    /// estimator `opts.photons.caustic_estimator`.
    pub fn build(scene: &Scene, opts: &RenderOptions) -> Self {
        let p = &opts.photons;
        let c = trace_photons(
            scene,
            p.caustic_photons,
            MapKind::Caustic,
            CAUSTIC_STREAM,
            opts,
        );
        let g = Self::trace_global(scene, opts);
        let mut stats = c.stats;
        stats += g.stats;
        let warnings = c.warning.into_iter().chain(g.warning).collect();
        let caustic = PhotonMap::new(c.photons, c.paths);
        let spec = caustic_spec(&caustic, &opts.photons);
        let t = std::time::Instant::now();
        let caustic_estimator = Estimator::prepare(&spec, &caustic.points(&p.estimate));
        let prepare_secs = t.elapsed().as_secs_f64();
        Self {
            caustic,
            global: PhotonMap::new(g.photons, g.paths),
            caustic_estimator,
            prepare_secs,
            differential: None,
            stats,
            warnings,
        }
    }

    /// The maps of `pdm`: the caustic light paths of [`PhotonMaps::build`] (same stream) traced
    /// as photon differentials with smoothing `opts.photons.smoothing`
    /// ([`trace_photon_differentials`]), and the global map as for `pm`.
    pub fn build_differential(scene: &Scene, opts: &RenderOptions) -> Self {
        let p = &opts.photons;
        let d =
            trace_photon_differentials(scene, p.caustic_photons, p.smoothing, CAUSTIC_STREAM, opts);
        let g = Self::trace_global(scene, opts);
        let mut stats = d.stats;
        stats += g.stats;
        let warnings = d.warning.iter().cloned().chain(g.warning).collect();
        Self {
            caustic: PhotonMap::new(Vec::new(), d.paths),
            global: PhotonMap::new(g.photons, g.paths),
            caustic_estimator: PhotonMap::knn_estimator(&p.estimate),
            prepare_secs: 0.0,
            differential: Some(PdmMap::with_filter(d, footprint_filter(p))),
            stats,
            warnings,
        }
    }

    /// Maps with the global map of [`PhotonMaps::build`] and no caustic photons (`pds` splats
    /// them instead).
    pub fn global_only(scene: &Scene, opts: &RenderOptions) -> Self {
        let g = Self::trace_global(scene, opts);
        Self {
            caustic: PhotonMap::new(Vec::new(), 0),
            global: PhotonMap::new(g.photons, g.paths),
            caustic_estimator: PhotonMap::knn_estimator(&opts.photons.estimate),
            prepare_secs: 0.0,
            differential: None,
            stats: g.stats,
            warnings: g.warning.into_iter().collect(),
        }
    }

    /// The global map, or none when it is not needed.
    fn trace_global(scene: &Scene, opts: &RenderOptions) -> crate::photon_tracer::TracedPhotons {
        let p = &opts.photons;
        // Caustics alone need no global map.
        if p.global_photons > 0 && !opts.caustics_only {
            trace_photons(
                scene,
                p.global_photons,
                MapKind::Global,
                GLOBAL_STREAM,
                opts,
            )
        } else {
            crate::photon_tracer::TracedPhotons {
                photons: Vec::new(),
                paths: 0,
                stats: RenderStats::default(),
                warning: None,
            }
        }
    }
}

/// How photon-differential footprints are evaluated (`pdm` and `pds` alike).
pub fn footprint_filter(p: &PhotonOptions) -> FootprintFilter {
    FootprintFilter {
        kernel: p.footprint_kernel,
        normal_distance: p.normal_distance,
    }
}

/// The caustic map's estimator as `opts` asks for it, with the data-driven default bandwidth
/// (median k-NN radius, k = `estimate.k`) where none is given.
pub fn caustic_spec(map: &PhotonMap, opts: &PhotonOptions) -> EstimatorSpec {
    let e = &opts.estimate;
    let bandwidth = || {
        opts.bandwidth
            .or_else(|| median_knn_radius(&map.points(e), e.k))
            .unwrap_or(1.0)
    };
    match opts.caustic_estimator {
        CausticEstimator::Knn => EstimatorSpec::Knn {
            k: e.k,
            max_radius: e.max_radius,
            kernel: e.kernel,
        },
        CausticEstimator::Fixed => EstimatorSpec::Fixed {
            h: bandwidth(),
            kernel: e.kernel,
        },
        CausticEstimator::Variable => EstimatorSpec::Variable {
            k: e.k,
            max_radius: e.max_radius,
            kernel: e.kernel,
        },
        CausticEstimator::Diffusion => {
            let h = bandwidth();
            let d = &opts.diffusion;
            EstimatorSpec::Diffusion(DiffusionParams {
                bandwidth: h,
                noise_scale: d.noise_scale.unwrap_or(0.5 * h),
                q: d.q,
                alpha: d.alpha,
                isotropic: d.isotropic,
                kernel: e.kernel,
            })
        }
    }
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// The caustic map's radiance estimate at `v`, with the maps' caustic estimator.
fn caustic_estimate(maps: &PhotonMaps, v: &Vertex, opts: &RenderOptions) -> Spectrum {
    if let Some(d) = &maps.differential {
        return d.radiance(v);
    }
    SCRATCH.with(|b| {
        maps.caustic.estimate_with(
            v,
            &opts.photons.estimate,
            &maps.caustic_estimator,
            &mut b.borrow_mut(),
        )
    })
}

/// The global map's radiance estimate at `v` (its own k when `global_k` is set).
fn global_estimate(map: &PhotonMap, v: &Vertex, opts: &RenderOptions) -> Spectrum {
    let mut est = opts.photons.estimate;
    if let Some(k) = opts.photons.global_k {
        est.k = k;
    }
    SCRATCH.with(|b| map.estimate(v, &est, &mut b.borrow_mut()))
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
        beta * caustic_estimate(maps, v, opts)
    })
}

/// [`radiance`] with the caustic term left to `caustic(v, β)`, called at the first non-delta
/// vertex `v` of the camera path (throughput β) when caustic light is wanted there; it returns
/// the contribution to add (`β · L_caustic` for the photon maps, zero for photon differential
/// splatting, which records the vertex and splats onto it later). It draws no random numbers.
pub(crate) fn radiance_with(
    scene: &Scene,
    maps: &PhotonMaps,
    mut ray: Ray,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    stats: &mut RenderStats,
    caustic: &mut dyn FnMut(&Vertex, Spectrum) -> Spectrum,
) -> Spectrum {
    let mut l = Spectrum::ZERO;
    let mut beta = Spectrum::ONE;
    let mut depth = 0u32;
    loop {
        stats.rays += 1;
        let Some(si) = scene.intersect(&ray) else {
            // Every earlier vertex was delta: the environment is seen through them.
            for &li in &scene.infinite_lights {
                l += beta * scene.lights[li as usize].le(Vec3::ZERO, -ray.d);
            }
            break;
        };
        depth += 1;
        beta *= interior_transmittance(scene, &si, &ray);
        let v = Vertex::new(scene, si, &ray);
        let smooth = v.bsdf.flags().is_smooth();
        if opts.caustics_only {
            // L S+ D E only: the caustic map at the first surface, if it is non-delta.
            if smooth {
                l += caustic(&v, beta);
            }
            break;
        }
        if v.si.light != NONE {
            l += beta * scene.lights[v.si.light as usize].le(v.si.ng, -ray.d);
        }
        if depth >= opts.max_depth {
            break;
        }
        if smooth {
            l += beta * shade(scene, maps, &v, sampler, opts, stats);
            if opts.photons.final_gather > 0 {
                l += caustic(&v, beta);
            }
            break;
        }
        let Some((weight, next)) = scatter_delta(&v, sampler) else {
            break;
        };
        beta *= weight;
        if beta.is_black() {
            break;
        }
        ray = next;
    }
    l
}

/// Reflected radiance at the first non-delta vertex `v` of a camera path, without the caustic
/// term (added by the caller) unless the global map is visualised directly.
fn shade(
    scene: &Scene,
    maps: &PhotonMaps,
    v: &Vertex,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    stats: &mut RenderStats,
) -> Spectrum {
    let gather_rays = opts.photons.final_gather;
    if gather_rays == 0 {
        return global_estimate(&maps.global, v, opts);
    }
    let direct = sample_direct(scene, v, sampler, stats, false);
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
            indirect += bs.weight * gather(scene, maps, v.si.spawn_ray(wi), sampler, opts, stats);
        }
        indirect /= gather_rays as f32;
    }
    direct + indirect
}

/// Radiance arriving along a final-gather ray from the global map at the first non-delta
/// surface it reaches (through up to [`MAX_GATHER_CHAIN`] delta vertices). Emission is not
/// counted: NEE and the caustic map already hold it.
fn gather(
    scene: &Scene,
    maps: &PhotonMaps,
    mut ray: Ray,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    stats: &mut RenderStats,
) -> Spectrum {
    let mut beta = Spectrum::ONE;
    for _ in 0..MAX_GATHER_CHAIN {
        stats.rays += 1;
        let Some(si) = scene.intersect(&ray) else {
            return Spectrum::ZERO;
        };
        beta *= interior_transmittance(scene, &si, &ray);
        let v = Vertex::new(scene, si, &ray);
        if v.bsdf.flags().is_smooth() {
            return beta * global_estimate(&maps.global, &v, opts);
        }
        let Some((weight, next)) = scatter_delta(&v, sampler) else {
            return Spectrum::ZERO;
        };
        beta *= weight;
        if beta.is_black() {
            return Spectrum::ZERO;
        }
        ray = next;
    }
    Spectrum::ZERO
}

/// One step along a specular chain from the delta vertex `v` (camera side, radiance mode):
/// the BSDF sample's weight and the continuing ray, or `None` when the sample fails or
/// carries nothing. Consumes 3 sampler dimensions.
fn scatter_delta(v: &Vertex, sampler: &mut Sampler) -> Option<(Spectrum, Ray)> {
    let uc = sampler.next_1d();
    let u = sampler.next_2d();
    let bs = v.bsdf.sample(v.wo, uc, u, TransportMode::Radiance)?;
    if bs.weight.is_black() {
        return None;
    }
    Some((bs.weight, v.si.spawn_ray(v.frame.to_world(bs.wi))))
}
