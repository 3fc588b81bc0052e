//! Triangle meshes.

use super::Aabb;
use caustica_core::{Affine3A, Vec2, Vec3};

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
