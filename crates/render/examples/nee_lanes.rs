//! Next-event estimation in the Cornell box one vertex at a time
//! (`transport::direct::direct_with`, with its shadow ray) against the path tracer's lanes
//! (`transport::direct_lanes::DirectBatch`: the estimates deferred, computed four at a time, the
//! shadow rays traced after), for issue 26's deliverable 3 (SIMD across paths).
//!
//! The vertices are the first hits of 2¹² camera rays off the light (Lambertian surfaces; few
//! enough to stay in the caches), each with three random numbers for its estimate. A
//! path takes `g` estimates, as a path with `g` vertices would (the Cornell box's paths average
//! 3.15). With a batch per path, as before the batch was shared, the lanes are full at `g = 4`;
//! with one batch for all paths (finished every 32 paths, as the pixel driver does) they are
//! full whatever `g`. Checks that all sums are equal bit for bit, then prints nanoseconds per
//! estimate, the best of `reps` passes of 16 rounds.
//!
//! ```text
//! cargo run --release -p caustica-render --example nee_lanes -- [reps]
//! ```

use caustica_core::sampling::{Pcg32, Sampler, SamplerKind};
use caustica_core::{Spectrum, Vec2};
use caustica_loader::builtin_scene;
use caustica_render::RenderStats;
use caustica_render::transport::Vertex;
use caustica_render::transport::direct::direct_with;
use caustica_render::transport::direct_lanes::DirectBatch;
use caustica_render::transport::vertex::Scatterer;
use caustica_scene::intersection::NONE;
use std::time::Instant;

/// Passes over the vertices per timing.
const ROUNDS: usize = 16;

fn main() {
    let scene = builtin_scene("cornell-box")
        .expect("the built-in Cornell box")
        .build()
        .expect("the built-in Cornell box builds");
    let reps: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(7);
    let mut rng = Pcg32::new(7, 3);
    let n = 1 << 12;
    let mut verts: Vec<(Vertex, f32, Vec2)> = Vec::with_capacity(n);
    while verts.len() < n {
        let raster = Vec2::new(rng.next_f32() * 256.0, rng.next_f32() * 256.0);
        let ray = scene.camera.generate_ray(raster, Vec2::ZERO).ray;
        if let Some(si) = scene.geometry.intersect(&ray)
            && si.light == NONE
        {
            let u = (rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32()));
            verts.push((Vertex::rgb(&scene, si, &ray), u.0, u.1));
        }
    }
    // Without media the sampler is not drawn from.
    let mut sampler = Sampler::new(SamplerKind::Independent, 1);
    let mut stats = RenderStats::default();
    let mut scalar = |g: usize| -> Vec<Spectrum> {
        verts
            .chunks(g)
            .map(|path| {
                let mut l = Spectrum::ZERO;
                for (v, u_light, u) in path {
                    let at = Scatterer::Surface { v, medium: NONE };
                    l += direct_with(&scene, at, *u_light, *u, &mut sampler, &mut stats, true);
                }
                l
            })
            .collect()
    };
    let mut stats_lanes = RenderStats::default();
    // Paths of `g` estimates, the batch finished every `every` paths.
    let mut lanes = |g: usize, every: usize| -> Vec<Spectrum> {
        let mut out = Vec::with_capacity(n / g + 1);
        let mut batch = DirectBatch::default();
        for paths in verts.chunks(g * every) {
            for path in paths.chunks(g) {
                let mut l = batch.path(&scene);
                for (v, u_light, u) in path {
                    assert!(l.defer_direct(Spectrum::ONE, v, *u_light, *u));
                }
                assert!(l.total().is_none());
            }
            batch.finish(&mut stats_lanes, |_, l| out.push(l));
        }
        out
    };
    for g in 1..=4 {
        let bits = |s: Vec<Spectrum>| s.iter().map(|s| s.c.map(f32::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(scalar(g)), bits(lanes(g, 1)), "paths of {g}");
        assert_eq!(bits(scalar(g)), bits(lanes(g, 32)), "paths of {g}, shared");
    }
    println!("{n} estimates, the lanes' sums equal the scalar ones bit for bit");

    let time = |f: &mut dyn FnMut() -> Vec<Spectrum>| {
        let mut best = f64::MAX;
        for _ in 0..reps {
            let t = Instant::now();
            for _ in 0..ROUNDS {
                std::hint::black_box(f());
            }
            best = best.min(t.elapsed().as_secs_f64());
        }
        best * 1e9 / (n * ROUNDS) as f64
    };
    let one = time(&mut || scalar(4));
    for (every, what) in [(1, "a batch per path"), (32, "a batch per 32 paths")] {
        let ns: Vec<f64> = (1..=4).map(|g| time(&mut || lanes(g, every))).collect();
        println!(
            "ns per estimate, {what}, paths of 1 / 2 / 3 / 4 estimates: {:.1} / {:.1} / {:.1} / {:.1} (best of {reps})",
            ns[0], ns[1], ns[2], ns[3]
        );
    }
    println!("one at a time: {one:.1}");
}
