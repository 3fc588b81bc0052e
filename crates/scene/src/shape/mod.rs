//! Shapes: triangle meshes and analytic spheres and disks. Rectangles and cubes are built as
//! meshes ([`TriangleMesh::rectangle`], [`TriangleMesh::cube`]); the case-study scenes' water
//! wave and ring are generated in [`procedural`], the torus of `torus-glass` in [`torus`],
//! surfaces of revolution in [`lathe`] and height fields in [`height_field`].

pub mod aabb;
pub mod disk;
pub mod height_field;
pub mod lathe;
pub mod mesh;
pub mod motion;
pub mod procedural;
pub mod sphere;
pub mod torus;

pub use aabb::Aabb;
pub use disk::Disk;
pub use height_field::height_field_mesh;
pub use lathe::{circle_arc, lathe_mesh};
pub use mesh::{SanitizeReport, TriangleMesh};
pub use motion::MeshMotion;
pub use procedural::{
    DomeParams, RingParams, WaveParams, faceted_dome_mesh, geodesic_sphere_mesh, moving_water_wave,
    ring_mesh, rod_mesh, water_wave_mesh,
};
pub use sphere::Sphere;
pub use torus::torus_mesh;

use crate::intersection::NONE;

/// The surface of a shape.
#[derive(Clone, Debug)]
pub enum ShapeGeometry {
    Mesh(TriangleMesh),
    Sphere(Sphere),
    Disk(Disk),
}

/// A shape placed in the scene: geometry already in world space (instances are baked by their
/// affine transform when the scene is built) plus what it is made of.
#[derive(Clone, Debug)]
pub struct Shape {
    pub geometry: ShapeGeometry,
    /// Index into `Scene::materials`.
    pub material: u32,
    /// Index into `Scene::lights` of the area light on this shape, or `NONE`.
    pub light: u32,
    /// Reverse geometric and shading normals (swaps inside and outside).
    pub flip_normals: bool,
    /// Media inside (−ng) and outside (+ng), or `NONE` (vacuum); both `NONE`: not a medium
    /// boundary (`crate::medium::MediumInterface`).
    pub medium_inside: u32,
    pub medium_outside: u32,
    /// Keyframed vertex motion of a mesh (`None`: static). The mesh's own positions and
    /// normals are those of the first keyframe.
    pub motion: Option<std::sync::Arc<MeshMotion>>,
}

impl Shape {
    pub fn new(geometry: ShapeGeometry, material: u32) -> Self {
        Self {
            geometry,
            material,
            light: NONE,
            flip_normals: false,
            medium_inside: NONE,
            medium_outside: NONE,
            motion: None,
        }
    }
    /// Number of primitives (triangles; 1 for analytic shapes).
    pub fn primitive_count(&self) -> usize {
        match &self.geometry {
            ShapeGeometry::Mesh(m) => m.indices.len(),
            _ => 1,
        }
    }
}
