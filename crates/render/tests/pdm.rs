//! Photon differential mapping (`pdm`, seed 002 eq. 10 = seed 000 eq. 5.14): the footprint
//! estimate against the analytic irradiance of a point light seen in a mirror, against the
//! light tracer's caustics on the built-in scenes, determinism, and dropped footprints.

mod common;

use caustica_core::image_io::Image;
use caustica_core::{Affine3A, Spectrum, Vec3};
use caustica_density::kernel::Kernel;
use caustica_loader::builtin_scene;
use caustica_render::integrator::photon_mapping::PhotonMaps;
use caustica_render::photon::caustic::{CAUSTIC_STREAM, CausticEstimate};
use caustica_render::photon::differential::{
    Landing, PdmMap, TracedDiffPhotons, photons_from_landings, trace_photon_differentials,
};
use caustica_render::{
    FootprintSettings, IntegratorKind, PathLimits, PhotonBudget, PhotonOptions, RenderControl,
    RenderOptions, RenderStats, Smoothing, render,
};
use caustica_scene::camera::PerspectiveCamera;
use caustica_scene::light::{Light, PointLight};
use caustica_scene::material::Material;
use caustica_scene::{Scene, SceneBuilder};
use std::f32::consts::FRAC_PI_2;

const INTENSITY: f32 = 10.0; // W/sr
const LIGHT_Y: f32 = 0.5; // m above the floor
const MIRROR_Y: f32 = 1.5; // m: a mirror ceiling facing down

/// A 4 m × 4 m diffuse floor at y = 0 under a point light at (0, `LIGHT_Y`, 0) and a 4 m × 4 m
/// mirror (reflectance 1) at y = `MIRROR_Y` facing down: the caustic on the floor is the light
/// of the mirror image of the source, at height d = 2·MIRROR_Y − LIGHT_Y.
fn mirror_scene() -> Scene {
    let mut b = SceneBuilder::new("mirror-ceiling");
    let floor = common::diffuse(&mut b, "floor", 0.5);
    let mirror = b
        .add_material(
            "mirror",
            Material::Mirror {
                reflectance: Spectrum::ONE,
            },
        )
        .unwrap();
    b.add_shape(
        common::quad(
            Affine3A::from_rotation_x(-FRAC_PI_2) * Affine3A::from_scale(Vec3::splat(2.0)),
        ),
        floor,
        None,
        false,
    )
    .unwrap();
    b.add_shape(
        common::quad(
            Affine3A::from_translation(Vec3::new(0.0, MIRROR_Y, 0.0))
                * Affine3A::from_rotation_x(FRAC_PI_2)
                * Affine3A::from_scale(Vec3::splat(2.0)),
        ),
        mirror,
        None,
        false,
    )
    .unwrap();
    b.add_light(Light::Point(PointLight::new(
        Vec3::new(0.0, LIGHT_Y, 0.0),
        Spectrum::splat(INTENSITY),
    )));
    b.set_camera(PerspectiveCamera::look_at(
        Vec3::new(0.0, 1.0, 3.5),
        Vec3::ZERO,
        Vec3::Y,
        50.0,
        16,
        16,
    ));
    b.build().unwrap()
}

fn bytes(img: &Image) -> Vec<u32> {
    img.data.iter().flat_map(|p| p.map(f32::to_bits)).collect()
}

