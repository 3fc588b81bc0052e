//! White furnace: a Lambertian sphere of albedo 1 inside a constant environment of radiance 1
//! must look exactly like the environment (radiance 1 in every pixel), for the path tracer.

mod common;

use caustica_core::{Spectrum, Vec3};
use caustica_render::IntegratorKind;
use caustica_scene::SceneBuilder;
use caustica_scene::camera::PerspectiveCamera;
use caustica_scene::light::{EnvironmentLight, Light};
use caustica_scene::shape::{ShapeGeometry, Sphere};

#[test]
fn white_furnace_path_tracer() {
    let mut b = SceneBuilder::new("furnace");
    let white = common::diffuse(&mut b, "white", 1.0);
    b.add_shape(
        ShapeGeometry::Sphere(Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        }),
        white,
        None,
        false,
    )
    .unwrap();
    b.add_light(Light::Environment(EnvironmentLight::constant(
        Spectrum::ONE,
    )));
    b.set_camera(PerspectiveCamera::look_at(
        Vec3::new(0.0, 0.0, 4.0),
        Vec3::ZERO,
        Vec3::Y,
        35.0,
        24,
        24,
    ));
    let scene = b.build().unwrap();
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
