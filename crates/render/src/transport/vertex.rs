//! The scattering state at a surface vertex, shared by every walker and integrator, and rays
//! spawned off surfaces.

use caustica_core::{Frame, Ray, Vec3};
use caustica_scene::bsdf::{Bsdf, TransportMode};
use caustica_scene::light::EmissionSample;
use caustica_scene::{Scene, SurfaceInteraction};

/// The scattering state at a path vertex.
#[derive(Clone)]
pub struct Vertex {
    pub si: SurfaceInteraction,
    pub bsdf: Bsdf,
    pub frame: Frame,
    /// Direction back along the incoming ray, local frame.
    pub wo: Vec3,
}

impl Vertex {
    /// Sets up the BSDF and frame at a hit reached by `ray`.
    #[inline]
    pub fn new(scene: &Scene, si: SurfaceInteraction, ray: &Ray) -> Self {
        let bsdf = scene.materials[si.material as usize].bsdf(&si);
        let frame = si.shading_frame();
        let wo = frame.to_local(-ray.d);
        Self {
            si,
            bsdf,
            frame,
            wo,
        }
    }

    /// The geometric normal on the side the vertex is seen from (toward `wo`).
    #[inline]
    pub fn facing_normal(&self) -> Vec3 {
        self.si.ng_toward(self.frame.to_world(self.wo))
    }

    /// Factor that makes transport with shading normals correct for importance (light paths):
    /// |wo·ns| |wi·ng| / (|wo·ng| |wi·ns|) (Veach 1997, §5.3). `wo` and `wi` are world space.
    #[inline]
    pub fn shading_normal_correction(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        if mode == TransportMode::Radiance {
            return 1.0;
        }
        let num = wo.dot(self.si.ns).abs() * wi.dot(self.si.ng).abs();
        let den = wo.dot(self.si.ng).abs() * wi.dot(self.si.ns).abs();
        if den == 0.0 { 0.0 } else { num / den }
    }

    /// True if `wi` (world) leaves on a side consistent with the sampled lobe, judged by the
    /// geometric normal; prevents light leaking through surfaces with bent shading normals.
    #[inline]
    pub fn same_side_consistent(&self, wo_world: Vec3, wi_world: Vec3, wi_local: Vec3) -> bool {
        let geo_reflect = wo_world.dot(self.si.ng) * wi_world.dot(self.si.ng) > 0.0;
        let shade_reflect = self.wo.z * wi_local.z > 0.0;
        geo_reflect == shade_reflect
    }
}

/// Moves `p` off a surface with normal `n` to the side of direction `d`, by the same relative
/// offset `SurfaceInteraction::spawn_ray` uses.
#[inline]
pub fn offset_origin(p: Vec3, n: Vec3, d: Vec3) -> Vec3 {
    let eps = 1e-4 * (1.0 + p.abs().max_element());
    p + n * (eps * if d.dot(n) >= 0.0 { 1.0 } else { -1.0 })
}

/// The emitted ray of a light sample, with its origin moved off the emitting surface so it does
/// not hit that surface again (lights return origins exactly on their surface).
#[inline]
pub fn emission_ray(es: &EmissionSample) -> Ray {
    match es.normal {
        Some(n) => Ray::new(offset_origin(es.ray.o, n, es.ray.d), es.ray.d),
        None => es.ray,
    }
}
