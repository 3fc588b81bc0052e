//! All shapes of a scene behind one BVH: closest-hit and shadow queries.

use crate::bvh::Bvh;
use crate::intersection::SurfaceInteraction;
use crate::shape::{Aabb, Shape};
use caustica_core::Ray;

/// The scene's shapes and their acceleration structure.
pub struct Geometry {
    pub shapes: Vec<Shape>,
    pub bvh: Bvh,
    bounds: Aabb,
}

impl Geometry {
    /// Builds the BVH over every primitive of `shapes`.
    pub fn build(shapes: Vec<Shape>) -> Self {
        let _ = shapes;
        todo!("Geometry::build")
    }
    /// Closest hit along `ray` with `t < ray.t_max`.
    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceInteraction> {
        let _ = ray;
        todo!("Geometry::intersect")
    }
    /// True if anything blocks `ray` before `ray.t_max`.
    pub fn occluded(&self, ray: &Ray) -> bool {
        let _ = ray;
        todo!("Geometry::occluded")
    }
    /// World bounds of all shapes.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }
}
