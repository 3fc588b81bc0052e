//! Photon-map k-d tree: our [`KdTree`] against the `kiddo` crate (v6, `ImmutableKdTree<f32, 3>`,
//! its recommended immutable layout) on 10⁶ photon-like points.
//!
//! Photons lie on surfaces, so the points are not a uniform 3-D cloud: 70 % lie on a floor
//! plane (half of them in a tight Gaussian "caustic" blob, half uniform), the rest on two walls.
//! Queries are taken at the positions of other photons (estimates are made on surfaces where
//! photons are), in a fixed pseudo-random order.
//!
//! Run: `cargo bench -p caustica-density --bench kdtree`. Everything is single-threaded except
//! our build (rayon over subtrees; kiddo's build is single-threaded), which is also measured
//! with one thread.
//!
//! Fairness: our query writes into a caller-owned buffer; kiddo's `nearest_n` returns a fresh
//! `Vec` per query. That is each library's intended use, so it is what is compared.

use std::hint::black_box;
use std::num::NonZero;

use caustica_core::Vec3;
use caustica_core::sampling::Pcg32;
use caustica_density::KdTree;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use kiddo::{ImmutableKdTree, SquaredEuclidean};

const N: usize = 1_000_000;
const QUERIES: usize = 2_000;

fn photon_like_points(n: usize, seed: u64) -> Vec<Vec3> {
    let mut rng = Pcg32::new(seed, 7);
    let mut pts = Vec::with_capacity(n);
    for i in 0..n {
        let (a, b) = (rng.next_f32(), rng.next_f32());
        let p = match i % 10 {
            // Caustic blob on the floor: Box–Muller Gaussian, σ = 5 cm.
            0..=3 => {
                let r = 0.05 * (-2.0 * (1.0 - a).ln()).sqrt();
                let t = std::f32::consts::TAU * b;
                Vec3::new(0.3 + r * t.cos(), 0.0, -0.2 + r * t.sin())
            }
            4..=6 => Vec3::new(4.0 * a - 2.0, 0.0, 4.0 * b - 2.0),
            7 | 8 => Vec3::new(4.0 * a - 2.0, 2.0 * b, -2.0),
            _ => Vec3::new(-2.0, 2.0 * a, 4.0 * b - 2.0),
        };
        pts.push(p);
    }
    pts
}

fn queries(pts: &[Vec3]) -> Vec<Vec3> {
    let mut rng = Pcg32::new(99, 1);
    (0..QUERIES)
        .map(|_| pts[(rng.next_u32() as usize) % pts.len()] + Vec3::new(1e-4, 0.0, -1e-4))
        .collect()
}

fn bench(c: &mut Criterion) {
    let pts = photon_like_points(N, 1);
    let arr: Vec<[f32; 3]> = pts.iter().map(|p| p.to_array()).collect();
    let qs = queries(&pts);
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("thread pool");

    let mut g = c.benchmark_group("kdtree_build_1M");
    g.sample_size(10);
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("caustica_1_thread", |b| {
        b.iter(|| one_thread.install(|| black_box(KdTree::build(black_box(&pts)))))
    });
    g.bench_function("caustica_all_threads", |b| {
        b.iter(|| black_box(KdTree::build(black_box(&pts))))
    });
    g.bench_function("kiddo", |b| {
        b.iter(|| {
            black_box(ImmutableKdTree::<f32, 3>::new_from_slice(black_box(&arr)).expect("kiddo"))
        })
    });
    g.finish();

    let ours = KdTree::build(&pts);
    let theirs = ImmutableKdTree::<f32, 3>::new_from_slice(&arr).expect("kiddo");
    // Both must find the same k-th distance, or the comparison is meaningless.
    for &k in &[50usize, 500] {
        let mut buf = Vec::new();
        for q in qs.iter().take(100) {
            ours.knn(*q, k, f32::INFINITY, &mut buf);
            let r = theirs
                .query(&q.to_array())
                .nearest_n::<SquaredEuclidean<f32>>(NonZero::new(k).expect("k > 0"))
                .execute();
            let (a, b) = (buf[k - 1].dist2, r[k - 1].distance);
            assert!((a - b).abs() <= 1e-6 * a.max(1e-12), "k={k}: {a} vs {b}");
        }
    }
    println!(
        "memory: caustica {:.1} bytes/point (positions + indices + split axes)",
        ours.memory_bytes() as f64 / N as f64
    );

    for &k in &[50usize, 500] {
        let mut g = c.benchmark_group(format!("knn_1M_k{k}"));
        g.sample_size(10);
        g.throughput(Throughput::Elements(QUERIES as u64));
        g.bench_function("caustica", |b| {
            let mut buf = Vec::new();
            b.iter(|| {
                let mut s = 0.0f32;
                for q in &qs {
                    ours.knn(*q, k, f32::INFINITY, &mut buf);
                    s += buf[buf.len() - 1].dist2;
                }
                black_box(s)
            })
        });
        g.bench_function("caustica_unsorted", |b| {
            let mut buf = Vec::new();
            b.iter(|| {
                let mut s = 0.0f32;
                for q in &qs {
                    ours.knn_unsorted(*q, k, f32::INFINITY, &mut buf);
                    s += buf[0].dist2;
                }
                black_box(s)
            })
        });
        g.bench_function("kiddo", |b| {
            let kk = NonZero::new(k).expect("k > 0");
            b.iter(|| {
                let mut s = 0.0f32;
                for q in &qs {
                    let r = theirs
                        .query(&q.to_array())
                        .nearest_n::<SquaredEuclidean<f32>>(kk)
                        .execute();
                    s += r[r.len() - 1].distance;
                }
                black_box(s)
            })
        });
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
