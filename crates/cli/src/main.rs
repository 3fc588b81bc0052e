//! `caustica`: the command-line renderer.

mod render_cmd;

use anyhow::Result;
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
    /// List the built-in scenes.
    Scenes,
}

fn main() {
    let cli = Cli::parse();
    let result: Result<()> = match cli.command {
        Command::Render(args) => render_cmd::run(*args),
        Command::Scenes => {
            for name in caustica_scene::loader::builtin_names() {
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
