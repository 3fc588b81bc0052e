//! The camera-side walker: a camera or final-gather ray followed through delta vertices (mirrors,
//! glass) to its first non-delta vertex, or out of the scene — the specular chain D S* E that
//! photon mapping's camera pass, its final gather and the eye pass of photon differential
//! splatting all walk (and, later, the visible points of progressive photon mapping and the
//! importons of photon cone focusing).
//!
//! The walker owns the chain: segments ([`trace_transmitted`], weighted by their transmittance, each
//! medium span shown to the visitor for volume estimates), the
//! vertices ([`Vertex`]), and the delta scattering between them (radiance mode, 3 sampler
//! dimensions per delta vertex). The visitor decides what each vertex is for: it sees every
//! vertex, delta or not, and the escape; it returns [`Flow::Stop`] to end the chain there. The
//! chain always ends at its first non-delta vertex.

use crate::stats::RenderStats;
use crate::transport::medium::{MediumSpan, Segment, trace_transmitted};
use crate::transport::vertex::Vertex;
use caustica_core::sampling::Sampler;
use caustica_core::{Channels, Ray, Spectrum, Vec3};
use caustica_scene::Scene;
use caustica_scene::bsdf::TransportMode;

/// What [`walk_eye`] shows its visitor.
pub enum EyeEvent<'a> {
    /// The ray `ray` left the scene; every earlier vertex was delta, so whatever lies beyond (an
    /// environment light) is seen through them with throughput `beta`.
    Escaped { ray: &'a Ray, beta: Spectrum },
    /// A medium span the ray crossed before its next vertex (or escape): the visitor may add
    /// in-scattered light there (the volume photon estimates); `beta` is the throughput at the
    /// span's start. The walker does not sample scattering: the chain's segments are weighted
    /// by their transmittance. Its [`Flow`] is ignored.
    Medium {
        span: MediumSpan<'a>,
        beta: Spectrum,
    },
    /// A surface vertex, delta or not.
    Vertex {
        v: &'a Vertex,
        /// The medium of the ray that reached the vertex (`NONE` = vacuum).
        medium: u32,
        /// Unit direction back along the incoming ray (world space), −ray direction.
        wo: Vec3,
        /// Throughput of the chain up to this vertex, including the transmittance of the
        /// segment that reached it (1 for the first vertex of a camera ray in vacuum).
        beta: Spectrum,
        /// Vertices so far, this one included (1 = the first surface the ray meets).
        depth: u32,
    },
}

/// What the visitor tells the walker after a vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Flow {
    /// Follow the chain on if the vertex is delta (a non-delta vertex always ends it).
    Continue,
    /// End the chain here.
    Stop,
}

/// Follows `ray`, starting in medium `medium`, through delta vertices, at most `max_vertices`
/// of them in all, calling `visit` at each medium span, each vertex and at the escape. Sampler
/// use: what the visitor draws, 2 dimensions per medium span, then 3 per delta vertex the chain
/// continues through.
#[allow(clippy::too_many_arguments)]
pub fn walk_eye(
    scene: &Scene,
    mut ray: Ray,
    mut medium: u32,
    sampler: &mut Sampler,
    max_vertices: u32,
    stats: &mut RenderStats,
    mut visit: impl FnMut(EyeEvent, &mut Sampler, &mut RenderStats) -> Flow,
) {
    let mut beta = Spectrum::ONE;
    let mut depth = 0u32;
    while depth < max_vertices {
        let mut spans = Vec::new();
        // The camera side of the photon methods is RGB in both modes (docs/spectral.md).
        let ch = Channels::Rgb;
        let seg = trace_transmitted(scene, &ray, &mut medium, sampler, stats, &ch, |span, _| {
            spans.push((*span.ray, span.t_max, span.medium, span.tr));
        });
        for (r, t_max, m, tr) in spans {
            let span = MediumSpan {
                ray: &r,
                t_max,
                medium: m,
                tr,
            };
            let _ = visit(
                EyeEvent::Medium {
                    span,
                    beta: beta * tr,
                },
                sampler,
                stats,
            );
        }
        let (si, transmittance) = match seg {
            Segment::Surface { si, transmittance } => (si, transmittance),
            Segment::Escaped { transmittance } => {
                visit(
                    EyeEvent::Escaped {
                        ray: &ray,
                        beta: beta * transmittance,
                    },
                    sampler,
                    stats,
                );
                return;
            }
            // trace_transmitted samples no scattering.
            Segment::Medium { .. } => return,
        };
        depth += 1;
        beta *= transmittance;
        let v = Vertex::rgb(scene, si, &ray);
        let flow = visit(
            EyeEvent::Vertex {
                v: &v,
                medium,
                wo: -ray.d,
                beta,
                depth,
            },
            sampler,
            stats,
        );
        if flow == Flow::Stop || v.bsdf.flags().is_smooth() {
            return;
        }
        let Some((weight, next)) = scatter_delta(&v, sampler) else {
            return;
        };
        medium = v.si.medium_toward(next.d, medium);
        beta *= weight;
        if beta.is_black() {
            return;
        }
        ray = next;
    }
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
