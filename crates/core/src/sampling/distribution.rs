//! Discrete distributions sampled by inverting a cumulative table (light selection by power,
//! triangle selection by area).

/// Tables of at most this many cdf entries are searched by a branch-free count.
const SHORT: usize = 16;

/// A discrete distribution over `0..n` proportional to non-negative weights.
#[derive(Clone, Debug, Default)]
pub struct Distribution1D {
    /// Normalised CDF with `cdf[0] = 0` and `cdf[n] = 1`.
    cdf: Vec<f32>,
    pmf: Vec<f32>,
    total: f64,
}

impl Distribution1D {
    /// Builds from weights; returns `None` when there is no positive, finite weight.
    pub fn new(weights: &[f32]) -> Option<Self> {
        let mut acc = 0.0f64;
        let mut cdf = Vec::with_capacity(weights.len() + 1);
        cdf.push(0.0f64);
        for &w in weights {
            acc += if w.is_finite() && w > 0.0 {
                w as f64
            } else {
                0.0
            };
            cdf.push(acc);
        }
        if acc <= 0.0 {
            return None;
        }
        let pmf = weights
            .iter()
            .map(|&w| {
                if w.is_finite() && w > 0.0 {
                    (w as f64 / acc) as f32
                } else {
                    0.0
                }
            })
            .collect();
        Some(Self {
            cdf: cdf.iter().map(|c| (c / acc) as f32).collect(),
            pmf,
            total: acc,
        })
    }
    pub fn len(&self) -> usize {
        self.pmf.len()
    }
    pub fn is_empty(&self) -> bool {
        self.pmf.is_empty()
    }
    /// Sum of the weights.
    pub fn total(&self) -> f64 {
        self.total
    }
    /// Probability of index `i`.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        self.pmf[i]
    }
    /// Samples an index with `u ∈ [0, 1)`; returns the index, its probability and `u` remapped
    /// to [0, 1) within the chosen bucket (so one number can be reused).
    #[inline(always)]
    pub fn sample(&self, u: f32) -> (usize, f32, f32) {
        use crate::sampling::sampler::ONE_MINUS_EPSILON;
        // The commonest tables, a scene's single light and a quad light's two triangles, are
        // sampled here without a call, by the table search's own arithmetic (so the same bits).
        match (&*self.pmf, &*self.cdf) {
            // One entry: `cdf = [0, 1]`, the index is 0 for every `u`.
            ([p], [c0, _]) => (0, *p, ((u - c0) / p).clamp(0.0, ONE_MINUS_EPSILON)),
            // Two entries of positive probability: no zero entry to skip.
            ([p0, p1], [c0, c1, c2]) if *p0 > 0.0 && *p1 > 0.0 => {
                let below = (*c0 <= u) as usize + (*c1 <= u) as usize + (*c2 <= u) as usize;
                // The entry by its index, not by a choice between the two (which the compiler
                // made a branch, a coin flip for the predictor).
                let i = (below >= 2) as usize;
                let (p, c) = (self.pmf[i], self.cdf[i]);
                (i, p, ((u - c) / p).clamp(0.0, ONE_MINUS_EPSILON))
            }
            _ => self.sample_table(u),
        }
    }

    /// [`Self::sample`] by searching the table (any length).
    #[inline(never)]
    fn sample_table(&self, u: f32) -> (usize, f32, f32) {
        // First index with cdf[i+1] > u, skipping zero-probability entries.
        let n = self.pmf.len();
        // The number of cdf entries ≤ u, minus one. Short tables (a few lights, a quad light's
        // two triangles) count without branches: the binary search's comparisons are coin flips
        // that a branch predictor loses. Both give the same index, the cdf being sorted.
        // One or two entries (a single light, a quad light's two triangles: the commonest
        // tables) are counted without the vectorised loop's set-up.
        let below = match *self.cdf {
            [a, b] => (a <= u) as usize + (b <= u) as usize,
            [a, b, c] => (a <= u) as usize + (b <= u) as usize + (c <= u) as usize,
            _ if self.cdf.len() <= SHORT => self.cdf.iter().map(|&c| (c <= u) as usize).sum(),
            _ => self.cdf.partition_point(|&c| c <= u),
        };
        let mut i = below.saturating_sub(1).min(n - 1);
        while self.pmf[i] == 0.0 && i + 1 < n {
            i += 1;
        }
        while self.pmf[i] == 0.0 && i > 0 {
            i -= 1;
        }
        let p = self.pmf[i];
        let rem = ((u - self.cdf[i]) / p).clamp(0.0, crate::sampling::sampler::ONE_MINUS_EPSILON);
        (i, p, rem)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chi2::chi_square;
    use crate::sampling::Pcg32;

    #[test]
    fn sampling_follows_weights() {
        let w = [1.0, 0.0, 3.0, 0.5, 0.0, 2.0];
        let d = Distribution1D::new(&w).unwrap();
        let mut rng = Pcg32::new(9, 9);
        let n = 100_000;
        let mut obs = vec![0.0; w.len()];
        for _ in 0..n {
            let (i, p, rem) = d.sample(rng.next_f32());
            assert!(p > 0.0 && (0.0..1.0).contains(&rem));
            obs[i] += 1.0;
        }
        let exp: Vec<f64> = (0..w.len()).map(|i| d.pmf(i) as f64 * n as f64).collect();
        let r = chi_square(&obs, &exp);
        assert!(r.passed(), "{r}");
        assert!(Distribution1D::new(&[0.0, f32::NAN]).is_none());
    }

    #[test]
    fn short_tables_pick_what_the_binary_search_picks() {
        // The branch-free count against the binary search it replaces, on tables below and
        // above the cut-off, with zero weights and with u exactly on cdf entries.
        let mut rng = Pcg32::new(4, 21);
        for n in 1..=2 * SHORT {
            let w: Vec<f32> = (0..n)
                .map(|k| {
                    if k % 3 == 1 {
                        0.0
                    } else {
                        0.1 + rng.next_f32()
                    }
                })
                .collect();
            let Some(d) = Distribution1D::new(&w) else {
                continue;
            };
            let by_search = |u: f32| {
                let mut i = d
                    .cdf
                    .partition_point(|&c| c <= u)
                    .saturating_sub(1)
                    .min(n - 1);
                while d.pmf[i] == 0.0 && i + 1 < n {
                    i += 1;
                }
                while d.pmf[i] == 0.0 && i > 0 {
                    i -= 1;
                }
                i
            };
            let us: Vec<f32> = (0..200)
                .map(|_| rng.next_f32())
                .chain(d.cdf.iter().copied().filter(|&c| c < 1.0))
                .collect();
            for u in us {
                assert_eq!(d.sample(u).0, by_search(u), "n = {n}, u = {u}");
            }
        }
    }

    #[test]
    fn one_and_two_entries_give_the_table_search_bits() {
        // The shortcuts for one and two entries against the search they skip (which handles
        // any length), on ordinary numbers, on the cdf's entries and on the edges: 0, −0, just
        // below 1, 1, beyond, NaN. Two-entry tables with a zero weight take the search.
        let bits = |(i, p, r): (usize, f32, f32)| (i, p.to_bits(), r.to_bits());
        let mut rng = Pcg32::new(8, 3);
        let tables: [&[f32]; 9] = [
            &[1.0],
            &[0.3],
            &[7.5e-12],
            &[3.0e30],
            &[1.0, 1.0],
            &[0.2, 0.7],
            &[3.0e-20, 1.0],
            &[0.0, 2.0],
            &[5.0, 0.0],
        ];
        for w in tables {
            let d = Distribution1D::new(w).unwrap();
            let edges = [0.0, -0.0, 0.999_999_94, 1.0, 1.5, -0.25, f32::NAN];
            let us = (0..100).map(|_| rng.next_f32()).chain(edges);
            for u in us.chain(d.cdf.clone()) {
                assert_eq!(
                    bits(d.sample(u)),
                    bits(d.sample_table(u)),
                    "w = {w:?}, u = {u}"
                );
            }
        }
    }
}
