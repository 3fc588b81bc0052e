use super::parse_toml_scene;
use super::position::line_column;
use crate::error::LoadError;
use caustica_core::Vec3;
use caustica_scene::camera::FovAxis;
use caustica_scene::light::Light;
use caustica_scene::material::{Material, conductor_preset};
use caustica_scene::scene::{FilterKind, SceneBuilder};
use caustica_scene::shape::ShapeGeometry;
use caustica_scene::texture::Texture;
use std::path::{Path, PathBuf};

fn parse(text: &str) -> Result<SceneBuilder, LoadError> {
    parse_toml_scene(text, Path::new("/virtual/dir/test.toml"))
}

const CAMERA: &str =
    "[camera]\neye = [0, 0, 4.1]\ntarget = [0, 0, 0]\nfov = 39.3077\nwidth = 256\nheight = 256\n";

/// Asserts a Parse error at `line` whose message contains every word of `words`.
#[track_caller]
fn expect_parse_error(text: &str, line: usize, words: &[&str]) {
    match parse(text) {
        Err(LoadError::Parse {
            path,
            line: l,
            message,
            ..
        }) => {
            assert_eq!(path, Path::new("/virtual/dir/test.toml"));
            assert_eq!(l, line, "wrong line for error '{message}'");
            for w in words {
                assert!(message.contains(w), "'{message}' lacks '{w}'");
            }
        }
        Err(e) => panic!("expected a parse error at line {line}, got {e}"),
        Ok(_) => panic!("expected a parse error at line {line}, got a scene"),
    }
}

#[test]
fn line_column_is_one_based() {
    assert_eq!(line_column("ab\ncd\n", 0), (1, 1));
    assert_eq!(line_column("ab\ncd\n", 4), (2, 2));
    assert_eq!(line_column("é\nx", 3), (2, 1));
}

#[test]
fn syntax_error_reports_the_right_line() {
    // Missing closing bracket of a table header on line 8.
    let text = format!("{CAMERA}\n[render\nspp = 4\n");
    expect_parse_error(&text, 8, &[]);
    // Missing closing bracket of an array on line 2: arrays may span lines, so the error is
    // found at the first token that cannot continue it, on line 3.
    expect_parse_error(
        "[camera]\neye = [0, 0, 4.1\ntarget = [0, 0, 0]\n",
        3,
        &["expected"],
    );
    // A string inside a number array, on line 3.
    expect_parse_error("[camera]\nfov = 30\neye = [0, \"x\", 4]\n", 3, &["eye"]);
}

#[test]
fn type_errors_name_the_field_and_line() {
    let text =
        "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov = \"wide\"\nwidth = 4\nheight = 4\n";
    expect_parse_error(text, 4, &["fov"]);
    let text = format!("{CAMERA}\n[[material]]\nname = \"m\"\ntype = \"velvet\"\n");
    expect_parse_error(&text, 10, &["velvet"]);
    let text = format!("{CAMERA}\n[[material]]\nname = \"m\"\ntype = \"diffuse\"\ncolour = 0.5\n");
    expect_parse_error(&text, 11, &["colour"]);
    let text = format!("{CAMERA}\n[[light]]\ntype = \"laser\"\n");
    expect_parse_error(&text, 9, &["laser"]);
}

