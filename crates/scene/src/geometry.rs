//! All shapes of a scene behind one BVH: closest-hit and shadow queries.
//!
//! Every primitive (mesh triangle, sphere, disk) is a leaf primitive of the same wide BVH
//! ([`WideBvh`]: obvhs's PLOC build collapsed to eight children per node with AVX2, four
//! without; boxes tested eight or four at a time, triangles four at a time). The primitives are copied in BVH order into a compact array
//! (triangles as their three vertices). Traversal only tracks `(t, primitive, b1, b2)`; the full
//! [`SurfaceInteraction`] is computed once, for the closest hit.

use crate::bvh::{BvhWidth, WideBvh, WideHit};
use crate::intersection::{SurfaceInteraction, TriangleVertices};
use crate::shape::mesh::{TriangleConstants, TriangleMesh, TriangleRay};
use crate::shape::{Aabb, Disk, Shape, ShapeGeometry, Sphere};
use caustica_core::{Ray, Vec2, Vec3};
use rayon::prelude::*;

/// Surface data of a hit computed by a shape (before shape-level flags are applied).
#[derive(Clone, Copy, Debug)]
pub struct ShapeHit {
    pub p: Vec3,
    pub ng: Vec3,
    pub ns: Vec3,
    pub uv: Vec2,
    pub bary: Vec2,
    pub dpdu: Vec3,
    pub dpdv: Vec3,
}

/// Geometry of one primitive in BVH order.
#[derive(Clone, Copy, Debug)]
enum PrimGeom {
    Triangle([Vec3; 3]),
    Sphere(Sphere),
    Disk(Disk),
}

const _: () = assert!(std::mem::size_of::<PrimGeom>() == 40);

/// One primitive in BVH order: its geometry (what the traversal tests for non-triangles)
/// and what a hit's record reads besides, side by side, so that a record's data lies in two
/// or three adjacent cache lines instead of three arrays (84 bytes; on the benchmark's
/// 1 M-triangle mesh, where a record's reads miss the caches: docs/performance.md, fourteenth
/// session).
#[derive(Clone, Copy, Debug)]
struct PrimRecord {
    geom: PrimGeom,
    /// The shape, and the primitive within it.
    shape: u32,
    prim: u32,
    /// Normal and tangents of a mesh triangle (unused for other primitives), so a hit only
    /// interpolates.
    constants: TriangleConstants,
}

const _: () = assert!(std::mem::size_of::<PrimRecord>() == 84);

impl PrimGeom {
    /// `(t, b1, b2)` of a hit with `t ∈ (0, t_max)`.
    #[inline(always)]
    fn intersect(&self, tr: &TriangleRay, o: Vec3, d: Vec3, t_max: f32) -> Option<(f32, f32, f32)> {
        match self {
            PrimGeom::Triangle([p0, p1, p2]) => tr.intersect(t_max, *p0, *p1, *p2),
            PrimGeom::Sphere(s) => s.intersect(o, d, t_max).map(|t| (t, 0.0, 0.0)),
            PrimGeom::Disk(k) => k.intersect(o, d, t_max).map(|t| (t, 0.0, 0.0)),
        }
    }
}

/// The scene's shapes and their acceleration structure.
pub struct Geometry {
    pub shapes: Vec<Shape>,
    /// The wide BVH over all primitives (empty when there are none).
    pub bvh: WideBvh,
    bounds: Aabb,
    /// The primitives in BVH order.
    prims: Vec<PrimRecord>,
    /// The triangles of moving meshes, behind their own BVH over swept bounds.
    moving: MovingTriangles,
}

/// Triangles of meshes with keyframed motion ([`crate::shape::MeshMotion`]), behind a BVH over
/// each triangle's bounds swept over all its keyframes (the union of the keyframe boxes bounds
/// the linear interpolation between them). A query at time `t` interpolates the triangle's
/// vertices to `t` before the watertight test, so hits are exact for the interpolated mesh.
/// Static shapes keep the fast path of [`Geometry::bvh`] untouched.
#[derive(Default)]
struct MovingTriangles {
    bvh: WideBvh,
    /// (shape, triangle) in BVH order.
    ids: Vec<(u32, u32)>,
}

