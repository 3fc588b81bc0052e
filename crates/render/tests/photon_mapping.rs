//! Photon mapping: the photon tracer's flux convention against an analytic irradiance, the
//! caustic/global classification, determinism, and `pm` against the path tracer.

mod common;

use caustica_core::{Ray, Vec3};
use caustica_density::kernel::Kernel;
use caustica_render::integrator::photon_mapping::PhotonMaps;
use caustica_render::photon::map::{EstimateOptions, PhotonMap};
use caustica_render::photon::tracer::{MapKind, trace_photons};
use caustica_render::transport::Vertex;
use caustica_render::{
    IntegratorKind, PhotonBudget, PhotonOptions, RenderControl, RenderOptions, render,
};
use caustica_scene::Scene;

const ALBEDO: f32 = 0.5;
const INTENSITY: f32 = 10.0; // W/sr
const HEIGHT: f32 = 1.0; // m

/// The diffuse floor under a point light `HEIGHT` above the origin, or, with the glass ball
/// between them, the light 4 m up (`common::ball_on_floor`).
fn floor_scene(with_glass: bool) -> Scene {
    let light_y = if with_glass { 4.0 } else { HEIGHT };
    common::ball_on_floor(ALBEDO, INTENSITY, light_y, with_glass, 32)
}

/// The floor vertex at (x, 0, z), seen from straight above.
fn floor_vertex(scene: &Scene, x: f32, z: f32) -> Vertex {
    let ray = Ray::new(Vec3::new(x, 0.5, z), Vec3::NEG_Y);
    let si = scene.intersect(&ray).expect("floor hit");
    Vertex::rgb(scene, si, &ray)
}

#[test]
fn radiance_estimate_matches_the_analytic_irradiance_of_a_point_light() {
    // L = ρ/π · E with E = I cos θ / r² (W/m²). The photon estimate with the uniform kernel and k
    // photons has relative standard deviation ≈ 1/√k (1 % at k = 10⁴); its bias from the
    // curvature of E (E ≈ E₀(1 − 1.5 ρ²) near the axis, ρ the radial offset in units of the
    // height) averages ρ² over the disc, −0.75 h², below 1 % for h ≈ 0.1 m. Tolerance: 4 %.
    let scene = floor_scene(false);
    let opts = RenderOptions {
        seed: 3,
        ..Default::default()
    };
    let traced = trace_photons(
        &scene,
        PhotonBudget::Records(1_500_000),
        MapKind::Global,
        0,
        &opts,
        &mut |_| true,
    );
    assert!(traced.warning.is_none());
    // Every photon is a direct hit on the floor: depth 1, not caustic, on the floor plane.
    assert!(
        traced
            .photons
            .iter()
            .all(|p| p.depth == 1 && !p.caustic && p.p.y.abs() < 1e-4)
    );
    // Flux conservation: the stored flux is the power the floor intercepts, I·Ω, with Ω the
    // solid angle of a square of half-side a seen from height d on its axis,
    // Ω = 4 asin(a² / (a² + d²)).
    let a = 2.0f64;
    let d = HEIGHT as f64;
    let omega = 4.0 * (a * a / (a * a + d * d)).asin();
    let total: f64 = traced.photons.iter().map(|p| p.flux.c[0] as f64).sum();
    let expect = INTENSITY as f64 * omega;
    // Each path stores 0 or 1 photon; binomial noise of the count, relative √((1−q)/(qN)).
    let q = omega / (4.0 * std::f64::consts::PI);
    let rel_sd = ((1.0 - q) / (q * traced.paths as f64)).sqrt();
    assert!(
        (total / expect - 1.0).abs() < 5.0 * rel_sd,
        "stored flux {total} W vs intercepted {expect} W (±{rel_sd})"
    );
    let map = PhotonMap::new(traced.photons, traced.paths);
    let est = EstimateOptions {
        k: 10_000,
        kernel: Kernel::Uniform,
        ..Default::default()
    };
    let mut buf = caustica_density::estimator::Scratch::default();
    for (x, z) in [(0.0f32, 0.0f32), (0.5, 0.0), (0.0, -0.7)] {
        let v = floor_vertex(&scene, x, z);
        let r2 = x * x + z * z + HEIGHT * HEIGHT;
        let e = INTENSITY * HEIGHT / r2.sqrt() / r2;
        let expect = ALBEDO / std::f32::consts::PI * e;
        let got = map.estimate(&v, &est, &mut buf).c[0];
        assert!(
            (got / expect - 1.0).abs() < 0.04,
            "at ({x}, {z}): estimate {got} vs analytic {expect}"
        );
    }
}

