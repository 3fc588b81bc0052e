//! `caustica render --integrator pppm|ppds|...`: the state file every resumable progressive
//! render writes, `--resume` to the bytes of an uninterrupted render, and clean refusals of bad
//! state files and options (non-zero exit, nothing overwritten).

mod common;
use common::{assert_clean_failure, caustica, stderr, tmp_in};

fn tmp(name: &str) -> std::path::PathBuf {
    tmp_in("progressive", name)
}

fn args<'a>(out: &'a str, iterations: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut a = vec![
        "render",
        "water-wave",
        "--integrator",
        "pppm",
        "--caustics-only",
        "--width",
        "24",
        "--photons-per-iteration",
        "5000",
        "--iterations",
        iterations,
        "-q",
        "-o",
        out,
    ];
    a.extend_from_slice(extra);
    a
}

#[test]
fn resume_continues_to_the_bytes_of_an_uninterrupted_render() {
    let (part, whole) = (tmp("part.exr"), tmp("whole.exr"));
    let (p, w) = (part.to_str().unwrap(), whole.to_str().unwrap());
    let o = caustica(&args(p, "2", &[]));
    assert!(o.status.success(), "{}", stderr(&o));
    let state = format!("{p}.state");
    assert!(std::path::Path::new(&state).exists());
    let o = caustica(&args(p, "4", &["--resume", &state]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("resuming after iteration 2"),
        "{}",
        stderr(&o)
    );
    let o = caustica(&args(w, "4", &[]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(&part).unwrap(),
        std::fs::read(&whole).unwrap()
    );
}

#[test]
fn bad_state_files_and_options_are_refused_and_nothing_is_overwritten() {
    let first = tmp("first.exr");
    let f = first.to_str().unwrap();
    let o = caustica(&args(f, "2", &[]));
    assert!(o.status.success(), "{}", stderr(&o));
    let state = format!("{f}.state");
    let image = std::fs::read(&first).unwrap();
    // Another seed: the option is named.
    let o = caustica(&args(f, "3", &["--resume", &state, "--seed", "5"]));
    assert_clean_failure(&o, &["cannot resume", "seed"]);
    // Truncated.
    let bytes = std::fs::read(&state).unwrap();
    let cut = tmp("cut.state");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let o = caustica(&args(f, "3", &["--resume", cut.to_str().unwrap()]));
    assert_clean_failure(&o, &["truncated or corrupted"]);
    // Not a state file, and a missing one.
    let o = caustica(&args(f, "3", &["--resume", f]));
    assert_clean_failure(&o, &["not a caustica state file"]);
    let o = caustica(&args(f, "3", &["--resume", "/nonexistent/x.state"]));
    assert_clean_failure(&o, &["cannot read the state file"]);
    // Already as many iterations as asked for.
    let o = caustica(&args(f, "2", &["--resume", &state]));
    assert_clean_failure(&o, &["already holds 2 iterations"]);
    assert_eq!(
        std::fs::read(&first).unwrap(),
        image,
        "the image was overwritten"
    );
    // Bad values and misplaced options.
    let o = caustica(&args(f, "3", &["--ppm-alpha", "0"]));
    assert_clean_failure(&o, &["--ppm-alpha must be a number in (0, 1]"]);
    let o = caustica(&[
        "render",
        "water-wave",
        "--integrator",
        "ppds",
        "--photons-per-iteration",
        "0",
        "-q",
    ]);
    assert_clean_failure(&o, &["--photons-per-iteration must be at least 1"]);
    let o = caustica(&[
        "render",
        "water-wave",
        "--integrator",
        "pm",
        "--iterations",
        "3",
        "-q",
    ]);
    assert_clean_failure(&o, &["progressive methods"]);
    let o = caustica(&args(f, "3", &["--radius", "-1"]));
    assert_clean_failure(
        &o,
        &["the first gather radius (--radius) must be a positive"],
    );
    assert_eq!(
        std::fs::read(&first).unwrap(),
        image,
        "the image was overwritten"
    );
}

/// `--save-iterations 1,3` writes the images after iterations 1 and 3 with the bytes of
/// 1- and 3-iteration renders, and a table of when each was reached; refused for a one-shot
/// method and for a bad list.
#[test]
fn save_iterations_writes_the_images_of_shorter_renders() {
    let (all, one, three) = (tmp("all.exr"), tmp("one.exr"), tmp("three.exr"));
    let a = all.to_str().unwrap();
    let o = caustica(&args(a, "4", &["--save-iterations", "3,1"]));
    assert!(o.status.success(), "{}", stderr(&o));
    for (n, path) in [("1", &one), ("3", &three)] {
        let o = caustica(&args(path.to_str().unwrap(), n, &[]));
        assert!(o.status.success(), "{}", stderr(&o));
        let saved = tmp(&format!("all-it{n}.exr"));
        assert_eq!(
            std::fs::read(&saved).unwrap(),
            std::fs::read(path).unwrap(),
            "iteration {n}"
        );
    }
    let table = std::fs::read_to_string(format!("{a}.iterations.csv")).unwrap();
    let rows: Vec<&str> = table.lines().collect();
    assert_eq!(rows[0], "iteration,seconds,image");
    assert_eq!(rows.len(), 3, "{table}");
    assert!(
        rows[1].starts_with("1,") && rows[2].starts_with("3,"),
        "{table}"
    );
    let secs = |r: &str| r.split(',').nth(1).unwrap().parse::<f64>().unwrap();
    assert!(secs(rows[1]) <= secs(rows[2]), "{table}");
    let bad = tmp("bad.exr");
    let b = bad.to_str().unwrap();
    let o = caustica(&args(b, "2", &["--save-iterations", "1,x"]));
    assert_clean_failure(&o, &["--save-iterations", "positive iteration counts"]);
    assert!(!bad.exists());
    let mut pm = args(b, "2", &["--save-iterations", "1"]);
    pm[3] = "pm";
    pm.retain(|a| !["--iterations", "2", "--photons-per-iteration", "5000"].contains(a));
    let o = caustica(&pm);
    assert_clean_failure(&o, &["--save-iterations", "not of pm"]);
    assert!(!bad.exists());
}
