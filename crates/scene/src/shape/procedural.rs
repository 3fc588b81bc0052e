//! Procedural meshes of the case-study scenes (seed 000 ch. 6, seed 002 fig. 1): a sinusoidal
//! water-wave height field and a thick cylindrical ring; and of the participating-media scenes
//! (seed 000 sec. 8.5): a flat-shaded geodesic sphere and a faceted dome with a pentagonal cap.
//! The built-in scenes build them here; `scenes/meshes/*.ply` are these meshes written out for
//! the TOML and Mitsuba versions.

use super::{MeshMotion, TriangleMesh};
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

/// The height field of `p` as an open triangle mesh ([`super::height_field_mesh`]): a
/// `(cells_x + 1) × (cells_z + 1)` vertex
/// grid with the analytic unit normals of [`WaveParams::normal`] at the vertices (shading normals
/// are their Phong interpolation), triangles wound counter-clockwise seen from above so that the
/// geometric normals point up (+y, the air side of a water surface). The boundary is the
/// square's perimeter.
pub fn water_wave_mesh(p: &WaveParams) -> TriangleMesh {
    let w = p.half_width as f64;
    super::height_field_mesh((-w, w), (-w, w), (p.cells_x, p.cells_z), |x, _| {
        (p.height(x), [p.slope(x), 0.0])
    })
}

/// The water wave of `p` travelling toward +x by `phase_step` m per frame (the crests move
/// perpendicular to themselves, seed 003 sec. 5), as keyframes `0 … frames − 1`: the mesh of
/// [`water_wave_mesh`] at frame 0 and the [`MeshMotion`] whose keyframe `f` has the heights
/// `h(x − f · phase_step)` and their exact normals. Vertices move vertically only.
pub fn moving_water_wave(
    p: &WaveParams,
    phase_step: f32,
    frames: u32,
) -> (TriangleMesh, MeshMotion) {
    let mesh = water_wave_mesh(p);
    let frames = frames.max(1);
    let mut positions = Vec::with_capacity(frames as usize);
    let mut normals = Vec::with_capacity(frames as usize);
    for f in 0..frames {
        let shift = f as f64 * phase_step as f64;
        positions.push(
            mesh.positions
                .iter()
                .map(|v| Vec3::new(v.x, p.height(v.x as f64 - shift) as f32, v.z))
                .collect::<Vec<_>>(),
        );
        normals.push(
            mesh.positions
                .iter()
                .map(|v| {
                    let n = p.normal(v.x as f64 - shift);
                    Vec3::new(n[0] as f32, n[1] as f32, n[2] as f32)
                })
                .collect::<Vec<_>>(),
        );
    }
    let n = mesh.positions.len();
    let motion = MeshMotion::new(0.0, positions, Some(normals), n)
        .expect("keyframes of the generated mesh have its vertex count and are finite");
    (mesh, motion)
}

