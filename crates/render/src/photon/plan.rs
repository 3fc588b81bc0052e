//! Numbered light paths and how they are cut into work: the seam between *what* a photon pass
//! traces and *where* it runs (threads today, iterations and machines later).
//!
//! Light path `i` of a [`PathStream`] positions its sampler on `(seed, stream, i)`, so a path is
//! the same wherever and whenever it is traced. Paths are traced in fixed chunks of [`CHUNK`]
//! consecutive paths ([`run_chunk`], a pure function of the chunk's range), chunks in parallel
//! waves whose sizes depend only on counts ([`next_wave`]), and the records of the chunks are
//! concatenated in path order and cut at the path where a target is reached ([`Cut`]). Nothing
//! depends on the thread count; a shard or an iteration is a range of paths starting at
//! `first_path`.

use crate::options::RenderOptions;
use crate::photon::adaptive::ChainState;
use crate::stats::RenderStats;
use caustica_core::Vec3;
use caustica_core::sampling::{Sampler, SamplerKind};
use rayon::prelude::*;
use std::ops::Range;

/// Paths per chunk.
pub const CHUNK: u64 = 1 << 12;
/// Give up (with a warning) after this many paths per requested record.
const MAX_PATHS_PER_RECORD: u64 = 1 << 12;
/// Give up (with a warning) when this many paths have stored no record at all: the scene has no
/// lit diffuse surface (or, for the caustic map, no specular path to one). A caustic yield below
/// 1 in 2²⁰ paths would need ~10¹¹ paths for a usable map anyway.
const MAX_PATHS_WITHOUT_RECORD: u64 = 1 << 20;
/// Chunks per wave of a fixed range of paths ([`trace_path_range`]).
const RANGE_WAVE: u64 = 64;

/// The random numbers of a family of numbered light paths: path `i` starts its sampler at
/// `(seed, stream, i)`. Different maps of one render use different streams.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PathStream {
    pub sampler: SamplerKind,
    pub seed: u64,
    pub stream: u64,
}

impl PathStream {
    /// Stream `stream` of the render `opts` describes (its sampler and seed).
    pub fn new(opts: &RenderOptions, stream: u64) -> Self {
        Self {
            sampler: opts.sampler,
            seed: opts.seed,
            stream,
        }
    }
}

/// What one chunk of paths produced.
pub struct ChunkRun<P> {
    /// The records of its paths, in path order.
    pub records: Vec<P>,
    /// The number of records after each of its paths (for the cut).
    pub counts: Vec<u32>,
    pub stats: RenderStats,
}

/// Traces the paths `paths` of `stream` in order: `trace_one(path, sampler, records, stats)`
/// with the sampler positioned on each path. A pure function of its arguments.
pub fn run_chunk<P>(
    paths: Range<u64>,
    stream: &PathStream,
    trace_one: &(impl Fn(u64, &mut Sampler, &mut Vec<P>, &mut RenderStats) + Sync),
) -> ChunkRun<P> {
    let n = paths.end.saturating_sub(paths.start);
    let mut records = Vec::new();
    let mut counts = Vec::with_capacity(n as usize);
    let mut stats = RenderStats::default();
    let mut sampler = Sampler::new(stream.sampler, stream.seed);
    for path in paths {
        sampler.start_path(stream.stream, path);
        trace_one(path, &mut sampler, &mut records, &mut stats);
        counts.push(records.len() as u32);
    }
    stats.samples += n;
    ChunkRun {
        records,
        counts,
        stats,
    }
}

/// Chunks of the next wave toward `target` records when `found` records came from `emitted`
/// paths so far: 16 chunks while nothing is found, then enough for the remaining records at the
/// yield so far plus 5 %, between 1 and 256 chunks, and at most as many paths as were emitted
/// before (waves at most double, so a time budget or Ctrl-C, checked between waves, is overrun
/// by at most the time already spent, never by a sudden 2²⁰-path wave after a 2¹⁶-path one).
/// Counts only, so the waves are the same on every machine; the records do not depend on the
/// waves at all (the [`Cut`] is in path order).
pub fn next_wave(target: usize, found: usize, emitted: u64) -> u64 {
    let wave = if found == 0 {
        16 * CHUNK
    } else {
        let per_path = found as f64 / emitted as f64;
        (((target - found) as f64 / per_path * 1.05) as u64)
            .clamp(CHUNK, 256 * CHUNK)
            .min(emitted.max(16 * CHUNK))
    };
    wave.div_ceil(CHUNK)
}

