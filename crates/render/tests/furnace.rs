//! White furnace: a Lambertian sphere of albedo 1 inside a constant environment of radiance 1
//! must look exactly like the environment (radiance 1 in every pixel), for the path tracer.

mod common;

use caustica_core::Spectrum;
use caustica_render::IntegratorKind;
use caustica_scene::material::Material;
use caustica_scene::texture::Texture;

#[test]
fn white_furnace_path_tracer() {
    let scene = common::furnace(
        Material::Diffuse {
            reflectance: Texture::Constant(Spectrum::ONE),
        },
        24,
    );
    let img = common::render_image(&scene, IntegratorKind::Path, 2048, 1);
    let mut worst = 0.0f32;
    for p in &img.data {
        for &c in p {
            worst = worst.max((c - 1.0).abs());
        }
    }
    assert!(worst < 0.01, "largest deviation from 1 is {worst}");
    // The sphere is in view: the centre pixel sees it, not the environment behind.
    assert!(
        scene
            .intersect(
                &scene
                    .camera
                    .generate_ray(
                        caustica_core::Vec2::new(12.0, 12.0),
                        caustica_core::Vec2::splat(0.5)
                    )
                    .ray
            )
            .is_some()
    );
}
