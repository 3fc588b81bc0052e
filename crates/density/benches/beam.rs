//! The beam radiance estimate's photon gather: [`SphereBvh`] segment queries over 200k volume
//! photons with k-NN pilot radii, with and without the chord weights of [`caustica_density::beam`].
//!
//! Photons fill a 2 m cube of fog: 60 % uniformly, 40 % in a "volume caustic", a cone of light
//! focused to a point (radial Gaussian falloff around its axis), so that the densities, and
//! hence the radii, span more than a decade. Each photon's radius is the distance to its
//! `K_PILOT`-th nearest neighbour (Jarosz et al.'s pilot estimate, seed 000 sec. 8.2). The
//! anisotropic case gives each photon an ellipsoid with a random filter matrix whose largest
//! semi-axis is that radius (the index holds the bounding spheres).
//!
//! Eye segments start at a camera 4 m in front of the cube and end at the cube's far side,
//! aimed at uniformly random points of it, in a fixed pseudo-random order.
//!
//! Run: `cargo bench -p caustica-density --bench beam -- --measurement-time 5`. Single-threaded.

use std::hint::black_box;

use caustica_core::sampling::Pcg32;
use caustica_core::{Mat3, Vec3};
use caustica_density::KdTree;
use caustica_density::beam::{
    BeamKernel, Clip, RaySegment, ball_weight, ellipsoid_weight, filter_bounding_radius,
    filter_matrix,
};
use caustica_density::sphere_bvh::SphereBvh;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

const N: usize = 200_000;
const K_PILOT: usize = 32;
const QUERIES: usize = 2_000;

fn photons(n: usize, seed: u64) -> Vec<Vec3> {
    let mut rng = Pcg32::new(seed, 3);
    (0..n)
        .map(|i| {
            let (a, b, c) = (rng.next_f32(), rng.next_f32(), rng.next_f32());
            if i % 5 < 3 {
                Vec3::new(2.0 * a - 1.0, 2.0 * b - 1.0, 2.0 * c - 1.0)
            } else {
                // Cone from y = 1 (a lens 0.4 m across) focused at (0.2, −0.6, 0.1).
                let y = 1.0 - 1.6 * a;
                let spread = 0.2 * (y + 0.6) / 1.6 + 0.005;
                let r = spread * (-2.0 * (1.0 - b).ln()).sqrt() * 0.5;
                let phi = std::f32::consts::TAU * c;
                let axis =
                    Vec3::new(0.2, -0.6, 0.1).lerp(Vec3::new(0.0, 1.0, 0.0), (1.0 - y) / 1.6);
                Vec3::new(axis.x + r * phi.cos(), y, axis.z + r * phi.sin())
            }
        })
        .collect()
}

fn pilot_radii(pts: &[Vec3]) -> Vec<f32> {
    let tree = KdTree::build(pts);
    let mut buf = Vec::new();
    pts.iter()
        .map(|p| {
            tree.knn(*p, K_PILOT + 1, f32::INFINITY, &mut buf);
            buf[buf.len() - 1].dist2.sqrt()
        })
        .collect()
}

fn segments(seed: u64) -> Vec<RaySegment> {
    let mut rng = Pcg32::new(seed, 5);
    let cam = Vec3::new(0.3, 0.2, -5.0);
    (0..QUERIES)
        .map(|_| {
            let target = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0;
            let dir = (target - cam).normalize();
            // To the cube's far face z = 1.
            RaySegment::new(cam, dir, 0.0, (1.0 - cam.z) / dir.z)
        })
        .collect()
}

