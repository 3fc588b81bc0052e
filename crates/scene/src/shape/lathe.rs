//! Surfaces of revolution: a profile in the (r, y) half-plane turned about the y axis into a
//! triangle mesh with smooth vertex normals (the cognac glass and its liquid of the built-in
//! scene `cognac-glass`, seed 002 fig. 10).

use super::TriangleMesh;
use caustica_core::{Affine3A, Vec3};
use std::f64::consts::PI;

/// The surface swept by turning `pieces` about the y axis in `segments` steps, then moved by
/// `to_world`. Each piece is a polyline of points `[r, y]` (r ≥ 0, the distance from the axis)
/// that is smooth inside: a vertex's normal is the mean of the normals of the two profile
/// segments meeting there, so an arc sampled at equal steps gets its exact normals inside. A
/// piece's end points take their one segment's normal, and the point where two pieces meet is a
/// crease (its ring is repeated, once with each piece's normal). A point on the axis (r = 0) gets
/// the normal ±y and closes its piece with a fan.
///
/// The surface's front (+normal, the side the triangles wind counter-clockwise on) is to the
/// **right** of the direction of travel along the profile, drawn with r to the right and y up: a
/// closed solid's profile traversed with its interior on the left (e.g. a base from the axis
/// outward, then up the outside) gets outward normals. Point (r, y) at angle φ is
/// (r cos φ, y, r sin φ).
pub fn lathe_mesh(pieces: &[Vec<[f64; 2]>], segments: u32, to_world: &Affine3A) -> TriangleMesh {
    let ns = segments.max(3);
    let mut m = TriangleMesh::default();
    let mut normals = Vec::new();
    let angles: Vec<(f64, f64)> = (0..ns)
        .map(|j| (2.0 * PI * j as f64 / ns as f64).sin_cos())
        .collect();
    for piece in pieces.iter().filter(|p| p.len() >= 2) {
        // The right-hand normal (dy, −dr) of every profile segment.
        let seg: Vec<[f64; 2]> = piece
            .windows(2)
            .map(|w| unit([w[1][1] - w[0][1], -(w[1][0] - w[0][0])]))
            .collect();
        let first = m.positions.len() as u32;
        for (i, &[r, y]) in piece.iter().enumerate() {
            let [mut nr, mut ny] = match (i.checked_sub(1).map(|k| seg[k]), seg.get(i).copied()) {
                (Some(a), Some(b)) => unit([a[0] + b[0], a[1] + b[1]]),
                (Some(a), None) | (None, Some(a)) => a,
                (None, None) => [0.0, 1.0],
            };
            if r == 0.0 {
                (nr, ny) = (0.0, if ny < 0.0 { -1.0 } else { 1.0 });
            }
            for &(s, c) in &angles {
                m.positions
                    .push(Vec3::new((r * c) as f32, y as f32, (r * s) as f32));
                normals.push(Vec3::new((nr * c) as f32, ny as f32, (nr * s) as f32));
            }
        }
        let at = |i: usize, j: u32| first + i as u32 * ns + j % ns;
        for i in 0..piece.len() - 1 {
            for j in 0..ns {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                // ∂p/∂s × ∂p/∂φ = r (y′ cos φ, −r′, y′ sin φ): the right-hand side.
                if piece[i + 1][0] != 0.0 {
                    m.indices.push([a, b, c]);
                }
                if piece[i][0] != 0.0 {
                    m.indices.push([a, c, d]);
                }
            }
        }
    }
    m.normals = Some(normals);
    m.transform(to_world);
    m
}

fn unit([x, y]: [f64; 2]) -> [f64; 2] {
    let l = x.hypot(y);
    if l > 0.0 { [x / l, y / l] } else { [0.0, 1.0] }
}

