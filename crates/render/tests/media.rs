//! Participating media, end to end: the volumetric white furnace (a non-absorbing medium in a
//! constant environment looks exactly like the environment) and analytic single scattering of a
//! collimated beam seen side-on (seed notes test TM5), for the volumetric path tracer and the
//! light tracer.

mod common;

use caustica_core::image_io::Image;
use caustica_core::{Affine3A, Spectrum, Vec2, Vec3};
use caustica_render::{IntegratorKind, PathLimits, RenderControl, RenderOptions, render};
use caustica_scene::camera::PerspectiveCamera;
use caustica_scene::intersection::NONE;
use caustica_scene::light::{BeamLight, EnvironmentLight, Light};
use caustica_scene::material::Material;
use caustica_scene::medium::{DensityGrid, Medium, MediumInterface};
use caustica_scene::phase::PhaseFunction;
use caustica_scene::shape::{ShapeGeometry, Sphere};
use caustica_scene::{Scene, SceneBuilder};

/// Adds a sphere of `radius` at the origin made of `boundary`, holding medium `m` (vacuum
/// outside).
fn add_medium_sphere(b: &mut SceneBuilder, radius: f32, boundary: u32, m: u32) {
    b.add_shape_with_media(
        ShapeGeometry::Sphere(Sphere {
            center: Vec3::ZERO,
            radius,
        }),
        boundary,
        None,
        false,
        MediumInterface {
            inside: m,
            outside: NONE,
        },
    )
    .unwrap();
}

/// A sphere of radius 1 at the origin bounded by a `null` surface, filled with `medium`, in a
/// constant environment of radiance 1, seen from outside.
fn furnace(medium: Medium) -> Scene {
    furnace_in(medium, Material::Null)
}

/// [`furnace`] with the sphere's surface made of `boundary` (a dielectric: murky water).
fn furnace_in(medium: Medium, boundary: Material) -> Scene {
    let mut b = SceneBuilder::new("volumetric furnace");
    let null = b.add_material("boundary", boundary).unwrap();
    let m = b.add_medium("fog", medium).unwrap();
    add_medium_sphere(&mut b, 1.0, null, m);
    b.add_light(Light::Environment(EnvironmentLight::constant(
        Spectrum::ONE,
    )));
    b.set_camera(PerspectiveCamera::look_at(
        Vec3::new(0.0, 0.0, 3.0),
        Vec3::ZERO,
        Vec3::Y,
        30.0,
        12,
        12,
    ));
    b.build().unwrap()
}

/// A grid density on the unit sphere's bounding box: 0.2–1.8 varying in x, y, z.
fn lumpy_grid() -> DensityGrid {
    DensityGrid::from_fn(
        [16, 16, 16],
        Affine3A::from_scale_rotation_translation(
            Vec3::splat(2.0),
            caustica_core::Affine3A::IDENTITY
                .to_scale_rotation_translation()
                .1,
            Vec3::splat(-1.0),
        ),
        |u| 1.0 + 0.8 * (7.0 * u.x).sin() * (5.0 * u.y).cos() * (3.0 * u.z + 1.0).sin(),
    )
    .unwrap()
}

/// Checks that each channel of an image whose pixels all have expectation 1 has mean 1 within
/// 5σ/√n, σ the spread of its pixels (their noise).
fn assert_furnace(img: &Image, what: &str) {
    for c in 0..3 {
        let v: Vec<f64> = img.data.iter().map(|p| p[c] as f64).collect();
        let n = v.len() as f64;
        let mean = v.iter().sum::<f64>() / n;
        let sigma = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        assert!(sigma < 0.2, "{what} channel {c}: noise {sigma}");
        assert!(
            (mean - 1.0).abs() < 5.0 * sigma / n.sqrt() + 1e-3,
            "{what} channel {c}: image mean {mean} (σ {sigma})"
        );
    }
}

