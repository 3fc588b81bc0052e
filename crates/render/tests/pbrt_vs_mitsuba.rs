//! The pbrt-v4 translations in `scenes/pbrt-v4/` against their Mitsuba XML originals in
//! `scenes/mitsuba/`: both load into the same scene (camera, settings, lights, shapes,
//! triangles) and render the same image, byte for byte, small and fast with the integrator the
//! scenes suggest and a fixed seed. Bitwise equality holds because the pbrt files give caustica
//! the same single-precision numbers: transforms composed in the same products, the same
//! look-at frame, fovs chosen so that the screen extents round alike (docs/pbrt.md).

use caustica_core::image_io::Image;
use caustica_loader::{load_mitsuba, load_pbrt};
use caustica_render::{IntegratorKind, PathLimits, RenderControl, RenderOptions, render};
use caustica_scene::SceneBuilder;
use caustica_scene::shape::ShapeGeometry;
use std::path::PathBuf;

fn scenes() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

fn load(name: &str) -> (SceneBuilder, SceneBuilder) {
    let xml = scenes().join(format!("mitsuba/{name}.xml"));
    let pbrt = scenes().join(format!("pbrt-v4/{name}.pbrt"));
    let m = load_mitsuba(&xml, &[]).unwrap_or_else(|e| panic!("{}: {e}", xml.display()));
    let p = load_pbrt(&pbrt).unwrap_or_else(|e| panic!("{}: {e}", pbrt.display()));
    (m, p)
}

fn triangles(b: &SceneBuilder) -> usize {
    b.shapes()
        .iter()
        .map(|s| match &s.geometry {
            ShapeGeometry::Mesh(m) => m.indices.len(),
            _ => 0,
        })
        .sum()
}

/// Shrinks the camera's film to `w`×`h` (the scenes' aspect ratios are kept by the callers).
fn shrink(b: &mut SceneBuilder, w: u32, h: u32) {
    let mut c = b.camera().expect("camera").clone();
    (c.width, c.height) = (w, h);
    b.set_camera(c);
}

fn render_small(b: SceneBuilder, kind: IntegratorKind, max_depth: u32) -> Image {
    let scene = b.build().expect("scene builds");
    let opts = RenderOptions {
        spp: 8,
        seed: 7,
        limits: PathLimits {
            max_depth,
            ..PathLimits::default()
        },
        ..Default::default()
    };
    render(&scene, kind, &opts, &RenderControl::silent())
        .expect("valid options")
        .film
        .to_image()
}

/// Loads both versions of `name`, checks that they describe the same scene, renders both at
/// `w`×`h` and checks that the images are the same bytes.
fn same_scene(name: &str, w: u32, h: u32) {
    let (mut m, mut p) = load(name);
    let (cm, cp) = (m.camera().unwrap().clone(), p.camera().unwrap().clone());
    assert_eq!(
        (cm.width, cm.height),
        (cp.width, cp.height),
        "{name}: film size"
    );
    assert_eq!(
        cm.screen_half_extent(),
        cp.screen_half_extent(),
        "{name}: screen extents (fov)"
    );
    assert_eq!(cm.to_world, cp.to_world, "{name}: camera frame");
    assert_eq!(cm.lens_radius, cp.lens_radius, "{name}: lens");
    let kind = |b: &SceneBuilder| -> IntegratorKind {
        b.settings
            .integrator
            .as_deref()
            .expect("integrator")
            .parse()
            .expect("known integrator")
    };
    assert_eq!(kind(&m), kind(&p), "{name}: integrator");
    assert_eq!(
        m.settings.max_depth, p.settings.max_depth,
        "{name}: max depth"
    );
    assert_eq!(m.settings.spp, p.settings.spp, "{name}: spp");
    assert_eq!(m.settings.filter, p.settings.filter, "{name}: pixel filter");
    assert_eq!(m.lights().len(), p.lights().len(), "{name}: lights");
    assert_eq!(m.shape_count(), p.shape_count(), "{name}: shapes");
    assert_eq!(triangles(&m), triangles(&p), "{name}: triangles");
    assert_eq!(
        m.materials().len(),
        p.materials().len(),
        "{name}: materials"
    );
    let k = kind(&m);
    let depth = m.settings.max_depth.unwrap_or(u32::MAX);
    shrink(&mut m, w, h);
    shrink(&mut p, w, h);
    let (a, b) = (render_small(m, k, depth), render_small(p, k, depth));
    assert!(
        a.data.iter().flatten().any(|&x| x > 0.0),
        "{name}: the image is black"
    );
    let differing = a
        .data
        .iter()
        .zip(&b.data)
        .filter(|(x, y)| x.map(f32::to_bits) != y.map(f32::to_bits))
        .count();
    assert_eq!(
        differing,
        0,
        "{name}: {differing} of {} pixels differ",
        a.data.len()
    );
}

#[test]
fn cornell_box_pbrt_renders_as_the_mitsuba_xml() {
    same_scene("cornell-box", 48, 48);
}

#[test]
fn glass_sphere_point_pbrt_renders_as_the_mitsuba_xml() {
    same_scene("glass-sphere-point", 64, 48);
}

#[test]
fn water_wave_pbrt_renders_as_the_mitsuba_xml() {
    same_scene("water-wave", 48, 48);
}

#[test]
fn metal_ring_pbrt_renders_as_the_mitsuba_xml() {
    same_scene("metal-ring", 48, 48);
}

#[test]
fn gold_ring_pbrt_renders_as_the_mitsuba_xml() {
    same_scene("gold-ring", 64, 48);
}
