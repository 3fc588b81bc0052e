//! The film: per-pixel accumulators for camera samples and a splat buffer for light paths.
//!
//! Pixel values are radiance (W/m²/sr) averaged over the pixel's filter footprint. Camera
//! samples are averaged per pixel (each has weight 1 under filter importance sampling); splats
//! from light tracing are summed and scaled by 1/N, N the number of light paths traced.
//!
//! The sums are [`ExactSum`]s: each addend is truncated once on its own and the additions are
//! exact, so a film is the same whatever order its samples, splat buffers, iterations or shards
//! were added in. That is what makes `--shard` merges byte-identical to one render.
//!
//! A film may hold only a [`CropWindow`] of the camera's film: its `width` × `height` are the
//! window's, pixel (0, 0) is the window's top-left pixel, and [`Film::window`] says where that
//! lies on the full film (whose coordinates the drivers use for rays and random numbers).

use caustica_core::image_io::Image;
use caustica_core::{Spectrum, Vec2};

use crate::crop::CropWindow;
use crate::exact_sum::ExactSum;
use crate::filter::Filter;
use crate::shard::RowSet;

/// The accumulators of one image (exact sums, [`ExactSum`]).
#[derive(Clone, Debug)]
pub struct Film {
    /// Size of the image held (the window's).
    pub width: usize,
    pub height: usize,
    /// Where the image lies on the camera's film, and that film's size.
    window: CropWindow,
    pub(crate) full: (usize, usize),
    /// Σ L per pixel (camera samples, W/m²/sr).
    pub(crate) sum: Vec<[ExactSum; 3]>,
    /// Number of camera samples per pixel.
    pub(crate) count: Vec<u32>,
    /// Σ splatted contributions per pixel (light paths; W/m²/sr once divided by their count).
    pub(crate) splat: Vec<[ExactSum; 3]>,
    /// Number of light paths whose splats are in `splat`.
    pub(crate) splat_paths: u64,
    /// The rows (of the film held) that camera samples are added to: all of them, or a shard's
    /// ([`Film::restrict_rows`]).
    rows: RowSet,
}

impl Film {
    /// A film for a whole `width` × `height` image.
    pub fn new(width: usize, height: usize) -> Self {
        Self::cropped(CropWindow::full(width as u32, height as u32), width, height)
    }

    /// A film for `window` of a `full_width` × `full_height` camera film (the window is assumed
    /// inside it, see [`CropWindow::check`]).
    pub fn cropped(window: CropWindow, full_width: usize, full_height: usize) -> Self {
        debug_assert!(
            window.x as usize + window.width as usize <= full_width
                && window.y as usize + window.height as usize <= full_height,
            "crop window {window} outside the {full_width}x{full_height} film"
        );
        let (width, height) = (window.width as usize, window.height as usize);
        let n = width * height;
        Self {
            width,
            height,
            window,
            full: (full_width, full_height),
            sum: vec![[ExactSum::ZERO; 3]; n],
            count: vec![0; n],
            splat: vec![[ExactSum::ZERO; 3]; n],
            splat_paths: 0,
            rows: RowSet::ALL,
        }
    }

    /// Adds camera samples only to `rows` (a shard's rows of the film held): the pixel driver
    /// renders no other row, or, when the method needs every pixel's eye vertices, renders them
    /// without adding their samples. Splats still reach every pixel.
    pub fn restrict_rows(&mut self, rows: RowSet) {
        self.rows = rows;
    }

    /// The rows camera samples are added to.
    pub fn rows(&self) -> RowSet {
        self.rows
    }

    /// The window of the camera's film this film holds (the whole film unless cropped).
    pub fn window(&self) -> CropWindow {
        self.window
    }

    /// Size of the camera's full film (pixels).
    pub fn full_size(&self) -> (usize, usize) {
        self.full
    }

    /// Mean camera samples per pixel so far.
    pub fn mean_samples(&self) -> f64 {
        self.count.iter().map(|&c| c as f64).sum::<f64>() / self.count.len().max(1) as f64
    }

    /// Adds the samples and splats of `other` (a film of the same window) to this one: the
    /// result is the estimate of both renders' samples pooled (with equal samples per pixel,
    /// the mean of their images). Exact: merging films in any order or grouping gives the same
    /// film.
    pub fn merge(&mut self, other: &Film) {
        debug_assert_eq!((self.window, self.full), (other.window, other.full));
        for (d, s) in self.sum.iter_mut().zip(&other.sum) {
            for k in 0..3 {
                d[k] += s[k];
            }
        }
        for (d, s) in self.count.iter_mut().zip(&other.count) {
            *d += s;
        }
        for (d, s) in self.splat.iter_mut().zip(&other.splat) {
            for k in 0..3 {
                d[k] += s[k];
            }
        }
        self.splat_paths += other.splat_paths;
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
                *out = (self.sum[i][k].to_f64() * inv_count + self.splat[i][k].to_f64() * inv_paths)
                    as f32;
            }
        }
        img
    }
}

/// A buffer of a film's pixels that light paths splat into; merged into a [`Film`] in a fixed
/// order so the result does not depend on the thread schedule. Splats are at raster positions of
/// the camera's full film and spread over its pixels as if the whole film were held; only the
/// film's window is kept.
#[derive(Clone, Debug)]
pub struct SplatBuffer {
    /// Size of the camera's full film.
    width: usize,
    height: usize,
    window: CropWindow,
    data: Vec<[f32; 3]>,
}

impl SplatBuffer {
    /// A buffer for the pixels `film` holds.
    pub fn for_film(film: &Film) -> Self {
        let (width, height) = film.full;
        Self {
            width,
            height,
            window: film.window,
            data: vec![[0.0; 3]; film.width * film.height],
        }
    }

    /// Adds `c` to full-film pixel (`x`, `y`) if it is in the window.
    #[inline]
    fn add_pixel(&mut self, x: usize, y: usize, c: [f32; 3]) {
        if !self.window.contains(x, y) {
            return;
        }
        let (lx, ly) = (x - self.window.x as usize, y - self.window.y as usize);
        let d = &mut self.data[ly * self.window.width as usize + lx];
        for (d, c) in d.iter_mut().zip(c) {
            *d += c;
        }
    }

    /// True when a splat at raster position `p` may reach a pixel of the window (a conservative
    /// test: the light tracer skips the camera connection's shadow ray when it cannot).
    pub fn reaches(&self, filter: &Filter, p: Vec2) -> bool {
        let r = filter.radius().max(0.5);
        let win = self.window;
        p.x + r >= win.x as f32
            && p.y + r >= win.y as f32
            && p.x - r < (win.x + win.width) as f32
            && p.y - r < (win.y + win.height) as f32
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
                self.add_pixel(x, y, v.c);
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
                    self.add_pixel(x, y, v.c.map(|v| w * v));
                }
            }
        }
    }

    /// Adds this buffer into `film` as the splats of `paths` light paths.
    pub fn merge_into(&self, film: &mut Film, paths: u64) {
        for (d, s) in film.splat.iter_mut().zip(&self.data) {
            for k in 0..3 {
                if s[k] != 0.0 {
                    d[k] += ExactSum::from_f32(s[k]);
                }
            }
        }
        film.splat_paths += paths;
    }
}
