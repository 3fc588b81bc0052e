//! `--emission` end to end: the render notes name the rule and its caustic yield (and the
//! adaptive sampler's acceptance and normalisation), a scene without specular surfaces falls
//! back to uniform emission with a warning, and a bad value fails cleanly.

mod common;

use common::{assert_clean_failure, caustica, stderr, stdout};

fn render(extra: &[&str]) -> std::process::Output {
    let name = if extra.is_empty() {
        "default".to_string()
    } else {
        extra.join("-")
    };
    let out = common::tmp_in("emission-cli", &format!("{name}.exr"));
    let mut args = vec![
        "render",
        "glass-sphere",
        "--integrator",
        "pds",
        "--photons",
        "3000",
        "--smoothing",
        "2",
        "--spp",
        "1",
        "--width",
        "32",
        "--caustics-only",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    caustica(&args)
}

#[test]
fn notes_report_the_rule_and_the_caustic_yield() {
    let o = render(&["--emission", "uniform"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let all = |o: &std::process::Output| format!("{}{}", stdout(o), stderr(o));
    assert!(
        all(&o).contains("caustic emission: uniform; caustic yield 0."),
        "{}",
        all(&o)
    );
    // The default is projection maps.
    let o = render(&[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = all(&o);
    assert!(s.contains("caustic emission: projection map,"), "{s}");
    assert!(
        s.contains("cells marked") && s.contains("caustic yield 5"),
        "{s}"
    );
    let o = render(&["--emission", "adaptive"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = all(&o);
    assert!(
        s.contains("adaptive photon tracing: 64 chains")
            && s.contains("acceptance")
            && s.contains("V_c ="),
        "{s}"
    );
}

#[test]
fn a_scene_without_specular_surfaces_falls_back_to_uniform_emission() {
    let out = common::tmp_in("emission-cli", "cornell.exr");
    let o = caustica(&[
        "render",
        "cornell-box",
        "--integrator",
        "pm",
        "--photons",
        "100",
        "--global-photons",
        "1000",
        "--final-gather",
        "0",
        "--spp",
        "1",
        "--width",
        "16",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let all = format!("{}{}", stdout(&o), stderr(&o));
    assert!(
        all.contains("no light reaches a mirror, glass or smooth metal surface; caustic photons are emitted uniformly"),
        "{all}"
    );
}

#[test]
fn an_unknown_rule_fails_cleanly() {
    let o = render(&["--emission", "guided"]);
    assert_clean_failure(&o, &["guided", "projection"]);
}
