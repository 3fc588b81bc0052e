//! The hybrid integrator: a guided light tracer for the paths L S … D E and a path tracer for
//! every other path. Its image must be the path tracer's under an area light (whose caustics the
//! path tracer finds by BSDF sampling, so the hybrid's camera side must drop them or count them
//! twice) and the light tracer's under a point light (which the path tracer cannot reach through
//! the glass, so the light tracer's half must count every such path, the caustic's diffuse
//! reflections too).

mod common;

use caustica_core::image_io::Image;
use caustica_core::{Affine3A, Spectrum, Vec2, Vec3};
use caustica_render::{IntegratorKind, LightShare, RenderControl, RenderOptions, Shard, render};
use caustica_scene::light::{Light, PointLight, SpotLight};
use caustica_scene::material::Material;
use caustica_scene::{Scene, SceneBuilder};

/// The light of [`ball_room`].
#[derive(Clone, Copy)]
enum Lamp {
    /// A point light of 20 W/sr at (0, 4, 0).
    Point,
    /// A square area light 0.6 m wide at y = 3 facing down, radiance 20 W/m²/sr.
    Area,
}

/// A glass ball (IOR 1.5, radius 0.5, centre 1 m up) on a diffuse floor in front of a diffuse
/// back wall (z = −0.8), under `lamp`: the ball focuses the light onto the floor below it, a
/// caustic (L S+ D E) that lights the wall in turn (L S+ D D E). Under the area light the path
/// tracer reaches both by BSDF sampling through the ball.
fn ball_room(lamp: Lamp, size: u32) -> Scene {
    let mut b = SceneBuilder::new("ball-room");
    let floor = common::add_floor(&mut b, 0.8);
    b.add_shape(
        common::quad(
            Affine3A::from_translation(Vec3::new(0.0, 1.0, -0.8))
                * Affine3A::from_scale(Vec3::new(2.0, 1.0, 1.0)),
        ),
        floor,
        None,
        false,
    )
    .unwrap();
    common::add_glass_ball(&mut b);
    match lamp {
        Lamp::Point => b.add_light(Light::Point(PointLight::new(
            Vec3::new(0.0, 4.0, 0.0),
            Spectrum::splat(20.0),
        ))),
        Lamp::Area => {
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
        }
    }
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

/// What the tests measure: the mean luminance of a 7 × 7 window around the caustic under the
/// ball, of two windows on the wall beside the ball (lit by the caustic in turn, L S+ D D E, and
/// directly), and of the whole image.
const MEASURES: [&str; 3] = ["caustic window", "wall windows", "whole image"];

fn measures(scene: &Scene, img: &Image) -> [f64; 3] {
    let window = |p: Vec3| {
        let cs = scene
            .camera
            .sample_wi(p, Vec2::splat(0.5))
            .expect("the point is in view");
        let (x, y) = (cs.raster.x as usize, cs.raster.y as usize);
        common::lum_arr(common::region_mean(img, x - 3, y - 3, x + 4, y + 4))
    };
    let wall = 0.5 * (window(Vec3::new(1.0, 0.3, -0.8)) + window(Vec3::new(-1.0, 0.3, -0.8)));
    [window(Vec3::ZERO), wall, common::mean_lum(img)]
}

/// Mean and standard error over four seeds of each measure.
fn over_seeds(
    scene: &Scene,
    kind: IntegratorKind,
    make: impl Fn(u64) -> RenderOptions,
) -> [(f64, f64); 3] {
    let runs: Vec<[f64; 3]> = (1..=4)
        .map(|seed| measures(scene, &run(scene, kind, &make(seed))))
        .collect();
    let n = runs.len() as f64;
    [0, 1, 2].map(|k| {
        let mean = runs.iter().map(|r| r[k]).sum::<f64>() / n;
        let var = runs.iter().map(|r| (r[k] - mean).powi(2)).sum::<f64>() / (n - 1.0);
        (mean, (var / n).sqrt())
    })
}

/// 4 standard errors of the difference of two four-seed means, floored at 0.3 % of `a`.
fn tolerance((a, sa): (f64, f64), (_, sb): (f64, f64)) -> f64 {
    4.0 * (sa * sa + sb * sb).sqrt() + 0.003 * a
}

/// Under an area light the path tracer renders every path, the caustics by BSDF sampling through
/// the ball: the hybrid must agree with it everywhere, which it cannot if its camera side counts
/// the light tracer's paths a second time.
#[test]
fn under_an_area_light_the_hybrid_is_the_path_tracer_without_double_counting() {
    let scene = ball_room(Lamp::Area, 48);
    let path = over_seeds(&scene, IntegratorKind::Path, |s| opts(256, s));
    let hybrid = over_seeds(&scene, IntegratorKind::Hybrid, |s| opts(64, 100 + s));
    // The caustic alone, as a light tracer renders it: a lower bound of what counting the light
    // tracer's paths twice would add.
    let caustic_only = measures(
        &scene,
        &run(
            &scene,
            IntegratorKind::LightTrace,
            &RenderOptions {
                caustics_only: true,
                ..opts(64, 9)
            },
        ),
    );
    for (k, what) in MEASURES.iter().enumerate() {
        let ((p, sp), (h, sh)) = (path[k], hybrid[k]);
        let tol = tolerance(path[k], hybrid[k]);
        assert!(
            (h - p).abs() < tol,
            "{what}: hybrid {h:.5} ± {sh:.5}, path tracer {p:.5} ± {sp:.5} (tolerance {tol:.5})"
        );
    }
    // The test can see double counting: the caustic is far above the tolerance.
    let tol = tolerance(path[0], hybrid[0]);
    assert!(
        caustic_only[0] > 3.0 * tol,
        "the caustic ({:.5}) is within the tolerance {tol:.5}: the scene cannot tell double counting",
        caustic_only[0]
    );
}

/// Under a point light the path tracer finds no path through the ball; the light tracer finds
/// every path whose camera end is diffuse. On the floor and the wall (not the ball, which the
/// light tracer leaves black) the hybrid must agree with it: the caustic and its reflection onto
/// the wall (L S+ D D E), which the light tracer half must count since the path tracer cannot.
#[test]
fn under_a_point_light_the_hybrid_is_the_light_tracer() {
    let scene = ball_room(Lamp::Point, 48);
    let lt = over_seeds(&scene, IntegratorKind::LightTrace, |s| opts(256, s));
    let hybrid = over_seeds(&scene, IntegratorKind::Hybrid, |s| opts(64, 100 + s));
    let path = measures(&scene, &run(&scene, IntegratorKind::Path, &opts(256, 9)));
    for k in 0..2 {
        let ((l, sl), (h, sh)) = (lt[k], hybrid[k]);
        let tol = tolerance(lt[k], hybrid[k]);
        assert!(
            (h - l).abs() < tol,
            "{}: hybrid {h:.5} ± {sh:.5}, light tracer {l:.5} ± {sl:.5} (tolerance {tol:.5})",
            MEASURES[k]
        );
        // What the light tracer half adds there (the path tracer's blind spot) is far above
        // the tolerance, so a half that missed it (the caustics alone) fails.
        assert!(
            l - path[k] > 3.0 * tol,
            "{}: the light tracer's own paths ({:.5}) are within the tolerance {tol:.5}",
            MEASURES[k],
            l - path[k]
        );
    }
}

/// A spot light whose whole cone falls on a mirror, which reflects it onto a diffuse wall: every
/// light path starts L S. The wall's bright spot is a caustic seen directly (L S D E); the floor
/// in front is lit only by that spot's diffuse reflection (L S D D E), which a path tracer cannot
/// find and the caustics-only light tracer does not connect.
fn periscope(size: u32) -> Scene {
    let mut b = SceneBuilder::new("periscope");
    let white = common::diffuse(&mut b, "white", 0.8);
    b.add_shape(
        common::quad(
            Affine3A::from_rotation_x(-std::f32::consts::FRAC_PI_2)
                * Affine3A::from_scale(Vec3::splat(2.0)),
        ),
        white,
        None,
        false,
    )
    .unwrap();
    b.add_shape(
        common::quad(
            Affine3A::from_translation(Vec3::new(0.0, 1.0, -1.0))
                * Affine3A::from_scale(Vec3::new(2.0, 1.0, 1.0)),
        ),
        white,
        None,
        false,
    )
    .unwrap();
    let mirror = b
        .add_material(
            "mirror",
            Material::Mirror {
                reflectance: Spectrum::splat(0.9),
            },
        )
        .unwrap();
    // Normal (0, √½, −√½): the spot's downward beam leaves toward −z, onto the wall at y = 1.
    b.add_shape(
        common::quad(
            Affine3A::from_translation(Vec3::new(0.0, 1.0, 0.0))
                * Affine3A::from_rotation_x(-0.75 * std::f32::consts::PI)
                * Affine3A::from_scale(Vec3::splat(0.3)),
        ),
        mirror,
        None,
        false,
    )
    .unwrap();
    b.add_light(Light::Spot(SpotLight::new(
        Vec3::new(0.0, 2.0, 0.0),
        Vec3::NEG_Y,
        Spectrum::splat(50.0),
        10.0,
        10.0,
    )));
    b.set_camera(caustica_scene::camera::PerspectiveCamera::look_at(
        Vec3::new(0.0, 1.2, 3.5),
        Vec3::new(0.0, 0.4, 0.0),
        Vec3::Y,
        50.0,
        size,
        size,
    ));
    b.build().unwrap()
}

#[test]
fn the_light_tracer_half_counts_the_diffuse_reflections_of_caustics() {
    let scene = periscope(32);
    // The floor in front of the mirror (L S D D E only) and the spot on the wall (L S D E).
    let probes = [
        Vec3::new(0.8, 0.0, 1.0),
        Vec3::new(-0.8, 0.0, 1.0),
        Vec3::new(0.0, 0.0, 1.5),
        Vec3::new(0.0, 1.0, -1.0),
    ];
    let windows = |img: &Image| -> [f64; 2] {
        let w = |p: Vec3| {
            let cs = scene
                .camera
                .sample_wi(p, Vec2::splat(0.5))
                .expect("in view");
            let (x, y) = (cs.raster.x as usize, cs.raster.y as usize);
            common::lum_arr(common::region_mean(img, x - 2, y - 2, x + 3, y + 3))
        };
        [
            (w(probes[0]) + w(probes[1]) + w(probes[2])) / 3.0,
            w(probes[3]),
        ]
    };
    let stats = |kind, spp, seed0| -> [(f64, f64); 2] {
        let runs: Vec<[f64; 2]> = (0..4u64)
            .map(|s| windows(&run(&scene, kind, &opts(spp, seed0 + s))))
            .collect();
        [0, 1].map(|k| {
            let mean = runs.iter().map(|r| r[k]).sum::<f64>() / 4.0;
            let var = runs.iter().map(|r| (r[k] - mean).powi(2)).sum::<f64>() / 3.0;
            (mean, (var / 4.0).sqrt())
        })
    };
    let lt = stats(IntegratorKind::LightTrace, 256, 1);
    let hybrid = stats(IntegratorKind::Hybrid, 64, 101);
    let path = windows(&run(&scene, IntegratorKind::Path, &opts(64, 9)));
    for (k, what) in ["floor (L S D D E)", "wall spot (L S D E)"]
        .iter()
        .enumerate()
    {
        let ((l, sl), (h, sh)) = (lt[k], hybrid[k]);
        let tol = tolerance(lt[k], hybrid[k]);
        assert!(
            (h - l).abs() < tol,
            "{what}: hybrid {h:.5} ± {sh:.5}, light tracer {l:.5} ± {sl:.5} (tolerance {tol:.5})"
        );
        // Light only the light tracer finds: the path tracer sees none of it.
        assert!(
            l > 3.0 * tol,
            "{what}: {l:.5} is within the tolerance {tol:.5}"
        );
        assert!(
            path[k] < 1e-3 * l,
            "{what}: the path tracer finds {}",
            path[k]
        );
    }
}

#[test]
fn the_hybrid_is_deterministic_and_shards_by_light_paths_and_rows() {
    let scene = ball_room(Lamp::Area, 24);
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
    let scene = ball_room(Lamp::Area, 8);
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
