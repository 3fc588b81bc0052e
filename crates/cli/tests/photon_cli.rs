//! End-to-end checks of the photon-mapping command line: `--integrator pm`, `caustica photons`,
//! and their bad input (k = 0, negative radius, zero photons, no lights, no diffuse surface).

mod common;

use common::{assert_clean_failure, caustica};
use std::path::PathBuf;
use std::process::Output;

fn tmp(name: &str) -> PathBuf {
    common::tmp_in("pm-cli-test", name)
}

fn write(name: &str, text: &str) -> String {
    let p = tmp(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A tiny glass-ball scene: 16×16 pixels, point light, diffuse floor (or a mirror floor).
fn ball_scene(name: &str, floor: &str, light: bool) -> String {
    let light = if light {
        "[[light]]\ntype = \"point\"\nposition = [0, 3, 0]\nintensity = 20\n"
    } else {
        ""
    };
    write(
        name,
        &format!(
            "name = \"tiny-ball\"\n\
             [camera]\neye = [0, 2.5, 2.5]\ntarget = [0, 0.3, 0]\nfov = 45\nwidth = 16\nheight = 16\n\
             [[material]]\nname = \"floor\"\n{floor}\n\
             [[material]]\nname = \"glass\"\ntype = \"dielectric\"\nior = 1.5\n\
             [[shape]]\ntype = \"rectangle\"\nmaterial = \"floor\"\nscale = 2\n\
             rotate = {{ axis = [1, 0, 0], angle = -90 }}\n\
             [[shape]]\ntype = \"sphere\"\nmaterial = \"glass\"\ncenter = [0, 0.5, 0]\nradius = 0.5\n\
             {light}"
        ),
    )
}

const DIFFUSE: &str = "type = \"diffuse\"\nreflectance = 0.8";

/// Runs `render SCENE --integrator pm` writing `out` (one file per test: tests run in parallel).
fn pm(scene: &str, out: &str, extra: &[&str]) -> Output {
    let out = tmp(out);
    let mut args = vec![
        "render",
        scene,
        "--integrator",
        "pm",
        "--spp",
        "2",
        "-q",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    caustica(&args)
}

#[test]
fn pm_renders_a_caustic_and_reports_its_photon_pass() {
    let scene = ball_scene("ok.toml", DIFFUSE, true);
    let o = pm(
        &scene,
        "ok.exr",
        &["--photons", "2000", "--global-photons", "2000", "--k", "20"],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(err.contains("photons: caustic 2000"), "{err}");
    let out = text(&o.stdout);
    assert!(out.contains("samples/s"), "{out}");
    let img = caustica_core::image_io::Image::read(&tmp("ok.exr")).unwrap();
    assert!(img.data.iter().any(|p| p[0] > 0.0), "black image");
}

#[test]
fn pm_bad_parameters_fail_with_a_message_naming_them() {
    let scene = ball_scene("bad.toml", DIFFUSE, true);
    assert_clean_failure(
        &pm(&scene, "bad.exr", &["--k", "0"]),
        &["photons per estimate (--k)"],
    );
    assert_clean_failure(
        &pm(&scene, "bad.exr", &["--max-radius", "-1"]),
        &["maximum radius", "-1"],
    );
    assert_clean_failure(
        &pm(&scene, "bad.exr", &["--max-radius", "nan"]),
        &["maximum radius"],
    );
    assert_clean_failure(
        &pm(&scene, "bad.exr", &["--photons", "0"]),
        &["caustic photons"],
    );
    assert_clean_failure(
        &pm(&scene, "bad.exr", &["--global-k", "0"]),
        &["global map (--global-k)"],
    );
    assert_clean_failure(
        &pm(&scene, "bad.exr", &["--kernel", "box"]),
        &["unknown kernel 'box'"],
    );
    assert_clean_failure(&pm(&scene, "bad.exr", &["--kernel", "cone:0.5"]), &["cone"]);
}

#[test]
fn pm_without_lights_is_an_error() {
    let scene = ball_scene("dark.toml", DIFFUSE, false);
    assert_clean_failure(&pm(&scene, "bad.exr", &[]), &["no lights"]);
    assert_clean_failure(
        &caustica(&["photons", &scene, "-o", tmp("p.png").to_str().unwrap()]),
        &["no lights"],
    );
}

#[test]
fn pm_without_diffuse_surfaces_warns_and_renders() {
    // A mirror floor and a glass ball: no surface can hold a photon. The photon pass gives up
    // after a bounded number of paths with a warning, and the image is still written.
    let scene = ball_scene("mirror.toml", "type = \"mirror\"", true);
    let o = pm(
        &scene,
        "mirror.exr",
        &["--photons", "1000", "--global-photons", "1000"],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(err.contains("warning: only 0 caustic photons"), "{err}");
    assert!(err.contains("warning: only 0 global photons"), "{err}");
    assert!(tmp("mirror.exr").exists());
}

#[test]
fn photons_command_draws_the_photons() {
    let scene = ball_scene("draw.toml", DIFFUSE, true);
    let png = tmp("photons.png");
    let o = caustica(&[
        "photons",
        &scene,
        "--photons",
        "500",
        "--global-photons",
        "500",
        "--background-spp",
        "1",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    assert!(out.contains("of 500 caustic photons"), "{out}");
    let img = caustica_core::image_io::Image::read(&png).unwrap();
    assert_eq!((img.width, img.height), (16, 16));
}

#[test]
fn pm_renders_a_mitsuba_xml_scene() {
    let xml = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/mitsuba/glass-sphere-point.xml"
    );
    let o = pm(
        xml,
        "xml.exr",
        &[
            "-D",
            "width=16",
            "-D",
            "height=12",
            "--photons",
            "500",
            "--global-photons",
            "500",
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("photons: caustic 500"));
    let img = caustica_core::image_io::Image::read(&tmp("xml.exr")).unwrap();
    assert_eq!((img.width, img.height), (16, 12));
}

/// pm without global photons and without final gathering would show an empty global map (a
/// black image): refused with what to give instead; with --caustics-only it is fine.
#[test]
fn pm_showing_an_empty_global_map_is_an_error() {
    let scene = ball_scene("empty-global.toml", DIFFUSE, true);
    let args = [
        "--global-photons",
        "0",
        "--final-gather",
        "0",
        "--photons",
        "1000",
    ];
    assert_clean_failure(
        &pm(&scene, "empty-global.exr", &args),
        &["--global-photons 0", "black image"],
    );
    let mut with_caustics = args.to_vec();
    with_caustics.push("--caustics-only");
    let o = pm(&scene, "caustics-only.exr", &with_caustics);
    assert!(o.status.success(), "{}", text(&o.stderr));
}
