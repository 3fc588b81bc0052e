//! Samplers: Owen-scrambled Sobol (low discrepancy) and independent (PCG32).
//!
//! A sampler is positioned on one *stream* — a pixel sample `(x, y, index)` or a light path
//! `(path index)` — with [`Sampler::start_pixel_sample`] / [`Sampler::start_path`]; the numbers it
//! then returns depend only on the global seed and that position, never on the thread, so images
//! are bit-identical for any thread count.

use super::rng::{Pcg32, mix_seed};
use super::sobol;
use glam::Vec2;

/// Which sequence a [`Sampler`] draws from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SamplerKind {
    /// Owen-scrambled Sobol (Burley 2020) for the first 256 dimensions, then PCG32.
    #[default]
    Sobol,
    /// Independent uniform numbers from PCG32.
    Independent,
}

impl std::str::FromStr for SamplerKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "sobol" => Ok(Self::Sobol),
            "independent" | "random" => Ok(Self::Independent),
            _ => Err(format!(
                "unknown sampler '{s}' (expected 'sobol' or 'independent')"
            )),
        }
    }
}

const SOBOL_DIMS: u32 = sobol::DIMENSIONS;

/// A deterministic sample generator; see the module docs.
#[derive(Clone, Debug)]
pub struct Sampler {
    kind: SamplerKind,
    seed: u64,
    stream_seed: u32,
    /// The stream's point, shuffled once for all its dimensions ([`sobol::shuffled_index`]).
    shuffled: u32,
    dim: u32,
    rng: Pcg32,
    /// Four consecutive Sobol dimensions computed at once ([`sobol::sample_4d`]).
    cache: [f32; 4],
    /// Primary-sample-space mode, for Markov chains over paths (Kelemen et al. 2002): `None`
    /// normally (one predictable branch per number).
    primary: Option<Box<Primary>>,
}

/// The numbers of one path in primary sample space: given ones replayed first, then the
/// positioned sequence's, each of those appended (lazily extended, as Kelemen et al.'s).
#[derive(Clone, Debug)]
struct Primary {
    values: Vec<f32>,
    /// Next value to return.
    pos: usize,
}

impl Sampler {
    pub fn new(kind: SamplerKind, seed: u64) -> Self {
        Self {
            kind,
            seed,
            stream_seed: 0,
            shuffled: 0,
            dim: 0,
            rng: Pcg32::new(seed, 0),
            cache: [0.0; 4],
            primary: None,
        }
    }

    /// Primary-sample-space mode until [`Self::take_primary`]: the next numbers drawn are
    /// `values`, then the positioned sequence's, each appended to `values`. With no values it
    /// records the path's numbers; with a mutated state it replays it, so that
    /// [`Self::take_primary`] returns every number the path used.
    pub fn replay_primary(&mut self, values: Vec<f32>) {
        self.primary = Some(Box::new(Primary { values, pos: 0 }));
    }

    /// Leaves primary-sample-space mode, returning the numbers replayed and drawn.
    pub fn take_primary(&mut self) -> Vec<f32> {
        self.primary.take().map(|p| p.values).unwrap_or_default()
    }

    #[cold]
    fn next_primary(&mut self) -> f32 {
        let Some(mut p) = self.primary.take() else {
            return self.next_sequence();
        };
        let x = match p.values.get(p.pos) {
            Some(&x) => x,
            None => {
                let x = self.next_sequence();
                p.values.push(x);
                x
            }
        };
        p.pos += 1;
        self.primary = Some(p);
        x
    }

    pub fn kind(&self) -> SamplerKind {
        self.kind
    }
    /// Positions the sampler on sample `index` of pixel `(x, y)`. Like paths, samples are
    /// grouped in blocks of 2¹⁶ (the Sobol generator's limit), each with its own scramble.
    pub fn start_pixel_sample(&mut self, x: u32, y: u32, index: u32) {
        let stream = self.pixel_stream(x, y, index);
        self.start_in_stream(stream, index);
    }

