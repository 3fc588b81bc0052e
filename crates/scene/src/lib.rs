//! Scene description of caustica: everything a ray can meet.
//!
//! * [`shape`] — triangle meshes, spheres, disks; [`geometry`] puts all their primitives in one
//!   wide BVH ([`bvh`]: eight children per node with AVX2, four with SSE, collapsed from the
//!   `obvhs` crate's binary tree) and answers closest-hit and shadow queries with a
//!   [`SurfaceInteraction`].
//! * [`bsdf`] — scattering functions in the local shading frame; [`material`] builds a
//!   [`bsdf::Bsdf`] at a hit from (textured) parameters; [`texture`] evaluates those.
//! * [`light`] — lights for next-event estimation and for emitting photons.
//! * [`medium`] — participating media (homogeneous, voxel grids) with their tracking
//!   estimators; [`phase`] — their phase functions.
//! * [`camera`] — perspective cameras with ray differentials.
//! * [`scene`] — the assembled, immutable [`Scene`], put together by a [`SceneBuilder`]; the
//!   `caustica-loader` crate fills builders from files and holds the built-in scenes.
//!
//! # Normal orientation and two-sidedness (the one place these rules are written)
//!
//! * The **geometric normal** `ng` of a triangle is `(p1 − p0) × (p2 − p0)` normalised
//!   (counter-clockwise winding faces the viewer); a sphere's points outward; a disk's is its
//!   stated normal. `ng` is never flipped toward the ray; it tells *inside* from *outside*.
//!   `flip_normals` on a shape reverses it (and the shading normals).
//! * The **shading normal** `ns` is the barycentric interpolation of vertex normals (Phong),
//!   normalised and flipped if needed to lie in the hemisphere of `ng`; without vertex normals
//!   `ns = ng`.
//! * BSDFs work in the local frame whose +z is `ns`. **Opaque** BSDFs (diffuse, mirror,
//!   conductors, Phong) are **two-sided**: if `wo` is below the surface they mirror both
//!   directions to the upper side, so a surface looks the same from both sides.
//! * **Dielectrics** are oriented: `wo.z > 0` means the ray arrives from the outside (the side
//!   `ng` points to), with relative IOR η = η_inside/η_outside; `wo.z < 0` means it leaves the
//!   object. Closed dielectric meshes must therefore be wound consistently outward.
//! * **Area lights** emit only on the side `ng` points to (as in pbrt and Mitsuba), unless
//!   declared two-sided.

pub mod bsdf;
pub mod bvh;
pub mod camera;
pub mod dispersion;
pub mod error;
pub mod geometry;
pub mod intersection;
pub mod light;
pub mod material;
pub mod medium;
pub mod phase;
pub mod scene;
pub mod shape;
pub mod texture;

pub use error::SceneError;
pub use intersection::SurfaceInteraction;
pub use scene::{Scene, SceneBuilder, Shutter};
