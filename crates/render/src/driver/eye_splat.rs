//! The eye-splat driver: the pipeline of photon differential splatting (seed 002 sec. 3.3),
//! written once for every method that splats light-side records onto camera-side vertices.
//!
//! 1. **Eye pass** ([`eye_pass`]): the pixel driver runs the method's camera paths and each
//!    sample records its eye vertices ([`EyeVertex`]) into an [`EyeMap`] of spatial tiles.
//! 2. **Batches** ([`splat_batches`]): chunks of light paths are traced in parallel by the
//!    method's [`SplatRule::trace_chunk`]; their photons, concatenated in path order, form a
//!    batch; every tile (in parallel) takes the batch's photons in order, finds its vertices in
//!    each photon's box ([`SplatRule::bounds`]) and adds the photon's contribution to their own
//!    accumulators ([`SplatRule::splat`]); after the batch each vertex may update its state
//!    ([`SplatRule::end_of_batch`], e.g. a progressive radius). No vertex is written by two
//!    threads and each sums its photons in path order, so the image is independent of the
//!    thread count and of the batch size.
//! 3. **Resolve** ([`resolve`]): each vertex adds what it gathered to its pixel's sample sum
//!    ([`SplatRule::resolve`]).
//!
//! One time budget covers all three: each runs in its own [`Stage`] of the render, and the
//! batches stop when their share of the budget is spent (the rule then knows how many chunks
//! were done and scales accordingly).

use crate::control::Stage;
use crate::driver::pixels::render_pixels_collect;
use crate::exact_sum::ExactSum;
use crate::film::Film;
use crate::filter::Filter;
use crate::options::RenderOptions;
use crate::photon::eye_map::{EyeMap, EyeVertex};
use crate::stats::RenderStats;
use caustica_core::sampling::Sampler;
use caustica_core::{Spectrum, Vec2, Vec3};
use rayon::prelude::*;
use std::ops::AddAssign;

/// A method's rule over the eye-splat driver.
pub trait SplatRule: Sync {
    /// A light-side record that splats (a photon with its footprint, …).
    type Photon: Send + Sync;
    /// What each eye vertex accumulates.
    type Acc: Clone + Send + Sync;
    /// Counts of one chunk of light paths, for the method's report.
    type Totals: Default + AddAssign + Send;

    /// The accumulator of a vertex before any photon.
    fn empty(&self) -> Self::Acc;
    /// Chunks of light paths in the pass.
    fn chunks(&self) -> u64;
    /// Traces chunk `c` of the light paths; its photons in path order.
    fn trace_chunk(&self, c: u64, stats: &mut RenderStats) -> (Vec<Self::Photon>, Self::Totals);
    /// The box `[lo, hi]` (m) of the points `photon` can reach, `None` if it reaches none.
    fn bounds(&self, photon: &Self::Photon) -> Option<(Vec3, Vec3)>;
    /// Adds `photon`'s contribution at vertex `v` to `acc`; true if it contributed.
    fn splat(&self, photon: &Self::Photon, v: &EyeVertex, acc: &mut Self::Acc) -> bool;
    /// Called for every vertex after each batch (a progressive method updates its statistics
    /// here); does nothing by default.
    fn end_of_batch(&self, v: &EyeVertex, acc: &mut Self::Acc) {
        let _ = (v, acc);
    }
    /// Radiance sum (W/m²/sr, times the sample's count of 1) that vertex `v` adds to its pixel
    /// after the first `chunks_done` chunks. Exact, so a rule whose accumulator is an exact sum
    /// of fully weighted contributions can return it unrounded: its pixels then do not depend
    /// on how the light paths were split (into batches, or into shards).
    fn resolve(&self, v: &EyeVertex, acc: &Self::Acc, chunks_done: u64) -> [ExactSum; 3];
}

/// Runs the eye pass into `film`: `sample(sampler, raster, pixel, vertices, stats)` renders a
/// camera sample (radiance it adds directly, W/m²/sr) and records its eye vertices. Returns the
/// eye map and the statistics.
pub fn eye_pass<F>(
    film: &mut Film,
    filter: &Filter,
    opts: &RenderOptions,
    stage: &Stage,
    sample: F,
) -> (EyeMap, RenderStats)
where
    F: Fn(&mut Sampler, Vec2, u32, &mut Vec<EyeVertex>, &mut RenderStats) -> Spectrum + Sync,
{
    let (stats, vertices) = render_pixels_collect(film, filter, opts, stage, sample);
    (EyeMap::new(vertices), stats)
}

/// What the batches did.
pub struct Splatted<R: SplatRule> {
    /// Per tile, per vertex: the accumulators.
    pub acc: Vec<Vec<R::Acc>>,
    /// Chunks of light paths traced and splatted (all of the rule's once a shard has done its
    /// range).
    pub chunks_done: u64,
    /// The rule's counts over those chunks.
    pub totals: R::Totals,
    /// (photon, vertex) pairs that contributed.
    pub splats: u64,
    pub stats: RenderStats,
}

