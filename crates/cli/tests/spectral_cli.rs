//! `--spectral` end to end: a spectral render says so in its summary and differs from the RGB
//! one only through dispersion; bad spectral input (unknown glass or illuminant, a dispersion
//! law below IOR 1) fails cleanly with the file and line; media render in spectral mode.

mod common;

use caustica_render::IntegratorKind;
use common::{assert_clean_failure, caustica, stderr, stdout};
use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    common::tmp_in("spectral-cli", name)
}

#[test]
fn prism_renders_in_spectral_mode_and_says_so() {
    let out = tmp("prism.exr");
    let o = caustica(&[
        "render",
        "prism",
        "--spectral",
        "--integrator",
        "lighttrace",
        "--spp",
        "1",
        "--width",
        "40",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("lighttrace (spectral)"),
        "{}",
        stdout(&o)
    );
}

/// Writes a small scene whose glass has `dispersion_line` (or whose light has `light_line`).
fn scene_with(name: &str, material_line: &str, light_line: &str) -> PathBuf {
    let p = tmp(name);
    std::fs::write(
        &p,
        format!(
            r#"[camera]
eye = [0, 1, 3]
target = [0, 0, 0]
fov = 40
width = 16
height = 16

[[material]]
name = "glass"
type = "dielectric"
{material_line}

[[shape]]
type = "sphere"
material = "glass"
center = [0, 0, 0]
radius = 0.5

[[light]]
type = "point"
position = [0, 2, 0]
intensity = 1
{light_line}
"#
        ),
    )
    .unwrap();
    p
}

#[test]
fn bad_spectral_input_fails_with_file_and_line() {
    let out = tmp("bad.exr");
    let render = |scene: &PathBuf| {
        caustica(&[
            "render",
            scene.to_str().unwrap(),
            "--spectral",
            "--spp",
            "1",
            "-o",
            out.to_str().unwrap(),
        ])
    };
    let s = scene_with("glass.toml", r#"dispersion = "unobtanium""#, "");
    assert_clean_failure(
        &render(&s),
        &["glass.toml:11:", "unknown glass 'unobtanium'"],
    );
    let s = scene_with("below1.toml", "dispersion = { cauchy = [0.9, 0.001] }", "");
    assert_clean_failure(&render(&s), &["below1.toml:11:", "must be finite and > 1"]);
    let s = scene_with("both.toml", "ior = 1.5\ndispersion = \"BK7\"", "");
    assert_clean_failure(&render(&s), &["both.toml", "either 'ior' or 'dispersion'"]);
    let s = scene_with("light.toml", r#"dispersion = "BK7""#, r#"spectrum = "D50""#);
    assert_clean_failure(&render(&s), &["light.toml", "unknown illuminant `D50`"]);
    let s = scene_with(
        "kelvin.toml",
        r#"dispersion = "BK7""#,
        r#"spectrum = "blackbody:-3""#,
    );
    assert_clean_failure(&render(&s), &["kelvin.toml", "blackbody temperature"]);
    // A good one renders.
    let s = scene_with(
        "good.toml",
        r#"dispersion = "water""#,
        r#"spectrum = "blackbody:3000""#,
    );
    let o = render(&s);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// Participating media render in spectral mode (the fog box, tiny) with every integrator that
/// renders media: a clean exit, the summary says spectral, no sample is NaN or infinite, and the
/// image is the same bytes for 1 and 2 threads. The progressive methods, which trace no volume
/// photons in either mode, still refuse the scene cleanly.
#[test]
fn media_render_in_spectral_mode_deterministically() {
    let render = |kind: &str, threads: &str| {
        let out = tmp(&format!("fog-{kind}-{threads}.exr"));
        let o = caustica(&[
            "render",
            "fog-box",
            "--spectral",
            "--integrator",
            kind,
            "--width",
            "16",
            "--spp",
            "1",
            "--photons",
            "2000",
            "--threads",
            threads,
            "-o",
            out.to_str().unwrap(),
        ]);
        (o, out)
    };
    let mut rendered = 0;
    for &kind in IntegratorKind::NAMES {
        let k: IntegratorKind = kind.parse().unwrap();
        let (o, out) = render(kind, "1");
        if k.is_progressive() {
            assert_clean_failure(&o, &["scattering media"]);
            continue;
        }
        assert!(o.status.success(), "{kind}: {}", stderr(&o));
        let s = stdout(&o);
        assert!(s.contains("(spectral)"), "{kind}: {s}");
        assert!(s.contains(" 0 NaN/Inf samples discarded"), "{kind}: {s}");
        let one = std::fs::read(&out).unwrap();
        let (o, out) = render(kind, "2");
        assert!(o.status.success(), "{kind}: {}", stderr(&o));
        assert_eq!(
            one,
            std::fs::read(&out).unwrap(),
            "{kind}: 1 and 2 threads differ"
        );
        rendered += 1;
    }
    // path, lighttrace, pm, dpm, pdm, pds, vpm, beam, vpd, hybrid.
    assert_eq!(rendered, 10);
}

/// Every integrator runs in spectral mode (the prism, tiny): a clean exit, the summary says
/// spectral, and no sample is NaN or infinite.
#[test]
fn every_integrator_runs_in_spectral_mode() {
    let out = tmp("every.exr");
    for &kind in IntegratorKind::NAMES {
        let mut args = vec![
            "render",
            "prism",
            "--spectral",
            "--integrator",
            kind,
            "--width",
            "24",
            "--spp",
            "1",
            "--photons",
            "2000",
            "-o",
            out.to_str().unwrap(),
        ];
        let k: IntegratorKind = kind.parse().unwrap();
        if k.is_progressive() {
            args.extend(["--iterations", "2"]);
        }
        let o = caustica(&args);
        assert!(o.status.success(), "{kind}: {}", stderr(&o));
        let s = stdout(&o);
        assert!(s.contains("(spectral)"), "{kind}: {s}");
        assert!(s.contains(" 0 NaN/Inf samples discarded"), "{kind}: {s}");
    }
}

/// A spectral render is the same bytes whatever the thread count.
#[test]
fn spectral_render_is_deterministic_across_thread_counts() {
    let render = |threads: &str, name: &str| {
        let out = tmp(name);
        let o = caustica(&[
            "render",
            "prism",
            "--spectral",
            "--integrator",
            "pds",
            "--width",
            "48",
            "--spp",
            "2",
            "--photons",
            "5000",
            "--threads",
            threads,
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(out).unwrap()
    };
    assert_eq!(render("1", "t1.exr"), render("2", "t2.exr"));
}