/// `n + 1` points of the circle of radius `radius` about (0, `center_y`) in the (r, y)
/// half-plane at the angles `from + (to − from) k / n` measured from the downward axis: the point
/// at angle α is (radius sin α, center_y − radius cos α). The last point is computed at `to`
/// exactly, so arcs that share an end share it bit for bit.
pub fn circle_arc(center_y: f64, radius: f64, from: f64, to: f64, n: u32) -> Vec<[f64; 2]> {
    let n = n.max(1);
    (0..=n)
        .map(|k| {
            let a = if k == n {
                to
            } else {
                from + (to - from) * k as f64 / n as f64
            };
            [radius * a.sin(), center_y - radius * a.cos()]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn volume_and_area(m: &TriangleMesh) -> (f64, f64) {
        let mut v = 0.0;
        let mut area = 0.0;
        for (i, t) in m.indices.iter().enumerate() {
            let [a, b, c] = t.map(|k| m.positions[k as usize].as_dvec3());
            v += a.dot(b.cross(c)) / 6.0;
            area += m.triangle_area(i) as f64;
        }
        (v, area)
    }

    #[test]
    fn a_closed_cylinder_has_outward_winding_and_its_volume() {
        // Base from the axis out, up the side, top back to the axis: interior on the left.
        let (r, h) = (0.5, 2.0);
        let pieces = vec![
            vec![[0.0, 0.0], [r, 0.0]],
            vec![[r, 0.0], [r, h]],
            vec![[r, h], [0.0, h]],
        ];
        let m = lathe_mesh(&pieces, 256, &Affine3A::IDENTITY);
        let ns = m.normals.as_ref().unwrap();
        for t in &m.indices {
            let [a, b, c] = t.map(|k| m.positions[k as usize]);
            let face = (b - a).cross(c - a);
            assert!(face.length() > 0.0, "degenerate triangle {t:?}");
            let mean: Vec3 = t.iter().map(|&k| ns[k as usize]).sum();
            assert!(face.normalize().dot(mean.normalize()) > 0.99, "{t:?}");
        }
        let (v, area) = volume_and_area(&m);
        let (ev, ea) = (PI * r * r * h, 2.0 * PI * r * r + 2.0 * PI * r * h);
        assert!((v - ev).abs() < 1e-3 * ev, "{v} vs {ev}");
        assert!((area - ea).abs() < 1e-3 * ea, "{area} vs {ea}");
        // Fans at the poles: 256 triangles per cap, 512 on the side.
        assert_eq!(m.indices.len(), 4 * 256);
    }

    #[test]
    fn a_sphere_from_arcs_gets_its_radial_normals_and_volume() {
        let (r, yc) = (0.3, 1.0);
        // From the bottom pole up to the top pole: increasing α travels with the inside on the
        // left, so the normals point outward; two pieces meeting at the equator.
        let lower = circle_arc(yc, r, 0.0, PI / 2.0, 32);
        let upper = circle_arc(yc, r, PI / 2.0, PI, 32);
        assert_eq!(lower.last(), upper.first());
        let m = lathe_mesh(&[lower, upper], 128, &Affine3A::IDENTITY);
        let ns = m.normals.as_ref().unwrap();
        let c = Vec3::new(0.0, yc as f32, 0.0);
        for (p, n) in m.positions.iter().zip(ns) {
            assert!(((*p - c).length() - r as f32).abs() < 1e-5);
            // Inside a piece exact; at the ends half a step (π/128) off at most.
            assert!((*p - c).normalize().dot(*n) > (PI / 128.0).cos() as f32 - 1e-5);
        }
        let (v, _) = volume_and_area(&m);
        let ev = 4.0 / 3.0 * PI * r.powi(3);
        assert!((v - ev).abs() < 3e-3 * ev, "{v} vs {ev}");
    }

    #[test]
    fn reversing_a_profile_reverses_the_normals() {
        let p = circle_arc(0.0, 1.0, 0.3, 1.2, 8);
        let mut q = p.clone();
        q.reverse();
        let a = lathe_mesh(&[p], 16, &Affine3A::IDENTITY);
        let b = lathe_mesh(&[q], 16, &Affine3A::IDENTITY);
        let (na, nb) = (a.normals.unwrap(), b.normals.unwrap());
        // b's ring k is a's ring 8 − k.
        for k in 0..9 {
            for j in 0..16 {
                let (x, y) = (na[k * 16 + j], nb[(8 - k) * 16 + j]);
                assert!(x.abs_diff_eq(-y, 1e-6), "{x} {y}");
            }
        }
    }
}