/// The deterministic merge of chunk runs toward a target: records are appended in path order
/// until the path whose records reach the target; that path ends the pass.
pub struct Cut<P> {
    target: usize,
    pub records: Vec<P>,
    /// Paths merged so far (relative to the first path of the pass).
    pub emitted: u64,
    /// `(paths, records)` at the path where the target was reached.
    reached: Option<(u64, usize)>,
    pub stats: RenderStats,
}

impl<P: Clone> Cut<P> {
    pub fn new(target: usize) -> Self {
        Self {
            target,
            // Reserved up front: growing by doubling touches twice the memory (page faults were
            // ~5 % of a photon-differential pass).
            records: Vec::with_capacity(target),
            emitted: 0,
            reached: None,
            stats: RenderStats::default(),
        }
    }

    /// True once the target is reached.
    pub fn done(&self) -> bool {
        self.reached.is_some()
    }

    /// Merges the run of the next `len` paths (a chunk's range); runs beyond the cut count in
    /// the statistics only.
    pub fn merge(&mut self, run: ChunkRun<P>, len: u64) {
        self.stats += run.stats;
        if self.reached.is_none() {
            let base = self.records.len();
            if base + run.records.len() >= self.target {
                // Only the chunk that crosses the target needs its per-path counts.
                let i = run
                    .counts
                    .iter()
                    .position(|&n| base + n as usize >= self.target)
                    .expect("the chunk reaches the target");
                self.reached = Some((self.emitted + i as u64 + 1, base + run.counts[i] as usize));
            }
            self.records.extend_from_slice(&run.records);
        }
        self.emitted += len;
    }

    /// The records up to the cut, the number of paths they came from and the statistics.
    pub fn finish(mut self) -> (Vec<P>, u64, RenderStats) {
        let (paths, keep) = self.reached.unwrap_or((self.emitted, self.records.len()));
        self.records.truncate(keep);
        (self.records, paths, self.stats)
    }
}

/// Emits the paths `first_path, first_path + 1, …` of `stream` until `target` records exist
/// (`trace_one` stores each path's records), cut at the path where the count reaches `target`
/// (so every path counted contributes all its records). `on_wave(found)` after each wave of
/// chunks; it returns false to stop early (then the pass ends after that wave, with the records
/// and paths so far). Returns the records in path order, the number of paths (from
/// `first_path` on) and the statistics. Gives up early when the yield is hopeless (see
/// [`MAX_PATHS_PER_RECORD`], [`MAX_PATHS_WITHOUT_RECORD`]).
pub fn trace_paths<P: Clone + Send>(
    target: usize,
    stream: &PathStream,
    first_path: u64,
    on_wave: &mut dyn FnMut(usize) -> bool,
    trace_one: impl Fn(u64, &mut Sampler, &mut Vec<P>, &mut RenderStats) + Sync,
) -> (Vec<P>, u64, RenderStats) {
    let mut cut = Cut::new(target);
    let limit = (target as u64)
        .saturating_mul(MAX_PATHS_PER_RECORD)
        .max(CHUNK);
    while !cut.done()
        && cut.emitted < limit
        && !(cut.records.is_empty() && cut.emitted >= MAX_PATHS_WITHOUT_RECORD)
    {
        let chunks = next_wave(target, cut.records.len(), cut.emitted);
        let start = first_path + cut.emitted;
        let runs: Vec<ChunkRun<P>> = (0..chunks)
            .into_par_iter()
            .map(|c| {
                run_chunk(
                    start + c * CHUNK..start + (c + 1) * CHUNK,
                    stream,
                    &trace_one,
                )
            })
            .collect();
        for run in runs {
            cut.merge(run, CHUNK);
        }
        if !on_wave(cut.records.len().min(target)) {
            break;
        }
    }
    cut.finish()
}