impl Geometry {
    /// Builds the BVH over every primitive of `shapes`. Primitives that cannot be hit are
    /// skipped: triangles with out-of-range indices or non-finite vertices, spheres and disks
    /// with non-positive or non-finite radii (loaders report those; nothing here panics).
    pub fn build(shapes: Vec<Shape>) -> Self {
        Self::build_with_width(shapes, BvhWidth::detect())
    }

    /// [`Self::build`] with BVH nodes of the given width (four where the CPU cannot run
    /// eight): to test the fallback and compare the two on one machine.
    pub fn build_with_width(shapes: Vec<Shape>, width: BvhWidth) -> Self {
        // (shape, primitive) of every candidate primitive, in shape order.
        let mut ids: Vec<(u32, u32)> = Vec::new();
        let mut moving_ids: Vec<(u32, u32)> = Vec::new();
        for (s, shape) in shapes.iter().enumerate() {
            let prims = (0..shape.primitive_count() as u32).map(|p| (s as u32, p));
            if moving_mesh(shape).is_some() {
                moving_ids.extend(prims);
            } else {
                ids.extend(prims);
            }
        }
        let moving = MovingTriangles::build(&shapes, moving_ids);
        let geoms: Vec<Option<PrimGeom>> = ids
            .par_iter()
            .with_min_len(4096)
            .map(|&(s, p)| match &shapes[s as usize].geometry {
                ShapeGeometry::Mesh(m) => {
                    let v = m.triangle(p as usize)?;
                    if !(v[0].is_finite() && v[1].is_finite() && v[2].is_finite()) {
                        return None;
                    }
                    Some(PrimGeom::Triangle(v))
                }
                ShapeGeometry::Sphere(sp) => sp.is_valid().then_some(PrimGeom::Sphere(*sp)),
                ShapeGeometry::Disk(dk) => dk.is_valid().then_some(PrimGeom::Disk(Disk {
                    normal: dk.normal.normalize(),
                    ..*dk
                })),
            })
            .collect();
        let boxes: Vec<Aabb> = geoms
            .par_iter()
            .with_min_len(4096)
            .map(|g| match g {
                None => Aabb::EMPTY,
                Some(PrimGeom::Triangle(v)) => {
                    let mut b = Aabb::from_point(v[0]);
                    b.grow(v[1]);
                    b.grow(v[2]);
                    b
                }
                Some(PrimGeom::Sphere(s)) => s.bounds(),
                Some(PrimGeom::Disk(d)) => d.bounds(),
            })
            .collect();
        // Only primitives with valid geometry enter the BVH.
        let valid: Vec<u32> = (0..boxes.len() as u32)
            .filter(|&i| geoms[i as usize].is_some())
            .collect();
        let vboxes: Vec<Aabb> = valid.iter().map(|&i| pad(boxes[i as usize])).collect();
        let vtris: Vec<Option<[Vec3; 3]>> = valid
            .iter()
            .map(|&i| match geoms[i as usize] {
                Some(PrimGeom::Triangle(v)) => Some(v),
                _ => None,
            })
            .collect();
        let bvh = WideBvh::build_with_width(&vboxes, &vtris, width);
        // BVH order → index into `geoms` / `ids`.
        let order: Vec<u32> = bvh.order().iter().map(|&k| valid[k as usize]).collect();
        // A valid primitive's geometry with its ids and (for a mesh triangle) constants.
        let prims: Vec<PrimRecord> = order
            .par_iter()
            .with_min_len(4096)
            .filter_map(|&i| {
                let geom = geoms[i as usize]?;
                let (shape, prim) = ids[i as usize];
                let constants = match &shapes[shape as usize].geometry {
                    ShapeGeometry::Mesh(m) => {
                        m.triangle_constants(prim as usize).unwrap_or_default()
                    }
                    _ => TriangleConstants::default(),
                };
                Some(PrimRecord {
                    geom,
                    shape,
                    prim,
                    constants,
                })
            })
            .collect();
        debug_assert_eq!(prims.len(), order.len());
        let mut bounds = order.iter().fold(Aabb::EMPTY, |mut b, &i| {
            let pb = &boxes[i as usize];
            b.grow(pb.min);
            b.grow(pb.max);
            b
        });
        if let Some(mb) = moving.bounds(&shapes) {
            bounds.grow(mb.min);
            bounds.grow(mb.max);
        }
        Self {
            shapes,
            bvh,
            bounds,
            prims,
            moving,
        }
    }

