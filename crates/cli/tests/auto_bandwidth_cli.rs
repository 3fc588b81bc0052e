//! Automatic bandwidths on the command line: the render's notes name the choice; explicit
//! `--k`, `--smoothing`, `--bandwidth`/`--q`, the scene's `smoothing` and `--no-auto-bandwidth`
//! disable it, and then the output is byte for byte what caustica wrote before the feature
//! (FNV-1a hashes of the PFM files the binary of commit 2e30294 wrote for the same commands).

mod common;

use common::{caustica, stderr};

/// FNV-1a, 64 bits (Fowler, Noll, Vo; the IETF draft-eastlake-fnv's test vectors).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Renders the water wave small with `args` (after `--integrator`), returns stderr and the
/// PFM's hash.
fn render(name: &str, args: &[&str]) -> (String, u64) {
    let mut all = vec!["--integrator"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--seed", "2"]);
    render_scene("water-wave", name, &all)
}

/// Renders `scene` small (2000 caustic photons, caustics only, 1 spp, 32 pixels wide) with
/// `args`; returns stderr and the PFM's hash.
fn render_scene(scene: &str, name: &str, args: &[&str]) -> (String, u64) {
    let out = common::tmp_in("auto-bandwidth-cli", &format!("{name}.pfm"));
    let out_s = out.to_str().unwrap();
    let mut all = vec!["render", scene];
    all.extend_from_slice(args);
    all.extend_from_slice(&[
        "--photons",
        "2000",
        "--caustics-only",
        "--spp",
        "1",
        "--width",
        "32",
        "-o",
        out_s,
    ]);
    let o = caustica(&all);
    assert!(o.status.success(), "{}", stderr(&o));
    (stderr(&o), fnv1a(&std::fs::read(&out).unwrap()))
}

#[test]
fn fnv_matches_its_test_vector() {
    assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
}

#[test]
fn notes_name_the_automatic_choice() {
    for (integrator, name) in [("pm", "k = "), ("pds", "s = "), ("pdm", "s = ")] {
        let (err, _) = render(&format!("auto-{integrator}"), &[integrator]);
        let note = err
            .lines()
            .find(|l| l.starts_with("automatic bandwidth: "))
            .unwrap_or_else(|| panic!("{integrator}: no note in\n{err}"));
        assert!(
            note.contains(name) && note.contains("least-squares cross-validation"),
            "{note}"
        );
    }
}

#[test]
fn explicit_values_disable_the_choice_and_render_as_before() {
    for (name, args, hash) in [
        // Uniform emission, as caustica emitted before projection maps became the default.
        (
            "pm-k50",
            &["pm", "--k", "50", "--emission", "uniform"][..],
            0xa8d4_ee89_2b08_8766u64,
        ),
        (
            "pds-s4",
            &["pds", "--smoothing", "4", "--emission", "uniform"][..],
            0xd1fd_6847_e715_a73f,
        ),
        (
            "dpm-h-q",
            &[
                "dpm",
                "--bandwidth",
                "0.07",
                "--q",
                "0.05",
                "--emission",
                "uniform",
            ][..],
            0x5642_7cb0_695c_cc03,
        ),
    ] {
        let (err, h) = render(name, args);
        assert!(!err.contains("automatic bandwidth"), "{name}: {err}");
        assert_eq!(
            h, hash,
            "{name}: not the bytes of caustica before the feature"
        );
    }
    // --no-auto-bandwidth is the fixed default k = 50.
    let (err, h) = render(
        "pm-fixed",
        &["pm", "--no-auto-bandwidth", "--emission", "uniform"],
    );
    assert!(!err.contains("automatic bandwidth"), "{err}");
    assert_eq!(h, 0xa8d4_ee89_2b08_8766);
    // Only the given value is fixed: dpm with --bandwidth still chooses q.
    let (err, _) = render("dpm-h", &["dpm", "--bandwidth", "0.07"]);
    let note = err
        .lines()
        .find(|l| l.starts_with("automatic bandwidth: "))
        .unwrap_or_else(|| panic!("{err}"));
    assert!(note.contains("q = ") && !note.contains("h = "), "{note}");
}

/// The scene's `[integrator] smoothing` is an explicit value too.
#[test]
fn the_scenes_smoothing_disables_the_choice() {
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/water-wave.toml");
    // Its meshes by absolute path, since the copy lives elsewhere.
    let dir = src.parent().unwrap().canonicalize().unwrap();
    let text = std::fs::read_to_string(&src)
        .unwrap()
        .replace("\"meshes/", &format!("\"{}/meshes/", dir.display()));
    assert!(text.contains("type = \"pds\"\n"));
    for (name, text, auto) in [
        (
            "with-s.toml",
            text.replace("type = \"pds\"\n", "type = \"pds\"\nsmoothing = 4\n"),
            false,
        ),
        ("without-s.toml", text.clone(), true),
    ] {
        let scene = common::tmp_in("auto-bandwidth-cli", name);
        std::fs::write(&scene, text).unwrap();
        let (err, _) = render_scene(scene.to_str().unwrap(), name, &[]);
        assert_eq!(
            err.contains("automatic bandwidth: s = "),
            auto,
            "{name}: {err}"
        );
    }
}