#[test]
fn murky_water_in_a_white_furnace_is_one_everywhere() {
    // A dielectric sphere (IOR 1.33) holding a non-absorbing medium, in a constant environment
    // of radiance 1: a closed lossless system in equilibrium looks like its surroundings, the η²
    // of radiance inside the water undone on the way out. Tests rays that refract into a
    // medium, scatter there, meet total internal reflection and leave.
    for phase in [
        PhaseFunction::default(),
        PhaseFunction::henyey_greenstein(0.5).unwrap(),
    ] {
        let medium = Medium::homogeneous(Spectrum::ZERO, Spectrum::splat(1.2), phase);
        let scene = furnace_in(
            medium,
            Material::Dielectric {
                ior: 1.33,
                absorption: Spectrum::ZERO,
                dispersion: None,
            },
        );
        let img = common::render_image_depth(&scene, IntegratorKind::Path, 256, 5, 1000);
        assert_furnace(&img, &format!("murky water {phase:?}"));
    }
    // The rays do enter the water's medium: with absorption the sphere darkens (the centre
    // pixels see it), where clear water would stay at 1.
    let absorbing = Medium::homogeneous(
        Spectrum::splat(1.0),
        Spectrum::splat(0.2),
        PhaseFunction::default(),
    );
    let scene = furnace_in(
        absorbing,
        Material::Dielectric {
            ior: 1.33,
            absorption: Spectrum::ZERO,
            dispersion: None,
        },
    );
    let img = common::render_image_depth(&scene, IntegratorKind::Path, 64, 5, 1000);
    let data = &img.data;
    let centre = (5..7)
        .flat_map(|y| (5..7).map(move |x| data[y * 12 + x][1] as f64))
        .sum::<f64>()
        / 4.0;
    assert!(centre < 0.7, "absorbing water looks {centre}");
}

#[test]
fn volumetric_white_furnace_is_one_everywhere() {
    // Albedo 1 (σ_a = 0), optical radius 1.5 (homogeneous) or up to 2.7 (grid), chromatic
    // σ_s so that spectral MIS is exercised: every channel of every pixel must be 1.
    let sigma_s = Spectrum::new(0.8, 1.5, 2.2);
    for phase in [
        PhaseFunction::default(),
        PhaseFunction::henyey_greenstein(0.6).unwrap(),
        PhaseFunction::henyey_greenstein(-0.4).unwrap(),
    ] {
        for grid in [false, true] {
            let medium = if grid {
                Medium::grid(lumpy_grid(), Spectrum::ZERO, sigma_s, phase)
            } else {
                Medium::homogeneous(Spectrum::ZERO, sigma_s, phase)
            };
            let scene = furnace(medium);
            // The camera is outside, the sphere fills the centre of the image.
            assert_eq!(scene.camera_medium, NONE);
            let img = common::render_image_depth(&scene, IntegratorKind::Path, 256, 3, 1000);
            // Every pixel has the same expectation (1), so the spread of the pixels is the
            // per-pixel noise σ; blocks of 4×4 pixels must agree with 1 within 5σ/4 and the
            // whole image within 5σ/√n, per channel.
            for c in 0..3 {
                let v: Vec<f64> = img.data.iter().map(|p| p[c] as f64).collect();
                let n = v.len() as f64;
                let mean = v.iter().sum::<f64>() / n;
                let sigma = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
                assert!(
                    sigma < 0.2,
                    "{phase:?} grid {grid} channel {c}: noise {sigma}"
                );
                assert!(
                    (mean - 1.0).abs() < 5.0 * sigma / n.sqrt() + 1e-3,
                    "{phase:?} grid {grid} channel {c}: image mean {mean} (σ {sigma})"
                );
                for by in 0..3 {
                    for bx in 0..3 {
                        let mut s = 0.0;
                        for y in by * 4..by * 4 + 4 {
                            for x in bx * 4..bx * 4 + 4 {
                                s += v[y * 12 + x];
                            }
                        }
                        let m = s / 16.0;
                        assert!(
                            (m - 1.0).abs() < 5.0 * sigma / 4.0 + 1e-3,
                            "{phase:?} grid {grid} channel {c} block ({bx}, {by}): {m} (σ {sigma})"
                        );
                    }
                }
            }
        }
    }
}

