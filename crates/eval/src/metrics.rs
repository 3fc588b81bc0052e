//! All metrics of one image against a reference, in one pass over the selected region.

use crate::display::{display_value, luminance};
use crate::region::Region;
use crate::zscore::{BlockZ, PixelZ, block_z, pixel_z};
use crate::{EvalError, ssim};
use caustica_core::image_io::Image;

/// Constant in the relative MSE denominator, (I − R)² / (R² + ε), that keeps black reference
/// pixels from dominating (as in Rousselle et al. 2011 and most denoising papers).
pub const REL_MSE_EPSILON: f64 = 1e-2;

/// Settings of [`compare`].
#[derive(Clone, Copy, Debug)]
pub struct CompareOptions {
    /// Exposure (stops) of the display transform used by MISE and SSIM.
    pub exposure: f32,
    /// Side of the blocks of the regional bias test (pixels).
    pub block_size: usize,
    /// Smallest relative block difference the regional bias test reports.
    pub block_tolerance: f64,
}

impl Default for CompareOptions {
    fn default() -> Self {
        Self {
            exposure: 0.0,
            block_size: 16,
            block_tolerance: 0.01,
        }
    }
}

/// The result of comparing an image with a reference.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// Pixels compared.
    pub pixels: usize,
    /// Mean linear RGB of image and reference over the region (W/m²/sr).
    pub mean_image: [f64; 3],
    pub mean_reference: [f64; 3],
    /// Relative difference of the mean luminance, mean(Y_I)/mean(Y_R) − 1.
    pub relative_mean_difference: f64,
    /// Root mean square difference over pixels and RGB channels, linear (W/m²/sr).
    pub rmse: f64,
    /// Mean over pixels and channels of (I − R)² / (R² + [`REL_MSE_EPSILON`]).
    pub relative_mse: f64,
    /// Mean integrated square error of seed 000 ch. 6: the squared difference of display values
    /// integrated over the region with the region's area normalised to 1, i.e. the mean over
    /// pixels of (D(I) − D(R))², D the display transform of [`crate::display`].
    pub mise: f64,
    /// Mean SSIM on display values (`None` if the region is narrower than the 11×11 window).
    pub ssim: Option<f64>,
    pub pixel_z: PixelZ,
    pub block_z: BlockZ,
}

impl Comparison {
    /// The acceptance rule used against peer renderers: relative mean difference below
    /// `tolerance` and no block flagged by the regional bias test.
    pub fn agrees(&self, tolerance: f64) -> bool {
        self.relative_mean_difference.abs() < tolerance && self.block_z.flagged == 0
    }
}

