//! `--wavelength-spread` (wavelength photon differentials, issue 22) end to end: pds and pdm
//! render the prism with it, the same bytes on 1 and 2 threads, and differently from without it
//! when the spread is wide; misuse fails cleanly (no --spectral, another integrator, with
//! --temporal, a factor that is not positive).

mod common;

use common::{assert_clean_failure, caustica, stderr};
use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    common::tmp_in("wavelength-spread-cli", name)
}

/// Renders the prism's caustic by `integrator` at 80 × 60 with `extra` arguments into `name`.
fn render(name: &str, integrator: &str, extra: &[&str]) -> Vec<u8> {
    let out = tmp(name);
    let mut args = vec![
        "render",
        "prism",
        "--spectral",
        "--caustics-only",
        "--integrator",
        integrator,
        "--spp",
        "1",
        "--photons",
        "20000",
        "--smoothing",
        "8",
        "--width",
        "80",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = caustica(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::read(&out).unwrap()
}

#[test]
fn pds_and_pdm_render_with_wavelength_spread_deterministically() {
    for integrator in ["pds", "pdm"] {
        let wide = ["--wavelength-spread", "1000"];
        let one = render(
            &format!("{integrator}-t1.exr"),
            integrator,
            &[&wide[..], &["--threads", "1"]].concat(),
        );
        let two = render(
            &format!("{integrator}-t2.exr"),
            integrator,
            &[&wide[..], &["--threads", "2"]].concat(),
        );
        assert!(
            one == two,
            "{integrator}: bytes differ between 1 and 2 threads"
        );
        let plain = render(&format!("{integrator}-plain.exr"), integrator, &[]);
        assert!(
            one != plain,
            "{integrator}: a spread of 1000 photon shares changed nothing"
        );
    }
}

#[test]
fn wavelength_spread_misuse_fails_cleanly() {
    let out = tmp("bad.exr");
    let base = [
        "render",
        "prism",
        "--width",
        "20",
        "-o",
        out.to_str().unwrap(),
    ];
    let run = |extra: &[&str]| caustica(&[&base[..], extra].concat());
    assert_clean_failure(
        &run(&["--integrator", "pds", "--wavelength-spread", "10"]),
        &["--wavelength-spread", "--spectral"],
    );
    assert_clean_failure(
        &run(&[
            "--spectral",
            "--integrator",
            "pm",
            "--wavelength-spread",
            "10",
        ]),
        &["--wavelength-spread", "pds and pdm", "pm"],
    );
    assert_clean_failure(
        &run(&[
            "--spectral",
            "--integrator",
            "pds",
            "--wavelength-spread",
            "10",
            "--temporal",
        ]),
        &["--wavelength-spread", "--temporal"],
    );
    for bad in ["0", "-2", "nan"] {
        assert_clean_failure(
            &run(&[
                "--spectral",
                "--integrator",
                "pds",
                "--wavelength-spread",
                bad,
            ]),
            &["--wavelength-spread", "positive"],
        );
    }
}
