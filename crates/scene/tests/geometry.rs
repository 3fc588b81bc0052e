//! Geometry queries: BVH against brute force, analytic hits, orientation and degenerate input.

use caustica_core::sampling::Pcg32;
use caustica_core::{Affine3A, PI, Ray, Vec2, Vec3};
use caustica_scene::bvh::BvhWidth;
use caustica_scene::geometry::Geometry;
use caustica_scene::intersection::NONE;
use caustica_scene::shape::mesh::intersect_triangle;
use caustica_scene::shape::{Disk, Shape, ShapeGeometry, Sphere, TriangleMesh};

/// Every BVH width this CPU runs: the fallback (four) always, eight where AVX2 is present.
fn widths() -> Vec<BvhWidth> {
    [BvhWidth::Four, BvhWidth::Eight]
        .into_iter()
        .filter(|w| w.supported())
        .collect()
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

fn rand_vec(rng: &mut Pcg32, lo: f32, hi: f32) -> Vec3 {
    Vec3::new(
        lo + (hi - lo) * rng.next_f32(),
        lo + (hi - lo) * rng.next_f32(),
        lo + (hi - lo) * rng.next_f32(),
    )
}

fn rand_dir(rng: &mut Pcg32) -> Vec3 {
    let z = 1.0 - 2.0 * rng.next_f32();
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * rng.next_f32();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Random triangle soup in two meshes, plus spheres and disks.
fn random_scene(rng: &mut Pcg32) -> Vec<Shape> {
    let mut shapes = Vec::new();
    for _ in 0..2 {
        let mut m = TriangleMesh::default();
        for t in 0..400u32 {
            let c = rand_vec(rng, -10.0, 10.0);
            let size = 0.2 + 2.0 * rng.next_f32();
            for _ in 0..3 {
                m.positions.push(c + rand_vec(rng, -size, size));
            }
            m.indices.push([3 * t, 3 * t + 1, 3 * t + 2]);
        }
        shapes.push(Shape::new(ShapeGeometry::Mesh(m), 0));
    }
    for _ in 0..25 {
        let s = Sphere {
            center: rand_vec(rng, -10.0, 10.0),
            radius: 0.1 + 1.5 * rng.next_f32(),
        };
        shapes.push(Shape::new(ShapeGeometry::Sphere(s), 1));
    }
    for _ in 0..25 {
        let d = Disk {
            center: rand_vec(rng, -10.0, 10.0),
            normal: rand_dir(rng),
            radius: 0.1 + 1.5 * rng.next_f32(),
        };
        shapes.push(Shape::new(ShapeGeometry::Disk(d), 2));
    }
    shapes
}

/// Closest (t, shape, prim) by testing every primitive.
fn brute_force(shapes: &[Shape], ray: &Ray) -> Option<(f32, u32, u32)> {
    let mut best: Option<(f32, u32, u32)> = None;
    let mut t_max = ray.t_max;
    for (s, shape) in shapes.iter().enumerate() {
        let mut consider = |t: Option<f32>, p: u32| {
            if let Some(t) = t
                && t < t_max
            {
                t_max = t;
                best = Some((t, s as u32, p));
            }
        };
        match &shape.geometry {
            ShapeGeometry::Mesh(m) => {
                for (i, tri) in m.indices.iter().enumerate() {
                    let [a, b, c] = tri.map(|k| m.positions[k as usize]);
                    let h = intersect_triangle(ray.o, ray.d, ray.t_max, a, b, c);
                    consider(h.map(|h| h.0), i as u32);
                }
            }
            ShapeGeometry::Sphere(sp) => consider(sp.intersect(ray.o, ray.d, ray.t_max), 0),
            ShapeGeometry::Disk(dk) => consider(dk.intersect(ray.o, ray.d, ray.t_max), 0),
        }
    }
    best
}

#[test]
fn bvh_matches_brute_force_on_random_rays() {
    let mut rng = Pcg32::new(7, 1);
    let shapes = random_scene(&mut rng);
    for width in widths() {
        random_rays_match_brute_force(&shapes, width, rng.clone());
    }
}

fn random_rays_match_brute_force(shapes: &[Shape], width: BvhWidth, mut rng: Pcg32) {
    let shapes = shapes.to_vec();
    let geo = Geometry::build_with_width(shapes.clone(), width);
    assert_eq!(geo.bvh.width(), width);
    assert_eq!(geo.primitive_count(), 800 + 50);
    let mut hits = 0;
    let mut occluded = 0;
    for i in 0..6000 {
        let o = rand_vec(&mut rng, -13.0, 13.0);
        let d = rand_dir(&mut rng);
        let t_max = if i % 3 == 0 {
            f32::INFINITY
        } else {
            0.5 + 15.0 * rng.next_f32()
        };
        let ray = Ray::with_t_max(o, d, t_max);
        let expect = brute_force(&shapes, &ray);
        let got = geo.intersect(&ray);
        match (expect, got) {
            (None, None) => {}
            (Some((t, s, p)), Some(si)) => {
                hits += 1;
                assert!(
                    (t - si.t).abs() <= 1e-5 * t.max(1.0),
                    "ray {i}: t {t} vs {}",
                    si.t
                );
                assert_eq!((s, p), (si.shape, si.prim), "ray {i}");
                assert_eq!(si.material, shapes[s as usize].material);
                assert!(close(si.p, ray.at(t), 1e-3 * t.max(1.0)), "ray {i}");
                assert!((si.ng.length() - 1.0).abs() < 1e-4);
                assert!(si.t > 0.0 && si.t < t_max);
            }
            (e, g) => panic!("ray {i}: brute force {e:?}, BVH {:?}", g.map(|s| s.t)),
        }
        let occ = geo.occluded(&ray);
        assert_eq!(occ, expect.is_some(), "ray {i} occlusion");
        occluded += occ as u32;
    }
    // The test is meaningful only if a fair share of rays hit something and some miss.
    assert!(hits > 1000 && hits < 5900, "hits {hits}");
    assert!(occluded > 1000);
}

#[test]
fn large_mesh_bvh_matches_brute_force() {
    // Enough primitives for a deep, many-level wide BVH.
    let n = 40_000u32;
    let mut rng = Pcg32::new(11, 3);
    let mut m = TriangleMesh::default();
    for t in 0..n {
        let c = rand_vec(&mut rng, -20.0, 20.0);
        for _ in 0..3 {
            m.positions.push(c + rand_vec(&mut rng, -0.5, 0.5));
        }
        m.indices.push([3 * t, 3 * t + 1, 3 * t + 2]);
    }
    let shapes = vec![Shape::new(ShapeGeometry::Mesh(m), 0)];
    for width in widths() {
        large_mesh_matches(&shapes, n, width, rng.clone());
    }
}

fn large_mesh_matches(shapes: &[Shape], n: u32, width: BvhWidth, mut rng: Pcg32) {
    let geo = Geometry::build_with_width(shapes.to_vec(), width);
    assert_eq!(geo.primitive_count(), n as usize);
    // Every primitive appears exactly once in the BVH order.
    let mut seen = vec![false; n as usize];
    for &k in geo.bvh.order() {
        assert!(!seen[k as usize]);
        seen[k as usize] = true;
    }
    assert!(seen.iter().all(|&s| s));
    for i in 0..300 {
        let ray = Ray::new(rand_vec(&mut rng, -25.0, 25.0), rand_dir(&mut rng));
        let e = brute_force(shapes, &ray).map(|h| (h.1, h.2));
        let g = geo.intersect(&ray).map(|s| (s.shape, s.prim));
        assert_eq!(e, g, "{width:?}, ray {i}");
        assert_eq!(geo.occluded(&ray), e.is_some());
    }
}

#[test]
fn build_is_independent_of_thread_count() {
    // Renders must be bit-identical whatever the thread count, so the tree must be too.
    let n = 30_000u32;
    let mut rng = Pcg32::new(3, 7);
    let mut m = TriangleMesh::default();
    for t in 0..n {
        let c = rand_vec(&mut rng, -20.0, 20.0);
        for _ in 0..3 {
            m.positions.push(c + rand_vec(&mut rng, -0.5, 0.5));
        }
        m.indices.push([3 * t, 3 * t + 1, 3 * t + 2]);
    }
    let shapes = vec![Shape::new(ShapeGeometry::Mesh(m), 0)];
    let build = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool")
            .install(|| {
                widths()
                    .into_iter()
                    .map(|w| Geometry::build_with_width(shapes.clone(), w).bvh)
                    .collect::<Vec<_>>()
            })
    };
    let (a, b, c) = (build(1), build(2), build(4));
    assert!(a == b && a == c);
}

#[test]
fn coincident_triangles_match_brute_force() {
    // Thousands of identical triangles: every bound and Morton code ties, the worst case for the
    // build's tree shape and the traversal stack.
    let n = 5000u32;
    let mut m = TriangleMesh::default();
    for t in 0..n {
        m.positions.extend([
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ]);
        m.indices.push([3 * t, 3 * t + 1, 3 * t + 2]);
    }
    let shapes = vec![Shape::new(ShapeGeometry::Mesh(m), 0)];
    for width in widths() {
        coincident_match(&shapes, width);
    }
}

fn coincident_match(shapes: &[Shape], width: BvhWidth) {
    let geo = Geometry::build_with_width(shapes.to_vec(), width);
    let mut rng = Pcg32::new(5, 9);
    let mut hits = 0;
    for i in 0..500 {
        let o = Vec3::new(0.0, 0.0, 3.0) + rand_vec(&mut rng, -1.0, 1.0);
        let d = (rand_vec(&mut rng, -1.2, 1.2).with_z(0.0) - o).normalize();
        let ray = Ray::new(o, d);
        let e = brute_force(shapes, &ray).map(|h| h.0);
        let g = geo.hit_distance(&ray);
        match (e, g) {
            (Some(a), Some(b)) => assert!((a - b).abs() <= 1e-5 * a, "ray {i}: {a} vs {b}"),
            (None, None) => {}
            _ => panic!("ray {i}: brute force {e:?}, bvh {g:?}"),
        }
        assert_eq!(geo.occluded(&ray), e.is_some(), "ray {i}");
        hits += e.is_some() as u32;
    }
    assert!(hits > 100 && hits < 490, "hits {hits}");
}

#[test]
fn sphere_hit_from_outside() {
    let geo = Geometry::build(vec![Shape::new(
        ShapeGeometry::Sphere(Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        }),
        3,
    )]);
    let si = geo
        .intersect(&Ray::new(Vec3::new(5.0, 0.0, 0.0), -Vec3::X))
        .unwrap();
    assert!((si.t - 4.0).abs() < 1e-5);
    assert!(close(si.p, Vec3::X, 1e-6));
    assert!(close(si.ng, Vec3::X, 1e-6));
    assert!(close(si.ns, Vec3::X, 1e-6));
    // φ = 0, θ = π/2.
    assert!(close(si.uv.extend(0.0), Vec3::new(0.0, 0.5, 0.0), 1e-6));
    assert!(close(si.dpdu, Vec3::new(0.0, 2.0 * PI, 0.0), 1e-5));
    assert!(close(si.dpdv, Vec3::new(0.0, 0.0, -PI), 1e-5));
    assert_eq!(si.material, 3);
    assert_eq!(si.light, NONE);
    assert!(geo.triangle_vertices(&si).is_none());
    // Hit at (0, 1, 0): φ = π/2 → u = 1/4.
    let si = geo
        .intersect(&Ray::new(Vec3::new(0.0, 3.0, 0.0), -Vec3::Y))
        .unwrap();
    assert!((si.uv.x - 0.25).abs() < 1e-6 && (si.uv.y - 0.5).abs() < 1e-6);
    // Missing ray and ray pointing away.
    assert!(
        geo.intersect(&Ray::new(Vec3::new(5.0, 1.01, 0.0), -Vec3::X))
            .is_none()
    );
    assert!(
        geo.intersect(&Ray::new(Vec3::new(5.0, 0.0, 0.0), Vec3::X))
            .is_none()
    );
    // t_max before the sphere.
    assert!(!geo.occluded(&Ray::with_t_max(Vec3::new(5.0, 0.0, 0.0), -Vec3::X, 3.9)));
    assert!(geo.occluded(&Ray::with_t_max(Vec3::new(5.0, 0.0, 0.0), -Vec3::X, 4.1)));
}