    /// True if some mesh moves (then queries depend on the ray's time).
    pub fn has_motion(&self) -> bool {
        !self.moving.ids.is_empty()
    }

    /// Number of primitives in the BVH.
    pub fn primitive_count(&self) -> usize {
        self.prims.len()
    }

    /// The two prepared rays of a traversal, or `None` when nothing can be hit.
    #[inline(always)]
    fn rays(&self, ray: &Ray) -> Option<TriangleRay> {
        if (self.prims.is_empty() && self.moving.ids.is_empty())
            || ray.t_max.is_nan()
            || ray.t_max <= 0.0
        {
            return None;
        }
        Some(TriangleRay::new(ray.o, ray.d))
    }

    /// The closest hit; with `prefetch`, the static triangles that become the closest hit so
    /// far have their record's data ([`Self::interaction`] reads) asked for from memory while
    /// the traversal goes on.
    #[inline]
    fn closest(&self, ray: &Ray, prefetch: bool) -> Option<WideHit> {
        let tr = self.rays(ray)?;
        let (o, d) = (ray.o, ray.d);
        // (Reading the ray through its reference: capturing copies of `o` and `d` made every
        // query store them again.)
        let other = |k: u32, t_max| {
            self.prims[k as usize]
                .geom
                .intersect(&tr, ray.o, ray.d, t_max)
        };
        // In a scene whose records fit the caches the hints would only be extra instructions:
        // there the traversal is the one without the hook (each is compiled on its own).
        let hit = if prefetch && crate::bvh::prefetch::worth(&self.prims) {
            let hook = |k| self.prefetch_record(k);
            self.bvh.closest(o, d, &tr, ray.t_max, other, hook)
        } else {
            self.bvh.closest(o, d, &tr, ray.t_max, other, |_| {})
        };
        if self.moving.ids.is_empty() {
            return hit;
        }
        let t_max = hit.map_or(ray.t_max, |h| h.t);
        let base = self.prims.len() as u32;
        match self.moving.bvh.closest(
            ray.o,
            ray.d,
            &tr,
            t_max,
            |k, t_max| self.moving_intersect(k, &tr, ray.time, t_max),
            |_| {},
        ) {
            // Moving triangles are numbered after the static primitives.
            Some(h) => Some(WideHit {
                prim: base + h.prim,
                ..h
            }),
            None => hit,
        }
    }

    /// Asks the CPU to bring into the cache what [`Self::interaction`] reads of static
    /// primitive `k` (BVH order): its record (vertices, ids, triangle constants; two or three
    /// adjacent lines). In a scene larger than the caches these are misses per hit, which the
    /// rest of the traversal hides.
    #[inline(always)]
    fn prefetch_record(&self, k: u32) {
        use crate::bvh::prefetch::element;
        let k = k as usize;
        element(&self.prims, k);
    }

