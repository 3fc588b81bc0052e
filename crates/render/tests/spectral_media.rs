//! Participating media in spectral mode: a grey fog renders the same in RGB and spectral mode;
//! a chromatic absorbing medium transmits the CIE integral of its upsampled spectrum (computed
//! here independently by quadrature), not the RGB exponentials; every integrator that renders
//! media gives the same bytes for 1 and 2 threads in spectral mode.

mod common;

use caustica_core::spectral::RgbUnbounded;
use caustica_core::spectral::cie::{CIE_Y_INTEGRAL, cie_xyz, d65_n, xyz_to_linear_srgb};
use caustica_core::{Affine3A, Spectrum, Vec3};
use caustica_render::{IntegratorKind, RenderControl, RenderOptions, render};
use caustica_scene::camera::PerspectiveCamera;
use caustica_scene::intersection::NONE;
use caustica_scene::material::Material;
use caustica_scene::medium::{Medium, MediumInterface};
use caustica_scene::phase::PhaseFunction;
use caustica_scene::shape::{ShapeGeometry, Sphere};
use caustica_scene::{Scene, SceneBuilder};
use std::f32::consts::FRAC_PI_2;

/// Per channel: the mean image value over `seeds` seeds from `first_seed` and its standard
/// error (from the seeds' spread).
fn seeds_mean(
    scene: &Scene,
    kind: IntegratorKind,
    spp: u32,
    first_seed: u64,
    seeds: u64,
) -> [(f64, f64); 3] {
    let runs: Vec<[f64; 3]> = (0..seeds)
        .map(|i| {
            let mut opts = RenderOptions {
                spp,
                seed: first_seed + i,
                ..Default::default()
            };
            // Photon methods: enough volume photons for a 32 × 32 fog, few surface ones.
            opts.photons.volume.photons = 50_000;
            opts.photons.global_photons = 20_000;
            opts.photons.caustic_photons = 1000;
            opts.photons.final_gather = 4;
            let out = render(scene, kind, &opts, &RenderControl::silent()).unwrap();
            common::mean_rgb(&out.film.to_image())
        })
        .collect();
    common::mean_and_standard_error(&runs)
}

/// A null sphere of `radius` at `center` holding medium `m` (vacuum outside).
fn add_medium_sphere(b: &mut SceneBuilder, center: Vec3, radius: f32, m: u32) {
    let null = b.add_material("boundary", Material::Null).unwrap();
    b.add_shape_with_media(
        ShapeGeometry::Sphere(Sphere { center, radius }),
        null,
        None,
        false,
        MediumInterface {
            inside: m,
            outside: NONE,
        },
    )
    .unwrap();
}

/// A spectrally flat fog box: a grey diffuse room (floor, ceiling, back and side walls; albedos
/// 0.7 and 0.4) lit by an orange square area light under the ceiling (RGB (16, 8, 3) W/m²/sr:
/// its upsampled spectrum renders as that RGB again, and every other factor is grey, so both
/// modes have the same expectation), with a sphere of grey fog (σ_a = 0.1, σ_s = 0.9 m⁻¹,
/// Henyey–Greenstein g = 0.3) filling most of it; 32 × 32 pixels. The coloured light makes a
/// spectral value that skipped its conversion to RGB (`Channels::to_rgb`) visibly wrong: its
/// lanes are wavelengths, not channels.
fn grey_fog_box() -> Scene {
    let mut b = SceneBuilder::new("grey-fog-box");
    let white = common::diffuse(&mut b, "white", 0.7);
    let grey = common::diffuse(&mut b, "grey", 0.4);
    let black = common::diffuse(&mut b, "black", 0.0);
    let walls = [
        (
            Affine3A::from_translation(Vec3::new(0.0, -1.0, 0.0))
                * Affine3A::from_rotation_x(-FRAC_PI_2),
            white,
        ),
        (
            Affine3A::from_translation(Vec3::new(0.0, 1.0, 0.0))
                * Affine3A::from_rotation_x(FRAC_PI_2),
            white,
        ),
        (Affine3A::from_translation(Vec3::new(0.0, 0.0, -1.0)), grey),
        (
            Affine3A::from_translation(Vec3::new(-1.0, 0.0, 0.0))
                * Affine3A::from_rotation_y(FRAC_PI_2),
            white,
        ),
        (
            Affine3A::from_translation(Vec3::new(1.0, 0.0, 0.0))
                * Affine3A::from_rotation_y(-FRAC_PI_2),
            grey,
        ),
    ];
    for (t, m) in walls {
        b.add_shape(common::quad(t), m, None, false).unwrap();
    }
    b.add_shape(
        common::quad(
            Affine3A::from_translation(Vec3::new(0.0, 0.98, 0.0))
                * Affine3A::from_rotation_x(FRAC_PI_2)
                * Affine3A::from_scale(Vec3::splat(0.3)),
        ),
        black,
        Some(Spectrum::new(16.0, 8.0, 3.0)),
        false,
    )
    .unwrap();
    let fog = b
        .add_medium(
            "fog",
            Medium::homogeneous(
                Spectrum::splat(0.1),
                Spectrum::splat(0.9),
                PhaseFunction::henyey_greenstein(0.3).unwrap(),
            ),
        )
        .unwrap();
    add_medium_sphere(&mut b, Vec3::ZERO, 0.9, fog);
    b.set_camera(PerspectiveCamera::look_at(
        Vec3::new(0.0, 0.0, 3.5),
        Vec3::ZERO,
        Vec3::Y,
        40.0,
        32,
        32,
    ));
    b.build().unwrap()
}

