//! `caustica`: the command-line renderer.

#![forbid(unsafe_code)]

use anyhow::Result;
use caustica_cli::{
    compare_cmd, convert_cmd, merge_cmd, photons_cmd, render_cmd, sweep_cmd, testbed_cmd,
};
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "caustica",
    version,
    about = "Physically based renderer for density-estimation global illumination"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene (a TOML file or a built-in name; the embedded default scene if omitted).
    Render(Box<render_cmd::RenderArgs>),
    /// Merge the partial results of a sharded render (`render --shard I/N`) into its image,
    /// byte-identical to the render without shards; refuses parts that do not belong together
    /// or a missing shard (unless --partial).
    Merge(merge_cmd::MergeArgs),
    /// Compare an image with a reference: relative mean difference, RMSE, relative MSE, MISE,
    /// SSIM, and z-score tests for noise versus bias.
    Compare(compare_cmd::CompareArgs),
    /// Convert an image between EXR, PFM and PNG (PNG tone-mapped like `render --png`).
    Convert(convert_cmd::ConvertArgs),
    /// Render a scene once per value of one option (--param NAME --values A,B,C) and compare
    /// each image with a reference: a CSV of RMSE, relative MSE, MISE, SSIM and render time, the
    /// images, and a plot of RMSE and SSIM against the value.
    Sweep(Box<sweep_cmd::SweepArgs>),
    /// Draw the stored photons as points over a dim image of the scene (debugging).
    Photons(Box<photons_cmd::PhotonsArgs>),
    /// Run every density estimator (k-NN, fixed, variable bandwidth, diffusion) on 2-D photon
    /// distributions with a known density (Schjøth 2009 fig. 4.4–4.5): images, MISE, SSIM.
    Testbed(testbed_cmd::TestbedArgs),
    /// List the built-in scenes.
    Scenes,
}

fn main() {
    let cli = Cli::parse();
    let result: Result<()> = match cli.command {
        Command::Render(args) => render_cmd::run(*args),
        Command::Compare(args) => match compare_cmd::run(args) {
            Ok(0) => Ok(()),
            Ok(code) => std::process::exit(code),
            Err(e) => Err(e),
        },
        Command::Convert(args) => convert_cmd::run(args),
        Command::Merge(args) => merge_cmd::run(args),
        Command::Sweep(args) => sweep_cmd::run(*args),
        Command::Photons(args) => photons_cmd::run(*args),
        Command::Testbed(args) => testbed_cmd::run(args),
        Command::Scenes => {
            for name in caustica_loader::builtin_names() {
                println!("{name}");
            }
            Ok(())
        }
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
