//! Where a ray segment meets what lies between surfaces: the one hook every walker calls to
//! advance a ray ([`trace_segment`], [`trace_transmitted`]) and to test a connection
//! ([`shadow_transmittance`]).
//!
//! * In a scene without media (`Scene::has_media` false) a segment is one closest-hit ray; the
//!   only attenuation is the Beer–Lambert interior of absorbing dielectrics
//!   (`Material::interior_absorption`), and no sampler dimension is drawn.
//! * With media, a walker carries the index of the medium its ray is in. [`trace_segment`]
//!   samples a free flight in that medium (delta tracking with spectral MIS,
//!   `caustica_scene::medium::tracking`): the segment ends at a real scattering event
//!   ([`Segment::Medium`]) or at the next surface, with the flight's weight. Index-matched
//!   (`null`) boundaries are crossed inside the call, changing the medium; they are not path
//!   vertices. [`trace_transmitted`] does not sample scattering: it reaches the next surface
//!   weighted by the transmittance and shows each medium span it crossed to a callback, where a
//!   density estimator adds in-scattered light (photon mapping's camera rays).
//! * Every call takes the path's lanes (`Channels`): the media's σ_a, σ_s are evaluated in them
//!   once per medium span (`Medium::coefficients`; in spectral mode upsampled spectra at the
//!   path's wavelengths, in RGB mode the RGB values themselves).
//! * Each medium span draws two sampler dimensions (a [`TrackingSampler`]); a shadow ray in a
//!   scene with media draws two (for ratio tracking), whether or not it meets a medium, so the
//!   dimension layout of a path depends only on its vertices.

use crate::stats::RenderStats;
use caustica_core::sampling::Sampler;
use caustica_core::{Channels, Ray, Spectrum, Vec3};
use caustica_scene::intersection::NONE;
use caustica_scene::medium::{FreeFlight, TrackingSampler};
use caustica_scene::{Scene, SurfaceInteraction};

/// Where a traced ray segment ended.
pub enum Segment {
    /// The ray reached a surface (never a `null` one); `transmittance` (dimensionless, per
    /// channel) is the weight of the segment to multiply the path throughput by.
    Surface {
        si: SurfaceInteraction,
        transmittance: Spectrum,
    },
    /// A real scattering event at `p` (m) in medium `medium`; multiply the throughput by
    /// `weight` (σ_s T / p of the free flight) and scatter with the medium's phase function.
    /// The incoming direction is the ray's.
    Medium {
        p: Vec3,
        medium: u32,
        weight: Spectrum,
    },
    /// The ray left the scene; `transmittance` as for a surface.
    Escaped { transmittance: Spectrum },
}

/// One medium span a [`trace_transmitted`] ray crossed: `ray` from its origin to `t_max` in
/// medium `medium`, reached with transmittance `tr` from the start of the whole segment.
pub struct MediumSpan<'a> {
    pub ray: &'a Ray,
    pub t_max: f32,
    pub medium: u32,
    pub tr: Spectrum,
}

/// Largest number of `null` boundaries one segment crosses (a safety bound for broken meshes).
const MAX_NULL_CROSSINGS: u32 = 256;

/// Traces `ray` (origin off any surface) from medium `*medium` to the next scattering event or
/// non-null surface, crossing index-matched boundaries and updating `*medium` as it goes. `ch`:
/// the lanes of the path (the media's coefficients and the Beer–Lambert absorption inside
/// dielectrics at its wavelengths). The case without media is inlined into the caller (a call
/// and a copy of the hit record fewer per segment); the walk through media is not.
#[inline(always)]
pub fn trace_segment(
    scene: &Scene,
    ray: &Ray,
    medium: &mut u32,
    sampler: &mut Sampler,
    stats: &mut RenderStats,
    ch: &Channels,
) -> Segment {
    if !scene.has_media {
        stats.rays += 1;
        return match scene.intersect(ray) {
            Some(si) => Segment::Surface {
                transmittance: interior_transmittance(scene, &si, ray, ch),
                si,
            },
            None => Segment::Escaped {
                transmittance: Spectrum::ONE,
            },
        };
    }
    trace_segment_in_media(scene, ray, medium, sampler, stats, ch)
}

/// [`trace_segment`] in a scene with media.
#[inline(never)]
fn trace_segment_in_media(
    scene: &Scene,
    ray: &Ray,
    medium: &mut u32,
    sampler: &mut Sampler,
    stats: &mut RenderStats,
    ch: &Channels,
) -> Segment {
    walk_spans(scene, ray, medium, stats, ch, |span, _| {
        let m = &scene.media[span.medium as usize];
        let mut ts = TrackingSampler::new(sampler.next_1d(), sampler.next_1d());
        match m.sample_free_flight(span.ray, span.t_max, ch, &mut ts) {
            FreeFlight::Scatter { t, weight } => Err(Segment::Medium {
                p: span.ray.at(t),
                medium: span.medium,
                weight: span.tr * weight,
            }),
            FreeFlight::Pass { weight } => Ok(weight),
        }
    })
}

