//! Single-ray queries in a small scene, where a traversal's fixed cost per ray (preparing the
//! ray, the call, the stack) weighs more than its nodes: 2¹⁸ incoherent rays (origins uniform
//! in the Cornell box, directions uniform) through `Geometry::intersect` and, cut to 0.5 m, as
//! shadow rays through `Geometry::occluded`. Prints nanoseconds per ray, the best of `reps`
//! passes (load only ever adds time, so the minimum is the least disturbed pass). To compare
//! two builds on this shared machine, run their binaries alternately.
//!
//! ```text
//! cargo run --release -p caustica-render --example cornell_rays -- [reps]
//! ```

use caustica_core::sampling::Pcg32;
use caustica_core::{Ray, Vec3};
use caustica_loader::builtin_scene;
use std::time::Instant;

fn main() {
    let scene = builtin_scene("cornell-box")
        .expect("the built-in Cornell box")
        .build()
        .expect("the built-in Cornell box builds");
    let g = &scene.geometry;
    let b = g.bounds();
    let mut rng = Pcg32::new(1, 2);
    let n = 1 << 18;
    let mut rays: Vec<Ray> = Vec::with_capacity(n);
    while rays.len() < n {
        let u = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let o = b.min + (b.max - b.min) * (u * 0.9 + 0.05);
        let d = Vec3::new(
            rng.next_f32() - 0.5,
            rng.next_f32() - 0.5,
            rng.next_f32() - 0.5,
        );
        if d.length() < 0.1 || d.length() > 0.5 {
            continue;
        }
        rays.push(Ray::new(o, d.normalize()));
    }
    let reps: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(5);
    let (mut best_i, mut best_o) = (f64::MAX, f64::MAX);
    for _ in 0..reps {
        let t = Instant::now();
        let mut c = 0usize;
        for r in &rays {
            c += g.intersect(r).is_some() as usize;
        }
        best_i = best_i.min(t.elapsed().as_secs_f64());
        let t = Instant::now();
        for r in &rays {
            let mut r2 = *r;
            r2.t_max = 0.5;
            c += g.occluded(&r2) as usize;
        }
        best_o = best_o.min(t.elapsed().as_secs_f64());
        std::hint::black_box(c);
    }
    let ns = |s: f64| s * 1e9 / n as f64;
    println!(
        "intersect {:.1} ns, occluded {:.1} ns (best of {reps})",
        ns(best_i),
        ns(best_o)
    );
}
