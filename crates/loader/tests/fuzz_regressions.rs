//! Inputs found by the fuzz targets in `fuzz/` (docs/fuzzing.md): each must give an error (or a
//! scene), not a panic.

use caustica_loader::{LoadError, parse_obj, parse_toml_scene};
use std::path::Path;

fn toml_error(text: &str) -> LoadError {
    match parse_toml_scene(text, Path::new("/virtual/dir/fuzz.toml")) {
        Err(e) => e,
        Ok(_) => panic!("expected an error for {text:?}"),
    }
}

/// `toml_scene`: a syntax error after `key =` whose key ends in a multi-byte character made
/// the field-name hint slice inside that character (panic "byte index is not a char boundary").
#[test]
fn toml_error_hint_after_a_non_ascii_key() {
    for text in [
        "é = \"x\" \"y\"\n",
        "[camera]\nfov§ = 1 2\n",
        "a.bé = 1 2\n",
    ] {
        match toml_error(text) {
            LoadError::Parse { line, message, .. } => {
                assert_eq!(line, text.lines().count(), "{text:?}: {message}")
            }
            e => panic!("expected a parse error for {text:?}, got {e}"),
        }
    }
}

fn obj(text: &str) -> Result<caustica_scene::shape::TriangleMesh, LoadError> {
    parse_obj(&mut text.as_bytes(), Path::new("/virtual/dir/fuzz.obj"))
}

/// `obj_mesh`: tobj 4.0.5 computes `vt * 2` and `vn * 3` unchecked when it builds the mesh, so
/// a relative texture-coordinate or normal index reaching before the first one overflowed (a
/// panic with overflow checks, wrong data without).
#[test]
fn obj_relative_indices_before_the_start_are_errors() {
    let e = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/-2 2/1 3/1\n").unwrap_err();
    assert!(matches!(e, LoadError::File { .. }));
    let msg = e.to_string();
    assert!(
        msg.contains("fuzz.obj") && msg.contains("line 5") && msg.contains("'1/-2'"),
        "{msg}"
    );
    // The fuzzer's case: the index resolves to -2 or below with texture coordinates present
    // (-1 would wrap to tobj's "no index" marker).
    let e = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/-3 2/1 3/1\n").unwrap_err();
    assert!(e.to_string().contains("'1/-3'"), "{e}");
    for face in [
        "f 1//-1 2//-1 3//-1",
        "vn 0 0 1\nf 1//-9 2//1 3//1",
        "f 1//9223372036854775807 2 3",
    ] {
        let e = obj(&format!("v 0 0 0\nv 1 0 0\nv 0 1 0\n{face}\n")).unwrap_err();
        assert!(e.to_string().contains("face index"), "{face}: {e}");
    }
    // Position indices out of range were already tobj's own error.
    let e = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 -3 -2\n").unwrap_err();
    assert!(e.to_string().contains("malformed OBJ file"), "{e}");
    // Relative indices inside the file still load; lines and points are ignored.
    let m = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf -3//-1 -2//-1 -1//-1\nl -9 -8\nf -7\n")
        .unwrap();
    assert_eq!(m.indices.len(), 1);
    assert!(m.normals.is_some());
}

/// `obj_mesh`, open (docs/fuzzing.md): this mesh of a few distinct triangles, most of them
/// repeated and some degenerate, gets a binary BVH 98 levels deep from obvhs 0.4, whose
/// debug-build validation asserts a depth below 96, so `SceneBuilder::build` panics in debug
/// builds. Release builds skip the check and caustica's traversal stack grows on the heap, so
/// they render it; this test passes there. Not a loader bug: the fix belongs to the BVH build.
#[test]
#[ignore = "open: obvhs debug-build depth assertion in SceneBuilder::build (docs/fuzzing.md)"]
fn obj_duplicated_triangles_build_in_debug_builds() {
    use caustica_core::{Affine3A, Spectrum};
    use caustica_scene::SceneBuilder;
    use caustica_scene::camera::{FovAxis, PerspectiveCamera};
    use caustica_scene::material::Material;
    use caustica_scene::shape::ShapeGeometry;
    use caustica_scene::texture::Texture;
    let text = include_str!("data/bvh-depth.obj");
    let mesh = obj(text).expect("the mesh loads");
    let mut b = SceneBuilder::new("bvh-depth");
    b.set_camera(PerspectiveCamera {
        width: 8,
        height: 8,
        to_world: Affine3A::IDENTITY,
        fov_deg: 40.0,
        fov_axis: FovAxis::X,
        lens_radius: 0.0,
        focus_distance: 1.0,
        near_clip: 1e-4,
    });
    let diffuse = Material::Diffuse {
        reflectance: Texture::Constant(Spectrum::splat(0.5)),
    };
    let m = b.add_material("d", diffuse).expect("valid material");
    b.add_shape(ShapeGeometry::Mesh(mesh), m, Some(Spectrum::ONE), false)
        .expect("finite mesh");
    assert!(b.build().is_ok());
}
