//! Eight rays at a time or one by one in a small scene, for rays grouped as the eight samples
//! of one pixel would give them at a diffuse vertex: 2¹⁸ rays in groups of eight whose origins
//! lie within 1 cm of each other (the group's corner uniform in the Cornell box). Bounce rays
//! take directions uniform on the sphere, through `Geometry::intersect` one by one and
//! `Geometry::intersect_stream` eight at a time; shadow rays go to points on a square of a
//! fifth of the box's width under the ceiling (the light's place), through `occluded` and
//! `occluded_stream`. Prints nanoseconds per ray, the best of seven passes. It asks whether
//! path tracing's queries would gain from being traced eight samples at a time
//! (docs/performance.md, issue 26's sixth session).
//!
//! ```text
//! cargo run --release -p caustica-render --example cornell_groups
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
    let mut u3 = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
    let n = 1 << 18;
    let (mut bounce, mut shadow) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let light = Vec3::new(0.0, b.max.y - 1e-3, 0.0);
    let width = b.max.x - b.min.x;
    while bounce.len() < n {
        let corner = b.min + (b.max - b.min) * (u3() * 0.9 + 0.05);
        for _ in 0..8 {
            let o = corner + u3() * 0.01;
            let d = loop {
                let d = u3() - Vec3::splat(0.5);
                if (0.1..0.5).contains(&d.length()) {
                    break d.normalize();
                }
            };
            bounce.push(Ray::new(o, d));
            let s = u3();
            let to = light + Vec3::new(s.x - 0.5, 0.0, s.z - 0.5) * 0.2 * width - o;
            shadow.push(Ray::with_t_max(o, to.normalize(), to.length() * 0.999));
        }
    }
    let mut best = [f64::MAX; 4];
    let (mut hits, mut blocked) = (Vec::new(), Vec::new());
    let mut time = |k: usize, f: &mut dyn FnMut() -> usize| {
        let t = Instant::now();
        std::hint::black_box(f());
        best[k] = best[k].min(t.elapsed().as_secs_f64());
    };
    for _ in 0..7 {
        time(0, &mut || {
            bounce.iter().filter(|r| g.intersect(r).is_some()).count()
        });
        time(1, &mut || {
            let mut c = 0;
            for group in bounce.chunks(8) {
                g.intersect_stream(group, &mut hits);
                c += hits.iter().filter(|h| h.is_some()).count();
            }
            c
        });
        time(2, &mut || shadow.iter().filter(|r| g.occluded(r)).count());
        time(3, &mut || {
            let mut c = 0;
            for group in shadow.chunks(8) {
                g.occluded_stream(group, &mut blocked);
                c += blocked.iter().filter(|&&x| x).count();
            }
            c
        });
    }
    let ns = |s: f64| s * 1e9 / n as f64;
    println!(
        "bounce rays: intersect {:.1} ns, intersect_stream {:.1} ns; shadow rays: occluded {:.1} ns, occluded_stream {:.1} ns (best of 7)",
        ns(best[0]),
        ns(best[1]),
        ns(best[2]),
        ns(best[3])
    );
}
