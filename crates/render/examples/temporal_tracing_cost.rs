//! Cost of tracing temporal photon differentials (three parameters: the emission's two and
//! time, seed 003) against ordinary ones (two) on the same light paths of a moving scene (issue
//! 19, target ≤ 1.15×), and the memory of a photon. One tracer (traced at the shutter's
//! opening, the exposure set) runs alternately with `N = 2` and `N = 3` columns on one thread,
//! `reps` times each; the ratio of the minimum times is reported (load only adds time).
//! Both include making the footprints from the landings (`photons_from_landings`).
//!
//! ```text
//! cargo run --release -p caustica-render --example temporal_tracing_cost -- [reps] [scene paths]...
//! ```
//!
//! `TRACING_COST_ONLY=2` or `=3` runs one of the two, for instruction counts under
//! `valgrind --tool=callgrind` with `reps = 1` (`bench/temporal_tracing_cost.sh` does both).

use std::time::{Duration, Instant};

use caustica_core::sampling::{Sampler, SamplerKind};
use caustica_loader::builtin_scene;
use caustica_render::photon::differential::{
    DiffPhoton, EMISSION_PARAMS, Landing, LandingTracer, TEMPORAL_PARAMS, photons_from_landings,
    unit_budget,
};
use caustica_render::photon::tracer::Photon;
use caustica_render::{FootprintSettings, PathLimits, RenderStats, Smoothing};
use caustica_scene::Shutter;

/// Traces light paths `0..paths` with `N` differential columns; returns the photons made.
fn trace<const N: usize>(tracer: &LandingTracer, limits: &PathLimits, paths: u64) -> (usize, u64) {
    let mut sampler = Sampler::new(SamplerKind::Independent, 1);
    let mut st = RenderStats::default();
    let mut landings: Vec<Landing<N>> = Vec::new();
    for path in 0..paths {
        sampler.start_path(1, path);
        tracer.trace::<N>(&mut sampler, limits, &mut landings, &mut st);
    }
    let made = photons_from_landings(&landings, paths, tracer.align(), None);
    (made.photons.len(), made.collapsed + made.failed)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let reps: usize = args
        .first()
        .and_then(|a| a.parse().ok())
        .unwrap_or(15)
        .max(1);
    let rest = if args.is_empty() { &[][..] } else { &args[1..] };
    let cases: Vec<(String, u64)> = if rest.is_empty() {
        vec![
            ("moving-wave".into(), 20_000),
            ("rotating-rod".into(), 400_000),
        ]
    } else {
        rest.chunks(2)
            .map(|c| {
                (
                    c[0].clone(),
                    c.get(1).and_then(|n| n.parse().ok()).unwrap_or(20_000),
                )
            })
            .collect()
    };
    let only = std::env::var("TRACING_COST_ONLY").ok();
    let limits = PathLimits {
        max_depth: 16,
        ..PathLimits::default()
    };
    let settings = FootprintSettings {
        temporal: true,
        ..Default::default()
    };
    println!(
        "| scene | light paths | photons | two parameters (ms, min of {reps}) | three (ms) | ratio |"
    );
    println!("|---|---:|---:|---:|---:|---:|");
    for (name, paths) in cases {
        let Some(mut b) = builtin_scene(&name) else {
            eprintln!("unknown built-in scene {name}");
            std::process::exit(2);
        };
        b.set_shutter(Shutter::new(0.0, 1.0).expect("a valid shutter"));
        let scene = b.build().expect("a valid built-in scene");
        let tracer =
            LandingTracer::new(&scene, &unit_budget(Smoothing::ONE)).with_time(&settings, &scene);
        assert!(tracer.is_temporal(), "{name} does not move");
        let (mut two, mut three) = (Duration::MAX, Duration::MAX);
        let mut photons = 0;
        for _ in 0..reps {
            if only.as_deref() != Some("3") {
                let t = Instant::now();
                let (n, _) = trace::<EMISSION_PARAMS>(&tracer, &limits, paths);
                two = two.min(t.elapsed());
                photons = n;
            }
            if only.as_deref() != Some("2") {
                let t = Instant::now();
                let (n, _) = trace::<TEMPORAL_PARAMS>(&tracer, &limits, paths);
                three = three.min(t.elapsed());
                assert!(photons == 0 || photons == n, "both follow the same paths");
                photons = n;
            }
        }
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        println!(
            "| {name} | {paths} | {photons} | {:.1} | {:.1} | {:.3} |",
            ms(two),
            ms(three),
            three.as_secs_f64() / two.as_secs_f64()
        );
    }
    println!();
    println!("| record | bytes |");
    println!("|---|---:|");
    println!(
        "| `DiffPhoton` (stored/splatted footprint; `dt` is 12 of them) | {} |",
        size_of::<DiffPhoton>()
    );
    println!("| `Photon` (pm and TDPM) | {} |", size_of::<Photon>());
    println!(
        "| `Landing<2>` (transient, per chunk) | {} |",
        size_of::<Landing<2>>()
    );
    println!(
        "| `Landing<3>` (transient, per chunk) | {} |",
        size_of::<Landing<3>>()
    );
}
