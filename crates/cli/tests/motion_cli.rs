//! `caustica render --frames A..B`: one image per frame, each the render `--frame F` gives, an
//! animated PNG preview of them, resuming with `--skip-existing`, and clean errors.

mod common;
use caustica_core::image_io::Image;
use common::{assert_clean_failure, caustica, stderr, stdout, tmp_in};

fn tmp(name: &str) -> std::path::PathBuf {
    tmp_in("motion", name)
}

const SMALL: [&str; 8] = [
    "--integrator",
    "lighttrace",
    "--caustics-only",
    "--spp",
    "2",
    "--width",
    "24",
    "-q",
];

/// The `acTL` chunk of an APNG: (frames, plays).
fn apng_frames(bytes: &[u8]) -> Option<(u32, u32)> {
    let at = bytes.windows(4).position(|w| w == b"acTL")?;
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    Some((be(at + 4), be(at + 8)))
}

#[test]
fn a_sequence_is_the_renders_of_its_frames_and_a_preview() {
    let pattern = tmp("wave_%02d.exr");
    let mut args = vec!["render", "moving-wave", "--frames", "2..4", "-o"];
    let p = pattern.to_str().unwrap().to_string();
    args.push(&p);
    args.extend(SMALL);
    let o = caustica(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("frames 2..4 (3 rendered, 0 kept)"),
        "{}",
        stdout(&o)
    );
    let frames: Vec<Image> = (2..=4)
        .map(|f| Image::read(&tmp(&format!("wave_{f:02}.exr"))).unwrap())
        .collect();
    // Each frame is the render of that frame alone.
    let single = tmp("single.exr");
    let s = single.to_str().unwrap().to_string();
    let mut one = vec!["render", "moving-wave", "--frame", "3", "-o", &s];
    one.extend(SMALL);
    let o = caustica(&one);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(Image::read(&single).unwrap(), frames[1]);
    // The wave moves: frames differ (by far more than nothing).
    let diff: f32 = frames[0]
        .data
        .iter()
        .zip(&frames[2].data)
        .map(|(a, b)| (a[0] - b[0]).abs())
        .sum();
    assert!(diff > 1.0, "frames 2 and 4 are alike: {diff}");
    // The preview: an APNG of three frames, looping.
    let preview = std::fs::read(tmp("wave_preview.png")).unwrap();
    assert_eq!(&preview[1..4], b"PNG");
    assert_eq!(apng_frames(&preview), Some((3, 0)));
    // Resuming keeps what exists.
    let mut again = args.clone();
    again.push("--skip-existing");
    let o = caustica(&again);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("(0 rendered, 3 kept)"),
        "{}",
        stdout(&o)
    );
}

#[test]
fn bad_sequences_fail_cleanly() {
    let x = tmp("x_%d.exr");
    let x = x.to_str().unwrap();
    for (extra, words) in [
        (
            vec!["--frames", "4..2", "-o", x],
            &["--frames", "first frame"][..],
        ),
        (vec!["--frames", "0-2", "-o", x], &["A..B"][..]),
        (
            vec!["--frames", "0..2", "-o", "plain.exr"],
            &["frame field"][..],
        ),
        (
            vec!["--frames", "0..2", "--frame", "1", "-o", x],
            &["exclude"][..],
        ),
        (
            vec!["--apng", "p.png", "-o", "plain.exr"],
            &["--frames"][..],
        ),
        (vec!["--shutter", "-1", "-o", "plain.exr"], &["shutter"][..]),
    ] {
        let mut args = vec!["render", "moving-wave", "--spp", "1", "-q"];
        args.extend(extra);
        assert_clean_failure(&caustica(&args), words);
    }
}

#[test]
fn bad_animation_tables_name_file_and_line() {
    let scene = tmp("bad-fps.toml");
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/moving-wave.toml"),
    )
    .unwrap()
    .replace("fps = 25 ", "fps = 0 ")
    .replace(
        "meshes/",
        &format!("{}/../../scenes/meshes/", env!("CARGO_MANIFEST_DIR")),
    );
    let line = text.lines().position(|l| l.starts_with("fps = 0")).unwrap() + 1;
    std::fs::write(&scene, text).unwrap();
    let o = caustica(&[
        "render",
        scene.to_str().unwrap(),
        "--spp",
        "1",
        "-q",
        "-o",
        "n.exr",
    ]);
    assert_clean_failure(&o, &[&format!("bad-fps.toml:{line}"), "fps", "positive"]);
}