    /// Hit of moving triangle `k` (moving-BVH order) at `time` closer than `t_max`.
    #[inline]
    fn moving_intersect(
        &self,
        k: u32,
        tr: &TriangleRay,
        time: f32,
        t_max: f32,
    ) -> Option<(f32, f32, f32)> {
        let (s, p) = self.moving.ids[k as usize];
        let v = self.moving_triangle(s, p, time)?;
        tr.intersect(t_max, v[0], v[1], v[2])
    }

    /// Vertices of triangle `p` of moving shape `s` at `time`.
    #[inline]
    fn moving_triangle(&self, s: u32, p: u32, time: f32) -> Option<[Vec3; 3]> {
        let shape = self.shapes.get(s as usize)?;
        let (m, motion) = moving_mesh(shape)?;
        let idx = m.indices.get(p as usize)?;
        Some(idx.map(|i| motion.position(i as usize, time)))
    }

    /// Closest hit along `ray` with `t ∈ (0, ray.t_max)`.
    pub fn intersect(&self, ray: &Ray) -> Option<SurfaceInteraction> {
        let hit = self.closest(ray, true)?;
        Some(self.interaction(ray, hit))
    }

    /// Distance to the closest hit along `ray` (`t ∈ (0, ray.t_max)`), without computing the
    /// surface record.
    pub fn hit_distance(&self, ray: &Ray) -> Option<f32> {
        self.closest(ray, false).map(|h| h.t)
    }

    /// The closest hit of every ray of `rays`, in order: the same records as [`Self::intersect`]
    /// gives one by one, bit for bit, but rays are traced eight at a time through the 8-wide
    /// BVH, so a node or packet is fetched once for the rays that enter it. Worth it for
    /// coherent rays (a tile of camera rays); rays that differ from their packet's first in the
    /// dominant axis of their direction, packets left with five such rays or fewer, scenes with
    /// moving meshes and 4-wide BVHs go one by one.
    pub fn intersect_stream(&self, rays: &[Ray], out: &mut Vec<Option<SurfaceInteraction>>) {
        out.clear();
        out.reserve(rays.len());
        if !self.moving.ids.is_empty() {
            out.extend(rays.iter().map(|r| self.intersect(r)));
            return;
        }
        let prefetch = crate::bvh::prefetch::worth(&self.prims);
        for chunk in rays.chunks(8) {
            let (hits, taken) = self.bvh.closest_packet(chunk, |i, k, t_max| {
                self.other_in_packet(chunk, i, k, t_max)
            });
            if prefetch {
                // The records' data for all the packet's hits asked for at once, so that their
                // misses overlap (the one-ray query hides them behind its traversal instead).
                for h in hits.iter().flatten() {
                    if (h.prim as usize) < self.prims.len() {
                        self.prefetch_record(h.prim);
                    }
                }
            }
            for (i, ray) in chunk.iter().enumerate() {
                out.push(if taken >> i & 1 == 1 {
                    hits[i].map(|h| self.interaction(ray, h))
                } else {
                    self.intersect(ray)
                });
            }
        }
    }

    /// The distance to the closest hit of every ray of `rays`, in order: [`Self::hit_distance`]
    /// for each, bit for bit, traced eight at a time as in [`Self::intersect_stream`] but
    /// without the surface records (the stream counterpart of `hit_distance`, and what a
    /// packet query of Embree's, `rtcIntersect8`, returns besides the hit's ids).
    pub fn hit_distance_stream(&self, rays: &[Ray], out: &mut Vec<Option<f32>>) {
        self.stream(rays, out, Self::hit_distance, |chunk| {
            let (hits, taken) = self.bvh.closest_packet(chunk, |i, k, t_max| {
                self.other_in_packet(chunk, i, k, t_max)
            });
            (hits.map(|h| h.map(|h| h.t)), taken)
        });
    }

    /// Whether each ray of `rays` is blocked before its `t_max`, in order: [`Self::occluded`]
    /// for each, traced eight at a time as in [`Self::intersect_stream`].
    pub fn occluded_stream(&self, rays: &[Ray], out: &mut Vec<bool>) {
        self.stream(rays, out, Self::occluded, |chunk| {
            let (hit, taken) = self.bvh.any_packet(chunk, |i, k, t_max| {
                self.other_in_packet(chunk, i, k, t_max)
            });
            (std::array::from_fn(|i| hit >> i & 1 == 1), taken)
        });
    }

