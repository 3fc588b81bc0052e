//! Light tracer: follows paths from the lights and connects every non-delta vertex to the camera
//! (the unbiased reference for caustics from delta lights seen directly, L S+ D E, like
//! Mitsuba's `ptracer`). Splats are importance-weighted so the image is in the same units as the
//! path tracer's (radiance averaged over each pixel).

use crate::film::SplatBuffer;
use crate::filter::Filter;
use crate::options::RenderOptions;
use crate::stats::RenderStats;
use crate::surface::{
    Vertex, emission_ray, interior_transmittance, offset_origin, russian_roulette,
};
use caustica_core::sampling::Sampler;
use caustica_core::{Ray, Spectrum};
use caustica_scene::Scene;
use caustica_scene::bsdf::TransportMode;

/// Traces one light path and splats its camera connections into `out` (unnormalised: the film
/// divides by the number of paths).
pub fn trace_light_path(
    scene: &Scene,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    filter: &Filter,
    out: &mut SplatBuffer,
    stats: &mut RenderStats,
) {
    let u_light = sampler.next_1d();
    let u_pos = sampler.next_2d();
    let u_dir = sampler.next_2d();
    let u_lens = sampler.next_2d();
    let Some(dist) = &scene.light_distribution else {
        return;
    };
    let (li, pmf, _) = dist.sample(u_light);
    let light = &scene.lights[li];
    let es = light.sample_emission(u_pos, u_dir);
    if es.pdf_pos <= 0.0 || es.pdf_dir <= 0.0 || es.weight.is_black() {
        return;
    }
    let camera = &scene.camera;
    let splat = |out: &mut SplatBuffer, raster, v: Spectrum, stats: &mut RenderStats| {
        if v.is_finite() {
            out.add(filter, raster, v);
        } else {
            stats.nonfinite += 1;
        }
    };

    // Path of one edge: the light seen directly (area lights only; delta positions cannot be hit).
    if !es.delta_pos
        && opts.max_depth >= 1
        && let Some(n) = es.normal
        && let Some(cs) = camera.sample_wi(es.ray.o, u_lens)
    {
        let le = light.le(n, cs.wi);
        if !le.is_black() {
            let o = offset_origin(es.ray.o, n, cs.wi);
            let shadow = Ray::with_t_max(o, cs.wi, (cs.lens_p - o).length() * (1.0 - 1e-4));
            stats.rays += 1;
            if !scene.occluded(&shadow) {
                splat(
                    out,
                    cs.raster,
                    le * (n.dot(cs.wi).abs() / (es.pdf_pos * pmf)) * cs.weight,
                    stats,
                );
            }
        }
    }

    let mut beta = es.weight / pmf;
    let mut ray = emission_ray(&es);
    let mut depth = 1u32; // edges of the light subpath including the one being traced
    loop {
        stats.rays += 1;
        let Some(si) = scene.intersect(&ray) else {
            break;
        };
        beta *= interior_transmittance(scene, &si, &ray);
        let v = Vertex::new(scene, si, &ray);
        let flags = v.bsdf.flags();
        let wo_world = -ray.d;
        let u_lens = sampler.next_2d();
        // Connect to the camera: the full path then has depth + 1 edges.
        if flags.is_smooth()
            && depth < opts.max_depth
            && let Some(cs) = camera.sample_wi(v.si.p, u_lens)
        {
            let wi_local = v.frame.to_local(cs.wi);
            let f = v.bsdf.eval(v.wo, wi_local, TransportMode::Importance);
            if !f.is_black() && v.same_side_consistent(wo_world, cs.wi, wi_local) {
                let shadow = v.si.spawn_ray_to(cs.lens_p);
                stats.rays += 1;
                if !scene.occluded(&shadow) {
                    let corr =
                        v.shading_normal_correction(wo_world, cs.wi, TransportMode::Importance);
                    splat(
                        out,
                        cs.raster,
                        beta * f * (wi_local.z.abs() * corr) * cs.weight,
                        stats,
                    );
                }
            }
        }
        let uc = sampler.next_1d();
        let u = sampler.next_2d();
        let u_rr = sampler.next_1d();
        if depth + 1 >= opts.max_depth {
            break;
        }
        let Some(bs) = v.bsdf.sample(v.wo, uc, u, TransportMode::Importance) else {
            break;
        };
        let wi = v.frame.to_world(bs.wi);
        if !v.same_side_consistent(wo_world, wi, bs.wi) {
            break;
        }
        beta *= bs.weight * v.shading_normal_correction(wo_world, wi, TransportMode::Importance);
        if beta.is_black() {
            break;
        }
        depth += 1;
        if !russian_roulette(&mut beta, depth, opts.rr_depth, u_rr) {
            break;
        }
        ray = v.si.spawn_ray(wi);
    }
}