#[test]
fn invalid_values_are_rejected_with_field_names() {
    expect_parse_error(&format!("{CAMERA}[render]\nspp = 0\n"), 8, &["spp"]);
    expect_parse_error(&format!("{CAMERA}[render]\nspp = -3\n"), 8, &["spp"]);
    let m = "[[material]]\nname = \"g\"\ntype = \"dielectric\"\n";
    expect_parse_error(&format!("{CAMERA}{m}ior = 0\n"), 10, &["ior", "positive"]);
    expect_parse_error(&format!("{CAMERA}{m}ior = -1.5\n"), 10, &["ior"]);
    expect_parse_error(&format!("{CAMERA}{m}ior = nan\n"), 10, &["ior"]);
    expect_parse_error(
        &format!("{CAMERA}{m}absorption = [0, -1, 0]\n"),
        10,
        &["absorption"],
    );
    let d = "[[material]]\nname = \"d\"\ntype = \"diffuse\"\n";
    let sphere = "[[shape]]\ntype = \"sphere\"\nmaterial = \"d\"\n";
    expect_parse_error(
        &format!("{CAMERA}{d}{sphere}radius = -0.5\n"),
        13,
        &["radius", "positive"],
    );
    expect_parse_error(
        &format!("{CAMERA}{d}{sphere}center = [0, nan, 0]\n"),
        13,
        &["center", "finite"],
    );
    expect_parse_error(
        &format!("{CAMERA}{d}{sphere}radius = 1\nmaterial2 = 1\n"),
        14,
        &["material2"],
    );
    expect_parse_error(
        &format!("{CAMERA}{d}{sphere}rotate = {{ axis = [0, 1], angle = 3 }}\n"),
        13,
        &["axis", "vector"],
    );
    // Cross-field problems are reported at their table.
    expect_parse_error(&format!("{CAMERA}{d}ior = 1.5\n"), 7, &["ior", "diffuse"]);
    expect_parse_error(
        &format!("{CAMERA}{d}reflectance = 1.5\n"),
        7,
        &["reflectance"],
    );
    expect_parse_error(
        &format!("{CAMERA}{d}{sphere}radius = 1\nscale = [1, 2, 1]\n"),
        10,
        &["uniform"],
    );
    expect_parse_error(
        &format!("{CAMERA}[[shape]]\ntype = \"cube\"\nmaterial = \"nope\"\n"),
        7,
        &["nope"],
    );
    let cam = "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 4]\nfov = 40\nwidth = 4\nheight = 4\n";
    expect_parse_error(cam, 1, &["eye"]);
    let cam = "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov = 200\nwidth = 4\nheight = 4\n";
    expect_parse_error(cam, 1, &["fov"]);
    let cam = "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov = 40\nwidth = 0\nheight = 4\n";
    expect_parse_error(cam, 5, &["width"]);
    let spot = "[[light]]\ntype = \"spot\"\nintensity = 1\ndirection = [0, -1, 0]\n";
    expect_parse_error(
        &format!("{CAMERA}{spot}cutoff_angle = 10\nbeam_width = 20\n"),
        7,
        &["beam_width"],
    );
}

#[test]
fn absurd_camera_sizes_are_errors() {
    // Each side is a valid count, but the film (about 50 bytes per pixel) would need ~200 GB and
    // abort when allocated; the TOML loader shares the Mitsuba loader's cap.
    let cam = |w: u32, h: u32| {
        format!(
            "[camera]\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov = 40\nwidth = {w}\nheight = {h}\n"
        )
    };
    expect_parse_error(
        &cam(65536, 65536),
        1,
        &["camera", "65536x65536", "too large", "268435456"],
    );
    expect_parse_error(&cam(1 << 28, 2), 1, &["too large"]);
    let b = parse(&cam(16384, 16384)).unwrap();
    let c = b.camera().unwrap();
    assert_eq!((c.width, c.height), (16384, 16384));
    let b = parse(&cam(1 << 28, 1)).unwrap();
    assert_eq!(b.camera().unwrap().width, 1 << 28);
}

#[cfg(unix)]
#[test]
fn devices_and_directories_are_not_read() {
    // A directory is not a mesh or an image; reading /dev/zero would never end.
    let dir = std::env::temp_dir();
    let d = "[[material]]\nname = \"d\"\ntype = \"diffuse\"\n";
    let shape = |ty: &str, file: &str| {
        format!("{CAMERA}{d}[[shape]]\ntype = \"{ty}\"\nmaterial = \"d\"\nfilename = \"{file}\"\n")
    };
    let dir_name = dir.display().to_string();
    expect_parse_error(
        &shape("obj", &dir_name),
        10,
        &[&dir_name, "not a regular file"],
    );
    expect_parse_error(
        &shape("ply", "/dev/zero"),
        10,
        &["/dev/zero", "not a regular file"],
    );
    expect_parse_error(&shape("obj", "/dev/zero"), 10, &["not a regular file"]);
    let tex = format!(
        "{CAMERA}[[material]]\nname = \"t\"\ntype = \"diffuse\"\nreflectance = {{ texture = \"{dir_name}\" }}\n"
    );
    expect_parse_error(&tex, 7, &["not a regular file"]);
    // A missing file is still a file error naming the path.
    match parse(&shape("ply", "missing.ply")) {
        Err(LoadError::File { path, .. }) => assert!(path.ends_with("dir/missing.ply")),
        r => panic!("expected a file error, got {:?}", r.err()),
    }
}

#[test]
fn missing_mesh_file_names_the_resolved_path() {
    let text = format!(
        "{CAMERA}[[material]]\nname = \"d\"\ntype = \"diffuse\"\n\
         [[shape]]\ntype = \"obj\"\nmaterial = \"d\"\nfilename = \"meshes/missing.obj\"\n"
    );
    match parse(&text) {
        Err(e @ LoadError::File { .. }) => {
            assert!(
                e.to_string().contains("/virtual/dir/meshes/missing.obj"),
                "{e}"
            )
        }
        Err(e) => panic!("expected a file error, got {e}"),
        Ok(_) => panic!("expected a file error"),
    }
}

