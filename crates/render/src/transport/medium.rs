//! Where a ray segment meets what lies between surfaces: the one hook every walker calls to
//! advance a ray ([`trace_segment`]).
//!
//! Today the only medium is the absorbing interior of a dielectric (Beer–Lambert,
//! `Material::interior_absorption`): a segment that ends on a surface hit from its inside (−ng
//! side) is attenuated by exp(−σ_a t). Participating media replace this with free-flight
//! sampling (a scattering event inside the medium becomes a third [`Segment`] variant), and
//! every walker — the light walker, the eye walker and the path tracer — must then handle it.

use crate::stats::RenderStats;
use caustica_core::{Ray, Spectrum};
use caustica_scene::{Scene, SurfaceInteraction};

/// Where a traced ray segment ended.
pub enum Segment {
    /// The ray reached a surface; `transmittance` (dimensionless, per channel) is the weight of
    /// the segment to multiply the path throughput by.
    Surface {
        si: SurfaceInteraction,
        transmittance: Spectrum,
    },
    /// The ray left the scene.
    Escaped,
}

/// Traces `ray` to the next surface (one closest-hit ray, counted in `stats`).
#[inline]
pub fn trace_segment(scene: &Scene, ray: &Ray, stats: &mut RenderStats) -> Segment {
    stats.rays += 1;
    match scene.intersect(ray) {
        Some(si) => Segment::Surface {
            transmittance: interior_transmittance(scene, &si, ray),
            si,
        },
        None => Segment::Escaped,
    }
}

/// Beer–Lambert transmittance exp(−σa t) of the segment that ended at `si`, if that segment ran
/// inside an absorbing dielectric, i.e. the ray hit the surface from its inside (−ng side).
#[inline]
fn interior_transmittance(scene: &Scene, si: &SurfaceInteraction, ray: &Ray) -> Spectrum {
    if ray.d.dot(si.ng) > 0.0
        && let Some(sigma) = scene.materials[si.material as usize].interior_absorption()
    {
        return (sigma * -si.t).exp();
    }
    Spectrum::ONE
}
