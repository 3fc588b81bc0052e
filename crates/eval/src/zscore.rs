//! z-score tests that tell Monte Carlo noise from systematic bias between two images rendered
//! independently (different renderers or seeds). All tests work on the per-pixel luminance
//! difference d = Y(image) − Y(reference) (W/m²/sr) over the selected region.

use crate::normal;
use crate::region::Region;

/// Neighbourhood half-width for the per-pixel noise estimate (a 5×5 window).
pub const PIXEL_RADIUS: usize = 2;
/// Two-sided tail probabilities of Student's t with 24 degrees of freedom (a full 5×5
/// neighbourhood minus the centre): P(|t| > 2) and P(|t| > 3). These are the fractions of
/// pixels expected beyond |z| = 2 and 3 when d is pure zero-mean Gaussian noise of locally
/// constant variance.
pub const T24_TAIL_2: f64 = 0.056_94;
pub const T24_TAIL_3: f64 = 0.006_21;

/// Summary of per-pixel z-scores z = d / σ̂, where σ̂² is the mean of d² over the selected
/// neighbours in a 5×5 window (centre excluded), so σ̂ estimates the combined noise of both images
/// at that pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct PixelZ {
    /// Pixels with a usable noise estimate (≥ 8 selected neighbours, σ̂ > 0).
    pub pixels: usize,
    /// Mean z: near 0 for unbiased images, with standard error ≈ 1/√pixels.
    pub mean: f64,
    /// Root mean square of z: near 1 when the noise estimate is sound.
    pub rms: f64,
    /// Fraction of pixels with |z| > 2 and |z| > 3 (compare with [`T24_TAIL_2`], [`T24_TAIL_3`]).
    pub frac_over_2: f64,
    pub frac_over_3: f64,
}

/// Per-pixel z-scores of the luminance difference `d` (row-major, `width` wide) over `region`.
pub fn pixel_z(d: &[f64], width: usize, region: &Region) -> PixelZ {
    let height = d.len() / width.max(1);
    let r = PIXEL_RADIUS;
    let (mut n, mut sum, mut sum2, mut over2, mut over3) = (0usize, 0.0, 0.0, 0usize, 0usize);
    for i in region.indices() {
        let (x, y) = (i % width, i / width);
        let (mut m, mut s2) = (0usize, 0.0);
        for ny in y.saturating_sub(r)..(y + r + 1).min(height) {
            for nx in x.saturating_sub(r)..(x + r + 1).min(width) {
                if (nx, ny) != (x, y) && region.contains(nx, ny) {
                    s2 += d[ny * width + nx].powi(2);
                    m += 1;
                }
            }
        }
        if m < 8 || s2 <= 0.0 {
            continue;
        }
        let z = d[i] / (s2 / m as f64).sqrt();
        n += 1;
        sum += z;
        sum2 += z * z;
        over2 += usize::from(z.abs() > 2.0);
        over3 += usize::from(z.abs() > 3.0);
    }
    let nf = n.max(1) as f64;
    PixelZ {
        pixels: n,
        mean: sum / nf,
        rms: (sum2 / nf).sqrt(),
        frac_over_2: over2 as f64 / nf,
        frac_over_3: over3 as f64 / nf,
    }
}

/// Per-block test for regional bias: the region's crop rectangle is cut into `size`×`size`
/// blocks; in each block with at least 16 selected pixels the mean difference is divided by its
/// standard error, z = d̄ / (s/√n). Without bias each z is approximately standard normal, so a
/// block is flagged when |z| exceeds the Bonferroni threshold Φ⁻¹(1 − α/(2m)) for m tested blocks
/// and family-wise level α **and** its relative mean difference is at least `tolerance`: a
/// deterministic difference far below what matters (say 0.02 % in a noise-free mirror
/// reflection, from different spectral data) is statistically significant but not a bias worth
/// reporting.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockZ {
    pub size: usize,
    /// Blocks tested, and the flagging threshold on |z|.
    pub blocks: usize,
    pub threshold: f64,
    /// Largest |z| among blocks differing by at least `tolerance`, where it is (block's top-left
    /// pixel), and that block's relative mean difference (image/reference − 1 of mean luminance).
    pub max_abs_z: f64,
    pub worst_block: (usize, usize),
    pub worst_relative: f64,
    /// Relative difference below which a block is never flagged.
    pub tolerance: f64,
    /// Blocks with |z| > threshold and |relative difference| ≥ tolerance.
    pub flagged: usize,
}

/// Family-wise significance level of the block test.
pub const BLOCK_ALPHA: f64 = 0.01;