#[test]
fn caustic_map_holds_only_specular_chain_photons_and_maps_are_deterministic() {
    let scene = floor_scene(true);
    let opts = RenderOptions {
        seed: 5,
        photons: PhotonOptions {
            caustic_photons: 20_000,
            global_photons: 20_000,
            ..Default::default()
        },
        ..Default::default()
    };
    let build = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| PhotonMaps::build(&scene, &opts))
    };
    let one = build(1);
    let two = build(2);
    assert_eq!(one.caustic.point_photons(), two.caustic.point_photons());
    assert_eq!(one.global.photons, two.global.photons);
    assert_eq!(one.caustic.paths(), two.caustic.paths());
    let c = &one.caustic;
    assert!(c.len() >= 20_000 && c.len() < 20_010, "{}", c.len());
    // Caustic photons came through or off the glass (≥ 2 edges) and lie on the floor.
    assert!(
        c.point_photons()
            .iter()
            .all(|p| p.caustic && p.depth >= 2 && p.p.y.abs() < 1e-4)
    );
    // Energy: a caustic path stores one photon (at its first diffuse hit), so the caustic flux is
    // at most the power the ball intercepts, I·Ω with Ω = 2π(1 − cos α), sin α = r/d (d = 3 m
    // from the light to the centre). Most of it reaches the 4 m floor: refracted light (~90 %
    // of it after Fresnel) focuses below the ball; reflected light goes partly upward.
    let sin_a = 0.5f64 / 3.0;
    let omega = 2.0 * std::f64::consts::PI * (1.0 - (1.0 - sin_a * sin_a).sqrt());
    let intercepted = INTENSITY as f64 * omega;
    let caustic_flux: f64 = c.point_photons().iter().map(|p| p.flux.c[0] as f64).sum();
    assert!(
        caustic_flux < 1.02 * intercepted && caustic_flux > 0.7 * intercepted,
        "caustic flux {caustic_flux} W vs {intercepted} W intercepted by the ball"
    );
    // The refracted light focuses: most caustic photons fall within 0.5 m of the axis.
    let focused = c
        .point_photons()
        .iter()
        .filter(|p| p.p.x.hypot(p.p.z) < 0.5)
        .count();
    assert!(
        focused as f64 > 0.8 * c.len() as f64,
        "{focused} of {} focused",
        c.len()
    );
    // The global map has direct photons too, and no photon sits on the glass.
    let g = &one.global.photons;
    assert!(g.iter().any(|p| p.depth == 1 && !p.caustic));
    assert!(g.iter().any(|p| p.caustic));
    assert!(g.iter().all(|p| p.p.y.abs() < 1e-4));
}

fn render_pm(scene: &Scene, photons: PhotonOptions, spp: u32) -> caustica_core::image_io::Image {
    let opts = RenderOptions {
        spp,
        seed: 11,
        photons,
        ..Default::default()
    };
    render(
        scene,
        IntegratorKind::PhotonMapping,
        &opts,
        &RenderControl::silent(),
    )
    .expect("valid options")
    .film
    .to_image()
}

#[test]
fn pm_with_final_gathering_agrees_with_the_path_tracer_on_a_diffuse_scene() {
    let scene = common::diffuse_box(40, 30);
    let reference = common::render_image(&scene, IntegratorKind::Path, 512, 1);
    let pm = render_pm(
        &scene,
        PhotonOptions {
            caustic_photons: 1000,
            global_photons: 100_000,
            final_gather: 16,
            ..Default::default()
        },
        32,
    );
    let (m_pm, m_ref) = (common::mean_lum(&pm), common::mean_lum(&reference));
    assert!(
        (m_pm / m_ref - 1.0).abs() < 0.02,
        "pm mean {m_pm} vs path tracer {m_ref}"
    );
}

#[test]
fn pm_error_shrinks_as_photons_grow() {
    // Global map shown directly (no final gathering): the image error is the photon map's. The
    // estimate is consistent when k → ∞ and k/N → 0 (seed 000 sec. 2.3); k = √N does both, so
    // variance (∝ 1/k) and bias (∝ h² ∝ k/N) both fall. Pixels that see the light are masked:
    // their anti-aliasing noise is the same for every photon count.
    let scene = common::diffuse_box(40, 30);
    let reference = common::render_image(&scene, IntegratorKind::Path, 1024, 1);
    let lit: Vec<bool> = reference
        .data
        .iter()
        .map(|&p| common::lum(p) < 2.0)
        .collect();
    let err = |n: usize| {
        let img = render_pm(
            &scene,
            PhotonOptions {
                caustic_photons: 1000,
                global_photons: n,
                final_gather: 0,
                estimate: EstimateOptions {
                    k: (n as f64).sqrt() as usize,
                    ..Default::default()
                },
                ..Default::default()
            },
            16,
        );
        let (mut s, mut count) = (0.0, 0usize);
        for ((&a, &b), &keep) in img.data.iter().zip(&reference.data).zip(&lit) {
            if keep {
                s += (common::lum(a) - common::lum(b)).powi(2);
                count += 1;
            }
        }
        (s / count as f64).sqrt()
    };
    let (e1, e2, e3) = (err(4_000), err(40_000), err(400_000));
    assert!(e2 < 0.8 * e1 && e3 < 0.8 * e2, "RMSE {e1} -> {e2} -> {e3}");
}

