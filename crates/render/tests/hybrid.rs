//! The hybrid integrator: a guided light tracer for the caustics seen directly (L S+ D E) and a
//! path tracer for every other path. Its image must be the path tracer's under an area light
//! (whose caustics the path tracer finds by BSDF sampling, so the hybrid's camera side must drop
//! them or count them twice), the light tracer's under a point light, and exactly the sum of its
//! two halves.

mod common;

use caustica_core::image_io::Image;
use caustica_core::{Affine3A, Spectrum, Vec2, Vec3};
use caustica_render::{IntegratorKind, LightShare, RenderControl, RenderOptions, Shard, render};
use caustica_scene::material::Material;
use caustica_scene::shape::{ShapeGeometry, Sphere};
use caustica_scene::{Scene, SceneBuilder};

/// A glass ball (IOR 1.5, radius 0.5, centre 1 m up) on a diffuse floor under a square area
/// light 0.6 m wide at y = 3 facing down: the ball focuses the light onto the floor below it, a
/// caustic the path tracer reaches by BSDF sampling through the ball.
fn ball_under_area_light(size: u32) -> Scene {
    let mut b = SceneBuilder::new("ball-under-area-light");
    let floor = common::diffuse(&mut b, "floor", 0.8);
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
    let glass = b
        .add_material(
            "glass",
            Material::Dielectric {
                ior: 1.5,
                absorption: Spectrum::ZERO,
                dispersion: None,
            },
        )
        .unwrap();
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
    let black = common::diffuse(&mut b, "light", 0.0);
    b.add_shape(
        common::quad(
            Affine3A::from_translation(Vec3::new(0.0, 3.0, 0.0))
                * Affine3A::from_rotation_x(std::f32::consts::FRAC_PI_2)
                * Affine3A::from_scale(Vec3::splat(0.3)),
        ),
        black,
        Some(Spectrum::splat(20.0)),
        false,
    )
    .unwrap();
    b.set_camera(caustica_scene::camera::PerspectiveCamera::look_at(
        Vec3::new(0.0, 3.0, 3.5),
        Vec3::ZERO,
        Vec3::Y,
        50.0,
        size,
        size,
    ));
    b.build().unwrap()
}

fn run(scene: &Scene, kind: IntegratorKind, opts: &RenderOptions) -> Image {
    render(scene, kind, opts, &RenderControl::silent())
        .expect("valid options")
        .film
        .to_image()
}

fn opts(spp: u32, seed: u64) -> RenderOptions {
    RenderOptions {
        spp,
        seed,
        ..Default::default()
    }
}

/// The caustic under the ball (a 7 × 7 window around the floor's origin) and the whole image
/// (or, `floor_only`, the bottom quarter of the image, floor in front of the ball): mean
/// luminance of each.
fn caustic_and_whole(scene: &Scene, img: &Image, floor_only: bool) -> [f64; 2] {
    let cs = scene
        .camera
        .sample_wi(Vec3::ZERO, Vec2::splat(0.5))
        .expect("the floor's origin is in view");
    let (x, y) = (cs.raster.x as usize, cs.raster.y as usize);
    let caustic = common::lum_arr(common::region_mean(img, x - 3, y - 3, x + 4, y + 4));
    let rest = if floor_only {
        let (w, h) = (img.width, img.height);
        common::lum_arr(common::region_mean(img, 0, 3 * h / 4, w, h))
    } else {
        common::mean_lum(img)
    };
    [caustic, rest]
}

/// Mean and standard error over seeds of each of the two measures.
fn over_seeds(
    scene: &Scene,
    kind: IntegratorKind,
    floor_only: bool,
    make: impl Fn(u64) -> RenderOptions,
) -> [(f64, f64); 2] {
    let runs: Vec<[f64; 2]> = (1..=4)
        .map(|seed| caustic_and_whole(scene, &run(scene, kind, &make(seed)), floor_only))
        .collect();
    let n = runs.len() as f64;
    [0, 1].map(|k| {
        let mean = runs.iter().map(|r| r[k]).sum::<f64>() / n;
        let var = runs.iter().map(|r| (r[k] - mean).powi(2)).sum::<f64>() / (n - 1.0);
        (mean, (var / n).sqrt())
    })
}

#[test]
fn under_an_area_light_the_hybrid_is_the_path_tracer_without_double_counting() {
    let scene = ball_under_area_light(48);
    let path = over_seeds(&scene, IntegratorKind::Path, false, |s| opts(256, s));
    let hybrid = over_seeds(&scene, IntegratorKind::Hybrid, false, |s| opts(64, 100 + s));
    // The caustic alone, as the hybrid's light tracer renders it: what counting it twice adds.
    let caustic_only = caustic_and_whole(
        &scene,
        &run(
            &scene,
            IntegratorKind::LightTrace,
            &RenderOptions {
                caustics_only: true,
                ..opts(64, 9)
            },
        ),
        false,
    );
    for (k, what) in ["caustic window", "whole image"].iter().enumerate() {
        let ((p, sp), (h, sh)) = (path[k], hybrid[k]);
        // 4 standard errors of the difference (four seeds each), floored at 0.3 %.
        let tol = 4.0 * (sp * sp + sh * sh).sqrt() + 0.003 * p;
        assert!(
            (h - p).abs() < tol,
            "{what}: hybrid {h:.5} ± {sh:.5}, path tracer {p:.5} ± {sp:.5} (tolerance {tol:.5})"
        );
        // The test can see double counting: the caustic is far above the tolerance.
        assert!(
            caustic_only[k] > 3.0 * tol,
            "{what}: the caustic ({:.5}) is within the tolerance {tol:.5}: the scene cannot tell double counting",
            caustic_only[k]
        );
    }
}