/// Runs the block test (see [`BlockZ`]) on `d` with the reference luminance `yr` for the
/// relative differences.
pub fn block_z(
    d: &[f64],
    yr: &[f64],
    width: usize,
    region: &Region,
    size: usize,
    tolerance: f64,
) -> BlockZ {
    let size = size.max(1);
    let mut results = Vec::new();
    for by in (region.y0..region.y0 + region.h).step_by(size) {
        for bx in (region.x0..region.x0 + region.w).step_by(size) {
            let (mut n, mut s, mut s2, mut sr) = (0usize, 0.0, 0.0, 0.0);
            for y in by..(by + size).min(region.y0 + region.h) {
                for x in bx..(bx + size).min(region.x0 + region.w) {
                    if region.contains(x, y) {
                        let v = d[y * width + x];
                        n += 1;
                        s += v;
                        s2 += v * v;
                        sr += yr[y * width + x];
                    }
                }
            }
            if n < 16 {
                continue;
            }
            let nf = n as f64;
            let mean = s / nf;
            let var = ((s2 - s * mean) / (nf - 1.0)).max(0.0);
            let z = if var > 0.0 {
                mean / (var / nf).sqrt()
            } else if mean == 0.0 {
                0.0
            } else {
                f64::INFINITY.copysign(mean)
            };
            let rel = if sr > 0.0 {
                s / sr
            } else if s == 0.0 {
                0.0
            } else {
                f64::INFINITY.copysign(s)
            };
            results.push((z, (bx, by), rel));
        }
    }
    let m = results.len();
    let threshold = normal::quantile(1.0 - BLOCK_ALPHA / (2.0 * m.max(1) as f64));
    let worst = results
        .iter()
        .copied()
        .filter(|r| r.2.abs() >= tolerance)
        .max_by(|a, b| a.0.abs().total_cmp(&b.0.abs()))
        .unwrap_or((0.0, (0, 0), 0.0));
    BlockZ {
        size,
        blocks: m,
        threshold,
        max_abs_z: worst.0.abs(),
        worst_block: worst.1,
        worst_relative: worst.2,
        tolerance,
        flagged: results
            .iter()
            .filter(|r| r.0.abs() > threshold && r.2.abs() >= tolerance)
            .count(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::rng::Pcg32;

    /// Standard normal samples by Box–Muller.
    fn gaussian(rng: &mut Pcg32) -> f64 {
        let u1 = 1.0 - f64::from(rng.next_f32());
        let u2 = f64::from(rng.next_f32());
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }

    fn noise(w: usize, h: usize, sigma: f64, seed: u64) -> Vec<f64> {
        let mut rng = Pcg32::new(seed, 3);
        (0..w * h).map(|_| sigma * gaussian(&mut rng)).collect()
    }

    #[test]
    fn pure_noise_is_not_flagged() {
        let (w, h) = (128, 96);
        let d = noise(w, h, 0.05, 11);
        let yr = vec![1.0; w * h];
        let region = Region::full(w, h);
        let b = block_z(&d, &yr, w, &region, 16, 0.0);
        assert_eq!(b.blocks, 48);
        assert_eq!(b.flagged, 0, "{b:?}");
        let p = pixel_z(&d, w, &region);
        assert_eq!(p.pixels, w * h);
        // Mean of ~12k nearly independent z: standard error ~0.009; allow 4.5 of them.
        assert!(p.mean.abs() < 4.5 / (p.pixels as f64).sqrt(), "{p:?}");
        // Tail fractions near Student-t(24) values (binomial standard errors ~0.002 / 0.0007).
        assert!((p.frac_over_2 - T24_TAIL_2).abs() < 0.012, "{p:?}");
        assert!((p.frac_over_3 - T24_TAIL_3).abs() < 0.004, "{p:?}");
        assert!((p.rms - (24.0f64 / 22.0).sqrt()).abs() < 0.05, "{p:?}");
    }

    #[test]
    fn a_biased_block_is_found() {
        let (w, h) = (128, 96);
        let mut d = noise(w, h, 0.05, 12);
        // +2 % of a unit reference in the block at (32, 48): z ≈ 0.02 / (0.05/16) = 6.4.
        for y in 48..64 {
            for x in 32..48 {
                d[y * w + x] += 0.02;
            }
        }
        let yr = vec![1.0; w * h];
        let b = block_z(&d, &yr, w, &Region::full(w, h), 16, 0.01);
        assert_eq!(b.flagged, 1, "{b:?}");
        assert_eq!(b.worst_block, (32, 48));
        assert!((b.worst_relative - 0.02).abs() < 0.01);
        // The same block is significant but within a 5 % tolerance.
        assert_eq!(
            block_z(&d, &yr, w, &Region::full(w, h), 16, 0.05).flagged,
            0
        );
    }

    #[test]
    fn a_global_bias_shifts_the_mean_pixel_z() {
        let (w, h) = (64, 64);
        let d: Vec<f64> = noise(w, h, 0.05, 13).iter().map(|v| v + 0.01).collect();
        let p = pixel_z(&d, w, &Region::full(w, h));
        // Expected mean z ≈ 0.01 / 0.051 ≈ 0.2, far beyond 1/√4096 ≈ 0.016.
        assert!(p.mean > 0.12, "{p:?}");
    }

    #[test]
    fn threshold_is_bonferroni() {
        let d = vec![0.0; 64 * 64];
        let b = block_z(&d, &d, 64, &Region::full(64, 64), 16, 0.0);
        assert_eq!(b.blocks, 16);
        assert_eq!(b.flagged, 0);
        assert!((b.threshold - normal::quantile(1.0 - 0.01 / 32.0)).abs() < 1e-12);
    }
}