#[test]
fn sphere_hit_from_inside_and_far_away() {
    let c = Vec3::new(1.0, 2.0, 3.0);
    let geo = Geometry::build(vec![Shape::new(
        ShapeGeometry::Sphere(Sphere {
            center: c,
            radius: 2.0,
        }),
        0,
    )]);
    let d = Vec3::new(1.0, -2.0, 2.0) / 3.0;
    let si = geo.intersect(&Ray::new(c, d)).unwrap();
    assert!((si.t - 2.0).abs() < 1e-5);
    // Outward normal even though the ray comes from inside.
    assert!(close(si.ng, d, 1e-5));
    // Off-centre inside: o = c + (1,0,0), d = +x → exit at c + (2,0,0), t = 1.
    let si = geo.intersect(&Ray::new(c + Vec3::X, Vec3::X)).unwrap();
    assert!((si.t - 1.0).abs() < 1e-5);
    // Numerically stable far hit: unit sphere 1000 m away, grazing ray near the silhouette.
    let geo = Geometry::build(vec![Shape::new(
        ShapeGeometry::Sphere(Sphere {
            center: Vec3::new(1000.0, 0.0, 0.0),
            radius: 1.0,
        }),
        0,
    )]);
    let si = geo.intersect(&Ray::new(Vec3::ZERO, Vec3::X)).unwrap();
    assert!((si.t - 999.0).abs() < 1e-3, "t {}", si.t);
    // Offset 0.6 in y: t = 1000 − sqrt(1 − 0.36) = 999.2.
    let si = geo
        .intersect(&Ray::new(Vec3::new(0.0, 0.6, 0.0), Vec3::X))
        .unwrap();
    assert!((si.t - 999.2).abs() < 2e-3, "t {}", si.t);
    assert!(close(si.ng, Vec3::new(-0.8, 0.6, 0.0), 1e-3));
}