/// TM5: a collimated beam of radius R and irradiance E₀ shining down (−y) from the aperture at
/// y = 1 through a homogeneous medium (σ_s, σ_t, isotropic) that also holds the camera, which
/// looks along −z at the beam from z = 2. Single scattering only (paths of two edges).
struct Beam {
    sigma_s: f32,
    sigma_t: f32,
    radius: f32,
    e0: f32,
    top: f32,
}

const BEAM: Beam = Beam {
    sigma_s: 0.8,
    sigma_t: 1.0,
    radius: 0.3,
    e0: 1.0,
    top: 1.0,
};

fn beam_scene(size: u32, sphere: f32) -> Scene {
    let mut b = SceneBuilder::new("beam");
    let null = b.add_material("boundary", Material::Null).unwrap();
    let m = b
        .add_medium(
            "medium",
            Medium::homogeneous(
                Spectrum::splat(BEAM.sigma_t - BEAM.sigma_s),
                Spectrum::splat(BEAM.sigma_s),
                PhaseFunction::default(),
            ),
        )
        .unwrap();
    add_medium_sphere(&mut b, sphere, null, m);
    b.add_light(Light::Beam(BeamLight::new(
        Vec3::new(0.0, BEAM.top, 0.0),
        -Vec3::Y,
        BEAM.radius,
        Spectrum::splat(BEAM.e0),
    )));
    b.set_camera(PerspectiveCamera::look_at(
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::ZERO,
        Vec3::Y,
        20.0,
        size,
        size,
    ));
    b.build().unwrap()
}

/// L along `ray`: ∫ σ_s/(4π) E₀ e^{−σ_t (top − y)} e^{−σ_t t} dt over the part of the ray inside
/// the beam (seed notes TM5, here by quadrature along the ray), with the medium filling the
/// sphere of radius `rm` around the origin (distances counted inside it only).
fn single_scattering(o: Vec3, d: Vec3, rm: f64) -> f64 {
    let n = 4000;
    let t_max = 4.0f64;
    let h = t_max / n as f64;
    let mut s = 0.0f64;
    let mut t_in = None;
    for i in 0..n {
        let t = (i as f64 + 0.5) * h;
        let x = o.as_dvec3() + d.as_dvec3() * t;
        if x.length() >= rm {
            continue;
        }
        let t0 = *t_in.get_or_insert(t - 0.5 * h);
        let r2 = x.x * x.x + x.z * x.z;
        if r2 < (BEAM.radius as f64).powi(2) && x.y < BEAM.top as f64 {
            let top = (BEAM.top as f64).min((rm * rm - r2).max(0.0).sqrt());
            let inside = (top - x.y).max(0.0) + (t - t0);
            s += (-(BEAM.sigma_t as f64) * inside).exp();
        }
    }
    s * h * BEAM.sigma_s as f64 * BEAM.e0 as f64 / (4.0 * std::f64::consts::PI)
}

/// [`single_scattering`] averaged over 4×4 rays per pixel of `scene`'s camera (a box filter's
/// pixel values), row by row.
fn expected_pixels(scene: &Scene, rm: f64) -> Vec<f64> {
    let cam = &scene.camera;
    (0..cam.width * cam.height)
        .map(|i| {
            let (x, y) = (i % cam.width, i / cam.width);
            let mut s = 0.0;
            for a in 0..4 {
                for b in 0..4 {
                    let raster = Vec2::new(
                        x as f32 + (a as f32 + 0.5) / 4.0,
                        y as f32 + (b as f32 + 0.5) / 4.0,
                    );
                    let r = cam.generate_ray(raster, Vec2::splat(0.5)).ray;
                    s += single_scattering(r.o, r.d, rm);
                }
            }
            s / 16.0
        })
        .collect()
}

#[test]
fn single_scattering_of_a_beam_matches_the_closed_form() {
    // The camera and the beam's aperture inside the medium (a sphere of radius 20), then both
    // outside it (radius 0.9): connections cross the null boundary.
    for sphere in [20.0f32, 0.9] {
        single_scattering_case(sphere);
    }
}