/// [`trace_segment`] without scattering: the ray goes on to the next non-null surface (or out),
/// weighted by the transmittance of the media it crossed, and `span` sees each medium span on
/// the way (with the transmittance up to its start). Never returns [`Segment::Medium`]. `ch`:
/// the lanes of the path, as for [`trace_segment`].
pub fn trace_transmitted(
    scene: &Scene,
    ray: &Ray,
    medium: &mut u32,
    sampler: &mut Sampler,
    stats: &mut RenderStats,
    ch: &Channels,
    mut span: impl FnMut(MediumSpan, &mut RenderStats),
) -> Segment {
    if !scene.has_media {
        return trace_segment(scene, ray, medium, sampler, stats, ch);
    }
    walk_spans(scene, ray, medium, stats, ch, |s, stats| {
        let m = &scene.media[s.medium as usize];
        let (r, t_max) = (*s.ray, s.t_max);
        span(s, stats);
        let mut ts = TrackingSampler::new(sampler.next_1d(), sampler.next_1d());
        Ok(m.transmittance(&r, t_max, ch, &mut ts))
    })
}

/// The loop both tracers share: closest hits along `ray`, each stretch inside a medium shown to
/// `in_medium` (with the weight so far as `tr`), which returns the stretch's weight or ends the
/// segment; `null` boundaries crossed (changing `*medium`), the first other surface or the escape
/// returned with the product of the weights.
fn walk_spans(
    scene: &Scene,
    ray: &Ray,
    medium: &mut u32,
    stats: &mut RenderStats,
    ch: &Channels,
    mut in_medium: impl FnMut(MediumSpan, &mut RenderStats) -> Result<Spectrum, Segment>,
) -> Segment {
    let mut ray = *ray;
    let mut weight = Spectrum::ONE;
    for _ in 0..MAX_NULL_CROSSINGS {
        stats.rays += 1;
        let hit = scene.intersect(&ray);
        let t_end = hit.as_ref().map_or(f32::INFINITY, |si| si.t);
        if *medium != NONE {
            let span = MediumSpan {
                ray: &ray,
                t_max: t_end,
                medium: *medium,
                tr: weight,
            };
            match in_medium(span, stats) {
                Ok(w) => weight *= w,
                Err(segment) => return segment,
            }
        }
        let Some(si) = hit else {
            return Segment::Escaped {
                transmittance: weight,
            };
        };
        if !scene.materials[si.material as usize].is_null() {
            return Segment::Surface {
                transmittance: weight * interior_transmittance(scene, &si, &ray, ch),
                si,
            };
        }
        *medium = si.medium_toward(ray.d, *medium);
        ray = si.spawn_ray(ray.d);
    }
    Segment::Escaped {
        transmittance: Spectrum::ZERO,
    }
}

/// Transmittance of the connection `shadow` (a ray with `t_max` just short of its target) that
/// starts in medium `medium`: 0 if a non-null surface blocks it, else the product of the
/// media's transmittances along it (ratio tracking in grids), in the lanes `ch` of the path
/// that makes the connection. Draws two sampler dimensions in scenes with media, none
/// otherwise.
pub fn shadow_transmittance(
    scene: &Scene,
    shadow: &Ray,
    medium: u32,
    sampler: &mut Sampler,
    stats: &mut RenderStats,
    ch: &Channels,
) -> Spectrum {
    if !scene.has_media {
        stats.rays += 1;
        return if scene.occluded(shadow) {
            Spectrum::ZERO
        } else {
            Spectrum::ONE
        };
    }
    let mut ts = TrackingSampler::new(sampler.next_1d(), sampler.next_1d());
    let end = shadow.at(shadow.t_max);
    let mut ray = *shadow;
    let mut medium = medium;
    let mut tr = Spectrum::ONE;
    for _ in 0..MAX_NULL_CROSSINGS {
        stats.rays += 1;
        let hit = scene.intersect(&ray);
        let t_end = hit.as_ref().map_or(ray.t_max, |si| si.t);
        if medium != NONE {
            tr *= scene.media[medium as usize].transmittance(&ray, t_end, ch, &mut ts);
            if tr.is_black() {
                return tr;
            }
        }
        let Some(si) = hit else {
            return tr;
        };
        if !scene.materials[si.material as usize].is_null() {
            return Spectrum::ZERO;
        }
        medium = si.medium_toward(ray.d, medium);
        // Re-aim at the connection's end: the origin moves off the boundary along its normal,
        // and a ray kept parallel would end beside the target, possibly on the far side of the
        // light's own surface.
        if ray.t_max <= si.t {
            return tr;
        }
        ray = if end.is_finite() {
            si.spawn_ray_to(end)
        } else {
            si.spawn_ray(ray.d)
        };
    }
    Spectrum::ZERO
}

/// Beer–Lambert transmittance exp(−σa t) of the segment that ended at `si`, if that segment ran
/// inside an absorbing dielectric, i.e. the ray hit the surface from its inside (−ng side).
#[inline(always)]
pub(crate) fn interior_transmittance(
    scene: &Scene,
    si: &SurfaceInteraction,
    ray: &Ray,
    ch: &Channels,
) -> Spectrum {
    if ray.d.dot(si.ng) > 0.0
        && let Some(sigma) = scene.materials[si.material as usize].interior_absorption()
    {
        return (ch.unbounded(sigma) * -si.t).exp();
    }
    Spectrum::ONE
}
