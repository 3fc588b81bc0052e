//! Structural similarity (SSIM) of Wang, Bovik, Sheikh and Simoncelli, "Image quality assessment:
//! from error visibility to structural similarity", IEEE TIP 13(4), 2004.
//!
//! Settings of the paper (sec. III-C): an 11×11 circular-symmetric Gaussian window with σ = 1.5
//! normalised to unit sum, K1 = 0.01, K2 = 0.03, dynamic range L = 1 (images are display values
//! in [0, 1], see [`crate::display`]). The local index is eq. 13,
//! SSIM(x, y) = (2 μx μy + C1)(2 σxy + C2) / ((μx² + μy² + C1)(σx² + σy² + C2)),
//! C1 = (K1 L)², C2 = (K2 L)², and the image index is the mean of the local indices (eq. 17) over
//! the window positions that lie wholly inside the compared rectangle.

/// Window half-width: 11×11 window.
pub const RADIUS: usize = 5;
/// Gaussian window standard deviation (pixels).
pub const SIGMA: f64 = 1.5;
pub const K1: f64 = 0.01;
pub const K2: f64 = 0.03;

/// Normalised 1-D Gaussian weights; the 2-D window is their outer product.
pub fn window_1d() -> [f64; 2 * RADIUS + 1] {
    let mut w = [0.0; 2 * RADIUS + 1];
    for (i, wi) in w.iter_mut().enumerate() {
        let d = i as f64 - RADIUS as f64;
        *wi = (-d * d / (2.0 * SIGMA * SIGMA)).exp();
    }
    let sum: f64 = w.iter().sum();
    w.map(|v| v / sum)
}

/// Local SSIM map of two `w`×`h` display images (row-major), computed at every window centre
/// that keeps the window inside the image: the map is (`w`−10)×(`h`−10), or `None` if either
/// side is shorter than the window.
pub fn ssim_map(x: &[f64], y: &[f64], w: usize, h: usize) -> Option<(Vec<f64>, usize, usize)> {
    let n = 2 * RADIUS + 1;
    if w < n || h < n || x.len() != w * h || y.len() != w * h {
        return None;
    }
    let (mw, mh) = (w - 2 * RADIUS, h - 2 * RADIUS);
    let g = window_1d();
    // Separable filtering of the five moment images: horizontally, then vertically.
    let moments: [Vec<f64>; 5] = [
        x.to_vec(),
        y.to_vec(),
        x.iter().map(|v| v * v).collect(),
        y.iter().map(|v| v * v).collect(),
        x.iter().zip(y).map(|(a, b)| a * b).collect(),
    ];
    let filtered = moments.map(|m| {
        let mut horiz = vec![0.0; mw * h];
        for row in 0..h {
            for c in 0..mw {
                let src = &m[row * w + c..row * w + c + n];
                horiz[row * mw + c] = src.iter().zip(&g).map(|(a, b)| a * b).sum();
            }
        }
        let mut out = vec![0.0; mw * mh];
        for r in 0..mh {
            for c in 0..mw {
                out[r * mw + c] = (0..n).map(|k| g[k] * horiz[(r + k) * mw + c]).sum();
            }
        }
        out
    });
    let [mx, my, mxx, myy, mxy] = &filtered;
    let c1 = K1 * K1;
    let c2 = K2 * K2;
    let map = (0..mw * mh)
        .map(|i| {
            let (ux, uy) = (mx[i], my[i]);
            let sx = mxx[i] - ux * ux;
            let sy = myy[i] - uy * uy;
            let sxy = mxy[i] - ux * uy;
            ((2.0 * ux * uy + c1) * (2.0 * sxy + c2)) / ((ux * ux + uy * uy + c1) * (sx + sy + c2))
        })
        .collect();
    Some((map, mw, mh))
}