fn single_scattering_case(sphere: f32) {
    let size = 16u32;
    let scene = beam_scene(size, sphere);
    let inside = sphere > 5.0;
    assert_eq!(scene.camera_medium != NONE, inside, "camera medium");
    assert_eq!(scene.light_media[0] != NONE, inside, "beam medium");
    // Expected pixel values: the integral averaged over 4×4 rays per pixel (box filter).
    let mut scene_box = scene;
    scene_box.settings.filter = caustica_scene::scene::FilterKind::Box;
    let expected = expected_pixels(&scene_box, sphere as f64);
    let peak = expected.iter().copied().fold(0.0, f64::max);
    assert!(peak > 1e-3, "the beam is in view ({peak})");
    for (kind, spp) in [
        (IntegratorKind::Path, 256),
        (IntegratorKind::LightTrace, 512),
    ] {
        // Two independent renders measure the noise of each 4×4 block.
        let imgs: Vec<Image> = (0..2)
            .map(|seed| common::render_image_depth(&scene_box, kind, spp, 10 + seed, 2))
            .collect();
        let block = |img: &Image, bx: u32, by: u32| {
            let mut s = 0.0f64;
            for y in by * 4..by * 4 + 4 {
                for x in bx * 4..bx * 4 + 4 {
                    s += img.data[(y * size + x) as usize][1] as f64;
                }
            }
            s / 16.0
        };
        let (mut got, mut want) = (0.0, 0.0);
        for by in 0..size / 4 {
            for bx in 0..size / 4 {
                let e: f64 = (by * 4..by * 4 + 4)
                    .flat_map(|y| (bx * 4..bx * 4 + 4).map(move |x| (x, y)))
                    .map(|(x, y)| expected[(y * size + x) as usize])
                    .sum::<f64>()
                    / 16.0;
                let (a, b) = (block(&imgs[0], bx, by), block(&imgs[1], bx, by));
                let mean = 0.5 * (a + b);
                // σ of the mean of two from their difference; floor at 1 % of the peak.
                let sigma = ((a - b).abs() / 2.0).max(0.01 * peak);
                assert!(
                    (mean - e).abs() < 5.0 * sigma,
                    "{kind:?} block ({bx}, {by}): {mean} vs closed form {e}"
                );
                got += mean;
                want += e;
            }
        }
        assert!(
            (got / want - 1.0).abs() < 0.02,
            "{kind:?}: total {got} vs closed form {want}"
        );
    }
}

#[test]
fn volume_photon_estimates_of_single_scattering_approach_the_closed_form() {
    // TM5 for the density estimates: with single scattering only (max depth 2, so the volume
    // photons are first scatterings), the beam estimate and the ray-marched one tend to the
    // closed form as the photon count grows: the error over the pixels shrinks. The beam
    // estimate (a kernel estimate: each photon's flux is spread, not created) keeps the total
    // within 3 %; the march's k-NN estimate (eq. 8.3) is biased bright (Σ of k photons over the
    // ball reaching the k-th, and the long tails of k-NN estimates outside the beam), less so as
    // the photons grow: about +11 % at 25 000 photons, +6 % at 400 000.
    let size = 16u32;
    let mut scene = beam_scene(size, 20.0);
    scene.settings.filter = caustica_scene::scene::FilterKind::Box;
    let cam = &scene.camera;
    let expected: Vec<f64> = (0..size * size)
        .map(|i| {
            let (x, y) = (i % size, i / size);
            let r = cam
                .generate_ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5), Vec2::splat(0.5))
                .ray;
            single_scattering(r.o, r.d, 20.0)
        })
        .collect();
    let want: f64 = expected.iter().sum();
    for kind in [
        IntegratorKind::BeamRadianceEstimate,
        IntegratorKind::VolumetricPhotonMapping,
    ] {
        let mut errs = Vec::new();
        for n in [25_000usize, 200_000] {
            let mut opts = RenderOptions {
                spp: 1,
                seed: 3,
                limits: PathLimits {
                    max_depth: 2,
                    ..PathLimits::default()
                },
                ..Default::default()
            };
            opts.photons.volume.photons = n;
            opts.photons.light_paths = Some(1000);
            opts.photons.global_photons = 0;
            let img = render(&scene, kind, &opts, &RenderControl::silent())
                .expect("valid options")
                .film
                .to_image();
            let got: f64 = img.data.iter().map(|p| p[1] as f64).sum();
            let err: f64 = img
                .data
                .iter()
                .zip(&expected)
                .map(|(p, e)| (p[1] as f64 - e).abs())
                .sum::<f64>()
                / want;
            errs.push((got / want - 1.0, err));
        }
        assert!(
            errs[1].1 < errs[0].1,
            "{kind:?}: relative L1 errors {errs:?}"
        );
        let tolerance = if kind == IntegratorKind::BeamRadianceEstimate {
            0.03
        } else {
            0.1
        };
        assert!(errs[1].0.abs() < tolerance, "{kind:?}: totals {errs:?}");
    }
}

