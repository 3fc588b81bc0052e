//! Shards: one of N parts of a render's work, rendered anywhere and merged exactly.
//!
//! Every sample of a render is positioned on the seed and its own index (a pixel sample on
//! (seed, pixel, sample index), a light path on (seed, stream, path index), an iteration on its
//! number), and the film's sums are exact ([`crate::ExactSum`]). So a render cut into parts
//! that together do each piece of work once, rendered on any machines, merges ([`crate::film::Film::merge`])
//! into exactly the film one machine gives. Each method cuts along its natural unit
//! ([`ShardUnit`]); the work of setting up (photon maps, the pds eye map and count, pcf's
//! importons) is done by every shard, since it is a pure function of the options.

use crate::error::OptionError;
use crate::integrator::IntegratorKind;
use std::ops::Range;

/// Shard `index` of `count` (0 ≤ index < count).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    index: u32,
    count: u32,
}

impl Shard {
    /// Shard `index` of `count`; refuses `count` = 0 and `index` ≥ `count`.
    pub fn new(index: u32, count: u32) -> Result<Self, OptionError> {
        if count == 0 {
            return Err(OptionError::Conflict(
                "a render has at least one shard: --shard I/N needs N >= 1".into(),
            ));
        }
        if index >= count {
            return Err(OptionError::Conflict(format!(
                "--shard {index}/{count}: shards are numbered 0 to {} (I < N)",
                count - 1
            )));
        }
        Ok(Self { index, count })
    }

    pub fn index(self) -> u32 {
        self.index
    }

    pub fn count(self) -> u32 {
        self.count
    }

    /// This shard's part of `units` units of work numbered `0..units`: the contiguous range
    /// `⌊I·U/N⌋ .. ⌊(I+1)·U/N⌋`. The ranges of shards `0..N` tile `0..units`, each unit once.
    pub fn range(self, units: u64) -> Range<u64> {
        let at = |i: u32| ((units as u128 * i as u128) / self.count as u128) as u64;
        at(self.index)..at(self.index + 1)
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// The rows of a film a shard adds camera samples to: every `step`-th row from row `first`.
/// Interleaved rows give every shard a share of every part of the image, so the shards take
/// about equal time (with bands, the shard holding the caustic or the glass was the slowest:
/// docs/distributed.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RowSet {
    first: u32,
    step: u32,
}

impl RowSet {
    /// Every row.
    pub const ALL: Self = Self { first: 0, step: 1 };

    /// The rows of `shard`: I, I + N, I + 2N, …
    pub fn of(shard: Shard) -> Self {
        Self {
            first: shard.index,
            step: shard.count,
        }
    }

    #[inline]
    pub fn contains(self, y: usize) -> bool {
        y % self.step as usize == self.first as usize
    }

    /// How many of rows `0..height` are in the set.
    pub fn count(self, height: usize) -> usize {
        height
            .saturating_sub(self.first as usize)
            .div_ceil(self.step as usize)
    }
}

/// What a method's shards split.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShardUnit {
    /// Rows of the film, interleaved ([`RowSet`]; the path tracer and the one-shot photon
    /// methods: every pixel's samples are summed by one shard; the photon maps are traced by
    /// every shard).
    PixelRows,
    /// Chunks of light paths (the light tracer), each splatting over the whole film.
    LightPathChunks,
    /// Chunks of a light-path pass beside camera samples split by rows: pds's splatting pass
    /// (every shard traces the whole eye map and counts the light paths, since every chunk
    /// splats onto it) and the hybrid's caustic light tracer.
    SplatChunks,
    /// Iterations of a progressive method (each a pure function of its number).
    Iterations,
}

impl ShardUnit {
    /// How `kind` is split, or why it cannot be.
    pub fn of(kind: IntegratorKind) -> Result<Self, OptionError> {
        use IntegratorKind as K;
        Ok(match kind {
            K::Path
            | K::PhotonMapping
            | K::DiffusionPhotonMapping
            | K::PhotonDifferentialMapping
            | K::VolumetricPhotonMapping
            | K::BeamRadianceEstimate
            | K::VolumePhotonDifferentials => ShardUnit::PixelRows,
            K::LightTrace => ShardUnit::LightPathChunks,
            K::PhotonDifferentialSplatting | K::Hybrid => ShardUnit::SplatChunks,
            K::ProgressivePhotonMapping
            | K::ProgressiveSplatting
            | K::ProgressiveDifferentialMapping
            | K::ProgressiveDiffusion
            | K::PhotonConeFocusing => ShardUnit::Iterations,
            K::StochasticProgressivePhotonMapping | K::ProgressivePhotonMappingHitPoints => {
                return Err(OptionError::Conflict(format!(
                    "--integrator {} cannot be sharded exactly: each pixel's radius and photon \
                     statistics after iteration i depend on every earlier iteration, so no \
                     iteration can be rendered without the ones before it; use pppm or ppds, \
                     whose iterations are independent and shard exactly",
                    kind.name()
                )));
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_tile_the_units_for_any_count() {
        for units in [0u64, 1, 5, 7, 64, 1000, u64::MAX / 3] {
            for count in [1u32, 2, 3, 7, 64, 1000] {
                let mut next = 0;
                for i in 0..count {
                    let r = Shard::new(i, count).unwrap().range(units);
                    assert_eq!(r.start, next, "{units} units, shard {i}/{count}");
                    assert!(r.end >= r.start);
                    // Balanced: sizes differ by at most one.
                    let size = r.end - r.start;
                    assert!(size == units / count as u64 || size == units / count as u64 + 1);
                    next = r.end;
                }
                assert_eq!(next, units);
            }
        }
    }

    #[test]
    fn row_sets_tile_the_rows() {
        for h in [0usize, 1, 5, 64, 65] {
            for n in [1u32, 2, 3, 7, 100] {
                let sets: Vec<RowSet> = (0..n)
                    .map(|i| RowSet::of(Shard::new(i, n).unwrap()))
                    .collect();
                for y in 0..h {
                    assert_eq!(sets.iter().filter(|s| s.contains(y)).count(), 1);
                }
                let counts: usize = sets.iter().map(|s| s.count(h)).sum();
                assert_eq!(counts, h);
                for s in &sets {
                    assert_eq!(s.count(h), (0..h).filter(|&y| s.contains(y)).count());
                }
            }
        }
        assert_eq!(RowSet::ALL.count(9), 9);
    }

    #[test]
    fn bad_shards_are_refused() {
        assert!(Shard::new(0, 0).is_err());
        let e = Shard::new(5, 4).unwrap_err().to_string();
        assert!(e.contains("0 to 3"), "{e}");
        assert_eq!(Shard::new(3, 4).unwrap().to_string(), "3/4");
        let e = ShardUnit::of(IntegratorKind::StochasticProgressivePhotonMapping)
            .unwrap_err()
            .to_string();
        assert!(e.contains("pppm"), "{e}");
        for kind in IntegratorKind::ALL {
            let refused = matches!(
                kind,
                IntegratorKind::StochasticProgressivePhotonMapping
                    | IntegratorKind::ProgressivePhotonMappingHitPoints
            );
            assert_eq!(ShardUnit::of(kind).is_err(), refused, "{}", kind.name());
        }
    }
}