/// A random filter matrix with largest semi-axis `r`: semi-axes `r`, `r·s₂`, `r·s₃`
/// (s ∈ [0.2, 1]) along a random orthonormal frame.
fn random_filter(rng: &mut Pcg32, r: f32) -> Mat3 {
    loop {
        let u = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0;
        if u.length_squared() < 0.01 {
            continue;
        }
        let u = u.normalize();
        let v = u.any_orthonormal_vector();
        let w = u.cross(v);
        let du = u * 2.0 * r;
        let dv = v * 2.0 * r * (0.2 + 0.8 * rng.next_f32());
        let dw = w * 2.0 * r * (0.2 + 0.8 * rng.next_f32());
        if let Some(m) = filter_matrix(du, dv, dw) {
            return m;
        }
    }
}

fn bench(c: &mut Criterion) {
    let pts = photons(N, 1);
    let radii = pilot_radii(&pts);
    let segs = segments(2);
    let mut sorted = radii.clone();
    sorted.sort_unstable_by(f32::total_cmp);
    println!(
        "pilot radii (k = {K_PILOT}): min {:.4} median {:.4} max {:.4} m",
        sorted[0],
        sorted[N / 2],
        sorted[N - 1]
    );

    let mut g = c.benchmark_group("beam_bvh_build_200k");
    g.sample_size(10);
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("sphere_bvh", |b| {
        b.iter(|| black_box(SphereBvh::build(black_box(&pts), black_box(&radii))))
    });
    g.finish();

    let bvh = SphereBvh::build(&pts, &radii);
    let mut crossings = 0usize;
    for s in &segs {
        bvh.for_each_crossing(s, |_, _, _| crossings += 1);
    }
    println!(
        "index: {:.1} bytes/photon; {:.0} photons crossed per segment on average",
        bvh.memory_bytes() as f64 / N as f64,
        crossings as f64 / QUERIES as f64
    );

    let mut rng = Pcg32::new(3, 7);
    let filters: Vec<Mat3> = radii.iter().map(|&r| random_filter(&mut rng, r)).collect();
    let bounds: Vec<f32> = filters
        .iter()
        .map(|m| filter_bounding_radius(*m).expect("regular"))
        .collect();
    let ebvh = SphereBvh::build(&pts, &bounds);

    let mut g = c.benchmark_group("beam_query_200k");
    g.sample_size(10);
    g.throughput(Throughput::Elements(QUERIES as u64));
    g.bench_function("index_only", |b| {
        b.iter(|| {
            let mut n = 0u32;
            for s in &segs {
                bvh.for_each_crossing(s, |_, _, _| n += 1);
            }
            black_box(n)
        })
    });
    g.bench_function("ball_epanechnikov_clipped", |b| {
        b.iter(|| {
            let mut sum = 0.0f32;
            for s in &segs {
                bvh.for_each_crossing(s, |_, c, r| {
                    if let Some(h) = ball_weight(BeamKernel::Epanechnikov, s, c, r, Clip::Exact) {
                        sum += h.weight / (r * r * r);
                    }
                });
            }
            black_box(sum)
        })
    });
    g.bench_function("ellipsoid_epanechnikov_clipped", |b| {
        b.iter(|| {
            let mut sum = 0.0f32;
            for s in &segs {
                ebvh.for_each_crossing(s, |i, c, _| {
                    let i = i as usize;
                    let k = BeamKernel::Epanechnikov;
                    if let Some(h) = ellipsoid_weight(k, s, c, filters[i], Clip::Exact) {
                        sum += h.weight * h.t;
                    }
                });
            }
            black_box(sum)
        })
    });
    g.finish();

    // Every photon against every segment: the baseline the index is for (200 segments).
    let mut g = c.benchmark_group("beam_query_200k_brute_force");
    g.sample_size(10);
    g.throughput(Throughput::Elements((QUERIES / 10) as u64));
    g.bench_function("ball_epanechnikov_clipped", |b| {
        b.iter(|| {
            let mut sum = 0.0f32;
            for s in segs.iter().take(QUERIES / 10) {
                for i in 0..N {
                    if let Some(h) =
                        ball_weight(BeamKernel::Epanechnikov, s, pts[i], radii[i], Clip::Exact)
                    {
                        sum += h.weight;
                    }
                }
            }
            black_box(sum)
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
