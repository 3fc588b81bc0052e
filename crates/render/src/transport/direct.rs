//! Next-event estimation: direct light at a vertex by sampling a light, with MIS against BSDF
//! sampling (power heuristic, Veach 1997).

use crate::stats::RenderStats;
use crate::transport::vertex::Vertex;
use caustica_core::sampling::Sampler;
use caustica_core::sampling::warp::power_heuristic;
use caustica_core::{Ray, Spectrum};
use caustica_scene::Scene;
use caustica_scene::bsdf::TransportMode;

/// Reflected radiance (W/m²/sr) at `v` toward `wo` due to one light sample, MIS-weighted
/// against BSDF sampling when `mis` is true (the caller then also counts emission found by BSDF
/// sampling), unweighted otherwise (light sampling alone). Consumes exactly three sampler
/// dimensions.
pub fn sample_direct(
    scene: &Scene,
    v: &Vertex,
    sampler: &mut Sampler,
    stats: &mut RenderStats,
    mis: bool,
) -> Spectrum {
    let u_light = sampler.next_1d();
    let u = sampler.next_2d();
    let Some(dist) = &scene.light_distribution else {
        return Spectrum::ZERO;
    };
    let (li, pmf, _) = dist.sample(u_light);
    let light = &scene.lights[li];
    let Some(ls) = light.sample_li(v.si.p, u) else {
        return Spectrum::ZERO;
    };
    if ls.pdf <= 0.0 || ls.weight.is_black() {
        return Spectrum::ZERO;
    }
    let wi_local = v.frame.to_local(ls.wi);
    let f = v.bsdf.eval(v.wo, wi_local, TransportMode::Radiance) * wi_local.z.abs();
    if f.is_black() {
        return Spectrum::ZERO;
    }
    // Reject directions on the wrong geometric side (light leaks through shading normals).
    if !v.same_side_consistent(v.frame.to_world(v.wo), ls.wi, wi_local) {
        return Spectrum::ZERO;
    }
    let shadow: Ray = if ls.dist.is_finite() {
        v.si.spawn_ray_to(ls.p)
    } else {
        v.si.spawn_ray(ls.wi)
    };
    stats.rays += 1;
    if scene.occluded(&shadow) {
        return Spectrum::ZERO;
    }
    let mis = if ls.delta || !mis {
        1.0
    } else {
        power_heuristic(
            pmf * ls.pdf,
            v.bsdf.pdf(v.wo, wi_local, TransportMode::Radiance),
        )
    };
    f * ls.weight * (mis / pmf)
}
