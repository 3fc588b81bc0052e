//! `caustica merge`: the partial results of a sharded render (`render --shard I/N`) into its
//! image, byte-identical to the render without shards.

use crate::render_cmd::{check_image_extension, check_writable, write_atomically};
use anyhow::{Context, Result, bail};
use caustica_render::partial::{Merge, Part};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Args, Debug)]
pub struct MergeArgs {
    /// Partial results: .cpart files written by `caustica render --shard I/N`, or directories
    /// (every .cpart file inside is read).
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// Output image (.exr, .pfm or .png), or a .cpart: a part holding every shard given, to
    /// merge again with the parts of the other shards (a tree of merges: each merge reads a few
    /// films instead of one reading them all; the result is the same bytes).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Also write an sRGB PNG.
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Exposure (stops) applied to PNG output.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = crate::values::finite_f32)]
    pub exposure: f32,
    /// Merge the shards given even if some are missing, for a preview of a render in progress
    /// (the parts still must belong together): missing pixel rows are black, a light tracer's
    /// image is normalised by the paths present, pds's caustic is dimmer by the share of splat
    /// chunks missing, progressive methods average the iterations present.
    #[arg(long)]
    pub partial: bool,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
}

/// The .cpart files of `inputs`: files as given, directories' .cpart files sorted by name.
fn part_files(inputs: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for p in inputs {
        if p.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(p)
                .with_context(|| format!("cannot list {}", p.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| f.extension().and_then(|e| e.to_str()) == Some("cpart"))
                // A shard still writing (or killed while writing) leaves its temporary file.
                .filter(|f| !f.to_string_lossy().ends_with(".partial.cpart"))
                .collect();
            found.sort();
            if found.is_empty() && inputs.len() == 1 {
                bail!("{}: no .cpart files in this directory", p.display());
            }
            files.extend(found);
        } else {
            files.push(p.clone());
        }
    }
    Ok(files)
}

pub fn run(args: MergeArgs) -> Result<()> {
    let to_part = args.output.extension().and_then(|e| e.to_str()) == Some("cpart");
    if !to_part {
        check_image_extension(&args.output)
            .context("merge writes an image, or a .cpart of the shards given")?;
    }
    if to_part && args.png.is_some() {
        bail!("--png goes with an image output, not a merged part (.cpart)");
    }
    let files = part_files(&args.parts)?;
    if files.is_empty() {
        bail!("no partial results to merge");
    }
    check_writable(&args.output)?;
    if let Some(png) = &args.png {
        check_writable(png)?;
    }
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(files.len() as u64)
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} parts, {eta} left",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let started = Instant::now();
    let mut merge = Merge::new();
    let mut bytes_read = 0u64;
    for f in &files {
        let name = f.display().to_string();
        let bytes = std::fs::read(f).map_err(|e| anyhow::anyhow!("cannot read {name}: {e}"))?;
        bytes_read += bytes.len() as u64;
        let part = Part::decode(&bytes, &name)?;
        drop(bytes);
        merge.add(part, &name)?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    let missing = merge.missing();
    let manifest = merge
        .manifest()
        .cloned()
        .context("no partial results to merge")?;
    let count = manifest.count;
    if to_part {
        // An inner node of a tree of merges: the shards given, whatever is missing.
        let part = merge.finish_part()?;
        let bytes = part.to_bytes();
        write_atomically(&args.output, |p| std::fs::write(p, &bytes))?;
        let secs = started.elapsed().as_secs_f64().max(1e-9);
        println!(
            "merged {} parts into one holding shards {} in {secs:.2} s: {:.1} MB read at {:.0} MB/s -> {}",
            files.len(),
            part.manifest.shards_text(),
            bytes_read as f64 / 1e6,
            bytes_read as f64 / 1e6 / secs,
            args.output.display()
        );
        return Ok(());
    }
    let film = merge.finish(args.partial)?;
    let img = film.to_image();
    write_image(&img, &args.output, args.png.as_deref(), args.exposure)?;
    let secs = started.elapsed().as_secs_f64().max(1e-9);
    let mut lines = manifest.fingerprint.lines();
    let (version, scene, integrator) = (lines.next(), lines.next(), lines.next());
    if !missing.is_empty() {
        eprintln!(
            "preview: {} of {count} shards missing ({})",
            missing.len(),
            missing
                .iter()
                .map(|i| i.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    println!(
        "merged {} of {count} shards from {} parts ({}; {}; {}) in {secs:.2} s: {:.1} MB read at {:.0} MB/s -> {}",
        count as usize - missing.len(),
        files.len(),
        scene.unwrap_or("?"),
        integrator.unwrap_or("?"),
        version.unwrap_or("?"),
        bytes_read as f64 / 1e6,
        bytes_read as f64 / 1e6 / secs,
        args.output.display()
    );
    Ok(())
}

fn write_image(
    img: &caustica_core::image_io::Image,
    out: &Path,
    png: Option<&Path>,
    exposure: f32,
) -> Result<()> {
    write_atomically(out, |p| img.write(p))?;
    if let Some(png) = png {
        write_atomically(png, |p| img.write_png(p, exposure))?;
    }
    Ok(())
}
