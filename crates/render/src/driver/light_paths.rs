//! The path driver: light-path-parallel splats into the film. Paths are numbered; fixed-size chunks of consecutive paths
//! each splat into their own buffer, and buffers are merged into the film in chunk order. Since
//! neither the chunking nor the merge order depends on the thread count, neither does the image.

use crate::control::Stage;
use crate::film::{Film, SplatBuffer};
use crate::options::RenderOptions;
use crate::stats::RenderStats;
use caustica_core::sampling::Sampler;
use rayon::prelude::*;

/// Light paths per chunk.
pub const CHUNK: u64 = 1 << 14;
/// Chunks rendered concurrently before merging (a constant, not the thread count).
const WAVE: usize = 8;

/// Traces the light paths `paths` (or paths from `paths.start` until the time budget is spent)
/// by calling `trace(sampler, out, stats)` with the sampler positioned on each path. Chunks
/// start at `paths.start`, so a range starting on a multiple of [`CHUNK`] (a shard's) splats
/// exactly the chunks of the whole render.
pub fn render_paths<F>(
    film: &mut Film,
    paths: std::ops::Range<u64>,
    opts: &RenderOptions,
    stage: &Stage,
    trace: F,
) -> RenderStats
where
    F: Fn(&mut Sampler, &mut SplatBuffer, &mut RenderStats) + Sync,
{
    let mut buffers: Vec<SplatBuffer> = (0..WAVE).map(|_| SplatBuffer::for_film(film)).collect();
    let mut stats = RenderStats::default();
    let total_paths = paths.end.saturating_sub(paths.start);
    let mut next_path = paths.start;
    loop {
        let remaining = match opts.time_limit {
            Some(_) => u64::MAX,
            None => paths.end.saturating_sub(next_path),
        };
        if remaining == 0 {
            break;
        }
        let wave_start = next_path;
        let results: Vec<(u64, RenderStats)> = buffers
            .par_iter_mut()
            .enumerate()
            .map(|(c, buf)| {
                buf.clear();
                let mut st = RenderStats::default();
                let first = wave_start + c as u64 * CHUNK;
                let last = (first + CHUNK).min(wave_start.saturating_add(remaining));
                let mut sampler = Sampler::new(opts.sampler, opts.seed);
                for path in first..last.max(first) {
                    sampler.start_path(0, path);
                    trace(&mut sampler, buf, &mut st);
                }
                let n = last.saturating_sub(first);
                st.samples += n;
                (n, st)
            })
            .collect();
        for (buf, (n, st)) in buffers.iter().zip(results) {
            if n > 0 {
                buf.merge_into(film, n);
            }
            next_path += n;
            stats += st;
        }
        let done = next_path - paths.start;
        stage.report(done as f64 / total_paths.max(1) as f64, done);
        if stage.end_of_pass(film) {
            break;
        }
    }
    stats
}