#[test]
fn disk_hits_inside_radius_only() {
    let shape = Shape::new(
        ShapeGeometry::Disk(Disk {
            center: Vec3::new(0.0, 0.0, 2.0),
            normal: Vec3::Z * 3.0, // not unit: the build normalises
            radius: 1.0,
        }),
        0,
    );
    let geo = Geometry::build(vec![shape]);
    let si = geo
        .intersect(&Ray::new(Vec3::new(0.5, 0.0, 0.0), Vec3::Z))
        .unwrap();
    assert!((si.t - 2.0).abs() < 1e-6);
    assert!(close(si.p, Vec3::new(0.5, 0.0, 2.0), 1e-6));
    assert!(close(si.ng, Vec3::Z, 1e-6));
    // Polar uv: radius fraction 0.5; angle consistent with the tangent dpdu.
    assert!((si.uv.x - 0.5).abs() < 1e-6);
    let radial = si.dpdu.normalize();
    assert!(close(radial, Vec3::X, 1e-5), "dpdu {:?}", si.dpdu);
    assert!(si.dpdv.dot(Vec3::Z).abs() < 1e-6 && si.dpdv.length() > 0.0);
    assert!(si.dpdu.cross(si.dpdv).dot(Vec3::Z) > 0.0);
    // From above the normal is NOT flipped toward the ray.
    let si = geo
        .intersect(&Ray::new(Vec3::new(0.0, 0.3, 5.0), -Vec3::Z))
        .unwrap();
    assert!((si.t - 3.0).abs() < 1e-6 && close(si.ng, Vec3::Z, 1e-6));
    // Centre hit has a usable tangent frame.
    let si = geo.intersect(&Ray::new(Vec3::ZERO, Vec3::Z)).unwrap();
    assert!(si.dpdu.cross(si.dpdv).length() > 0.0);
    // Outside the radius and parallel to the plane: misses.
    assert!(
        geo.intersect(&Ray::new(Vec3::new(1.01, 0.0, 0.0), Vec3::Z))
            .is_none()
    );
    assert!(
        geo.intersect(&Ray::new(Vec3::new(-5.0, 0.0, 2.0), Vec3::X))
            .is_none()
    );
}

