//! The pixel driver: pixel-parallel camera samples. Work is split into passes of a few samples per pixel; within a
//! pass rows are rendered in parallel and each pixel's samples in index order, so the result is
//! a pure function of (scene, options, seed) whatever the thread count. Between passes the
//! driver checks the stop flag, the time budget and the checkpoint timer.
//!
//! A cropped film ([`Film::window`]) renders only its window's pixels, each with the raster
//! position and the sampler stream of its full-film pixel, so each equals the uncropped pixel.

use crate::control::Stage;
use crate::exact_sum::ExactSum;
use crate::film::Film;
use crate::filter::Filter;
use crate::options::RenderOptions;
use crate::stats::RenderStats;
use crate::transport::direct_lanes::DirectBatch;
use caustica_core::sampling::Sampler;
use caustica_core::{Spectrum, Vec2};
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

/// Target number of samples per pass (keeps passes short enough for Ctrl-C and checkpoints).
const SAMPLES_PER_PASS: u64 = 1 << 18;

/// Samples whose radiance may wait in a row's [`DirectBatch`] before it is finished: enough that
/// the lanes run full, few enough that the held terms stay in the first-level cache.
pub(crate) const WAITING_SAMPLES: usize = 32;

/// Renders into `film` by calling `sample(sampler, raster)` for every pixel sample; the closure
/// returns radiance (W/m²/sr) and must draw all its random numbers from `sampler`.
pub fn render_pixels<F>(
    film: &mut Film,
    filter: &Filter,
    opts: &RenderOptions,
    stage: &Stage,
    sample: F,
) -> RenderStats
where
    F: Fn(&mut Sampler, Vec2, &mut RenderStats) -> Spectrum + Sync,
{
    render_pixels_batched(film, filter, opts, stage, |s, raster, _, st| {
        Some(sample(s, raster, st))
    })
}

/// [`render_pixels`] whose closure may leave a sample's radiance waiting in the row's
/// [`DirectBatch`] (returning `None`): the path tracer's next-event estimates computed across
/// samples. The batch is finished every [`WAITING_SAMPLES`] waiting samples and at the row's end;
/// the film's exact sums do not depend on the order samples arrive in, so the image is the same.
pub fn render_pixels_batched<'s, F>(
    film: &mut Film,
    filter: &Filter,
    opts: &RenderOptions,
    stage: &Stage,
    sample: F,
) -> RenderStats
where
    F: Fn(&mut Sampler, Vec2, &mut DirectBatch<'s>, &mut RenderStats) -> Option<Spectrum> + Sync,
{
    let sample = |s: &mut Sampler,
                  raster,
                  _,
                  _: &mut Vec<()>,
                  batch: &mut DirectBatch<'s>,
                  st: &mut RenderStats| { sample(s, raster, batch, st) };
    let (stats, _) = render_rows(film, opts, stage, false, |r, out, st, add| {
        samples_in_order(r, filter, opts, &sample, out, st, add)
    });
    stats
}

/// [`render_pixels`] whose closure also learns the film's pixel index (`y · width + x` within
/// the film's window) and may push records into `out`; the records of all samples are returned
/// in a fixed order (pass, row, column, sample index), so they too are a pure function of the
/// seed. Photon differential splatting keeps its eye-path vertices this way. Every row is
/// rendered for its records, even those outside the film's [`Film::rows`] (whose samples are not
/// added to the film).
pub fn render_pixels_collect<F, R>(
    film: &mut Film,
    filter: &Filter,
    opts: &RenderOptions,
    stage: &Stage,
    sample: F,
) -> (RenderStats, Vec<R>)
where
    F: Fn(&mut Sampler, Vec2, u32, &mut Vec<R>, &mut RenderStats) -> Spectrum + Sync,
    R: Send,
{
    let sample =
        |s: &mut Sampler,
         raster,
         pixel,
         out: &mut Vec<R>,
         _: &mut DirectBatch,
         st: &mut RenderStats| { Some(sample(s, raster, pixel, out, st)) };
    render_rows(film, opts, stage, true, |r, out, st, add| {
        samples_in_order(r, filter, opts, &sample, out, st, add)
    })
}

/// The sampler stream ([`Sampler::pixel_stream`]) of the last pixel and block of sample
/// indices started in a row.
#[derive(Clone, Copy, Debug, Default)]
pub struct PixelStream {
    /// The full-film column and the block of sample indices (`index >> 16`).
    key: Option<(u32, u32)>,
    stream: u64,
}

/// One row's samples in a pass: pixels `0..width` of film row `y` (full-film row `fy`, first
/// full-film column `x0`), each with the sample indices `first .. first + spp`, taken pixel by
/// pixel in index order.
#[derive(Clone, Copy, Debug)]
pub struct RowSamples {
    /// The row within the film's window.
    pub y: usize,
    /// The full-film row and the full-film column of the window's first pixel.
    pub fy: u32,
    pub x0: u32,
    pub width: usize,
    /// The pass's first sample index and its samples per pixel.
    pub first: u32,
    pub spp: u32,
}

impl RowSamples {
    /// The samples in order: `(x, full-film x, sample index)` with `x` the window's column.
    pub fn iter(&self) -> impl Iterator<Item = (usize, u32, u32)> + '_ {
        (0..self.width).flat_map(move |x| {
            (self.first..self.first + self.spp).map(move |s| (x, x as u32 + self.x0, s))
        })
    }

    /// Starts `sampler` on the sample `(fx, s)` of this row (see [`RowSamples::iter`]) and draws
    /// its raster position through `filter`: the first two numbers of every camera sample.
    /// `stream` keeps the last pixel's sampler stream for the next sample of the same pixel
    /// (start it as [`PixelStream::default`]).
    #[inline]
    pub fn start(
        &self,
        sampler: &mut Sampler,
        stream: &mut PixelStream,
        filter: &Filter,
        opts: &RenderOptions,
        fx: u32,
        s: u32,
    ) -> Vec2 {
        let index = opts.first_sample.wrapping_add(s);
        let key = Some((fx, index >> 16));
        if stream.key != key {
            *stream = PixelStream {
                key,
                stream: sampler.pixel_stream(fx, self.fy, index),
            };
        }
        sampler.start_in_stream(stream.stream, index);
        let offset = filter.sample(sampler.next_2d());
        Vec2::new(fx as f32 + 0.5, self.fy as f32 + 0.5) + offset
    }
}

