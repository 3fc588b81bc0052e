//! `caustica render --crop X,Y,W,H` on every scene kind (built-in, TOML, Mitsuba XML), after the
//! `--width`/`--height` overrides: the image written is W×H and its pixels are the uncropped
//! render's, byte for byte.

mod common;

use caustica_core::image_io::Image;
use common::{caustica, stderr, stdout, tmp_in};
use std::path::Path;

/// Renders `scene` with `extra` arguments into `name` and reads it back.
fn render(scene: &str, name: &str, extra: &[&str]) -> (Image, String) {
    let out = tmp_in("crop", name);
    let mut args = vec![
        "render",
        scene,
        "-q",
        "--width",
        "36",
        "--height",
        "27",
        "--spp",
        "2",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let o = caustica(&args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    (Image::read(&out).unwrap(), stdout(&o))
}

fn bits(img: &Image, x0: usize, y0: usize, w: usize, h: usize) -> Vec<[u32; 3]> {
    (y0..y0 + h)
        .flat_map(|y| (x0..x0 + w).map(move |x| (x, y)))
        .map(|(x, y)| img.data[y * img.width + x].map(f32::to_bits))
        .collect()
}

#[test]
fn a_crop_of_every_scene_kind_is_the_full_render_s_sub_image() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let toml = root.join("scenes/cornell-box.toml");
    let xml = root.join("scenes/mitsuba/cornell-box.xml");
    for (i, (scene, integrator)) in [
        ("cornell-box", "path"),
        (toml.to_str().unwrap(), "path"),
        (xml.to_str().unwrap(), "path"),
        ("cornell-box", "lighttrace"),
    ]
    .into_iter()
    .enumerate()
    {
        let kind = ["--integrator", integrator];
        let (full, _) = render(scene, &format!("full{i}.exr"), &kind);
        assert_eq!((full.width, full.height), (36, 27));
        let (crop, line) = render(
            scene,
            &format!("crop{i}.exr"),
            &["--integrator", integrator, "--crop", "5,20,30,7"],
        );
        assert_eq!((crop.width, crop.height), (30, 7), "{scene}");
        assert!(
            bits(&crop, 0, 0, 30, 7) == bits(&full, 5, 20, 30, 7),
            "{scene} {integrator}: the crop differs from the full render's pixels"
        );
        assert!(
            crop.data.iter().flatten().any(|&v| v > 0.0),
            "{scene}: black"
        );
        assert!(line.contains("30x7 (crop 5,20,30,7 of 36x27)"), "{line}");
    }
}

#[test]
fn help_states_the_crop_rule() {
    let o = caustica(&["render", "--help"]);
    assert!(o.status.success());
    let help = stdout(&o);
    for rule in [
        "--crop <X,Y,W,H>",
        "pixelbounds",
        "W and H at least 1",
        "inside the film",
    ] {
        assert!(help.contains(rule), "render --help does not state {rule:?}");
    }
}