#[test]
fn flip_normals_reverses_ng_and_ns() {
    let rect = TriangleMesh::rectangle(&Affine3A::IDENTITY);
    let sphere = Sphere {
        center: Vec3::new(0.0, 0.0, 10.0),
        radius: 1.0,
    };
    for flip in [false, true] {
        let mut a = Shape::new(ShapeGeometry::Mesh(rect.clone()), 0);
        let mut b = Shape::new(ShapeGeometry::Sphere(sphere), 1);
        a.flip_normals = flip;
        b.flip_normals = flip;
        let sign = if flip { -1.0 } else { 1.0 };
        let geo = Geometry::build(vec![a, b]);
        let si = geo
            .intersect(&Ray::new(Vec3::new(0.2, 0.1, 1.0), -Vec3::Z))
            .unwrap();
        assert!(close(si.ng, Vec3::Z * sign, 1e-6));
        assert!(close(si.ns, Vec3::Z * sign, 1e-6));
        // The rectangle's uvs span [0,1]² over [−1,1]²: uv = (0.6, 0.55), dpdu = (2,0,0).
        assert!(close(si.uv.extend(0.0), Vec3::new(0.6, 0.55, 0.0), 1e-5));
        assert!(close(si.dpdu, Vec3::new(2.0, 0.0, 0.0), 1e-5));
        assert!(close(si.dpdv, Vec3::new(0.0, 2.0, 0.0), 1e-5));
        let tv = geo
            .triangle_vertices(&si)
            .expect("mesh hit has its vertices");
        assert!(tv.p.contains(&Vec3::new(-1.0, -1.0, 0.0)));
        let si = geo
            .intersect(&Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::Z))
            .unwrap();
        assert_eq!(si.shape, 1);
        assert!(close(si.ng, -Vec3::Z * sign, 1e-6));
    }
}

