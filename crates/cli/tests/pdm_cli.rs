//! End-to-end checks of photon differential mapping on the command line: `--integrator pdm`,
//! `--smoothing`, the render notes on dropped footprints, and bad input.

mod common;

use common::{assert_clean_failure, caustica, stderr, stdout, tmp_in};

fn tmp(name: &str) -> std::path::PathBuf {
    tmp_in("pdm-cli-test", name)
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
        "-o",
        out.to_str().unwrap(),
    ];
    all.extend_from_slice(args);
    caustica(&all)
}

#[test]
fn pdm_renders_a_scene_and_reports_its_footprints() {
    let o = render("pdm.pfm", &["--integrator", "pdm", "--smoothing", "3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("pdm 256x256"), "{}", stdout(&o));
    let err = stderr(&o);
    assert!(
        err.contains("photon differentials: smoothing s = 3"),
        "{err}"
    );
    assert!(err.contains("collapsed footprint"), "{err}");
    let img = caustica_core::image_io::Image::read(&tmp("pdm.pfm")).unwrap();
    let sum: f64 = img.data.iter().flatten().map(|&v| v as f64).sum();
    assert!(
        sum > 0.0 && sum.is_finite(),
        "empty or non-finite caustic: {sum}"
    );
}

#[test]
fn bad_pdm_parameters_are_rejected() {
    for (args, must) in [
        (vec!["--integrator", "pdm", "--smoothing", "0"], "smoothing"),
        (
            vec!["--integrator", "pdm", "--smoothing", "-1"],
            "smoothing",
        ),
        (
            vec!["--integrator", "pdm", "--smoothing", "NaN"],
            "smoothing",
        ),
        (
            vec!["--integrator", "pdm", "--estimator", "knn"],
            "--integrator pm",
        ),
    ] {
        let o = render("bad.pfm", &args);
        assert_clean_failure(&o, &[must]);
    }
}

#[test]
fn smoothing_warns_on_other_integrators() {
    let o = render("warn.pfm", &["--integrator", "pm", "--smoothing", "2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--smoothing and --normal-distance only affect"),
        "{}",
        stderr(&o)
    );
}
