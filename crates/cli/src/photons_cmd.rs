//! `caustica photons SCENE`: the stored photons drawn as points over a dim image of the scene.

use crate::photon_args::PhotonArgs;
use crate::render_cmd::load;
use anyhow::{Context, Result, bail};
use caustica_core::Spectrum;
use caustica_core::sampling::SamplerKind;
use caustica_render::integrator::photon_mapping::PhotonMaps;
use caustica_render::photon_view::draw_photons;
use caustica_render::{IntegratorKind, PathLimits, RenderControl, RenderOptions, render};
use clap::Args;
use std::path::PathBuf;

#[derive(Args)]
pub struct PhotonsArgs {
    /// Scene file or built-in scene name.
    pub scene: Option<String>,
    /// Mitsuba scene parameter: `-D name=value` (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    pub define: Vec<String>,
    /// Output image (.png, .exr or .pfm).
    #[arg(short, long, default_value = "photons.png")]
    pub output: PathBuf,
    /// Samples per pixel of the path-traced background (0 = black).
    #[arg(long, default_value_t = 4)]
    pub background_spp: u32,
    /// Background brightness factor.
    #[arg(long, default_value_t = 0.3)]
    pub dim: f32,
    /// Seed of the photon and background random numbers (same seed, same image).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Longest light path in edges (-1 = unlimited).
    #[arg(long, default_value_t = -1, allow_negative_numbers = true)]
    pub max_depth: i64,
    #[command(flatten)]
    pub photon: PhotonArgs,
}

pub fn run(args: PhotonsArgs) -> Result<()> {
    let defines = crate::render_cmd::parse_defines(&args.define)?;
    crate::render_cmd::check_writable(&args.output)?;
    let scene = load(args.scene.as_deref(), &defines, Default::default())?;
    IntegratorKind::PhotonMapping.check_scene(&scene)?;
    let max_depth = match args.max_depth {
        -1 => u32::MAX,
        d if d >= 1 => d.min(u32::MAX as i64) as u32,
        d => bail!("--max-depth must be -1 (unlimited) or at least 1, got {d}"),
    };
    let opts = RenderOptions {
        spp: args.background_spp.max(1),
        seed: args.seed,
        sampler: SamplerKind::Sobol,
        limits: PathLimits {
            max_depth,
            ..PathLimits::default()
        },
        photons: args.photon.options()?,
        ..RenderOptions::default()
    };
    let mut img = if args.background_spp > 0 {
        let out = render(
            &scene,
            IntegratorKind::Path,
            &opts,
            &RenderControl::silent(),
        )?;
        let mut img = out.film.to_image();
        for p in &mut img.data {
            *p = p.map(|c| c * args.dim);
        }
        img
    } else {
        caustica_core::image_io::Image::new(
            scene.camera.width as usize,
            scene.camera.height as usize,
        )
    };
    let maps = PhotonMaps::build(&scene, &opts);
    for w in &maps.warnings {
        eprintln!("warning: {w}");
    }
    // Global photons in blue, caustic photons (drawn last, on top) in orange.
    let g = draw_photons(
        &scene,
        &maps.global.photons,
        Spectrum::new(0.1, 0.35, 1.0),
        &mut img,
    );
    let c = draw_photons(
        &scene,
        maps.caustic.point_photons(),
        Spectrum::new(1.0, 0.55, 0.05),
        &mut img,
    );
    img.write(&args.output)
        .with_context(|| format!("cannot write {}", args.output.display()))?;
    println!(
        "{}: {} of {} global photons (blue) and {} of {} caustic photons (orange) visible -> {}",
        scene.name,
        g,
        maps.global.len(),
        c,
        maps.caustic.len(),
        args.output.display()
    );
    Ok(())
}
