//! BVH benchmarks on a procedurally displaced sphere of ~1M triangles:
//! build time, closest-hit throughput for coherent (pinhole camera) and incoherent rays,
//! shadow-ray throughput of [`Geometry`] (our wide BVH, eight or four children per node by
//! [`caustica_scene::bvh::BvhWidth::detect`], collapsed from obvhs's binary PLOC tree, with
//! four-at-a-time watertight triangle tests), against raw `obvhs` on its own triangles
//! (its CWBVH from `build_cwbvh_from_tris` and its own triangle test) as the reference.
//!
//! Run: `cargo bench -p caustica-scene --bench bvh`. Traversal benchmarks are single-threaded;
//! both builds are single-threaded (obvhs without its `parallel` feature).

use std::hint::black_box;
use std::time::{Duration, Instant};

use caustica_scene::geometry::Geometry;
use caustica_scene::shape::{Shape, ShapeGeometry, TriangleMesh};
use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3A;

/// The mesh and ray generators, shared with `bench/embree` (the Embree comparison).
mod workload;
use workload::{
    INCOHERENT_SEED, SHADOW_SEED, camera_rays, displaced_sphere, incoherent_rays, shadow_rays,
};

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
    let random = incoherent_rays(200_000, &bounds, INCOHERENT_SEED);
    let shadows = shadow_rays(200_000, &bounds, SHADOW_SEED);

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
