//! `caustica compare IMAGE REFERENCE`: the numbers two images differ by.

use anyhow::{Context, Result};
use caustica_core::image_io::Image;
use caustica_eval::metrics::CompareOptions;
use caustica_eval::zscore::{T24_TAIL_2, T24_TAIL_3};
use caustica_eval::{Region, colormap, compare, display::luminance};
use clap::Args;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct CompareArgs {
    /// Image to judge (.exr, .pfm or .png).
    pub image: PathBuf,
    /// Reference image of the same size.
    pub reference: PathBuf,
    #[command(flatten)]
    pub metric: MetricArgs,
    /// Block side (pixels) of the regional bias test.
    #[arg(long, default_value_t = 16)]
    pub block: usize,
    /// Relative block difference below which the bias test never flags a block.
    #[arg(long, default_value_t = 0.01)]
    pub block_tolerance: f64,
    /// Write a false-colour image of the signed luminance difference (blue: image darker, red:
    /// brighter); full colour at --error-scale.
    #[arg(long, value_name = "FILE")]
    pub error_image: Option<PathBuf>,
    /// Luminance difference (W/m²/sr) shown at full colour (default: 3 × luminance RMSE).
    #[arg(long)]
    pub error_scale: Option<f64>,
    /// Exit with status 2 unless the images agree: |relative mean difference| < TOL and no
    /// block flagged by the bias test.
    #[arg(long, value_name = "TOL")]
    pub check: Option<f64>,
}

/// Which pixels the metrics look at and the display transform of MISE and SSIM (shared by
/// `compare` and `sweep`).
#[derive(Args, Clone, Debug)]
pub struct MetricArgs {
    /// Compare only this rectangle: left,top,width,height in pixels.
    #[arg(long, value_name = "X,Y,W,H")]
    pub crop: Option<String>,
    /// Compare only pixels where this image (same size) is non-zero.
    #[arg(long, value_name = "MASK")]
    pub mask: Option<PathBuf>,
    /// Ignore pixels that are black in both images (light tracers leave pixels that see glass
    /// or mirrors directly black); this leaves the ratio of the means unchanged.
    #[arg(long)]
    pub mask_black: bool,
    /// Exposure (stops) of the display transform used by MISE and SSIM.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = crate::values::finite_f32)]
    pub exposure: f32,
}

impl MetricArgs {
    /// The crop rectangle and mask (read here) for `width`×`height` images, checked.
    pub fn region(&self, width: usize, height: usize) -> Result<Region> {
        let mask = match &self.mask {
            Some(m) => Some((read(m, "mask")?, m.display().to_string())),
            None => None,
        };
        self.region_with(width, height, mask.as_ref().map(|(m, n)| (m, n.as_str())))
    }

    /// [`MetricArgs::region`] with the mask given as an image and the name its errors use
    /// (`self.mask` is not read): the Python package's `compare`.
    pub fn region_with(
        &self,
        width: usize,
        height: usize,
        mask: Option<(&Image, &str)>,
    ) -> Result<Region> {
        let mut region = match &self.crop {
            Some(c) => {
                // The same X,Y,W,H rule as `render --crop`, checked against the images.
                let win = caustica_render::CropWindow::parse(c, width as u32, height as u32)?;
                let (x, y, w, h) = (win.x, win.y, win.width, win.height);
                Region::crop(
                    width,
                    height,
                    (x as usize, y as usize, w as usize, h as usize),
                )?
            }
            None => Region::full(width, height),
        };
        if let Some((m, name)) = mask {
            region = region
                .with_mask(m)
                .with_context(|| format!("mask {name}"))?;
        }
        Ok(region)
    }

    /// `region` for one image pair: without the pixels black in both under `--mask-black`.
    pub fn region_for(&self, region: &Region, image: &Image, reference: &Image) -> Region {
        if self.mask_black {
            region.clone().without_black(image, reference)
        } else {
            region.clone()
        }
    }
}

