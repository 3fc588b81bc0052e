//! Procedural meshes of the case-study scenes (seed 000 ch. 6, seed 002 fig. 1): a sinusoidal
//! water-wave height field and a thick cylindrical ring. The built-in scenes build them here;
//! `scenes/meshes/*.ply` are these meshes written out for the TOML and Mitsuba versions.

use super::TriangleMesh;
use caustica_core::Vec3;
use std::f64::consts::PI;

/// A water surface `y = h(x) = mean_height + amplitude · cos(π x / half_width)` over the
/// square `|x|, |z| ≤ half_width`: one wavelength (2 · `half_width`) with the crest at `x = 0`
/// and troughs at the edges, constant along z (seed 000 fig. 6.2(a) is this profile).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaveParams {
    /// Half the side of the square surface and half the wavelength (m).
    pub half_width: f32,
    /// Mean height of the surface above y = 0 (m).
    pub mean_height: f32,
    /// Amplitude of the cosine (m).
    pub amplitude: f32,
    /// Grid cells along x (the wave direction) and along z.
    pub cells_x: u32,
    pub cells_z: u32,
}

impl WaveParams {
    /// Height h(x) (m), evaluated in double precision.
    pub fn height(&self, x: f64) -> f64 {
        let k = PI / self.half_width as f64;
        self.mean_height as f64 + self.amplitude as f64 * (k * x).cos()
    }
    /// Slope dh/dx.
    pub fn slope(&self, x: f64) -> f64 {
        let k = PI / self.half_width as f64;
        -self.amplitude as f64 * k * (k * x).sin()
    }
    /// Unit upward normal `(−h′(x), 1, 0) / |·|` of the height field at `x`.
    pub fn normal(&self, x: f64) -> [f64; 3] {
        let s = self.slope(x);
        let l = (1.0 + s * s).sqrt();
        [-s / l, 1.0 / l, 0.0]
    }
}

/// The height field of `p` as an open triangle mesh: a `(cells_x + 1) × (cells_z + 1)` vertex
/// grid with the analytic unit normals of [`WaveParams::normal`] at the vertices (shading normals
/// are their Phong interpolation), triangles wound counter-clockwise seen from above so that the
/// geometric normals point up (+y, the air side of a water surface). The boundary is the
/// square's perimeter.
pub fn water_wave_mesh(p: &WaveParams) -> TriangleMesh {
    let (nx, nz) = (p.cells_x.max(1), p.cells_z.max(1));
    let w = p.half_width as f64;
    let mut m = TriangleMesh::default();
    let mut normals = Vec::new();
    for j in 0..=nz {
        let z = -w + 2.0 * w * j as f64 / nz as f64;
        for i in 0..=nx {
            let x = -w + 2.0 * w * i as f64 / nx as f64;
            m.positions
                .push(Vec3::new(x as f32, p.height(x) as f32, z as f32));
            let n = p.normal(x);
            normals.push(Vec3::new(n[0] as f32, n[1] as f32, n[2] as f32));
        }
    }
    let row = nx + 1;
    for j in 0..nz {
        for i in 0..nx {
            let v00 = j * row + i;
            let (v10, v01, v11) = (v00 + 1, v00 + row, v00 + row + 1);
            m.indices.push([v00, v01, v10]);
            m.indices.push([v10, v01, v11]);
        }
    }
    m.normals = Some(normals);
    m
}

/// A thick ring standing on y = 0 around the y axis: the solid between the cylinders of radii
/// `inner_radius` and `outer_radius`, from y = 0 to y = `height`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RingParams {
    pub inner_radius: f32,
    pub outer_radius: f32,
    pub height: f32,
    /// Segments around the axis.
    pub segments: u32,
}

