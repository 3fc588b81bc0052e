//! `[animation]`, mesh sequences and keyframed transforms: what they build, and every bad input
//! the issue names (different topology or vertex counts, a missing frame file, a frame rate
//! ≤ 0, a shutter < 0, degenerate motion) as an error naming the file and frame.

use super::parse_toml_scene;
use crate::error::LoadError;
use caustica_core::Vec3;
use caustica_scene::scene::SceneBuilder;
use std::path::{Path, PathBuf};

const CAMERA: &str =
    "[camera]\neye = [0, 0, 4.1]\ntarget = [0, 0, 0]\nfov = 39.3077\nwidth = 16\nheight = 16\n";
const MATERIAL: &str = "[[material]]\nname = \"d\"\ntype = \"diffuse\"\n";

/// A folder with `tri-0.ply` … `tri-{n-1}.ply`: one triangle moved by `step(k)` at frame k.
fn sequence_dir(tag: &str, n: usize, step: impl Fn(usize) -> Vec3) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("caustica-anim-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for k in 0..n {
        let d = step(k);
        let v = [Vec3::ZERO, Vec3::X, Vec3::Y].map(|p| p + d);
        let text = format!(
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
             property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
             end_header\n{} {} {}\n{} {} {}\n{} {} {}\n3 0 1 2\n",
            v[0].x, v[0].y, v[0].z, v[1].x, v[1].y, v[1].z, v[2].x, v[2].y, v[2].z
        );
        std::fs::write(dir.join(format!("tri-{k}.ply")), text).unwrap();
    }
    dir
}

fn parse_in(dir: &Path, text: &str) -> Result<SceneBuilder, LoadError> {
    parse_toml_scene(text, &dir.join("scene.toml"))
}

const ANIMATION: &str = "[animation]\nfps = 24\nframe = 1\nshutter = 0.5\n";

#[test]
fn a_mesh_sequence_becomes_keyframes_at_its_frame_numbers() {
    let dir = sequence_dir("seq", 3, |k| Vec3::new(0.0, 0.0, 0.25 * k as f32));
    let text = format!(
        "{CAMERA}{ANIMATION}{MATERIAL}[[shape]]\ntype = \"ply\"\nmaterial = \"d\"\n\
         frames = \"tri-%d.ply\"\nframe_range = [0, 2]\ntranslate = [1, 0, 0]\n"
    );
    let b = parse_in(&dir, &text).unwrap();
    assert_eq!(b.settings.fps, Some(24.0));
    assert_eq!((b.shutter().open, b.shutter().length), (1.0, 0.5));
    let m = b.shapes()[0].motion.clone().expect("the shape moves");
    assert_eq!((m.first_frame, m.frame_count()), (0.0, 3));
    // The shape's transform applies to every frame; keyframe k is the file of frame k.
    for k in 0..3 {
        assert_eq!(m.positions[k][1], Vec3::new(2.0, 0.0, 0.25 * k as f32));
    }
    // The scene builds, and at frame 1.5 the triangle is halfway between frames 1 and 2.
    let scene = b.build().unwrap();
    assert!(scene.has_motion());
    assert!((m.position(0, 1.5).z - 0.375).abs() < 1e-6);

    // A list of files, starting at frame 10.
    let text = format!(
        "{CAMERA}{ANIMATION}{MATERIAL}[[shape]]\ntype = \"ply\"\nmaterial = \"d\"\n\
         frames = [\"tri-2.ply\", \"tri-0.ply\"]\nfirst_frame = 10\n"
    );
    let b = parse_in(&dir, &text).unwrap();
    let m = b.shapes()[0].motion.as_ref().unwrap();
    assert_eq!((m.first_frame, m.frame_count()), (10.0, 2));
    assert_eq!(m.positions[0][0], Vec3::new(0.0, 0.0, 0.5));
    assert_eq!(m.positions[1][0], Vec3::ZERO);
}

#[test]
fn keyframed_transforms_interpolate_per_frame() {
    // A unit quad turning 90° about +y over frames 0 … 6 while moving 3 m along +x and growing
    // to twice its size: at frame 2 a third of each.
    let text = format!(
        "{CAMERA}{ANIMATION}{MATERIAL}[[shape]]\ntype = \"rectangle\"\nmaterial = \"d\"\n\
         [[shape.keyframe]]\nframe = 0\n\
         [[shape.keyframe]]\nframe = 6\nrotate = {{ axis = [0, 1, 0], angle = 90 }}\n\
         translate = [3, 0, 0]\nscale = 2\n"
    );
    let b = parse_in(Path::new("/virtual"), &text).unwrap();
    let m = b.shapes()[0].motion.as_ref().unwrap();
    assert_eq!((m.first_frame, m.frame_count()), (0.0, 7));
    // The rectangle's corner (1, 1, 0) at frame 2: scale 4/3, turned 30°, moved by 1.
    let (s, a) = (4.0f32 / 3.0, 30f32.to_radians());
    let k = (0..4)
        .find(|&i| m.positions[0][i].abs_diff_eq(Vec3::new(1.0, 1.0, 0.0), 1e-6))
        .expect("the rectangle has the corner (1, 1, 0)");
    let want = Vec3::new(s * a.cos() + 1.0, s, -s * a.sin());
    assert!(
        m.positions[2][k].abs_diff_eq(want, 1e-5),
        "{}",
        m.positions[2][k]
    );
    assert!(m.positions[6][k].abs_diff_eq(Vec3::new(3.0, 2.0, -2.0), 1e-5));
}

