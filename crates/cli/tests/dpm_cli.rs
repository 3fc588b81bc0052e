//! End-to-end checks of diffusion-based photon mapping and the density testbed on the command
//! line: `--integrator dpm`, `--estimator`, `caustica testbed`, and their bad input.

mod common;

use common::{assert_clean_failure, caustica, stderr, stdout, tmp_in};

fn tmp(name: &str) -> std::path::PathBuf {
    tmp_in("dpm-cli-test", name)
}

/// Renders the built-in water wave's caustic (256², so 1 spp and 2000 photons keep it fast)
/// with `args`.
fn render(out: &str, args: &[&str]) -> std::process::Output {
    let out = tmp(out);
    let mut all = vec![
        "render",
        "water-wave",
        "--caustics-only",
        "--spp",
        "1",
        "--photons",
        "2000",
        "-q",
        "-o",
        out.to_str().unwrap(),
    ];
    all.extend_from_slice(args);
    caustica(&all)
}

#[test]
fn dpm_renders_a_scene_and_reports_its_prepass() {
    let o = render(
        "dpm.pfm",
        &["--integrator", "dpm", "--q", "0.3", "--alpha", "2"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let s = stdout(&o);
    assert!(s.contains("dpm 256x256"), "{s}");
    let img = caustica_core::image_io::Image::read(&tmp("dpm.pfm")).unwrap();
    let sum: f64 = img.data.iter().flatten().map(|&v| v as f64).sum();
    assert!(
        sum > 0.0 && sum.is_finite(),
        "empty or non-finite caustic: {sum}"
    );
}

#[test]
fn every_estimator_is_selectable_for_pm() {
    for est in ["knn", "fixed", "variable", "diffusion"] {
        let o = render(
            &format!("est-{est}.pfm"),
            &["--integrator", "pm", "--estimator", est],
        );
        assert!(o.status.success(), "{est}: {}", stderr(&o));
    }
}

#[test]
fn bad_diffusion_parameters_are_rejected() {
    for (args, must) in [
        (
            vec!["--integrator", "dpm", "--q", "0"],
            "diffusivity coefficient q",
        ),
        (
            vec!["--integrator", "dpm", "--q", "NaN"],
            "diffusivity coefficient q",
        ),
        (vec!["--integrator", "dpm", "--alpha", "-1"], "alpha"),
        (
            vec!["--integrator", "dpm", "--bandwidth", "-0.1"],
            "bandwidth",
        ),
        (
            vec!["--integrator", "dpm", "--noise-scale", "0"],
            "noise scale",
        ),
        (
            vec!["--integrator", "pm", "--estimator", "magic"],
            "unknown estimator 'magic'",
        ),
        (
            vec!["--integrator", "dpm", "--estimator", "knn"],
            "--integrator pm",
        ),
    ] {
        let o = render("bad.pfm", &args);
        assert_clean_failure(&o, &[must]);
    }
}

#[test]
fn diffusion_options_warn_on_other_integrators() {
    let o = render("warn.pfm", &["--integrator", "lighttrace", "--q", "0.3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("no effect"), "{}", stderr(&o));
}

#[test]
fn testbed_writes_images_tables_and_a_report() {
    let dir = tmp("testbed");
    let _ = std::fs::remove_dir_all(&dir);
    let o = caustica(&[
        "testbed",
        "--distribution",
        "composite",
        "--samples",
        "3000",
        "--size",
        "32",
        "--realisations",
        "1",
        "--quiet",
        "-o",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("best knn"), "{}", stdout(&o));
    let csv = std::fs::read_to_string(dir.join("results.csv")).unwrap();
    for est in [
        "knn",
        "fixed",
        "variable",
        "diffusion",
        "isotropic-diffusion",
    ] {
        assert!(csv.contains(&format!(",{est},")), "no {est} row in\n{csv}");
    }
    let md = std::fs::read_to_string(dir.join("README.md")).unwrap();
    assert!(md.contains("fig. 4.5"), "{md}");
    for f in ["exact.png", "knn-k150.png", "diffusion-q0.1.png"] {
        assert!(dir.join("composite").join(f).is_file(), "missing {f}");
    }
}

#[test]
fn testbed_bad_input() {
    let dir = tmp("testbed-bad");
    let d = dir.to_str().unwrap();
    assert_clean_failure(
        &caustica(&["testbed", "--distribution", "blob", "-o", d]),
        &["unknown distribution 'blob'", "composite"],
    );
    assert_clean_failure(
        &caustica(&["testbed", "--samples", "0", "-o", d]),
        &["--samples"],
    );
    assert_clean_failure(&caustica(&["testbed", "--size", "4", "-o", d]), &["--size"]);
    assert_clean_failure(
        &caustica(&["testbed", "--realisations", "0", "-o", d]),
        &["--realisations"],
    );
}
