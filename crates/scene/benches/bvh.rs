//! BVH benchmarks on a procedurally displaced sphere of ~1M triangles:
//! build time, closest-hit throughput for coherent (pinhole camera) and incoherent rays,
//! shadow-ray throughput of [`Geometry`] (our 4-wide BVH, collapsed from obvhs's binary PLOC
//! tree, with four-at-a-time watertight triangle tests), against raw `obvhs` on its own triangles
//! (its CWBVH from `build_cwbvh_from_tris` and its own triangle test) as the reference.
//!
//! Run: `cargo bench -p caustica-scene --bench bvh`. Traversal benchmarks are single-threaded;
//! both builds are single-threaded (obvhs without its `parallel` feature).

use std::hint::black_box;
use std::time::{Duration, Instant};

use caustica_core::sampling::Pcg32;
use caustica_core::{PI, Ray, Vec3};
use caustica_scene::geometry::Geometry;
use caustica_scene::shape::{Aabb, Shape, ShapeGeometry, TriangleMesh};
use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3A;

/// A sphere displaced by a few sinusoids, tessellated into `2·nphi·(ntheta − 1)` triangles.
fn displaced_sphere(nphi: u32, ntheta: u32) -> TriangleMesh {
    let mut m = TriangleMesh::default();
    for j in 0..=ntheta {
        let theta = PI * j as f32 / ntheta as f32;
        for i in 0..nphi {
            let phi = 2.0 * PI * i as f32 / nphi as f32;
            let r = 1.0
                + 0.08 * (7.0 * theta).sin() * (9.0 * phi).cos()
                + 0.03 * (31.0 * theta + 13.0 * phi).sin()
                + 0.01 * (97.0 * theta).sin() * (61.0 * phi).sin();
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

/// Pinhole camera rays (w×h) looking at the mesh from outside.
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

fn rand_point(rng: &mut Pcg32, b: &Aabb) -> Vec3 {
    let u = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
    b.min + u * (b.max - b.min)
}

fn rand_dir(rng: &mut Pcg32) -> Vec3 {
    let z = 1.0 - 2.0 * rng.next_f32();
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * rng.next_f32();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Random origins inside the bounds, uniformly random directions.
fn incoherent_rays(n: usize, b: &Aabb, seed: u64) -> Vec<Ray> {
    let mut rng = Pcg32::new(seed, 0);
    (0..n)
        .map(|_| Ray::new(rand_point(&mut rng, b), rand_dir(&mut rng)))
        .collect()
}

/// Segments between two random points inside the bounds.
fn shadow_rays(n: usize, b: &Aabb, seed: u64) -> Vec<Ray> {
    let mut rng = Pcg32::new(seed, 1);
    (0..n)
        .map(|_| {
            let (p, q) = (rand_point(&mut rng, b), rand_point(&mut rng, b));
            let d = q - p;
            let len = d.length();
            Ray::with_t_max(p, d / len, len)
        })
        .collect()
}

fn obvhs_tris(m: &TriangleMesh) -> Vec<obvhs::triangle::Triangle> {
    m.indices
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|k| Vec3A::from(m.positions[k as usize]));
            obvhs::triangle::Triangle {
                v0: a,
                v1: b,
                v2: c,
            }
        })
        .collect()
}

fn benches(c: &mut Criterion) {
    let mesh = displaced_sphere(1024, 512);
    let n_tris = mesh.indices.len();
    let shapes = vec![Shape::new(ShapeGeometry::Mesh(mesh.clone()), 0)];

    let t0 = Instant::now();
    let geo = Geometry::build(shapes.clone());
    let build_once = t0.elapsed();
    eprintln!(
        "caustica: {n_tris} triangles, build {:.3} s, {} 4-wide nodes, {} packets",
        build_once.as_secs_f64(),
        geo.bvh.node_count(),
        geo.bvh.packet_count(),
    );
    let bounds = geo.bounds();

    let tris = obvhs_tris(&mesh);
    let params = obvhs::BvhBuildParams::medium_build();
    let t0 = Instant::now();
    let cw = obvhs::cwbvh::builder::build_cwbvh_from_tris(&tris, params, &mut Duration::default());
    eprintln!(
        "obvhs cwbvh medium_build: {:.3} s",
        t0.elapsed().as_secs_f64()
    );
    let cw_tris: Vec<_> = cw
        .primitive_indices
        .iter()
        .map(|&i| tris[i as usize])
        .collect();

    let primary = camera_rays(512, 512);
    let random = incoherent_rays(200_000, &bounds, 1);
    let shadows = shadow_rays(200_000, &bounds, 2);

    // Sanity: both BVHs agree on hit distances of the incoherent rays.
    let mut agree = 0;
    for r in &random {
        let a = geo.intersect(r).map(|s| s.t);
        let ray = obvhs::ray::Ray::new(Vec3A::from(r.o), Vec3A::from(r.d), 0.0, f32::INFINITY);
        let mut hit = obvhs::ray::RayHit::none();
        let b = cw
            .ray_traverse(ray, &mut hit, |ray, id| cw_tris[id].intersect(ray))
            .then_some(hit.t);
        if match (a, b) {
            (Some(a), Some(b)) => (a - b).abs() <= 1e-4 * a.max(1.0),
            (None, None) => true,
            _ => false,
        } {
            agree += 1;
        }
    }
    eprintln!(
        "caustica vs obvhs agree on {agree}/{} incoherent rays",
        random.len()
    );

    let mut g = c.benchmark_group("bvh_build");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(15));
    g.bench_function(format!("caustica_{n_tris}_tris"), |b| {
        b.iter_batched(
            || shapes.clone(),
            |s| black_box(Geometry::build(s)),
            BatchSize::LargeInput,
        )
    });
    g.bench_function(format!("obvhs_cwbvh_medium_{n_tris}_tris"), |b| {
        b.iter(|| {
            black_box(obvhs::cwbvh::builder::build_cwbvh_from_tris(
                &tris,
                params,
                &mut Duration::default(),
            ))
        })
    });
    g.finish();

    let mut g = c.benchmark_group("bvh_trace");
    g.sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    g.throughput(Throughput::Elements(primary.len() as u64));
    g.bench_function("caustica_closest_coherent", |b| {
        b.iter(|| {
            primary
                .iter()
                .filter(|r| geo.intersect(r).is_some())
                .count()
        })
    });
    g.throughput(Throughput::Elements(random.len() as u64));
    g.bench_function("caustica_closest_incoherent", |b| {
        b.iter(|| random.iter().filter(|r| geo.intersect(r).is_some()).count())
    });
    g.bench_function("caustica_distance_only_incoherent", |b| {
        b.iter(|| {
            random
                .iter()
                .filter(|r| geo.hit_distance(r).is_some())
                .count()
        })
    });
    g.bench_function("obvhs_closest_incoherent", |b| {
        b.iter(|| {
            random
                .iter()
                .filter(|r| {
                    let ray = obvhs::ray::Ray::new(
                        Vec3A::from(r.o),
                        Vec3A::from(r.d),
                        0.0,
                        f32::INFINITY,
                    );
                    let mut hit = obvhs::ray::RayHit::none();
                    cw.ray_traverse(ray, &mut hit, |ray, id| cw_tris[id].intersect(ray))
                })
                .count()
        })
    });
    g.throughput(Throughput::Elements(shadows.len() as u64));
    g.bench_function("caustica_shadow", |b| {
        b.iter(|| shadows.iter().filter(|r| geo.occluded(r)).count())
    });
    g.finish();
}

criterion_group!(bvh, benches);
criterion_main!(bvh);