/// Mean SSIM of two `w`×`h` display images, averaging only the window centres (`cx`, `cy`)
/// (in image coordinates) for which `keep(cx, cy)` is true. `None` if no centre remains.
pub fn mean_ssim(
    x: &[f64],
    y: &[f64],
    w: usize,
    h: usize,
    keep: impl Fn(usize, usize) -> bool,
) -> Option<f64> {
    let (map, mw, mh) = ssim_map(x, y, w, h)?;
    let (mut sum, mut count) = (0.0, 0usize);
    for r in 0..mh {
        for c in 0..mw {
            if keep(c + RADIUS, r + RADIUS) {
                sum += map[r * mw + c];
                count += 1;
            }
        }
    }
    (count > 0).then(|| sum / count as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::rng::Pcg32;

    fn noise(w: usize, h: usize, seed: u64) -> Vec<f64> {
        let mut rng = Pcg32::new(seed, 0);
        (0..w * h).map(|_| f64::from(rng.next_f32())).collect()
    }

    #[test]
    fn window_is_normalised_gaussian() {
        let g = window_1d();
        assert!((g.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        // Ratio of neighbouring weights is exp(-(2d+1)/(2σ²)).
        assert!((g[RADIUS + 1] / g[RADIUS] - (-1.0 / (2.0 * SIGMA * SIGMA)).exp()).abs() < 1e-12);
    }

    #[test]
    fn identical_images_score_one_and_small_images_none() {
        let x = noise(20, 16, 1);
        assert!((mean_ssim(&x, &x, 20, 16, |_, _| true).unwrap() - 1.0).abs() < 1e-12);
        assert!(ssim_map(&x[..10 * 16], &x[..10 * 16], 10, 16).is_none());
        assert!(mean_ssim(&x, &x, 20, 16, |_, _| false).is_none());
    }

    #[test]
    fn constant_images_follow_the_luminance_term() {
        // Zero variance: SSIM = (2 a b + C1) / (a² + b² + C1) (eq. 13 with σ = 0).
        let (a, b) = (0.3, 0.6);
        let x = vec![a; 15 * 15];
        let y = vec![b; 15 * 15];
        let expect = (2.0 * a * b + K1 * K1) / (a * a + b * b + K1 * K1);
        let got = mean_ssim(&x, &y, 15, 15, |_, _| true).unwrap();
        assert!((got - expect).abs() < 1e-12, "{got} vs {expect}");
    }

    #[test]
    fn negated_contrast_matches_brute_force_window_statistics() {
        // y = 2m − x has μy = 2m − μx, σy² = σx², σxy = −σx² under any window; the expected
        // local index is computed with a direct 2-D window sum, independent of the separable code.
        let (w, h) = (17, 14);
        let x = noise(w, h, 7);
        let y: Vec<f64> = x.iter().map(|v| 1.0 - v).collect();
        let g = window_1d();
        let (c1, c2) = (K1 * K1, K2 * K2);
        let (mut sum, mut count) = (0.0, 0);
        for cy in RADIUS..h - RADIUS {
            for cx in RADIUS..w - RADIUS {
                let (mut m1, mut m2) = (0.0, 0.0);
                for dy in 0..11 {
                    for dx in 0..11 {
                        let v = x[(cy + dy - RADIUS) * w + cx + dx - RADIUS];
                        m1 += g[dy] * g[dx] * v;
                        m2 += g[dy] * g[dx] * v * v;
                    }
                }
                let var = m2 - m1 * m1;
                let uy = 1.0 - m1;
                sum += (2.0 * m1 * uy + c1) / (m1 * m1 + uy * uy + c1) * (c2 - 2.0 * var)
                    / (2.0 * var + c2);
                count += 1;
            }
        }
        let expect = sum / count as f64;
        let got = mean_ssim(&x, &y, w, h, |_, _| true).unwrap();
        assert!((got - expect).abs() < 1e-9, "{got} vs {expect}");
        assert!(got < 0.0, "negated structure must score below zero: {got}");
    }
}
