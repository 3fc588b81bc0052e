//! Pixel reconstruction filters, applied by filter importance sampling: each camera sample's
//! offset from the pixel centre is drawn from the filter itself, so every sample has weight 1
//! and belongs to exactly one pixel (pbrt-v4 §8.8). Pixels are then independent, which keeps
//! renders deterministic under any parallel schedule. Light-tracer splats, which arrive at
//! arbitrary raster positions, are spread over the pixels within the filter radius with
//! normalised filter weights.

use caustica_core::Vec2;
use caustica_scene::scene::FilterKind;

/// A separable reconstruction filter.
#[derive(Clone, Debug)]
pub struct Filter {
    kind: FilterKind,
    /// Inverse CDF table of the 1-D marginal on [−radius, radius] (Gaussian only).
    inv_cdf: Vec<f32>,
}

const TABLE: usize = 1024;

impl Filter {
    pub fn new(kind: FilterKind) -> Self {
        let inv_cdf = match kind {
            FilterKind::Box => Vec::new(),
            FilterKind::Gaussian { stddev, radius } => {
                // Tabulate the CDF of the truncated Gaussian on a fine grid and invert it.
                let n = 4096;
                let mut cdf = vec![0.0f64; n + 1];
                for i in 0..n {
                    let x = -radius as f64 + (i as f64 + 0.5) / n as f64 * 2.0 * radius as f64;
                    cdf[i + 1] = cdf[i] + gaussian(x, stddev as f64);
                }
                let total = cdf[n];
                (0..=TABLE)
                    .map(|j| {
                        let target = j as f64 / TABLE as f64 * total;
                        let k = cdf.partition_point(|&c| c < target).clamp(1, n);
                        let (c0, c1) = (cdf[k - 1], cdf[k]);
                        let frac = if c1 > c0 {
                            (target - c0) / (c1 - c0)
                        } else {
                            0.5
                        };
                        (-radius as f64 + (k as f64 - 1.0 + frac) / n as f64 * 2.0 * radius as f64)
                            as f32
                    })
                    .collect()
            }
        };
        Self { kind, inv_cdf }
    }

    /// Radius of support (pixels).
    pub fn radius(&self) -> f32 {
        match self.kind {
            FilterKind::Box => 0.5,
            FilterKind::Gaussian { radius, .. } => radius,
        }
    }

    /// Offset from the pixel centre (pixels) distributed like the filter, from `u ∈ [0,1)²`.
    #[inline]
    pub fn sample(&self, u: Vec2) -> Vec2 {
        match self.kind {
            FilterKind::Box => u - Vec2::splat(0.5),
            FilterKind::Gaussian { .. } => Vec2::new(self.invert(u.x), self.invert(u.y)),
        }
    }

    fn invert(&self, u: f32) -> f32 {
        let x = u * TABLE as f32;
        let i = (x as usize).min(TABLE - 1);
        let f = x - i as f32;
        self.inv_cdf[i] * (1.0 - f) + self.inv_cdf[i + 1] * f
    }

    /// Unnormalised filter value at offset `d` (pixels).
    #[inline]
    pub fn eval(&self, d: Vec2) -> f32 {
        match self.kind {
            FilterKind::Box => {
                if d.x.abs() <= 0.5 && d.y.abs() <= 0.5 {
                    1.0
                } else {
                    0.0
                }
            }
            FilterKind::Gaussian { stddev, radius } => {
                if d.x.abs() > radius || d.y.abs() > radius {
                    0.0
                } else {
                    (gaussian(d.x as f64, stddev as f64) * gaussian(d.y as f64, stddev as f64))
                        as f32
                }
            }
        }
    }
}

fn gaussian(x: f64, s: f64) -> f64 {
    (-0.5 * x * x / (s * s)).exp()
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::chi2::chi_square;
    use caustica_core::sampling::Pcg32;

    #[test]
    fn gaussian_sampling_matches_filter_shape() {
        let f = Filter::new(FilterKind::Gaussian {
            stddev: 0.5,
            radius: 1.5,
        });
        let bins = 30;
        let mut obs = vec![0.0f64; bins];
        let mut rng = Pcg32::new(1, 2);
        let n = 200_000;
        for _ in 0..n {
            let x = f.sample(Vec2::new(rng.next_f32(), 0.5)).x;
            let b = (((x + 1.5) / 3.0) * bins as f32)
                .floor()
                .clamp(0.0, bins as f32 - 1.0) as usize;
            obs[b] += 1.0;
        }
        // Expected counts from the analytic Gaussian integrated per bin.
        let fine = 100;
        let mut exp = vec![0.0f64; bins];
        let mut total = 0.0;
        for (b, e) in exp.iter_mut().enumerate() {
            for k in 0..fine {
                let x = -1.5 + 3.0 * (b as f64 + (k as f64 + 0.5) / fine as f64) / bins as f64;
                *e += (-0.5 * x * x / 0.25).exp();
            }
            total += *e;
        }
        exp.iter_mut().for_each(|e| *e *= n as f64 / total);
        let r = chi_square(&obs, &exp);
        assert!(r.passed(), "{r}");
    }

    #[test]
    fn box_sampling_covers_the_pixel() {
        let f = Filter::new(FilterKind::Box);
        assert_eq!(f.sample(Vec2::ZERO), Vec2::splat(-0.5));
        assert_eq!(f.eval(Vec2::new(0.6, 0.0)), 0.0);
    }
}
