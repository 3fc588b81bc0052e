//! Moving meshes in the BVH: a ray at time `t` meets exactly the static mesh whose vertices
//! (and normals) are the keyframes interpolated to `t`; times outside the shutter clamp to its
//! ends; a "moving" mesh whose keyframes are all equal is the static mesh, to the bit.

use caustica_core::sampling::Pcg32;
use caustica_core::{PI, Ray, Spectrum, Vec3};
use caustica_scene::camera::PerspectiveCamera;
use caustica_scene::material::Material;
use caustica_scene::shape::{MeshMotion, ShapeGeometry, TriangleMesh};
use caustica_scene::texture::Texture;
use caustica_scene::{Scene, SceneBuilder, Shutter};

fn rand_dir(rng: &mut Pcg32) -> Vec3 {
    let z = 1.0 - 2.0 * rng.next_f32();
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * rng.next_f32();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// A bumpy 12 × 12 height field in [−1, 1]² with vertex normals, at keyframe `k` of a wave
/// travelling along x (keyframes 0, 1, 2 are far apart: a vertex moves up to 0.3 m per frame).
fn wave_frame(k: usize) -> TriangleMesh {
    let n = 12;
    let h = |x: f32, y: f32| 0.3 * (3.0 * x - 1.3 * k as f32).sin() * (2.0 * y).cos();
    let mut m = TriangleMesh::default();
    let mut normals = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (
                -1.0 + 2.0 * i as f32 / n as f32,
                -1.0 + 2.0 * j as f32 / n as f32,
            );
            m.positions.push(Vec3::new(x, y, h(x, y)));
            let e = 1e-3;
            let dx = (h(x + e, y) - h(x - e, y)) / (2.0 * e);
            let dy = (h(x, y + e) - h(x, y - e)) / (2.0 * e);
            normals.push(Vec3::new(-dx, -dy, 1.0).normalize());
        }
    }
    m.normals = Some(normals);
    let v = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..n {
        for i in 0..n {
            m.indices.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            m.indices.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    m
}

fn builder(shutter: Shutter) -> (SceneBuilder, u32) {
    let mut b = SceneBuilder::new("motion");
    let mat = b
        .add_material(
            "d",
            Material::Diffuse {
                reflectance: Texture::Constant(Spectrum::splat(0.5)),
            },
        )
        .unwrap();
    b.set_camera(PerspectiveCamera::look_at(
        Vec3::new(0.0, 0.0, 5.0),
        Vec3::ZERO,
        Vec3::Y,
        40.0,
        8,
        8,
    ));
    b.set_shutter(shutter);
    (b, mat)
}

/// The wave moving over keyframes 0, 1, 2 (frames 0 … 2), with the shutter open over them.
fn moving_scene(frames: &[TriangleMesh]) -> Scene {
    let (mut b, mat) = builder(Shutter::new(0.0, 2.0).unwrap());
    let motion = MeshMotion::new(
        0.0,
        frames.iter().map(|m| m.positions.clone()).collect(),
        Some(frames.iter().map(|m| m.normals.clone().unwrap()).collect()),
        frames[0].positions.len(),
    )
    .unwrap();
    b.add_moving_mesh(frames[0].clone(), motion, mat, false)
        .unwrap();
    b.build().unwrap()
}

/// The static wave with the keyframes interpolated to `t` (frames 0 … 2).
fn static_scene_at(frames: &[TriangleMesh], t: f32) -> Scene {
    let (mut b, mat) = builder(Shutter::default());
    let k = (t.floor() as usize).min(frames.len() - 2);
    let a = t - k as f32;
    let mut m = frames[k].clone();
    let lerp = |p: Vec3, q: Vec3| p + (q - p) * a;
    for (i, p) in m.positions.iter_mut().enumerate() {
        *p = lerp(frames[k].positions[i], frames[k + 1].positions[i]);
    }
    let (n0, n1) = (
        frames[k].normals.as_ref().unwrap(),
        frames[k + 1].normals.as_ref().unwrap(),
    );
    m.normals = Some((0..n0.len()).map(|i| lerp(n0[i], n1[i])).collect());
    b.add_shape(ShapeGeometry::Mesh(m), mat, None, false)
        .unwrap();
    b.build().unwrap()
}

/// Rays from random points above and below the field, aimed at random points on it.
fn rays(rng: &mut Pcg32, n: usize) -> Vec<Ray> {
    (0..n)
        .map(|_| {
            let o = Vec3::new(0.0, 0.0, 2.0) * if rng.next_f32() < 0.5 { 1.0 } else { -1.0 }
                + rand_dir(rng) * 0.8;
            let target = Vec3::new(2.2 * rng.next_f32() - 1.1, 2.2 * rng.next_f32() - 1.1, 0.0);
            Ray::new(o, (target - o).normalize())
        })
        .collect()
}

/// Compares the hits of `rays` at `time` in `moving` with those in `fixed`: hit or miss, the
/// distance, the point, the geometric and shading normals. Returns the number of rays whose
/// hit differs in kind (a ray grazing an edge may fall on either side in rounding).
fn compare(moving: &Scene, fixed: &Scene, rays: &[Ray], time: f32) -> usize {
    let mut mismatches = 0;
    for r in rays {
        let mut rt = *r;
        rt.time = time;
        match (moving.intersect(&rt), fixed.intersect(r)) {
            (Some(a), Some(b)) => {
                assert!(
                    (a.t - b.t).abs() < 1e-4,
                    "time {time}: t {} vs {}",
                    a.t,
                    b.t
                );
                assert!(
                    (a.p - b.p).length() < 1e-4,
                    "time {time}: {} vs {}",
                    a.p,
                    b.p
                );
                assert!(a.ng.dot(b.ng) > 1.0 - 1e-4, "time {time}: ng");
                assert!(a.ns.dot(b.ns) > 1.0 - 1e-4, "time {time}: ns");
                assert_eq!(a.prim, b.prim, "time {time}: another triangle");
                assert_eq!(a.time, time, "the hit keeps the ray's time");
            }
            (None, None) => {}
            _ => mismatches += 1,
        }
    }
    mismatches
}

#[test]
fn a_ray_at_time_t_meets_the_mesh_interpolated_to_t() {
    let frames: Vec<TriangleMesh> = (0..3).map(wave_frame).collect();
    let moving = moving_scene(&frames);
    assert!(moving.has_motion());
    let mut rng = Pcg32::new(11, 3);
    let rays = rays(&mut rng, 3000);
    for t in [0.0, 0.25, 0.5, 0.999, 1.0, 1.37, 2.0] {
        let fixed = static_scene_at(&frames, t);
        let bad = compare(&moving, &fixed, &rays, t);
        assert!(
            bad <= 3,
            "time {t}: {bad} of {} rays hit differently",
            rays.len()
        );
    }
    // The geometry really moves: frame 0's mesh is not what a ray meets at 1.37.
    let frame0 = static_scene_at(&frames, 0.0);
    let moved = rays
        .iter()
        .filter(|r| {
            let mut rt = **r;
            rt.time = 1.37;
            match (moving.intersect(&rt), frame0.intersect(r)) {
                (Some(a), Some(b)) => (a.t - b.t).abs() > 1e-3,
                (a, b) => a.is_some() != b.is_some(),
            }
        })
        .count();
    assert!(moved > rays.len() / 2, "only {moved} rays see the motion");
}

#[test]
fn times_outside_the_shutter_clamp_to_its_ends() {
    let frames: Vec<TriangleMesh> = (0..3).map(wave_frame).collect();
    let moving = moving_scene(&frames);
    let mut rng = Pcg32::new(12, 5);
    let rays = rays(&mut rng, 2000);
    for (t, at) in [(-3.0, 0.0), (-1e-3, 0.0), (2.5, 2.0), (1e6, 2.0)] {
        // The moving scene asked at `t` answers as its static mesh at `at`.
        let fixed = static_scene_at(&frames, at);
        let mut bad = 0;
        for r in &rays {
            let mut rt = *r;
            rt.time = t;
            match (moving.intersect(&rt), fixed.intersect(r)) {
                (Some(a), Some(b)) => assert!((a.t - b.t).abs() < 1e-4, "time {t}"),
                (None, None) => {}
                _ => bad += 1,
            }
        }
        assert!(bad <= 3, "time {t}: {bad} rays differ from time {at}");
    }
    // NaN times do not produce NaN hits.
    for r in &rays[..200] {
        let mut rt = *r;
        rt.time = f32::NAN;
        if let Some(h) = moving.intersect(&rt) {
            assert!(h.p.is_finite() && h.ns.is_finite(), "NaN time gave {h:?}");
        }
    }
}

#[test]
fn a_mesh_whose_keyframes_are_equal_is_the_static_mesh() {
    let frame = wave_frame(1);
    let still = moving_scene(&[frame.clone(), frame.clone(), frame.clone()]);
    assert!(!still.has_motion(), "equal keyframes are not motion");
    let fixed = static_scene_at(&[frame.clone(), frame], 0.0);
    let mut rng = Pcg32::new(13, 7);
    for r in rays(&mut rng, 2000) {
        let mut rt = r;
        rt.time = 0.7;
        let (a, b) = (still.intersect(&rt), fixed.intersect(&r));
        assert_eq!(a.is_some(), b.is_some());
        if let (Some(a), Some(b)) = (a, b) {
            assert_eq!((a.t.to_bits(), a.prim), (b.t.to_bits(), b.prim));
            assert_eq!(a.ns, b.ns);
        }
    }
}
