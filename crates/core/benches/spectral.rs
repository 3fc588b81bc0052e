//! Spectral-mode foundations (`caustica_core::spectral`): the cost of building the RGB → spectrum
//! coefficient table (Jakob and Hanika 2019, pbrt-v4's layout) at the resolution renders use and
//! one above, of upsampling an RGB (table lookup, and the exact Newton fit), of evaluating an
//! upsampled spectrum at the three wavelengths of a path, of hero wavelength sampling and of the
//! film's spectral → linear sRGB conversion.
//!
//! Run: `cargo bench -p caustica-core --bench spectral`. Per-call benchmarks run over 1024
//! inputs from a fixed-seed generator (reported per element). The table build uses three
//! threads (one per sub-table).

use std::hint::black_box;

use caustica_core::Spectrum;
use caustica_core::sampling::Pcg32;
use caustica_core::spectral::upsample::TABLE_RES;
use caustica_core::spectral::{
    RgbIlluminant, RgbReflectance, RgbToSpectrumTable, SampledWavelengths, srgb_table,
};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

const N: usize = 1024;

fn inputs() -> (Vec<[f32; 3]>, Vec<f32>) {
    let mut rng = Pcg32::new(22, 9);
    let rgbs = (0..N)
        .map(|_| [rng.next_f32(), rng.next_f32(), rng.next_f32()])
        .collect();
    let us = (0..N).map(|_| rng.next_f32()).collect();
    (rgbs, us)
}

fn bench(c: &mut Criterion) {
    let (rgbs, us) = inputs();
    srgb_table(); // built once, outside the per-call measurements

    let mut g = c.benchmark_group("spectral_table_build");
    g.sample_size(10);
    for res in [TABLE_RES, 48] {
        g.bench_function(format!("res_{res}"), |b| {
            b.iter(|| RgbToSpectrumTable::build(black_box(res)))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("spectral");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("rgb_reflectance_new", |b| {
        b.iter(|| {
            rgbs.iter()
                .map(|&c| RgbReflectance::new(black_box(c)).coefficients()[2])
                .sum::<f32>()
        })
    });
    g.bench_function("rgb_illuminant_new", |b| {
        b.iter(|| {
            rgbs.iter()
                .map(|&c| RgbIlluminant::new(black_box(c)).eval(550.0))
                .sum::<f32>()
        })
    });
    let refl: Vec<RgbReflectance> = rgbs.iter().map(|&c| RgbReflectance::new(c)).collect();
    let wls: Vec<SampledWavelengths> = us
        .iter()
        .map(|&u| SampledWavelengths::sample_visible(u))
        .collect();
    g.bench_function("rgb_reflectance_eval", |b| {
        b.iter(|| {
            refl.iter()
                .zip(&us)
                .map(|(s, &u)| s.eval(black_box(360.0 + 470.0 * u)))
                .sum::<f32>()
        })
    });
    g.bench_function("rgb_reflectance_sample_3_wavelengths", |b| {
        b.iter(|| {
            refl.iter()
                .zip(&wls)
                .map(|(s, wl)| s.sample(black_box(wl)))
                .sum::<Spectrum>()
        })
    });
    g.bench_function("sample_visible", |b| {
        b.iter(|| {
            us.iter()
                .map(|&u| SampledWavelengths::sample_visible(black_box(u)).lambda[2])
                .sum::<f32>()
        })
    });
    g.bench_function("to_linear_srgb", |b| {
        b.iter(|| {
            wls.iter()
                .zip(&rgbs)
                .map(|(wl, &c)| wl.to_linear_srgb(black_box(Spectrum::from_rgb(c))))
                .sum::<Spectrum>()
        })
    });
    g.finish();

    let mut g = c.benchmark_group("spectral_exact_fit");
    g.throughput(Throughput::Elements(64));
    g.bench_function("rgb_reflectance_new_exact", |b| {
        b.iter(|| {
            rgbs[..64]
                .iter()
                .map(|&c| RgbReflectance::new_exact(black_box(c)).coefficients()[2])
                .sum::<f32>()
        })
    });
    g.finish();
}

criterion_group!(spectral, bench);
criterion_main!(spectral);