#[test]
fn phong_shading_normal_matches_hand_computation() {
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let mesh = TriangleMesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        normals: Some(vec![Vec3::Z, Vec3::new(h, 0.0, h), Vec3::new(0.0, h, h)]),
        uvs: None,
        indices: vec![[0, 1, 2]],
    };
    let geo = Geometry::build(vec![Shape::new(ShapeGeometry::Mesh(mesh.clone()), 0)]);
    let si = geo
        .intersect(&Ray::new(Vec3::new(0.25, 0.25, 1.0), -Vec3::Z))
        .unwrap();
    // b = (0.5, 0.25, 0.25): n = (0.25/√2, 0.25/√2, 0.5 + 0.5/√2) normalised.
    let expect = Vec3::new(0.198_757_4, 0.198_757_4, 0.959_682_9);
    assert!(close(si.ns, expect, 1e-5), "ns {:?}", si.ns);
    assert!(close(si.ng, Vec3::Z, 1e-6));
    assert!(close(si.bary.extend(0.0), Vec3::new(0.25, 0.25, 0.0), 1e-6));
    // Without uvs: uv = barycentrics, dpdu = e1, dpdv = e2.
    assert!(close(si.uv.extend(0.0), Vec3::new(0.25, 0.25, 0.0), 1e-6));
    assert!(close(si.dpdu, Vec3::X, 1e-6) && close(si.dpdv, Vec3::Y, 1e-6));
    assert_eq!(
        geo.triangle_vertices(&si).unwrap().n.unwrap()[1],
        Vec3::new(h, 0.0, h)
    );
    // Vertex normals pointing to the other side get flipped into ng's hemisphere.
    let mut inv = mesh;
    inv.normals = Some(vec![-Vec3::Z; 3]);
    let geo = Geometry::build(vec![Shape::new(ShapeGeometry::Mesh(inv), 0)]);
    let si = geo
        .intersect(&Ray::new(Vec3::new(0.25, 0.25, -1.0), Vec3::Z))
        .unwrap();
    assert!(close(si.ns, Vec3::Z, 1e-6) && close(si.ng, Vec3::Z, 1e-6));
}

#[test]
fn degenerate_uvs_fall_back_to_a_frame() {
    let mesh = TriangleMesh {
        positions: vec![Vec3::ZERO, Vec3::Y, Vec3::Z],
        normals: None,
        uvs: Some(vec![Vec2::ZERO; 3]),
        indices: vec![[0, 1, 2]],
    };
    let geo = Geometry::build(vec![Shape::new(ShapeGeometry::Mesh(mesh), 0)]);
    let si = geo
        .intersect(&Ray::new(Vec3::new(1.0, 0.2, 0.2), -Vec3::X))
        .unwrap();
    assert!(close(si.ng, Vec3::X, 1e-6));
    assert!(si.dpdu.dot(si.ng).abs() < 1e-6 && si.dpdv.dot(si.ng).abs() < 1e-6);
    assert!(si.dpdu.cross(si.dpdv).length() > 0.5);
    assert!(si.shading_frame().n.dot(Vec3::X) > 0.999);
}

