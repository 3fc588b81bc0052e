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