    /// The loop of the streams whose answers are small ([`Self::hit_distance_stream`],
    /// [`Self::occluded_stream`]): `packet` answers up to eight rays and says which it took,
    /// `one` answers the others (and every ray where meshes move). `intersect_stream` keeps its
    /// own loop: passing its eight records through here cost 8 % more instructions per ray
    /// (docs/performance.md, fourteenth session).
    #[inline(always)]
    fn stream<T: Copy>(
        &self,
        rays: &[Ray],
        out: &mut Vec<T>,
        one: impl Fn(&Self, &Ray) -> T,
        mut packet: impl FnMut(&[Ray]) -> ([T; 8], u32),
    ) {
        out.clear();
        out.reserve(rays.len());
        if !self.moving.ids.is_empty() {
            out.extend(rays.iter().map(|r| one(self, r)));
            return;
        }
        for chunk in rays.chunks(8) {
            let (answers, taken) = packet(chunk);
            for (i, ray) in chunk.iter().enumerate() {
                out.push(if taken >> i & 1 == 1 {
                    answers[i]
                } else {
                    one(self, ray)
                });
            }
        }
    }

    /// Ray `i` of a packet against non-triangle primitive `k` (the packet traversals'
    /// `other`): the test [`Self::intersect`]'s traversal makes, with the ray's prepared
    /// triangle ray made again (the same function of the ray, so the same bits).
    fn other_in_packet(
        &self,
        rays: &[Ray],
        i: usize,
        k: u32,
        t_max: f32,
    ) -> Option<(f32, f32, f32)> {
        let ray = rays.get(i)?;
        let tr = TriangleRay::new(ray.o, ray.d);
        self.prims[k as usize]
            .geom
            .intersect(&tr, ray.o, ray.d, t_max)
    }

    /// True if anything blocks `ray` before `ray.t_max` (stops at the first hit found).
    pub fn occluded(&self, ray: &Ray) -> bool {
        let Some(tr) = self.rays(ray) else {
            return false;
        };
        let (o, d) = (ray.o, ray.d);
        self.bvh.any(o, d, &tr, ray.t_max, |k, t_max| {
            self.prims[k as usize]
                .geom
                .intersect(&tr, ray.o, ray.d, t_max)
        }) || (!self.moving.ids.is_empty()
            && self.moving.bvh.any(o, d, &tr, ray.t_max, |k, t_max| {
                self.moving_intersect(k, &tr, ray.time, t_max)
            }))
    }

    /// World bounds of all shapes.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// The full record of a hit found by the traversal.
    #[inline(always)]
    fn interaction(&self, ray: &Ray, hit: WideHit) -> SurfaceInteraction {
        if let Some(&(s, p)) = (hit.prim as usize)
            .checked_sub(self.prims.len())
            .and_then(|k| self.moving.ids.get(k))
        {
            return self.moving_interaction(ray, hit, s, p);
        }
        let rec = &self.prims[hit.prim as usize];
        let (geom, shape_id, prim_id) = (&rec.geom, rec.shape, rec.prim);
        let shape = &self.shapes[shape_id as usize];
        let p_ray = ray.at(hit.t);
        let sh = match (&shape.geometry, geom) {
            (ShapeGeometry::Mesh(m), PrimGeom::Triangle(v)) => {
                m.surface_at(prim_id as usize, v, &rec.constants, hit.b1, hit.b2)
            }
            (_, PrimGeom::Sphere(s)) => s.surface(p_ray),
            (_, PrimGeom::Disk(d)) => d.surface(p_ray),
            // Unreachable (triangles come from meshes only); keep a sane record anyway.
            (_, PrimGeom::Triangle(_)) => flat_hit(p_ray, -ray.d),
        };
        self.record(shape, shape_id, prim_id, hit.t, ray.time, sh)
    }

