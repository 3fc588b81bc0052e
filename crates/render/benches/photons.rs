//! Photon tracing and photon-map queries on the built-in scenes, single-threaded.
//!
//! * `trace/<scene>`: light paths emitted and photons stored per second per thread by the shared
//!   photon tracer (`trace_photons`), for the global map (every non-delta hit) of the Cornell box
//!   and the caustic map (L S+ D) of the glass sphere.
//! * `estimate/cornell-box`: radiance estimates (eq. 3.2, k = 50, Epanechnikov) per second on a
//!   global map of 10⁶ photons at the floor points seen by the camera.
//! * `differentials/<scene>`: the same caustic light paths traced as plain photons
//!   (`trace_photons`) and as photon differentials with their footprints
//!   (`trace_photon_differentials`), no map built: the cost of carrying the differentials
//!   (issue 5's target: ≤ 1.3×).
//! * The memory per stored photon (photon record + k-d tree) is printed.
//!
//! Run: `cargo bench -p caustica-render --bench photons`.

use std::hint::black_box;

use caustica_core::Vec2;
use caustica_loader::builtin_scene;
use caustica_render::photon::differential::trace_photon_differentials;
use caustica_render::photon::map::{EstimateOptions, PhotonMap};
use caustica_render::photon::tracer::{MapKind, Photon, trace_photons};
use caustica_render::transport::Vertex;
use caustica_render::{PhotonBudget, RenderOptions, Smoothing};
use caustica_scene::Scene;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn scene(name: &str) -> Scene {
    builtin_scene(name)
        .expect("built-in scene")
        .build()
        .expect("scene builds")
}

fn bench(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("thread pool");
    let opts = RenderOptions::default();
    let mut g = c.benchmark_group("trace");
    g.sample_size(10);
    for (name, kind, n) in [
        ("cornell-box", MapKind::Global, 200_000usize),
        ("glass-sphere", MapKind::Caustic, 20_000),
    ] {
        let s = scene(name);
        let probe = pool
            .install(|| trace_photons(&s, PhotonBudget::Records(n), kind, 0, &opts, &mut |_| true));
        println!(
            "{name}: {n} {kind:?} photons from {} light paths ({:.3} photons/path)",
            probe.paths,
            probe.photons.len() as f64 / probe.paths as f64
        );
        g.throughput(Throughput::Elements(n as u64));
        g.bench_function(format!("{name}_{kind:?}_photons"), |b| {
            b.iter(|| {
                pool.install(|| {
                    black_box(trace_photons(
                        &s,
                        PhotonBudget::Records(n),
                        kind,
                        0,
                        &opts,
                        &mut |_| true,
                    ))
                })
            })
        });
    }
    g.finish();

    let mut g = c.benchmark_group("differentials");
    g.sample_size(10);
    for (name, n) in [
        ("glass-sphere", 10_000usize),
        ("water-wave", 100_000),
        ("metal-ring", 50_000),
    ] {
        let s = scene(name);
        g.throughput(Throughput::Elements(n as u64));
        g.bench_function(format!("{name}_plain"), |b| {
            b.iter(|| {
                pool.install(|| {
                    black_box(trace_photons(
                        &s,
                        PhotonBudget::Records(n),
                        MapKind::Caustic,
                        0,
                        &opts,
                        &mut |_| true,
                    ))
                })
            })
        });
        g.bench_function(format!("{name}_differential"), |b| {
            b.iter(|| {
                pool.install(|| {
                    black_box(trace_photon_differentials(
                        &s,
                        PhotonBudget::Records(n),
                        Smoothing::ONE,
                        0,
                        &opts,
                        &mut |_| true,
                    ))
                })
            })
        });
    }
    g.finish();

    let s = scene("cornell-box");
    let traced = trace_photons(
        &s,
        PhotonBudget::Records(1_000_000),
        MapKind::Global,
        0,
        &opts,
        &mut |_| true,
    );
    let map = PhotonMap::new(traced.photons, traced.paths);
    println!(
        "memory: {:.1} bytes per stored photon ({} bytes record + k-d tree)",
        map.memory_bytes() as f64 / map.len() as f64,
        std::mem::size_of::<Photon>()
    );
    // Query points: the first diffuse hits of a 64×64 grid of camera rays.
    let cam = &s.camera;
    let mut vertices = Vec::new();
    for j in 0..64 {
        for i in 0..64 {
            let raster = Vec2::new(
                (i as f32 + 0.5) * cam.width as f32 / 64.0,
                (j as f32 + 0.5) * cam.height as f32 / 64.0,
            );
            let ray = cam.generate_ray(raster, Vec2::splat(0.5)).ray;
            if let Some(si) = s.intersect(&ray) {
                vertices.push(Vertex::rgb(&s, si, &ray));
            }
        }
    }
    let mut g = c.benchmark_group("estimate");
    g.sample_size(10);
    g.throughput(Throughput::Elements(vertices.len() as u64));
    for k in [50usize, 500] {
        let est = EstimateOptions {
            k,
            ..Default::default()
        };
        g.bench_function(format!("cornell-box_1M_k{k}"), |b| {
            let mut buf = caustica_density::estimator::Scratch::default();
            b.iter(|| {
                for v in &vertices {
                    black_box(map.estimate(v, &est, &mut buf));
                }
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