/// Asserts an error whose text holds every word of `words`.
#[track_caller]
fn expect_error(r: Result<SceneBuilder, LoadError>, words: &[&str]) {
    match r {
        Err(e) => {
            let s = e.to_string();
            for w in words {
                assert!(s.contains(w), "'{s}' lacks '{w}'");
            }
        }
        Ok(_) => panic!("expected an error with {words:?}"),
    }
}

#[test]
fn bad_animations_are_errors_naming_file_frame_and_line() {
    let dir = sequence_dir("bad", 3, |k| Vec3::new(0.0, 0.0, 0.1 * k as f32));
    let shape = |extra: &str| {
        format!("{CAMERA}{ANIMATION}{MATERIAL}[[shape]]\ntype = \"ply\"\nmaterial = \"d\"\n{extra}")
    };
    // A missing frame file: named, with its frame and the shape's line (12).
    expect_error(
        parse_in(
            &dir,
            &shape("frames = \"tri-%d.ply\"\nframe_range = [0, 3]\n"),
        ),
        &["tri-3.ply", "frame 3", "scene.toml:14"],
    );
    // A frame with another vertex count, and one with other faces.
    std::fs::write(
        dir.join("quad.ply"),
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
         property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n",
    )
    .unwrap();
    expect_error(
        parse_in(&dir, &shape("frames = [\"tri-0.ply\", \"quad.ply\"]\n")),
        &[
            "frame 1",
            "quad.ply",
            "4 vertices",
            "same topology",
            "scene.toml:14",
        ],
    );
    std::fs::write(
        dir.join("flipped.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0\n1 0 0\n0 1 0\n3 0 2 1\n",
    )
    .unwrap();
    expect_error(
        parse_in(&dir, &shape("frames = [\"tri-0.ply\", \"flipped.ply\"]\n")),
        &["frame 1", "flipped.ply", "other faces"],
    );
    // Degenerate motion: the triangle jumps 1000 m between frames 0 and 1.
    let far = sequence_dir("far", 2, |k| Vec3::new(1000.0 * k as f32, 0.0, 0.0));
    expect_error(
        parse_in(
            &far,
            &shape("frames = \"tri-%d.ply\"\nframe_range = [0, 1]\n"),
        ),
        &["degenerate motion", "frames 0 and 1", "scene.toml:14"],
    );
    // Patterns and ranges.
    for (extra, words) in [
        (
            "frames = \"tri.ply\"\nframe_range = [0, 1]\n",
            &["no frame field"][..],
        ),
        ("frames = \"tri-%d.ply\"\n", &["frame_range"][..]),
        (
            "frames = \"tri-%d.ply\"\nframe_range = [2, 1]\n",
            &["first ≤ last"][..],
        ),
        ("frames = []\n", &["1 to"][..]),
        (
            "frames = [\"tri-0.ply\"]\nframe_range = [0, 1]\n",
            &["first_frame"][..],
        ),
        (
            "frames = \"tri-%d.ply\"\nfilename = \"tri-0.ply\"\n",
            &["not both"][..],
        ),
        (
            "frames = \"tri-%d.ply\"\nframe_range = [0, 1]\nemission = 1\n",
            &["cannot emit"][..],
        ),
    ] {
        expect_error(parse_in(&dir, &shape(extra)), words);
    }
    // No [animation] for a moving shape; a frame rate ≤ 0; a negative shutter.
    let moving = "[[shape]]\ntype = \"ply\"\nmaterial = \"d\"\nframes = \"tri-%d.ply\"\nframe_range = [0, 1]\n";
    expect_error(
        parse_in(&dir, &format!("{CAMERA}{MATERIAL}{moving}")),
        &["[animation]", "fps", "scene.toml:10"],
    );
    for (anim, line, field) in [
        ("[animation]\nfps = 0\n", 8, "fps"),
        ("[animation]\nfps = -25\n", 8, "fps"),
        ("[animation]\nfps = 25\nshutter = -1\n", 9, "shutter"),
        ("[animation]\nfps = 25\nframe = nan\n", 9, "frame"),
    ] {
        match parse_in(&dir, &format!("{CAMERA}{anim}{MATERIAL}{moving}")) {
            Err(LoadError::Parse {
                line: l, message, ..
            }) => {
                assert_eq!(l, line, "{message}");
                assert!(message.contains(field), "{message}");
            }
            other => panic!("{anim}: expected a parse error, got {:?}", other.err()),
        }
    }
    // Keyframes out of order, or on a shape that cannot move.
    let keyed = |ty: &str, frames: [i64; 2]| {
        format!(
            "{CAMERA}{ANIMATION}{MATERIAL}[[shape]]\ntype = \"{ty}\"\nmaterial = \"d\"\n\
             [[shape.keyframe]]\nframe = {}\n[[shape.keyframe]]\nframe = {}\n",
            frames[0], frames[1]
        )
    };
    expect_error(
        parse_in(&dir, &keyed("cube", [3, 3])),
        &["increasing", "scene.toml:19"],
    );
    expect_error(
        parse_in(&dir, &keyed("sphere", [0, 1])),
        &["keyframe", "does not apply"],
    );
}
