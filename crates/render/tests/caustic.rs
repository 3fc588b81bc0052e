//! The glass-sphere caustic: a point light above a glass ball (IOR 1.5) focused onto a diffuse
//! floor. The light tracer must show the focused caustic; the path tracer with NEE cannot find
//! L S+ D E paths from a point light but must agree with the light tracer on the directly lit
//! floor away from the caustic and the shadow.

mod common;

use caustica_core::{Vec2, Vec3};
use caustica_render::IntegratorKind;
use caustica_scene::Scene;

fn glass_sphere_scene() -> Scene {
    common::ball_on_floor(0.8, 20.0, 4.0, true, 64)
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
    let pt = common::render_image(&scene, IntegratorKind::Path, 64, 3);
    // Direct light only (paths of two edges: light → floor → camera), where the two estimators
    // see exactly the same light transport.
    let lt_direct = [3, 4]
        .map(|seed| common::render_image_depth(&scene, IntegratorKind::LightTrace, 256, seed, 2));
    let pt_direct = common::render_image_depth(&scene, IntegratorKind::Path, 64, 3, 2);
    let focus = raster_of(&scene, Vec3::ZERO);
    let lit = [
        Vec3::new(1.4, 0.0, 0.8),
        Vec3::new(-1.4, 0.0, 0.8),
        Vec3::new(1.2, 0.0, -1.0),
    ];
    for p in lit {
        let px = raster_of(&scene, p);
        // Direct irradiance on the floor is I cos θ / d²; a Lambertian floor gives L = ρ E / π.
        let d = Vec3::new(0.0, 4.0, 0.0) - p;
        let expected = 0.8 / std::f64::consts::PI * 20.0 * (d.y / d.length()) as f64
            / d.length_squared() as f64;
        let t = window(&pt_direct, px, 2);
        assert!(
            (t - expected).abs() / expected < 0.03,
            "lit floor at {p}: path tracer {t:.4}, analytic {expected:.4} (5x5 window over a gradient)"
        );
        // The light tracer's noise in the window from two independent seeds: σ of their mean
        // ≈ |l1 − l2| / 2. Allow 4σ, floored at 0.5 %, plus 0.5 % for the path tracer.
        let (l1, l2) = (window(&lt_direct[0], px, 2), window(&lt_direct[1], px, 2));
        let lm = 0.5 * (l1 + l2);
        let tol = (2.0 * (l1 - l2).abs()).max(0.005 * t) + 0.005 * t;
        assert!(
            (lm - t).abs() < tol,
            "direct light at {p}: light tracer {lm:.4} (seeds {l1:.4}, {l2:.4}), path tracer {t:.4}, tolerance {tol:.4}"
        );
        // With all path lengths the light tracer adds light the sphere reflects and scatters
        // onto the floor (L S+ D E), which the path tracer cannot find from a point light: it
        // must be non-negative and small this far from the caustic.
        let (l_full, t_full) = (window(&lt, px, 2), window(&pt, px, 2));
        assert!(
            l_full > t_full - tol && l_full < 1.03 * t_full + tol,
            "lit floor at {p}: light tracer {l_full:.4}, path tracer {t_full:.4}"
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