/// Renders into `film` with `row`, which computes the samples of a [`RowSamples`] in any order
/// and hands each sample's radiance (W/m²/sr) to `add(x, radiance)`; its random numbers must come
/// from samplers started by [`RowSamples::start`]. The film's exact sums do not depend on the
/// order, so the image is the same whatever order `row` chooses: the path tracer's lanes
/// ([`crate::integrator::path_lanes`]) take a row's samples eight at a time.
pub fn render_pixels_rows<F>(
    film: &mut Film,
    opts: &RenderOptions,
    stage: &Stage,
    row: F,
) -> RenderStats
where
    F: Fn(&RowSamples, &mut RenderStats, &mut dyn FnMut(usize, Spectrum)) + Sync,
{
    let (stats, _) = render_rows(film, opts, stage, false, |r, _: &mut Vec<()>, st, add| {
        row(r, st, add)
    });
    stats
}

/// The per-sample row of [`render_pixels_batched`] and [`render_pixels_collect`]: each sample in
/// order, radiance that waits in the row's [`DirectBatch`] delivered every
/// [`WAITING_SAMPLES`] waiting samples and at the row's end.
fn samples_in_order<'s, F, R>(
    r: &RowSamples,
    filter: &Filter,
    opts: &RenderOptions,
    sample: &F,
    out: &mut Vec<R>,
    st: &mut RenderStats,
    add: &mut dyn FnMut(usize, Spectrum),
) where
    F: Fn(
        &mut Sampler,
        Vec2,
        u32,
        &mut Vec<R>,
        &mut DirectBatch<'s>,
        &mut RenderStats,
    ) -> Option<Spectrum>,
{
    let mut sampler = Sampler::new(opts.sampler, opts.seed);
    let mut batch = DirectBatch::default();
    // The pixel (column) of each sample waiting in `batch`, in order.
    let mut waiting: Vec<usize> = Vec::new();
    let mut last_x = usize::MAX;
    let mut stream = PixelStream::default();
    for (x, fx, s) in r.iter() {
        if x != last_x {
            last_x = x;
            if waiting.len() >= WAITING_SAMPLES {
                batch.finish(st, |i, l| add(waiting[i], l));
                waiting.clear();
            }
        }
        let raster = r.start(&mut sampler, &mut stream, filter, opts, fx, s);
        let pixel = (r.y * r.width + x) as u32;
        match sample(&mut sampler, raster, pixel, out, &mut batch, st) {
            Some(l) => add(x, l),
            None => waiting.push(x),
        }
    }
    batch.finish(st, |i, l| add(waiting[i], l));
}