#[test]
fn empty_and_degenerate_inputs() {
    let geo = Geometry::build(Vec::new());
    let ray = Ray::new(Vec3::ZERO, Vec3::X);
    assert!(geo.intersect(&ray).is_none());
    assert!(!geo.occluded(&ray));
    assert!(geo.bounds().is_empty());

    // Ray parallel to a triangle, in its plane and above it; triangle behind the origin.
    let tri = TriangleMesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        normals: None,
        uvs: None,
        indices: vec![[0, 1, 2]],
    };
    let geo = Geometry::build(vec![Shape::new(ShapeGeometry::Mesh(tri), 0)]);
    for ray in [
        Ray::new(Vec3::new(-1.0, 0.2, 0.0), Vec3::X),
        Ray::new(Vec3::new(-1.0, 0.2, 0.5), Vec3::X),
        Ray::new(
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0).normalize(),
        ),
        Ray::new(Vec3::new(0.2, 0.2, 1.0), Vec3::Z),
        // Origin exactly on the triangle: t = 0 is not a hit.
        Ray::new(Vec3::new(0.2, 0.2, 0.0), Vec3::Z),
        Ray::new(Vec3::new(0.2, 0.2, 0.0), -Vec3::Z),
    ] {
        assert!(geo.intersect(&ray).is_none(), "{ray:?}");
        assert!(!geo.occluded(&ray), "{ray:?}");
    }

    // Tilted triangle, rays lying in its plane (rounding makes the projection non-degenerate).
    let mut rng = Pcg32::new(3, 3);
    for _ in 0..1000 {
        let p = [
            rand_vec(&mut rng, -1.0, 1.0),
            rand_vec(&mut rng, -1.0, 1.0),
            rand_vec(&mut rng, -1.0, 1.0),
        ];
        let (a, b) = (rng.next_f32() * 0.5, rng.next_f32() * 0.5);
        let inside = p[0] * (1.0 - a - b) + p[1] * a + p[2] * b;
        let o = p[0] - (inside - p[0]) * 2.0;
        let d = (inside - o).normalize();
        if let Some((t, _, _)) = intersect_triangle(o, d, f32::INFINITY, p[0], p[1], p[2]) {
            // Allowed (grazing hit), but then at a point of the triangle's segment on the ray.
            let q = o + d * t;
            let seg = (inside - o).length();
            assert!(t > 0.0 && t < 4.0 * seg, "t {t} seg {seg} q {q:?}");
        }
    }

    // Bad indices, NaN vertices, zero-area triangles and invalid analytic shapes: no panic,
    // and the valid triangle is still found.
    let bad = TriangleMesh {
        positions: vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::new(f32::NAN, 0.0, 0.0),
            Vec3::X * 2.0,
        ],
        normals: Some(vec![Vec3::Z]), // wrong length: ignored
        uvs: None,
        indices: vec![[0, 1, 9], [0, 1, 3], [0, 1, 4], [0, 1, 2]],
    };
    let geo = Geometry::build(vec![
        Shape::new(ShapeGeometry::Mesh(bad), 0),
        Shape::new(
            ShapeGeometry::Sphere(Sphere {
                center: Vec3::ZERO,
                radius: -1.0,
            }),
            0,
        ),
        Shape::new(
            ShapeGeometry::Disk(Disk {
                center: Vec3::ZERO,
                normal: Vec3::ZERO,
                radius: 1.0,
            }),
            0,
        ),
    ]);
    let si = geo
        .intersect(&Ray::new(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z))
        .unwrap();
    assert_eq!((si.shape, si.prim), (0, 3));
    assert!(close(si.ns, Vec3::Z, 1e-6));
    // Many identical triangles (all centroids equal) still build a valid tree.
    let same = TriangleMesh {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        indices: vec![[0, 1, 2]; 100],
        ..Default::default()
    };
    let geo = Geometry::build(vec![Shape::new(ShapeGeometry::Mesh(same), 0)]);
    assert!(geo.occluded(&Ray::new(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z)));
}

/// A closed, consistently outward-wound tessellated sphere (`2·n·(n/2 − 1)` triangles).
fn closed_sphere(n: u32) -> TriangleMesh {
    let nt = n / 2;
    let mut m = TriangleMesh::default();
    for j in 0..=nt {
        let theta = PI * j as f32 / nt as f32;
        for i in 0..n {
            let phi = 2.0 * PI * i as f32 / n as f32;
            let r = 1.0 + 0.1 * (5.0 * theta).sin() * (3.0 * phi).cos();
            m.positions.push(
                r * Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                ),
            );
        }
    }
    let idx = |i: u32, j: u32| j * n + i % n;
    for j in 0..nt {
        for i in 0..n {
            let (a, b, c, d) = (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
            if j != 0 {
                m.indices.push([a, c, b]);
            }
            if j != nt - 1 {
                m.indices.push([a, d, c]);
            }
        }
    }
    m
}

