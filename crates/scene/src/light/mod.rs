//! Lights. Every light can
//! (a) sample a direction toward a shading point for next-event estimation ([`Light::sample_li`],
//!     density [`Light::pdf_li`] for MIS),
//! (b) sample an emitted ray for photon and light tracing ([`Light::sample_emission`]) together
//!     with the local frame at the origin that photon differentials need (seed 002 eq. 2–6), and
//! (c) report its total emitted power ([`Light::power`], W).
//!
//! Units: point and spot `intensity` in W/sr; directional and beam `irradiance` in W/m² on a
//! plane perpendicular to the light; area and environment `radiance` in W/m²/sr.

pub mod area;
pub mod beam;
pub mod directional;
pub mod emission_spectrum;
pub mod environment;
pub mod point;
pub mod projection_map;
pub mod spot;

pub use area::{AreaLight, AreaShape};
pub use beam::BeamLight;
pub use directional::DirectionalLight;
pub use emission_spectrum::{EmissionSpectrum, NamedSpectrum};
pub use environment::EnvironmentLight;
pub use point::PointLight;
pub use projection_map::{EmissionDensity, GuidedStart, ProjectionMap};
pub use spot::SpotLight;

use caustica_core::{Ray, Spectrum, Vec2, Vec3};

/// A direction toward a light, sampled from a shading point.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Unit direction from the shading point toward the light.
    pub wi: Vec3,
    /// Distance to the sampled light point (m); `f32::INFINITY` for infinite lights.
    pub dist: f32,
    /// Sampled point on the light (or a point beyond the scene for infinite lights).
    pub p: Vec3,
    /// Radiance arriving along `-wi` divided by `pdf` (for delta lights: the incident
    /// irradiance-per-unit-solid-angle factor, i.e. I/d² for a point light). The direct-light
    /// contribution is `f(wo, wi)·|cos θi|·weight` (times an MIS weight for non-delta lights).
    pub weight: Spectrum,
    /// Solid-angle density of `wi` at the shading point (sr⁻¹); 1 for delta lights.
    pub pdf: f32,
    /// True for point, spot, directional and beam lights (cannot be hit by rays).
    pub delta: bool,
}

impl LightSample {
    /// Sample of a delta light (point, spot, directional, beam): `weight` is the incident
    /// radiance-times-solid-angle factor (e.g. I/d² for a point light), `pdf` is 1.
    #[inline]
    pub fn delta(wi: Vec3, dist: f32, p: Vec3, weight: Spectrum) -> Self {
        Self {
            wi,
            dist,
            p,
            weight,
            pdf: 1.0,
            delta: true,
        }
    }
}

/// Unit direction, distance and squared distance from `p` to a light position, or `None` when
/// they coincide or the distance is not finite (shared by the point-like lights).
#[inline]
pub(crate) fn toward(p: Vec3, light: Vec3) -> Option<(Vec3, f32, f32)> {
    let v = light - p;
    let d2 = v.length_squared();
    if !(d2 > 0.0 && d2.is_finite()) {
        return None;
    }
    let dist = d2.sqrt();
    Some((v / dist, dist, d2))
}

/// An emitted ray, sampled for photon or light tracing.
#[derive(Clone, Copy, Debug)]
pub struct EmissionSample {
    /// Origin on the light and unit direction of emission.
    pub ray: Ray,
    /// Surface normal at the origin (area lights, beam aperture), `None` for point-like sources.
    pub normal: Option<Vec3>,
    /// Flux carried by the sample, Le·|cos θ| / (pdf_pos·pdf_dir), in W (before dividing by the
    /// number of emitted samples).
    pub weight: Spectrum,
    /// Area density of the origin (m⁻²), 1 for delta positions.
    pub pdf_pos: f32,
    /// Solid-angle density of the direction (sr⁻¹), 1 for delta directions.
    pub pdf_dir: f32,
    pub delta_pos: bool,
    pub delta_dir: bool,
}

/// Moves `p` off a surface with normal `n` to the side of direction `d`, by the same relative
/// offset `SurfaceInteraction::spawn_ray` uses.
#[inline]
pub fn offset_origin(p: Vec3, n: Vec3, d: Vec3) -> Vec3 {
    let eps = 1e-4 * (1.0 + p.abs().max_element());
    p + n * (eps * if d.dot(n) >= 0.0 { 1.0 } else { -1.0 })
}

impl EmissionSample {
    /// The emitted ray with its origin moved off the emitting surface so it does not hit that
    /// surface again (lights return origins exactly on their surface).
    #[inline]
    pub fn spawn_ray(&self) -> Ray {
        match self.normal {
            Some(n) => Ray::new(offset_origin(self.ray.o, n, self.ray.d), self.ray.d)
                .at_time(self.ray.time),
            None => self.ray,
        }
    }

    /// Local frame at the origin: around the surface normal where the light has one, else
    /// around the emitted direction. Photon differentials (seed 002 eq. 2–3) choose their
    /// positional (u, v) and directional (θ, φ) bases in the planes of this frame's normal and
    /// of the direction.
    pub fn frame(&self) -> caustica_core::Frame {
        caustica_core::Frame::from_normal(self.normal.unwrap_or(self.ray.d))
    }
}

