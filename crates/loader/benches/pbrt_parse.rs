//! Load time of the same 1 M-triangle `plymesh` scene as pbrt-v4 and as Mitsuba XML (and of
//! the pbrt tokenizer on the mesh written inline as a `trianglemesh`): `bench/pbrt_parse.sh`
//! writes the scenes and runs this with their folder as the argument. Times the loaders
//! (`parse_scene_file`: text, PLY, mesh transform) without building the BVH; runs alternate
//! between the formats and the medians are reported.

use std::path::{Path, PathBuf};
use std::time::Instant;

fn time_load(path: &Path) -> f64 {
    let t = Instant::now();
    let b = caustica_loader::parse_scene_file(path).unwrap_or_else(|e| panic!("{e}"));
    let s = t.elapsed().as_secs_f64();
    assert!(b.shape_count() > 0);
    std::hint::black_box(b);
    s
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    // `cargo bench` passes `--bench`; the folder is the first other argument.
    let dir: PathBuf = std::env::args()
        .skip(1)
        .find(|a| !a.starts_with("--"))
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            eprintln!("usage: pbrt_parse <folder with ply.pbrt, ply.xml and inline.pbrt>");
            std::process::exit(2);
        });
    let runs: usize = std::env::var("RUNS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(7);
    let scenes = ["ply.pbrt", "ply.xml", "inline.pbrt"].map(|f| dir.join(f));
    // One warm-up load of each (page cache).
    for s in &scenes {
        time_load(s);
    }
    let mut t: [Vec<f64>; 3] = Default::default();
    for _ in 0..runs {
        for (i, s) in scenes.iter().enumerate() {
            t[i].push(time_load(s));
        }
    }
    let m = t.clone().map(median);
    for (s, (m, all)) in scenes.iter().zip(m.iter().zip(&t)) {
        let all: Vec<String> = all.iter().map(|x| format!("{x:.3}")).collect();
        println!(
            "{:<12} median {:.3} s  runs [{}]",
            s.file_name().unwrap().to_string_lossy(),
            m,
            all.join(" ")
        );
    }
    println!("ratio pbrt plymesh / Mitsuba ply: {:.3}", m[0] / m[1]);
    println!(
        "ratio pbrt inline trianglemesh / Mitsuba ply: {:.3}",
        m[2] / m[1]
    );
}
