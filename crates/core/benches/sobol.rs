//! Owen-scrambled Sobol points as a path draws them: 1024 streams (random point index and
//! seed), each drawing its first eight dimension sets (32 numbers), with the crate's
//! `sobol_burley::sample_4d` and with `caustica_core::sampling::sobol` (the index shuffled
//! once per stream, the generator matrices from nibble tables). Both give the same bits.
//!
//! Run: `cargo bench -p caustica-core --bench sobol` (reported per stream).

use std::hint::black_box;

use caustica_core::sampling::{Pcg32, sobol};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

const STREAMS: usize = 1024;
const SETS: u32 = 8;

fn bench(c: &mut Criterion) {
    let mut rng = Pcg32::new(5, 77);
    let streams: Vec<(u32, u32)> = (0..STREAMS)
        .map(|_| (rng.next_u32() & 0xFFFF, rng.next_u32()))
        .collect();
    let mut g = c.benchmark_group("sobol_4d_x8");
    g.throughput(Throughput::Elements(STREAMS as u64));
    g.bench_function("sobol_burley", |b| {
        b.iter(|| {
            let mut acc = 0.0f32;
            for &(index, seed) in &streams {
                for set in 0..SETS {
                    acc += sobol_burley::sample_4d(black_box(index), set, seed)[0];
                }
            }
            acc
        })
    });
    g.bench_function("tables", |b| {
        b.iter(|| {
            let mut acc = 0.0f32;
            for &(index, seed) in &streams {
                let shuffled = sobol::shuffled_index(black_box(index), seed);
                for set in 0..SETS {
                    acc += sobol::sample_4d(shuffled, set, seed)[0];
                }
            }
            acc
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
