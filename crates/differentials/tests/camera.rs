//! Camera ray differentials (issue 5 item 1): [`camera_ray_diff`] against finite differences
//! of [`PerspectiveCamera::generate_ray`] (O(ε²)), against the camera's own Igehy
//! differentials, and the pixel footprint on a fronto-parallel plane after
//! [`transfer_to_plane`].
//!
//! Precision (`f32`, as the renderer): a 64×48 image with a 50° field of view turns the
//! direction by ~0.015 rad per pixel, so with ε = 1 px the second-order remainder of the
//! direction is ~1e-4, three orders of magnitude above `f32` rounding, and the third-order
//! term moves the ratio err(ε)/err(ε/2) from 4 by ~1 %. The origin is exactly linear in the
//! raster position (it lies on the near-clip plane), so its error is rounding only.

use caustica_core::{Vec2, Vec3};
use caustica_differentials::{RayDiff, camera_ray_diff, transfer_to_plane};
use caustica_scene::camera::{FovAxis, PerspectiveCamera};

const EPS: f32 = 1.0;
const RATIO: (f32, f32) = (3.2, 4.8);
/// Rounding floor for the (exactly linear) origin, in m, for a camera ~4 m from the origin.
const FLOOR: f32 = 4e-6;

fn pinhole() -> PerspectiveCamera {
    let mut cam = PerspectiveCamera::look_at(
        Vec3::new(1.0, 2.0, 3.0),
        Vec3::new(1.5, 1.8, 6.0),
        Vec3::Y,
        50.0,
        64,
        48,
    );
    // A visible near clip, so that ∂P/∂x ≠ 0 is exercised.
    cam.near_clip = 0.05;
    cam
}

fn thin_lens() -> PerspectiveCamera {
    let mut cam = pinhole();
    cam.lens_radius = 0.1;
    cam.focus_distance = 2.5;
    cam
}

const U_LENS: Vec2 = Vec2::new(0.8, 0.3);
const RASTERS: [Vec2; 3] = [
    Vec2::new(13.7, 30.2),
    Vec2::new(32.0, 24.0),
    Vec2::new(60.5, 2.25),
];

/// Errors of the first-order prediction of origin and direction at raster + ε eᵢ.
fn fd_errors(cam: &PerspectiveCamera, r0: Vec2, axis: usize, eps: f32) -> (f32, f32) {
    let d = camera_ray_diff(cam, r0, U_LENS).expect("differential");
    let mut step = [0.0; 2];
    step[axis] = eps;
    let (p_pred, v_pred) = d.first_order(step);
    let exact = cam
        .generate_ray(r0 + Vec2::new(step[0], step[1]), U_LENS)
        .ray;
    ((exact.o - p_pred).length(), (exact.d - v_pred).length())
}

fn check_second_order(name: &str, cam: &PerspectiveCamera) {
    for r0 in RASTERS {
        // The ray itself is generate_ray's.
        let d = camera_ray_diff(cam, r0, U_LENS).unwrap();
        let g = cam.generate_ray(r0, U_LENS).ray;
        assert!((d.p - g.o).length() < 1e-6, "{name} {r0}: origin");
        assert!((d.v - g.d).length() < 1e-6, "{name} {r0}: direction");
        assert!((d.v.length() - 1.0).abs() < 1e-6);
        for axis in 0..2 {
            assert!(d.v.dot(d.dv[axis]).abs() < 1e-7, "dv ⟂ v");
            let (ep1, ev1) = fd_errors(cam, r0, axis, EPS);
            let (ep2, ev2) = fd_errors(cam, r0, axis, EPS / 2.0);
            let ratio = ev1 / ev2;
            println!(
                "{name} raster {r0} axis {axis}: dir err {ev1:.3e} / {ev2:.3e} = {ratio:.3}, \
                 origin err {ep1:.1e} / {ep2:.1e}"
            );
            assert!(ep1 < FLOOR && ep2 < FLOOR, "{name}: origin not linear");
            assert!(ev1 > 1e-5, "{name}: remainder too small to measure");
            assert!(
                (RATIO.0..RATIO.1).contains(&ratio),
                "{name} raster {r0} axis {axis}: ratio {ratio}"
            );
        }
    }
}

#[test]
fn pinhole_matches_finite_differences_to_second_order() {
    check_second_order("pinhole", &pinhole());
}

#[test]
fn thin_lens_matches_finite_differences_to_second_order() {
    check_second_order("thin lens", &thin_lens());
    let mut cam = thin_lens();
    cam.fov_axis = FovAxis::Y;
    check_second_order("thin lens, fov along y", &cam);
}

