//! Automatic bandwidth selection by least-squares cross-validation (LSCV), scene-free.
//!
//! The integrated squared error of an estimate `f̂_h` of `f` is
//!
//! ```text
//! ISE(h) = ∫ f̂_h² − 2 ∫ f̂_h f + ∫ f²,
//! ```
//!
//! and only the first two terms depend on `h` (Rudemo 1982, Bowman 1984; Silverman 1986
//! sec. 3.4.3, eq. 3.39). The first is known; the cross term `∫ f̂_h f` is estimated with data
//! independent of `f̂_h`. Leave-one-out is the classical choice; here the independent data are
//! a *hold-out* sample: a second sample of `f`, drawn with its own random numbers, gives an
//! unbiased `f̃` of `f` on a set of cells (pixels, bins), so that, `f̂_h` and `f̃` being
//! independent, `E[Σ_p f̂_h(x_p) f̃_p] = Σ_p E[f̂_h(x_p)] f_p`. The score
//!
//! ```text
//! LSCV(h) = Σ_p f̂_h(x_p)² − 2 Σ_p f̂_h(x_p) f̃_p        (cells of equal size)
//! ```
//!
//! is then an unbiased estimate of `E Σ_p (f̂_h(x_p) − f_p)² − Σ_p f_p²` (the discrete ISE up
//! to a constant), and its minimiser over a grid of candidates estimates the bandwidth of least
//! mean integrated squared error. [`LscvScore`] holds the two sums, [`select_geometric`]
//! minimises them over a geometric grid, and [`amise_rescale`] carries a bandwidth chosen on a
//! pilot sample of `n` points to the full sample of `N` by the asymptotic (AMISE) rate.

/// The two `h`-dependent terms of the LSCV score over a set of cells: `Σ f̂²` and `Σ f̂ f̃`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LscvScore {
    /// `Σ_p f̂(x_p)²`.
    pub squares: f64,
    /// `Σ_p f̂(x_p) f̃_p`, the hold-out cross term.
    pub cross: f64,
}

impl LscvScore {
    /// Adds one cell with estimate `e` and hold-out value `h`.
    pub fn add(&mut self, e: f64, h: f64) {
        self.squares += e * e;
        self.cross += e * h;
    }

    /// `Σ f̂² − 2 Σ f̂ f̃` (Silverman 1986 eq. 3.39 with the hold-out cross term).
    pub fn value(&self) -> f64 {
        self.squares - 2.0 * self.cross
    }
}

/// What a bandwidth parameter measures, which decides how it scales with the sample size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Smoother {
    /// A neighbour count k (k-NN, eq. 3.2): the MISE-optimal k grows as `N^{4/(d+4)}`.
    NearestNeighbours,
    /// A bandwidth h (fixed-bandwidth and diffusion estimates): optimal h shrinks as
    /// `N^{-1/(d+4)}`.
    Bandwidth,
    /// A footprint scale s of photon differentials (Frisvad et al. 2014 eq. 5–6): the
    /// footprints' radii are `∝ s · N^{-1/d}`, so the optimal s grows as
    /// `N^{1/d − 1/(d+4)} = N^{4/(d(d+4))}` (`N^{1/3}` on a surface).
    FootprintScale,
}

impl Smoother {
    /// The exponent `a` of the AMISE-optimal parameter's growth `∝ N^a` in dimension `dim`.
    ///
    /// The AMISE of a second-order kernel estimate in `d` dimensions is
    /// `c₁ h⁴ + c₂ / (N h^d)` (Silverman 1986 eq. 4.14; Wand & Jones 1995 eq. 4.9), minimal at
    /// `h ∝ N^{-1/(d+4)}`. A k-NN estimate has `h^d ∝ k / N`, hence `k ∝ N h^d ∝ N^{4/(d+4)}`
    /// (Silverman 1986 sec. 5.2.2); a footprint of scale `s` has radius `∝ s N^{-1/d}`, hence
    /// `s ∝ h N^{1/d}`.
    pub fn rate(self, dim: u32) -> f64 {
        let d = f64::from(dim);
        match self {
            Smoother::NearestNeighbours => 4.0 / (d + 4.0),
            Smoother::Bandwidth => -1.0 / (d + 4.0),
            Smoother::FootprintScale => 1.0 / d - 1.0 / (d + 4.0),
        }
    }
}