#[test]
fn volume_photon_differentials_follow_the_volume_photons_with_the_beams_cross_section() {
    // The differential tracer walks the volume photon tracer's paths (same stream, same
    // events, same flux). With single scattering from the collimated beam (D_ω = 0, eq. 2–6 of
    // seed 002 on the aperture) the free flight keeps D_u x, D_v x (eq. 8.21 with dω = 0), so
    // every first-scatter kernel is the ball of diameter 2 s R/√N (sec. 8.4's D_w x = max):
    // V = (π/6) d³ (eq. 8.16).
    use caustica_render::Smoothing;
    use caustica_render::photon::differential::volume_trace::{
        KernelRule, trace_volume_differentials,
    };
    use caustica_render::photon::plan::PhotonBudget;
    use caustica_render::photon::tracer::{MapKind, trace_photons};
    let scene = beam_scene(8, 20.0);
    let opts = RenderOptions {
        seed: 5,
        limits: PathLimits {
            max_depth: 2,
            ..PathLimits::default()
        },
        ..Default::default()
    };
    let s = 3.0f32;
    let budget = PhotonBudget::Records(5000);
    let d = trace_volume_differentials(
        &scene,
        budget,
        Smoothing::new(s).unwrap(),
        KernelRule::default(),
        0x77,
        &opts,
        &mut |_| true,
    );
    let plain = trace_photons(&scene, budget, MapKind::Volume, 0x77, &opts, &mut |_| true);
    assert_eq!(
        (d.paths, d.photons.len()),
        (plain.paths, plain.photons.len())
    );
    assert_eq!((d.collapsed, d.failed), (0, 0));
    for (a, b) in d.photons.iter().zip(&plain.photons) {
        assert_eq!((a.p, a.wi, a.flux), (b.p, b.wi, b.flux));
    }
    let diameter = 2.0 * s * BEAM.radius / (d.paths as f32).sqrt();
    let want = std::f32::consts::PI / 6.0 * diameter.powi(3);
    for k in &d.kernels {
        let v = 1.0 / k.inv_volume;
        assert!((v - want).abs() < 1e-3 * want, "V = {v}, want {want}");
        assert!((k.bound - diameter / 2.0).abs() < 1e-3 * diameter);
    }
    // With multiple scattering (isotropic: k ≡ 1, a rotation) the kernels keep that size.
    let deep = RenderOptions {
        limits: PathLimits::default(),
        ..opts
    };
    let d = trace_volume_differentials(
        &scene,
        budget,
        Smoothing::new(s).unwrap(),
        KernelRule::default(),
        0x77,
        &deep,
        &mut |_| true,
    );
    let diameter = 2.0 * s * BEAM.radius / (d.paths as f32).sqrt();
    let want = std::f32::consts::PI / 6.0 * diameter.powi(3);
    assert!(d.photons.iter().any(|p| p.depth > 2));
    for k in &d.kernels {
        assert!((1.0 / k.inv_volume - want).abs() < 2e-3 * want);
    }
}

