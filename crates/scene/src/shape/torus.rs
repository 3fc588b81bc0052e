//! A torus as a closed triangle mesh with smooth vertex normals: the diffuse torus inside the
//! glass ball of the built-in scene `torus-glass` (seed 001 figs. 4.2 and 5.4, the "embedded
//! torus" of Hachisuka et al. 2008).

use super::TriangleMesh;
use caustica_core::{Affine3A, Vec2, Vec3};
use std::f64::consts::PI;

/// The torus of major radius `major` (centre of the tube to the axis) and minor radius `minor`
/// (the tube's), around the y axis through the origin, then moved by `to_world`: `segments`
/// steps around the axis × `rings` steps around the tube, two triangles per step, outward
/// winding and analytic (smooth) vertex normals, uv = (angle around the axis, angle around the
/// tube) / 2π. The seam is closed by index, so the mesh is watertight. Its area tends to
/// 4π² `major` `minor` (slightly less: the flat triangles cut the tube's curves).
pub fn torus_mesh(
    major: f32,
    minor: f32,
    segments: u32,
    rings: u32,
    to_world: &Affine3A,
) -> TriangleMesh {
    let (ns, nr) = (segments.max(3), rings.max(3));
    let (big, small) = (major as f64, minor as f64);
    let mut m = TriangleMesh::default();
    let mut normals = Vec::with_capacity((ns * nr) as usize);
    let mut uvs = Vec::with_capacity((ns * nr) as usize);
    for i in 0..ns {
        let phi = 2.0 * PI * i as f64 / ns as f64;
        let (sp, cp) = phi.sin_cos();
        for j in 0..nr {
            let theta = 2.0 * PI * j as f64 / nr as f64;
            let (st, ct) = theta.sin_cos();
            // Outward normal of the tube at (φ, θ): radial in the (axis-out, y) plane.
            let n = Vec3::new((ct * cp) as f32, st as f32, (ct * sp) as f32);
            let r = big + small * ct;
            m.positions.push(Vec3::new(
                (r * cp) as f32,
                (small * st) as f32,
                (r * sp) as f32,
            ));
            normals.push(n);
            uvs.push(Vec2::new(i as f32 / ns as f32, j as f32 / nr as f32));
        }
    }
    let at = |i: u32, j: u32| (i % ns) * nr + (j % nr);
    for i in 0..ns {
        for j in 0..nr {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            // ∂p/∂θ × ∂p/∂φ points outward, so (a, d, c) then (a, c, b) wind outward.
            m.indices.push([a, d, c]);
            m.indices.push([a, c, b]);
        }
    }
    m.normals = Some(normals);
    m.uvs = Some(uvs);
    m.transform(to_world);
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(m: &TriangleMesh) -> f64 {
        (0..m.indices.len())
            .map(|i| m.triangle_area(i) as f64)
            .sum()
    }

    #[test]
    fn area_tends_to_four_pi_squared_big_r_small_r() {
        let (big, small) = (0.25f32, 0.08f32);
        let exact = 4.0 * PI * PI * big as f64 * small as f64;
        let coarse = area(&torus_mesh(big, small, 16, 8, &Affine3A::IDENTITY));
        let fine = area(&torus_mesh(big, small, 128, 48, &Affine3A::IDENTITY));
        assert!(coarse < fine && fine < exact, "{coarse} {fine} {exact}");
        assert!((fine - exact).abs() < 2e-3 * exact, "{fine} vs {exact}");
        // Moved and scaled by 2: four times the area.
        let t = Affine3A::from_translation(Vec3::new(1.0, 2.0, 3.0))
            * Affine3A::from_axis_angle(Vec3::X, 1.0)
            * Affine3A::from_scale(Vec3::splat(2.0));
        let scaled = area(&torus_mesh(big, small, 128, 48, &t));
        assert!((scaled - 4.0 * fine).abs() < 1e-4 * scaled);
    }

    #[test]
    fn winding_agrees_with_the_outward_normals_and_the_volume_is_two_pi_squared_big_r_small_r2() {
        let (big, small) = (0.25f32, 0.08f32);
        let m = torus_mesh(big, small, 96, 32, &Affine3A::IDENTITY);
        let ns = m.normals.as_ref().unwrap();
        let mut volume = 0.0f64;
        for t in &m.indices {
            let [a, b, c] = t.map(|k| m.positions[k as usize]);
            let face = (b - a).cross(c - a);
            let mean = t.iter().map(|&k| ns[k as usize]).sum::<Vec3>();
            assert!(face.dot(mean) > 0.0, "triangle {t:?} winds inward");
            volume += a.as_dvec3().dot(b.as_dvec3().cross(c.as_dvec3())) / 6.0;
        }
        let exact = 2.0 * PI * PI * big as f64 * (small as f64).powi(2);
        assert!((volume - exact).abs() < 1e-2 * exact, "{volume} vs {exact}");
        // Every vertex lies on the torus and its normal points from the tube's centre to it.
        for (p, n) in m.positions.iter().zip(ns) {
            let ring = Vec3::new(p.x, 0.0, p.z).normalize() * big;
            let off = *p - ring;
            assert!((off.length() - small).abs() < 1e-6);
            assert!(off.normalize().abs_diff_eq(*n, 1e-5));
        }
    }

    #[test]
    fn every_edge_is_shared_by_two_triangles_in_opposite_directions() {
        let m = torus_mesh(1.0, 0.3, 12, 5, &Affine3A::IDENTITY);
        let mut edges = std::collections::HashMap::new();
        for t in &m.indices {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &n) in &edges {
            assert_eq!(n, 1);
            assert_eq!(edges.get(&(b, a)), Some(&1), "open edge {a}-{b}");
        }
        assert_eq!(m.indices.len(), 2 * 12 * 5);
    }
}