#[test]
fn footprint_irradiance_matches_a_point_light_seen_in_a_mirror() {
    // E(x) = I d / (d² + ρ²)^{3/2}, d = 2·1.5 − 0.5 = 2.5 m (the mirror image of the light).
    //
    // Noise: a point light's N_e footprints tile the sphere s² times, so a point of the floor
    // lies in ~s² footprints; with Silverman's kernel (∫K² = 3/(5π) over the unit disc) the
    // relative variance of E(x) = Σ π K Φ/A for Poisson-distributed photons is
    // π² ∫K² / (π s²) · (∫K)⁻²·π/π = 9/(5 s²): σ = 1.34/s = 4.2 % at s = 32 (a bound: the Sobol
    // paths are stratified). Bias: the semi-axis is R = 2 s D/√N_e (eq. 6, D the path length
    // ≈ 2.5–3.2 m), ≈ 0.14–0.18 m with N_e ≈ 1.3·10⁶ paths, and smoothing the curvature of E
    // (E ≈ E₀(1 − 1.5 ρ²/d²)) with ⟨ρ²⟩ = R²/4 costs ≈ 0.375 (R/d)² < 0.5 %. 49 points 0.3 m
    // apart (about one footprint diameter, so nearly independent): the mean ratio has
    // σ ≈ 0.6 %; tolerances 3 % on the mean (5σ + bias) and 20 % per point (≈ 5σ).
    let scene = mirror_scene();
    let s = 32.0;
    let opts = RenderOptions::default();
    let traced = trace_photon_differentials(
        &scene,
        PhotonBudget::Records(300_000),
        Smoothing::new(s).unwrap(),
        CAUSTIC_STREAM,
        &opts,
        &mut |_| true,
    );
    assert!(traced.warning.is_none(), "{:?}", traced.warning);
    assert_eq!(traced.landings, 300_000);
    // A flat mirror neither collapses nor fails a footprint.
    assert_eq!((traced.collapsed, traced.failed), (0, 0));
    let map = PdmMap::new(traced, Kernel::Silverman);
    let d = 2.0 * MIRROR_Y - LIGHT_Y;
    let mut ratios = Vec::new();
    for i in -3..=3 {
        for j in -3..=3 {
            let (x, z) = (0.3 * i as f32, 0.3 * j as f32);
            let rho2 = x * x + z * z;
            let exact = INTENSITY * d / (d * d + rho2).powf(1.5);
            let e = map.irradiance(Vec3::new(x, 0.0, z), Vec3::Y);
            assert!(e.is_finite());
            // grey light: all channels equal
            let r = e.luminance() / exact;
            assert!(
                (r - 1.0).abs() < 0.2,
                "({x}, {z}): E = {e:?}, exact {exact}, ratio {r}"
            );
            ratios.push(r as f64);
        }
    }
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    let sd = (ratios.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / ratios.len() as f64).sqrt();
    eprintln!("pdm/analytic: mean {mean:.4}, per-point sd {sd:.4}");
    assert!((mean - 1.0).abs() < 0.03, "mean ratio {mean} (sd {sd})");
    // Light from below the floor's tangent plane does not count.
    let below = map.irradiance(Vec3::ZERO, Vec3::NEG_Y);
    assert_eq!(below, Spectrum::ZERO);
}

/// A built-in scene at 32 × 32 pixels.
fn small_builtin(name: &str) -> Scene {
    let mut b = builtin_scene(name).unwrap();
    let mut camera = b.camera().unwrap().clone();
    (camera.width, camera.height) = (32, 32);
    b.set_camera(camera);
    b.build().unwrap()
}

fn caustics(
    scene: &Scene,
    kind: IntegratorKind,
    spp: u32,
    seed: u64,
    photons: PhotonOptions,
) -> (Image, Vec<String>) {
    let opts = RenderOptions {
        spp,
        seed,
        caustics_only: true,
        limits: PathLimits {
            max_depth: 16,
            ..PathLimits::default()
        },
        photons,
        ..Default::default()
    };
    let out = render(scene, kind, &opts, &RenderControl::silent()).expect("valid options");
    (out.film.to_image(), out.notes)
}

/// pdm's caustics-only image mean against the light tracer's (two seeds, which must agree to
/// 1 % for the comparison to mean anything). Footprints integrate to their photon's flux
/// (`Footprint::irradiance_at`), so the image mean is unbiased up to light leaving the
/// visible floor through footprint tails and pixel sampling of sharp caustics: 3 %.
fn pdm_agrees_with_the_light_tracer(name: &str, photons: usize, smoothing: f32, spp: u32) {
    let scene = small_builtin(name);
    let (lt1, _) = caustics(
        &scene,
        IntegratorKind::LightTrace,
        4096,
        1,
        PhotonOptions::default(),
    );
    let (lt2, _) = caustics(
        &scene,
        IntegratorKind::LightTrace,
        4096,
        2,
        PhotonOptions::default(),
    );
    let photons = PhotonOptions {
        caustic_photons: photons,
        footprints: footprints(smoothing),
        ..Default::default()
    };
    let (pdm, notes) = caustics(
        &scene,
        IntegratorKind::PhotonDifferentialMapping,
        spp,
        3,
        photons,
    );
    assert!(
        pdm.data.iter().all(|p| p.iter().all(|c| c.is_finite())),
        "{name}: non-finite pixel"
    );
    let (m1, m2, mp) = (
        common::mean_lum(&lt1),
        common::mean_lum(&lt2),
        common::mean_lum(&pdm),
    );
    assert!(m1 > 0.0, "{name}: no caustic in the light tracer");
    let lt_spread = (m1 / m2 - 1.0).abs();
    assert!(
        lt_spread < 0.01,
        "{name}: light tracer seeds differ by {lt_spread}"
    );
    let rel = mp / (0.5 * (m1 + m2)) - 1.0;
    eprintln!("{name}: pdm {mp:.5} vs light tracer {m1:.5}, {m2:.5}: {rel:+.4}; {notes:?}");
    assert!(
        rel.abs() < 0.03,
        "{name}: pdm caustic mean {mp} vs light tracer {m1}, {m2}: {rel:+.4}; {notes:?}"
    );
    assert!(
        notes.iter().any(|n| n.contains("collapsed footprint")),
        "{notes:?}"
    );
}