/// Reads an image; errors name `what` it is and the file.
pub fn read(path: &Path, what: &str) -> Result<Image> {
    Image::read(path).with_context(|| format!("cannot read {what} {}", path.display()))
}

/// Runs the command; returns the process exit status (0, or 2 when `--check` fails).
pub fn run(args: CompareArgs) -> Result<i32> {
    let image = read(&args.image, "image")?;
    let reference = read(&args.reference, "reference")?;
    let (w, h) = (reference.width, reference.height);
    let region = args.metric.region(w, h)?;
    let region = args.metric.region_for(&region, &image, &reference);
    let options = CompareOptions {
        exposure: args.metric.exposure,
        block_size: args.block,
        block_tolerance: args.block_tolerance,
    };
    let c = compare(&image, &reference, &region, options).with_context(|| {
        format!(
            "comparing {} with {}",
            args.image.display(),
            args.reference.display()
        )
    })?;
    let [a, b] =
        [c.mean_image, c.mean_reference].map(|m| format!("{:.6} {:.6} {:.6}", m[0], m[1], m[2]));
    println!("pixels                    {}", c.pixels);
    println!("mean image (RGB)          {a}");
    println!("mean reference (RGB)      {b}");
    println!(
        "relative mean difference  {:+.5}",
        c.relative_mean_difference
    );
    println!("RMSE                      {:.6}", c.rmse);
    println!("relative MSE              {:.6}", c.relative_mse);
    println!("MISE (display)            {:.6}", c.mise);
    match c.ssim {
        Some(s) => println!("SSIM (display)            {s:.5}"),
        None => println!("SSIM (display)            n/a (region narrower than 11 px)"),
    }
    let p = &c.pixel_z;
    println!(
        "pixel z                   mean {:+.4} (s.e. {:.4}), rms {:.3}, |z|>2 {:.2} % (noise {:.2} %), |z|>3 {:.2} % (noise {:.2} %), {} px",
        p.mean,
        1.0 / (p.pixels.max(1) as f64).sqrt(),
        p.rms,
        100.0 * p.frac_over_2,
        100.0 * T24_TAIL_2,
        100.0 * p.frac_over_3,
        100.0 * T24_TAIL_3,
        p.pixels
    );
    let bz = &c.block_z;
    println!(
        "block z ({0}x{0})           flagged {5} of {6} (|z| > {7:.2} and |diff| >= {8:.1} %); largest |z| of such blocks {1:.2} at ({2},{3}) [{4:+.2} %]",
        bz.size,
        bz.max_abs_z,
        bz.worst_block.0,
        bz.worst_block.1,
        100.0 * bz.worst_relative,
        bz.flagged,
        bz.blocks,
        bz.threshold,
        100.0 * bz.tolerance
    );
    if let Some(path) = &args.error_image {
        let d: Vec<f64> = image
            .data
            .iter()
            .zip(&reference.data)
            .map(|(&x, &y)| luminance(x) - luminance(y))
            .collect();
        let scale = args.error_scale.unwrap_or_else(|| {
            let n = c.pixels as f64;
            3.0 * (region.indices().map(|i| d[i] * d[i]).sum::<f64>() / n).sqrt()
        });
        let scale = if scale > 0.0 { scale } else { 1.0 };
        let keep = |i: usize| region.contains(i % w, i / w);
        colormap::signed_error_image(&d, w, h, scale, keep)
            .write(path)
            .with_context(|| format!("cannot write error image {}", path.display()))?;
        println!(
            "error image               {} (full colour at ±{scale:.4})",
            path.display()
        );
    }
    if let Some(tol) = args.check {
        let ok = c.agrees(tol);
        println!(
            "agreement                 {}",
            if ok { "yes" } else { "NO" }
        );
        return Ok(if ok { 0 } else { 2 });
    }
    Ok(0)
}