/// Traces the paths `paths` of `stream` (a fixed light-path budget: the seed's N_e), in chunks
/// of [`CHUNK`] from `paths.start` and waves of chunks; `on_wave(paths done)` after each wave
/// returns false to stop there. Returns every record in path order, the number of paths traced
/// (all of `paths` unless stopped) and the statistics.
pub fn trace_path_range<P: Send>(
    paths: Range<u64>,
    stream: &PathStream,
    on_wave: &mut dyn FnMut(u64) -> bool,
    trace_one: impl Fn(u64, &mut Sampler, &mut Vec<P>, &mut RenderStats) + Sync,
) -> (Vec<P>, u64, RenderStats) {
    let mut records = Vec::new();
    let mut stats = RenderStats::default();
    let n = paths.end.saturating_sub(paths.start);
    let chunk = |c: u64| {
        let lo = paths.start + c * CHUNK;
        lo..(lo + CHUNK).min(paths.end)
    };
    let (chunks, mut c, mut done) = (n.div_ceil(CHUNK), 0, 0);
    while c < chunks {
        let end = (c + RANGE_WAVE).min(chunks);
        let runs: Vec<ChunkRun<P>> = (c..end)
            .into_par_iter()
            .map(|i| run_chunk(chunk(i), stream, &trace_one))
            .collect();
        for run in runs {
            stats += run.stats;
            records.extend(run.records);
        }
        c = end;
        done = chunk(c - 1).end - paths.start;
        if !on_wave(done) {
            break;
        }
    }
    (records, done, stats)
}

/// How many light paths a photon pass emits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhotonBudget {
    /// Until the pass holds this many records (photons, caustic landings), cut at the path that
    /// reaches the count; ≥ 1.
    Records(usize),
    /// Exactly this many light paths (seed 002's N_e), whatever they store; ≥ 1.
    Paths(u64),
}

impl PhotonBudget {
    /// Records asked for, if the budget counts records.
    pub fn records(self) -> Option<usize> {
        match self {
            PhotonBudget::Records(n) => Some(n),
            PhotonBudget::Paths(_) => None,
        }
    }
}

/// A photon pass under `budget` from path `first_path` of `stream`: [`trace_paths`] or
/// [`trace_path_range`]. `progress(fraction)` after each wave (records found / asked, or paths
/// traced / budget) returns false to stop there. Returns the records in path order, the number
/// of paths they came from and the statistics.
pub fn trace_budget<P: Clone + Send>(
    budget: PhotonBudget,
    stream: &PathStream,
    first_path: u64,
    progress: &mut dyn FnMut(f64) -> bool,
    trace_one: impl Fn(u64, &mut Sampler, &mut Vec<P>, &mut RenderStats) + Sync,
) -> (Vec<P>, u64, RenderStats) {
    match budget {
        PhotonBudget::Records(target) => trace_paths(
            target,
            stream,
            first_path,
            &mut |found| progress(found as f64 / target.max(1) as f64),
            trace_one,
        ),
        PhotonBudget::Paths(n) => trace_path_range(
            first_path..first_path.saturating_add(n),
            stream,
            &mut |done| progress(done as f64 / n.max(1) as f64),
            trace_one,
        ),
    }
}

/// The light paths of a pass, in chunks of [`CHUNK`] paths: a range, or a list (ascending) of
/// the paths known to matter (e.g. those with a caustic landing).
#[derive(Clone, Copy, Debug)]
pub enum PathSet<'a> {
    /// Paths `first..first + n`.
    Range { first: u64, n: u64 },
    /// These paths (ascending), out of the range `first..first + n` they were chosen from.
    Listed { list: &'a [u64], first: u64, n: u64 },
    /// The states of adaptive photon tracing's chains ([`crate::photon::adaptive`]), each
    /// replayed once and weighted by its repeat count; they stand for `n` base light paths.
    States {
        states: &'a [ChainState<Vec3>],
        n: u64,
    },
}

