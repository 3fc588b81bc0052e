//! Shared by the mesh fuzz targets: a parsed mesh takes the path of a mesh a scene file names,
//! `SceneBuilder::add_shape` (non-finite vertices and bad indices removed, coordinates checked)
//! and `SceneBuilder::build` (BVH, and the area light it is made into).

use caustica_core::{Affine3A, Spectrum};
use caustica_scene::SceneBuilder;
use caustica_scene::camera::{FovAxis, PerspectiveCamera};
use caustica_scene::material::Material;
use caustica_scene::shape::{ShapeGeometry, TriangleMesh};
use caustica_scene::texture::Texture;

/// The name errors give the fuzzed mesh; nothing is read from it (the parsers read memory).
pub const MESH_DIR: &str = "/nonexistent-caustica-fuzz";

/// Adds `mesh` as an emitting diffuse shape to a minimal scene and builds it.
pub fn build(mesh: TriangleMesh) {
    let mut b = SceneBuilder::new("fuzz");
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
    let Ok(material) = b.add_material(
        "d",
        Material::Diffuse {
            reflectance: Texture::Constant(Spectrum::splat(0.5)),
        },
    ) else {
        return;
    };
    if b.add_shape(
        ShapeGeometry::Mesh(mesh),
        material,
        Some(Spectrum::ONE),
        false,
    )
    .is_ok()
    {
        let _ = b.build();
    }
}
