//! Photon differential splatting (`pds`, seed 002 sec. 3.3): the same estimate as `pdm` (eq. 10)
//! evaluated by splatting instead of gathering, so for the same photons both give the same
//! image up to the order of floating-point sums; determinism; scenes without caustics; bad
//! options.

mod common;

use caustica_core::image_io::Image;
use caustica_loader::builtin_scene;
use caustica_render::{
    FootprintSettings, IntegratorKind, NormalDistance, PathLimits, PhotonOptions, RenderControl,
    RenderOptions, Smoothing, render,
};
use caustica_scene::Scene;

/// A built-in scene at `w` × `h` pixels.
fn small_builtin(name: &str, w: u32, h: u32) -> Scene {
    let mut b = builtin_scene(name).unwrap();
    let mut camera = b.camera().unwrap().clone();
    (camera.width, camera.height) = (w, h);
    b.set_camera(camera);
    b.build().unwrap()
}

fn run(scene: &Scene, kind: IntegratorKind, opts: &RenderOptions) -> (Image, Vec<String>) {
    let out = render(scene, kind, opts, &RenderControl::silent()).expect("valid options");
    (out.film.to_image(), out.notes)
}

/// Largest per-pixel difference relative to the image's peak; the two images must also be
/// finite and not black.
fn max_rel_diff(a: &Image, b: &Image) -> f32 {
    let peak = a
        .data
        .iter()
        .flat_map(|p| p.iter().copied())
        .fold(0.0f32, f32::max);
    assert!(peak > 0.0, "black image");
    a.data
        .iter()
        .zip(&b.data)
        .flat_map(|(p, q)| p.iter().zip(q).map(|(x, y)| (x - y).abs()))
        .inspect(|d| assert!(d.is_finite(), "non-finite pixel"))
        .fold(0.0f32, f32::max)
        / peak
}

/// `pds` and `pdm` on the same photons (same seed, count and smoothing) and the same camera
/// samples: equal within float noise. Sums of the same terms in a different order differ by a
/// few ulps of the sum; 1e-5 of the peak leaves room for that and nothing else (one photon more
/// or less changes a caustic pixel by ≫ 1e-3).
fn assert_pds_equals_pdm(name: &str, opts: RenderOptions) {
    let scene = small_builtin(name, 48, 48);
    let (pdm, pdm_notes) = run(&scene, IntegratorKind::PhotonDifferentialMapping, &opts);
    let (pds, pds_notes) = run(&scene, IntegratorKind::PhotonDifferentialSplatting, &opts);
    let d = max_rel_diff(&pdm, &pds);
    eprintln!("{name}: max |pds − pdm| / peak = {d:e}\n{pdm_notes:?}\n{pds_notes:?}");
    assert!(
        d < 1e-5,
        "{name}: pds and pdm differ by {d:e} of the peak\n{pdm_notes:?}\n{pds_notes:?}"
    );
    // Both used the same photons: pdm stores what pds splats.
    let stored = pdm_notes
        .iter()
        .find_map(|n| {
            n.split(" stored")
                .next()?
                .rsplit(' ')
                .next()?
                .parse::<u64>()
                .ok()
        })
        .expect("pdm reports its stored photons");
    assert!(
        pds_notes
            .iter()
            .any(|n| n.contains(&format!(", {stored} photons splatted"))),
        "{name}: pdm stored {stored}; {pds_notes:?}"
    );
}

/// Paths of at most 16 edges.
fn depth16() -> PathLimits {
    PathLimits {
        max_depth: 16,
        ..PathLimits::default()
    }
}

/// The default footprints with smoothing `s`.
fn footprints(s: f32) -> FootprintSettings {
    FootprintSettings {
        smoothing: Smoothing::new(s).unwrap(),
        ..Default::default()
    }
}

fn caustics_only(photons: usize, smoothing: f32, spp: u32) -> RenderOptions {
    RenderOptions {
        spp,
        seed: 5,
        caustics_only: true,
        limits: depth16(),
        photons: PhotonOptions {
            caustic_photons: photons,
            footprints: footprints(smoothing),
            ..Default::default()
        },
        ..Default::default()
    }
}

#[test]
fn pds_equals_pdm_on_the_water_wave() {
    // Phong-interpolated mesh, refraction; 8 eye vertices per pixel.
    assert_pds_equals_pdm("water-wave", caustics_only(20_000, 2.0, 8));
}

#[test]
fn pds_equals_pdm_on_the_metal_ring() {
    // Reflection off a curved conductor mesh.
    assert_pds_equals_pdm("metal-ring", caustics_only(20_000, 2.0, 4));
}

