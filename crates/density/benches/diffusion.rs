//! Diffusion-based estimation (seed 000 ch. 4) against the plain k-NN estimate (eq. 3.2) on
//! 10⁵ and 10⁶ photon-like points: the cost of the two pre-passes (gradient at the noise scale
//! at every photon, then the eigenvalue normaliser) and of one estimate.
//!
//! Points: piecewise-uniform photons on surfaces with their normals — 70 % on a 4 × 4 m floor,
//! 15 % on each of two 4 × 2 m walls (densities within a factor 2.3 of each other), the kind of
//! map a fixed bandwidth suits. Queries at 2000 photon positions. The diffusion bandwidth is the
//! median 50-NN radius (the `dpm` default with k = 50), so estimates gather about as many
//! photons as the k = 50 k-NN; noise scale h/2, q = 0.2, α = 1.
//!
//! A fixed bandwidth costs in proportion to the local photon density: on the k-d tree bench's
//! layout, with 40 % of the photons in a 5 cm caustic blob, the median-radius bandwidth gathers
//! ~30 000 photons per estimate in the blob and one estimate costs 60× a k = 50 k-NN estimate
//! (measured at 10⁵ photons, 2026-12-01). That is the price of eq. 4.19's fixed support; pass a
//! smaller `--bandwidth` for such maps.
//!
//! Run: `cargo bench -p caustica-density --bench diffusion`. Single-threaded throughout (the
//! pre-pass is parallel in use; here a one-thread pool makes the ratio machine-independent).

use std::hint::black_box;

use caustica_core::Vec3;
use caustica_core::sampling::Pcg32;
use caustica_density::diffusion::{DiffusionEstimator, DiffusionParams};
use caustica_density::estimator::{
    Estimator, EstimatorSpec, PointSet, Query, Scratch, WeightedPoints, median_knn_radius,
};
use caustica_density::kernel::Kernel;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

const QUERIES: usize = 2_000;
const K: usize = 50;

fn photon_like(n: usize, seed: u64) -> WeightedPoints {
    let mut rng = Pcg32::new(seed, 7);
    let mut p = Vec::with_capacity(n);
    let mut nrm = Vec::with_capacity(n);
    for i in 0..n {
        let (a, b) = (rng.next_f32(), rng.next_f32());
        let (x, m) = match i % 20 {
            0..=13 => (Vec3::new(4.0 * a - 2.0, 0.0, 4.0 * b - 2.0), Vec3::Y),
            14..=16 => (Vec3::new(4.0 * a - 2.0, 2.0 * b, -2.0), Vec3::Z),
            _ => (Vec3::new(-2.0, 2.0 * a, 4.0 * b - 2.0), Vec3::X),
        };
        p.push(x);
        nrm.push(m);
    }
    WeightedPoints::new(p, nrm, vec![1.0 / n as f32; n])
}

fn queries(pts: &WeightedPoints) -> Vec<Query> {
    let mut rng = Pcg32::new(99, 1);
    (0..QUERIES)
        .map(|_| {
            let i = rng.next_u32() % pts.len() as u32;
            Query::new(pts.position(i) + Vec3::new(1e-4, 0.0, -1e-4), pts.normal(i))
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("one-thread pool");
    for n in [100_000usize, 1_000_000] {
        let pts = photon_like(n, 1);
        let qs = queries(&pts);
        let h = median_knn_radius(&pts, K).expect("points");
        let params = DiffusionParams::new(h);
        let knn = Estimator::prepare(
            &EstimatorSpec::Knn {
                k: K,
                max_radius: None,
                kernel: Kernel::Epanechnikov,
            },
            &pts,
        );
        let dpm = pool.install(|| Estimator::Diffusion(DiffusionEstimator::new(&pts, params)));
        let mut scratch = Scratch::default();
        let per_query = |e: &Estimator, scratch: &mut Scratch| {
            let mut count = 0usize;
            for q in &qs {
                e.weights(&pts, q, scratch, |_, _| count += 1);
            }
            count as f64 / qs.len() as f64
        };
        eprintln!(
            "{n} points: bandwidth {h:.4}, points per estimate: knn {:.1}, dpm {:.1}",
            per_query(&knn, &mut scratch),
            per_query(&dpm, &mut scratch)
        );
        let mut g = c.benchmark_group(format!("diffusion-{n}"));
        g.sample_size(10);
        g.throughput(Throughput::Elements(QUERIES as u64));
        g.bench_function("knn-estimate", |b| {
            b.iter(|| {
                for q in &qs {
                    black_box(knn.density(&pts, q, &mut scratch));
                }
            })
        });
        g.bench_function("dpm-estimate", |b| {
            b.iter(|| {
                for q in &qs {
                    black_box(dpm.density(&pts, q, &mut scratch));
                }
            })
        });
        g.throughput(Throughput::Elements(n as u64));
        g.bench_function("dpm-prepass", |b| {
            b.iter(|| pool.install(|| black_box(DiffusionEstimator::new(&pts, params))))
        });
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