/// Under a point light, on the floor (the caustic window, and the strip of floor nearest the
/// camera): the light tracer leaves pixels that see the glass black, so the ball is left out.
#[test]
fn under_a_point_light_the_hybrid_is_the_light_tracer() {
    let scene = common::ball_on_floor(0.8, 20.0, 4.0, true, 48);
    let lt = over_seeds(&scene, IntegratorKind::LightTrace, true, |s| opts(256, s));
    let hybrid = over_seeds(&scene, IntegratorKind::Hybrid, true, |s| opts(64, 100 + s));
    for (k, what) in ["caustic window", "floor strip"].iter().enumerate() {
        let ((l, sl), (h, sh)) = (lt[k], hybrid[k]);
        let tol = 4.0 * (sl * sl + sh * sh).sqrt() + 0.003 * l;
        assert!(
            (h - l).abs() < tol,
            "{what}: hybrid {h:.5} ± {sh:.5}, light tracer {l:.5} ± {sl:.5} (tolerance {tol:.5})"
        );
    }
}

/// The hybrid's film holds its two halves: under a point light its camera side is the path
/// tracer (it reaches no light through a delta vertex, and draws the same numbers), and its light
/// side the caustics-only light tracer with the same light paths.
#[test]
fn the_hybrid_is_the_sum_of_its_halves() {
    let scene = common::ball_on_floor(0.8, 20.0, 4.0, true, 32);
    let (w, h) = (scene.camera.width as u64, scene.camera.height as u64);
    let mut o = opts(8, 5);
    o.photons.light_paths = Some(8 * w * h);
    let hybrid = run(&scene, IntegratorKind::Hybrid, &o);
    let path = run(&scene, IntegratorKind::Path, &o);
    let caustics = run(
        &scene,
        IntegratorKind::LightTrace,
        &RenderOptions {
            caustics_only: true,
            ..o.clone()
        },
    );
    let mut caustic_pixels = 0;
    for ((a, p), c) in hybrid.data.iter().zip(&path.data).zip(&caustics.data) {
        for k in 0..3 {
            let sum = p[k] + c[k];
            assert!(
                (a[k] - sum).abs() <= 1e-6 * sum.abs().max(1.0),
                "hybrid {} against path {} + caustics {}",
                a[k],
                p[k],
                c[k]
            );
        }
        caustic_pixels += (c[1] > 0.0) as usize;
    }
    assert!(
        caustic_pixels > 20,
        "only {caustic_pixels} pixels see the caustic"
    );
}

#[test]
fn the_hybrid_is_deterministic_and_shards_by_light_paths_and_rows() {
    let scene = ball_under_area_light(24);
    let bits =
        |img: &Image| -> Vec<u32> { img.data.iter().flat_map(|p| p.map(f32::to_bits)).collect() };
    let o = opts(4, 3);
    let one = common::with_threads(1, || run(&scene, IntegratorKind::Hybrid, &o));
    let two = common::with_threads(2, || run(&scene, IntegratorKind::Hybrid, &o));
    assert_eq!(bits(&one), bits(&two), "1 and 2 threads differ");
    assert_ne!(
        bits(&one),
        bits(&run(&scene, IntegratorKind::Hybrid, &opts(4, 4)))
    );
    // Two shards merged: the same film.
    let films: Vec<_> = (0..2)
        .map(|i| {
            let o = RenderOptions {
                shard: Some(Shard::new(i, 2).unwrap()),
                ..o.clone()
            };
            render(&scene, IntegratorKind::Hybrid, &o, &RenderControl::silent())
                .unwrap()
                .film
        })
        .collect();
    let mut merged = films[0].clone();
    merged.merge(&films[1]);
    assert_eq!(
        bits(&merged.to_image()),
        bits(&one),
        "shards merge into another image"
    );
}

#[test]
fn the_hybrid_refuses_what_it_cannot_do() {
    let scene = ball_under_area_light(8);
    for o in [
        RenderOptions {
            caustics_only: true,
            ..opts(1, 1)
        },
        RenderOptions {
            volume_only: true,
            ..opts(1, 1)
        },
    ] {
        let err = render(&scene, IntegratorKind::Hybrid, &o, &RenderControl::silent())
            .err()
            .expect("refused");
        assert!(err.to_string().contains("lighttrace"), "{err}");
    }
    let mut o = opts(1, 1);
    o.photons.light_paths = Some(0);
    assert!(render(&scene, IntegratorKind::Hybrid, &o, &RenderControl::silent()).is_err());
    for bad in [0.0, 1.0, -0.5, f32::NAN, f32::INFINITY] {
        assert!(LightShare::new(bad).is_err(), "share {bad} accepted");
    }
    assert_eq!(LightShare::new(0.5).unwrap().get(), 0.5);
}
