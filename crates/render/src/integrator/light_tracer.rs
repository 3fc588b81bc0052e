//! Light tracer: follows paths from the lights and connects every non-delta vertex to the camera
//! (the unbiased reference for caustics from delta lights seen directly, L S+ D E, like
//! Mitsuba's `ptracer`), and every scattering event in a medium too (volume caustics from
//! delta lights, L S+ M E, which a path tracer cannot find). Splats are importance-weighted so the image is in the same units as the
//! path tracer's (radiance averaged over each pixel).

use crate::film::SplatBuffer;
use crate::filter::Filter;
use crate::options::RenderOptions;
use crate::stats::RenderStats;
use crate::transport::Emission;
use crate::transport::light_walk::{EventsOnly, LightEvent, walk_light_path_at};
use crate::transport::medium::shadow_transmittance;
use crate::transport::time::PathTime;
use crate::transport::vertex::offset_origin;
use caustica_core::sampling::Sampler;
use caustica_core::{Ray, Spectrum};
use caustica_scene::Scene;
use caustica_scene::bsdf::TransportMode;
use caustica_scene::phase::Phase;

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
    let camera = &scene.camera;
    let splat = |out: &mut SplatBuffer, raster, v: Spectrum, stats: &mut RenderStats| {
        if v.is_finite() {
            out.add(filter, raster, v);
        } else {
            stats.nonfinite += 1;
        }
    };
    // Guided emission aims at caustics: only the caustics-only image may use it.
    let emission = if opts.caustics_only {
        opts.photons.emission.caustic_rule()
    } else {
        Emission::Uniform
    };
    walk_light_path_at(
        scene,
        sampler,
        &opts.limits,
        stats,
        &mut EventsOnly(
            |event: LightEvent, sampler: &mut Sampler, stats: &mut RenderStats| {
                let u_lens = sampler.next_2d();
                match event {
                    // Path of one edge: the light seen directly (area lights only; delta positions
                    // cannot be hit).
                    LightEvent::Start(start) => {
                        let es = start.emission;
                        if !es.delta_pos
                            && !opts.caustics_only
                            && !opts.volume_only
                            && opts.limits.max_depth >= 1
                            && let Some(n) = es.normal
                            && let Some(cs) = camera.sample_wi(es.ray.o, u_lens)
                            && out.reaches(filter, cs.raster)
                        {
                            let le = scene.light_emission(
                                start.light,
                                scene.lights[start.light].le(n, cs.wi),
                                &start.channels,
                            );
                            if !le.is_black() {
                                let o = offset_origin(es.ray.o, n, cs.wi);
                                let shadow = Ray::with_t_max(
                                    o,
                                    cs.wi,
                                    (cs.lens_p - o).length() * (1.0 - 1e-4),
                                )
                                .at_time(start.ray.time);
                                let tr = shadow_transmittance(
                                    scene,
                                    &shadow,
                                    start.medium,
                                    sampler,
                                    stats,
                                    &start.channels,
                                );
                                if !tr.is_black() {
                                    let w = n.dot(cs.wi).abs()
                                        / (es.pdf_pos * start.pmf * start.density.total());
                                    let c = start.channels.to_rgb(le * w * cs.weight * tr);
                                    splat(out, cs.raster, c, stats);
                                }
                            }
                        }
                    }
                    // Connect to the camera: the full path then has depth + 1 edges.
                    LightEvent::Vertex(lv) => {
                        let v = lv.v;
                        let wanted = if opts.caustics_only {
                            let caustic = lv.is_caustic();
                            stats.caustic_vertices += caustic as u64;
                            caustic
                        } else {
                            v.bsdf.flags().is_smooth()
                        };
                        if wanted
                            && !opts.volume_only
                            && lv.depth < opts.limits.max_depth
                            && let Some(cs) = camera.sample_wi(v.si.p, u_lens)
                            && out.reaches(filter, cs.raster)
                        {
                            let wi_local = v.frame.to_local(cs.wi);
                            let f = v.bsdf.eval(v.wo, wi_local, TransportMode::Importance);
                            if !f.is_black() && v.same_side_consistent(lv.wo, cs.wi, wi_local) {
                                let shadow = v.si.spawn_ray_to(cs.lens_p);
                                let medium = v.si.medium_toward(shadow.d, lv.medium);
                                let tr = shadow_transmittance(
                                    scene,
                                    &shadow,
                                    medium,
                                    sampler,
                                    stats,
                                    &v.channels,
                                );
                                if !tr.is_black() {
                                    let corr = v.shading_normal_correction(
                                        lv.wo,
                                        cs.wi,
                                        TransportMode::Importance,
                                    );
                                    // The RGB mode's operation order (same bytes as before
                                    // spectral mode); the conversion is linear.
                                    let c = lv.v.channels.to_rgb(
                                        lv.beta * f * (wi_local.z.abs() * corr) * cs.weight * tr,
                                    );
                                    splat(out, cs.raster, c, stats);
                                }
                            }
                        }
                    }
                    // A scattering in a medium seen by the camera (paths … M E, the volume
                    // caustics L S+ M E among them): β p(wo, ω_cam) T W.
                    LightEvent::Medium(lm) => {
                        let mv = lm.v;
                        if !opts.caustics_only
                            && lm.depth < opts.limits.max_depth
                            && let Some(cs) = camera.sample_wi(mv.p, u_lens)
                            && out.reaches(filter, cs.raster)
                        {
                            let shadow = mv.ray_to(cs.lens_p);
                            let tr = shadow_transmittance(
                                scene,
                                &shadow,
                                mv.medium,
                                sampler,
                                stats,
                                &mv.channels,
                            );
                            if !tr.is_black() {
                                let c = mv
                                    .channels
                                    .to_rgb(lm.beta * mv.phase.eval(mv.wo, cs.wi) * cs.weight * tr);
                                splat(out, cs.raster, c, stats);
                            }
                        }
                    }
                }
            },
        ),
        PathTime::Shutter,
        emission,
    );
}
