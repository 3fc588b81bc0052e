//! Photon differential splatting's inner loop (seed 002 sec. 3.3) against photon differential
//! mapping's (seed 002 eq. 10 evaluated by gathering): the same footprints and the same eye
//! points, the two evaluation orders of one sum.
//!
//! Eye vertices: a jittered 512 × 512 grid on a 1 m × 1 m Lambertian floor (262 144 vertices,
//! ~2 mm apart, as a 256² image at 4 spp). Photons: 20 000 footprints at uniform positions with
//! random orientation, semi-axes a ∈ [4, 12] mm and b = a · [0.25, 1] (anisotropic, like the
//! case studies' footprints), so a footprint covers ~25 vertices on average.
//!
//! * `splat`: every photon splatted onto the eye map's tiles (`EyeTile::splat`), into per-vertex
//!   accumulators — what `pds` does per batch.
//! * `gather`: every eye vertex gathers the footprints that reach it from a `PdmMap` (radius
//!   buckets) — what `pdm` does per camera sample.
//!
//! Throughput is in splats (vertex–footprint contributions); both produce the same number.
//! Both loops are single-threaded (no rayon inside), so the ratio does not depend on the number
//! of cores.
//! Run: `cargo bench -p caustica-render --bench splat`.

use std::hint::black_box;

use caustica_core::sampling::Pcg32;
use caustica_core::{Frame, Spectrum, Vec3};
use caustica_differentials::Footprint;
use caustica_render::integrator::photon_splatting::{ChunkedSum, splat_footprint};
use caustica_render::photon::differential::{
    DiffPhoton, FootprintFilter, PdmMap, TracedDiffPhotons,
};
use caustica_render::photon::eye_map::{EyeMap, EyeVertex};
use caustica_scene::bsdf::{Bsdf, Lambertian, TransportMode};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

const GRID: usize = 512;
const PHOTONS: usize = 20_000;

fn eye_vertices() -> Vec<EyeVertex> {
    let mut rng = Pcg32::new(3, 1);
    let frame = Frame::from_normal(Vec3::Y);
    let mut v = Vec::with_capacity(GRID * GRID);
    for y in 0..GRID {
        for x in 0..GRID {
            let p = Vec3::new(
                (x as f32 + rng.next_f32()) / GRID as f32,
                0.0,
                (y as f32 + rng.next_f32()) / GRID as f32,
            );
            v.push(EyeVertex {
                p,
                n: Vec3::Y,
                wo: frame.to_local(Vec3::new(0.3, 1.0, 0.2).normalize()),
                frame,
                bsdf: Bsdf::Lambertian(Lambertian::new(Spectrum::splat(0.6))),
                beta: Spectrum::ONE,
                pixel: (y * GRID + x) as u32,
            });
        }
    }
    v
}

fn photons() -> Vec<DiffPhoton> {
    let mut rng = Pcg32::new(5, 2);
    (0..PHOTONS)
        .map(|_| {
            let c = Vec3::new(rng.next_f32(), 0.0, rng.next_f32());
            let phi = rng.next_f32() * std::f32::consts::TAU;
            let a = 0.004 + 0.008 * rng.next_f32();
            let b = a * (0.25 + 0.75 * rng.next_f32());
            let (s, co) = phi.sin_cos();
            let du = Vec3::new(co, 0.0, s) * (2.0 * a);
            let dv = Vec3::new(-s, 0.0, co) * (2.0 * b);
            DiffPhoton {
                footprint: Footprint::new(c, du, dv, Vec3::Y).expect("a valid footprint"),
                wi: Vec3::new(-0.2, 1.0, 0.1).normalize(),
                n: Vec3::Y,
                flux: Spectrum::splat(1e-4),
                depth: 2,
                dt: Vec3::ZERO,
            }
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    {
        let vertices = eye_vertices();
        let photons = photons();
        let filter = FootprintFilter::default();
        let eye = EyeMap::new(vertices.clone());
        let pdm = PdmMap::with_filter(
            TracedDiffPhotons::given(photons.clone(), PHOTONS as u64),
            filter,
        );
        let mut acc: Vec<Vec<ChunkedSum>> = eye
            .tiles
            .iter()
            .map(|t| vec![ChunkedSum::default(); t.len()])
            .collect();
        let splat = |acc: &mut Vec<Vec<ChunkedSum>>| {
            let mut n = 0usize;
            let boxed: Vec<(&DiffPhoton, Vec3, Vec3)> = photons
                .iter()
                .filter_map(|ph| filter.bounds(ph).map(|(lo, hi)| (ph, lo, hi)))
                .collect();
            for (tile, acc) in eye.tiles.iter().zip(acc.iter_mut()) {
                for &(ph, lo, hi) in &boxed {
                    tile.for_each_in_box(lo, hi, |i, v| {
                        n += splat_footprint(&filter, ph, 0, v, &mut acc[i]) as usize;
                    });
                }
            }
            n
        };
        let gather = || {
            let mut n = 0usize;
            let mut total = Spectrum::ZERO;
            for v in &vertices {
                pdm.for_each(v.p, v.n, |ph, w| {
                    let f = v
                        .bsdf
                        .eval(v.wo, v.frame.to_local(ph.wi), TransportMode::Radiance);
                    total += f * ph.flux * w;
                    n += 1;
                });
            }
            (n, total)
        };
        let splats = splat(&mut acc);
        let (gathered, _) = gather();
        assert_eq!(splats, gathered, "both orders evaluate the same terms");
        eprintln!(
            "{splats} splats ({:.1} per photon)",
            splats as f64 / PHOTONS as f64
        );
        let mut g = c.benchmark_group("pds_vs_pdm");
        g.throughput(Throughput::Elements(splats as u64));
        g.sample_size(10);
        g.bench_function("splat", |b| b.iter(|| black_box(splat(&mut acc))));
        g.bench_function("gather", |b| b.iter(|| black_box(gather())));
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
