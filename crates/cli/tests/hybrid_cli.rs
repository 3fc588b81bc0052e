//! `--integrator hybrid` end to end: the notes and the summary say what each half did, a time
//! budget is split by `--light-share`, and bad values fail cleanly.

mod common;

use common::{assert_clean_failure, caustica, stderr, stdout};

fn render(extra: &[&str]) -> std::process::Output {
    let out = common::tmp_in("hybrid-cli", &format!("{}.pfm", extra.join("-")));
    let mut args = vec![
        "render",
        "glass-sphere",
        "--integrator",
        "hybrid",
        "--width",
        "32",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    caustica(&args)
}

#[test]
fn the_notes_say_what_each_half_did() {
    let o = render(&["--spp", "2", "--light-paths", "5000"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let all = format!("{}{}", stdout(&o), stderr(&o));
    assert!(all.contains("caustic emission: projection map,"), "{all}");
    assert!(all.contains("hybrid: 5000 light paths in"), "{all}");
    assert!(all.contains("5000 light paths, 2.0 spp"), "{all}");
    // Without a time budget the share has nothing to split: said, not silently ignored.
    let o = render(&["--spp", "1", "--light-share", "0.3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--light-share splits a time budget"),
        "{}",
        stderr(&o)
    );
    // A budget is split: both halves ran.
    let o = render(&["--time", "1", "--light-share", "0.3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let all = format!("{}{}", stdout(&o), stderr(&o));
    assert!(
        all.contains("light paths, ") && all.contains(" spp in "),
        "{all}"
    );
}

#[test]
fn bad_values_fail_cleanly() {
    for share in ["0", "1", "1.5", "-0.2", "nan", "x"] {
        let o = render(&["--spp", "1", "--light-share", share]);
        assert_clean_failure(&o, &["--light-share"]);
    }
    let o = render(&["--spp", "1", "--light-paths", "0"]);
    assert_clean_failure(&o, &["--light-paths"]);
    let o = render(&["--spp", "1", "--caustics-only"]);
    assert_clean_failure(&o, &["lighttrace"]);
}
