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
use crate::transport::light_walk::{
    LightEvent, LightMediumVertex, LightScatter, LightVisitor, walk_light_path_at,
};
use crate::transport::medium::shadow_transmittance;
use crate::transport::time::PathTime;
use crate::transport::vertex::offset_origin;
use caustica_core::sampling::Sampler;
use caustica_core::{Ray, Spectrum};
use caustica_scene::Scene;
use caustica_scene::bsdf::TransportMode;
use caustica_scene::phase::{Phase, PhaseSample};

/// Which light-path vertices the light tracer connects to the camera.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Connect {
    /// Every vertex a camera connection can see: the light itself (area lights), non-delta
    /// surface vertices and medium vertices. The plain light tracer; uniform emission.
    All,
    /// Only the caustic vertices, L S+ D (`--caustics-only`); emission by `--emission`.
    Caustics,
    /// Non-delta surface vertices of the paths whose first scattering was delta, L S … D E:
    /// every path a path tracer reaches only by BSDF sampling after a delta bounce (never, for a
    /// delta light). The hybrid integrator's half; emission by `--emission`.
    SpecularFirst,
}

impl Connect {
    /// The plain light tracer's rule, or `--caustics-only`'s.
    pub fn of(opts: &RenderOptions) -> Self {
        if opts.caustics_only {
            Self::Caustics
        } else {
            Self::All
        }
    }
}

/// The light tracer's visitor: `events` at every event, and paths ended where no later vertex
/// can be connected under `connect` (after a non-delta scattering for [`Connect::Caustics`],
/// after a first scattering that is not delta for [`Connect::SpecularFirst`]). Ending them
/// changes no splat.
struct Connections<F> {
    events: F,
    connect: Connect,
    scatterings: u32,
}

impl<F: FnMut(LightEvent, &mut Sampler, &mut RenderStats)> LightVisitor for Connections<F> {
    fn event(&mut self, event: LightEvent, sampler: &mut Sampler, stats: &mut RenderStats) {
        (self.events)(event, sampler, stats)
    }
    fn scatter(&mut self, scatter: &LightScatter, _: &mut RenderStats) -> bool {
        self.scatterings += 1;
        match self.connect {
            Connect::All => true,
            Connect::Caustics => scatter.sample.flags.is_delta(),
            Connect::SpecularFirst => self.scatterings > 1 || scatter.sample.flags.is_delta(),
        }
    }
    fn scatter_in_medium(&mut self, _: &LightMediumVertex, _: &PhaseSample) -> bool {
        self.scatterings += 1;
        match self.connect {
            Connect::All => true,
            Connect::Caustics => false,
            Connect::SpecularFirst => self.scatterings > 1,
        }
    }
}

/// Traces one light path and splats its camera connections into `out` (unnormalised: the film
/// divides by the number of paths): every connection, or `--caustics-only`'s.
pub fn trace_light_path(
    scene: &Scene,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    filter: &Filter,
    out: &mut SplatBuffer,
    stats: &mut RenderStats,
) {
    trace_light_path_with(scene, sampler, opts, Connect::of(opts), filter, out, stats)
}

/// [`trace_light_path`] connecting the vertices `connect` selects.
pub fn trace_light_path_with(
    scene: &Scene,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    connect: Connect,
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
    // Guided emission aims at specular surfaces: only the images of paths through them use it.
    let emission = match connect {
        Connect::All => Emission::Uniform,
        Connect::Caustics | Connect::SpecularFirst => opts.photons.emission.caustic_rule(),
    };
    // Whether the path's first scattering was delta (known at the vertex after it).
    let mut specular_first = false;
    walk_light_path_at(
        scene,
        sampler,
        &opts.limits,
        stats,
        &mut Connections {
            connect,
            scatterings: 0,
            events: |event: LightEvent, sampler: &mut Sampler, stats: &mut RenderStats| {
                let u_lens = sampler.next_2d();
                match event {
                    // Path of one edge: the light seen directly (area lights only; delta positions
                    // cannot be hit).
                    LightEvent::Start(start) => {
                        let es = start.emission;
                        if !es.delta_pos
                            && connect == Connect::All
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
                        if lv.depth == 2 {
                            specular_first = lv.after_specular_chain;
                        }
                        if connect != Connect::All {
                            stats.caustic_vertices += lv.is_caustic() as u64;
                        }
                        let wanted = match connect {
                            Connect::All => v.bsdf.flags().is_smooth(),
                            Connect::Caustics => lv.is_caustic(),
                            Connect::SpecularFirst => {
                                lv.depth >= 2 && specular_first && v.bsdf.flags().is_smooth()
                            }
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
                        if lm.depth == 2 {
                            specular_first = lm.after_specular_chain;
                        }
                        if connect == Connect::All
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
        },
        PathTime::Shutter,
        emission,
    );
}