/// Traces the rule's light paths in batches and splats each batch onto `eye` (see the module
/// docs) until every chunk is done or `stage` must end; checkpoints hand the callback `film`
/// with the splats so far resolved. A shard splats only its range of the chunks
/// ([`crate::shard`]): since each vertex's accumulator is an exact sum, the shards' sums add up
/// to the whole render's.
pub fn splat_batches<R: SplatRule>(
    film: &Film,
    eye: &EyeMap,
    rule: &R,
    stage: &Stage,
    shard: Option<crate::shard::Shard>,
) -> Splatted<R> {
    let mut acc: Vec<Vec<R::Acc>> = eye
        .tiles
        .iter()
        .map(|t| vec![rule.empty(); t.len()])
        .collect();
    let mut totals = R::Totals::default();
    let mut stats = RenderStats::default();
    let mut splats = 0u64;
    let all = rule.chunks();
    let range = shard.map_or(0..all, |s| s.range(all));
    let (first, chunks) = (range.start, range.end);
    // Chunks traced concurrently per batch (any number gives the same image: each vertex sums
    // its photons in path order).
    let wave = (4 * rayon::current_num_threads()).max(1) as u64;
    let mut c = first;
    while c < chunks {
        let end = (c + wave).min(chunks);
        let parts: Vec<(Vec<R::Photon>, R::Totals, RenderStats)> = (c..end)
            .into_par_iter()
            .map(|i| {
                let mut st = RenderStats::default();
                let (photons, tot) = rule.trace_chunk(i, &mut st);
                (photons, tot, st)
            })
            .collect();
        let mut batch = Vec::new();
        for (photons, tot, st) in parts {
            batch.extend(photons);
            totals += tot;
            stats.rays += st.rays;
            stats.nonfinite += st.nonfinite;
        }
        splats += splat_batch(eye, rule, &batch, &mut acc);
        c = end;
        stage.report(
            (c - first) as f64 / (chunks - first).max(1) as f64,
            c - first,
        );
        if c < chunks
            && stage.end_of_pass_with(|| {
                let mut partial = film.clone();
                resolve(&mut partial, eye, rule, &acc, c);
                partial
            })
        {
            break;
        }
    }
    Splatted {
        acc,
        // A complete shard stands for the whole pass (its splats carry the flux of all N paths).
        chunks_done: if c >= chunks { all } else { c },
        totals,
        splats,
        stats,
    }
}

/// Splats `photons` in order onto every tile (tiles in parallel, each into its own
/// accumulators `acc[tile]`), then lets every vertex end the batch; returns the number of
/// splats.
fn splat_batch<R: SplatRule>(
    eye: &EyeMap,
    rule: &R,
    photons: &[R::Photon],
    acc: &mut [Vec<R::Acc>],
) -> u64 {
    // Each photon's box, computed once (every tile tests it).
    let boxed: Vec<(&R::Photon, Vec3, Vec3)> = photons
        .par_iter()
        .filter_map(|ph| rule.bounds(ph).map(|(lo, hi)| (ph, lo, hi)))
        .collect();
    eye.tiles
        .par_iter()
        .zip(acc.par_iter_mut())
        .map(|(tile, acc)| {
            let mut n = 0u64;
            for &(ph, lo, hi) in &boxed {
                tile.for_each_in_box(lo, hi, |i, v| {
                    n += rule.splat(ph, v, &mut acc[i]) as u64;
                });
            }
            for (v, a) in tile.vertices.iter().zip(acc.iter_mut()) {
                rule.end_of_batch(v, a);
            }
            n
        })
        .sum()
}