fn assert_rel(a: Vec3, b: Vec3, what: &str) {
    let err = (a - b).length();
    assert!(
        err <= 1e-5 * b.length() + 1e-12,
        "{what}: {a} vs {b}, relative {}",
        err / b.length()
    );
}

#[test]
fn agrees_with_the_cameras_igehy_differentials() {
    for (name, cam) in [("pinhole", pinhole()), ("thin lens", thin_lens())] {
        for r0 in RASTERS {
            let d = camera_ray_diff(&cam, r0, U_LENS).unwrap();
            let g = cam.generate_ray(r0, U_LENS);
            let g = RayDiff::<2>::from(&g);
            for i in 0..2 {
                assert_rel(d.dp[i], g.dp[i], &format!("{name} {r0} dp[{i}]"));
                assert_rel(d.dv[i], g.dv[i], &format!("{name} {r0} dv[{i}]"));
            }
        }
    }
    // Pinhole with the default near clip (1e-4 m): the origin differential is tiny but agrees.
    let cam = PerspectiveCamera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0, 640, 480);
    let d = camera_ray_diff(&cam, Vec2::new(100.3, 400.9), Vec2::ZERO).unwrap();
    let g = cam.generate_ray(Vec2::new(100.3, 400.9), Vec2::ZERO);
    assert_rel(d.dp[0], g.dodx, "dodx");
    assert_rel(d.dp[1], g.dody, "dody");
    assert_rel(d.dv[0], g.dddx, "dddx");
    assert_rel(d.dv[1], g.dddy, "dddy");
}

/// Footprint |∂Q/∂x × ∂Q/∂y| (m² per pixel) on the plane through `q0` with normal `n`.
fn footprint(d: &RayDiff<2>, q0: Vec3, n: Vec3) -> f32 {
    let z = [Vec3::ZERO; 2];
    let hit = transfer_to_plane(d, q0, &z, n, &z).expect("transfer");
    hit.ray.dp[0].cross(hit.ray.dp[1]).length()
}

#[test]
fn pixel_footprint_on_fronto_parallel_plane() {
    let (w, h, fov) = (640u32, 480u32, 60.0f32);
    let tan = (0.5 * fov.to_radians()).tan();
    let centre = Vec2::new(0.5 * w as f32, 0.5 * h as f32);
    // Axis-aligned camera at the origin, and a rotated, translated one.
    let eye = Vec3::new(0.3, -1.0, 2.0);
    let target = Vec3::new(-2.0, 0.5, -1.0);
    let cams = [
        PerspectiveCamera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, fov, w, h),
        PerspectiveCamera::look_at(eye, target, Vec3::Y, fov, w, h),
    ];
    for cam in cams {
        let e = cam.position();
        let axis = cam.to_world.transform_vector3(Vec3::Z).normalize();
        for dist in [0.5f32, 1.0, 2.5, 10.0] {
            let expected = (2.0 * dist * tan / w as f32).powi(2);
            let q0 = e + dist * axis;
            let d = camera_ray_diff(&cam, centre, Vec2::ZERO).unwrap();
            let a = footprint(&d, q0, axis);
            println!("d = {dist}: footprint {a:.6e}, analytic {expected:.6e}");
            assert!(
                (a / expected - 1.0).abs() < 1e-4,
                "centre, d = {dist}: {a} vs {expected}"
            );
            // A fronto-parallel plane is a scaled copy of the image plane: the same area at a
            // corner pixel.
            let d = camera_ray_diff(&cam, Vec2::new(3.5, 470.0), Vec2::ZERO).unwrap();
            let a = footprint(&d, q0, axis);
            assert!(
                (a / expected - 1.0).abs() < 1e-4,
                "corner, d = {dist}: {a} vs {expected}"
            );
            // A thin lens focused on the plane images a pixel onto the same area, whatever the
            // lens sample.
            let mut lens = cam.clone();
            lens.lens_radius = 0.05;
            lens.focus_distance = dist;
            for u in [Vec2::new(0.1, 0.9), Vec2::new(0.7, 0.2)] {
                let d = camera_ray_diff(&lens, centre, u).unwrap();
                let a = footprint(&d, q0, axis);
                assert!(
                    (a / expected - 1.0).abs() < 1e-4,
                    "thin lens, d = {dist}: {a}"
                );
            }
        }
    }
}

#[test]
fn non_finite_input_gives_none() {
    let cam = pinhole();
    assert!(camera_ray_diff(&cam, Vec2::NAN, U_LENS).is_none());
    assert!(camera_ray_diff(&cam, Vec2::new(f32::INFINITY, 0.0), U_LENS).is_none());
}
