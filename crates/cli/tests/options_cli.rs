//! Every invalid value of every `render` option: one clear message naming the option, a
//! non-zero exit, no panic, no image written. The rules are the ones `--help` states.

mod common;

use common::{caustica, stderr, tmp_in};

/// `render` of the default scene with `args` fails cleanly, naming `needle`.
fn rejects(args: &[&str], needle: &str) {
    let out = tmp_in("options", "never.exr");
    let out = out.to_str().unwrap();
    let mut all = vec!["render", "-q", "-o", out];
    all.extend_from_slice(args);
    let o = caustica(&all);
    let err = stderr(&o);
    assert!(!o.status.success(), "{args:?} was accepted");
    // 2 for what the argument parser rejects (clap's convention), 1 for what the renderer does.
    assert!(
        matches!(o.status.code(), Some(1 | 2)),
        "{args:?}: {:?}",
        o.status
    );
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert!(
        err.contains(needle),
        "{args:?}: the message does not name {needle:?}: {err}"
    );
    assert!(
        !std::path::Path::new(out).exists(),
        "{args:?} wrote an image"
    );
}

#[test]
fn every_invalid_general_option_is_rejected_naming_it() {
    for v in ["0", "-1", "many"] {
        rejects(&["--spp", v], "--spp");
    }
    for v in ["0", "-2", "nan", "inf", "soon"] {
        rejects(&["--time", v], "--time");
    }
    rejects(&["--threads", "0"], "--threads");
    rejects(&["--threads", "-1"], "--threads");
    rejects(&["--seed", "-1"], "--seed");
    rejects(&["--sampler", "halton"], "halton");
    for v in ["0", "-2", "deep"] {
        rejects(&["--max-depth", v], "--max-depth");
    }
    rejects(&["--integrator", "bdpt"], "bdpt");
    for v in ["0", "-1", "nan", "inf", "lots"] {
        rejects(&["--memory", v], "--memory");
    }
    // Counts too large for the machine: refused with the figure and the option, never an
    // allocation abort.
    rejects(
        &["--integrator", "pm", "--photons", "100000000000"],
        "memory budget",
    );
    rejects(
        &["--integrator", "pds", "--spp", "100000", "--memory", "1"],
        "eye map",
    );
    rejects(&["-D", "spp"], "NAME=VALUE");
    rejects(
        &["--integrator", "path", "--spp", "4", "--time", "1"],
        "--spp and --time",
    );
    rejects(
        &["--integrator", "pm", "--spp", "4", "--time", "1"],
        "--spp and --time",
    );
}

#[test]
fn every_invalid_photon_option_is_rejected_naming_it() {
    let pm = ["--integrator", "pm"];
    let with = |extra: &[&'static str]| -> Vec<&'static str> {
        pm.iter().copied().chain(extra.iter().copied()).collect()
    };
    for (opt, bad) in [
        ("--photons", &["0", "-5", "x"][..]),
        ("--light-paths", &["0", "-5", "x"]),
        ("--global-photons", &["-1", "x"]),
        ("--k", &["0", "-1"]),
        ("--global-k", &["0", "-1"]),
        ("--max-radius", &["0", "-1", "nan", "inf"]),
        ("--final-gather", &["-1", "x"]),
    ] {
        for v in bad {
            rejects(&with(&[opt, v]), opt);
        }
    }
    rejects(
        &with(&["--photons", "10", "--light-paths", "10"]),
        "--light-paths",
    );
    rejects(&with(&["--kernel", "box"]), "box");
    rejects(&with(&["--kernel", "cone:0.5"]), "cone");
    rejects(&with(&["--estimator", "magic"]), "magic");
}

#[test]
fn every_invalid_dpm_and_differential_option_is_rejected_naming_it() {
    let with = |kind: &'static str, extra: &[&'static str]| -> Vec<&'static str> {
        ["--integrator", kind]
            .into_iter()
            .chain(extra.iter().copied())
            .collect()
    };
    for opt in ["--bandwidth", "--q", "--alpha", "--noise-scale"] {
        for v in ["0", "-1", "nan", "inf", "x"] {
            rejects(&with("dpm", &[opt, v]), opt);
        }
    }
    for kind in ["pdm", "pds"] {
        for v in ["0", "-1", "nan", "inf", "x"] {
            rejects(&with(kind, &["--smoothing", v]), "--smoothing");
        }
        for v in ["-1", "nan", "x"] {
            rejects(&with(kind, &["--normal-distance", v]), "--normal-distance");
        }
    }
}

#[test]
fn help_lists_every_integrator_and_states_the_rules() {
    let o = caustica(&["render", "--help"]);
    assert!(o.status.success());
    let help = String::from_utf8_lossy(&o.stdout);
    for name in ["path", "lighttrace", "pm", "dpm", "pdm", "pds"] {
        assert!(
            help.split(|c: char| !c.is_alphanumeric())
                .any(|w| w == name),
            "--help does not name {name}"
        );
    }
    for rule in ["at least 1", "positive finite", "-1 = unlimited", ">= 0"] {
        assert!(help.contains(rule), "--help does not state {rule:?}");
    }
}

#[test]
fn every_invalid_crop_is_rejected_naming_it_and_the_film() {
    // The film is the default scene's after the size overrides: 32x24.
    for v in [
        "",
        "1,2,3",
        "1,2,3,4,5",
        "a,0,1,1",
        "-1,0,4,4",
        "0,-2,4,4",
        "1.5,0,1,1",
        "0,0,0,4",
        "0,0,4,0",
        "30,0,3,1",
        "0,20,1,5",
        "32,0,1,1",
        "4294967295,0,2,2",
    ] {
        let args = ["--width", "32", "--height", "24", "--crop", v];
        rejects(&args, "--crop");
        let out = tmp_in("options", "never.exr");
        let mut all = vec!["render", "-q", "-o", out.to_str().unwrap()];
        all.extend_from_slice(&args);
        let o = caustica(&all);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "--crop {v:?}: {err}");
        for needle in ["32x24", "X,Y,W,H"] {
            assert!(
                err.contains(needle),
                "--crop {v:?} does not name {needle}: {err}"
            );
        }
    }
}