/// Compares `image` with `reference` over `region`.
pub fn compare(
    image: &Image,
    reference: &Image,
    region: &Region,
    options: CompareOptions,
) -> Result<Comparison, EvalError> {
    if image.width != reference.width || image.height != reference.height {
        return Err(EvalError::SizeMismatch {
            iw: image.width,
            ih: image.height,
            rw: reference.width,
            rh: reference.height,
        });
    }
    let pixels = region.count();
    if pixels == 0 {
        return Err(EvalError::EmptyRegion);
    }
    let width = image.width;
    let finite = |v: f32| if v.is_finite() { f64::from(v) } else { 0.0 };
    let (mut mi, mut mr) = ([0.0f64; 3], [0.0f64; 3]);
    let (mut se, mut rel, mut ise) = (0.0, 0.0, 0.0);
    for i in region.indices() {
        let (a, r) = (image.data[i], reference.data[i]);
        for c in 0..3 {
            let (va, vr) = (finite(a[c]), finite(r[c]));
            mi[c] += va;
            mr[c] += vr;
            se += (va - vr).powi(2);
            rel += (va - vr).powi(2) / (vr * vr + REL_MSE_EPSILON);
        }
        ise += (display_value(a, options.exposure) - display_value(r, options.exposure)).powi(2);
    }
    let n = pixels as f64;
    let mean_image = mi.map(|v| v / n);
    let mean_reference = mr.map(|v| v / n);
    let lum = |m: [f64; 3]| luminance(m.map(|v| v as f32));
    let relative_mean_difference = lum(mean_image) / lum(mean_reference) - 1.0;

    // SSIM over the crop rectangle; window centres must be selected pixels.
    let crop = |img: &Image| -> Vec<f64> {
        (region.y0..region.y0 + region.h)
            .flat_map(|y| (region.x0..region.x0 + region.w).map(move |x| (x, y)))
            .map(|(x, y)| display_value(img.get(x, y), options.exposure))
            .collect()
    };
    let ssim = ssim::mean_ssim(
        &crop(image),
        &crop(reference),
        region.w,
        region.h,
        |x, y| region.contains(region.x0 + x, region.y0 + y),
    );

    let yi: Vec<f64> = image.data.iter().map(|&p| luminance(p)).collect();
    let yr: Vec<f64> = reference.data.iter().map(|&p| luminance(p)).collect();
    let d: Vec<f64> = yi.iter().zip(&yr).map(|(a, b)| a - b).collect();
    Ok(Comparison {
        pixels,
        mean_image,
        mean_reference,
        relative_mean_difference,
        rmse: (se / (3.0 * n)).sqrt(),
        relative_mse: rel / (3.0 * n),
        mise: ise / n,
        ssim,
        pixel_z: pixel_z(&d, width, region),
        block_z: block_z(
            &d,
            &yr,
            width,
            region,
            options.block_size,
            options.block_tolerance,
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(w: usize, h: usize, v: [f32; 3]) -> Image {
        let mut img = Image::new(w, h);
        img.data.fill(v);
        img
    }

    #[test]
    fn identical_images() {
        let mut img = flat(32, 24, [0.2, 0.4, 0.1]);
        img.set(3, 5, [1.0, 0.0, 0.5]);
        let c = compare(&img, &img, &Region::full(32, 24), CompareOptions::default()).unwrap();
        assert_eq!(c.pixels, 32 * 24);
        assert_eq!((c.rmse, c.relative_mse, c.mise), (0.0, 0.0, 0.0));
        assert_eq!(c.relative_mean_difference, 0.0);
        assert!((c.ssim.unwrap() - 1.0).abs() < 1e-12);
        assert!(c.agrees(1e-6));
    }

    #[test]
    fn constant_offset_has_analytic_errors() {
        let r = flat(20, 20, [0.5, 0.5, 0.5]);
        let i = flat(20, 20, [0.6, 0.6, 0.6]);
        let c = compare(&i, &r, &Region::full(20, 20), CompareOptions::default()).unwrap();
        assert!((c.rmse - 0.1).abs() < 1e-6);
        assert!((c.relative_mse - 0.01 / (0.25 + REL_MSE_EPSILON)).abs() < 1e-6);
        assert!((c.relative_mean_difference - 0.2).abs() < 1e-6);
        let (di, dr) = (display_value([0.6; 3], 0.0), display_value([0.5; 3], 0.0));
        assert!((c.mise - (di - dr).powi(2)).abs() < 1e-12);
        // Constant images: SSIM is the luminance term alone.
        let c1 = ssim::K1 * ssim::K1;
        let expect = (2.0 * di * dr + c1) / (di * di + dr * dr + c1);
        assert!((c.ssim.unwrap() - expect).abs() < 1e-9);
        assert!(!c.agrees(0.01));
    }

    #[test]
    fn crop_and_mask_restrict_every_metric() {
        let r = flat(40, 40, [0.5; 3]);
        let mut i = r.clone();
        // A large error outside the crop must not show.
        for y in 0..40 {
            i.set(0, y, [9.0; 3]);
        }
        let region = Region::crop(40, 40, (5, 5, 30, 30)).unwrap();
        let c = compare(&i, &r, &region, CompareOptions::default()).unwrap();
        assert_eq!(c.pixels, 900);
        assert_eq!(c.rmse, 0.0);
        assert!((c.ssim.unwrap() - 1.0).abs() < 1e-12);
        let mut mask = Image::new(40, 40);
        mask.set(0, 0, [1.0; 3]);
        let c = compare(
            &i,
            &r,
            &Region::full(40, 40).with_mask(&mask).unwrap(),
            CompareOptions::default(),
        )
        .unwrap();
        assert_eq!(c.pixels, 1);
        assert!((c.rmse - 8.5).abs() < 1e-6);
        assert!(c.ssim.is_none());
    }

    #[test]
    fn errors() {
        let a = Image::new(4, 4);
        let b = Image::new(4, 5);
        assert!(matches!(
            compare(&a, &b, &Region::full(4, 4), CompareOptions::default()),
            Err(EvalError::SizeMismatch { .. })
        ));
        let region = Region::full(4, 4).without_black(&a, &a);
        assert!(matches!(
            compare(&a, &a, &region, CompareOptions::default()),
            Err(EvalError::EmptyRegion)
        ));
    }
}