#[test]
fn pds_equals_pdm_in_a_full_render_of_the_glass_sphere() {
    // Direct light, the global map with final gathering, and caustics seen through the glass
    // (eye vertices reached through specular chains).
    let opts = RenderOptions {
        spp: 2,
        seed: 9,
        limits: depth16(),
        photons: PhotonOptions {
            caustic_photons: 20_000,
            global_photons: 5_000,
            final_gather: 2,
            footprints: footprints(2.0),
            ..Default::default()
        },
        ..Default::default()
    };
    assert_pds_equals_pdm("glass-sphere", opts);
}

#[test]
fn pds_gives_the_same_bytes_for_any_thread_count() {
    let scene = small_builtin("water-wave", 24, 24);
    let opts = caustics_only(5_000, 1.0, 2);
    let bytes = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let img =
            pool.install(|| run(&scene, IntegratorKind::PhotonDifferentialSplatting, &opts).0);
        img.data
            .iter()
            .flat_map(|p| p.map(f32::to_bits))
            .collect::<Vec<u32>>()
    };
    let (a, b) = (bytes(1), bytes(2));
    assert!(a == b, "1 and 2 threads differ");
    assert!(a.iter().any(|&x| x != 0), "black image");
}

#[test]
fn pds_without_caustic_paths_warns_and_renders_the_rest() {
    // A diffuse box has no specular surface: no caustic photon, the direct light still there.
    let scene = common::diffuse_box(16, 16);
    let opts = RenderOptions {
        spp: 4,
        photons: PhotonOptions {
            caustic_photons: 1000,
            global_photons: 1000,
            final_gather: 1,
            ..Default::default()
        },
        ..Default::default()
    };
    let (img, notes) = run(&scene, IntegratorKind::PhotonDifferentialSplatting, &opts);
    assert!(
        notes.iter().any(|n| n.contains("only 0 caustic photons")),
        "{notes:?}"
    );
    assert!(img.data.iter().all(|p| p.iter().all(|c| c.is_finite())));
    assert!(common::mean_lum(&img) > 0.0);
}

#[test]
fn a_negative_normal_distance_threshold_is_rejected() {
    for t in [-0.1, f32::NAN] {
        let e = NormalDistance::new(t).unwrap_err().to_string();
        assert!(e.contains("normal-distance"), "{e}");
    }
    assert_eq!(NormalDistance::new(f32::INFINITY), Ok(NormalDistance::OFF));
}

#[test]
fn the_recorded_landing_paths_are_exactly_the_paths_with_caustic_photons() {
    // pds re-traces only the recorded paths; that gives pdm's photons only if the record holds
    // every path with a landing and its count agrees with the unrecorded count.
    use caustica_core::sampling::Sampler;
    use caustica_render::photon::caustic::CAUSTIC_STREAM;
    use caustica_render::photon::differential::{
        Landing, LandingTracer, count_caustic_paths, unit_budget,
    };
    use caustica_render::photon::plan::PathStream;
    let scene = small_builtin("metal-ring", 8, 8);
    let opts = caustics_only(3000, 1.0, 1);
    let stream = PathStream::new(&opts, CAUSTIC_STREAM);
    let limits = &opts.limits;
    let rec = count_caustic_paths(&scene, 3000, &stream, limits, true, &mut |_| true);
    let plain = count_caustic_paths(&scene, 3000, &stream, limits, false, &mut |_| true);
    assert_eq!((rec.paths, rec.landings), (plain.paths, plain.landings));
    assert!(plain.landing_paths.is_none());
    let listed = rec.landing_paths.expect("recorded");
    let tracer = LandingTracer::new(&scene, &unit_budget(Smoothing::ONE));
    let mut sampler = Sampler::new(opts.sampler, opts.seed);
    let (mut with_landings, mut total) = (Vec::new(), 0usize);
    let mut stats = caustica_render::RenderStats::default();
    for path in 0..rec.paths {
        sampler.start_path(CAUSTIC_STREAM, path);
        let mut out: Vec<Landing> = Vec::new();
        tracer.trace(&mut sampler, limits, &mut out, &mut stats);
        if !out.is_empty() {
            with_landings.push(path);
            total += out.len();
        }
    }
    assert_eq!(total, rec.landings);
    assert!(
        listed == with_landings,
        "the record differs from brute force"
    );
    assert!(
        listed.len() < rec.paths as usize / 2,
        "metal ring: most paths miss the ring"
    );
}
