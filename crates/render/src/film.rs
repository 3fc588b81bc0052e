//! The film: per-pixel accumulators for camera samples and a splat buffer for light paths.
//!
//! Pixel values are radiance (W/m²/sr) averaged over the pixel's filter footprint. Camera
//! samples are averaged per pixel (each has weight 1 under filter importance sampling); splats
//! from light tracing are summed and scaled by 1/N, N the number of light paths traced.

use caustica_core::image_io::Image;
use caustica_core::{Spectrum, Vec2};

use crate::filter::Filter;

/// Float accumulators of one image.
#[derive(Clone, Debug)]
pub struct Film {
    pub width: usize,
    pub height: usize,
    /// Σ L per pixel (camera samples).
    pub(crate) sum: Vec<[f64; 3]>,
    /// Number of camera samples per pixel.
    pub(crate) count: Vec<u32>,
    /// Σ splatted contributions per pixel (light paths).
    pub(crate) splat: Vec<[f64; 3]>,
    /// Number of light paths whose splats are in `splat`.
    pub(crate) splat_paths: u64,
}

impl Film {
    pub fn new(width: usize, height: usize) -> Self {
        let n = width * height;
        Self {
            width,
            height,
            sum: vec![[0.0; 3]; n],
            count: vec![0; n],
            splat: vec![[0.0; 3]; n],
            splat_paths: 0,
        }
    }

    /// Mean camera samples per pixel so far.
    pub fn mean_samples(&self) -> f64 {
        self.count.iter().map(|&c| c as f64).sum::<f64>() / self.count.len().max(1) as f64
    }

    /// Light paths accumulated so far.
    pub fn light_paths(&self) -> u64 {
        self.splat_paths
    }

    /// The current estimate as an image.
    pub fn to_image(&self) -> Image {
        let mut img = Image::new(self.width, self.height);
        let inv_paths = if self.splat_paths > 0 {
            1.0 / self.splat_paths as f64
        } else {
            0.0
        };
        for (i, px) in img.data.iter_mut().enumerate() {
            let c = self.count[i];
            let inv_count = if c > 0 { 1.0 / c as f64 } else { 0.0 };
            for (k, out) in px.iter_mut().enumerate() {
                *out = (self.sum[i][k] * inv_count + self.splat[i][k] * inv_paths) as f32;
            }
        }
        img
    }
}

/// A full-resolution buffer that light paths splat into; merged into a [`Film`] in a fixed order
/// so the result does not depend on the thread schedule.
#[derive(Clone, Debug)]
pub struct SplatBuffer {
    width: usize,
    height: usize,
    data: Vec<[f32; 3]>,
}

impl SplatBuffer {
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            width,
            height,
            data: vec![[0.0; 3]; width * height],
        }
    }

    pub fn clear(&mut self) {
        self.data.iter_mut().for_each(|p| *p = [0.0; 3]);
    }

    /// Adds `v` at raster position `p` (pixels), spread over the pixels in the filter's support
    /// with weights normalised to sum to one.
    pub fn add(&mut self, filter: &Filter, p: Vec2, v: Spectrum) {
        let r = filter.radius();
        let x0 = ((p.x - r).floor().max(0.0)) as usize;
        let y0 = ((p.y - r).floor().max(0.0)) as usize;
        let x1 = ((p.x + r).floor() as isize).min(self.width as isize - 1);
        let y1 = ((p.y + r).floor() as isize).min(self.height as isize - 1);
        if x1 < 0 || y1 < 0 {
            return;
        }
        let (x1, y1) = (x1 as usize, y1 as usize);
        if x0 == x1 && y0 == y1 || r <= 0.5 {
            let (x, y) = (p.x.floor() as usize, p.y.floor() as usize);
            if x < self.width && y < self.height {
                let d = &mut self.data[y * self.width + x];
                for (d, v) in d.iter_mut().zip(v.c) {
                    *d += v;
                }
            }
            return;
        }
        let mut total = 0.0;
        for y in y0..=y1 {
            for x in x0..=x1 {
                total += filter.eval(p - Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
            }
        }
        if total <= 0.0 {
            return;
        }
        for y in y0..=y1 {
            for x in x0..=x1 {
                let w = filter.eval(p - Vec2::new(x as f32 + 0.5, y as f32 + 0.5)) / total;
                if w > 0.0 {
                    let d = &mut self.data[y * self.width + x];
                    for (d, v) in d.iter_mut().zip(v.c) {
                        *d += w * v;
                    }
                }
            }
        }
    }

    /// Adds this buffer into `film` as the splats of `paths` light paths.
    pub fn merge_into(&self, film: &mut Film, paths: u64) {
        for (d, s) in film.splat.iter_mut().zip(&self.data) {
            for k in 0..3 {
                d[k] += s[k] as f64;
            }
        }
        film.splat_paths += paths;
    }
}