#[test]
fn spread_collimated_photons_grow_after_their_first_scattering_only() {
    // The extension `--spread-collimated S`: a beam's photons keep the beam's ball at their
    // first scattering event (stored before any scattering), and once scattered they spread
    // like a point light's (eq. 6 with ω_e = 4π at smoothing S): no later kernel is smaller than
    // the beam's ball, and the typical one is far larger. Without it every kernel keeps the
    // beam's size (previous test).
    use caustica_render::Smoothing;
    use caustica_render::photon::differential::volume_trace::{
        KernelRule, trace_volume_differentials,
    };
    use caustica_render::photon::plan::PhotonBudget;
    let scene = beam_scene(8, 20.0);
    let opts = RenderOptions {
        seed: 5,
        ..Default::default()
    };
    let s = 3.0f32;
    let trace = |spread: Option<f32>| {
        trace_volume_differentials(
            &scene,
            PhotonBudget::Records(5000),
            Smoothing::new(s).unwrap(),
            KernelRule {
                spread_collimated: spread.map(|x| Smoothing::new(x).unwrap()),
                ..KernelRule::default()
            },
            0x77,
            &opts,
            &mut |_| true,
        )
    };
    let (plain, spread) = (trace(None), trace(Some(2.0)));
    assert_eq!(plain.photons.len(), spread.photons.len());
    let diameter = 2.0 * s * BEAM.radius / (spread.paths as f32).sqrt();
    let ball = std::f32::consts::PI / 6.0 * diameter.powi(3);
    let first = spread.photons.iter().map(|p| p.depth).min().unwrap();
    let mut later = Vec::new();
    for ((p, k), k0) in spread
        .photons
        .iter()
        .zip(&spread.kernels)
        .zip(&plain.kernels)
    {
        let v = 1.0 / k.inv_volume;
        if p.depth == first {
            assert_eq!(k, k0, "first-scattering kernels are the thesis's");
        } else {
            assert!(
                v >= ball * (1.0 - 1e-3),
                "V = {v} below the beam's ball {ball}"
            );
            later.push(v / ball);
        }
    }
    assert!(
        later.len() > 100,
        "{} multiply scattered photons",
        later.len()
    );
    later.sort_by(f32::total_cmp);
    let median = later[later.len() / 2];
    assert!(
        median > 10.0,
        "median later kernel only {median}× the beam's ball"
    );
}

#[test]
fn volume_photon_differentials_of_single_scattering_match_the_closed_form() {
    // TM5 for vpd: each photon's flux is spread over its ellipsoid (eq. 8.16's V with the mean-1
    // kernel), so the total over the image is the closed form's within the noise, at two photon
    // counts; and no pixel is NaN. With seed 002's scaling the kernels shrink as 1/√N, so the
    // number of kernels a ray crosses (about s² times the ray's length in the beam over the
    // beam's length) does not grow with N: the noise per camera ray is set by s, the bias by N.
    let size = 16u32;
    let mut scene = beam_scene(size, 20.0);
    scene.settings.filter = caustica_scene::scene::FilterKind::Box;
    let want: f64 = expected_pixels(&scene, 20.0).iter().sum();
    for n in [25_000usize, 100_000] {
        let mut opts = RenderOptions {
            spp: 16,
            seed: 3,
            limits: PathLimits {
                max_depth: 2,
                ..PathLimits::default()
            },
            ..Default::default()
        };
        opts.photons.volume.photons = n;
        opts.photons.volume.smoothing = Some(caustica_render::Smoothing::new(6.0).unwrap());
        opts.photons.light_paths = Some(1000);
        opts.photons.global_photons = 0;
        let img = render(
            &scene,
            IntegratorKind::VolumePhotonDifferentials,
            &opts,
            &RenderControl::silent(),
        )
        .expect("valid options")
        .film
        .to_image();
        assert!(img.data.iter().all(|p| p.iter().all(|c| c.is_finite())));
        let got: f64 = img.data.iter().map(|p| p[1] as f64).sum();
        assert!(
            (got / want - 1.0).abs() < 0.03,
            "{n} photons: total {got} vs closed form {want}"
        );
    }
}

