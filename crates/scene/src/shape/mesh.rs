//! Triangle meshes.

// NaN-rejecting `!(x > 0.0)` comparisons are intentional here.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::Aabb;
use crate::geometry::ShapeHit;
use caustica_core::{Affine3A, Frame, Vec2, Vec3};

/// A ray prepared for the watertight ray/triangle test of Woop, Benthin and Wald (2013):
/// vertices are translated to the ray origin, permuted so the ray's dominant axis is z and
/// sheared so the ray becomes +z. Each vertex is transformed by the same function whatever
/// triangle it belongs to, so neighbouring triangles leave no cracks (no leaks through shared
/// edges or vertices of closed meshes).
#[derive(Clone, Copy, Debug)]
pub struct TriangleRay {
    pub(crate) o: Vec3,
    /// Axis permutation: the ray's dominant axis is `kz`; `kx`, `ky` keep a right-handed order.
    pub(crate) kx: usize,
    pub(crate) ky: usize,
    pub(crate) kz: usize,
    /// Shear `(−d_kx/d_kz, −d_ky/d_kz)` and scale `1/d_kz` (Woop et al. 2013, eq. 2).
    pub(crate) sx: f32,
    pub(crate) sy: f32,
    pub(crate) sz: f32,
}

impl TriangleRay {
    #[inline]
    pub fn new(o: Vec3, d: Vec3) -> Self {
        let kz = d.abs().max_position();
        let mut kx = if kz == 2 { 0 } else { kz + 1 };
        let mut ky = if kx == 2 { 0 } else { kx + 1 };
        let da = d.to_array();
        if da[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let sz = 1.0 / da[kz];
        Self {
            o,
            kx,
            ky,
            kz,
            sx: da[kx] * sz,
            sy: da[ky] * sz,
            sz,
        }
    }

    /// Hit with triangle `(p0, p1, p2)`: `(t, b1, b2)` with `t ∈ (0, t_max)` and barycentrics
    /// `b1, b2 ≥ 0`, `b1 + b2 ≤ 1` (edges inclusive). Rays in the triangle's plane and
    /// degenerate triangles miss.
    ///
    /// Each vertex `v` maps to `x' = (v − o)_kx − sx (v − o)_kz`, `y' = (v − o)_ky − sy (v − o)_kz`,
    /// `z' = sz (v − o)_kz`, the same function whatever triangle it belongs to (watertight).
    #[inline(always)]
    pub fn intersect(&self, t_max: f32, p0: Vec3, p1: Vec3, p2: Vec3) -> Option<(f32, f32, f32)> {
        // `& 3` on 4-lane arrays proves the indices in range without a bounds check.
        let (kx, ky, kz) = (self.kx & 3, self.ky & 3, self.kz & 3);
        let a = (p0 - self.o).extend(0.0).to_array();
        let b = (p1 - self.o).extend(0.0).to_array();
        let c = (p2 - self.o).extend(0.0).to_array();
        let (az, bz, cz) = (a[kz], b[kz], c[kz]);
        let (ax, ay) = (a[kx] - self.sx * az, a[ky] - self.sy * az);
        let (bx, by) = (b[kx] - self.sx * bz, b[ky] - self.sy * bz);
        let (cx, cy) = (c[kx] - self.sx * cz, c[ky] - self.sy * cz);
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            // Exactly on an edge in single precision: decide in double precision.
            let (ax, ay, bx, by, cx, cy) = (
                ax as f64, ay as f64, bx as f64, by as f64, cx as f64, cy as f64,
            );
            u = (cx * by - cy * bx) as f32;
            v = (ax * cy - ay * cx) as f32;
            w = (bx * ay - by * ax) as f32;
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let inv = 1.0 / det;
        let t = self.sz * (u * az + v * bz + w * cz) * inv;
        (t > 0.0 && t < t_max).then_some((t, v * inv, w * inv))
    }
}

/// One-off watertight ray/triangle test (see [`TriangleRay`]; prepare the ray once when
/// testing many triangles).
#[inline]
pub fn intersect_triangle(
    o: Vec3,
    d: Vec3,
    t_max: f32,
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
) -> Option<(f32, f32, f32)> {
    TriangleRay::new(o, d).intersect(t_max, p0, p1, p2)
}

/// The parts of a triangle's surface data that do not depend on the hit point (see
/// [`TriangleMesh::triangle_constants`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriangleConstants {
    /// Unit geometric normal (winding order).
    pub ng: Vec3,
    /// Surface tangents ∂p/∂u, ∂p/∂v.
    pub dpdu: Vec3,
    pub dpdv: Vec3,
}