#[test]
fn pdm_caustics_agree_with_the_light_tracer_on_glass_sphere() {
    // Analytic sphere: the sphere curvature model (dN = dQ/r) at both refractions. The ball
    // concentrates the caustic into a spot a few pixels wide covered by sub-millimetre
    // footprints (median gather radius ≈ 1 mm with 10⁵ photons, s = 2): a pixel estimates such
    // a spike's mean correctly only with many samples — with 5·10⁴ photons the image mean came
    // out 9 % low at 64 spp and 2 % low at 512 spp (pm's k-NN estimate moves by 13 % between the
    // two) — hence 1024 spp.
    pdm_agrees_with_the_light_tracer("glass-sphere", 100_000, 2.0, 1024);
}

#[test]
fn pdm_caustics_agree_with_the_light_tracer_on_water_wave() {
    // Mesh with vertex normals: the Phong triangle model; the floor lies beyond the crest's
    // focus, so the fold caustics stretch footprints to near-collapse.
    pdm_agrees_with_the_light_tracer("water-wave", 200_000, 2.0, 64);
}

#[test]
fn pdm_is_deterministic_and_follows_the_caustic_paths_of_pm() {
    let scene = small_builtin("glass-sphere");
    let photons = PhotonOptions {
        caustic_photons: 20_000,
        footprints: footprints(3.0),
        ..Default::default()
    };
    let run = |threads: usize, seed: u64| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            caustics(
                &scene,
                IntegratorKind::PhotonDifferentialMapping,
                4,
                seed,
                photons.clone(),
            )
            .0
        })
    };
    let (a, b, c) = (run(1, 7), run(2, 7), run(2, 8));
    assert_eq!(bytes(&a), bytes(&b), "1 and 2 threads differ");
    assert_eq!(bytes(&a), bytes(&run(2, 7)), "two runs differ");
    assert_ne!(bytes(&a), bytes(&c), "the seed has no effect");
    // The differentials ride on the caustic photon tracer's paths: same landings, same flux.
    let opts = RenderOptions {
        seed: 7,
        caustics_only: true,
        photons: photons.clone(),
        ..Default::default()
    };
    let pm = PhotonMaps::build(&scene, &opts);
    let pdm = PhotonMaps::build_differential(&scene, &opts);
    let CausticEstimate::Footprints(d) = &pdm.caustic else {
        panic!("pdm estimates caustics from footprints");
    };
    assert_eq!(pm.caustic.paths(), pdm.caustic.paths());
    assert_eq!(d.landings, pm.caustic.len());
    assert_eq!(d.collapsed + d.failed + d.len() as u64, d.landings as u64);
    assert!(
        d.len() as f64 > 0.99 * d.landings as f64,
        "{} of {} dropped",
        d.landings - d.len(),
        d.landings
    );
    if d.collapsed + d.failed == 0 {
        let mut by_trace: Vec<_> = d.traced_index.iter().zip(&d.photons).collect();
        by_trace.sort_by_key(|(i, _)| **i);
        for (p, (_, q)) in pm.caustic.point_photons().iter().zip(by_trace) {
            assert_eq!(p.p, q.footprint.center());
            assert_eq!(p.flux, q.flux);
        }
    }
}