/// A grey fog (grey room, coloured light) renders the same in both modes with the path tracer,
/// the light tracer and volumetric photon mapping (photons traced spectrally, stored in linear
/// sRGB, gathered in RGB): means over 4 seeds agree within 4 standard errors of their
/// difference plus the upsampling's 0.5 %, and that tolerance is a few per cent at most.
#[test]
fn grey_fog_same_in_rgb_and_spectral_mode() {
    let mut scene = grey_fog_box();
    let kinds = [
        (IntegratorKind::Path, 64),
        (IntegratorKind::LightTrace, 32),
        (IntegratorKind::VolumetricPhotonMapping, 4),
    ];
    let rgb: Vec<_> = kinds
        .iter()
        .map(|&(k, spp)| seeds_mean(&scene, k, spp, 1, 4))
        .collect();
    scene.set_spectral(true).unwrap();
    for (&(kind, spp), rgb) in kinds.iter().zip(&rgb) {
        let spectral = seeds_mean(&scene, kind, spp, 101, 4);
        for k in 0..3 {
            let ((a, sa), (b, sb)) = (spectral[k], rgb[k]);
            let tol = 4.0 * (sa * sa + sb * sb).sqrt() + 0.005 * b;
            assert!(
                (a - b).abs() < tol,
                "{kind:?} channel {k}: spectral {a} ± {sa} vs RGB {b} ± {sb}"
            );
            assert!(tol < 0.05 * b, "{kind:?}: noise too large ({tol} of {b})");
        }
    }
}

/// σ_a of the chromatic absorber (m⁻¹, RGB); σ_s = 0.
const SIGMA_A: [f32; 3] = [0.2, 1.0, 3.0];

/// The camera at the centre of a sphere of radius 1 m of a purely absorbing medium (σ_a =
/// [`SIGMA_A`]), looking at an emitting square (radiance (1, 1, 1): D65 white in spectral mode)
/// 1.5 m away that fills its view: every camera ray crosses exactly 1 m of medium before it
/// reaches the emitter. 8 × 8 pixels.
fn absorber(spectral: bool) -> Scene {
    let mut b = SceneBuilder::new("absorber");
    let black = common::diffuse(&mut b, "black", 0.0);
    b.add_shape(
        common::quad(Affine3A::from_translation(Vec3::new(0.0, 0.0, -1.5))),
        black,
        Some(Spectrum::ONE),
        false,
    )
    .unwrap();
    let m = b
        .add_medium(
            "absorber",
            Medium::homogeneous(
                Spectrum::from_rgb(SIGMA_A),
                Spectrum::ZERO,
                PhaseFunction::default(),
            ),
        )
        .unwrap();
    add_medium_sphere(&mut b, Vec3::ZERO, 1.0, m);
    b.set_camera_medium(m);
    b.set_camera(PerspectiveCamera::look_at(
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::Y,
        60.0,
        8,
        8,
    ));
    let mut scene = b.build().unwrap();
    scene.set_spectral(spectral).unwrap();
    scene
}

/// Linear sRGB of D65 white through 1 m of the upsampled σ_a: the CIE integral of
/// D65_n(λ) exp(−σ_a(λ)) by the midpoint rule at 1 nm over 360–830 nm, σ_a(λ) the unbounded
/// Jakob–Hanika spectrum of [`SIGMA_A`].
fn expected_spectral_transmission() -> [f64; 3] {
    let sigma = RgbUnbounded::new(SIGMA_A);
    let mut xyz = [0.0f64; 3];
    for i in 0..470 {
        let l = 360.5 + i as f32;
        let s = d65_n(l) as f64 * (-(sigma.eval(l) as f64)).exp();
        let c = cie_xyz(l);
        for k in 0..3 {
            xyz[k] += s * c[k] as f64 / CIE_Y_INTEGRAL as f64;
        }
    }
    xyz_to_linear_srgb(xyz.map(|v| v as f32)).map(f64::from)
}

