//! Next-event estimation: direct light at a surface or medium vertex by sampling a light, with
//! MIS against BSDF or phase sampling (power heuristic, Veach 1997), through media and
//! index-matched boundaries ([`shadow_transmittance`]).

use crate::stats::RenderStats;
use crate::transport::medium::shadow_transmittance;
use crate::transport::vertex::{Scatterer, Vertex};
use caustica_core::sampling::Sampler;
use caustica_core::sampling::warp::power_heuristic;
use caustica_core::{Spectrum, Vec2};
use caustica_scene::Scene;
use caustica_scene::bsdf::TransportMode;

/// Reflected radiance (W/m²/sr) at the surface vertex `v` (reached by a ray in `medium`, or
/// `NONE` for vacuum) toward `wo` due to one light sample, MIS-weighted against BSDF sampling when
/// `mis` is true (the caller then also counts emission found by BSDF sampling), unweighted
/// otherwise (light sampling alone). Consumes three sampler dimensions, and two more for the
/// shadow ray in scenes with media.
#[inline]
pub fn sample_direct(
    scene: &Scene,
    v: &Vertex,
    medium: u32,
    sampler: &mut Sampler,
    stats: &mut RenderStats,
    mis: bool,
) -> Spectrum {
    sample_direct_at(scene, Scatterer::Surface { v, medium }, sampler, stats, mis)
}

/// [`sample_direct`] at any scattering vertex: a surface (BSDF) or a medium point (phase
/// function; radiance per unit scattering coefficient, W/m²/sr·sr⁻¹·sr — the in-scattered
/// radiance before σ_s, which the free flight's weight supplies).
#[inline]
pub fn sample_direct_at(
    scene: &Scene,
    at: Scatterer,
    sampler: &mut Sampler,
    stats: &mut RenderStats,
    mis: bool,
) -> Spectrum {
    let u_light = sampler.next_1d();
    let u = sampler.next_2d();
    direct_with(scene, at, u_light, u, sampler, stats, mis)
}

/// [`sample_direct_at`] with its three numbers drawn: `u_light` picks the light, `u` the point
/// on it; `sampler` gives only the shadow ray's two in scenes with media.
pub fn direct_with(
    scene: &Scene,
    at: Scatterer,
    u_light: f32,
    u: Vec2,
    sampler: &mut Sampler,
    stats: &mut RenderStats,
    mis: bool,
) -> Spectrum {
    let Some(dist) = &scene.light_distribution else {
        if scene.has_media {
            sampler.next_2d();
        }
        return Spectrum::ZERO;
    };
    let (li, pmf, _) = dist.sample(u_light);
    let light = &scene.lights[li];
    let p = at.p();
    let sample = light
        .sample_li(p, u)
        .filter(|ls| ls.pdf > 0.0 && !ls.weight.is_black());
    let f = sample
        .as_ref()
        .map_or(Spectrum::ZERO, |ls| at.eval(ls.wi, TransportMode::Radiance));
    let (Some(ls), false) = (sample, f.is_black()) else {
        if scene.has_media {
            sampler.next_2d();
        }
        return Spectrum::ZERO;
    };
    let (shadow, medium) = if ls.dist.is_finite() {
        at.ray_to(ls.p)
    } else {
        at.ray_toward(ls.wi)
    };
    let ch = at.channels();
    let tr = shadow_transmittance(scene, &shadow, medium, sampler, stats, &ch);
    if tr.is_black() {
        return Spectrum::ZERO;
    }
    let mis = if ls.delta || !mis {
        1.0
    } else {
        power_heuristic(pmf * ls.pdf, at.pdf(ls.wi, TransportMode::Radiance))
    };
    f * tr * scene.light_emission(li, ls.weight, &ch) * (mis / pmf)
}
