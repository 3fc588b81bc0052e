//! BVH queries at a time against a static BVH (issue 19's performance item): a displaced
//! sphere of 131 072 triangles whose displacement wave travels between two keyframes, traced
//! (a) static, its first keyframe in an ordinary BVH; (b) moving, every ray at a random time in
//! the shutter `[0, 1]` (the BVH over the motion-swept bounds, triangles interpolated to the
//! ray's time at each test); (c) moving, every ray at time 0 (the same swept tree, so (c)/(a)
//! is the cost of the looser bounds and the interpolation, (b)/(c) that of rays spreading over
//! time). Camera (coherent) and random (incoherent) closest-hit rays, one thread.
//!
//! Run: `cargo bench -p caustica-scene --bench motion_bvh`; results in docs/performance.md.

use std::hint::black_box;
use std::sync::Arc;
use std::time::Duration;

use caustica_core::sampling::Pcg32;
use caustica_core::{PI, Ray, Vec3};
use caustica_scene::geometry::Geometry;
use caustica_scene::shape::{MeshMotion, Shape, ShapeGeometry, TriangleMesh};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

/// A sphere displaced by a wave of phase `phase`, `2·nphi·(ntheta − 1)` triangles.
fn displaced_sphere(nphi: u32, ntheta: u32, phase: f32) -> TriangleMesh {
    let mut m = TriangleMesh::default();
    for j in 0..=ntheta {
        let theta = PI * j as f32 / ntheta as f32;
        for i in 0..nphi {
            let phi = 2.0 * PI * i as f32 / nphi as f32;
            let r = 1.0
                + 0.08 * (7.0 * theta + phase).sin() * (9.0 * phi).cos()
                + 0.03 * (31.0 * theta + 13.0 * phi + 3.0 * phase).sin();
            m.positions.push(
                r * Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                ),
            );
        }
    }
    let idx = |i: u32, j: u32| j * nphi + i % nphi;
    for j in 0..ntheta {
        for i in 0..nphi {
            let (a, b, c, d) = (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
            if j != 0 {
                m.indices.push([a, c, b]);
            }
            if j != ntheta - 1 {
                m.indices.push([a, d, c]);
            }
        }
    }
    m
}

fn camera_rays(w: u32, h: u32) -> Vec<Ray> {
    let eye = Vec3::new(0.3, -3.2, 0.8);
    let fwd = (Vec3::ZERO - eye).normalize();
    let right = fwd.cross(Vec3::Z).normalize();
    let up = right.cross(fwd);
    let tan = (40.0f32.to_radians() * 0.5).tan();
    let mut rays = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let sx = (2.0 * (x as f32 + 0.5) / w as f32 - 1.0) * tan;
            let sy = (1.0 - 2.0 * (y as f32 + 0.5) / h as f32) * tan * h as f32 / w as f32;
            rays.push(Ray::new(eye, (fwd + right * sx + up * sy).normalize()));
        }
    }
    rays
}

fn incoherent_rays(n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Pcg32::new(seed, 0);
    (0..n)
        .map(|_| {
            let o = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.4 - 1.2;
            let z = 1.0 - 2.0 * rng.next_f32();
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = 2.0 * PI * rng.next_f32();
            Ray::new(o, Vec3::new(r * phi.cos(), r * phi.sin(), z))
        })
        .collect()
}

/// `rays` with times uniform in `[0, 1)` (a fixed sequence).
fn at_random_times(rays: &[Ray], seed: u64) -> Vec<Ray> {
    let mut rng = Pcg32::new(seed, 9);
    rays.iter()
        .map(|r| Ray {
            time: rng.next_f32(),
            ..*r
        })
        .collect()
}

fn benches(c: &mut Criterion) {
    let (nphi, ntheta) = (512, 129);
    let frame0 = displaced_sphere(nphi, ntheta, 0.0);
    let frame1 = displaced_sphere(nphi, ntheta, 0.6);
    let n_tris = frame0.indices.len();
    let fixed = Geometry::build(vec![Shape::new(ShapeGeometry::Mesh(frame0.clone()), 0)]);
    let mut shape = Shape::new(ShapeGeometry::Mesh(frame0.clone()), 0);
    shape.motion = Some(Arc::new(
        MeshMotion::new(
            0.0,
            vec![frame0.positions.clone(), frame1.positions],
            None,
            frame0.positions.len(),
        )
        .expect("two keyframes of one topology"),
    ));
    let moving = Geometry::build(vec![shape]);
    assert!(moving.has_motion() && !fixed.has_motion());
    eprintln!("{n_tris} triangles, each moving up to 0.1 m between its keyframes");

    let camera = camera_rays(256, 256);
    let random = incoherent_rays(100_000, 1);
    for (name, rays) in [("coherent", &camera), ("incoherent", &random)] {
        let timed = at_random_times(rays, 2);
        // The moving BVH at time 0 answers as the static one.
        let agree = rays
            .iter()
            .filter(|r| {
                let (a, b) = (fixed.intersect(r), moving.intersect(r));
                match (a, b) {
                    (Some(a), Some(b)) => (a.t - b.t).abs() < 1e-4,
                    (None, None) => true,
                    _ => false,
                }
            })
            .count();
        eprintln!(
            "{name}: moving at t = 0 agrees with static on {agree}/{}",
            rays.len()
        );
        let mut g = c.benchmark_group(format!("motion_bvh_{name}"));
        g.sample_size(20)
            .warm_up_time(Duration::from_secs(1))
            .measurement_time(Duration::from_secs(4))
            .throughput(Throughput::Elements(rays.len() as u64));
        let count = |geo: &Geometry, rays: &[Ray]| {
            rays.iter()
                .filter(|r| black_box(geo.intersect(r)).is_some())
                .count()
        };
        g.bench_function("static", |b| b.iter(|| count(&fixed, rays)));
        g.bench_function("moving_time_0", |b| b.iter(|| count(&moving, rays)));
        g.bench_function("moving_random_time", |b| b.iter(|| count(&moving, &timed)));
        g.finish();
    }
}

criterion_group!(motion, benches);
criterion_main!(motion);