/// The chromatic absorber in spectral mode: the image mean is the CIE integral of the
/// transmitted spectrum within 4 standard errors (over 6 seeds) + 0.2 %, for the path tracer
/// (free flights, delta tracking's pass weights) and the light tracer (shadow connections,
/// closed-form transmittance). In RGB mode it is exp(−σ_a) per channel. The two differ: the
/// spectral expectation is (0.7594, 0.3560, 0.02702) against RGB's (0.8187, 0.3679, 0.04979),
/// −7 %, −3 % and −46 % (the mean of an exponential is not the exponential of a mean), against
/// tolerances of about 0.5 %, 0.5 % and 1.2 % (path tracer; the light tracer's are smaller):
/// 7 to 70 times the tolerance (asserted below), so the test fails if the coefficients are used
/// unconverted in spectral mode.
#[test]
fn chromatic_absorber_transmits_the_cie_integral_of_its_spectrum() {
    let want = expected_spectral_transmission();
    let rgb_exp = SIGMA_A.map(|s| (-(s as f64)).exp());
    for (kind, spp) in [
        (IntegratorKind::Path, 1024),
        (IntegratorKind::LightTrace, 1024),
    ] {
        // RGB mode: exactly exp(−σ_a) per channel on average.
        let rgb = seeds_mean(&absorber(false), kind, spp, 1, 6);
        let spectral = seeds_mean(&absorber(true), kind, spp, 11, 6);
        for k in 0..3 {
            let (m, se) = rgb[k];
            assert!(
                (m - rgb_exp[k]).abs() < 4.0 * se + 0.002 * rgb_exp[k] + 1e-4,
                "{kind:?} RGB channel {k}: {m} ± {se}, want {}",
                rgb_exp[k]
            );
            let (m, se) = spectral[k];
            let tol = 4.0 * se + 0.002 * want[k];
            assert!(
                (m - want[k]).abs() < tol,
                "{kind:?} spectral channel {k}: {m} ± {se}, want {} (RGB exp(−σ_a) {})",
                want[k],
                rgb_exp[k]
            );
            // The test can tell: the per-channel RGB exponential lies far outside the
            // tolerance in every channel.
            assert!(
                (rgb_exp[k] - want[k]).abs() > 5.0 * tol,
                "{kind:?} channel {k}: RGB {} and spectral {} too close for tolerance {tol}",
                rgb_exp[k],
                want[k]
            );
        }
    }
}

/// Every integrator that renders media gives the same bytes in spectral mode for 1 and 2
/// threads on the built-in `fog-box` (16 × 16), and a different seed changes the image.
#[test]
fn media_in_spectral_mode_are_deterministic_for_every_integrator() {
    let mut scene = common::small_builtin("fog-box", 16, 16);
    scene.set_spectral(true).unwrap();
    let run = |kind: IntegratorKind, threads: usize, seed: u64| {
        let mut opts = RenderOptions {
            spp: 2,
            seed,
            ..Default::default()
        };
        opts.photons.volume.photons = 5_000;
        opts.photons.light_paths = Some(1000);
        opts.photons.global_photons = 2000;
        opts.photons.caustic_photons = 2000;
        opts.photons.final_gather = 1;
        let img = common::with_threads(threads, || {
            render(&scene, kind, &opts, &RenderControl::silent())
                .unwrap_or_else(|e| panic!("{kind:?}: {e}"))
                .film
                .to_image()
        });
        img.data
            .iter()
            .flat_map(|p| p.map(f32::to_bits))
            .collect::<Vec<u32>>()
    };
    let kinds: Vec<IntegratorKind> = IntegratorKind::NAMES
        .iter()
        .map(|n| n.parse::<IntegratorKind>().unwrap())
        .filter(|k| k.check_scene(&scene).is_ok())
        .collect();
    assert!(kinds.len() >= 9, "{kinds:?}");
    for kind in kinds {
        let a = run(kind, 1, 3);
        assert!(
            a.iter().all(|&b| f32::from_bits(b).is_finite()),
            "{kind:?}: non-finite pixels"
        );
        assert_eq!(a, run(kind, 2, 3), "{kind:?}: 1 and 2 threads differ");
        assert_ne!(a, run(kind, 2, 4), "{kind:?}: the seed has no effect");
    }
}