/// The parameter `value` chosen for a pilot sample of `pilot` points carried to a sample of
/// `full` points at the AMISE rate of `what` in dimension `dim`: `value · (full/pilot)^a`
/// ([`Smoother::rate`]). Returns `value` when either count is 0.
pub fn amise_rescale(value: f64, what: Smoother, pilot: u64, full: u64, dim: u32) -> f64 {
    if pilot == 0 || full == 0 {
        return value;
    }
    value * (full as f64 / pilot as f64).powf(what.rate(dim))
}

/// Geometric grid `lo, lo·r, lo·r², …` up to `hi` (inclusive within rounding); `r > 1`.
/// Empty if `lo > hi`, `lo ≤ 0` or `r ≤ 1`.
pub fn geometric_grid(lo: f64, hi: f64, ratio: f64) -> Vec<f64> {
    if !(lo > 0.0 && lo <= hi && ratio > 1.0 && hi.is_finite()) {
        return Vec::new();
    }
    let steps = ((hi / lo).ln() / ratio.ln() + 1e-9).floor() as i32;
    (0..=steps).map(|i| lo * ratio.powi(i)).collect()
}

/// A bandwidth chosen by [`select_geometric`].
#[derive(Clone, Debug, PartialEq)]
pub struct Selection {
    /// The candidate with the least score.
    pub value: f64,
    /// Every candidate scored, with its score, in the order scored.
    pub scored: Vec<(f64, f64)>,
}

/// Minimises `score(candidate)` over the geometric grid `lo..=hi` of ratio `ratio`
/// ([`geometric_grid`], scanned upward until [`PATIENCE`] candidates in a row are worse than
/// the best), then over the two geometric midpoints (`best · ratio^{±1/2}`) around
/// the best, each candidate passed through `snap` first (e.g. rounding a neighbour count) and
/// scored once. `score` returns `None` to stop (an interrupted render): the result is then
/// `None`. Ties go to the candidate scored first; non-finite scores never win.
pub fn select_geometric(
    lo: f64,
    hi: f64,
    ratio: f64,
    snap: impl Fn(f64) -> f64,
    mut score: impl FnMut(f64) -> Option<f64>,
) -> Option<Selection> {
    let mut scored: Vec<(f64, f64)> = Vec::new();
    let mut eval = |c: f64, scored: &mut Vec<(f64, f64)>| -> Option<()> {
        let c = snap(c);
        if scored.iter().any(|&(v, _)| v == c) {
            return Some(());
        }
        let s = score(c)?;
        scored.push((c, s));
        Some(())
    };
    // The coarse scan stops once `PATIENCE` candidates in a row score worse than the best so
    // far: the LSCV curve rises on both sides of its minimum, and the large bandwidths are the
    // dearest to evaluate.
    let mut worse = 0;
    for c in geometric_grid(lo, hi, ratio) {
        let before = best_score(&scored);
        let n = scored.len();
        eval(c, &mut scored)?;
        if scored.len() > n
            && before.is_some_and(|b| scored[n].1.partial_cmp(&b) != Some(std::cmp::Ordering::Less))
        {
            worse += 1;
            if worse >= PATIENCE {
                break;
            }
        } else if scored.len() > n {
            worse = 0;
        }
    }
    let best = best_of(&scored)?;
    let half = ratio.sqrt();
    for c in [best / half, best * half] {
        if c >= snap(lo) && c <= hi {
            eval(c, &mut scored)?;
        }
    }
    Some(Selection {
        value: best_of(&scored)?,
        scored,
    })
}

/// Coarse candidates in a row scoring worse than the best before the scan stops.
pub const PATIENCE: usize = 2;

