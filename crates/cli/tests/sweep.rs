//! End-to-end checks of `caustica sweep`: a sweep of spp against a high-spp reference (CSV,
//! images, plots, optimum line), a categorical sweep, and bad input (clear message, non-zero
//! exit, no panic).

mod common;

use caustica_core::image_io::Image;
use common::{assert_clean_failure, caustica_in, stderr, stdout};
use std::path::{Path, PathBuf};

/// A 24×24 diffuse sphere on a floor under a constant environment: cheap, and noisy at low spp
/// (soft occlusion), so the error falls with the sample count.
const SCENE: &str = r#"name = "sweep-test"

[camera]
eye = [0, 1.2, 3]
target = [0, 0.4, 0]
fov = 40
width = 24
height = 24

[[material]]
name = "m"
type = "diffuse"
reflectance = 0.6

[[shape]]
type = "rectangle"
material = "m"
scale = 3
rotate = { axis = [1, 0, 0], angle = -90 }

[[shape]]
type = "sphere"
material = "m"
center = [0, 0.5, 0]
radius = 0.5

[[light]]
type = "environment"
radiance = 1
"#;

/// A fresh directory for one test, holding the scene as `scene.toml` and, rendered with the
/// path tracer at 256 spp, the reference `ref.exr`.
fn setup(test: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("caustica-sweep-test-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("scene.toml"), SCENE).unwrap();
    let o = caustica_in(
        &dir,
        &[
            "render",
            "scene.toml",
            "--integrator",
            "path",
            "--spp",
            "256",
            "-q",
            "-o",
            "ref.exr",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    dir
}

/// The rows of sweep.csv after checking its header: (value, [rmse, rel_mse, mise, ssim, s]).
fn read_csv(path: &Path) -> Vec<(String, Vec<f64>)> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("value,rmse,rel_mse,mise,ssim,seconds"));
    lines
        .map(|l| {
            let mut fields = l.split(',');
            let value = fields.next().unwrap().to_string();
            let numbers: Vec<f64> = fields.map(|f| f.parse().unwrap()).collect();
            assert_eq!(numbers.len(), 5, "row {l:?}");
            (value, numbers)
        })
        .collect()
}

#[test]
fn spp_sweep_lowers_rmse_and_writes_table_images_and_plots() {
    let dir = setup("spp");
    // No -o: the output goes to sweep-spp/ in the working directory.
    let o = caustica_in(
        &dir,
        &[
            "sweep",
            "scene.toml",
            "--integrator",
            "path",
            "--param",
            "spp",
            "--values",
            "1,4,16",
            "--reference",
            "ref.exr",
            "--seed",
            "3",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = dir.join("sweep-spp");
    let rows = read_csv(&out.join("sweep.csv"));
    let values: Vec<&str> = rows.iter().map(|(v, _)| v.as_str()).collect();
    assert_eq!(values, ["1", "4", "16"]);
    let rmse: Vec<f64> = rows.iter().map(|(_, n)| n[0]).collect();
    assert!(
        rmse[0] > rmse[1] && rmse[1] > rmse[2] && rmse[2] > 0.0,
        "RMSE does not fall with spp: {rmse:?}"
    );
    for (_, n) in &rows {
        assert!(
            n[1] > 0.0 && n[2] > 0.0,
            "rel. MSE and MISE positive: {n:?}"
        );
        assert!(n[3] > 0.0 && n[3] <= 1.0, "SSIM in (0, 1]: {n:?}");
        assert!(n[4] >= 0.0, "seconds: {n:?}");
    }
    assert!(rows[2].1[3] > rows[0].1[3], "SSIM rises with spp");
    for v in ["1", "4", "16"] {
        let img = Image::read(&out.join(format!("spp-{v}.exr"))).unwrap();
        assert_eq!((img.width, img.height), (24, 24));
    }
    let svg = std::fs::read_to_string(out.join("sweep.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(svg.contains("min RMSE") && svg.contains("max SSIM"));
    let png = Image::read(&out.join("sweep.png")).unwrap();
    assert_eq!((png.width, png.height), (800, 500));

    let text = stdout(&o);
    let last = text.lines().last().unwrap_or_default();
    assert!(
        last.contains("RMSE-optimal spp = 16") && last.contains("SSIM-optimal spp = 16"),
        "final line: {last}\n{text}"
    );
    // The table has a header and one line per value.
    assert!(text.lines().next().unwrap_or_default().contains("RMSE"));
    assert_eq!(
        text.lines()
            .filter(|l| ["1", "4", "16"].contains(&l.split_whitespace().next().unwrap_or("")))
            .count(),
        3,
        "{text}"
    );
}

#[test]
fn categorical_sweep_with_crop_and_explicit_output() {
    let dir = setup("sampler");
    let o = caustica_in(
        &dir,
        &[
            "sweep",
            "scene.toml",
            "--param",
            "sampler",
            "--values",
            "sobol,independent",
            "--spp",
            "4",
            "--reference",
            "ref.exr",
            "--crop",
            "4,4,16,16",
            "-o",
            "samplers",
            "--png",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read_csv(&dir.join("samplers/sweep.csv"));
    assert_eq!(rows.len(), 2);
    assert_eq!(rows[0].0, "sobol");
    // --png: a PNG beside each EXR, the same picture.
    let exr = Image::read(&dir.join("samplers/sampler-sobol.exr")).unwrap();
    let png = Image::read(&dir.join("samplers/sampler-sobol.png")).unwrap();
    assert_eq!((png.width, png.height), (exr.width, exr.height));
    for f in [
        "sampler-sobol.exr",
        "sampler-independent.exr",
        "sampler-independent.png",
        "sweep.svg",
        "sweep.png",
    ] {
        assert!(dir.join("samplers").join(f).is_file(), "no {f}");
    }
}

#[test]
fn bad_sweeps_fail_with_a_clear_message() {
    let dir = setup("errors");
    let sweep = |extra: &[&str]| {
        let mut args = vec!["sweep", "scene.toml", "--reference", "ref.exr", "-o", "bad"];
        args.extend_from_slice(extra);
        caustica_in(&dir, &args)
    };
    assert_clean_failure(
        &sweep(&["--param", "smoothness", "--values", "1,2"]),
        &["smoothness", "valid:", "spp", "k", "global-photons"],
    );
    assert_clean_failure(
        &sweep(&["--param", "spp", "--values", "1,x,16"]),
        &["'x'", "spp"],
    );
    assert_clean_failure(
        &sweep(&["--param", "k", "--values", "10,-5"]),
        &["'-5'", "k"],
    );
    assert_clean_failure(
        &sweep(&["--param", "spp", "--values", "1,0"]),
        &["'0'", "--spp"],
    );
    assert_clean_failure(&sweep(&["--param", "spp", "--values", ""]), &["--values"]);
    assert_clean_failure(
        &sweep(&["--param", "spp", "--values", "1,4,1"]),
        &["'1'", "twice"],
    );
    assert_clean_failure(
        &sweep(&["--param", "spp", "--param", "k", "--values", "1,4"]),
        &["--param"],
    );
    assert_clean_failure(
        &sweep(&["--param", "spp", "--spp", "8", "--values", "1,4"]),
        &["--spp", "swept"],
    );
    assert_clean_failure(
        &sweep(&["--param", "spp", "--values", "1,4", "--crop", "0,0,30,30"]),
        &["crop", "24x24"],
    );
    assert!(!dir.join("bad").exists(), "a failed sweep rendered");

    // A reference of another size: both sizes and the file are named.
    std::fs::write(
        dir.join("wide.toml"),
        SCENE.replace("width = 24", "width = 32"),
    )
    .unwrap();
    let o = caustica_in(
        &dir,
        &["render", "wide.toml", "--spp", "1", "-q", "-o", "wide.exr"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = caustica_in(
        &dir,
        &[
            "sweep",
            "scene.toml",
            "--param",
            "spp",
            "--values",
            "1,4",
            "--reference",
            "wide.exr",
            "-o",
            "bad",
        ],
    );
    assert_clean_failure(&o, &["wide.exr", "24x24", "32x24"]);
}
