//! Unidirectional path tracer with next-event estimation, MIS (power heuristic) and Russian
//! roulette. Radiance estimate of one camera ray (W/m²/sr). Its own loop (MIS needs the previous
//! vertex's pdf at every emitter hit), over the shared segment and vertex code of
//! [`crate::transport`].

use crate::options::RenderOptions;
use crate::stats::RenderStats;
use crate::transport::direct::sample_direct;
use crate::transport::limits::russian_roulette;
use crate::transport::medium::{Segment, trace_segment};
use crate::transport::vertex::Vertex;
use caustica_core::sampling::Sampler;
use caustica_core::sampling::warp::power_heuristic;
use caustica_core::{Ray, Spectrum, Vec3};
use caustica_scene::Scene;
use caustica_scene::bsdf::TransportMode;
use caustica_scene::intersection::NONE;

/// Radiance arriving at the camera along `ray`.
pub fn radiance(
    scene: &Scene,
    mut ray: Ray,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    stats: &mut RenderStats,
) -> Spectrum {
    let mut l = Spectrum::ZERO;
    let mut beta = Spectrum::ONE;
    // State of the previous vertex for MIS of emission hit by BSDF sampling.
    let mut prev_delta = true;
    let mut prev_pdf = 0.0f32;
    let mut prev_p = Vec3::ZERO;
    let mut depth = 0u32; // edges traced so far
    loop {
        let Segment::Surface { si, transmittance } = trace_segment(scene, &ray, stats) else {
            for &li in &scene.infinite_lights {
                let light = &scene.lights[li as usize];
                let le = light.le(Vec3::ZERO, -ray.d);
                let w = if prev_delta {
                    1.0
                } else {
                    power_heuristic(
                        prev_pdf,
                        scene.light_pmf(li) * light.pdf_li(prev_p, ray.d, Vec3::ZERO, Vec3::ZERO),
                    )
                };
                l += beta * le * w;
            }
            break;
        };
        depth += 1;
        beta *= transmittance;
        if si.light != NONE {
            let light = &scene.lights[si.light as usize];
            let le = light.le(si.ng, -ray.d);
            if !le.is_black() {
                let w = if prev_delta {
                    1.0
                } else {
                    power_heuristic(
                        prev_pdf,
                        scene.light_pmf(si.light) * light.pdf_li(prev_p, ray.d, si.p, si.ng),
                    )
                };
                l += beta * le * w;
            }
        }
        if depth >= opts.limits.max_depth {
            break;
        }
        let v = Vertex::new(scene, si, &ray);
        let flags = v.bsdf.flags();
        // Fixed dimension layout per bounce: 3 for NEE, 3 for the BSDF, 1 for roulette.
        if flags.is_smooth() {
            l += beta * sample_direct(scene, &v, sampler, stats, true);
        } else {
            sampler.next_1d();
            sampler.next_2d();
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
        prev_pdf = bs.pdf;
        prev_p = v.si.p;
        if beta.is_black() {
            break;
        }
        if !russian_roulette(&mut beta, depth, opts.limits.rr_depth, u_rr) {
            break;
        }
        ray = v.si.spawn_ray(wi);
    }
    l
}