    /// The record of a hit on moving triangle `prim_id` of shape `shape_id`: the triangle, its
    /// normal, tangents and vertex normals at the ray's time.
    fn moving_interaction(
        &self,
        ray: &Ray,
        hit: WideHit,
        shape_id: u32,
        prim_id: u32,
    ) -> SurfaceInteraction {
        let shape = &self.shapes[shape_id as usize];
        let sh = match (
            moving_mesh(shape),
            self.moving_triangle(shape_id, prim_id, ray.time),
        ) {
            (Some((m, motion)), Some(v)) => {
                let i = prim_id as usize;
                let normals = m.indices.get(i).and_then(|idx| {
                    let n = idx.map(|k| motion.normal(k as usize, ray.time));
                    Some([n[0]?, n[1]?, n[2]?])
                });
                m.surface_with_normals(i, &v, normals, &m.constants_of(i, &v), hit.b1, hit.b2)
            }
            _ => flat_hit(ray.at(hit.t), -ray.d),
        };
        self.record(shape, shape_id, prim_id, hit.t, ray.time, sh)
    }

    /// The full record from a shape's surface data.
    fn record(
        &self,
        shape: &Shape,
        shape_id: u32,
        prim_id: u32,
        t: f32,
        time: f32,
        mut sh: ShapeHit,
    ) -> SurfaceInteraction {
        if shape.flip_normals {
            sh.ng = -sh.ng;
            sh.ns = -sh.ns;
        }
        SurfaceInteraction {
            p: sh.p,
            t,
            ng: sh.ng,
            ns: sh.ns,
            uv: sh.uv,
            bary: sh.bary,
            dpdu: sh.dpdu,
            dpdv: sh.dpdv,
            shape: shape_id,
            prim: prim_id,
            material: shape.material,
            light: shape.light,
            medium_inside: shape.medium_inside,
            medium_outside: shape.medium_outside,
            time,
        }
    }

    /// The vertices (and vertex normals, when the mesh has them) of the triangle hit at `si`,
    /// as ray and photon differentials need them (seed 000 app. B.3); `None` unless `si` is on a
    /// mesh. Normals are reversed on `flip_normals` shapes, like `si.ns`. Looked up here rather
    /// than stored in every [`SurfaceInteraction`], which then stays small to copy.
    pub fn triangle_vertices(&self, si: &SurfaceInteraction) -> Option<TriangleVertices> {
        let (shape, m) = self.mesh_of(si)?;
        let i = si.prim as usize;
        if let Some(motion) = &shape.motion {
            // At the hit's time (flip_normals is already baked into the keyframes' normals).
            let idx = m.indices.get(i)?;
            let n = idx.map(|k| motion.normal(k as usize, si.time));
            return Some(TriangleVertices {
                p: idx.map(|k| motion.position(k as usize, si.time)),
                n: all_three(n),
            });
        }
        let n = m.triangle_normals(i);
        Some(TriangleVertices {
            p: m.triangle(i)?,
            n: if shape.flip_normals {
                n.map(|n| n.map(|v| -v))
            } else {
                n
            },
        })
    }

    /// The time derivatives of the vertices and vertex normals of the triangle hit at `si`
    /// (m and normal per frame; seed 003 eq. 5 before the exposure factor): the forward
    /// difference of the keyframe interval of `si.time`, backward at the last keyframe; zero
    /// for static shapes. `None` unless `si` is on a mesh.
    pub fn triangle_velocities(&self, si: &SurfaceInteraction) -> Option<TriangleVertices> {
        let (shape, m) = self.mesh_of(si)?;
        let idx = m.indices.get(si.prim as usize)?;
        let Some(motion) = &shape.motion else {
            return Some(TriangleVertices {
                p: [Vec3::ZERO; 3],
                n: m.normals.as_ref().map(|_| [Vec3::ZERO; 3]),
            });
        };
        let n = idx.map(|k| motion.normal_velocity(k as usize, si.time));
        Some(TriangleVertices {
            p: idx.map(|k| motion.velocity(k as usize, si.time)),
            n: all_three(n),
        })
    }

