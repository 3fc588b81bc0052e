//! Cost of tracing caustic photons with photon differentials against plain photons (issue 5,
//! target ≤ 1.3×), measured robustly on a shared machine: the two tracers run alternately in
//! one process on one thread, `reps` times each, and the ratio of their *minimum* times is
//! reported (load only ever adds time, so the minimum is the least disturbed run).
//!
//! ```text
//! cargo run --release -p caustica-render --example tracing_cost -- [reps] [scene photons]...
//! ```
//!
//! `TRACING_COST_ONLY=plain` or `=differential` runs one of the two tracers: under
//! `valgrind --tool=callgrind` with `reps = 1` the two runs' instruction totals give the ratio
//! in instructions, which load does not change (`bench/differential_tracing_cost.sh` does both).
//! `TRACING_COST_THREADS=T` uses `T` threads instead of one. `TRACING_COST_MAP=volume` compares
//! the volume photon tracer with the volume photon differentials of `vpd` (seed 000 sec. 8.4;
//! issue 18, target ≤ 1.3×) instead, `photons` then counting volume photons: the differential
//! side is timed tracing only (`trace_volume_landings`, the comparable work) and with its kernels
//! built (`kernels_from_landings`: filter matrices, volumes, bounds), an extra column.

use std::time::{Duration, Instant};

use caustica_loader::builtin_scene;
use caustica_render::photon::differential::trace_photon_differentials;
use caustica_render::photon::differential::volume_trace::{
    KernelRule, kernels_from_landings, trace_volume_landings,
};
use caustica_render::photon::tracer::{MapKind, trace_photons};
use caustica_render::{PhotonBudget, RenderOptions, Smoothing};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let reps: usize = args
        .first()
        .and_then(|a| a.parse().ok())
        .unwrap_or(15)
        .max(1);
    let rest = if args.is_empty() { &[][..] } else { &args[1..] };
    let cases: Vec<(String, usize)> = if rest.is_empty() {
        vec![
            ("glass-sphere".into(), 10_000),
            ("water-wave".into(), 100_000),
            ("metal-ring".into(), 50_000),
        ]
    } else {
        rest.chunks(2)
            .map(|c| {
                let n = c.get(1).and_then(|n| n.parse().ok()).unwrap_or(100_000);
                (c[0].clone(), n)
            })
            .collect()
    };
    let threads = std::env::var("TRACING_COST_THREADS")
        .ok()
        .and_then(|t| t.parse().ok())
        .unwrap_or(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a one-thread pool");
    let opts = RenderOptions::default();
    let only_var = std::env::var("TRACING_COST_ONLY").ok();
    let only = only_var.as_deref();
    let volume = std::env::var("TRACING_COST_MAP").ok().as_deref() == Some("volume");
    let kind = if volume {
        MapKind::Volume
    } else {
        MapKind::Caustic
    };
    if volume {
        println!(
            "| scene | volume photons | light paths | plain (ms, min of {reps}) | with differentials (ms) | ratio | kernels built too (ms) | ratio |"
        );
        println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    } else {
        println!(
            "| scene | caustic photons | light paths | plain (ms, min of {reps}) | with differentials (ms) | ratio |"
        );
        println!("|---|---:|---:|---:|---:|---:|");
    }
    for (name, n) in cases {
        let scene = match builtin_scene(&name).map(|s| s.build()) {
            Some(Ok(s)) => s,
            _ => {
                eprintln!("unknown or invalid built-in scene {name}");
                std::process::exit(2);
            }
        };
        let mut plain = Duration::MAX;
        let mut diff = Duration::MAX;
        let mut with_kernels = Duration::MAX;
        let mut paths = 0;
        for _ in 0..reps {
            if only != Some("differential") {
                let t = Instant::now();
                let p = pool.install(|| {
                    trace_photons(
                        &scene,
                        PhotonBudget::Records(n),
                        kind,
                        0,
                        &opts,
                        &mut |_| true,
                    )
                });
                plain = plain.min(t.elapsed());
                paths = p.paths;
            }
            if only != Some("plain") {
                let t = Instant::now();
                let d_paths = pool.install(|| {
                    if volume {
                        let budget = PhotonBudget::Records(n);
                        let rule = KernelRule::default();
                        let traced = trace_volume_landings(
                            &scene,
                            budget,
                            Smoothing::ONE,
                            rule,
                            0,
                            &opts,
                            &mut |_| true,
                        );
                        diff = diff.min(t.elapsed());
                        let built = kernels_from_landings(traced, budget, rule);
                        with_kernels = with_kernels.min(t.elapsed());
                        built.paths
                    } else {
                        trace_photon_differentials(
                            &scene,
                            PhotonBudget::Records(n),
                            Smoothing::ONE,
                            0,
                            &opts,
                            &mut |_| true,
                        )
                        .paths
                    }
                });
                if !volume {
                    diff = diff.min(t.elapsed());
                }
                assert!(
                    paths == 0 || paths == d_paths,
                    "both tracers follow the same paths"
                );
                paths = d_paths;
            }
        }
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        let ratio = |d: Duration| d.as_secs_f64() / plain.as_secs_f64();
        if volume {
            println!(
                "| {name} | {n} | {paths} | {:.1} | {:.1} | {:.2} | {:.1} | {:.2} |",
                ms(plain),
                ms(diff),
                ratio(diff),
                ms(with_kernels),
                ratio(with_kernels)
            );
        } else {
            println!(
                "| {name} | {n} | {paths} | {:.1} | {:.1} | {:.2} |",
                ms(plain),
                ms(diff),
                ratio(diff)
            );
        }
    }
}