#[test]
fn camera_follows_the_mitsuba_look_at_convention() {
    let text = "[camera]\neye = [1, 2, 3]\ntarget = [1, 2, -1]\nup = [0, 1, 0]\nfov = 30\n\
                fov_axis = \"smaller\"\nwidth = 64\nheight = 32\nlens_radius = 0.1\n\
                [render]\nspp = 7\nmax_depth = 5\n[film]\nfilter = \"gaussian\"\nstddev = 0.4\n";
    let b = parse(text).unwrap();
    let c = b.camera().unwrap();
    // Looking down −z: camera +x (image left) is world −x, +y is world +y, +z is world −z.
    let m = c.to_world;
    assert!(Vec3::from(m.matrix3.x_axis).abs_diff_eq(-Vec3::X, 1e-6));
    assert!(Vec3::from(m.matrix3.y_axis).abs_diff_eq(Vec3::Y, 1e-6));
    assert!(Vec3::from(m.matrix3.z_axis).abs_diff_eq(-Vec3::Z, 1e-6));
    assert_eq!(c.position(), Vec3::new(1.0, 2.0, 3.0));
    assert_eq!((c.width, c.height, c.fov_deg), (64, 32, 30.0));
    assert_eq!(c.fov_axis, FovAxis::Smaller);
    assert_eq!(c.lens_radius, 0.1);
    assert_eq!(c.focus_distance, 4.0);
    assert_eq!(b.settings.spp, Some(7));
    assert_eq!(b.settings.max_depth, Some(5));
    assert_eq!(
        b.settings.filter,
        FilterKind::Gaussian {
            stddev: 0.4,
            radius: 2.0
        }
    );
    assert_eq!(b.name, "test");
    // A rigid to_world is taken as is; a scaled one is rejected.
    let rows = "[[0, 0, 1, 5], [0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1]]";
    let text = format!("[camera]\nto_world = {rows}\nfov = 30\nwidth = 8\nheight = 8\n");
    let b = parse(&text).unwrap();
    let m = b.camera().unwrap().to_world;
    assert_eq!(Vec3::from(m.matrix3.z_axis), Vec3::X);
    assert_eq!(Vec3::from(m.translation), Vec3::new(5.0, 0.0, 0.0));
    let text = "[camera]\nto_world = [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n\
                fov = 30\nwidth = 8\nheight = 8\n";
    expect_parse_error(text, 1, &["rigid"]);
}

#[test]
fn lights_parse_without_materials() {
    let text = format!(
        "{CAMERA}[[light]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = [1, 2, 3]\n\
         [[light]]\ntype = \"spot\"\nposition = [0, 2, 0]\ntarget = [0, 0, 0]\nintensity = 5\n\
         [[light]]\ntype = \"directional\"\ndirection = [0, -1, 0]\nirradiance = 2\n\
         [[light]]\ntype = \"beam\"\ncenter = [0, 1, 0]\ndirection = [1, 0, 0]\nradius = 0.1\nirradiance = 3\n\
         [[light]]\ntype = \"environment\"\nradiance = 0.5\n"
    );
    let b = parse(&text).unwrap();
    let kinds: Vec<_> = b.lights().iter().map(std::mem::discriminant).collect();
    assert_eq!(kinds.len(), 5);
    assert!(matches!(b.lights()[0], Light::Point(_)));
    assert!(matches!(b.lights()[1], Light::Spot(_)));
    assert!(matches!(b.lights()[2], Light::Directional(_)));
    assert!(matches!(b.lights()[3], Light::Beam(_)));
    assert!(matches!(b.lights()[4], Light::Environment(_)));
    // Missing required parameters.
    expect_parse_error(
        &format!("{CAMERA}[[light]]\ntype = \"point\"\n"),
        7,
        &["intensity"],
    );
    expect_parse_error(
        &format!("{CAMERA}[[light]]\ntype = \"beam\"\ndirection = [1, 0, 0]\nirradiance = 1\n"),
        7,
        &["radius"],
    );
}

// The tests below add materials and emitting shapes, so they need `Material::validate`,
// `conductor_preset` and `AreaLight::new`, which other helpers implement in parallel.

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