#[test]
fn closed_mesh_does_not_leak() {
    // Rays from inside a closed mesh must all hit it from the inside (ng · d > 0), including
    // rays aimed exactly at shared vertices and through the pole fans.
    for width in widths() {
        closed_mesh_holds(width);
    }
}

fn closed_mesh_holds(width: BvhWidth) {
    let mesh = closed_sphere(64);
    let targets = mesh.positions.clone();
    let geo = Geometry::build_with_width(vec![Shape::new(ShapeGeometry::Mesh(mesh), 0)], width);
    let mut rng = Pcg32::new(5, 9);
    let mut rays: Vec<Ray> = (0..20_000)
        .map(|_| Ray::new(rand_vec(&mut rng, -0.3, 0.3), rand_dir(&mut rng)))
        .collect();
    for (k, v) in targets.iter().enumerate() {
        let o = if k % 2 == 0 {
            Vec3::ZERO
        } else {
            Vec3::new(0.01, -0.02, 0.03)
        };
        rays.push(Ray::new(o, (*v - o).normalize()));
    }
    let mut leaks = 0;
    for ray in &rays {
        match geo.intersect(ray) {
            Some(si) => assert!(si.ng.dot(ray.d) > 0.0, "hit from outside? {ray:?}"),
            None => leaks += 1,
        }
        assert!(geo.occluded(ray) || geo.intersect(ray).is_none());
    }
    assert_eq!(
        leaks,
        0,
        "{width:?}: {leaks} of {} rays escaped",
        rays.len()
    );
}

#[test]
fn tiny_scenes_and_short_hits_are_found() {
    // Hit distances far below 1e-4 (obvhs culls nodes entered before t = 1e-4 in its own ray
    // units): a millimetre-scale scene seen from 10 µm away.
    let s = 1e-6;
    let mut m = TriangleMesh::default();
    for t in 0..64u32 {
        let c = Vec3::new(t as f32 * 3.0 * s, 0.0, 0.0);
        m.positions.extend([
            c + Vec3::new(-s, -s, 0.0),
            c + Vec3::new(s, -s, 0.0),
            c + Vec3::new(0.0, s, 0.0),
        ]);
        m.indices.push([3 * t, 3 * t + 1, 3 * t + 2]);
    }
    let geo = Geometry::build(vec![Shape::new(ShapeGeometry::Mesh(m), 0)]);
    for t in 0..64 {
        let o = Vec3::new(t as f32 * 3.0 * s, 0.0, 1e-5);
        let ray = Ray::new(o, -Vec3::Z);
        let d = geo.hit_distance(&ray).expect("hit");
        assert!((d - 1e-5).abs() < 1e-9, "{d}");
        assert!(geo.occluded(&ray));
        let ray = Ray::with_t_max(o, -Vec3::Z, 0.9e-5);
        assert!(geo.hit_distance(&ray).is_none() && !geo.occluded(&ray));
    }
}

#[test]
fn both_bvh_widths_give_bit_identical_hits() {
    // The 8-wide (AVX2) layout and the 4-wide fallback test the same boxes and the same
    // triangles with the same operations; only the visiting order differs. On a closed mesh
    // with rays from inside and outside, some aimed exactly at vertices (where hits tie), the
    // full hit records must agree bit for bit.
    if !BvhWidth::Eight.supported() {
        eprintln!("no AVX2: only the fallback runs on this CPU");
        return;
    }
    let mesh = closed_sphere(256);
    let targets = mesh.positions.clone();
    let shapes = vec![
        Shape::new(ShapeGeometry::Mesh(mesh), 0),
        Shape::new(
            ShapeGeometry::Sphere(Sphere {
                center: Vec3::new(0.0, 0.0, 2.5),
                radius: 0.5,
            }),
            1,
        ),
    ];
    let four = Geometry::build_with_width(shapes.clone(), BvhWidth::Four);
    let eight = Geometry::build_with_width(shapes, BvhWidth::Eight);
    assert!(eight.bvh.node_count() < four.bvh.node_count());
    let mut rng = Pcg32::new(21, 4);
    let mut rays: Vec<Ray> = (0..20_000)
        .map(|i| {
            let o = rand_vec(&mut rng, -4.0, 4.0) * if i % 2 == 0 { 0.1 } else { 1.0 };
            let t_max = if i % 5 == 0 { 1.0 } else { f32::INFINITY };
            Ray::with_t_max(o, rand_dir(&mut rng), t_max)
        })
        .collect();
    rays.extend(targets.iter().step_by(7).map(|v| {
        let o = Vec3::new(0.01, -0.02, 0.03);
        Ray::new(o, (*v - o).normalize())
    }));
    let key = |g: &Geometry, r: &Ray| {
        g.intersect(r).map(|s| {
            (
                s.t.to_bits(),
                s.shape,
                s.prim,
                s.p.to_array().map(f32::to_bits),
                s.uv.to_array().map(f32::to_bits),
            )
        })
    };
    let mut hits = 0;
    for (i, r) in rays.iter().enumerate() {
        let k = key(&four, r);
        assert_eq!(k, key(&eight, r), "ray {i}");
        assert_eq!(four.occluded(r), eight.occluded(r), "ray {i}");
        assert_eq!(four.hit_distance(r).map(f32::to_bits), k.map(|k| k.0));
        hits += k.is_some() as u32;
    }
    assert!(hits > 12_000, "hits {hits}"); // 14 228 of 20 037
}

