//! What every path walks, light side and camera side alike.
//!
//! * [`medium`] — the one place a ray segment meets what lies between surfaces
//!   ([`trace_segment`]: free flights in participating media, null boundaries crossed, the
//!   Beer–Lambert interior of absorbing dielectrics; [`medium::trace_transmitted`] for estimators
//!   that gather in-scattered light along the ray; [`medium::shadow_transmittance`] for
//!   connections).
//! * [`vertex`] — the scattering state at a surface vertex ([`Vertex`]: BSDF, shading frame,
//!   shading-normal correction, side tests), at a medium vertex ([`vertex::MediumVertex`]:
//!   phase function), both behind [`vertex::Scatterer`], and rays spawned off surfaces.
//! * [`limits`] — path length limits and Russian roulette ([`PathLimits`]).
//! * [`direct`] — next-event estimation ([`sample_direct`]).
//! * [`emission`] — how a light path starts: uniform or guided by the projection maps.
//! * [`light_walk`] — the one light-path walker (light tracer, photon tracers, photon
//!   differentials), a [`LightVisitor`] deciding what each vertex is for.
//! * [`eye_walk`] — the one camera-side walker: a camera (or final-gather) ray followed through
//!   mirrors and glass to its first non-delta vertex or out of the scene. Photon mapping's camera
//!   pass and final gathering, and photon differential splatting's eye pass call it. The path
//!   tracer keeps its own MIS loop over [`trace_segment`] and [`Vertex`].

pub mod direct;
pub mod direct_lanes;
pub mod emission;
pub mod eye_walk;
pub mod light_walk;
pub mod limits;
pub mod medium;
pub mod time;
pub mod vertex;

pub use direct::sample_direct;
pub use emission::Emission;
pub use eye_walk::{EyeEvent, Flow, walk_eye};
pub use light_walk::{
    LightEvent, LightScatter, LightStart, LightVertex, LightVisitor, walk_light_path,
    walk_light_path_with,
};
pub use limits::{PathLimits, russian_roulette};
pub use medium::{Segment, trace_segment};
pub use time::PathTime;
pub use vertex::{Vertex, emission_ray, offset_origin};