/// The pixel driver: rows outside [`Film::rows`] are skipped, or rendered for their records
/// only when `all_rows`; `row` renders a row's samples (see [`render_pixels_rows`]).
fn render_rows<F, R>(
    film: &mut Film,
    opts: &RenderOptions,
    stage: &Stage,
    all_rows: bool,
    row: F,
) -> (RenderStats, Vec<R>)
where
    F: Fn(&RowSamples, &mut Vec<R>, &mut RenderStats, &mut dyn FnMut(usize, Spectrum)) + Sync,
    R: Send,
{
    let mut records = Vec::new();
    let (w, h) = (film.width, film.height);
    let (x0, y0) = (film.window().x, film.window().y);
    let band = film.rows();
    // The pixels whose samples this render computes (for the progress bar and the pass size).
    let pixels = if all_rows {
        (w * h) as u64
    } else {
        (w * band.count(h)) as u64
    };
    let per_pass = (SAMPLES_PER_PASS / pixels.max(1)).clamp(1, 64) as u32;
    let mut done_spp = 0u32;
    let mut stats = RenderStats::default();
    let samples_done = AtomicU64::new(0);
    // Under a time budget: seconds per sample per pixel, measured on the passes so far.
    let mut secs_per_spp: Option<f64> = None;
    loop {
        let mut pass_spp = match (opts.time_limit, stage.time_left()) {
            // Passes that end inside the budget: one sample per pixel first, to measure, then
            // as many as the time left allows at the measured rate (at most `per_pass`; none
            // when not even one fits, so the render ends early rather than late).
            (Some(_), Some(left)) => match secs_per_spp {
                None => 1,
                Some(rate) => ((left.as_secs_f64() / rate.max(1e-9)) as u32).min(per_pass),
            },
            _ => per_pass.min(opts.spp - done_spp),
        };
        // Stopped (Ctrl-C, or the budget spent by an earlier pass) before the first pass: one
        // sample per pixel, so the image written is never empty.
        if done_spp == 0 && (stage.interrupted() || stage.out_of_time()) {
            pass_spp = pass_spp.min(1);
        }
        if pass_spp == 0 {
            break;
        }
        let first = done_spp;
        let pass_start = std::time::Instant::now();
        let rows: Vec<(RenderStats, Vec<R>)> = film
            .sum
            .par_chunks_mut(w)
            .zip(film.count.par_chunks_mut(w))
            .enumerate()
            .map(|(y, (sum_row, count_row))| {
                let mut st = RenderStats::default();
                let mut out = Vec::new();
                let keep = band.contains(y);
                if !keep && !all_rows {
                    return (st, out);
                }
                let mut nonfinite = 0u64;
                let mut add = |x: usize, l: Spectrum| {
                    if !keep {
                        return;
                    }
                    if l.is_finite() {
                        for (acc, v) in sum_row[x].iter_mut().zip(l.c) {
                            *acc += ExactSum::from_f32(v);
                        }
                    } else {
                        nonfinite += 1;
                    }
                };
                let r = RowSamples {
                    y,
                    fy: y as u32 + y0,
                    x0,
                    width: w,
                    first,
                    spp: pass_spp,
                };
                row(&r, &mut out, &mut st, &mut add);
                if keep {
                    for count in count_row.iter_mut() {
                        *count += pass_spp;
                    }
                }
                st.nonfinite += nonfinite;
                st.samples += (w as u64) * pass_spp as u64;
                let total = samples_done.fetch_add(w as u64 * pass_spp as u64, Ordering::Relaxed)
                    + w as u64 * pass_spp as u64;
                stage.report(
                    total as f64 / (pixels * opts.spp as u64).max(1) as f64,
                    total,
                );
                (st, out)
            })
            .collect();
        for (r, out) in rows {
            stats += r;
            records.extend(out);
        }
        done_spp += pass_spp;
        secs_per_spp = Some(pass_start.elapsed().as_secs_f64() / pass_spp as f64);
        if stage.end_of_pass(film) {
            break;
        }
    }
    (stats, records)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{Clock, RenderControl};
    use crate::integrator::path::{PathOnly, camera_radiance};
    use caustica_core::sampling::SamplerKind;
    use caustica_loader::builtin_scene;
    use std::sync::atomic::AtomicUsize;

    /// The path tracer's samples, left waiting in the rows' batches across samples and pixels,
    /// reach the film as the same samples computed one by one: the same sums bit for bit, so
    /// each reached its own pixel; and the same shadow rays.
    #[test]
    fn waiting_samples_reach_their_own_pixels_bit_for_bit() {
        let mut builder = builtin_scene("cornell-box").unwrap();
        let mut camera = builder.camera().unwrap().clone();
        (camera.width, camera.height) = (24, 20);
        builder.set_camera(camera);
        let scene = builder.build().unwrap();
        let opts = RenderOptions {
            spp: 5,
            sampler: SamplerKind::Independent,
            ..RenderOptions::default()
        };
        let filter = Filter::new(scene.settings.filter);
        let (clock, ctl) = (Clock::start(&opts), RenderControl::silent());
        let stage = clock.stage(&ctl);
        let waited = AtomicUsize::new(0);
        let ext = scene.camera.screen_half_extent();
        let mut batched = Film::new(24, 20);
        let stats =
            render_pixels_batched(&mut batched, &filter, &opts, &stage, |s, raster, b, st| {
                let l = camera_radiance(&scene, raster, ext, s, &opts, st, &PathOnly, b);
                waited.fetch_add(l.is_none() as usize, Ordering::Relaxed);
                l
            });
        let mut one = Film::new(24, 20);
        let stats_one = render_pixels(&mut one, &filter, &opts, &stage, |s, raster, st| {
            let mut b = DirectBatch::one_by_one();
            camera_radiance(&scene, raster, ext, s, &opts, st, &PathOnly, &mut b).unwrap()
        });
        assert_eq!(batched.count, one.count);
        assert!(batched.sum == one.sum, "the films differ");
        assert_eq!(stats.rays, stats_one.rays);
        // Most samples waited (the scene's surfaces are Lambertian, its light a quad).
        let waited = waited.into_inner();
        assert!(waited > 24 * 20 * 5 / 2, "{waited} samples waited");
    }
}
