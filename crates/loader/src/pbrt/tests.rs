//! Unit tests of the pbrt-v4 loader: every directive, and malformed input with its line and
//! column.

use super::parse_pbrt;
use crate::error::LoadError;
use caustica_core::{Spectrum, Vec3};
use caustica_scene::SceneBuilder;
use caustica_scene::camera::FovAxis;
use caustica_scene::light::{EmissionSpectrum, Light, NamedSpectrum};
use caustica_scene::material::Material;
use caustica_scene::scene::FilterKind;
use caustica_scene::shape::ShapeGeometry;
use caustica_scene::texture::Texture;
use std::path::{Path, PathBuf};

const HEADER: &str = "Camera \"perspective\"\nWorldBegin\n";

fn parse(text: &str) -> Result<SceneBuilder, LoadError> {
    parse_pbrt(text, Path::new("/nonexistent-caustica-test/scene.pbrt"))
}

fn ok(text: &str) -> SceneBuilder {
    parse(text).unwrap_or_else(|e| panic!("{e}\n--- input:\n{text}"))
}

/// A world-block scene: `HEADER` then `body`.
fn world(body: &str) -> SceneBuilder {
    ok(&format!("{HEADER}{body}"))
}

/// The error of `text`: line, column, message (it must be a parse error).
fn err(text: &str) -> (usize, usize, String) {
    match parse(text) {
        Err(LoadError::Parse {
            line,
            column,
            message,
            ..
        }) => (line, column, message),
        Err(e) => panic!("not a parse error: {e}"),
        Ok(_) => panic!("no error for:\n{text}"),
    }
}

fn warnings(b: &SceneBuilder) -> String {
    b.warnings.join("\n")
}

fn mesh(b: &SceneBuilder, i: usize) -> &caustica_scene::shape::TriangleMesh {
    match &b.shapes()[i].geometry {
        ShapeGeometry::Mesh(m) => m,
        g => panic!("not a mesh: {g:?}"),
    }
}