    /// The stream of sample `index` of pixel `(x, y)`: the same for the 2¹⁶ indices of its block,
    /// so a caller that starts many samples of one pixel can compute it once and start each by
    /// [`Self::start_in_stream`].
    #[inline]
    pub fn pixel_stream(&self, x: u32, y: u32, index: u32) -> u64 {
        mix_seed(
            self.seed,
            &[x as u64, y as u64, (index >> 16) as u64, 0x5049_5845],
        )
    }

    /// [`Self::start_pixel_sample`] with the sample's [`Self::pixel_stream`] known.
    #[inline]
    pub fn start_in_stream(&mut self, stream: u64, index: u32) {
        self.start(stream, index & 0xFFFF);
    }
    /// Positions the sampler on light/photon path number `path` (of pass `pass`).
    ///
    /// The Sobol generator yields 2¹⁶ points per scramble, so paths are grouped in blocks of
    /// 2¹⁶ consecutive indices; each block gets its own scramble seed.
    pub fn start_path(&mut self, pass: u64, path: u64) {
        let stream = mix_seed(self.seed, &[pass, path >> 16, 0x5041_5448]);
        self.start(stream, (path & 0xFFFF) as u32);
    }
    fn start(&mut self, stream: u64, index: u32) {
        self.stream_seed = (stream ^ (stream >> 32)) as u32;
        // The shuffle is the Sobol points' alone: the independent sampler skips it per sample.
        if self.kind == SamplerKind::Sobol {
            self.shuffled = sobol::shuffled_index(index, self.stream_seed);
        }
        self.dim = 0;
        self.rng = Pcg32::new(mix_seed(stream, &[index as u64]), stream);
    }
    /// Next uniform number in [0, 1).
    #[inline(always)]
    pub fn next_1d(&mut self) -> f32 {
        if self.primary.is_some() {
            return self.next_primary();
        }
        // The independent sampler's step is a few instructions, cheaper inline than a call.
        if self.kind == SamplerKind::Independent {
            return self.rng.next_f32();
        }
        self.next_sequence()
    }

    #[inline]
    fn next_sequence(&mut self) -> f32 {
        match self.kind {
            SamplerKind::Independent => self.rng.next_f32(),
            SamplerKind::Sobol => {
                if self.dim < SOBOL_DIMS {
                    let lane = (self.dim % 4) as usize;
                    if lane == 0 {
                        self.cache =
                            sobol::sample_4d(self.shuffled, self.dim / 4, self.stream_seed);
                    }
                    self.dim += 1;
                    self.cache[lane].min(ONE_MINUS_EPSILON)
                } else {
                    self.rng.next_f32()
                }
            }
        }
    }
    /// Next uniform point in [0, 1)².
    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        let x = self.next_1d();
        let y = self.next_1d();
        Vec2::new(x, y)
    }

    /// The next `N` numbers, bit for bit those of `N` calls of [`Self::next_1d`]. The
    /// independent sampler checks its kind once and steps its generator in registers.
    #[inline(always)]
    pub fn next_1d_array<const N: usize>(&mut self) -> [f32; N] {
        let mut out = [0.0; N];
        if self.primary.is_none() && self.kind == SamplerKind::Independent {
            // (A copy held in registers, written back after the `N` steps.)
            let mut rng = self.rng.clone();
            for x in &mut out {
                *x = rng.next_f32();
            }
            self.rng = rng;
        } else {
            for x in &mut out {
                *x = self.next_1d();
            }
        }
        out
    }
}

