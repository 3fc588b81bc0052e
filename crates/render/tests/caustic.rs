//! The glass-sphere caustic: a point light above a glass ball (IOR 1.5) focused onto a diffuse
//! floor. The light tracer must show the focused caustic; the path tracer with NEE cannot find
//! L S+ D E paths from a point light but must agree with the light tracer on the directly lit
//! floor away from the caustic and the shadow.

mod common;

use caustica_core::{Affine3A, Spectrum, Vec2, Vec3};
use caustica_render::IntegratorKind;
use caustica_scene::camera::PerspectiveCamera;
use caustica_scene::light::{Light, PointLight};
use caustica_scene::material::Material;
use caustica_scene::shape::{ShapeGeometry, Sphere};
use caustica_scene::{Scene, SceneBuilder};

fn glass_sphere_scene() -> Scene {
    let mut b = SceneBuilder::new("caustic-test");
    let floor = common::diffuse(&mut b, "floor", 0.8);
    let glass = b
        .add_material(
            "glass",
            Material::Dielectric {
                ior: 1.5,
                absorption: Spectrum::ZERO,
            },
        )
        .unwrap();
    // Floor y = 0 facing up, 4 m × 4 m.
    b.add_shape(
        common::quad(
            Affine3A::from_rotation_x(-std::f32::consts::FRAC_PI_2)
                * Affine3A::from_scale(Vec3::splat(2.0)),
        ),
        floor,
        None,
        false,
    )
    .unwrap();
    // Ball lens of radius 0.5 centred 1 m above the floor: with the light 3 m above its centre,
    // the paraxial image (1/v = 2(n−1)/(nR) − 1/u) lies 1 m below the centre, on the floor.
    b.add_shape(
        ShapeGeometry::Sphere(Sphere {
            center: Vec3::new(0.0, 1.0, 0.0),
            radius: 0.5,
        }),
        glass,
        None,
        false,
    )
    .unwrap();
    b.add_light(Light::Point(PointLight::new(
        Vec3::new(0.0, 4.0, 0.0),
        Spectrum::splat(20.0),
    )));
    b.set_camera(PerspectiveCamera::look_at(
        Vec3::new(0.0, 3.0, 3.5),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::Y,
        50.0,
        64,
        64,
    ));
    b.build().unwrap()
}

fn raster_of(scene: &Scene, p: Vec3) -> (usize, usize) {
    let cs = scene
        .camera
        .sample_wi(p, Vec2::splat(0.5))
        .expect("point projects into the image");
    (cs.raster.x as usize, cs.raster.y as usize)
}

fn window(img: &caustica_core::image_io::Image, (x, y): (usize, usize), r: usize) -> f64 {
    common::lum_arr(common::region_mean(img, x - r, y - r, x + r + 1, y + r + 1))
}

#[test]
fn light_tracer_focuses_the_caustic_and_path_tracer_agrees_on_direct_light() {
    let scene = glass_sphere_scene();
    let lt = common::render_image(&scene, IntegratorKind::LightTrace, 256, 3);
    let lt2 = common::render_image(&scene, IntegratorKind::LightTrace, 256, 4);
    let pt = common::render_image(&scene, IntegratorKind::Path, 64, 3);
    let focus = raster_of(&scene, Vec3::ZERO);
    let lit = [
        Vec3::new(1.4, 0.0, 0.8),
        Vec3::new(-1.4, 0.0, 0.8),
        Vec3::new(1.2, 0.0, -1.0),
    ];
    // Direct irradiance on the floor at the lit points is I cos θ / d²; for a Lambertian floor
    // L = ρ E / π. Both images must reproduce it.
    for p in lit {
        let px = raster_of(&scene, p);
        let d = Vec3::new(0.0, 4.0, 0.0) - p;
        let expected = 0.8 / std::f64::consts::PI * 20.0 * (d.y / d.length()) as f64
            / d.length_squared() as f64;
        let (l, l2, t) = (window(&lt, px, 2), window(&lt2, px, 2), window(&pt, px, 2));
        // The light tracer's noise in the window, from two independent seeds: σ(mean of two)
        // ≈ |l − l2| / 2. Allow 4σ (floored at 1 %) plus 1 % for the path tracer's noise and
        // the sphere's weak reflected light, which only the light tracer sees.
        let tol = (2.0 * (l - l2).abs()).max(0.01 * t) + 0.01 * t;
        let lm = 0.5 * (l + l2);
        assert!(
            (lm - t).abs() < tol,
            "lit floor at {p}: light tracer {lm:.4} (seeds {l:.4}, {l2:.4}), path tracer {t:.4}, tolerance {tol:.4}"
        );
        assert!(
            (t - expected).abs() / expected < 0.03,
            "lit floor at {p}: path tracer {t:.4}, analytic {expected:.4}"
        );
    }
    let caustic = window(&lt, focus, 1);
    let floor = window(&pt, raster_of(&scene, lit[0]), 2);
    assert!(
        caustic > 10.0 * floor,
        "caustic {caustic:.3} is not focused (lit floor {floor:.3})"
    );
    // The path tracer sees only the shadow there (no caustic from a point light).
    let shadow = window(&pt, focus, 1);
    assert!(
        shadow < 0.2 * floor,
        "path tracer below the sphere {shadow:.3} should be in shadow"
    );
}