#[test]
fn feature_tour_parses_every_key() {
    let b = crate::parse_scene_file(&scenes_dir().join("feature-tour.toml")).unwrap();
    assert_eq!(b.name, "feature-tour");
    assert_eq!(b.materials().len(), 7);
    assert_eq!(b.shape_count(), 7);
    assert_eq!(b.lights().len(), 6); // five explicit plus the emitting disk
    assert_eq!(b.settings.filter, FilterKind::Box);
    assert_eq!((b.settings.spp, b.settings.max_depth), (Some(16), Some(6)));
    let c = b.camera().unwrap();
    assert_eq!((c.width, c.height, c.fov_axis), (320, 240, FovAxis::Y));
    assert_eq!((c.lens_radius, c.focus_distance), (0.01, 5.0));
    let idx = |n: &str| b.material_index(n).unwrap() as usize;
    assert!(matches!(
        &b.materials()[idx("checker")],
        Material::Diffuse { reflectance: Texture::Checkerboard { scale, .. } } if *scale == 8.0
    ));
    let (eta, k) = conductor_preset("Au").unwrap();
    assert!(matches!(
        &b.materials()[idx("gold")],
        Material::Conductor { eta: e, k: kk, .. } if *e == eta && *kk == k
    ));
    assert!(matches!(
        &b.materials()[idx("tinted-glass")],
        Material::Dielectric { ior, absorption, .. } if *ior == 1.5 && absorption.c == [0.0, 0.2, 0.4]
    ));
    assert!(
        matches!(&b.materials()[idx("frosted")], Material::RoughDielectric { alpha, .. } if *alpha == 0.3)
    );
    assert!(
        matches!(&b.materials()[idx("custom-metal")], Material::RoughConductor { alpha, .. } if *alpha == 0.2)
    );
    assert!(
        matches!(&b.materials()[idx("plastic")], Material::Phong { exponent, .. } if *exponent == 50.0)
    );
    assert!(
        matches!(&b.materials()[idx("chrome")], Material::Mirror { reflectance } if reflectance.c == [0.9; 3])
    );
    let shapes = b.shapes();
    // OBJ tetrahedron translated by (−1, 0.5, 0): edge length 2√2, centroid at the offset.
    let ShapeGeometry::Mesh(tet) = &shapes[0].geometry else {
        panic!()
    };
    assert_eq!(tet.indices.len(), 4);
    let centroid = tet.positions.iter().sum::<Vec3>() / 4.0;
    assert!(centroid.abs_diff_eq(Vec3::new(-1.0, 0.5, 0.0), 1e-6));
    // PLY quad scaled by 4 and rotated into the y = 0 plane facing +y.
    let ShapeGeometry::Mesh(quad) = &shapes[1].geometry else {
        panic!()
    };
    let area = quad.triangle_area(0) + quad.triangle_area(1);
    assert!((area - 16.0).abs() < 1e-4);
    let [p0, p1, p2] = quad.indices[0].map(|i| quad.positions[i as usize]);
    assert!(
        (p1 - p0)
            .cross(p2 - p0)
            .normalize()
            .abs_diff_eq(Vec3::Y, 1e-6)
    );
    assert!(quad.uvs.is_some());
    let ShapeGeometry::Mesh(tri) = &shapes[2].geometry else {
        panic!()
    };
    assert_eq!(tri.positions[1], Vec3::new(2.0, 0.0, 1.0));
    assert!(tri.normals.is_some() && tri.uvs.is_some());
    let ShapeGeometry::Sphere(s) = &shapes[3].geometry else {
        panic!()
    };
    assert_eq!((s.center, s.radius), (Vec3::new(0.0, 0.5, 0.0), 0.5));
    let ShapeGeometry::Disk(d) = &shapes[4].geometry else {
        panic!()
    };
    assert_eq!(
        (d.center, d.normal, d.radius),
        (Vec3::new(0.0, 2.0, 0.0), -Vec3::Y, 0.3)
    );
    assert_ne!(shapes[4].light, caustica_scene::intersection::NONE);
    let ShapeGeometry::Mesh(cube) = &shapes[5].geometry else {
        panic!()
    };
    let area: f32 = (0..12).map(|i| cube.triangle_area(i)).sum();
    assert!((area - 6.0 * 0.25).abs() < 1e-4); // six faces of side 0.5
}