/// The ring of `p` as a closed (watertight) triangle mesh with outward normals: the outer wall
/// (normals away from the axis), the inner wall (normals toward the axis — the reflecting side
/// of the case studies), the top annulus (+y) and the bottom annulus (−y). Curved walls carry
/// smooth radial vertex normals, the annuli flat ones, so the four parts have their own vertices
/// along the rims; those share bit-identical positions (every part uses the same cos/sin table).
pub fn ring_mesh(p: &RingParams) -> TriangleMesh {
    let n = p.segments.max(3);
    let (ri, ro, h) = (p.inner_radius, p.outer_radius, p.height);
    let dirs: Vec<(f32, f32)> = (0..n)
        .map(|i| {
            let phi = 2.0 * PI * i as f64 / n as f64;
            (phi.cos() as f32, phi.sin() as f32)
        })
        .collect();
    let at = |r: f32, y: f32, (c, s): (f32, f32)| Vec3::new(r * c, y, r * s);
    let mut m = TriangleMesh::default();
    let mut normals = Vec::new();
    // Each part is two rings of n vertices, `a` (index base) then `b` (base + n).
    let mut part = |m: &mut TriangleMesh,
                    a: &dyn Fn((f32, f32)) -> Vec3,
                    b: &dyn Fn((f32, f32)) -> Vec3,
                    normal: &dyn Fn((f32, f32)) -> Vec3,
                    flip: bool| {
        let base = m.positions.len() as u32;
        for &d in &dirs {
            m.positions.push(a(d));
            normals.push(normal(d));
        }
        for &d in &dirs {
            m.positions.push(b(d));
            normals.push(normal(d));
        }
        for i in 0..n {
            let j = (i + 1) % n;
            let (a0, a1, b0, b1) = (base + i, base + j, base + n + i, base + n + j);
            if flip {
                m.indices.push([a0, a1, b0]);
                m.indices.push([a1, b1, b0]);
            } else {
                m.indices.push([a0, b0, a1]);
                m.indices.push([a1, b0, b1]);
            }
        }
    };
    // Walls: a = bottom rim, b = top rim. Bottom → top × increasing φ points away from the axis.
    part(
        &mut m,
        &|d| at(ro, 0.0, d),
        &|d| at(ro, h, d),
        &|(c, s)| Vec3::new(c, 0.0, s),
        false,
    );
    part(
        &mut m,
        &|d| at(ri, 0.0, d),
        &|d| at(ri, h, d),
        &|(c, s)| Vec3::new(-c, 0.0, -s),
        true,
    );
    // Annuli: a = inner rim, b = outer rim. Outward radius × increasing φ points down (−y).
    part(
        &mut m,
        &|d| at(ri, h, d),
        &|d| at(ro, h, d),
        &|_| Vec3::Y,
        true,
    );
    part(
        &mut m,
        &|d| at(ri, 0.0, d),
        &|d| at(ro, 0.0, d),
        &|_| -Vec3::Y,
        false,
    );
    m.normals = Some(normals);
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// Directed edges keyed by the bit patterns of their end positions (vertices welded by
    /// position), with their multiplicity.
    fn directed_edges(m: &TriangleMesh) -> HashMap<([u32; 3], [u32; 3]), i32> {
        let key = |v: Vec3| v.to_array().map(f32::to_bits);
        let mut e = HashMap::new();
        for t in &m.indices {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let ka = key(m.positions[a as usize]);
                let kb = key(m.positions[b as usize]);
                *e.entry((ka, kb)).or_insert(0) += 1;
            }
        }
        e
    }

    /// Edges used by exactly one triangle (the boundary), after welding by position; panics if
    /// an edge is used twice in the same direction (inconsistent winding) or more than twice.
    fn boundary_edges(m: &TriangleMesh) -> Vec<([u32; 3], [u32; 3])> {
        let e = directed_edges(m);
        let mut boundary = Vec::new();
        for (&(a, b), &count) in &e {
            assert_eq!(count, 1, "edge used {count} times in one direction");
            if !e.contains_key(&(b, a)) {
                boundary.push((a, b));
            }
        }
        boundary
    }

    /// Σ over triangles of p0 · (p1 × p2) / 6: the enclosed volume of a closed mesh with outward
    /// winding.
    fn signed_volume(m: &TriangleMesh) -> f64 {
        m.indices
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|k| m.positions[k as usize].as_dvec3());
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    fn geometric_normal(m: &TriangleMesh, t: &[u32; 3]) -> Vec3 {
        let [a, b, c] = t.map(|k| m.positions[k as usize]);
        (b - a).cross(c - a).normalize()
    }

    const WAVE: WaveParams = WaveParams {
        half_width: 1.0,
        mean_height: 3.0,
        amplitude: 0.25,
        cells_x: 64,
        cells_z: 4,
    };

    #[test]
    fn wave_normals_are_the_analytic_derivative() {
        // The analytic slope against central differences of the height function.
        for i in 0..=100 {
            let x = -1.0 + 0.02 * i as f64;
            let eps = 1e-5;
            let fd = (WAVE.height(x + eps) - WAVE.height(x - eps)) / (2.0 * eps);
            assert!((WAVE.slope(x) - fd).abs() < 1e-8, "x = {x}");
        }
        // Vertex normals against central differences of the mesh's own vertices along x: the
        // tangent (p[i+1] − p[i−1]) is perpendicular to the normal up to O(Δx²).
        let m = water_wave_mesh(&WAVE);
        let ns = m.normals.as_ref().unwrap();
        let row = WAVE.cells_x as usize + 1;
        for j in 0..=WAVE.cells_z as usize {
            for i in 1..row - 1 {
                let k = j * row + i;
                let tangent = (m.positions[k + 1] - m.positions[k - 1]).normalize();
                assert!(tangent.dot(ns[k]).abs() < 2e-3, "vertex {i},{j}");
                assert!((ns[k].length() - 1.0).abs() < 1e-6);
                assert!(ns[k].y > 0.0 && ns[k].z == 0.0);
            }
        }
    }

    #[test]
    fn wave_is_an_open_sheet_facing_up_with_the_square_as_boundary() {
        let m = water_wave_mesh(&WAVE);
        let (nx, nz) = (WAVE.cells_x as usize, WAVE.cells_z as usize);
        assert_eq!(m.positions.len(), (nx + 1) * (nz + 1));
        assert_eq!(m.indices.len(), 2 * nx * nz);
        let ns = m.normals.as_ref().unwrap();
        for t in &m.indices {
            let ng = geometric_normal(&m, t);
            assert!(ng.y > 0.0, "triangle faces down");
            for &k in t {
                assert!(ng.dot(ns[k as usize]) > 0.99);
            }
        }
        let boundary = boundary_edges(&m);
        assert_eq!(boundary.len(), 2 * (nx + nz));
        for (a, _) in boundary {
            let p = Vec3::from_array(a.map(f32::from_bits));
            assert!(
                p.x.abs() == 1.0 || p.z.abs() == 1.0,
                "boundary vertex {p} is not on the square's edge"
            );
        }
        // Crest in the middle, troughs at the edges.
        let b = m.bounds();
        assert!((b.max.y - 3.25).abs() < 1e-6 && (b.min.y - 2.75).abs() < 1e-6);
    }

    #[test]
    fn ring_is_watertight_with_outward_normals() {
        let p = RingParams {
            inner_radius: 1.0,
            outer_radius: 1.1,
            height: 0.5,
            segments: 48,
        };
        let m = ring_mesh(&p);
        assert_eq!(m.indices.len(), 8 * 48);
        assert!(boundary_edges(&m).is_empty(), "the ring has a boundary");
        // Volume of the polygonal ring: (N/2) sin(2π/N) (ro² − ri²) h.
        let n = 48.0f64;
        let expected = n / 2.0 * (2.0 * PI / n).sin() * (1.1f64.powi(2) - 1.0) * 0.5;
        let v = signed_volume(&m);
        assert!((v - expected).abs() < 1e-5 * expected, "{v} vs {expected}");
        // Vertex normals agree with the winding; the inner wall faces the axis.
        let ns = m.normals.as_ref().unwrap();
        for t in &m.indices {
            let ng = geometric_normal(&m, t);
            let c = t.map(|k| m.positions[k as usize]);
            let centroid = (c[0] + c[1] + c[2]) / 3.0;
            for &k in t {
                assert!(ng.dot(ns[k as usize]) > 0.99);
            }
            let r = Vec3::new(centroid.x, 0.0, centroid.z);
            if ng.y.abs() < 1e-6 {
                let inner = r.length() < 1.05;
                assert_eq!(ng.dot(r) < 0.0, inner, "wall at {centroid} faces {ng}");
            } else {
                assert_eq!(ng.y > 0.0, centroid.y > 0.25, "annulus at {centroid}");
            }
        }
    }
}
