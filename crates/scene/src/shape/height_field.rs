//! Height fields y = h(x, z) over a rectangle as open triangle meshes with their analytic
//! normals (the wavy water surface of the built-in scene `swimming-pool`, seed 002 fig. 11).

use super::TriangleMesh;
use caustica_core::Vec3;

/// The height field over `x ∈ [x0, x1]`, `z ∈ [z0, z1]` on a grid of `cells_x × cells_z` cells:
/// `surface(x, z)` returns the height h and its gradient (∂h/∂x, ∂h/∂z), evaluated in double
/// precision at the `(cells_x + 1) × (cells_z + 1)` vertices. Vertex normals are the unit
/// upward normals (−∂h/∂x, 1, −∂h/∂z)/|·| (shading normals are their Phong interpolation);
/// triangles wind counter-clockwise seen from above, so the geometric normals point up (+y). The
/// boundary is the rectangle's perimeter, its vertices exactly at x0, x1, z0 and z1.
pub fn height_field_mesh(
    (x0, x1): (f64, f64),
    (z0, z1): (f64, f64),
    (cells_x, cells_z): (u32, u32),
    surface: impl Fn(f64, f64) -> (f64, [f64; 2]),
) -> TriangleMesh {
    let (nx, nz) = (cells_x.max(1), cells_z.max(1));
    let at = |a: f64, b: f64, k: u32, n: u32| {
        if k == n {
            b
        } else {
            a + (b - a) * k as f64 / n as f64
        }
    };
    let mut m = TriangleMesh::default();
    let mut normals = Vec::new();
    for j in 0..=nz {
        let z = at(z0, z1, j, nz);
        for i in 0..=nx {
            let x = at(x0, x1, i, nx);
            let (h, [hx, hz]) = surface(x, z);
            m.positions.push(Vec3::new(x as f32, h as f32, z as f32));
            let l = (1.0 + hx * hx + hz * hz).sqrt();
            // `0.0 - h` rather than `-h`: a zero slope gives a +0 component, not −0.
            normals.push(Vec3::new(
                ((0.0 - hx) / l) as f32,
                (1.0 / l) as f32,
                ((0.0 - hz) / l) as f32,
            ));
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tilted_plane_has_its_normal_and_upward_winding() {
        // h = 0.5 + 0.2 x − 0.1 z.
        let m = height_field_mesh((-1.0, 2.0), (0.0, 1.0), (6, 4), |x, z| {
            (0.5 + 0.2 * x - 0.1 * z, [0.2, -0.1])
        });
        assert_eq!(m.positions.len(), 7 * 5);
        assert_eq!(m.indices.len(), 2 * 6 * 4);
        let want = Vec3::new(-0.2, 1.0, 0.1).normalize();
        for n in m.normals.as_ref().unwrap() {
            assert!(n.abs_diff_eq(want, 1e-6));
        }
        for t in &m.indices {
            let [a, b, c] = t.map(|k| m.positions[k as usize]);
            assert!((b - a).cross(c - a).normalize().abs_diff_eq(want, 1e-5));
        }
        // Corners exactly on the rectangle.
        assert_eq!(m.positions[0], Vec3::new(-1.0, 0.5 - 0.2, 0.0));
        assert_eq!(m.positions[34].x, 2.0);
        assert_eq!(m.positions[34].z, 1.0);
    }

    #[test]
    fn the_area_of_a_sine_sheet_is_its_arc_length_times_its_width() {
        // h = 0.1 sin(2π x) over one wavelength, 1 m wide: area = ∫ √(1 + h′²) dx.
        let k = 2.0 * std::f64::consts::PI;
        let m = height_field_mesh((0.0, 1.0), (0.0, 1.0), (256, 2), |x, _| {
            (0.1 * (k * x).sin(), [0.1 * k * (k * x).cos(), 0.0])
        });
        let area: f64 = (0..m.indices.len())
            .map(|i| m.triangle_area(i) as f64)
            .sum();
        let n = 100_000;
        let exact: f64 = (0..n)
            .map(|i| {
                let x = (i as f64 + 0.5) / n as f64;
                (1.0 + (0.1 * k * (k * x).cos()).powi(2)).sqrt() / n as f64
            })
            .sum();
        assert!((area - exact).abs() < 1e-4 * exact, "{area} vs {exact}");
    }
}
