//! End-to-end checks of the `caustica` binary: the default render, outputs, the summary line,
//! and bad input (clear message, non-zero exit, no panic).

mod common;

use caustica_core::image_io::Image;
use common::{assert_clean_failure, caustica, stderr};
use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    common::tmp_in("cli-test", name)
}

#[test]
fn default_scene_renders_exr_and_png_with_summary() {
    let (exr, png) = (tmp("default.exr"), tmp("default.png"));
    let o = caustica(&[
        "render",
        "--spp",
        "1",
        "--photons",
        "20000",
        "-q",
        "-o",
        exr.to_str().unwrap(),
        "--png",
        png.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    for part in ["samples/s", "rays/s", "NaN/Inf samples discarded"] {
        assert!(out.contains(part), "summary lacks '{part}': {out}");
    }
    let img = caustica_core::image_io::Image::read(&exr).unwrap();
    assert!(
        img.width > 0 && img.data.iter().any(|p| p[0] > 0.0),
        "default image is black"
    );
    assert_eq!(
        caustica_core::image_io::Image::read(&png).unwrap().width,
        img.width
    );
}

fn write(name: &str, text: &str) -> PathBuf {
    let p = tmp(name);
    std::fs::write(&p, text).unwrap();
    p
}

const CAMERA: &str =
    "[camera]\neye = [0, 0, 3]\ntarget = [0, 0, 0]\nfov = 40\nwidth = 8\nheight = 8\n";

#[test]
fn malformed_scene_names_file_line_and_expectation() {
    let p = write("malformed.toml", "[camera]\neye = [0, 0, 1\nfov = 40\n");
    let o = caustica(&[
        "render",
        p.to_str().unwrap(),
        "-o",
        tmp("m.exr").to_str().unwrap(),
    ]);
    assert_clean_failure(&o, &["malformed.toml:3:", "expected"]);
    let p = write(
        "wrongtype.toml",
        &CAMERA.replace("fov = 40", "fov = \"wide\""),
    );
    let o = caustica(&[
        "render",
        p.to_str().unwrap(),
        "-o",
        tmp("m.exr").to_str().unwrap(),
    ]);
    assert_clean_failure(&o, &["wrongtype.toml:4:", "fov"]);
}

#[test]
fn missing_mesh_names_the_path() {
    let text = format!(
        "{CAMERA}[[material]]\nname = \"m\"\ntype = \"diffuse\"\nreflectance = 0.5\n[[shape]]\ntype = \"obj\"\nfilename = \"no-such-mesh.obj\"\nmaterial = \"m\"\n"
    );
    let p = write("missing-mesh.toml", &text);
    let o = caustica(&[
        "render",
        p.to_str().unwrap(),
        "-o",
        tmp("m.exr").to_str().unwrap(),
    ]);
    assert_clean_failure(&o, &["no-such-mesh.obj"]);
}

#[test]
fn invalid_parameters_are_rejected() {
    let out = tmp("p.exr");
    let out = out.to_str().unwrap();
    assert_clean_failure(&caustica(&["render", "--spp", "0", "-o", out]), &["--spp"]);
    assert_clean_failure(
        &caustica(&["render", "--max-depth", "0", "-o", out]),
        &["--max-depth"],
    );
    assert_clean_failure(
        &caustica(&["render", "--threads", "0", "-o", out]),
        &["--threads"],
    );
    assert_clean_failure(
        &caustica(&["render", "--time", "0", "-o", out]),
        &["--time"],
    );
    assert_clean_failure(&caustica(&["render", "-o", "out.txt"]), &[".exr"]);
    assert_clean_failure(&caustica(&["render", "no-such-scene"]), &["no-such-scene"]);
    let glass = format!("{CAMERA}[[material]]\nname = \"g\"\ntype = \"dielectric\"\nior = -1.5\n");
    let p = write("bad-ior.toml", &glass);
    assert_clean_failure(
        &caustica(&["render", p.to_str().unwrap(), "-o", out]),
        &["ior"],
    );
    let sphere = format!(
        "{CAMERA}[[material]]\nname = \"m\"\ntype = \"diffuse\"\nreflectance = 0.5\n[[shape]]\ntype = \"sphere\"\nmaterial = \"m\"\nradius = -1\n"
    );
    let p = write("bad-radius.toml", &sphere);
    assert_clean_failure(
        &caustica(&["render", p.to_str().unwrap(), "-o", out]),
        &["radius"],
    );
}

#[test]
fn nan_and_degenerate_triangles_are_skipped_with_a_warning() {
    let obj = write(
        "bad.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv nan 0 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 1 2 5\n",
    );
    let text = format!(
        "{CAMERA}[[material]]\nname = \"m\"\ntype = \"diffuse\"\nreflectance = 0.5\n[[shape]]\ntype = \"obj\"\nfilename = \"{}\"\nmaterial = \"m\"\n[[light]]\ntype = \"point\"\nposition = [0, 0, 2]\nintensity = [1, 1, 1]\n",
        obj.file_name().unwrap().to_str().unwrap()
    );
    let p = write("nan-mesh.toml", &text);
    let o = caustica(&[
        "render",
        p.to_str().unwrap(),
        "--spp",
        "1",
        "-q",
        "-o",
        tmp("n.exr").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("warning") && err.contains("2 triangles"),
        "no skip warning: {err}"
    );
}

/// Starts `caustica args`, sends it Ctrl-C (SIGINT) after `after_ms`, and returns its output
/// and the seconds it took to exit after the signal; a process still running `deadline` s
/// after the signal is killed and fails the test instead of hanging it.
fn interrupt(args: &[&str], after_ms: u64, deadline: f64) -> (std::process::Output, f64) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_caustica"))
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(after_ms));
    let sent = std::time::Instant::now();
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    while child.try_wait().unwrap().is_none() {
        if sent.elapsed().as_secs_f64() > deadline {
            let _ = child.kill();
            panic!("{args:?}: still running {deadline} s after Ctrl-C");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let waited = sent.elapsed().as_secs_f64();
    (child.wait_with_output().unwrap(), waited)
}

#[test]
fn interrupt_writes_the_image_so_far() {
    let out = tmp("interrupted.exr");
    let _ = std::fs::remove_file(&out);
    let args = [
        "render",
        "cornell-box",
        "--spp",
        "1000000",
        "-q",
        "-o",
        out.to_str().unwrap(),
    ];
    let (o, _) = interrupt(&args, 1500, 60.0);
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert!(Path::new(&out).exists(), "no image written after Ctrl-C");
    let img = caustica_core::image_io::Image::read(&out).unwrap();
    assert!(img.data.iter().any(|p| p[0] > 0.0));
}

#[test]
fn checkpoints_are_written_during_the_render() {
    let out = tmp("checkpoint.exr");
    let _ = std::fs::remove_file(&out);
    let mut child = Command::new(env!("CARGO_BIN_EXE_caustica"))
        .args([
            "render",
            "cornell-box",
            "--time",
            "4",
            "--checkpoint",
            "0.5",
            "-q",
            "-o",
            out.to_str().unwrap(),
        ])
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Poll for the first checkpoint while the render is still running.
    let mut seen = false;
    for _ in 0..30 {
        std::thread::sleep(std::time::Duration::from_millis(100));
        if out.exists() && child.try_wait().unwrap().is_none() {
            seen = true;
            break;
        }
    }
    assert!(child.wait().unwrap().success());
    assert!(
        seen,
        "no checkpoint image appeared before the render finished"
    );
}

#[test]
fn mitsuba_xml_scene_renders_with_defines() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/mitsuba/cornell-box.xml");
    let out = tmp("xml.exr");
    let o = caustica(&[
        "render",
        scene.to_str().unwrap(),
        "--spp",
        "1",
        "-q",
        "-D",
        "res=32",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).starts_with("cornell-box: path"));
    assert_clean_failure(
        &caustica(&["render", scene.to_str().unwrap(), "-D", "novalue"]),
        &["NAME=VALUE"],
    );
}

/// A 48×32 image of smooth structure plus deterministic hash noise of amplitude `noise`.
fn synthetic(noise: f32, seed: u32, offset: f32) -> caustica_core::image_io::Image {
    let mut img = caustica_core::image_io::Image::new(48, 32);
    for y in 0..32 {
        for x in 0..48 {
            let h =
                ((x as u32 * 73_856_093) ^ (y as u32 * 19_349_663) ^ seed.wrapping_mul(83_492_791))
                    % 1000;
            let n = noise * (h as f32 / 1000.0 - 0.5);
            let v = 0.3 + 0.2 * (x as f32 / 48.0) + n + offset;
            img.set(x, y, [v, 0.8 * v, 0.5 * v]);
        }
    }
    img
}

#[test]
fn compare_reports_metrics_and_checks_agreement() {
    let (a, b, c) = (tmp("cmp-a.exr"), tmp("cmp-b.exr"), tmp("cmp-c.pfm"));
    synthetic(0.02, 1, 0.0).write(&a).unwrap();
    synthetic(0.02, 2, 0.0).write(&b).unwrap();
    synthetic(0.02, 3, 0.05).write(&c).unwrap(); // ~ +12 % brighter everywhere
    let err = tmp("cmp-err.png");
    let o = caustica(&[
        "compare",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--check",
        "0.01",
        "--error-image",
        err.to_str().unwrap(),
    ]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}{}", stderr(&o));
    for key in [
        "relative mean difference",
        "RMSE",
        "relative MSE",
        "MISE",
        "SSIM",
        "pixel z",
        "block z",
        "agreement                 yes",
    ] {
        assert!(out.contains(key), "output lacks '{key}': {out}");
    }
    assert_eq!(
        caustica_core::image_io::Image::read(&err).unwrap().width,
        48
    );
    // A biased image fails the check with exit status 2.
    let o = caustica(&[
        "compare",
        c.to_str().unwrap(),
        b.to_str().unwrap(),
        "--check",
        "0.01",
        "--crop",
        "8,8,32,16",
    ]);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    assert!(String::from_utf8_lossy(&o.stdout).contains("pixels                    512"));
}

#[test]
fn compare_bad_input_fails_cleanly() {
    let a = tmp("cmp-bad-a.exr");
    synthetic(0.0, 1, 0.0).write(&a).unwrap();
    let small = tmp("cmp-bad-small.exr");
    caustica_core::image_io::Image::new(8, 8)
        .write(&small)
        .unwrap();
    let (a, small) = (a.to_str().unwrap(), small.to_str().unwrap());
    assert_clean_failure(
        &caustica(&["compare", a, small]),
        &["sizes differ", "48x32"],
    );
    assert_clean_failure(
        &caustica(&["compare", a, a, "--crop", "40,0,20,10"]),
        &["--crop", "outside"],
    );
    assert_clean_failure(
        &caustica(&["compare", a, a, "--crop", "1,2,x,4"]),
        &["--crop"],
    );
    assert_clean_failure(
        &caustica(&["compare", a, "/nonexistent/ref.exr"]),
        &["cannot read reference", "/nonexistent/ref.exr"],
    );
    assert_clean_failure(&caustica(&["compare", a, a, "--mask", small]), &["mask"]);
}

#[test]
fn convert_writes_every_format_and_applies_the_exposure() {
    let mut img = Image::new(3, 2);
    img.set(0, 0, [0.25, 0.5, 1.0]);
    img.set(2, 1, [4.0, 0.0, 0.125]);
    let exr = tmp("conv-in.exr");
    img.write(&exr).unwrap();
    let pfm = tmp("conv-out.pfm");
    let o = caustica(&["convert", exr.to_str().unwrap(), pfm.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        Image::read(&pfm).unwrap().data,
        img.data,
        "EXR -> PFM is lossless"
    );
    // Two stops brighter: every value times 4, exactly (a power of two).
    let o = caustica(&[
        "convert",
        exr.to_str().unwrap(),
        pfm.to_str().unwrap(),
        "--exposure",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bright = Image::read(&pfm).unwrap();
    for (b, a) in bright.data.iter().zip(&img.data) {
        assert_eq!(*b, a.map(|v| v * 4.0));
    }
    // PNG: sRGB of the scaled value, clamped; 0.25 · 4 = 1 is white.
    let png = tmp("conv-out.png");
    let o = caustica(&[
        "convert",
        exr.to_str().unwrap(),
        png.to_str().unwrap(),
        "--exposure",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let back = Image::read(&png).unwrap();
    assert_eq!(back.get(0, 0)[0], 1.0);
    assert_eq!(back.get(1, 0), [0.0; 3]);
    for (args, needle) in [
        (
            vec!["convert", exr.to_str().unwrap(), "x.txt"],
            ".exr, .pfm or .png",
        ),
        (
            vec!["convert", "/nonexistent/in.exr", "x.png"],
            "/nonexistent/in.exr",
        ),
        (
            vec![
                "convert",
                exr.to_str().unwrap(),
                "x.png",
                "--exposure",
                "nan",
            ],
            "--exposure",
        ),
    ] {
        assert_clean_failure(&caustica(&args), &[needle]);
    }
}

#[test]
fn a_non_finite_exposure_is_refused() {
    let out = tmp("exposure.exr");
    let png = tmp("exposure.png");
    for v in ["nan", "inf"] {
        assert_clean_failure(
            &caustica(&[
                "render",
                "-q",
                "--spp",
                "1",
                "-o",
                out.to_str().unwrap(),
                "--png",
                png.to_str().unwrap(),
                "--exposure",
                v,
            ]),
            &["--exposure"],
        );
    }
    let img = tmp("exposure-ref.pfm");
    Image::new(2, 2).write(&img).unwrap();
    let i = img.to_str().unwrap();
    assert_clean_failure(
        &caustica(&["compare", i, i, "--exposure", "nan"]),
        &["--exposure"],
    );
}

#[test]
fn unwritable_outputs_fail_before_rendering_naming_the_path_once() {
    // A path under a regular file cannot be created, even by root.
    let file = tmp("not-a-dir");
    std::fs::write(&file, "x").unwrap();
    let bad = file.join("o.exr");
    let bad = bad.to_str().unwrap();
    let good = tmp("writable.exr");
    let good = good.to_str().unwrap();
    for args in [
        vec!["render", "--spp", "64", "-q", "-o", bad],
        vec!["render", "--spp", "64", "-q", "-o", good, "--png", bad],
        vec!["photons", "-o", bad],
    ] {
        let o = caustica(&args);
        let err = stderr(&o);
        assert_clean_failure(&o, &[bad]);
        assert_eq!(err.matches(bad).count(), 1, "{args:?}: {err}");
        assert!(!err.contains("partial"), "{args:?}: {err}");
        // Refused before any work: no render summary, no photon pass.
        assert!(
            String::from_utf8_lossy(&o.stdout).is_empty(),
            "{args:?} rendered"
        );
    }
    // A missing directory is created.
    let dir = tmp("new-dir");
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.join("deep/o.exr");
    let o = caustica(&["render", "--spp", "1", "-q", "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.is_file());
    assert!(!dir.join("deep/o.partial.exr").exists());
}

#[test]
fn interrupting_the_photon_pass_writes_an_image_of_the_photons_so_far() {
    // The glass sphere's caustic yield is 0.4 %: 2·10⁷ caustic photons would take many minutes,
    // so Ctrl-C lands in the photon pass. The pass stops after its current wave, the camera pass
    // takes one sample per pixel, and the image (of the photons so far, flux over the paths
    // actually traced) is written, labelled as interrupted.
    for kind in ["pm", "dpm", "pdm", "pds"] {
        let out = tmp(&format!("interrupted-{kind}.exr"));
        let _ = std::fs::remove_file(&out);
        let args = [
            "render",
            "glass-sphere",
            "--integrator",
            kind,
            "--photons",
            "20000000",
            "--global-photons",
            "20000",
            "--final-gather",
            "4",
            "-o",
            out.to_str().unwrap(),
        ];
        // One wave of light paths (≤ 2^20) and one sample per pixel: well under a second on
        // an idle machine; 4 s leaves room for a loaded one.
        let (o, waited) = interrupt(&args, 1500, 4.0);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(130), "{kind}: {err}");
        let summary = String::from_utf8_lossy(&o.stdout);
        assert!(summary.contains("(interrupted)"), "{kind}: {summary}");
        assert!(err.contains("requested 20000000"), "{kind}: {err}");
        let img = Image::read(&out).unwrap_or_else(|e| panic!("{kind}: {e}"));
        assert!(img.data.iter().any(|p| p[0] > 0.0), "{kind}: black image");
        eprintln!("{kind}: exited {waited:.2} s after Ctrl-C");
    }
}

#[test]
fn a_time_budget_is_kept_by_every_integrator() {
    // --time S is one budget for every pass: the render ends within S plus a bounded overrun
    // (10 % here, and at most one wave or batch of work). The glass sphere's photon pass
    // would take minutes at 10⁷ photons; the budget cuts it.
    let out = tmp("timed.exr");
    for kind in ["path", "lighttrace", "pm", "dpm", "pdm", "pds"] {
        let start = std::time::Instant::now();
        let o = caustica(&[
            "render",
            "glass-sphere",
            "--integrator",
            kind,
            "--photons",
            "10000000",
            "--time",
            "3",
            "-q",
            "-o",
            out.to_str().unwrap(),
        ]);
        let wall = start.elapsed().as_secs_f64();
        assert!(o.status.success(), "{kind}: {}", stderr(&o));
        // The renderer's own clock, from the summary's "… in 3.08 s": it is what the budget
        // bounds. The process's wall time adds start-up, scene build and the EXR write, and on
        // CI's two cores shared with other test binaries, waits for a core; it is checked only
        // loosely (a budget ignored would take minutes here).
        let summary = String::from_utf8_lossy(&o.stdout);
        let secs: f64 = summary
            .split(" in ")
            .nth(1)
            .and_then(|t| t.split(" s").next())
            .and_then(|t| t.trim().parse().ok())
            .unwrap_or_else(|| panic!("{kind}: no render time in {summary:?}"));
        eprintln!("{kind}: rendered in {secs:.2} s, process {wall:.2} s, for --time 3");
        assert!(
            secs < 3.3 + 0.3,
            "{kind}: rendered in {secs:.2} s for --time 3"
        );
        assert!(wall < 3.0 + 5.0, "{kind}: process {wall:.2} s for --time 3");
        let img = Image::read(&out).unwrap();
        assert!(img.data.iter().any(|p| p[0] > 0.0), "{kind}: black image");
    }
}

#[test]
fn the_path_tracer_warns_once_where_it_cannot_see_the_caustic() {
    let out = tmp("blind.exr");
    let run = |scene: &str, kind: &str| {
        let o = caustica(&[
            "render",
            scene,
            "--integrator",
            kind,
            "--spp",
            "1",
            "-q",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        stderr(&o).matches("cannot render their caustics").count()
    };
    // Directional light into water, point light into a glass ball: one warning each.
    assert_eq!(run("water-wave", "path"), 1);
    assert_eq!(run("glass-sphere", "path"), 1);
    // An area light and diffuse walls, or a method that sees the caustic: none.
    assert_eq!(run("cornell-box", "path"), 0);
    assert_eq!(run("glass-sphere", "pm"), 0);
}

#[test]
fn a_define_the_scene_does_not_declare_is_an_error_listing_those_it_does() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let xml = root.join("scenes/mitsuba/cornell-box.xml");
    let toml = root.join("scenes/cornell-box.toml");
    let out = tmp("defines.exr");
    let out = out.to_str().unwrap();
    let render =
        |scene: &str, d: &str| caustica(&["render", scene, "-D", d, "--spp", "1", "-q", "-o", out]);
    // Declared: accepted.
    let o = render(xml.to_str().unwrap(), "spp=1");
    assert!(o.status.success(), "{}", stderr(&o));
    // A typo: refused, naming the name and the scene's parameters.
    assert_clean_failure(
        &render(xml.to_str().unwrap(), "sp=1"),
        &["-D sp", "no parameter 'sp'", "spp"],
    );
    // TOML and built-in scenes have no parameters.
    assert_clean_failure(
        &render(toml.to_str().unwrap(), "spp=1"),
        &["-D spp", "TOML"],
    );
    assert_clean_failure(&render("cornell-box", "spp=1"), &["-D spp", "built-in"]);
}

#[test]
fn width_and_height_override_every_scene_kind() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = tmp("size.exr");
    let o_str = out.to_str().unwrap();
    let size = |scene: &str, extra: &[&str]| {
        let mut args = vec!["render", scene, "--spp", "1", "-q", "-o", o_str];
        args.extend_from_slice(extra);
        let o = caustica(&args);
        assert!(o.status.success(), "{scene} {extra:?}: {}", stderr(&o));
        let img = Image::read(&out).unwrap();
        (img.width, img.height)
    };
    let toml = root.join("scenes/cornell-box.toml");
    let xml = root.join("scenes/mitsuba/glass-sphere-point.xml");
    // Built-in 256×256: the other side follows the aspect ratio.
    assert_eq!(size("cornell-box", &["--width", "40"]), (40, 40));
    assert_eq!(size(toml.to_str().unwrap(), &["--height", "24"]).1, 24);
    // Mitsuba 256×192: 64 wide is 48 high; both given, both taken.
    assert_eq!(size(xml.to_str().unwrap(), &["--width", "64"]), (64, 48));
    assert_eq!(
        size(xml.to_str().unwrap(), &["--width", "30", "--height", "10"]),
        (30, 10)
    );
    for bad in [["--width", "0"], ["--height", "-3"]] {
        let mut args = vec!["render", "--spp", "1", "-q", "-o", o_str];
        args.extend_from_slice(&bad);
        assert_clean_failure(&caustica(&args), &[bad[0]]);
    }
    assert_clean_failure(
        &caustica(&[
            "render", "--width", "100000", "--height", "100000", "-o", o_str,
        ]),
        &["too large", "268435456"],
    );
}

/// Mean of `img`'s channels over the pixels where `mask` holds.
fn masked_mean(img: &Image, mask: &[bool]) -> f32 {
    let (sum, n) = img
        .data
        .iter()
        .zip(mask)
        .filter(|(_, m)| **m)
        .fold((0.0, 0usize), |(s, n), (p, _)| {
            (s + (p[0] + p[1] + p[2]) / 3.0, n + 1)
        });
    sum / n.max(1) as f32
}

/// Renders `scene` at `args` plus tiny common settings and reads the image back.
fn render_tiny(scene: Option<&str>, args: &[&str], out: &Path) -> (Image, String) {
    let mut all: Vec<&str> = vec!["render"];
    all.extend(scene);
    all.extend_from_slice(&["-q", "-o", out.to_str().unwrap()]);
    all.extend_from_slice(args);
    let o = caustica(&all);
    let err = stderr(&o);
    assert!(o.status.success(), "{scene:?} {args:?}: {err}");
    (Image::read(out).unwrap(), err)
}

/// The caustic region of `scene` at `width`: the pixels where the light tracer's caustics
/// (L S+ D E, an estimator independent of the photon methods) reach a quarter of their
/// maximum, and their mean there (W/m²/sr). `None` for a scene without caustics.
fn caustic_region(scene: Option<&str>, width: &str, out: &Path) -> Option<(Vec<bool>, f32)> {
    let (lt, _) = render_tiny(
        scene,
        &[
            "--integrator",
            "lighttrace",
            "--caustics-only",
            "--width",
            width,
            "--spp",
            "512",
        ],
        out,
    );
    let lum: Vec<f32> = lt.data.iter().map(|p| (p[0] + p[1] + p[2]) / 3.0).collect();
    let max = lum.iter().copied().fold(0.0f32, f32::max);
    if max <= 0.0 {
        return None;
    }
    let mask: Vec<bool> = lum.iter().map(|&v| v >= 0.25 * max).collect();
    let mean = masked_mean(&lt, &mask);
    Some((mask, mean))
}

#[test]
fn every_shipped_and_built_in_scene_shows_its_light_with_its_own_integrator() {
    // Tiny settings, each scene's own integrator and options otherwise. The caustic scenes were
    // black (water wave, metal ring: the path tracer under a directional light) before they
    // named their integrator.
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut scenes: Vec<String> = std::fs::read_dir(root.join("scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| p.to_str().unwrap().to_string())
        .collect();
    scenes.sort();
    let output = caustica(&["scenes"]);
    let listed = String::from_utf8_lossy(&output.stdout).to_string();
    for b in caustica_loader::builtin_names() {
        assert!(listed.contains(b), "`caustica scenes` does not list {b}");
        scenes.push(b.to_string());
    }
    let out = tmp("every-scene.exr");
    let tiny = [
        "--width",
        "32",
        "--spp",
        "2",
        "--photons",
        "3000",
        "--global-photons",
        "3000",
    ];
    for scene in &scenes {
        let (img, err) = render_tiny(Some(scene), &tiny, &out);
        assert!(
            !err.contains("cannot render their caustics"),
            "{scene}: {err}"
        );
        let mean = masked_mean(&img, &vec![true; img.data.len()]);
        // Radiance of the lit regions is O(0.1–10) W/m²/sr in every scene; 1e-3 on average is
        // far from black and far below any of them.
        assert!(mean > 1e-3, "{scene}: mean radiance {mean}");
        // Where the scene has a caustic, its own integrator must show it: over the region the
        // light tracer lights (its caustics alone), the scene's integrator's caustics alone
        // reach at least 40 % of the light tracer's mean there. A method that misses the
        // caustic gives 0 (the path tracer under a point or directional light); the photon
        // methods' blur at 3000 photons spreads the caustic over its neighbours and loses at
        // most a third of it from the region.
        // Except in `laser-smoke`, whose caustics are the laser's wall spots, 4 cm across: a
        // sixth of a pixel at 32 × 32, which the light tracer splats exactly but 2 camera rays
        // per pixel rarely hit (at 128 × 128, `pm` with 100 000 photons and 64 spp matches the
        // light tracer's caustics there within 5 %). The mean above still sees its beams.
        // Likewise `glass-smoke`'s floor caustic, focused to about 5 cm (a fifth of a pixel at
        // 32 px): its footprints are left to 2 rays per pixel (at 160 × 120, 16 spp and
        // 100 000 photons its own integrator matches the light tracer's caustics within 1 %).
        let subpixel_caustics = ["laser-smoke", "glass-smoke"]
            .iter()
            .any(|n| scene == n || scene.ends_with(&format!("/{n}.toml")));
        if subpixel_caustics {
            continue;
        }
        if let Some((mask, reference)) = caustic_region(Some(scene), "32", &out) {
            let mut args = tiny.to_vec();
            args.push("--caustics-only");
            let (img, _) = render_tiny(Some(scene), &args, &out);
            let m = masked_mean(&img, &mask);
            eprintln!("{scene}: caustic region {m:.4} W/m²/sr, light tracer {reference:.4}");
            assert!(
                m >= 0.4 * reference,
                "{scene}: caustic region mean {m} W/m²/sr, light tracer {reference}"
            );
        }
    }
}

#[test]
fn the_default_render_shows_its_caustic() {
    // The README's render command without a scene (at 64 × 64 and fewer photons): the glass
    // ball's caustic on the floor of `caustic-box`, in the region the light tracer's caustics
    // light, holds at least half and at most twice the light tracer's radiance there (about
    // 0.3 W/m²/sr), and the full render there is at least as bright as its caustics alone.
    let out = tmp("default-caustic.exr");
    let (mask, reference) = caustic_region(None, "64", &out).expect("the default has a caustic");
    assert!(reference > 0.1, "light tracer caustic {reference} W/m²/sr");
    let tiny = ["--width", "64", "--spp", "2", "--photons", "20000"];
    let mut args = tiny.to_vec();
    args.push("--caustics-only");
    let (caustic, err) = render_tiny(None, &args, &out);
    assert!(!err.contains("cannot render"), "{err}");
    let c = masked_mean(&caustic, &mask);
    assert!(
        (0.5 * reference..=2.0 * reference).contains(&c),
        "default caustic {c} W/m²/sr vs light tracer {reference}"
    );
    let mut args = tiny.to_vec();
    args.extend_from_slice(&["--global-photons", "3000", "--final-gather", "1"]);
    let (full, _) = render_tiny(None, &args, &out);
    let f = masked_mean(&full, &mask);
    assert!(f >= 0.9 * c, "full render {f} W/m²/sr vs its caustics {c}");
}

#[test]
fn the_sse_fallback_bvh_renders_the_same_bytes() {
    // A CPU without AVX2 builds 4-wide BVH nodes instead of 8-wide ones; CAUSTICA_BVH_WIDTH=4
    // forces that fallback. The hits are the same bit for bit (the tie rule makes them
    // independent of the visiting order), so the images are too: a mesh scene (the water
    // wave's height field, a Cornell box) through the path tracer and photon splatting.
    for (scene, kind) in [
        ("cornell-box", "path"),
        ("water-wave", "pds"),
        ("metal-ring", "pm"),
    ] {
        let render = |width: Option<&str>, out: &Path| {
            let mut cmd = Command::new(env!("CARGO_BIN_EXE_caustica"));
            if let Some(w) = width {
                cmd.env("CAUSTICA_BVH_WIDTH", w);
            }
            let o = cmd
                .args([
                    "render",
                    scene,
                    "--integrator",
                    kind,
                    "--spp",
                    "2",
                    "--photons",
                    "20000",
                    "--width",
                    "64",
                    "--height",
                    "64",
                    "-q",
                    "-o",
                    out.to_str().unwrap(),
                ])
                .output()
                .expect("run caustica");
            assert!(o.status.success(), "{scene} {kind}: {}", stderr(&o));
            std::fs::read(out).unwrap()
        };
        let (a, b) = (tmp("bvh-default.exr"), tmp("bvh-four.exr"));
        let (default, four) = (render(None, &a), render(Some("4"), &b));
        assert!(
            default == four,
            "{scene} {kind}: the 4-wide BVH renders other bytes"
        );
        let img = Image::read(&a).unwrap();
        assert!(img.data.iter().any(|p| p[0] > 0.0), "{scene} {kind}: black");
    }
}