/// The least finite score so far.
fn best_score(scored: &[(f64, f64)]) -> Option<f64> {
    scored
        .iter()
        .map(|&(_, s)| s)
        .filter(|s| s.is_finite())
        .reduce(f64::min)
}

/// The candidate of least finite score (the first of equals), `None` if there is none.
fn best_of(scored: &[(f64, f64)]) -> Option<f64> {
    let mut best: Option<(f64, f64)> = None;
    for &(c, s) in scored {
        if s.is_finite() && best.is_none_or(|(_, b)| s < b) {
            best = Some((c, s));
        }
    }
    best.map(|(c, _)| c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::rng::Pcg32;

    /// The score of `estimate` (one value per cell) against `holdout`, cell by cell.
    fn score_of(estimate: &[f64], holdout: &[f64]) -> LscvScore {
        assert_eq!(estimate.len(), holdout.len());
        let mut s = LscvScore::default();
        for (&e, &h) in estimate.iter().zip(holdout) {
            s.add(e, h);
        }
        s
    }

    /// Standard normal variates (Box–Muller).
    fn normals(rng: &mut Pcg32, n: usize) -> Vec<f64> {
        (0..n)
            .map(|_| {
                let u1 = (rng.next_f32() as f64).max(1e-12);
                let u2 = rng.next_f32() as f64;
                (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
            })
            .collect()
    }

    fn gauss(x2: f64, d: i32) -> f64 {
        (-0.5 * x2).exp() / std::f64::consts::TAU.powf(d as f64 / 2.0)
    }

    /// A 1-D Gaussian-kernel estimate with bandwidth h at x.
    fn kde_1d(sample: &[f64], h: f64, x: f64) -> f64 {
        sample
            .iter()
            .map(|&xi| gauss(((x - xi) / h).powi(2), 1))
            .sum::<f64>()
            / (sample.len() as f64 * h)
    }

    /// Cell centres of `cells` equal bins over [lo, hi), with the bin width.
    fn cells(lo: f64, hi: f64, cells: usize) -> (Vec<f64>, f64) {
        let w = (hi - lo) / cells as f64;
        ((0..cells).map(|i| lo + (i as f64 + 0.5) * w).collect(), w)
    }

    /// Histogram density of `sample` on the bins (the unbiased hold-out estimate of each bin's
    /// mean density: E[count / (M w)] = P(bin) / w).
    fn histogram(sample: &[f64], lo: f64, w: f64, cells: usize) -> Vec<f64> {
        let mut h = vec![0.0; cells];
        for &x in sample {
            let i = ((x - lo) / w).floor();
            if i >= 0.0 && (i as usize) < cells {
                h[i as usize] += 1.0;
            }
        }
        h.iter().map(|c| c / (sample.len() as f64 * w)).collect()
    }

    /// On a standard normal sample, the hold-out LSCV minimiser lands near the known
    /// MISE-optimal bandwidth of the Gaussian kernel, h* = (4/(3n))^{1/5} σ (Silverman 1986
    /// eq. 3.28), and its true ISE is within 10 % of the best candidate's.
    #[test]
    fn lscv_1d_lands_near_the_mise_optimum() {
        let n = 2000;
        let mut rng = Pcg32::new(11, 1);
        let sample = normals(&mut rng, n);
        let mut rng = Pcg32::new(11, 2);
        let holdout = normals(&mut rng, 4000);
        let (lo, hi, m) = (-5.0, 5.0, 200);
        let (xs, w) = cells(lo, hi, m);
        let tilde = histogram(&holdout, lo, w, m);
        let truth: Vec<f64> = xs.iter().map(|&x| gauss(x * x, 1)).collect();
        let mut ise = Vec::new();
        let sel = select_geometric(
            0.02,
            2.0,
            2f64.powf(0.25),
            |h| h,
            |h| {
                let est: Vec<f64> = xs.iter().map(|&x| kde_1d(&sample, h, x)).collect();
                let e: f64 = est.iter().zip(&truth).map(|(a, b)| (a - b).powi(2)).sum();
                ise.push((h, e * w));
                Some(score_of(&est, &tilde).value() * w)
            },
        )
        .unwrap();
        let h_star = (4.0 / (3.0 * n as f64)).powf(0.2);
        assert!(
            (sel.value / h_star - 1.0).abs() < 0.3,
            "LSCV chose h = {}, MISE optimum {h_star}",
            sel.value
        );
        let best_ise = ise.iter().map(|&(_, e)| e).fold(f64::INFINITY, f64::min);
        let chosen_ise = ise.iter().find(|&&(h, _)| h == sel.value).unwrap().1;
        assert!(
            chosen_ise <= 1.1 * best_ise,
            "ISE {chosen_ise} vs best {best_ise}"
        );
    }

    /// The same in 2-D on a grid of "pixels": the AMISE-optimal bandwidth of the Gaussian
    /// kernel for a standard bivariate normal is h* = (4/((d+2) n))^{1/(d+4)} = n^{-1/6}
    /// (Silverman 1986 eq. 4.15 with d = 2).
    #[test]
    fn lscv_2d_lands_near_the_mise_optimum() {
        let n = 1500;
        let mut rng = Pcg32::new(5, 1);
        let sample: Vec<(f64, f64)> = normals(&mut rng, 2 * n)
            .chunks(2)
            .map(|c| (c[0], c[1]))
            .collect();
        let mut rng = Pcg32::new(5, 2);
        let holdout: Vec<(f64, f64)> = normals(&mut rng, 2 * 6000)
            .chunks(2)
            .map(|c| (c[0], c[1]))
            .collect();
        let (lo, hi, m) = (-4.0, 4.0, 32);
        let (xs, w) = cells(lo, hi, m);
        let mut tilde = vec![0.0; m * m];
        for &(x, y) in &holdout {
            let (i, j) = (((x - lo) / w).floor(), ((y - lo) / w).floor());
            if i >= 0.0 && j >= 0.0 && (i as usize) < m && (j as usize) < m {
                tilde[j as usize * m + i as usize] += 1.0 / (holdout.len() as f64 * w * w);
            }
        }
        let sel = select_geometric(
            0.05,
            2.0,
            2f64.powf(0.25),
            |h| h,
            |h| {
                let mut s = LscvScore::default();
                for (j, &y) in xs.iter().enumerate() {
                    for (i, &x) in xs.iter().enumerate() {
                        let f: f64 = sample
                            .iter()
                            .map(|&(a, b)| gauss(((x - a).powi(2) + (y - b).powi(2)) / (h * h), 2))
                            .sum::<f64>()
                            / (n as f64 * h * h);
                        s.add(f, tilde[j * m + i]);
                    }
                }
                Some(s.value())
            },
        )
        .unwrap();
        let h_star = (n as f64).powf(-1.0 / 6.0);
        assert!(
            (sel.value / h_star - 1.0).abs() < 0.3,
            "LSCV chose h = {}, AMISE optimum {h_star}",
            sel.value
        );
    }

    /// The hold-out cross term is unbiased: over many independent hold-out samples the mean of
    /// Σ_p g(x_p) f̃_p w equals Σ_p g(x_p) P(bin p) (a fixed g standing for f̂), within 4
    /// standard errors; P(bin) from the normal CDF.
    #[test]
    fn holdout_cross_term_has_the_expected_mean() {
        let (lo, hi, m) = (-4.0, 4.0, 40);
        let (xs, w) = cells(lo, hi, m);
        let g: Vec<f64> = xs.iter().map(|&x| (-(x - 0.5).powi(2)).exp()).collect();
        // P(bin) by Simpson's rule on the normal density (exact to ~1e-9 here).
        let prob: Vec<f64> = xs
            .iter()
            .map(|&c| {
                let (a, b) = (c - 0.5 * w, c + 0.5 * w);
                (b - a) / 6.0 * (gauss(a * a, 1) + 4.0 * gauss(c * c, 1) + gauss(b * b, 1))
            })
            .collect();
        let expected: f64 = g.iter().zip(&prob).map(|(a, b)| a * b).sum();
        let runs = 400;
        let mut rng = Pcg32::new(3, 9);
        let values: Vec<f64> = (0..runs)
            .map(|_| {
                let tilde = histogram(&normals(&mut rng, 500), lo, w, m);
                score_of(&g, &tilde).cross * w
            })
            .collect();
        let mean = values.iter().sum::<f64>() / runs as f64;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (runs - 1) as f64;
        let se = (var / runs as f64).sqrt();
        assert!(
            (mean - expected).abs() < 4.0 * se,
            "mean {mean}, expected {expected}, se {se}"
        );
        // And the test can tell a biased cross term: twice the hold-out is far off.
        assert!((2.0 * mean - expected).abs() > 4.0 * se);
    }

    /// The AMISE rates: h ∝ N^{-1/6}, k ∝ N^{2/3}, s ∝ N^{1/3} on a surface; and they agree
    /// with each other through h^d ∝ k/N (k-NN) and h ∝ s N^{-1/d} (footprints).
    #[test]
    fn amise_rescaling_follows_the_rates() {
        let (n, big) = (1000u64, 64_000u64);
        let r = big as f64 / n as f64;
        let h = amise_rescale(0.1, Smoother::Bandwidth, n, big, 2);
        let k = amise_rescale(20.0, Smoother::NearestNeighbours, n, big, 2);
        let s = amise_rescale(3.0, Smoother::FootprintScale, n, big, 2);
        assert!((h - 0.1 / 2.0).abs() < 1e-12, "{h}");
        assert!((k - 20.0 * 16.0).abs() < 1e-9, "{k}");
        assert!((s - 3.0 * 4.0).abs() < 1e-12, "{s}");
        for d in [1u32, 2, 3] {
            let dd = f64::from(d);
            let hr = amise_rescale(1.0, Smoother::Bandwidth, n, big, d);
            let kr = amise_rescale(1.0, Smoother::NearestNeighbours, n, big, d);
            let sr = amise_rescale(1.0, Smoother::FootprintScale, n, big, d);
            assert!((hr.powf(dd) - kr / r).abs() < 1e-9, "k-NN, d = {d}");
            assert!(
                (hr - sr * r.powf(-1.0 / dd)).abs() < 1e-9,
                "footprints, d = {d}"
            );
        }
        assert_eq!(amise_rescale(7.0, Smoother::Bandwidth, 0, 5, 2), 7.0);
    }

    #[test]
    fn grid_selection_and_errors() {
        assert_eq!(
            geometric_grid(1.0, 16.0, 2.0),
            vec![1.0, 2.0, 4.0, 8.0, 16.0]
        );
        assert!(geometric_grid(0.0, 1.0, 2.0).is_empty());
        assert!(geometric_grid(1.0, 2.0, 1.0).is_empty());
        // Minimum at 5: the coarse grid finds 4, the refinement tries 4/√2 → 3 and 4·√2 → 6.
        let sel =
            select_geometric(1.0, 64.0, 2.0, f64::round, |c| Some((c - 5.0).powi(2))).unwrap();
        assert_eq!(sel.value, 4.0);
        assert_eq!(sel.scored.len(), 7, "the scan stops after 8 and 16");
        // Interrupted: no choice.
        assert!(select_geometric(1.0, 8.0, 2.0, |c| c, |_| None).is_none());
        // NaN never wins.
        let sel = select_geometric(
            1.0,
            4.0,
            2.0,
            |c| c,
            |c| Some(if c == 1.0 { f64::NAN } else { c }),
        )
        .unwrap();
        assert!((sel.value - 2f64.sqrt()).abs() < 1e-12);
        // Σ f̂² = 1 + 4, Σ f̂ f̃ = 0.5 + 2.
        let s = score_of(&[1.0, 2.0], &[0.5, 1.0]);
        assert_eq!(s.value(), 5.0 - 2.0 * 2.5);
    }
}
