//! The scattering state at a surface vertex ([`Vertex`]) or a medium vertex ([`MediumVertex`]),
//! shared by every walker and integrator, both seen through [`Scatterer`] where the code is the
//! same; and rays spawned off surfaces.

use caustica_core::{Channels, Frame, Ray, Spectrum, Vec3};
use caustica_scene::bsdf::{Bsdf, TransportMode};
use caustica_scene::light::EmissionSample;
use caustica_scene::phase::{Phase, PhaseFunction};
use caustica_scene::{Scene, SurfaceInteraction};

/// The scattering state at a path vertex.
#[derive(Clone)]
pub struct Vertex {
    pub si: SurfaceInteraction,
    pub bsdf: Bsdf,
    pub frame: Frame,
    /// Direction back along the incoming ray, local frame.
    pub wo: Vec3,
    /// What the lanes of the BSDF's values (and the path's) mean here: RGB or the path's
    /// wavelengths, after any dispersion at this vertex ended the secondary ones.
    pub channels: Channels,
}

impl Vertex {
    /// Sets up the BSDF and frame at a hit reached by `ray`, for a path whose lanes mean `ch`
    /// (updated: a dispersive interface ends the secondary wavelengths).
    #[inline]
    pub fn new(scene: &Scene, si: SurfaceInteraction, ray: &Ray, ch: &mut Channels) -> Self {
        let bsdf = scene.materials[si.material as usize].bsdf(&si, ch);
        let frame = si.shading_frame();
        let wo = frame.to_local(-ray.d);
        Self {
            si,
            bsdf,
            frame,
            wo,
            channels: *ch,
        }
    }

    /// [`Vertex::new`] for a path in RGB (the camera side of the photon methods).
    #[inline]
    pub fn rgb(scene: &Scene, si: SurfaceInteraction, ray: &Ray) -> Self {
        Self::new(scene, si, ray, &mut Channels::Rgb)
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

pub use caustica_scene::light::offset_origin;

/// The emitted ray of a light sample, with its origin moved off the emitting surface so it does
/// not hit that surface again ([`EmissionSample::spawn_ray`]).
#[inline]
pub fn emission_ray(es: &EmissionSample) -> Ray {
    es.spawn_ray()
}

/// A scattering vertex inside a participating medium: a real scattering event of a free flight
/// ([`crate::transport::Segment::Medium`]).
#[derive(Clone, Copy, Debug)]
pub struct MediumVertex {
    /// Position (m).
    pub p: Vec3,
    /// Unit direction back along the incoming ray (world space).
    pub wo: Vec3,
    /// The medium's index in `Scene::media`.
    pub medium: u32,
    pub phase: PhaseFunction,
    /// Scene time (frames) of the path at this vertex.
    pub time: f32,
    /// The lanes of the path (RGB or its wavelengths): its connections' transmittances are
    /// evaluated in them, and what it delivers is converted by [`Channels::to_rgb`].
    pub channels: Channels,
}

impl MediumVertex {
    /// The vertex at `p` reached along `ray` in medium `medium` of `scene`, by a path with lanes
    /// `ch`.
    #[inline]
    pub fn new(scene: &Scene, p: Vec3, ray: &Ray, medium: u32, ch: &Channels) -> Self {
        Self {
            p,
            wo: -ray.d,
            medium,
            phase: scene.media[medium as usize].phase,
            time: ray.time,
            channels: *ch,
        }
    }

    /// Connection from this vertex toward `target`, stopping just short of it.
    #[inline]
    pub fn ray_to(&self, target: Vec3) -> Ray {
        let to = target - self.p;
        let dist = to.length();
        Ray::with_t_max(self.p, to / dist, dist * (1.0 - 1e-4)).at_time(self.time)
    }
}

/// Where a path scatters: at a surface (its BSDF) or in a medium (its phase function). Next-event
/// estimation and camera connections are written once over this.
#[derive(Clone, Copy)]
pub enum Scatterer<'a> {
    /// A surface vertex; `medium` is the medium of the ray that reached it.
    Surface {
        v: &'a Vertex,
        medium: u32,
    },
    Medium(&'a MediumVertex),
}

impl Scatterer<'_> {
    /// Position (m).
    #[inline]
    pub fn p(&self) -> Vec3 {
        match self {
            Scatterer::Surface { v, .. } => v.si.p,
            Scatterer::Medium(m) => m.p,
        }
    }
    /// Unit direction back toward the previous vertex (world space).
    #[inline]
    pub fn wo(&self) -> Vec3 {
        match self {
            Scatterer::Surface { v, .. } => v.frame.to_world(v.wo),
            Scatterer::Medium(m) => m.wo,
        }
    }
    /// The scattering factor toward `wi` (world, unit): f(wo, wi) |cos θi| (sr⁻¹) with the
    /// shading-normal correction in importance mode, or p(wo, wi) (sr⁻¹) in a medium; 0 on the
    /// wrong geometric side of a surface.
    #[inline]
    pub fn eval(&self, wi: Vec3, mode: TransportMode) -> Spectrum {
        match self {
            Scatterer::Surface { v, .. } => {
                let wi_local = v.frame.to_local(wi);
                let f = v.bsdf.eval(v.wo, wi_local, mode);
                let wo = v.frame.to_world(v.wo);
                if f.is_black() || !v.same_side_consistent(wo, wi, wi_local) {
                    return Spectrum::ZERO;
                }
                f * (wi_local.z.abs() * v.shading_normal_correction(wo, wi, mode))
            }
            Scatterer::Medium(m) => Spectrum::splat(m.phase.eval(m.wo, wi)),
        }
    }
    /// The lanes of the path at this vertex.
    #[inline]
    pub fn channels(&self) -> Channels {
        match self {
            Scatterer::Surface { v, .. } => v.channels,
            Scatterer::Medium(m) => m.channels,
        }
    }
    /// Solid-angle density (sr⁻¹) with which the vertex samples `wi` itself.
    #[inline]
    pub fn pdf(&self, wi: Vec3, mode: TransportMode) -> f32 {
        match self {
            Scatterer::Surface { v, .. } => v.bsdf.pdf(v.wo, v.frame.to_local(wi), mode),
            Scatterer::Medium(m) => m.phase.pdf(m.wo, wi),
        }
    }
    /// Connection toward the point `target` and the medium it starts in.
    #[inline]
    pub fn ray_to(&self, target: Vec3) -> (Ray, u32) {
        match self {
            Scatterer::Surface { v, medium } => {
                let r = v.si.spawn_ray_to(target);
                (r, v.si.medium_toward(r.d, *medium))
            }
            Scatterer::Medium(m) => (m.ray_to(target), m.medium),
        }
    }
    /// Connection in direction `wi` (to a light at infinity) and the medium it starts in.
    #[inline]
    pub fn ray_toward(&self, wi: Vec3) -> (Ray, u32) {
        match self {
            Scatterer::Surface { v, medium } => {
                (v.si.spawn_ray(wi), v.si.medium_toward(wi, *medium))
            }
            Scatterer::Medium(m) => (Ray::new(m.p, wi).at_time(m.time), m.medium),
        }
    }
}