    /// The shape of `si` and its mesh, if it is one.
    fn mesh_of(&self, si: &SurfaceInteraction) -> Option<(&Shape, &TriangleMesh)> {
        let shape = self.shapes.get(si.shape as usize)?;
        match &shape.geometry {
            ShapeGeometry::Mesh(m) => Some((shape, m)),
            _ => None,
        }
    }
}

/// The mesh and motion of a shape whose mesh moves.
#[inline]
fn moving_mesh(shape: &Shape) -> Option<(&TriangleMesh, &crate::shape::MeshMotion)> {
    match (&shape.geometry, &shape.motion) {
        (ShapeGeometry::Mesh(m), Some(motion)) => Some((m, motion)),
        _ => None,
    }
}

fn all_three(n: [Option<Vec3>; 3]) -> Option<[Vec3; 3]> {
    Some([n[0]?, n[1]?, n[2]?])
}

impl MovingTriangles {
    /// The BVH over `ids`' triangles swept over their keyframes; triangles with bad indices
    /// or non-finite vertices are skipped.
    fn build(shapes: &[Shape], ids: Vec<(u32, u32)>) -> Self {
        let boxes: Vec<Option<Aabb>> = ids
            .par_iter()
            .map(|&(s, p)| {
                let (m, motion) = moving_mesh(&shapes[s as usize])?;
                let idx = m.indices.get(p as usize)?;
                let mut b = Aabb::EMPTY;
                for frame in &motion.positions {
                    for &k in idx {
                        let v = *frame.get(k as usize)?;
                        if !v.is_finite() {
                            return None;
                        }
                        b.grow(v);
                    }
                }
                Some(b)
            })
            .collect();
        let ids: Vec<(u32, u32)> = ids
            .into_iter()
            .zip(&boxes)
            .filter_map(|(id, b)| b.map(|_| id))
            .collect();
        let boxes: Vec<Aabb> = boxes.into_iter().flatten().map(pad).collect();
        if boxes.is_empty() {
            return Self::default();
        }
        let bvh = WideBvh::build(&boxes, &vec![None; boxes.len()]);
        let ids = bvh.order().iter().map(|&k| ids[k as usize]).collect();
        Self { bvh, ids }
    }

    /// Bounds of every moving triangle over all its keyframes.
    fn bounds(&self, shapes: &[Shape]) -> Option<Aabb> {
        let mut b = Aabb::EMPTY;
        for &(s, p) in &self.ids {
            let (m, motion) = moving_mesh(&shapes[s as usize])?;
            for frame in &motion.positions {
                for &k in m.indices.get(p as usize)? {
                    b.grow(frame[k as usize]);
                }
            }
        }
        (!self.ids.is_empty()).then_some(b)
    }
}

/// A box padded by a few ulps of its coordinates so rays aimed at shared vertices and edges
/// cannot slip through a slab test (which also grows its far distance).
fn pad(b: Aabb) -> Aabb {
    let pad =
        (b.min.abs().max(b.max.abs()).max_element() * 4.0 * f32::EPSILON).max(f32::MIN_POSITIVE);
    Aabb {
        min: b.min - pad,
        max: b.max + pad,
    }
}

fn flat_hit(p: Vec3, n: Vec3) -> ShapeHit {
    let f = caustica_core::Frame::from_normal(n.normalize_or_zero());
    ShapeHit {
        p,
        ng: f.n,
        ns: f.n,
        uv: Vec2::ZERO,
        bary: Vec2::ZERO,
        dpdu: f.s,
        dpdv: f.t,
    }
}