#[test]
fn ray_streams_give_each_ray_its_own_hit() {
    // Eight rays at a time through the 8-wide tree (or one by one where it cannot): coherent
    // camera-like rays, rays of mixed dominant axes in one packet (left to the one-ray path),
    // rays aimed at shared vertices (ties), short rays, rays that can hit nothing (t_max ≤ 0,
    // NaN), a sphere among the triangles, and a count not a multiple of eight.
    let mesh = closed_sphere(128);
    let targets = mesh.positions.clone();
    let shapes = vec![
        Shape::new(ShapeGeometry::Mesh(mesh), 0),
        Shape::new(
            ShapeGeometry::Sphere(Sphere {
                center: Vec3::new(0.2, 0.1, 0.0),
                radius: 0.3,
            }),
            1,
        ),
    ];
    let mut rng = Pcg32::new(8, 2);
    let mut rays = Vec::new();
    for y in 0..40 {
        for x in 0..40 {
            let d = Vec3::new(x as f32 / 20.0 - 1.0, y as f32 / 20.0 - 1.0, 2.0).normalize();
            rays.push(Ray::new(Vec3::new(0.0, 0.0, -4.0), d));
        }
    }
    for i in 0..3000 {
        let t_max = match i % 7 {
            0 => 0.5,
            1 => f32::NAN,
            2 => -1.0,
            _ => f32::INFINITY,
        };
        rays.push(Ray::with_t_max(
            rand_vec(&mut rng, -0.5, 0.5),
            rand_dir(&mut rng),
            t_max,
        ));
    }
    rays.extend(targets.iter().step_by(3).map(|v| {
        let o = Vec3::new(0.01, -0.02, 0.03);
        Ray::new(o, (*v - o).normalize())
    }));
    rays.push(Ray::new(Vec3::ZERO, Vec3::X));
    for width in widths() {
        let geo = Geometry::build_with_width(shapes.clone(), width);
        let mut hits = Vec::new();
        geo.intersect_stream(&rays, &mut hits);
        let mut occluded = Vec::new();
        geo.occluded_stream(&rays, &mut occluded);
        let mut distances = Vec::new();
        geo.hit_distance_stream(&rays, &mut distances);
        assert_eq!(
            (hits.len(), occluded.len(), distances.len()),
            (rays.len(), rays.len(), rays.len())
        );
        let key = |s: &caustica_scene::SurfaceInteraction| {
            (
                s.t.to_bits(),
                s.shape,
                s.prim,
                s.p.to_array().map(f32::to_bits),
                s.uv.to_array().map(f32::to_bits),
            )
        };
        let mut n = 0;
        for (i, r) in rays.iter().enumerate() {
            let one = geo.intersect(r);
            assert_eq!(
                hits[i].as_ref().map(key),
                one.as_ref().map(key),
                "{width:?} ray {i}"
            );
            assert_eq!(occluded[i], geo.occluded(r), "{width:?} ray {i}");
            assert_eq!(
                distances[i].map(f32::to_bits),
                one.as_ref().map(|s| s.t.to_bits()),
                "{width:?} ray {i}"
            );
            n += one.is_some() as u32;
        }
        assert!(n > 3000, "hits {n}");
    }
}
