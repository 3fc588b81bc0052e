//! End-to-end checks of photon differential mapping and splatting on the command line:
//! `--integrator pdm|pds`, `--smoothing`, `--normal-distance`, the render notes on dropped
//! footprints and splats, and bad input.

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
fn pds_renders_the_same_caustic_as_pdm_and_reports_its_splats() {
    let args = ["--smoothing", "2", "--normal-distance", "0.5"];
    let o = render("pds.pfm", &[&["--integrator", "pds"][..], &args].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("pds 256x256"), "{}", stdout(&o));
    let err = stderr(&o);
    assert!(err.contains("eye map 65536 vertices"), "{err}");
    assert!(err.contains("2000 photons splatted"), "{err}");
    assert!(err.contains("M splats/s"), "{err}");
    let o = render("pdm2.pfm", &[&["--integrator", "pdm"][..], &args].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let a = caustica_core::image_io::Image::read(&tmp("pds.pfm")).unwrap();
    let b = caustica_core::image_io::Image::read(&tmp("pdm2.pfm")).unwrap();
    let sum = |i: &caustica_core::image_io::Image| -> f64 {
        i.data.iter().flatten().map(|&v| v as f64).sum()
    };
    let (sa, sb) = (sum(&a), sum(&b));
    assert!(
        sa > 0.0 && (sa / sb - 1.0).abs() < 1e-5,
        "pds {sa} vs pdm {sb}"
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
        (vec!["--integrator", "pds", "--smoothing", "0"], "smoothing"),
        (
            vec!["--integrator", "pds", "--normal-distance", "-1"],
            "normal-distance",
        ),
        (
            vec!["--integrator", "pds", "--estimator", "diffusion"],
            "--integrator pm",
        ),
        (
            vec!["--integrator", "pds", "--min-footprint", "-0.01"],
            "--min-footprint must be a positive finite length",
        ),
        (
            vec!["--integrator", "pdm", "--min-footprint", "inf"],
            "--min-footprint must be a positive finite length",
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
        stderr(&o).contains("--smoothing, --normal-distance and --min-footprint only affect"),
        "{}",
        stderr(&o)
    );
}
