//! The record of a ray hitting a surface.

use caustica_core::{Frame, Ray, Vec2, Vec3};

/// Vertices of the hit triangle, needed by ray/photon differentials on flat and Phong triangles
/// (seed 000 appendix B.3, eq. B.35–B.55).
#[derive(Clone, Copy, Debug)]
pub struct TriangleVertices {
    /// Positions Q0, Q1, Q2 in world space (m).
    pub p: [Vec3; 3],
    /// Unit vertex normals N0, N1, N2 in world space, when the mesh has them.
    pub n: Option<[Vec3; 3]>,
}

/// Marker for "no index" in `u32` index fields.
pub const NONE: u32 = u32::MAX;

/// Everything known about a ray–surface hit. See the crate docs for the orientation rules.
/// The hit triangle's vertices and vertex normals are not copied into every record:
/// `Geometry::triangle_vertices` looks them up from `shape` and `prim`.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceInteraction {
    /// Hit point (m).
    pub p: Vec3,
    /// Ray parameter of the hit (m for unit-length directions).
    pub t: f32,
    /// Unit geometric normal (never flipped toward the ray).
    pub ng: Vec3,
    /// Unit shading normal, in the hemisphere of `ng`.
    pub ns: Vec3,
    /// Texture coordinates.
    pub uv: Vec2,
    /// Barycentrics (b1, b2) of the hit on a triangle: p = (1−b1−b2) Q0 + b1 Q1 + b2 Q2; for
    /// analytic shapes their surface parameters.
    pub bary: Vec2,
    /// Surface tangents ∂p/∂u, ∂p/∂v with respect to the texture parameterisation.
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    /// Index of the shape in the scene and of the primitive (triangle) within it.
    pub shape: u32,
    pub prim: u32,
    /// Material index into `Scene::materials`.
    pub material: u32,
    /// Area light index into `Scene::lights`, or [`NONE`].
    pub light: u32,
    /// Medium indices on the inside (−ng) and outside (+ng) side, or [`NONE`] (vacuum); both
    /// [`NONE`] means the shape is not a medium boundary ([`SurfaceInteraction::medium_toward`]).
    pub medium_inside: u32,
    pub medium_outside: u32,
    /// Scene time (frames) of the hit: the ray's; rays spawned here inherit it.
    pub time: f32,
}

impl SurfaceInteraction {
    /// Shading frame with `n = ns`, first tangent along `dpdu`.
    #[inline]
    pub fn shading_frame(&self) -> Frame {
        Frame::from_normal_tangent(self.ns, self.dpdu)
    }

    /// The geometric normal on the side of direction `w` (world space): `ng` when `w · ng ≥ 0`,
    /// else `−ng`. The one rule for "the normal facing the viewer (or the light)" of photons,
    /// footprints, eye vertices and density queries.
    #[inline]
    pub fn ng_toward(&self, w: Vec3) -> Vec3 {
        if self.ng.dot(w) >= 0.0 {
            self.ng
        } else {
            -self.ng
        }
    }

    /// True if the hit shape separates media (names the medium on at least one side).
    #[inline]
    pub fn is_medium_transition(&self) -> bool {
        self.medium_inside != NONE || self.medium_outside != NONE
    }

    /// The medium a ray leaving this hit in direction `w` travels in, when the ray that arrived
    /// was in `current`: the outside medium for `w` on the +ng side, the inside one otherwise —
    /// or `current` if the shape is not a medium boundary (Mitsuba 3 and pbrt-v4 behave alike).
    #[inline]
    pub fn medium_toward(&self, w: Vec3, current: u32) -> u32 {
        if !self.is_medium_transition() {
            current
        } else if w.dot(self.ng) > 0.0 {
            self.medium_outside
        } else {
            self.medium_inside
        }
    }

    /// Offset applied to ray origins leaving this surface, relative to the hit's magnitude.
    #[inline]
    fn offset(&self) -> f32 {
        1e-4 * (1.0 + self.p.abs().max_element())
    }

    /// Ray leaving the surface in direction `d` (unit), with its origin pushed off the surface
    /// along ±ng so it does not re-hit it.
    #[inline]
    pub fn spawn_ray(&self, d: Vec3) -> Ray {
        let side = if d.dot(self.ng) >= 0.0 { 1.0 } else { -1.0 };
        Ray::new(self.p + self.ng * (side * self.offset()), d).at_time(self.time)
    }

    /// Shadow ray from this surface toward the point `target`, stopping just short of it.
    #[inline]
    pub fn spawn_ray_to(&self, target: Vec3) -> Ray {
        let dir = target - self.p;
        let side = if dir.dot(self.ng) >= 0.0 { 1.0 } else { -1.0 };
        let o = self.p + self.ng * (side * self.offset());
        let to = target - o;
        let dist = to.length();
        Ray::with_t_max(o, to / dist, dist * (1.0 - 1e-4)).at_time(self.time)
    }
}