/// Adds what every eye vertex gathered in the first `chunks_done` chunks to its pixel's
/// camera-sample sum (exactly: the order of the vertices does not matter, so a crop window's
/// smaller eye map gives its pixels the same sums).
pub fn resolve<R: SplatRule>(
    film: &mut Film,
    eye: &EyeMap,
    rule: &R,
    acc: &[Vec<R::Acc>],
    chunks_done: u64,
) {
    for (tile, acc) in eye.tiles.iter().zip(acc) {
        for (v, a) in tile.vertices.iter().zip(acc) {
            let add = rule.resolve(v, a, chunks_done);
            let px = &mut film.sum[v.pixel as usize];
            for k in 0..3 {
                px[k] += add[k];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{Clock, RenderControl};
    use caustica_core::Frame;
    use caustica_scene::bsdf::{Bsdf, Lambertian};

    /// Photons are points; a vertex records the indices of the photons within `R` of it, and
    /// `u32::MAX` at the end of every batch.
    struct Points {
        photons: Vec<Vec3>,
        per_chunk: usize,
    }

    const R: f32 = 0.15;

    impl SplatRule for Points {
        type Photon = (u32, Vec3);
        type Acc = Vec<u32>;
        type Totals = u64;
        fn empty(&self) -> Vec<u32> {
            Vec::new()
        }
        fn chunks(&self) -> u64 {
            self.photons.len().div_ceil(self.per_chunk) as u64
        }
        fn trace_chunk(&self, c: u64, _: &mut RenderStats) -> (Vec<(u32, Vec3)>, u64) {
            let lo = c as usize * self.per_chunk;
            let hi = (lo + self.per_chunk).min(self.photons.len());
            let out: Vec<(u32, Vec3)> = (lo..hi).map(|i| (i as u32, self.photons[i])).collect();
            let n = out.len() as u64;
            (out, n)
        }
        fn bounds(&self, p: &(u32, Vec3)) -> Option<(Vec3, Vec3)> {
            Some((p.1 - R, p.1 + R))
        }
        fn splat(&self, p: &(u32, Vec3), v: &EyeVertex, acc: &mut Vec<u32>) -> bool {
            let hit = (v.p - p.1).length() < R;
            if hit {
                acc.push(p.0);
            }
            hit
        }
        fn end_of_batch(&self, _: &EyeVertex, acc: &mut Vec<u32>) {
            acc.push(u32::MAX);
        }
        fn resolve(&self, _: &EyeVertex, acc: &Vec<u32>, _: u64) -> [ExactSum; 3] {
            let n = acc.iter().filter(|&&i| i != u32::MAX).count() as f64;
            [ExactSum::from_f64(n), ExactSum::ZERO, ExactSum::ZERO]
        }
    }

    fn vertex(p: Vec3, pixel: u32) -> EyeVertex {
        let frame = Frame::from_normal(Vec3::Y);
        EyeVertex {
            p,
            n: Vec3::Y,
            wo: Vec3::Z,
            frame,
            bsdf: Bsdf::Lambertian(Lambertian::new(Spectrum::splat(0.5))),
            beta: Spectrum::ONE,
            pixel,
        }
    }

    /// A pseudo-random point in the unit square of the plane y = 0.
    fn point(i: u32) -> Vec3 {
        let h = |k: u32| (i.wrapping_mul(2_654_435_761).wrapping_add(k) % 10_007) as f32 / 10_007.0;
        Vec3::new(h(1), 0.0, h(7_919))
    }

    /// Per pixel: the photons each vertex received and the number of batch ends it saw; the
    /// splat count; the film's sums.
    type Run = (Vec<Vec<u32>>, Vec<usize>, u64, Vec<[ExactSum; 3]>);

    fn run(threads: usize) -> Run {
        let vertices: Vec<EyeVertex> = (0..300).map(|i| vertex(point(i + 1000), i)).collect();
        let eye = EyeMap::with_tile_size(vertices, 16);
        let rule = Points {
            photons: (0..500).map(point).collect(),
            per_chunk: 7,
        };
        let opts = RenderOptions::default();
        let (clock, ctl) = (Clock::start(&opts), RenderControl::silent());
        let mut film = Film::new(300, 1);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let done = pool.install(|| splat_batches(&film, &eye, &rule, &clock.stage(&ctl), None));
        assert_eq!(done.chunks_done, rule.chunks());
        assert_eq!(done.totals, 500);
        resolve(&mut film, &eye, &rule, &done.acc, done.chunks_done);
        let mut received = vec![Vec::new(); 300];
        let mut batches = vec![0; 300];
        for (tile, acc) in eye.tiles.iter().zip(&done.acc) {
            for (v, a) in tile.vertices.iter().zip(acc) {
                received[v.pixel as usize] = a.iter().copied().filter(|&i| i != u32::MAX).collect();
                batches[v.pixel as usize] = a.iter().filter(|&&i| i == u32::MAX).count();
            }
        }
        (received, batches, done.splats, film.sum.clone())
    }

    #[test]
    fn every_vertex_receives_exactly_its_photons_in_path_order_whatever_the_threads() {
        let (one, batches_one, splats, sums) = run(1);
        // Brute force: the photons within R of each vertex, ascending.
        let mut total = 0;
        for (pixel, got) in one.iter().enumerate() {
            let v = point(pixel as u32 + 1000);
            let want: Vec<u32> = (0..500).filter(|&i| (v - point(i)).length() < R).collect();
            total += want.len() as u64;
            assert_eq!(got, &want, "vertex {pixel}");
        }
        assert!(total > 300, "the test should splat a lot: {total}");
        assert_eq!(splats, total);
        // Resolve adds each vertex's count to its own pixel.
        for (pixel, got) in one.iter().enumerate() {
            assert_eq!(sums[pixel][0].to_f64(), got.len() as f64);
        }
        // One batch end per batch, at every vertex; 2 threads batch differently (the batch holds
        // 4 chunks per thread) but give the same sums.
        let chunks = 500usize.div_ceil(7);
        assert!(batches_one.iter().all(|&b| b == chunks.div_ceil(4)));
        let (two, batches_two, _, sums_two) = run(2);
        assert_eq!(one, two);
        assert_eq!(sums, sums_two);
        assert!(batches_two.iter().all(|&b| b == chunks.div_ceil(8)));
    }
}
