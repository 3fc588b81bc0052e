//! `caustica convert`: an image from one format to another (EXR, PFM, PNG), PNGs tone-mapped
//! as `render --png` writes them (exposure, then sRGB, clamped to 8 bits).

use anyhow::{Context, Result, bail};
use caustica_core::image_io::Image;
use clap::Args;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// Image to read (.exr, .pfm or .png).
    pub input: PathBuf,
    /// Image to write (.exr, .pfm or .png), by its extension.
    pub output: PathBuf,
    /// Exposure in stops: pixels are scaled by 2^S before writing (any format; a finite
    /// number, default 0).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = crate::values::finite_f32)]
    pub exposure: f32,
}

pub fn run(args: ConvertArgs) -> Result<()> {
    let ext = |p: &std::path::Path| {
        p.extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
    };
    if !matches!(ext(&args.output).as_deref(), Some("exr" | "pfm" | "png")) {
        bail!(
            "output {} must end in .exr, .pfm or .png",
            args.output.display()
        );
    }
    let mut img = Image::read(&args.input)
        .with_context(|| format!("cannot read image {}", args.input.display()))?;
    if args.exposure != 0.0 {
        let scale = args.exposure.exp2();
        for p in &mut img.data {
            *p = p.map(|v| v * scale);
        }
    }
    img.write(&args.output)
        .with_context(|| format!("cannot write {}", args.output.display()))?;
    println!(
        "{} -> {} ({}x{})",
        args.input.display(),
        args.output.display(),
        img.width,
        img.height
    );
    Ok(())
}