#[test]
fn caustics_only_light_tracer_and_pm_agree() {
    // Two independent estimators of the same L S+ D E light: the light tracer splats each caustic
    // vertex into its pixel, pm estimates the caustic map's density at each camera sample. The
    // ball images the point light almost onto the floor, so the caustic has a sub-pixel peak:
    // pm's estimate there is a spike about one bandwidth wide, which a pixel only averages
    // correctly with samples finer than that (at 16 spp the image mean came out 6 % low, at
    // 256 spp 0.6 % low). The light tracer's noise is measured from two seeds (they must agree
    // to 1 %); the remaining k-NN bias at k = 50 with 2·10⁵ photons is below 1 %. Tolerance on
    // the image mean: 2 %.
    let scene = floor_scene(true);
    let lt = |seed: u64| {
        let opts = RenderOptions {
            spp: 4096,
            seed,
            caustics_only: true,
            ..Default::default()
        };
        render(
            &scene,
            IntegratorKind::LightTrace,
            &opts,
            &RenderControl::silent(),
        )
        .expect("valid options")
        .film
        .to_image()
    };
    let (lt1, lt2) = (lt(1), lt(2));
    let opts = RenderOptions {
        spp: 256,
        seed: 3,
        caustics_only: true,
        photons: PhotonOptions {
            caustic_photons: 200_000,
            ..Default::default()
        },
        ..Default::default()
    };
    let pm = render(
        &scene,
        IntegratorKind::PhotonMapping,
        &opts,
        &RenderControl::silent(),
    )
    .expect("valid options")
    .film
    .to_image();
    let (m1, m2, mp) = (
        common::mean_lum(&lt1),
        common::mean_lum(&lt2),
        common::mean_lum(&pm),
    );
    assert!(m1 > 0.0, "no caustic in the light tracer");
    let lt_spread = (m1 / m2 - 1.0).abs();
    assert!(lt_spread < 0.01, "light tracer seeds differ by {lt_spread}");
    let rel = mp / (0.5 * (m1 + m2)) - 1.0;
    assert!(
        rel.abs() < 0.02,
        "pm caustic mean {mp} vs light tracer {m1}, {m2}: {rel:+.4}"
    );
    // Only the caustic is rendered: the directly lit floor far from the ball is black in both.
    let corner = common::region_mean(&pm, 0, 0, 4, 4);
    assert_eq!(corner, [0.0; 3], "pm rendered non-caustic light");
    assert_eq!(common::region_mean(&lt1, 0, 0, 4, 4), [0.0; 3]);
}

#[test]
fn global_k_sets_the_global_maps_bandwidth_alone() {
    // With the global map shown directly (final_gather = 0) only the global estimate is used:
    // with global_k set, the caustic k must not change a byte, and global_k itself must.
    let scene = common::diffuse_box(16, 12);
    let opts = |k: usize, global_k: Option<usize>| PhotonOptions {
        caustic_photons: 100,
        global_photons: 5_000,
        final_gather: 0,
        global_k,
        estimate: EstimateOptions {
            k,
            ..Default::default()
        },
        ..Default::default()
    };
    let a = render_pm(&scene, opts(50, Some(20)), 2);
    let b = render_pm(&scene, opts(5, Some(20)), 2);
    let c = render_pm(&scene, opts(50, None), 2);
    assert_eq!(a.data, b.data, "the caustic k changed the global estimate");
    assert_ne!(a.data, c.data, "global_k had no effect");
}

#[test]
fn the_photon_pass_moves_the_progress_bar_of_pm_dpm_and_pdm() {
    // The photon pass owns the first fifth of the bar and reports after every wave of light
    // paths; it used to sit at 0 % until the camera pass began.
    use std::sync::Mutex;
    use std::sync::atomic::AtomicBool;
    let scene = floor_scene(true);
    for kind in [
        IntegratorKind::PhotonMapping,
        IntegratorKind::DiffusionPhotonMapping,
        IntegratorKind::PhotonDifferentialMapping,
    ] {
        let seen = Mutex::new(Vec::new());
        let record = |p: caustica_render::Progress| seen.lock().unwrap().push(p.fraction);
        let stop = AtomicBool::new(false);
        let ctl = RenderControl {
            stop: &stop,
            on_progress: &record,
            on_checkpoint: &|_| {},
            on_iteration: &|_| {},
        };
        let opts = RenderOptions {
            spp: 1,
            photons: PhotonOptions {
                caustic_photons: 20_000,
                global_photons: 20_000,
                final_gather: 0,
                ..Default::default()
            },
            ..Default::default()
        };
        render(&scene, kind, &opts, &ctl).expect("valid options");
        let seen = seen.into_inner().unwrap();
        // Reports before the camera pass: strictly inside the photon share, several of them,
        // and rising to the share's end.
        let photon_pass: Vec<f64> = seen.iter().copied().take_while(|&f| f <= 0.2).collect();
        let inside = photon_pass.iter().filter(|&&f| f > 0.0 && f < 0.2).count();
        assert!(
            inside >= 2,
            "{kind:?}: photon pass reported {photon_pass:?}"
        );
        assert!(
            photon_pass.windows(2).all(|w| w[0] <= w[1]),
            "{kind:?}: {photon_pass:?}"
        );
        assert!(*seen.last().unwrap() > 0.99, "{kind:?}: ends at {seen:?}");
    }
}