#[test]
fn collapsed_and_failed_footprints_are_dropped_and_counted_without_nan() {
    let landing = |p: Vec3, dp: Option<[Vec3; 2]>| Landing {
        p,
        wi: Vec3::Y,
        n: Vec3::Y,
        beta: Spectrum::splat(2.0),
        depth: 2,
        pmf: 1.0,
        dp,
    };
    let o = Vec3::ZERO;
    let landings = [
        landing(o, Some([Vec3::X, Vec3::Z])),                    // kept
        landing(o, Some([Vec3::X, 2.0 * Vec3::X])),              // parallel: collapsed
        landing(o, Some([Vec3::ZERO, Vec3::Z])),                 // zero vector: collapsed
        landing(o, Some([Vec3::Y, Vec3::Z])),                    // ⟂ plane: projects to 0
        landing(o, None),                                        // propagation failed
        landing(o, Some([Vec3::splat(f32::NAN), Vec3::Z])),      // not finite: failed
        landing(o, Some([Vec3::splat(f32::INFINITY), Vec3::Z])), // not finite: failed
    ];
    let paths = 4;
    let made = photons_from_landings(
        &landings,
        paths,
        caustica_render::ShutterAlign::Forward,
        None,
    );
    let (photons, collapsed, failed) = (made.photons, made.collapsed, made.failed);
    assert_eq!(
        (photons.len(), collapsed, failed, made.widened),
        (1, 3, 3, 0)
    );
    // With a minimum semi-axis the parallel vectors are rescued (a thin ellipse along X); a
    // zero vector beside a non-zero one is too, and the vectors ⟂ the plane project to one
    // zero and one non-zero: every landing with finite vectors becomes a photon.
    let floored = photons_from_landings(
        &landings,
        paths,
        caustica_render::ShutterAlign::Forward,
        Some(0.01),
    );
    assert_eq!(
        (floored.photons.len(), floored.collapsed, floored.failed),
        (4, 0, 3)
    );
    assert_eq!(floored.widened, 3);
    // The kept footprint: vectors X, Z scaled by 1/√4, area π/4 · ¼ = π/16, flux 2/4 W, and at
    // its centre π K(0) Φ/A = 3 Φ/A (eq. 10–11).
    let fp = photons[0].footprint;
    assert!((fp.area() - std::f32::consts::PI / 16.0).abs() < 1e-6);
    let traced = |photons: Vec<_>| TracedDiffPhotons {
        photons,
        paths,
        landings: landings.len(),
        collapsed,
        failed,
        widened: 0,
        stats: RenderStats::default(),
        warning: None,
        note: None,
    };
    // The kernel is selectable: at the centre π K(0) Φ/A is 3 Φ/A for Silverman's kernel
    // (eq. 11) and 2 Φ/A for Epanechnikov's.
    let epa = PdmMap::new(traced(photons.clone()), Kernel::Epanechnikov);
    let map = PdmMap::new(traced(photons), Kernel::Silverman);
    let e0 = map.irradiance(o, Vec3::Y);
    let area = std::f32::consts::PI / 16.0;
    let want = 3.0 * 0.5 / area;
    assert!(
        (e0.luminance() - want).abs() < 1e-4 * want,
        "{e0:?} vs {want}"
    );
    let e_epa = epa.irradiance(o, Vec3::Y).luminance();
    let want_epa = 2.0 * 0.5 / area;
    assert!(
        (e_epa - want_epa).abs() < 1e-4 * want_epa,
        "{e_epa} vs {want_epa}"
    );
    for x in [
        Vec3::new(0.2, 0.0, 0.1),
        Vec3::new(0.25, 0.0, 0.0),
        Vec3::splat(f32::NAN),
        Vec3::new(1e30, 0.0, 0.0),
    ] {
        let e = map.irradiance(x, Vec3::Y);
        assert!(e.is_finite(), "{x}: {e:?}");
    }
    // Outside the ellipse (semi-axes 0.25 along x and z) nothing.
    assert_eq!(
        map.irradiance(Vec3::new(0.26, 0.0, 0.0), Vec3::Y),
        Spectrum::ZERO
    );
}

#[test]
fn smoothing_must_be_positive() {
    for s in [0.0, -1.0, f32::NAN, f32::INFINITY] {
        let e = Smoothing::new(s).unwrap_err().to_string();
        assert!(e.contains("smoothing"), "{e}");
    }
    assert!(PhotonOptions::default().validate().is_ok());
}

/// The default footprints with smoothing `s`.
fn footprints(s: f32) -> FootprintSettings {
    FootprintSettings {
        smoothing: Smoothing::new(s).unwrap(),
        ..Default::default()
    }
}
