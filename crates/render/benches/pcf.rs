//! Photon cone focusing: the cost of making cones, building the cone map and looking it up,
//! single-threaded, on the default scene (`caustic-box`, area light, glass and gold balls).
//!
//! * `cones/<techniques>`: 20 000 light paths traced with their cones (tracing + storing), for
//!   each technique set: the light walk alone (`walk`, no cones), BSDF only, BSDF + camera NEE,
//!   the triplet (importon map traced before, not timed). Throughput: light paths; the cones
//!   per path are printed, so cones/s = paths/s × cones/path.
//! * `build`: the k-d tree over one iteration's cones (200 000 light paths, triplet).
//! * `lookup/<rule>`: cone-map estimates at the points the camera sees first (σ₁, θ₁ of the
//!   first iteration, and of iteration 1000): lookups/s; cones scanned per lookup printed.
//! * Memory per cone (cone + tree) is printed.
//!
//! Run: `cargo bench -p caustica-render --bench pcf`.

use std::hint::black_box;

use caustica_core::{Vec2, Vec3};
use caustica_loader::builtin_scene;
use caustica_render::RenderOptions;
use caustica_render::integrator::pcf::{PcfPlan, cone_rule, importon_map, iteration_map};
use caustica_render::options::{ConeTechniques, PcfSettings};
use caustica_render::pcf::{Aperture, ConeSet, LookupStats, PhotonConeMap, trace_cones};
use caustica_render::stats::RenderStats;
use caustica_render::transport::light_walk::walk_light_path;
use caustica_scene::Scene;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn scene(name: &str) -> Scene {
    builtin_scene(name)
        .expect("built-in scene")
        .build()
        .expect("scene builds")
}

fn options(techniques: &str) -> RenderOptions {
    let mut o = RenderOptions::default();
    o.photons.pcf = PcfSettings {
        techniques: Some(ConeTechniques::parse(techniques).expect("techniques")),
        ..Default::default()
    };
    o.photons.progressive.paths_per_iteration = 200_000;
    o
}

fn bench(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("thread pool");
    let s = scene("caustic-box");
    let n = 20_000u64;
    let mut g = c.benchmark_group("cones");
    g.sample_size(10);
    g.throughput(Throughput::Elements(n));
    let walk_opts = RenderOptions::default();
    g.bench_function("walk", |b| {
        b.iter(|| {
            pool.install(|| {
                let mut st = RenderStats::default();
                let mut sampler = caustica_core::sampling::Sampler::new(walk_opts.sampler, 0);
                for i in 0..n {
                    sampler.start_path(0xC0E5, i);
                    walk_light_path(&s, &mut sampler, &walk_opts.limits, &mut st, |_, _, _| {});
                }
                black_box(st)
            })
        })
    });
    for t in ["bsdf", "bsdf,camera", "bsdf,camera,importons"] {
        let o = options(t);
        let plan = PcfPlan::new(&s, &o).expect("plan");
        let imp = pool.install(|| importon_map(&s, &o, &plan, &mut |_| true).map(|m| m.0));
        let rule = cone_rule(&s, &plan, imp.as_ref(), &plan.schedule.kernel(1));
        let probe = pool.install(|| trace_cones(&s, &o, &rule, 0..n, &mut |_| true));
        println!(
            "{t}: {:.2} cones per light path",
            probe.0.len() as f64 / n as f64
        );
        g.bench_function(t, |b| {
            b.iter(|| pool.install(|| black_box(trace_cones(&s, &o, &rule, 0..n, &mut |_| true))))
        });
    }
    g.finish();

    // One iteration's map (triplet, 200 000 paths).
    let o = options("bsdf,camera,importons");
    let plan = PcfPlan::new(&s, &o).expect("plan");
    let imp = pool.install(|| importon_map(&s, &o, &plan, &mut |_| true).map(|m| m.0));
    let (map, _) = pool.install(|| iteration_map(&s, &o, &plan, imp.as_ref(), 1, &mut |_| true));
    println!(
        "cone map: {} cones from {} light paths, {:.1} B per cone with its tree",
        map.len(),
        map.light_paths(),
        map.memory_bytes() as f64 / map.len().max(1) as f64
    );
    let cones = map.cones().to_vec();
    let mut g = c.benchmark_group("build");
    g.sample_size(10);
    g.throughput(Throughput::Elements(cones.len() as u64));
    g.bench_function("kdtree", |b| {
        b.iter(|| black_box(PhotonConeMap::build(cones.clone(), 200_000)))
    });
    g.finish();

    // Lookups at the first hits of camera rays through a 64 × 64 grid of the film.
    let cam = &s.camera;
    // (position, direction to the camera, geometric normal on the camera's side)
    let mut queries: Vec<(Vec3, Vec3, Vec3)> = Vec::new();
    for y in 0..64 {
        for x in 0..64 {
            let raster = Vec2::new(
                (x as f32 + 0.5) / 64.0 * cam.width as f32,
                (y as f32 + 0.5) / 64.0 * cam.height as f32,
            );
            let ray = cam.generate_ray(raster, Vec2::splat(0.5)).ray;
            if let Some(si) = s.intersect(&ray) {
                let n = if si.ng.dot(ray.d) > 0.0 {
                    -si.ng
                } else {
                    si.ng
                };
                queries.push((si.p, -ray.d, n));
            }
        }
    }
    let mut g = c.benchmark_group("lookup");
    g.sample_size(10);
    g.throughput(Throughput::Elements(queries.len() as u64));
    // The cap (seed 001's kernel) and the cosine aperture of Lambertian lookups (every query
    // here, on caustic-box's walls, as if Lambertian: the same cones scanned, more inside).
    for (label, i, cosine) in [
        ("iteration-1", 1u64, false),
        ("iteration-1000", 1000, false),
        ("iteration-1-cosine", 1, true),
        ("iteration-1000-cosine", 1000, true),
    ] {
        let aperture = |q: &(Vec3, Vec3, Vec3)| {
            if cosine {
                Aperture::Cosine(q.2)
            } else {
                Aperture::Cap(q.1)
            }
        };
        let k = plan.schedule.kernel(i);
        let mut st = LookupStats::default();
        for q in &queries {
            map.estimate(q.0, aperture(q), &k, ConeSet::All, None, &mut st);
        }
        println!(
            "{label}: sigma {:.4} m, t {:.2} deg: {:.1} cones scanned, {:.2} inside per lookup",
            k.sigma,
            (k.theta as f64).to_degrees(),
            st.scanned as f64 / st.lookups as f64,
            st.inside as f64 / st.lookups as f64
        );
        g.bench_function(label, |b| {
            b.iter(|| {
                let mut st = LookupStats::default();
                for q in &queries {
                    black_box(map.estimate(q.0, aperture(q), &k, ConeSet::All, None, &mut st));
                }
                st
            })
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