#[test]
fn nan_vertex_in_obj_is_skipped_and_counted_in_warnings() {
    let dir = std::env::temp_dir().join(format!("caustica-toml-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("nan.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 NaN 1\nf 1 2 3\nf 1 2 4\nf 2 3 4\n",
    )
    .unwrap();
    let text = format!(
        "{CAMERA}[[material]]\nname = \"d\"\ntype = \"diffuse\"\n\
         [[shape]]\ntype = \"obj\"\nmaterial = \"d\"\nfilename = \"nan.obj\"\n"
    );
    let b = parse_toml_scene(&text, &dir.join("scene.toml")).unwrap();
    assert_eq!(b.shape_count(), 1);
    assert_eq!(b.shapes()[0].primitive_count(), 1);
    assert_eq!(b.skipped_triangles(), 2);
    assert!(
        b.pending_warnings()
            .iter()
            .any(|w| w.contains("skipped 2 triangles"))
    );
}

#[test]
fn shapes_transforms_and_flip() {
    let text = format!(
        "{CAMERA}[[material]]\nname = \"d\"\ntype = \"diffuse\"\nreflectance = {{ texture = \"missing.png\" }}\n"
    );
    assert!(
        matches!(parse(&text), Err(LoadError::File { path, .. }) if path.ends_with("dir/missing.png"))
    );
    let text = format!(
        "{CAMERA}[[material]]\nname = \"d\"\ntype = \"diffuse\"\n\
         [[shape]]\ntype = \"sphere\"\nmaterial = \"d\"\nradius = 0.5\ncenter = [1, 0, 0]\n\
         scale = 2\nrotate = {{ axis = [0, 0, 1], angle = 90 }}\ntranslate = [0, 0, 3]\n\
         [[shape]]\ntype = \"rectangle\"\nmaterial = \"d\"\nflip_normals = true\n"
    );
    let b = parse(&text).unwrap();
    let ShapeGeometry::Sphere(s) = &b.shapes()[0].geometry else {
        panic!()
    };
    // Scale first (centre → (2,0,0), radius 1), then rotate 90° about z → (0,2,0), then move.
    assert!(s.center.abs_diff_eq(Vec3::new(0.0, 2.0, 3.0), 1e-6));
    assert!((s.radius - 1.0).abs() < 1e-6);
    let ShapeGeometry::Mesh(r) = &b.shapes()[1].geometry else {
        panic!()
    };
    let [p0, p1, p2] = r.indices[0].map(|i| r.positions[i as usize]);
    assert!(
        (p1 - p0)
            .cross(p2 - p0)
            .normalize()
            .abs_diff_eq(-Vec3::Z, 1e-6)
    );
}

#[test]
fn the_integrator_table_names_the_method_and_its_photon_options() {
    let b = parse(&format!(
        "{CAMERA}[integrator]\ntype = \"pds\"\nphotons = 5000\nsmoothing = 4\nfinal_gather = 0\n"
    ))
    .unwrap();
    assert_eq!(b.settings.integrator.as_deref(), Some("pds"));
    assert_eq!(
        (
            b.settings.photons,
            b.settings.smoothing,
            b.settings.final_gather
        ),
        (Some(5000), Some(4.0), Some(0))
    );
    // The volume photon-mapping estimators too.
    for m in ["vpm", "beam"] {
        let b = parse(&format!("{CAMERA}[integrator]\ntype = \"{m}\"\n")).unwrap();
        assert_eq!(b.settings.integrator.as_deref(), Some(m));
    }
    // Without the table: nothing suggested.
    let b = parse(CAMERA).unwrap();
    assert_eq!((b.settings.integrator, b.settings.photons), (None, None));
    // Unknown method, unknown key, bad values: errors at their line.
    expect_parse_error(
        &format!("{CAMERA}[integrator]\ntype = \"bdpt\"\n"),
        8,
        &["bdpt", "pds"],
    );
    expect_parse_error(
        &format!("{CAMERA}[integrator]\ntype = \"pm\"\nk = 3\n"),
        9,
        &["k"],
    );
    expect_parse_error(
        &format!("{CAMERA}[integrator]\ntype = \"pdm\"\nsmoothing = -1\n"),
        7,
        &["smoothing"],
    );
    expect_parse_error(
        &format!("{CAMERA}[integrator]\ntype = \"pm\"\nphotons = 0\n"),
        9,
        &["photons"],
    );
    expect_parse_error(
        &format!("{CAMERA}[integrator]\ntype = \"pm\"\nfinal_gather = -2\n"),
        9,
        &["final_gather"],
    );
}

// ---- participating media ----

use caustica_scene::intersection::NONE;
use caustica_scene::medium::MediumKind;
use caustica_scene::phase::PhaseFunction;

fn close3(a: caustica_core::Spectrum, b: [f32; 3]) -> bool {
    (0..3).all(|i| (a.c[i] - b[i]).abs() <= 1e-6 * b[i].abs().max(1.0))
}

#[test]
fn media_parse_every_parameter_form() {
    let text = format!(
        r#"{CAMERA}medium = "thick"

[[medium]]
name = "fog"
type = "homogeneous"
sigma_a = 0.05
sigma_s = [0.4, 0.5, 0.6]

[[medium]]
name = "thick"
type = "homogeneous"
sigma_t = [1, 2, 3]
albedo = 0.5
scale = 2
phase = {{ type = "hg", g = 0.6 }}

[[medium]]
name = "iso"
type = "homogeneous"
sigma_a = [1, 0, 0]
sigma_s = 1
scale = 0.5
phase = {{ type = "isotropic" }}

[[medium]]
name = "plume"
type = "grid"
density = "plume"
res = [8, 6, 4]
min = [-1, 0, 2]
max = [1, 3, 4]
sigma_t = 1
albedo = [0.9, 0.8, 0.7]
scale = 6
phase = "isotropic"

[[material]]
name = "pass"
type = "null"

[[material]]
name = "glass"
type = "dielectric"

[[shape]]
type = "cube"
material = "pass"
interior = "fog"
scale = 5

[[shape]]
type = "sphere"
material = "glass"
radius = 0.5
interior = "thick"
exterior = "fog"

[[shape]]
type = "sphere"
material = "glass"
center = [3, 0, 0]
radius = 0.5

[[shape]]               # an area light in the fog's cube
type = "rectangle"
material = "glass"
emission = 1
scale = 0.1
translate = [0, -2, 0]

[[light]]
type = "point"
position = [0, 2, 0]
intensity = 1

[[light]]
type = "spot"
position = [0, 3, 0]
direction = [0, -1, 0]
intensity = 1
medium = "iso"

[[light]]
type = "directional"
direction = [0, -1, 0]
irradiance = 1
"#
    );
    let b = parse(&text).unwrap();
    assert!(
        b.pending_warnings().is_empty(),
        "{:?}",
        b.pending_warnings()
    );
    let m = b.media();
    assert_eq!(m.len(), 4);
    assert!(close3(m[0].sigma_a, [0.05; 3]) && close3(m[0].sigma_s, [0.4, 0.5, 0.6]));
    assert_eq!(m[0].phase, PhaseFunction::default());
    // scale multiplies sigma_t (both coefficients).
    assert!(close3(m[1].sigma_s, [1.0, 2.0, 3.0]) && close3(m[1].sigma_a, [1.0, 2.0, 3.0]));
    assert_eq!(m[1].phase, PhaseFunction::henyey_greenstein(0.6).unwrap());
    assert!(close3(m[2].sigma_a, [0.5, 0.0, 0.0]) && close3(m[2].sigma_s, [0.5; 3]));
    let MediumKind::Grid(g) = &m[3].kind else {
        panic!("a grid")
    };
    assert!(close3(m[3].sigma_t(), [6.0; 3]) && close3(m[3].sigma_s, [5.4, 4.8, 4.2]));
    assert_eq!(g.resolution(), [8, 6, 4]);
    // The grid fills [min, max]: the density at a voxel centre is the plume there.
    for (i, j, k) in [(0u32, 0u32, 0u32), (4, 2, 1), (7, 5, 3)] {
        let u = (Vec3::new(i as f32, j as f32, k as f32) + 0.5) / Vec3::new(8.0, 6.0, 4.0);
        let p = Vec3::new(-1.0, 0.0, 2.0) + Vec3::new(2.0, 3.0, 2.0) * u;
        assert!((g.density(p) - crate::plume_density(u)).abs() < 1e-5, "{u}");
    }
    assert_eq!(g.density(Vec3::new(0.0, 1.0, 1.9)), 0.0);
    assert!(b.materials()[0].is_null());
    let sides = |i: usize| (b.shapes()[i].medium_inside, b.shapes()[i].medium_outside);
    assert_eq!(sides(0), (0, NONE));
    assert_eq!(sides(1), (1, 0));
    assert_eq!(sides(2), (NONE, NONE));
    let scene = b.build().unwrap();
    assert_eq!(scene.camera_medium, 1, "given");
    // The area light and the point light found (in the fog cube), the spot light given, the
    // directional light at infinity (vacuum).
    assert_eq!(scene.light_media, vec![0, 0, 2, NONE]);
    // Without `medium` the camera (at z = 4.1, inside the cube of half-size 5) is found in the
    // fog; outside the cube it is in vacuum.
    let text = text.replacen("medium = \"thick\"\n", "", 1);
    assert_eq!(parse(&text).unwrap().build().unwrap().camera_medium, 0);
    let text = text.replacen("scale = 5", "scale = 3", 1);
    assert_eq!(parse(&text).unwrap().build().unwrap().camera_medium, NONE);
}

#[test]
fn grid_media_read_vol_files_relative_to_the_scene() {
    let dir = std::env::temp_dir().join(format!("caustica-toml-vol-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("grids")).unwrap();
    let data: Vec<f32> = (0..12).map(|i| i as f32).collect();
    let bbox = [Vec3::splat(7.0), Vec3::splat(9.0)];
    std::fs::write(
        dir.join("grids/ramp.vol"),
        crate::vol::encode_vol([3, 2, 2], 1, bbox, &data),
    )
    .unwrap();
    std::fs::write(
        dir.join("grids/rgb.vol"),
        crate::vol::encode_vol([1, 1, 1], 3, bbox, &[1.0, 2.0, 3.0]),
    )
    .unwrap();
    let medium = |file: &str| {
        format!(
            "{CAMERA}[[medium]]\nname = \"m\"\ntype = \"grid\"\nfile = \"{file}\"\nmin = [0, 0, 0]\nmax = [3, 2, 1]\nsigma_a = 0\nsigma_s = 0.5\n"
        )
    };
    let path = dir.join("scene.toml");
    let b = parse_toml_scene(&medium("grids/ramp.vol"), &path).unwrap();
    let MediumKind::Grid(g) = &b.media()[0].kind else {
        panic!()
    };
    // Voxel (i, j, k) at ((i + ½), (j + ½), (k + ½)/2) in the box [0, 3] × [0, 2] × [0, 1].
    for k in 0..2 {
        for j in 0..2 {
            for i in 0..3 {
                let p = Vec3::new(i as f32 + 0.5, j as f32 + 0.5, (k as f32 + 0.5) / 2.0);
                assert!((g.density(p) - data[(k * 2 + j) * 3 + i]).abs() < 1e-5);
            }
        }
    }
    let err_of = |text: &str| match parse_toml_scene(text, &path) {
        Err(LoadError::Parse {
            path: p,
            line,
            message,
            ..
        }) => {
            assert_eq!(p, path);
            (line, message)
        }
        other => panic!("expected a parse error, got {:?}", other.err()),
    };
    let (line, msg) = err_of(&medium("grids/none.vol"));
    assert_eq!(line, 7, "{msg}");
    assert!(
        msg.contains("medium 'm'") && msg.contains("grids/none.vol"),
        "{msg}"
    );
    let (line, msg) = err_of(&medium("grids/rgb.vol"));
    assert!(line == 7 && msg.contains("3 channels"), "{msg}");
    let (line, msg) = err_of(&format!("{}res = [1, 1, 1]\n", medium("grids/ramp.vol")));
    assert!(line == 7 && msg.contains("'res'"), "{msg}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_media_are_errors_naming_line_and_field() {
    let h = "[[medium]]\nname = \"fog\"\ntype = \"homogeneous\"\n";
    let grid = "[[medium]]\nname = \"g\"\ntype = \"grid\"\nsigma_t = 1\nalbedo = 0.5\n";
    // Line 7 is the medium's table, line 10 its first field after type.
    expect_parse_error(&format!("{CAMERA}{h}sigma = 1\n"), 10, &["sigma"]);
    expect_parse_error(
        &format!("{CAMERA}{h}sigma_a = -1\nsigma_s = 1\n"),
        10,
        &["sigma_a", "non-negative"],
    );
    expect_parse_error(
        &format!("{CAMERA}{h}sigma_a = [1, nan, 1]\nsigma_s = 1\n"),
        10,
        &["sigma_a", "finite"],
    );
    expect_parse_error(
        &format!("{CAMERA}{h}sigma_a = 1\n"),
        7,
        &["sigma_a", "sigma_s", "albedo"],
    );
    expect_parse_error(
        &format!("{CAMERA}{h}sigma_t = 1\nalbedo = [0.5, 1.2, 0]\n"),
        7,
        &["albedo", "[0, 1]"],
    );
    expect_parse_error(
        &format!("{CAMERA}{h}sigma_t = 1\nalbedo = 1\nscale = -2\n"),
        12,
        &["scale"],
    );
    expect_parse_error(
        &format!("{CAMERA}{h}sigma_t = 1\nalbedo = 1\nfile = \"x.vol\"\n"),
        7,
        &["'file'", "homogeneous"],
    );
    for g in ["1", "-1.0", "2.5"] {
        expect_parse_error(
            &format!("{CAMERA}{h}sigma_t = 1\nalbedo = 1\nphase = {{ type = \"hg\", g = {g} }}\n"),
            12,
            &["phase", "(-1, 1)"],
        );
    }
    expect_parse_error(
        &format!("{CAMERA}{h}sigma_t = 1\nalbedo = 1\nphase = \"rayleigh\"\n"),
        12,
        &["rayleigh"],
    );
    expect_parse_error(
        &format!("{CAMERA}{h}sigma_t = 1\nalbedo = 1\nphase = {{ type = \"hg\" }}\n"),
        12,
        &["'g'"],
    );
    expect_parse_error(&format!("{CAMERA}{h}type2 = 1\n"), 10, &["type2"]);
    expect_parse_error(
        &format!("{CAMERA}[[medium]]\nname = \"x\"\ntype = \"foam\"\n"),
        9,
        &["foam"],
    );
    expect_parse_error(
        &format!("{CAMERA}{grid}density = \"plume\"\nres = [4, 4, 4]\n"),
        7,
        &["'min'", "'max'"],
    );
    expect_parse_error(
        &format!(
            "{CAMERA}{grid}density = \"plume\"\nres = [4, 4, 4]\nmin = [0, 0, 0]\nmax = [1, 0, 1]\n"
        ),
        7,
        &["'min'", "below"],
    );
    expect_parse_error(
        &format!(
            "{CAMERA}{grid}density = \"fire\"\nres = [4, 4, 4]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"
        ),
        7,
        &["fire", "plume", "rising-smoke", "room-smoke"],
    );
    expect_parse_error(
        &format!("{CAMERA}{grid}density = \"plume\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"),
        7,
        &["res"],
    );
    expect_parse_error(
        &format!("{CAMERA}{grid}density = \"plume\"\nres = [4, 0, 4]\n"),
        13,
        &["res"],
    );
    expect_parse_error(
        &format!(
            "{CAMERA}{grid}scale = 1e30\ndensity = \"plume\"\nres = [4, 4, 4]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n"
        ),
        7,
        &["medium 'g'", "optical depth"],
    );
    // Names.
    let sigma = "sigma_t = 1\nalbedo = 1\n";
    expect_parse_error(
        &format!("{CAMERA}{h}{sigma}{h}{sigma}"),
        12,
        &["medium named 'fog' already exists"],
    );
    let m = "[[material]]\nname = \"n\"\ntype = \"null\"\n";
    expect_parse_error(
        &format!(
            "{CAMERA}{h}{sigma}{m}[[shape]]\ntype = \"cube\"\nmaterial = \"n\"\ninterior = \"smoke\"\n"
        ),
        18,
        &["interior", "no medium named 'smoke'"],
    );
    expect_parse_error(
        &format!(
            "{CAMERA}{h}{sigma}{m}[[shape]]\ntype = \"cube\"\nmaterial = \"n\"\nexterior = \"fig\"\n"
        ),
        18,
        &["exterior", "'fig'"],
    );
    expect_parse_error(
        "[camera]\nmedium = \"nowhere\"\neye = [0, 0, 4]\ntarget = [0, 0, 0]\nfov = 40\nwidth = 4\nheight = 4\n",
        2,
        &["medium", "'nowhere'"],
    );
    expect_parse_error(
        &format!(
            "{CAMERA}{h}{sigma}[[light]]\ntype = \"point\"\nintensity = 1\nmedium = \"mist\"\n"
        ),
        15,
        &["medium", "'mist'"],
    );
    expect_parse_error(
        &format!(
            "{CAMERA}{h}{sigma}[[light]]\ntype = \"directional\"\ndirection = [0, -1, 0]\nirradiance = 1\nmedium = \"fog\"\n"
        ),
        12,
        &["'medium'", "directional"],
    );
    expect_parse_error(
        &format!("{CAMERA}[[material]]\nname = \"n\"\ntype = \"null\"\nior = 1.5\n"),
        7,
        &["ior", "null"],
    );
}

#[test]
fn open_medium_boundaries_are_warned_about_with_their_line() {
    let text = format!(
        "{CAMERA}[[medium]]\nname = \"fog\"\ntype = \"homogeneous\"\nsigma_t = 1\nalbedo = 1\n\n[[material]]\nname = \"n\"\ntype = \"null\"\n\n[[shape]]\ntype = \"cube\"\nmaterial = \"n\"\ninterior = \"fog\"\n\n[[shape]]\ntype = \"rectangle\"\nmaterial = \"n\"\nexterior = \"fog\"\n\n[[shape]]\ntype = \"rectangle\"\nmaterial = \"n\"\n"
    );
    let b = parse(&text).unwrap();
    let w = b.pending_warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("rectangle shape at test.toml:22") && w[0].contains("not closed"),
        "{w:?}"
    );
}

/// Named emission spectra: an area light's `emission_spectrum` and a point light's `spectrum`
/// give their lights the spectrum and, in RGB, its colour times the one number given; a
/// coloured `emission` with a spectrum, or an unknown name, is an error at its line.
#[test]
fn named_emission_spectra() {
    let text = format!(
        "{CAMERA}
[[material]]
name = \"white\"
type = \"diffuse\"

[[shape]]
type = \"rectangle\"
material = \"white\"
emission = 5
emission_spectrum = \"blackbody:3000\"

[[light]]
type = \"point\"
intensity = 2
spectrum = \"D65\"
"
    );
    let b = parse(&text).unwrap();
    let scene = b.build().unwrap();
    use caustica_scene::light::{EmissionSpectrum, NamedSpectrum};
    assert_eq!(scene.lights.len(), 2);
    assert_eq!(
        scene.light_spectra[0],
        EmissionSpectrum::named(NamedSpectrum::Blackbody(3000.0))
    );
    assert_eq!(
        scene.light_spectra[1],
        EmissionSpectrum::named(NamedSpectrum::D65)
    );
    let Light::Area(a) = &scene.lights[0] else {
        panic!("{:?}", scene.lights[0])
    };
    let want = NamedSpectrum::Blackbody(3000.0).rgb() * 5.0;
    for k in 0..3 {
        assert!(
            (a.radiance.c[k] - want.c[k]).abs() < 1e-5,
            "{:?}",
            a.radiance
        );
    }
    expect_parse_error(
        &text.replace("emission = 5", "emission = [1, 2, 3]"),
        16,
        &["emission_spectrum", "one number"],
    );
    expect_parse_error(
        &text.replace("blackbody:3000", "tungsten"),
        16,
        &["unknown illuminant"],
    );
}