fn point_light(b: &SceneBuilder, i: usize) -> (Vec3, Spectrum) {
    match &b.lights()[i] {
        Light::Point(p) => (p.position, p.intensity),
        l => panic!("not a point light: {l:?}"),
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

/// A fresh directory under the system's temporary folder.
fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("caustica-pbrt-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

const QUAD: &str = r#"Shape "trianglemesh" "point3 P" [ 0 0 0  1 0 0  1 1 0  0 1 0 ] "integer indices" [ 0 1 2 0 2 3 ]"#;

// ---------------------------------------------------------------- tokens and parameters

#[test]
fn comments_strings_and_numbers_tokenize_with_positions() {
    use super::tokenizer::{Tok, tokenize};
    let t = tokenize("# c\n  Shape \"a\\\"b\" [ -1.5e2 .5 ] # x\nWorldBegin").unwrap();
    let kinds: Vec<_> = t.iter().map(|t| (t.tok.clone(), t.line, t.col)).collect();
    assert_eq!(
        kinds,
        vec![
            (Tok::Word("Shape".into()), 2, 3),
            (Tok::Str("a\"b".into()), 2, 9),
            (Tok::Open, 2, 16),
            (Tok::Num(-150.0), 2, 18),
            (Tok::Num(0.5), 2, 25),
            (Tok::Close, 2, 28),
            (Tok::Word("WorldBegin".into()), 3, 1),
        ]
    );
}

#[test]
fn unterminated_strings_and_brackets_are_errors_at_their_start() {
    let (l, c, m) = err("Camera \"perspective\"\nWorldBegin\nShape \"sphere\n");
    assert_eq!((l, c), (3, 7), "{m}");
    assert!(m.contains("unterminated string"), "{m}");
    let (l, c, m) = err(&format!("{HEADER}Shape \"sphere\" \"float radius\" [ 1\n"));
    assert_eq!((l, c), (3, 31), "{m}");
    assert!(
        m.contains("unterminated '['") && m.contains("expected ']'"),
        "{m}"
    );
}

#[test]
fn bad_and_huge_numbers_are_errors() {
    let (l, c, m) = err(&format!("{HEADER}Translate 1 2 3x\n"));
    assert_eq!((l, c), (3, 15), "{m}");
    assert!(m.contains("bad number '3x'"), "{m}");
    let (l, c, m) = err(&format!("{HEADER}Translate 1 2 1e400\n"));
    assert_eq!((l, c), (3, 15), "{m}");
    assert!(m.contains("finite"), "{m}");
    // Finite in f64 but not in f32.
    let (l, _, m) = err(&format!("{HEADER}Translate 1 2 1e300\n"));
    assert_eq!(l, 3);
    assert!(m.contains("single-precision"), "{m}");
    let (l, c, m) = err("Film \"rgb\" \"integer xresolution\" [ 1e30 ]\n");
    assert_eq!((l, c), (1, 36), "{m}");
    assert!(m.contains("'xresolution' is an integer"), "{m}");
    let (l, c, m) = err("Film \"rgb\" \"integer xresolution\" [ 100000 ]\n");
    assert_eq!((l, c), (1, 12), "{m}");
    assert!(m.contains("xresolution must be from 1 to 65536"), "{m}");
}

#[test]
fn parameter_types_are_checked() {
    let cases = [
        ("\"float radius\" \"big\"", "expected numbers"),
        ("\"floot radius\" 1", "unknown parameter type 'floot'"),
        ("\"radius\" 1", "expected \"type name\""),
        ("\"integer radius\" 1.5", "is an integer: got 1.5"),
        ("\"point3 p\" [ 1 2 ]", "multiple of 3 numbers"),
        ("\"bool b\" 3", "expected true or false"),
        ("\"float radius\" 1 \"float radius\" 2", "given twice"),
        ("\"float radius\" [ 1 \"a\" ]", "mixes value kinds"),
        ("\"float radius\" [ ]", "empty value list"),
        ("\"string radius\" \"a\"", "must be a float"),
    ];
    for (params, want) in cases {
        let (l, c, m) = err(&format!("{HEADER}Shape \"sphere\" {params}\n"));
        assert_eq!(l, 3, "{params}: {m}");
        assert!(c >= 15, "{params}: column {c}");
        assert!(m.contains(want), "{params}: {m}");
    }
}

#[test]
fn leftover_parameters_and_ignored_directives_make_one_warning_with_lines() {
    let b = ok(&format!(
        "Accelerator \"bvh\"\n{HEADER}Shape \"sphere\" \"float radius\" 1 \"float frobnicate\" 2\nAttribute \"shape\" \"float radius\" 2\n"
    ));
    let w: Vec<&String> = b
        .warnings
        .iter()
        .filter(|w| w.contains("unsupported"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", b.warnings);
    assert!(
        w[0].contains("Accelerator") && w[0].contains("scene.pbrt:1"),
        "{}",
        w[0]
    );
    assert!(
        w[0].contains("\"float frobnicate\" of Shape \"sphere\" (scene.pbrt:4)"),
        "{}",
        w[0]
    );
    assert!(
        w[0].contains("Attribute \"shape\"") && w[0].contains("scene.pbrt:5"),
        "{}",
        w[0]
    );
}

#[test]
fn unknown_directives_are_errors_naming_the_expectation() {
    let (l, c, m) = err(&format!("{HEADER}  Shpe \"sphere\"\n"));
    assert_eq!((l, c), (3, 3));
    assert!(
        m.contains("unknown directive 'Shpe'") && m.contains("expected"),
        "{m}"
    );
    let (l, c, m) = err(&format!("{HEADER}\"sphere\"\n"));
    assert_eq!((l, c), (3, 1));
    assert!(m.contains("expected a directive"), "{m}");
    let (l, c, m) = err(&format!("{HEADER}Translate 1 2\n"));
    assert_eq!((l, c), (3, 1), "{m}");
    assert!(
        m.contains("expected a number, got the end of the file"),
        "{m}"
    );
    let (l, c, m) = err(&format!("{HEADER}Rotate 1 0 0 0\n"));
    assert_eq!((l, c), (3, 1));
    assert!(m.contains("axis"), "{m}");
}

#[test]
fn directives_in_the_wrong_block_are_errors() {
    let (l, _, m) = err(&format!("Shape \"sphere\"\n{HEADER}"));
    assert_eq!(l, 1);
    assert!(m.contains("only allowed after WorldBegin"), "{m}");
    let (l, _, m) = err(&format!("{HEADER}Film \"rgb\"\n"));
    assert_eq!(l, 3);
    assert!(m.contains("only allowed before WorldBegin"), "{m}");
    let (l, _, m) = err(&format!("{HEADER}WorldBegin\n"));
    assert_eq!(l, 3);
    assert!(m.contains("twice"), "{m}");
}

// ---------------------------------------------------------------- transforms and attributes

#[test]
fn transforms_compose_like_pbrt() {
    let light = |t: &str| {
        point_light(
            &world(&format!(
                "{t}\nLightSource \"point\" \"point3 from\" [ 1 0 0 ]\n"
            )),
            0,
        )
        .0
    };
    assert!(close(light("Translate 1 2 3"), Vec3::new(2.0, 2.0, 3.0)));
    // ctm = T · S: the scale applies first.
    assert!(close(
        light("Translate 1 2 3 Scale 2 2 2"),
        Vec3::new(3.0, 2.0, 3.0)
    ));
    assert!(close(
        light("Scale 2 2 2 Translate 1 2 3"),
        Vec3::new(4.0, 4.0, 6.0)
    ));
    assert!(close(light("Rotate 90 0 0 1"), Vec3::new(0.0, 1.0, 0.0)));
    assert!(close(
        light("Translate 5 5 5 Identity"),
        Vec3::new(1.0, 0.0, 0.0)
    ));
    // Column-major matrices: the translation is in the last four numbers.
    let m = "[ 1 0 0 0  0 1 0 0  0 0 1 0  0 0 7 1 ]";
    assert!(close(
        light(&format!("Translate 5 5 5 Transform {m}")),
        Vec3::new(1.0, 0.0, 7.0)
    ));
    assert!(close(
        light(&format!("Translate 5 0 0 ConcatTransform {m}")),
        Vec3::new(6.0, 0.0, 7.0)
    ));
    assert!(close(
        light(
            "Translate 0 3 0 CoordinateSystem \"up\" Identity Translate 9 9 9 CoordSysTransform \"up\""
        ),
        Vec3::new(1.0, 3.0, 0.0)
    ));
    // LookAt is the inverse of the camera frame: the eye maps to the origin.
    let p = point_light(
        &world("LookAt 0 0 5  0 0 0  0 1 0\nLightSource \"point\" \"point3 from\" [ 0 0 5 ]\n"),
        0,
    )
    .0;
    assert!(close(p, Vec3::ZERO), "{p}");
    let (l, c, m) = err(&format!("{HEADER}CoordSysTransform \"nowhere\"\n"));
    assert_eq!((l, c), (3, 19));
    assert!(m.contains("unknown coordinate system"), "{m}");
    let (_, _, m) = err(&format!("{HEADER}Transform [ 1 2 3 ]\n"));
    assert!(m.contains("expected a number"), "{m}");
}

#[test]
fn the_camera_coordinate_system_is_the_camera_frame() {
    let b = ok(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\nCoordSysTransform \"camera\"\nLightSource \"point\"\n",
    );
    assert!(close(point_light(&b, 0).0, Vec3::new(0.0, 0.0, 5.0)));
}

#[test]
fn attributes_save_and_restore_the_graphics_state() {
    let b = world(&format!(
        "AttributeBegin\nTranslate 0 0 1\nReverseOrientation\nMaterial \"dielectric\"\n{QUAD}\nAttributeEnd\n{QUAD}\nTransformBegin\nTranslate 0 0 2\nTransformEnd\n{QUAD}\n"
    ));
    assert_eq!(b.shape_count(), 3);
    let (m0, m1) = (mesh(&b, 0), mesh(&b, 1));
    assert_eq!(m0.positions[0], Vec3::new(0.0, 0.0, 1.0));
    assert_eq!(m1.positions[0], Vec3::ZERO);
    assert_eq!(mesh(&b, 2).positions[0], Vec3::ZERO);
    // ReverseOrientation swapped the winding of the first quad only.
    assert_eq!(m0.indices[0], [0, 2, 1]);
    assert_eq!(m1.indices[0], [0, 1, 2]);
    let mats = b.materials();
    assert!(matches!(
        mats[b.shapes()[0].material as usize],
        Material::Dielectric { .. }
    ));
    assert!(matches!(
        mats[b.shapes()[1].material as usize],
        Material::Diffuse { .. }
    ));
}

#[test]
fn unbalanced_attribute_blocks_are_errors() {
    let (l, c, m) = err(&format!(
        "{HEADER}AttributeBegin\nAttributeEnd\n  AttributeEnd\n"
    ));
    assert_eq!((l, c), (5, 3));
    assert!(m.contains("unbalanced AttributeEnd"), "{m}");
    let (l, c, m) = err(&format!("{HEADER}\n AttributeBegin\n"));
    assert_eq!((l, c), (4, 2));
    assert!(m.contains("without a matching AttributeEnd"), "{m}");
    let (l, _, m) = err(&format!("{HEADER}AttributeBegin\nTransformEnd\n"));
    assert_eq!(l, 4);
    assert!(m.contains("closes the AttributeBegin of line 3"), "{m}");
}

// ---------------------------------------------------------------- options block

#[test]
fn camera_fov_spans_the_shorter_axis_and_look_at_is_left_handed() {
    for (w, h) in [(200, 100), (100, 200)] {
        let b = ok(&format!(
            "LookAt 1 2 3  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\nFilm \"rgb\" \"integer xresolution\" {w} \"integer yresolution\" {h}\nWorldBegin\n"
        ));
        let c = b.camera().unwrap();
        assert_eq!(
            (c.width, c.height, c.fov_deg, c.fov_axis),
            (w, h, 30.0, FovAxis::Smaller)
        );
        let ext = c.screen_half_extent();
        let t = (15f32).to_radians().tan();
        assert!((ext.x.min(ext.y) - t).abs() < 1e-6, "{ext}");
    }
    let frame = |pre: &str| {
        ok(&format!(
            "{pre}LookAt 1 2 3  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n"
        ))
        .camera()
        .unwrap()
        .to_world
    };
    let look =
        crate::toml::look_at_transform(Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO, Vec3::Y).unwrap();
    // With the exporters' Scale -1 1 1 the frame is Mitsuba's look-at frame exactly.
    assert_eq!(frame("Scale -1 1 1\n"), look);
    // Without it the image is pbrt's: mirrored, camera x = −(up × dir).
    let plain = frame("");
    assert!(close(
        plain.matrix3.x_axis.into(),
        -Vec3::from(look.matrix3.x_axis)
    ));
    assert!(close(
        plain.matrix3.z_axis.into(),
        look.matrix3.z_axis.into()
    ));
    assert!(close(plain.translation.into(), look.translation.into()));
}

#[test]
fn camera_parameters_and_defaults() {
    let b = ok(
        "Camera \"perspective\" \"float lensradius\" 0.1 \"float focaldistance\" 4\nWorldBegin\n",
    );
    let c = b.camera().unwrap();
    assert_eq!((c.lens_radius, c.focus_distance), (0.1, 4.0));
    assert_eq!((c.width, c.height, c.fov_deg), (1280, 720, 90.0));
    // No Camera at all: pbrt's default camera.
    assert!(ok("WorldBegin\n").camera().is_some());
    let (l, c, m) = err("Camera \"orthographic\"\nWorldBegin\n");
    assert_eq!((l, c), (1, 8));
    assert!(m.contains("supported: perspective"), "{m}");
    let (l, c, m) = err("Camera \"perspective\" \"float screenwindow\" [ 0 1 0 1 ]\nWorldBegin\n");
    assert_eq!((l, c), (1, 22));
    assert!(m.contains("screenwindow"), "{m}");
    // The default window is fine.
    ok(
        "Camera \"perspective\" \"float screenwindow\" [ -1 1 -1 1 ]\nFilm \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 64\nWorldBegin\n",
    );
    let (_, _, m) = err("Camera \"perspective\" \"float frameaspectratio\" 2\nWorldBegin\n");
    assert!(m.contains("frameaspectratio"), "{m}");
    let (_, _, m) = err("Camera \"perspective\" \"float fov\" 180\nWorldBegin\n");
    assert!(m.contains("fov must be in (0, 180)"), "{m}");
    let (_, _, m) = err("Scale 2 2 2\nCamera \"perspective\"\nWorldBegin\n");
    assert!(m.contains("rigid"), "{m}");
}

#[test]
fn film_sampler_filter_and_integrator_suggest_settings() {
    let b = ok(
        "Film \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 48 \"string filename\" \"x.exr\"\nSampler \"zsobol\" \"integer pixelsamples\" 32\nPixelFilter \"box\"\nIntegrator \"bdpt\" \"integer maxdepth\" 3\nWorldBegin\n",
    );
    let c = b.camera().unwrap();
    assert_eq!((c.width, c.height), (64, 48));
    assert_eq!(b.settings.spp, Some(32));
    assert_eq!(b.settings.filter, FilterKind::Box);
    assert_eq!(b.settings.integrator.as_deref(), Some("lighttrace"));
    assert_eq!(b.settings.max_depth, Some(4));
    let w = warnings(&b);
    assert!(w.contains("Film filename \"x.exr\""), "{w}");
    assert!(w.contains("sampler \"zsobol\""), "{w}");
    assert!(w.contains("bdpt"), "{w}");
    // pbrt's defaults: gaussian σ 0.5 radius 1.5, volpath with maxdepth 5.
    let d = ok("WorldBegin\n");
    assert_eq!(
        d.settings.filter,
        FilterKind::Gaussian {
            stddev: 0.5,
            radius: 1.5
        }
    );
    assert_eq!(
        (d.settings.integrator.as_deref(), d.settings.max_depth),
        (Some("path"), Some(6))
    );
    assert_eq!(d.settings.spp, None);
    let g = ok(
        "PixelFilter \"gaussian\" \"float sigma\" 0.25 \"float xradius\" 1 \"float yradius\" 1\nIntegrator \"sppm\"\nSampler \"stratified\" \"integer xsamples\" 2 \"integer ysamples\" 3\nWorldBegin\n",
    );
    assert_eq!(
        g.settings.filter,
        FilterKind::Gaussian {
            stddev: 0.25,
            radius: 1.0
        }
    );
    assert_eq!(g.settings.integrator.as_deref(), Some("sppm"));
    assert_eq!(g.settings.spp, Some(6));
    for (i, want) in [
        ("path", "path"),
        ("volpath", "path"),
        ("lighttracer", "lighttrace"),
    ] {
        let b = ok(&format!("Integrator \"{i}\"\nWorldBegin\n"));
        assert_eq!(b.settings.integrator.as_deref(), Some(want));
    }
    let (l, c, m) =
        err("Film \"rgb\" \"integer xresolution\" 65536 \"integer yresolution\" 65536\n");
    assert_eq!((l, c), (1, 6));
    assert!(m.contains("too large"), "{m}");
    let (_, _, m) = err("Integrator \"path\" \"integer maxdepth\" -2\n");
    assert!(m.contains("maxdepth"), "{m}");
    let (_, _, m) = err("Sampler \"independent\" \"integer pixelsamples\" 0\n");
    assert!(m.contains("positive"), "{m}");
}

// ---------------------------------------------------------------- shapes

#[test]
fn triangle_and_bilinear_meshes() {
    let b = world(&format!(
        "{QUAD} \"normal N\" [ 0 0 1 0 0 1 0 0 1 0 0 1 ] \"point2 uv\" [ 0 0 1 0 1 1 0 1 ]\nShape \"bilinearmesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0  1 1 0 ]\n"
    ));
    let m = mesh(&b, 0);
    assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(m.normals.as_ref().unwrap().len(), 4);
    assert_eq!(m.uvs.as_ref().unwrap()[2].to_array(), [1.0, 1.0]);
    // p00 p10 p01 p11 → (p00, p10, p11), (p00, p11, p01), both facing +z like ∂p/∂u × ∂p/∂v.
    let q = mesh(&b, 1);
    assert_eq!(q.indices, vec![[0, 1, 3], [0, 3, 2]]);
    for t in &q.indices {
        let p = t.map(|k| q.positions[k as usize]);
        assert!((p[1] - p[0]).cross(p[2] - p[0]).z > 0.0);
    }
    // One triangle needs no indices.
    let t = world("Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ]\n");
    assert_eq!(mesh(&t, 0).indices, vec![[0, 1, 2]]);
}

#[test]
fn malformed_meshes_are_errors() {
    let cases = [
        (
            "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"integer indices\" [ 0 1 3 ]",
            "vertex index 3 out of range",
        ),
        (
            "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"integer indices\" [ 0 1 -1 ]",
            "vertex index -1 out of range",
        ),
        (
            "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 0 0 1 ]",
            "\"integer indices\" is required",
        ),
        (
            "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"integer indices\" [ 0 1 ]",
            "multiple of 3",
        ),
        (
            "Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ]",
            "needs \"point3 P\"",
        ),
        (
            "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"normal N\" [ 0 0 1 ]",
            "1 normals for 3 vertices",
        ),
        (
            "Shape \"bilinearmesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"integer indices\" [ 0 1 2 ]",
            "multiple of 4",
        ),
        (
            "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"float alpha\" 0.5",
            "alpha",
        ),
    ];
    for (shape, want) in cases {
        let (l, _, m) = err(&format!("{HEADER}{shape}\n"));
        assert_eq!(l, 3, "{shape}: {m}");
        assert!(m.contains(want), "{shape}: {m}");
    }
}

#[test]
fn spheres_and_disks() {
    let b = world(
        "Translate 1 2 3\nScale 2 2 2\nShape \"sphere\" \"float radius\" 0.5\nShape \"disk\" \"float radius\" 2 \"float height\" 1\nReverseOrientation\nShape \"disk\"\n",
    );
    match &b.shapes()[0].geometry {
        ShapeGeometry::Sphere(s) => {
            assert_eq!((s.center, s.radius), (Vec3::new(1.0, 2.0, 3.0), 1.0));
        }
        g => panic!("{g:?}"),
    }
    match &b.shapes()[1].geometry {
        ShapeGeometry::Disk(d) => {
            assert_eq!(
                (d.center, d.normal, d.radius),
                (Vec3::new(1.0, 2.0, 5.0), Vec3::Z, 4.0)
            );
        }
        g => panic!("{g:?}"),
    }
    match &b.shapes()[2].geometry {
        ShapeGeometry::Disk(d) => assert_eq!(d.normal, -Vec3::Z),
        g => panic!("{g:?}"),
    }
    for (shape, want) in [
        ("Shape \"sphere\" \"float zmax\" 0.5", "partial spheres"),
        ("Shape \"sphere\" \"float phimax\" 180", "partial spheres"),
        ("Shape \"disk\" \"float innerradius\" 0.5", "annuli"),
        ("Scale 1 2 1\nShape \"sphere\"", "uniform scale"),
        (
            "Shape \"sphere\" \"float radius\" -1",
            "radius must be positive",
        ),
        (
            "Shape \"cylinder\"",
            "unknown or unsupported shape type \"cylinder\"",
        ),
    ] {
        let (_, c, m) = err(&format!("{HEADER}{shape}\n"));
        assert!(m.contains(want), "{shape}: {m}");
        assert!(c >= 1);
    }
    // The column points at the type for unknown shapes.
    let (l, c, _) = err(&format!("{HEADER}Shape \"curve\"\n"));
    assert_eq!((l, c), (3, 7));
}

#[test]
fn plymesh_reads_and_triangulates_quads_relative_to_the_scene() {
    let d = temp_dir("ply");
    std::fs::create_dir_all(d.join("meshes")).unwrap();
    std::fs::write(
        d.join("meshes/q.ply"),
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n",
    )
    .unwrap();
    let scene = d.join("s.pbrt");
    let text = format!(
        "{HEADER}Translate 0 0 1\nShape \"plymesh\" \"string filename\" \"meshes/q.ply\"\n"
    );
    let b = parse_pbrt(&text, &scene).unwrap();
    let m = mesh(&b, 0);
    assert_eq!(m.indices.len(), 2);
    assert_eq!(m.positions[2], Vec3::new(1.0, 1.0, 1.0));
    let missing = format!("{HEADER}Shape \"plymesh\" \"string filename\" \"meshes/none.ply\"\n");
    match parse_pbrt(&missing, &scene) {
        Err(LoadError::Parse {
            line,
            column,
            message,
            ..
        }) => {
            assert_eq!((line, column), (3, 17), "{message}");
            assert!(message.contains("none.ply"), "{message}");
        }
        r => panic!("{:?}", r.err()),
    }
    // A directory is not a mesh.
    let dir = format!("{HEADER}Shape \"plymesh\" \"string filename\" \"meshes\"\n");
    let e = parse_pbrt(&dir, &scene).err().unwrap().to_string();
    assert!(e.contains("not a regular file"), "{e}");
    let _ = std::fs::remove_dir_all(&d);
}

// ---------------------------------------------------------------- materials and textures

fn material_of(body: &str) -> (Material, String) {
    let b = world(&format!("{body}\n{QUAD}\n"));
    let m = b.materials()[b.shapes()[0].material as usize].clone();
    (m, warnings(&b))
}

#[test]
fn diffuse_and_default_materials() {
    let (m, _) = material_of("Material \"diffuse\" \"rgb reflectance\" [ 0.2 0.3 0.4 ]");
    match m {
        Material::Diffuse {
            reflectance: Texture::Constant(s),
        } => {
            assert_eq!(s.to_rgb(), [0.2, 0.3, 0.4]);
        }
        m => panic!("{m:?}"),
    }
    let (m, _) = material_of("");
    match m {
        Material::Diffuse {
            reflectance: Texture::Constant(s),
        } => assert_eq!(s, Spectrum::splat(0.5)),
        m => panic!("{m:?}"),
    }
    let (m, w) = material_of("Material \"diffuse\" \"rgb reflectance\" [ 2 0.5 0.5 ]");
    assert!(matches!(m, Material::Diffuse { .. }));
    assert!(w.contains("clamped"), "{w}");
}

#[test]
fn dielectrics_map_named_glasses_to_dispersive_glass_and_roughness_to_alpha() {
    let (m, _) = material_of("Material \"dielectric\" \"float eta\" 1.33");
    assert!(matches!(m, Material::Dielectric { ior, dispersion: None, .. } if ior == 1.33));
    let (m, _) = material_of("Material \"dielectric\" \"spectrum eta\" \"glass-BK7\"");
    match m {
        Material::Dielectric {
            ior,
            dispersion: Some(d),
            ..
        } => {
            assert!((ior - 1.5168).abs() < 1e-3, "{ior}");
            assert!(d.ior(450.0) > d.ior(650.0));
        }
        m => panic!("{m:?}"),
    }
    for (g, nd) in [
        ("glass-BAF10", 1.6700),
        ("glass-F11", 1.7847),
        ("glass-LASF9", 1.8503),
        ("glass-FK51A", 1.4866),
        ("glass-F5", 1.6727),
        ("glass-F10", 1.7283),
        ("glass-F2", 1.6200),
        ("fused silica", 1.4585),
    ] {
        let (m, _) = material_of(&format!("Material \"dielectric\" \"spectrum eta\" \"{g}\""));
        match m {
            Material::Dielectric {
                ior,
                dispersion: Some(_),
                ..
            } => assert!((ior - nd).abs() < 2e-3, "{g}: {ior}"),
            m => panic!("{g}: {m:?}"),
        }
    }
    let (m, _) = material_of("Material \"dielectric\" \"float roughness\" 0.04");
    assert!(matches!(m, Material::RoughDielectric { alpha, .. } if (alpha - 0.2).abs() < 1e-6));
    let (m, _) = material_of(
        "Material \"dielectric\" \"float roughness\" 0.04 \"bool remaproughness\" false",
    );
    assert!(matches!(m, Material::RoughDielectric { alpha, .. } if alpha == 0.04));
    let (m, w) =
        material_of("Material \"dielectric\" \"float uroughness\" 0.01 \"float vroughness\" 0.04");
    assert!(
        matches!(m, Material::RoughDielectric { alpha, .. } if (alpha - (0.1f32 * 0.2).sqrt()).abs() < 1e-6)
    );
    assert!(w.contains("anisotropic"), "{w}");
    let (m, w) = material_of("Material \"thindielectric\" \"float eta\" 1.5");
    assert!(matches!(m, Material::Dielectric { ior, .. } if ior == 1.0));
    assert!(w.contains("thindielectric"), "{w}");
    let (l, c, m) = err(&format!(
        "{HEADER}Material \"dielectric\" \"spectrum eta\" \"glass-XYZ\"\n"
    ));
    assert_eq!((l, c), (3, 23));
    assert!(m.contains("unknown glass \"glass-XYZ\""), "{m}");
}

#[test]
fn conductors_map_named_metals_and_reflectance() {
    let (m, _) = material_of(
        "Material \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"",
    );
    let (eta, k) = caustica_scene::material::conductor_preset("Au").unwrap();
    assert!(matches!(m, Material::Conductor { eta: e, k: kk, .. } if e == eta && kk == k));
    // pbrt-v4's default conductor is copper.
    let (m, _) = material_of("Material \"conductor\" \"float roughness\" 0.01");
    let (eta, _) = caustica_scene::material::conductor_preset("Cu").unwrap();
    assert!(
        matches!(m, Material::RoughConductor { eta: e, alpha, .. } if e == eta && (alpha - 0.1).abs() < 1e-6)
    );
    let (m, _) = material_of("Material \"conductor\" \"rgb reflectance\" [ 1 1 1 ]");
    assert!(matches!(m, Material::Mirror { reflectance } if reflectance == Spectrum::ONE));
    let (m, _) = material_of("Material \"conductor\" \"rgb reflectance\" [ 0.64 0.64 0.64 ]");
    match m {
        // k = 2 √r / √(1 − r) = 2 · 0.8 / 0.6.
        Material::Conductor { eta, k, .. } => {
            assert_eq!(eta, Spectrum::ONE);
            assert!((k.to_rgb()[0] - 8.0 / 3.0).abs() < 1e-5);
        }
        m => panic!("{m:?}"),
    }
    let (_, _, m) = err(&format!(
        "{HEADER}Material \"conductor\" \"spectrum eta\" \"metal-TiO2-eta\"\n"
    ));
    assert!(
        m.contains("unsupported conductor spectrum \"metal-TiO2-eta\""),
        "{m}"
    );
}

#[test]
fn coated_diffuse_is_approximated_and_unknown_materials_are_errors() {
    let (m, w) = material_of("Material \"coateddiffuse\" \"rgb reflectance\" [ 0.5 0.5 0.5 ]");
    match m {
        Material::Phong {
            specular, exponent, ..
        } => {
            assert!((specular.to_rgb()[0] - 0.04).abs() < 1e-6);
            assert_eq!(exponent, 1000.0);
        }
        m => panic!("{m:?}"),
    }
    assert!(w.contains("coateddiffuse rendered as Phong"), "{w}");
    let (m, _) = material_of("Material \"interface\"");
    assert!(matches!(m, Material::Null));
    let (l, c, m) = err(&format!("{HEADER}Material \"hair\"\n"));
    assert_eq!((l, c), (3, 10));
    assert!(m.contains("\"hair\" is not supported"), "{m}");
    let (_, _, m) = err(&format!("{HEADER}Material \"velvet\"\n"));
    assert!(m.contains("unknown material type \"velvet\""), "{m}");
}

#[test]
fn named_materials() {
    let b = world(&format!(
        "MakeNamedMaterial \"gold\" \"string type\" \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\"\nMakeNamedMaterial \"white\" \"string type\" \"diffuse\"\nNamedMaterial \"gold\"\n{QUAD}\nNamedMaterial \"white\"\n{QUAD}\nNamedMaterial \"gold\"\n{QUAD}\n"
    ));
    let idx: Vec<u32> = b.shapes().iter().map(|s| s.material).collect();
    assert_eq!(idx[0], idx[2]);
    assert_ne!(idx[0], idx[1]);
    assert_eq!(b.material_names()[idx[0] as usize], "gold");
    assert_eq!(b.materials().len(), 2);
    let (l, c, m) = err(&format!("{HEADER}NamedMaterial \"nope\"\n{QUAD}\n"));
    assert_eq!((l, c), (3, 15));
    assert!(m.contains("\"nope\" was not defined"), "{m}");
    let (_, _, m) = err(&format!("{HEADER}MakeNamedMaterial \"a\"\n"));
    assert!(m.contains("needs a \"string type\""), "{m}");
    let (_, _, m) = err(&format!(
        "{HEADER}MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\nMakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
    ));
    assert!(m.contains("defined twice"), "{m}");
}

#[test]
fn textures() {
    let (m, _) = material_of(
        "Texture \"c\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [ 1 0 0 ] \"float tex2\" 0.25 \"float uscale\" 4 \"float vscale\" 4\nMaterial \"diffuse\" \"texture reflectance\" \"c\"",
    );
    match m {
        Material::Diffuse {
            reflectance: Texture::Checkerboard { a, b, scale },
        } => {
            assert_eq!(
                (a.to_rgb(), b, scale),
                ([1.0, 0.0, 0.0], Spectrum::splat(0.25), 4.0)
            );
        }
        m => panic!("{m:?}"),
    }
    let (m, _) = material_of(
        "Texture \"k\" \"spectrum\" \"constant\" \"rgb value\" [ 0.1 0.2 0.3 ]\nMaterial \"diffuse\" \"texture reflectance\" \"k\"",
    );
    assert!(
        matches!(m, Material::Diffuse { reflectance: Texture::Constant(s) } if s.to_rgb() == [0.1, 0.2, 0.3])
    );
    let (m, _) = material_of(
        "Texture \"r\" \"float\" \"constant\" \"float value\" 0.09\nMaterial \"dielectric\" \"texture roughness\" \"r\"",
    );
    assert!(matches!(m, Material::RoughDielectric { alpha, .. } if (alpha - 0.3).abs() < 1e-6));
    let (l, c, m) = err(&format!(
        "{HEADER}Material \"diffuse\" \"texture reflectance\" \"none\"\n"
    ));
    assert_eq!((l, c), (3, 20));
    assert!(m.contains("unknown texture \"none\""), "{m}");
    let (l, c, m) = err(&format!(
        "{HEADER}Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"missing.png\"\n"
    ));
    assert_eq!((l, c), (3, 35));
    assert!(m.contains("missing.png"), "{m}");
    let (_, _, m) = err(&format!("{HEADER}Texture \"t\" \"spectrum\" \"marble\"\n"));
    assert!(m.contains("unsupported texture type \"marble\""), "{m}");
    let (_, _, m) = err(&format!("{HEADER}Texture \"t\" \"colour\" \"constant\"\n"));
    assert!(m.contains("unknown texture class"), "{m}");
}

#[test]
fn imagemap_textures_load_relative_to_the_scene() {
    let d = temp_dir("tex");
    let mut img = caustica_core::image_io::Image::new(2, 2);
    img.data = vec![[0.5, 0.5, 0.5]; 4];
    img.write(&d.join("t.pfm")).unwrap();
    let text = format!(
        "{HEADER}Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"t.pfm\" \"float scale\" 0.5\nMaterial \"diffuse\" \"texture reflectance\" \"t\"\n{QUAD}\n"
    );
    let b = parse_pbrt(&text, &d.join("s.pbrt")).unwrap();
    match &b.materials()[0] {
        Material::Diffuse {
            reflectance: Texture::Image(i),
        } => assert_eq!(i.image.data[0], [0.25; 3]),
        m => panic!("{m:?}"),
    }
    let _ = std::fs::remove_dir_all(&d);
}

// ---------------------------------------------------------------- lights

#[test]
fn point_and_spot_lights_with_scale_and_power() {
    let b = world(
        "Translate 0 1 0\nLightSource \"point\" \"rgb I\" [ 1 2 3 ] \"float scale\" 2 \"point3 from\" [ 1 0 0 ]\nLightSource \"point\" \"float power\" 100\n",
    );
    let (p, i) = point_light(&b, 0);
    assert_eq!((p, i.to_rgb()), (Vec3::new(1.0, 1.0, 0.0), [2.0, 4.0, 6.0]));
    let (_, i) = point_light(&b, 1);
    assert!((i.to_rgb()[1] - 100.0 / (4.0 * std::f32::consts::PI)).abs() < 1e-4);
    let b = world(
        "LightSource \"spot\" \"rgb I\" [ 5 5 5 ] \"point3 from\" [ 0 2 0 ] \"point3 to\" [ 0 0 0 ] \"float coneangle\" 20 \"float conedeltaangle\" 4\n",
    );
    match &b.lights()[0] {
        Light::Spot(s) => {
            assert_eq!(s.position, Vec3::new(0.0, 2.0, 0.0));
            assert!(close(s.frame.n, -Vec3::Y));
            assert!((s.cutoff_angle - 20f32.to_radians()).abs() < 1e-6);
            assert!((s.beam_width - 16f32.to_radians()).abs() < 1e-6);
            assert_eq!(s.intensity, Spectrum::splat(5.0));
        }
        l => panic!("{l:?}"),
    }
    assert!(warnings(&b).contains("spot falloff"));
    let (_, _, m) = err(&format!(
        "{HEADER}LightSource \"spot\" \"float coneangle\" 10 \"float conedeltaangle\" 20\n"
    ));
    assert!(m.contains("conedeltaangle"), "{m}");
}

#[test]
fn distant_infinite_and_named_spectra() {
    let b = world(
        "LightSource \"distant\" \"point3 from\" [ 0 0 0 ] \"point3 to\" [ 0 -2 0 ] \"rgb L\" [ 0.5 0.5 0.5 ] \"float illuminance\" 4\nLightSource \"infinite\" \"rgb L\" [ 0.1 0.2 0.3 ]\nLightSource \"point\" \"blackbody I\" 3000\n",
    );
    match &b.lights()[0] {
        Light::Directional(d) => {
            assert_eq!(d.direction, -Vec3::Y);
            assert_eq!(d.irradiance, Spectrum::splat(2.0));
        }
        l => panic!("{l:?}"),
    }
    match &b.lights()[1] {
        Light::Environment(e) => assert_eq!(e.radiance.to_rgb(), [0.1, 0.2, 0.3]),
        l => panic!("{l:?}"),
    }
    // A blackbody is normalised to luminance 1, as pbrt normalises light spectra.
    let (_, i) = point_light(&b, 2);
    assert_eq!(i, NamedSpectrum::Blackbody(3000.0).rgb());
    let (l, c, m) = err(&format!(
        "{HEADER}LightSource \"infinite\" \"string filename\" \"sky.exr\"\n"
    ));
    assert_eq!((l, c), (3, 24));
    assert!(m.contains("environment maps are not supported"), "{m}");
    let (l, c, m) = err(&format!("{HEADER}LightSource \"laser\"\n"));
    assert_eq!((l, c), (3, 13));
    assert!(m.contains("unknown light type \"laser\""), "{m}");
}

#[test]
fn area_lights_emit_from_the_shapes_in_their_attribute_block() {
    let b = world(&format!(
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 2 3 4 ] \"float scale\" 0.5\n{QUAD}\nAttributeEnd\n{QUAD}\nAttributeBegin\nAreaLightSource \"diffuse\" \"blackbody L\" 5000 \"float power\" 10\n{QUAD}\nAttributeEnd\n"
    ));
    assert_eq!(b.lights().len(), 2);
    match &b.lights()[0] {
        Light::Area(a) => assert_eq!(a.radiance.to_rgb(), [1.0, 1.5, 2.0]),
        l => panic!("{l:?}"),
    }
    match &b.lights()[1] {
        // power / (π · area), area 1.
        Light::Area(a) => {
            let want = NamedSpectrum::Blackbody(5000.0).rgb() * (10.0 / std::f32::consts::PI);
            assert!((a.radiance.to_rgb()[1] - want.to_rgb()[1]).abs() < 1e-4);
        }
        l => panic!("{l:?}"),
    }
    let _ = EmissionSpectrum::named(NamedSpectrum::D65);
    let (l, c, m) = err(&format!(
        "{HEADER}AreaLightSource \"diffuse\" \"bool twosided\" true\n"
    ));
    assert_eq!((l, c), (3, 27));
    assert!(m.contains("twosided"), "{m}");
    let (_, _, m) = err(&format!("{HEADER}AreaLightSource \"spherical\"\n"));
    assert!(m.contains("unknown area light type"), "{m}");
}

// ---------------------------------------------------------------- objects, includes, media

#[test]
fn object_instances_are_expanded() {
    let b = world(&format!(
        "ObjectBegin \"q\"\n{QUAD}\nObjectEnd\nTranslate 0 0 1\nObjectInstance \"q\"\nTranslate 0 0 1\nObjectInstance \"q\"\n"
    ));
    assert_eq!(b.shape_count(), 2);
    assert_eq!(mesh(&b, 0).positions[0], Vec3::new(0.0, 0.0, 1.0));
    assert_eq!(mesh(&b, 1).positions[0], Vec3::new(0.0, 0.0, 2.0));
    let (l, c, m) = err(&format!("{HEADER}ObjectInstance \"ghost\"\n"));
    assert_eq!((l, c), (3, 16));
    assert!(m.contains("unknown object \"ghost\""), "{m}");
    let (l, _, m) = err(&format!("{HEADER}ObjectBegin \"a\"\nObjectBegin \"b\"\n"));
    assert_eq!(l, 4);
    assert!(m.contains("cannot nest"), "{m}");
    let (l, _, m) = err(&format!("{HEADER}ObjectEnd\n"));
    assert_eq!(l, 3);
    assert!(m.contains("unbalanced ObjectEnd"), "{m}");
    let (l, _, m) = err(&format!("{HEADER}ObjectBegin \"a\"\n"));
    assert_eq!(l, 3);
    assert!(
        m.contains("without a matching ObjectEnd") || m.contains("AttributeEnd"),
        "{m}"
    );
    let (_, _, m) = err(&format!(
        "{HEADER}ObjectBegin \"a\"\nAreaLightSource \"diffuse\"\n{QUAD}\nObjectEnd\n"
    ));
    assert!(m.contains("area lights inside object definitions"), "{m}");
}

#[test]
fn includes_resolve_relative_to_the_including_file_and_cycles_are_errors() {
    let d = temp_dir("inc");
    std::fs::create_dir_all(d.join("sub")).unwrap();
    std::fs::write(
        d.join("sub/geo.pbrt"),
        format!("Include \"more.pbrt\"\n{QUAD}\n"),
    )
    .unwrap();
    std::fs::write(d.join("sub/more.pbrt"), "Translate 0 0 3\n").unwrap();
    let main = d.join("main.pbrt");
    let b = parse_pbrt(&format!("{HEADER}Import \"sub/geo.pbrt\"\n"), &main).unwrap();
    // The included file's transform stays in effect (Include is textual).
    assert_eq!(mesh(&b, 0).positions[0], Vec3::new(0.0, 0.0, 3.0));
    // A cycle is an error at the directive that closes it: `main` names `sub/NAME.pbrt` with
    // `directive`, whose `body` includes `main` back at `at` (line, column).
    let cycle = |main: &str, name: &str, directive: &str, body: &str, at: (usize, usize)| {
        std::fs::write(d.join(format!("sub/{name}.pbrt")), body).unwrap();
        let main = d.join(main);
        std::fs::write(&main, format!("{HEADER}{directive} \"sub/{name}.pbrt\"\n")).unwrap();
        match super::load_pbrt(&main) {
            Err(LoadError::Parse {
                path,
                line,
                column,
                message,
            }) => {
                assert!(
                    path.ends_with(format!("sub/{name}.pbrt")),
                    "{}",
                    path.display()
                );
                assert_eq!((line, column), at);
                assert!(message.contains("cyclic include"), "{message}");
            }
            r => panic!("{:?}", r.err()),
        }
    };
    cycle(
        "main.pbrt",
        "loop",
        "Include",
        "\n  Include \"../main.pbrt\"\n",
        (2, 11),
    );
    // `Import` is read as `Include`: a cycle through it is the same error.
    cycle(
        "main2.pbrt",
        "loop2",
        "Import",
        "Import \"../main2.pbrt\"\n",
        (1, 8),
    );
    let (l, c, m) = err(&format!("{HEADER}Include \"missing.pbrt\"\n"));
    assert_eq!((l, c), (3, 9));
    assert!(m.contains("missing.pbrt"), "{m}");
    // Errors inside an included file name that file.
    std::fs::write(d.join("bad.pbrt"), "\nShape \"torus\"\n").unwrap();
    let e = parse_pbrt(&format!("{HEADER}Include \"bad.pbrt\"\n"), &main)
        .err()
        .unwrap();
    assert!(e.to_string().contains("bad.pbrt:2:7"), "{e}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn media_are_errors_and_empty_medium_interfaces_are_not() {
    let (l, c, m) = err("MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\nWorldBegin\n");
    assert_eq!((l, c), (1, 1));
    assert!(m.contains("media"), "{m}");
    world("MediumInterface \"\" \"\"\n");
    let (l, c, m) = err(&format!("{HEADER}MediumInterface \"fog\" \"\"\n"));
    assert_eq!((l, c), (3, 17));
    assert!(m.contains("not supported"), "{m}");
    let (_, _, m) = err("ColorSpace \"aces2065-1\"\n");
    assert!(m.contains("ColorSpace"), "{m}");
}

#[test]
fn defines_on_pbrt_scenes_are_errors() {
    let e = crate::parse_scene_file_with_defines(
        Path::new("/nonexistent-caustica-test/x.pbrt"),
        &[("spp".into(), "4".into())],
    )
    .err()
    .unwrap();
    assert!(matches!(e, LoadError::UnknownParameter { .. }), "{e}");
    let e = crate::parse_scene_file(Path::new("/nonexistent-caustica-test/x.pbrt"))
        .err()
        .unwrap();
    assert!(matches!(e, LoadError::File { .. }), "{e}");
}

#[test]
fn includes_are_bounded_in_number_and_lights_must_stay_finite() {
    let d = temp_dir("fan");
    // Each file includes the next twice: 2^14 includes without a cycle.
    for k in 0..14 {
        std::fs::write(
            d.join(format!("f{k}.pbrt")),
            format!("Include \"f{0}.pbrt\"\nInclude \"f{0}.pbrt\"\n", k + 1),
        )
        .unwrap();
    }
    std::fs::write(d.join("f14.pbrt"), "Translate 0 0 0\n").unwrap();
    let e = parse_pbrt(
        &format!("{HEADER}Include \"f0.pbrt\"\n"),
        &d.join("main.pbrt"),
    )
    .err()
    .unwrap();
    assert!(e.to_string().contains("more than 4096 includes"), "{e}");
    let _ = std::fs::remove_dir_all(&d);
    let (l, c, m) = err(&format!(
        "{HEADER}LightSource \"point\" \"float power\" 3e38 \"float scale\" 1e10\n"
    ));
    assert_eq!((l, c), (3, 13));
    assert!(m.contains("not finite"), "{m}");
}

#[test]
fn many_parameters_parse_in_linear_time() {
    let params: String = (0..20_000).map(|k| format!("\"float p{k}\" 1 ")).collect();
    let t = std::time::Instant::now();
    let b = world(&format!("Shape \"sphere\" {params}\n"));
    assert!(t.elapsed().as_secs_f64() < 5.0);
    assert!(warnings(&b).contains("\"float p19999\""));
}

#[test]
fn emitting_meshes_face_their_vertex_normals_like_pbrt() {
    // Winding faces +z, the normals −z: pbrt emits toward the normals.
    let tri = "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"normal N\" [ 0 0 -1 0 0 -1 0 0 -1 ]";
    let b = world(&format!(
        "AttributeBegin\nAreaLightSource \"diffuse\"\n{tri}\nAttributeEnd\n{tri}\n"
    ));
    assert_eq!(mesh(&b, 0).indices[0], [0, 2, 1], "the emitter is rewound");
    assert_eq!(
        mesh(&b, 1).indices[0],
        [0, 1, 2],
        "other meshes keep their winding"
    );
}