/// An indexed triangle mesh in world space.
#[derive(Clone, Debug, Default)]
pub struct TriangleMesh {
    /// Vertex positions (m).
    pub positions: Vec<Vec3>,
    /// Optional unit vertex normals (interpolated as shading normals).
    pub normals: Option<Vec<Vec3>>,
    /// Optional texture coordinates.
    pub uvs: Option<Vec<Vec2>>,
    /// Counter-clockwise triangles (see the crate docs for orientation).
    pub indices: Vec<[u32; 3]>,
}

/// What [`TriangleMesh::sanitize`] removed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SanitizeReport {
    /// Triangles with a NaN/Inf vertex position.
    pub non_finite: usize,
    /// Triangles with (near) zero area.
    pub degenerate: usize,
    /// Triangles whose indices point past the vertex array.
    pub bad_index: usize,
}

impl SanitizeReport {
    pub fn total(&self) -> usize {
        self.non_finite + self.degenerate + self.bad_index
    }
}

impl TriangleMesh {
    /// The Mitsuba `rectangle`: the square [−1, 1]² in the z = 0 plane facing +z, transformed.
    pub fn rectangle(to_world: &Affine3A) -> Self {
        let p = [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ];
        let uv = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ];
        let mut m = Self {
            positions: p.to_vec(),
            normals: None,
            uvs: Some(uv.to_vec()),
            indices: vec![[0, 1, 2], [0, 2, 3]],
        };
        m.transform(to_world);
        m
    }

    /// The Mitsuba `cube`: [−1, 1]³ with outward faces, transformed.
    pub fn cube(to_world: &Affine3A) -> Self {
        let mut m = Self::default();
        let faces = [
            (Vec3::X, Vec3::Y, Vec3::Z),
            (Vec3::Y, Vec3::Z, Vec3::X),
            (Vec3::Z, Vec3::X, Vec3::Y),
        ];
        for (n, a, b) in faces {
            for s in [1.0f32, -1.0] {
                let n = n * s;
                let (a, b) = if s > 0.0 { (a, b) } else { (b, a) };
                let base = m.positions.len() as u32;
                for (u, v) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    m.positions.push(n + a * u + b * v);
                }
                m.indices.push([base, base + 1, base + 2]);
                m.indices.push([base, base + 2, base + 3]);
            }
        }
        m.transform(to_world);
        m
    }

    /// Applies an affine transform to positions and (via the inverse transpose) normals.
    pub fn transform(&mut self, m: &Affine3A) {
        for p in &mut self.positions {
            *p = m.transform_point3(*p);
        }
        if let Some(ns) = &mut self.normals {
            let nm = m.matrix3.inverse().transpose();
            for n in ns {
                *n = Vec3::from(nm * caustica_core::Vec3A::from(*n)).normalize_or_zero();
            }
        }
        // A transform with negative determinant mirrors the winding; restore outward faces.
        if m.matrix3.determinant() < 0.0 {
            for t in &mut self.indices {
                t.swap(1, 2);
            }
        }
    }

    /// Removes triangles with non-finite vertices, out-of-range indices or zero area, and
    /// replaces non-finite vertex normals by "no normals". Returns what it removed so loaders can
    /// warn with a count.
    pub fn sanitize(&mut self) -> SanitizeReport {
        let mut r = SanitizeReport::default();
        let n = self.positions.len();
        let pos = &self.positions;
        self.indices.retain(|t| {
            if t.iter().any(|&i| i as usize >= n) {
                r.bad_index += 1;
                return false;
            }
            let [a, b, c] = t.map(|i| pos[i as usize]);
            if !(a.is_finite() && b.is_finite() && c.is_finite()) {
                r.non_finite += 1;
                return false;
            }
            let cr = (b - a).cross(c - a);
            if !(cr.length_squared() > 0.0) || !cr.is_finite() {
                r.degenerate += 1;
                return false;
            }
            true
        });
        if let Some(ns) = &self.normals
            && (ns.len() != n
                || ns
                    .iter()
                    .any(|v| !v.is_finite() || v.length_squared() == 0.0))
        {
            self.normals = None;
        }
        if let Some(uv) = &self.uvs
            && (uv.len() != n || uv.iter().any(|v| !v.is_finite()))
        {
            self.uvs = None;
        }
        r
    }

    /// Area of triangle `i` (m²).
    pub fn triangle_area(&self, i: usize) -> f32 {
        let [a, b, c] = self.indices[i].map(|k| self.positions[k as usize]);
        0.5 * (b - a).cross(c - a).length()
    }

    /// Vertex positions of triangle `i`, or `None` if it indexes past the vertex array.
    #[inline]
    pub fn triangle(&self, i: usize) -> Option<[Vec3; 3]> {
        let t = self.indices.get(i)?;
        Some([
            *self.positions.get(t[0] as usize)?,
            *self.positions.get(t[1] as usize)?,
            *self.positions.get(t[2] as usize)?,
        ])
    }

    /// Vertex normals of triangle `i` when the mesh has a complete normal array.
    #[inline]
    pub fn triangle_normals(&self, i: usize) -> Option<[Vec3; 3]> {
        let ns = self.normals.as_ref()?;
        if ns.len() != self.positions.len() {
            return None;
        }
        let t = self.indices.get(i)?;
        Some(t.map(|k| ns[k as usize]))
    }

    /// Texture coordinates of triangle `i` when the mesh has a complete uv array.
    #[inline]
    pub fn triangle_uvs(&self, i: usize) -> Option<[Vec2; 3]> {
        let uv = self.uvs.as_ref()?;
        if uv.len() != self.positions.len() {
            return None;
        }
        let t = self.indices.get(i)?;
        Some(t.map(|k| uv[k as usize]))
    }

    /// What the surface data of triangle `i` has in common at every point, or `None` for a bad
    /// index: `ng = normalize(e1 × e2)` (winding; +z if degenerate) and the tangents `dpdu`,
    /// `dpdv` solved from the uv parameterisation (for `uv = (b1, b2)` they are the edges `e1`,
    /// `e2`), or a frame around `ng` if that degenerates. Computed once per triangle when the
    /// BVH is built.
    pub fn triangle_constants(&self, i: usize) -> Option<TriangleConstants> {
        Some(self.constants_of(i, &self.triangle(i)?))
    }

    /// [`Self::triangle_constants`] of triangle `i` with its vertices at `p` (a moving mesh's
    /// vertices at some time).
    pub fn constants_of(&self, i: usize, p: &[Vec3; 3]) -> TriangleConstants {
        let e1 = p[1] - p[0];
        let e2 = p[2] - p[0];
        let ng = e1.cross(e2).normalize_or_zero();
        let ng = if ng == Vec3::ZERO { Vec3::Z } else { ng };
        let (dpdu, dpdv) = match self.triangle_uvs(i) {
            Some(t) => {
                let d02 = t[0] - t[2];
                let d12 = t[1] - t[2];
                let dp02 = p[0] - p[2];
                let dp12 = p[1] - p[2];
                let det = d02.x * d12.y - d02.y * d12.x;
                let (mut du, mut dv) = (Vec3::ZERO, Vec3::ZERO);
                if det.abs() > 1e-12 {
                    let inv = 1.0 / det;
                    du = (dp02 * d12.y - dp12 * d02.y) * inv;
                    dv = (dp12 * d02.x - dp02 * d12.x) * inv;
                }
                (du, dv)
            }
            None => (e1, e2),
        };
        let (dpdu, dpdv) =
            if dpdu.is_finite() && dpdv.is_finite() && dpdu.cross(dpdv).length_squared() > 0.0 {
                (dpdu, dpdv)
            } else {
                let f = Frame::from_normal(ng);
                (f.s, f.t)
            };
        TriangleConstants { ng, dpdu, dpdv }
    }

    /// Surface data of triangle `i` (vertices `p`, constants `c` from
    /// [`Self::triangle_constants`]) at barycentrics `(b1, b2)`:
    /// `ns` the normalised Phong interpolation of vertex normals flipped into the hemisphere of
    /// `ng` (or `ng`); `uv` the interpolated texture coordinates or `(b1, b2)`.
    #[inline]
    pub fn surface_at(
        &self,
        i: usize,
        p: &[Vec3; 3],
        c: &TriangleConstants,
        b1: f32,
        b2: f32,
    ) -> ShapeHit {
        self.surface_with_normals(i, p, self.triangle_normals(i), c, b1, b2)
    }

    /// [`Self::surface_at`] with the vertex normals `normals` (a moving mesh's at some time).
    /// Inlined: it runs once per closest hit, and out of line its call and the copy of its
    /// record made the hit record cost 186 instructions instead of 150 (Cornell box, callgrind).
    #[inline(always)]
    pub fn surface_with_normals(
        &self,
        i: usize,
        p: &[Vec3; 3],
        normals: Option<[Vec3; 3]>,
        c: &TriangleConstants,
        b1: f32,
        b2: f32,
    ) -> ShapeHit {
        let b0 = 1.0 - b1 - b2;
        let ng = c.ng;
        let pos = p[0] * b0 + p[1] * b1 + p[2] * b2;
        let ns = match normals {
            Some(n) => {
                let v = (n[0] * b0 + n[1] * b1 + n[2] * b2).normalize_or_zero();
                if v == Vec3::ZERO || !v.is_finite() {
                    ng
                } else if v.dot(ng) < 0.0 {
                    -v
                } else {
                    v
                }
            }
            None => ng,
        };
        let uv = match self.triangle_uvs(i) {
            Some(t) => t[0] * b0 + t[1] * b1 + t[2] * b2,
            None => Vec2::new(b1, b2),
        };
        ShapeHit {
            p: pos,
            ng,
            ns,
            uv,
            bary: Vec2::new(b1, b2),
            dpdu: c.dpdu,
            dpdv: c.dpdv,
        }
    }

    pub fn bounds(&self) -> Aabb {
        let mut b = Aabb::EMPTY;
        for p in &self.positions {
            b.grow(*p);
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sanitize_counts_bad_triangles() {
        let mut m = TriangleMesh {
            positions: vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::Y,
                Vec3::new(f32::NAN, 0.0, 0.0),
                Vec3::X * 2.0,
            ],
            normals: None,
            uvs: None,
            indices: vec![[0, 1, 2], [0, 1, 3], [0, 1, 4], [0, 1, 9]],
        };
        let r = m.sanitize();
        assert_eq!(
            r,
            SanitizeReport {
                non_finite: 1,
                degenerate: 1,
                bad_index: 1
            }
        );
        assert_eq!(m.indices, vec![[0, 1, 2]]);
    }

    #[test]
    fn rectangle_faces_plus_z_and_has_area_four() {
        let m = TriangleMesh::rectangle(&Affine3A::IDENTITY);
        let [a, b, c] = m.indices[0].map(|k| m.positions[k as usize]);
        assert!((b - a).cross(c - a).normalize().dot(Vec3::Z) > 0.999);
        assert!((m.triangle_area(0) + m.triangle_area(1) - 4.0).abs() < 1e-6);
    }

    #[test]
    fn cube_faces_point_outward() {
        let m = TriangleMesh::cube(&Affine3A::IDENTITY);
        assert_eq!(m.indices.len(), 12);
        for t in &m.indices {
            let [a, b, c] = t.map(|k| m.positions[k as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.dot((a + b + c) / 3.0) > 0.0);
        }
    }
}