impl PathSet<'_> {
    /// Number of chunks.
    pub fn chunks(&self) -> u64 {
        match self {
            PathSet::Range { n, .. } => n.div_ceil(CHUNK),
            PathSet::Listed { list, .. } => (list.len() as u64).div_ceil(CHUNK),
            PathSet::States { states, .. } => (states.len() as u64).div_ceil(CHUNK),
        }
    }

    /// The chain states of chunk `c` (empty unless the set is [`PathSet::States`]).
    pub fn states_of_chunk(&self, c: u64) -> &[ChainState<Vec3>] {
        match *self {
            PathSet::States { states, .. } => {
                let lo = ((c * CHUNK) as usize).min(states.len());
                let hi = (((c + 1) * CHUNK) as usize).min(states.len());
                &states[lo..hi]
            }
            _ => &[],
        }
    }

    /// Calls `f(path)` for the paths of chunk `c`, in order (none for [`PathSet::States`]: see
    /// [`Self::states_of_chunk`]).
    pub fn for_each_path(&self, c: u64, mut f: impl FnMut(u64)) {
        match *self {
            PathSet::Range { first, n } => {
                (first + c * CHUNK..first + ((c + 1) * CHUNK).min(n)).for_each(f)
            }
            PathSet::Listed { list, .. } => {
                let lo = (c * CHUNK) as usize;
                let hi = ((c + 1) * CHUNK).min(list.len() as u64) as usize;
                list[lo..hi].iter().for_each(|&p| f(p));
            }
            PathSet::States { .. } => {}
        }
    }

    /// Paths traced in the first `c` chunks.
    pub fn traced(&self, c: u64) -> u64 {
        match self {
            PathSet::Range { n, .. } => (c * CHUNK).min(*n),
            PathSet::Listed { list, .. } => (c * CHUNK).min(list.len() as u64),
            PathSet::States { states, .. } => (c * CHUNK).min(states.len() as u64),
        }
    }

    /// Paths of the range that the first `c` chunks account for: every path before the next
    /// untraced one (a listed set skips only paths that contribute nothing).
    pub fn covered(&self, c: u64) -> u64 {
        match *self {
            PathSet::Range { n, .. } => (c * CHUNK).min(n),
            PathSet::Listed { list, first, n } => match list.get((c * CHUNK) as usize) {
                Some(&next) => next - first,
                None => n,
            },
            // The share of the chains' states splatted so far.
            PathSet::States { states, n } => {
                let done = (c * CHUNK).min(states.len() as u64);
                if done >= states.len() as u64 {
                    n
                } else {
                    (n as f64 * done as f64 / states.len() as f64) as u64
                }
            }
        }
    }

    /// Paths in the range.
    pub fn len(&self) -> u64 {
        match *self {
            PathSet::Range { n, .. } | PathSet::Listed { n, .. } | PathSet::States { n, .. } => n,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A path's records: path `i` stores `i % 3` records (its index each time).
    fn three(path: u64, _: &mut Sampler, out: &mut Vec<u64>, _: &mut RenderStats) {
        for _ in 0..path % 3 {
            out.push(path);
        }
    }

    fn stream() -> PathStream {
        PathStream {
            sampler: SamplerKind::Independent,
            seed: 1,
            stream: 7,
        }
    }

    #[test]
    fn the_cut_is_at_the_path_that_reaches_the_target() {
        // Paths 0, 1, 2, 3, 4, 5 store 0, 1, 2, 0, 1, 2 records: 6 records after path 5.
        let (rec, paths, stats) = trace_paths(6, &stream(), 0, &mut |_| true, three);
        assert_eq!(paths, 6);
        assert_eq!(rec, vec![1, 2, 2, 4, 5, 5]);
        // The whole first wave (16 chunks) was traced and counted.
        assert_eq!(stats.samples, 16 * CHUNK);
        // Overshooting inside one path keeps the whole path: target 5 cuts after path 5 too.
        let (rec, paths, _) = trace_paths(5, &stream(), 0, &mut |_| true, three);
        assert_eq!((rec.len(), paths), (6, 6));
    }

    #[test]
    fn a_pass_can_start_at_any_path() {
        // From path 4: 4 → 1, 5 → 2, 6 → 0, 7 → 1 records.
        let (rec, paths, _) = trace_paths(4, &stream(), 4, &mut |_| true, three);
        assert_eq!(paths, 4);
        assert_eq!(rec, vec![4, 5, 5, 7]);
        // A cut spanning chunks: the same records as one pass from 0, whatever the start's
        // alignment with chunks.
        let target = 3 * CHUNK as usize;
        let (all, n, _) = trace_paths(target, &stream(), 0, &mut |_| true, three);
        let (tail, m, _) = trace_paths(target - 3, &stream(), 3, &mut |_| true, three);
        assert_eq!(n, m + 3);
        assert_eq!(&all[3..], &tail[..]);
    }

    #[test]
    fn a_range_traces_exactly_its_paths_in_order() {
        let mut waves = Vec::new();
        let n = RANGE_WAVE * CHUNK + 5;
        let (rec, paths, stats) = trace_path_range(
            10..10 + n,
            &stream(),
            &mut |d| {
                waves.push(d);
                true
            },
            three,
        );
        assert_eq!(paths, n);
        let expected: Vec<u64> = (10..10 + n)
            .flat_map(|p| std::iter::repeat_n(p, (p % 3) as usize))
            .collect();
        assert_eq!(rec, expected);
        assert_eq!(stats.samples, n);
        assert_eq!(waves, vec![RANGE_WAVE * CHUNK, n]);
    }

    #[test]
    fn waves_at_most_double_so_a_budget_is_overrun_by_little() {
        // A plentiful yield toward a huge target would ask for the 256-chunk maximum at once;
        // the waves grow 16, 16, 32, 64, … chunks instead, each at most the paths so far.
        let mut waves = Vec::new();
        let mut emitted = 0;
        let mut chunks = 0;
        while chunks < 256 {
            chunks = next_wave(10_000_000, emitted as usize / 2, emitted.max(1));
            waves.push(chunks);
            assert!(emitted == 0 || chunks * CHUNK <= emitted.max(16 * CHUNK));
            emitted += chunks * CHUNK;
        }
        assert_eq!(waves, vec![16, 16, 32, 64, 128, 256]);
        // Near the target the wave is what is missing (10 records at 990 per 2²⁰ paths, plus
        // 5 %: 11 118 paths, 3 chunks), not the doubling bound.
        assert_eq!(next_wave(1_000, 990, 1 << 20), 3);
    }

    #[test]
    fn stopping_after_a_wave_keeps_what_was_merged() {
        let (rec, paths, _) =
            trace_paths(100 * CHUNK as usize, &stream(), 0, &mut |_| false, three);
        assert_eq!(paths, 16 * CHUNK);
        let expected: u64 = (0..16 * CHUNK).map(|p| p % 3).sum();
        assert_eq!(rec.len() as u64, expected);
    }

    #[test]
    fn path_sets_cover_their_range() {
        let list = [3u64, 9, 10];
        let listed = PathSet::Listed {
            list: &list,
            first: 0,
            n: 20,
        };
        assert_eq!(listed.chunks(), 1);
        assert_eq!(listed.covered(0), 3);
        assert_eq!(listed.covered(1), 20);
        let mut seen = Vec::new();
        listed.for_each_path(0, |p| seen.push(p));
        assert_eq!(seen, list);
        let range = PathSet::Range {
            first: 5,
            n: CHUNK + 1,
        };
        assert_eq!(range.chunks(), 2);
        let mut last = Vec::new();
        range.for_each_path(1, |p| last.push(p));
        assert_eq!(last, vec![5 + CHUNK]);
        assert_eq!(range.covered(1), CHUNK);
        assert_eq!(range.covered(2), CHUNK + 1);
    }
}