/// Largest `f32` below 1.
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_stream_same_numbers() {
        for kind in [SamplerKind::Sobol, SamplerKind::Independent] {
            let mut a = Sampler::new(kind, 42);
            let mut b = Sampler::new(kind, 42);
            a.start_pixel_sample(3, 4, 5);
            let _ = b.next_1d();
            b.start_pixel_sample(3, 4, 5);
            for _ in 0..300 {
                assert_eq!(a.next_1d().to_bits(), b.next_1d().to_bits());
            }
        }
    }

    #[test]
    fn arrays_hold_the_numbers_drawn_one_by_one() {
        // Every kind, and the independent sampler replaying primary samples (which draws one by
        // one): the array is the next seven numbers bit for bit, and the sampler goes on as if
        // they had been drawn one by one.
        for (kind, replay) in [
            (SamplerKind::Independent, false),
            (SamplerKind::Independent, true),
            (SamplerKind::Sobol, false),
        ] {
            let start = || {
                let mut s = Sampler::new(kind, 11);
                s.start_pixel_sample(3, 7, 5);
                s.next_1d();
                if replay {
                    s.replay_primary(vec![0.25, 0.75]);
                }
                s
            };
            let (mut a, mut b) = (start(), start());
            let got = a.next_1d_array::<7>();
            for (j, x) in got.iter().enumerate() {
                assert_eq!(x.to_bits(), b.next_1d().to_bits(), "{kind:?} draw {j}");
            }
            for _ in 0..5 {
                assert_eq!(
                    a.next_1d().to_bits(),
                    b.next_1d().to_bits(),
                    "{kind:?} after"
                );
            }
        }
    }

    #[test]
    fn primary_samples_record_replay_and_extend() {
        let mut s = Sampler::new(SamplerKind::Sobol, 7);
        s.start_path(1, 5);
        let drawn: Vec<f32> = (0..6).map(|_| s.next_1d()).collect();
        s.start_path(1, 5);
        s.replay_primary(Vec::new());
        let recorded: Vec<f32> = (0..6).map(|_| s.next_1d()).collect();
        assert_eq!(recorded, drawn, "recording does not change the numbers");
        assert_eq!(s.take_primary(), drawn);
        // Replaying returns the given numbers, then the positioned sequence's, appended.
        s.start_path(1, 9);
        let fresh: Vec<f32> = (0..3).map(|_| s.next_1d()).collect();
        s.start_path(1, 9);
        s.replay_primary(vec![0.25, 0.5]);
        let got: Vec<f32> = (0..5).map(|_| s.next_1d()).collect();
        assert_eq!(got, [0.25, 0.5, fresh[0], fresh[1], fresh[2]]);
        assert_eq!(s.take_primary(), got);
        // Out of the mode, the sequence again.
        s.start_path(1, 5);
        assert_eq!(s.next_1d(), drawn[0]);
    }

    #[test]
    fn paths_beyond_the_sobol_block_are_new_points() {
        // Sobol yields 2^16 points per scramble; later paths must not repeat earlier ones.
        let mut s = Sampler::new(SamplerKind::Sobol, 3);
        let mut first = Vec::new();
        for p in [5u64, 70_000, 5 + (1 << 16), 5 + (1 << 32)] {
            s.start_path(0, p);
            first.push(s.next_2d());
        }
        for i in 0..first.len() {
            for j in i + 1..first.len() {
                assert_ne!(first[i], first[j], "paths {i} and {j} share their samples");
            }
        }
        s.start_pixel_sample(1, 1, 5);
        let a = s.next_2d();
        s.start_pixel_sample(1, 1, 5 + (1 << 16));
        assert_ne!(a, s.next_2d());
    }

    #[test]
    fn sobol_2d_is_well_stratified() {
        // The first 256 points of a (0,2)-sequence put exactly one point in each of 16x16 cells.
        let mut s = Sampler::new(SamplerKind::Sobol, 1);
        let mut cells = [0u32; 256];
        for i in 0..256 {
            s.start_pixel_sample(0, 0, i);
            let p = s.next_2d();
            cells[(p.x * 16.0) as usize + 16 * (p.y * 16.0) as usize] += 1;
        }
        assert!(cells.iter().all(|&c| c == 1), "{cells:?}");
    }
}