#[test]
fn volume_photon_differentials_survive_thousands_of_scatterings() {
    // Bad input of the vpd issue: photons that scatter thousands of times (a dense, strongly
    // forward-scattering, non-absorbing sphere: optical radius 40, HG g = 0.9, so √k scales the
    // vectors at every event), and grazing rays through the resulting thin kernels. Defined
    // behaviour: every pixel finite, the dropped photons counted in the notes.
    let scene = furnace(Medium::homogeneous(
        Spectrum::ZERO,
        Spectrum::splat(40.0),
        PhaseFunction::henyey_greenstein(0.9).unwrap(),
    ));
    let mut opts = RenderOptions {
        spp: 2,
        seed: 9,
        limits: PathLimits {
            max_depth: u32::MAX,
            ..PathLimits::default()
        },
        volume_only: true,
        ..Default::default()
    };
    opts.photons.volume.photons = 20_000;
    opts.photons.volume.smoothing = Some(caustica_render::Smoothing::new(2.0).unwrap());
    // The image (finite everywhere) and the notes' line on the photon differentials.
    let run = |opts: &RenderOptions| {
        let out = render(
            &scene,
            IntegratorKind::VolumePhotonDifferentials,
            opts,
            &RenderControl::silent(),
        )
        .expect("valid options");
        let img = out.film.to_image();
        assert!(img.data.iter().all(|p| p.iter().all(|c| c.is_finite())));
        let note = out
            .notes
            .into_iter()
            .find(|n| n.starts_with("volume photon differentials"))
            .expect("the notes count the photon differentials");
        (img, note)
    };
    let (img, note) = run(&opts);
    assert!(img.data.iter().any(|p| p[1] > 0.0), "the sphere is lit");
    // HG's area factors have E[k] = 1 but E[ln k] < 0: over thousands of events the vectors
    // shrink until the kernels are flat, which are dropped and counted.
    assert!(!note.contains(" 0 dropped with a flat kernel"), "{note}");
    // The minimum semi-axis keeps them (widened, counted), and the image stays finite.
    opts.photons.volume.min_semi_axis = Some(0.01);
    let (_, note) = run(&opts);
    assert!(note.contains(" 0 dropped with a flat kernel"), "{note}");
    assert!(
        note.contains("widened to the minimum semi-axis 0.01 m"),
        "{note}"
    );
}

#[test]
fn vpd_gives_the_same_bytes_for_any_thread_count() {
    // Multiple scattering, the kernels built in parallel and collected in path order; and the
    // extensions (kernels renormalised in parallel, each from its own random rotation, in a
    // medium sphere small enough that the null boundary cuts them; collimated photons spread).
    let run = |scene: &Scene, threads: usize, seed: u64, extensions: bool| {
        let mut opts = RenderOptions {
            spp: 2,
            seed,
            ..Default::default()
        };
        opts.photons.volume.photons = 20_000;
        opts.photons.light_paths = Some(1000);
        opts.photons.global_photons = 1000;
        opts.photons.final_gather = 1;
        if extensions {
            opts.photons.volume.boundary =
                caustica_render::photon::kernel_boundary::KernelBoundary::Renormalised;
            opts.photons.volume.spread_collimated =
                Some(caustica_render::Smoothing::new(2.0).unwrap());
        }
        let img = common::with_threads(threads, || {
            render(
                scene,
                IntegratorKind::VolumePhotonDifferentials,
                &opts,
                &RenderControl::silent(),
            )
            .expect("valid options")
            .film
            .to_image()
        });
        img.data
            .iter()
            .flat_map(|p| p.map(f32::to_bits))
            .collect::<Vec<u32>>()
    };
    let scene = beam_scene(12, 20.0);
    let (a, b, c) = (
        run(&scene, 1, 4, false),
        run(&scene, 2, 4, false),
        run(&scene, 2, 5, false),
    );
    assert_eq!(a, b, "1 and 2 threads differ");
    assert_ne!(a, c, "the seed has no effect");
    let small = beam_scene(12, 0.8);
    let (a, b, plain) = (
        run(&small, 1, 4, true),
        run(&small, 2, 4, true),
        run(&small, 2, 4, false),
    );
    assert_eq!(a, b, "1 and 2 threads differ with the extensions");
    assert_ne!(a, plain, "the extensions have no effect");
}