/// Interface of one light type; [`Light`] dispatches.
pub trait LightSource {
    /// Called once with the scene's bounding sphere (centre, radius, m) before rendering.
    fn preprocess(&mut self, center: Vec3, radius: f32) {
        let _ = (center, radius);
    }
    fn sample_li(&self, p: Vec3, u: Vec2) -> Option<LightSample>;
    /// Solid-angle density with which `sample_li(p, ·)` returns direction `wi` hitting the light
    /// at `light_p` with light normal `light_n` (non-delta lights only; 0 otherwise).
    fn pdf_li(&self, p: Vec3, wi: Vec3, light_p: Vec3, light_n: Vec3) -> f32 {
        let _ = (p, wi, light_p, light_n);
        0.0
    }
    /// Emitted radiance (W/m²/sr) leaving a point with normal `n` on an area light in direction
    /// `w`; for the environment, radiance arriving from direction `-w`. Zero for delta lights.
    fn le(&self, n: Vec3, w: Vec3) -> Spectrum {
        let _ = (n, w);
        Spectrum::ZERO
    }
    fn sample_emission(&self, u_pos: Vec2, u_dir: Vec2) -> EmissionSample;
    /// Total emitted power (W). For infinite lights it is the power crossing the scene's
    /// bounding disk, which requires `preprocess`.
    fn power(&self) -> Spectrum;
    fn is_delta(&self) -> bool;
    fn is_infinite(&self) -> bool {
        false
    }
    /// Extent of the emission for the initial photon-differential lengths (seed 002 eq. 5–6):
    /// `(A_e, ω_e)` = area (m²) the photon origins are spread over and solid angle (sr) of the
    /// emitted directions around each origin; 0 for a delta position or direction. Infinite
    /// lights report their emission disk (requires `preprocess`).
    fn emission_extent(&self) -> (f32, f32);
    /// The direction and emitter normal every emitted ray shares, for collimated lights
    /// (directional, beam): what photon differentials need to compute their emission basis
    /// once per light. `None` for lights whose emitted directions vary.
    fn fixed_emission_direction(&self) -> Option<(Vec3, Option<Vec3>)> {
        None
    }
}

/// Any light of the scene.
#[derive(Clone, Debug)]
pub enum Light {
    Point(PointLight),
    Spot(SpotLight),
    Directional(DirectionalLight),
    Beam(BeamLight),
    Area(AreaLight),
    Environment(EnvironmentLight),
}

macro_rules! dispatch {
    ($self:ident, $l:ident => $e:expr) => {
        match $self {
            Light::Point($l) => $e,
            Light::Spot($l) => $e,
            Light::Directional($l) => $e,
            Light::Beam($l) => $e,
            Light::Area($l) => $e,
            Light::Environment($l) => $e,
        }
    };
}

impl Light {
    pub fn preprocess(&mut self, center: Vec3, radius: f32) {
        dispatch!(self, l => l.preprocess(center, radius))
    }
    #[inline]
    pub fn sample_li(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        dispatch!(self, l => l.sample_li(p, u))
    }
    #[inline]
    pub fn pdf_li(&self, p: Vec3, wi: Vec3, light_p: Vec3, light_n: Vec3) -> f32 {
        dispatch!(self, l => l.pdf_li(p, wi, light_p, light_n))
    }
    #[inline]
    pub fn le(&self, n: Vec3, w: Vec3) -> Spectrum {
        dispatch!(self, l => l.le(n, w))
    }
    #[inline]
    pub fn sample_emission(&self, u_pos: Vec2, u_dir: Vec2) -> EmissionSample {
        dispatch!(self, l => l.sample_emission(u_pos, u_dir))
    }
    pub fn power(&self) -> Spectrum {
        dispatch!(self, l => l.power())
    }
    pub fn is_delta(&self) -> bool {
        dispatch!(self, l => l.is_delta())
    }
    pub fn is_infinite(&self) -> bool {
        dispatch!(self, l => l.is_infinite())
    }
    /// See [`LightSource::emission_extent`].
    pub fn emission_extent(&self) -> (f32, f32) {
        dispatch!(self, l => l.emission_extent())
    }
    /// A point from which the medium a light emits into can be found (`Scene::medium_at`):
    /// the emission origin of a middle emission sample, moved off an emitting surface to its
    /// emitting side; `None` for lights at infinity (they shine in from vacuum).
    pub fn medium_probe_point(&self) -> Option<Vec3> {
        if self.is_infinite() {
            return None;
        }
        let es = self.sample_emission(Vec2::splat(0.5), Vec2::splat(0.5));
        let p = es.ray.o;
        if !p.is_finite() {
            return None;
        }
        Some(match es.normal {
            Some(n) => p + n * (n.dot(es.ray.d).signum() * 1e-3 * (1.0 + p.abs().max_element())),
            None => p,
        })
    }
    /// See [`LightSource::fixed_emission_direction`].
    pub fn fixed_emission_direction(&self) -> Option<(Vec3, Option<Vec3>)> {
        dispatch!(self, l => l.fixed_emission_direction())
    }
}