/// A solid rod (a closed cylinder) of `radius` along +x from x = 0 to x = `length`, centred
/// on the x axis: `segments` around, `rings` quads along; smooth outward vertex normals on the
/// side (Phong-shaded glass), flat caps with their own vertices. Watertight.
pub fn rod_mesh(radius: f32, length: f32, segments: u32, rings: u32) -> TriangleMesh {
    let (ns, nr) = (segments.max(3), rings.max(1));
    let mut m = TriangleMesh::default();
    let mut normals = Vec::new();
    let ring_dir = |i: u32| {
        let a = 2.0 * PI * i as f64 / ns as f64;
        Vec3::new(0.0, a.cos() as f32, a.sin() as f32)
    };
    // Side: (nr + 1) rings of ns vertices.
    for j in 0..=nr {
        let x = length * j as f32 / nr as f32;
        for i in 0..ns {
            let d = ring_dir(i);
            m.positions.push(Vec3::new(x, 0.0, 0.0) + d * radius);
            normals.push(d);
        }
    }
    for j in 0..nr {
        for i in 0..ns {
            let a = j * ns + i;
            let b = j * ns + (i + 1) % ns;
            let (c, d) = (a + ns, b + ns);
            // Counter-clockwise seen from outside.
            m.indices.push([a, b, d]);
            m.indices.push([a, d, c]);
        }
    }
    // Caps: a centre and a ring each, normals ∓x.
    for (x, n) in [(0.0, -Vec3::X), (length, Vec3::X)] {
        let c = m.positions.len() as u32;
        m.positions.push(Vec3::new(x, 0.0, 0.0));
        normals.push(n);
        for i in 0..ns {
            m.positions
                .push(Vec3::new(x, 0.0, 0.0) + ring_dir(i) * radius);
            normals.push(n);
        }
        for i in 0..ns {
            let (a, b) = (c + 1 + i, c + 1 + (i + 1) % ns);
            if n.x < 0.0 {
                m.indices.push([c, b, a]);
            } else {
                m.indices.push([c, a, b]);
            }
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

/// Reverses every triangle whose winding normal points toward `center` (so that the normals
/// of a mesh star-shaped about `center` point away from it).
fn orient_away_from(m: &mut TriangleMesh, center: Vec3) {
    for t in &mut m.indices {
        let [a, b, c] = t.map(|k| m.positions[k as usize]);
        if (b - a).cross(c - a).dot((a + b + c) / 3.0 - center) < 0.0 {
            t.swap(1, 2);
        }
    }
}

/// A flat-shaded geodesic sphere of `radius` (m) around `center`: the regular icosahedron with
/// each triangle split into four `subdivisions` times (20 · 4^`subdivisions` triangles: 80 for
/// 1), every vertex on the sphere. Closed, welded (each edge shared by two triangles), wound
/// counter-clockwise seen from outside and without vertex normals, so every facet shades flat.
pub fn geodesic_sphere_mesh(center: Vec3, radius: f32, subdivisions: u32) -> TriangleMesh {
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let mut verts: Vec<[f64; 3]> = vec![
        [-1.0, phi, 0.0],
        [1.0, phi, 0.0],
        [-1.0, -phi, 0.0],
        [1.0, -phi, 0.0],
        [0.0, -1.0, phi],
        [0.0, 1.0, phi],
        [0.0, -1.0, -phi],
        [0.0, 1.0, -phi],
        [phi, 0.0, -1.0],
        [phi, 0.0, 1.0],
        [-phi, 0.0, -1.0],
        [-phi, 0.0, 1.0],
    ];
    let unit = |v: [f64; 3]| {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        [v[0] / l, v[1] / l, v[2] / l]
    };
    for v in &mut verts {
        *v = unit(*v);
    }
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoints = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, verts: &mut Vec<[f64; 3]>| -> u32 {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (verts[a as usize], verts[b as usize]);
                verts.push(unit([p[0] + q[0], p[1] + q[1], p[2] + q[2]]));
                verts.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(4 * faces.len());
        for [a, b, c] in faces {
            let (ab, bc, ca) = (
                mid(a, b, &mut verts),
                mid(b, c, &mut verts),
                mid(c, a, &mut verts),
            );
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    let mut m = TriangleMesh {
        positions: verts
            .iter()
            .map(|v| center + Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32) * radius)
            .collect(),
        indices: faces,
        ..TriangleMesh::default()
    };
    orient_away_from(&mut m, center);
    m
}

/// A faceted dome (a low-poly hemisphere) standing on the plane y = `base.y`: an apex at
/// `base + radius · y`, a cap of `cap_facets` triangles around it (the pentagonal cap of
/// `laser-smoke` for 5), then `bands` bands of 2 · `cap_facets` vertices per ring down to the
/// rim on the base plane; open at the bottom.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DomeParams {
    /// Centre of the rim circle (m).
    pub base: Vec3,
    /// Radius of the sphere every vertex lies on (m).
    pub radius: f32,
    /// Triangles around the apex (≥ 3).
    pub cap_facets: u32,
    /// Polar angle of the cap's ring from the apex (degrees, in (0, 90)).
    pub cap_polar_deg: f32,
    /// Bands of quads (split into two triangles) below the cap (≥ 1); the rings below the cap
    /// are spaced evenly in polar angle down to 90°.
    pub bands: u32,
    /// Azimuth of the cap ring's first vertex (degrees from +x toward +z).
    pub azimuth_deg: f32,
}

impl DomeParams {
    /// Unit outward normal of cap facet `k` (the one between cap vertices k and k + 1): it
    /// leans away from the apex by `atan(tan(α/2) / cos(π/n))` (α the cap's polar angle, n
    /// the facet count) toward the azimuth midway between its two ring vertices.
    pub fn cap_normal(&self, k: u32) -> Vec3 {
        let n = self.cap_facets.max(3) as f64;
        let half = (self.cap_polar_deg as f64).to_radians() / 2.0;
        let tilt = (half.tan() / (PI / n).cos()).atan();
        let az = (self.azimuth_deg as f64).to_radians() + PI * (2.0 * k as f64 + 1.0) / n;
        Vec3::new(
            (tilt.sin() * az.cos()) as f32,
            tilt.cos() as f32,
            (tilt.sin() * az.sin()) as f32,
        )
    }
}

/// The dome of `p` as a flat-shaded triangle mesh (no vertex normals, wound counter-clockwise
/// seen from outside): `cap_facets` · (1 + 3 + 4 (`bands` − 1)) triangles, of which the first
/// `cap_facets` are the cap, in the order of [`DomeParams::cap_normal`]. Its boundary is the
/// rim on the base plane.
pub fn faceted_dome_mesh(p: &DomeParams) -> TriangleMesh {
    let n = p.cap_facets.max(3);
    let bands = p.bands.max(1);
    let r = p.radius as f64;
    let a0 = (p.azimuth_deg as f64).to_radians();
    let cap = (p.cap_polar_deg as f64).to_radians();
    let at = |polar: f64, az: f64| {
        let (s, c) = polar.sin_cos();
        p.base
            + Vec3::new(
                (r * s * az.cos()) as f32,
                (r * c) as f32,
                (r * s * az.sin()) as f32,
            )
    };
    let mut m = TriangleMesh::default();
    m.positions.push(p.base + Vec3::new(0.0, p.radius, 0.0));
    for k in 0..n {
        m.positions
            .push(at(cap, a0 + 2.0 * PI * k as f64 / n as f64));
    }
    // Rings below the cap: 2n vertices each, the even ones under the cap's vertices; the last
    // one on the base plane (y exactly base.y).
    for i in 1..=bands {
        let polar = cap + (PI / 2.0 - cap) * i as f64 / bands as f64;
        for k in 0..2 * n {
            let mut q = at(polar, a0 + PI * k as f64 / n as f64);
            if i == bands {
                q.y = p.base.y;
            }
            m.positions.push(q);
        }
    }
    let ring = |i: u32, k: u32| -> u32 {
        if i == 0 {
            1 + k % n
        } else {
            1 + n + (i - 1) * 2 * n + k % (2 * n)
        }
    };
    for k in 0..n {
        m.indices.push([0, ring(0, k), ring(0, k + 1)]);
    }
    for k in 0..n {
        let (a, b) = (ring(0, k), ring(0, k + 1));
        let (q0, q1, q2) = (ring(1, 2 * k), ring(1, 2 * k + 1), ring(1, 2 * k + 2));
        m.indices.extend([[a, q0, q1], [a, q1, b], [b, q1, q2]]);
    }
    for i in 1..bands {
        for k in 0..2 * n {
            let (a, b) = (ring(i, k), ring(i, k + 1));
            let (c, d) = (ring(i + 1, k), ring(i + 1, k + 1));
            m.indices.extend([[a, c, d], [a, d, b]]);
        }
    }
    orient_away_from(&mut m, p.base);
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

    #[test]
    fn geodesic_sphere_is_closed_flat_and_on_the_sphere() {
        let c = Vec3::new(0.1, -0.2, 0.3);
        for (sub, faces) in [(0, 20), (1, 80), (2, 320)] {
            let m = geodesic_sphere_mesh(c, 0.5, sub);
            assert_eq!(m.indices.len(), faces);
            assert_eq!(m.positions.len(), faces / 2 + 2, "Euler: V = F/2 + 2");
            assert!(m.normals.is_none(), "flat-shaded");
            assert!(boundary_edges(&m).is_empty(), "the sphere has a boundary");
            for p in &m.positions {
                assert!(((*p - c).length() - 0.5).abs() < 1e-6);
            }
            for t in &m.indices {
                let [a, b, cc] = t.map(|k| m.positions[k as usize]);
                assert!(geometric_normal(&m, t).dot((a + b + cc) / 3.0 - c) > 0.0);
            }
            // Inscribed: the volume is below the sphere's and grows with subdivision.
            let v = signed_volume(&geodesic_sphere_mesh(Vec3::ZERO, 0.5, sub));
            let sphere = 4.0 / 3.0 * PI * 0.125;
            assert!(v > 0.6 * sphere && v < sphere, "{v}");
        }
    }

    #[test]
    fn dome_has_a_pentagonal_cap_and_its_rim_on_the_base() {
        let p = DomeParams {
            base: Vec3::new(0.0, -1.0, 0.0),
            radius: 0.35,
            cap_facets: 5,
            cap_polar_deg: 40.0,
            bands: 2,
            azimuth_deg: 18.0,
        };
        let m = faceted_dome_mesh(&p);
        assert_eq!(m.indices.len(), 5 * (1 + 3 + 4));
        assert!(m.normals.is_none(), "flat-shaded");
        for q in &m.positions {
            assert!(((*q - p.base).length() - 0.35).abs() < 1e-6);
            assert!(q.y >= p.base.y);
        }
        // The boundary is the rim: 10 edges on the base plane.
        let boundary = boundary_edges(&m);
        assert_eq!(boundary.len(), 10);
        for (a, b) in boundary {
            for v in [a, b] {
                assert_eq!(f32::from_bits(v[1]), -1.0);
            }
        }
        // Every facet faces outward, upward (the dome stands on the base plane); the first
        // five meet at the apex and have the normals cap_normal gives.
        for (i, t) in m.indices.iter().enumerate() {
            let ng = geometric_normal(&m, t);
            let [a, b, c] = t.map(|k| m.positions[k as usize]);
            assert!(ng.dot((a + b + c) / 3.0 - p.base) > 0.0, "triangle {i}");
            assert!(ng.y > -1e-6, "triangle {i} faces down");
            if i < 5 {
                assert!(t.contains(&0), "cap triangle {i} misses the apex");
                let want = p.cap_normal(i as u32);
                assert!(ng.abs_diff_eq(want, 1e-5), "cap {i}: {ng} vs {want}");
            }
        }
        // Tilt atan(tan 20° / cos 36°) = 24.2°; the cap normal of facet 3 is at azimuth 270°.
        let tilt = p.cap_normal(0).y.acos().to_degrees();
        assert!((tilt - 24.22).abs() < 0.01, "{tilt}");
        assert!(p.cap_normal(3).z < -0.4 && p.cap_normal(3).x.abs() < 1e-6);
    }
}
