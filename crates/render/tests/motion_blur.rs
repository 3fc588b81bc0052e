//! Motion blur: the time-sampled light tracer is the unbiased reference, so its blurred caustic
//! must be the average of instantaneous renders across the shutter; and every integrator that
//! samples time stays a pure function of scene, parameters and seed (the same bytes with 1 and
//! 2 threads) on a moving scene.

use caustica_core::image_io::Image;
use caustica_loader::builtin_scene;
use caustica_render::{
    FootprintSettings, IntegratorKind, PathLimits, PhotonOptions, RenderControl, RenderOptions,
    render,
};
use caustica_scene::{Scene, Shutter};

/// The built-in moving wave at `size`² pixels, the shutter `[open, open + length]`.
fn wave(size: u32, open: f32, length: f32) -> Scene {
    moving("moving-wave", size, open, length)
}

/// The built-in scene `name` at `size`² pixels, the shutter `[open, open + length]`.
fn moving(name: &str, size: u32, open: f32, length: f32) -> Scene {
    let mut b = builtin_scene(name).unwrap();
    let mut camera = b.camera().unwrap().clone();
    (camera.width, camera.height) = (size, size);
    b.set_camera(camera);
    b.set_shutter(Shutter::new(open, length).unwrap());
    b.build().unwrap()
}

fn caustics(spp: u32, seed: u64) -> RenderOptions {
    RenderOptions {
        spp,
        seed,
        caustics_only: true,
        limits: PathLimits {
            max_depth: 16,
            ..PathLimits::default()
        },
        ..Default::default()
    }
}

fn run(scene: &Scene, kind: IntegratorKind, opts: &RenderOptions) -> Image {
    render(scene, kind, opts, &RenderControl::silent())
        .expect("valid options")
        .film
        .to_image()
}

/// Green channel, per pixel.
fn green(im: &Image) -> Vec<f64> {
    im.data.iter().map(|p| p[1] as f64).collect()
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The light tracer with time sampled over a one-frame shutter against the mean of 16
/// instantaneous light-tracer renders at the midpoints of 16 equal slices of it, at the same
/// total number of light paths. Both are unbiased estimates of (nearly) the same image — the
/// midpoint rule's error is second order in the slice — so their distance must be that of two
/// independent blurred renders (the noise floor, measured with a second seed), while the
/// unblurred instant at the shutter's opening lies far outside it. A light tracer that ignored
/// the time (every path at the opening) or sampled it outside the shutter fails.
#[test]
fn the_blurred_light_tracer_is_the_mean_of_instantaneous_renders() {
    let (size, spp, slices) = (32, 1024, 16u32);
    let blurred = wave(size, 0.0, 1.0);
    let a = green(&run(
        &blurred,
        IntegratorKind::LightTrace,
        &caustics(spp, 1),
    ));
    let b = green(&run(
        &blurred,
        IntegratorKind::LightTrace,
        &caustics(spp, 2),
    ));
    let mut mean = vec![0.0; a.len()];
    for j in 0..slices {
        let t = (j as f32 + 0.5) / slices as f32;
        let im = run(
            &wave(size, t, 0.0),
            IntegratorKind::LightTrace,
            &caustics(spp / slices, 100 + j as u64),
        );
        for (m, g) in mean.iter_mut().zip(green(&im)) {
            *m += g / slices as f64;
        }
    }
    let instant = green(&run(
        &wave(size, 0.0, 0.0),
        IntegratorKind::LightTrace,
        &caustics(spp, 3),
    ));
    let noise = distance(&a, &b);
    let to_mean = distance(&a, &mean);
    let to_instant = distance(&a, &instant);
    eprintln!(
        "noise floor {noise:.4}, to the mean of instants {to_mean:.4}, unblurred {to_instant:.4}"
    );
    assert!(noise > 0.0);
    // Two independent estimates with equal noise: distance ≈ the noise floor (a 30 % margin
    // for its own scatter over 1024 pixels, about 3 %).
    assert!(to_mean < 1.3 * noise, "{to_mean} vs noise {noise}");
    assert!(
        to_instant > 3.0 * noise,
        "the motion is not visible: {to_instant} vs {noise}"
    );
    let sum = |v: &[f64]| v.iter().sum::<f64>();
    let rel = (sum(&a) - sum(&mean)) / sum(&mean);
    assert!(rel.abs() < 0.02, "total flux {rel:+}");
}

fn bits(im: &Image) -> Vec<u32> {
    im.data.iter().flat_map(|p| p.map(f32::to_bits)).collect()
}

/// Same seed, same bytes with 1 and 2 threads on the moving wave, for every integrator that
/// draws a time: the path and light tracers (time per sample), photon mapping with in-between
/// frames (time-dependent photon mapping) and temporal photon differential splatting. The
/// path tracer runs on the rotating rod (under the wave its floor sees only caustics, which it
/// cannot find from a point light).
#[test]
fn moving_scenes_render_the_same_bytes_with_any_thread_count() {
    let (wave, rod) = (wave(20, 0.0, 1.0), moving("rotating-rod", 20, 0.0, 1.0));
    let tdpm = RenderOptions {
        photons: PhotonOptions {
            caustic_photons: 3000,
            global_photons: 0,
            in_between_frames: Some(2),
            ..Default::default()
        },
        ..caustics(2, 5)
    };
    let tpd = RenderOptions {
        photons: PhotonOptions {
            caustic_photons: 1000,
            footprints: FootprintSettings {
                temporal: true,
                ..Default::default()
            },
            ..Default::default()
        },
        ..caustics(2, 5)
    };
    let cases = [
        (
            &rod,
            IntegratorKind::Path,
            RenderOptions {
                caustics_only: false,
                ..caustics(8, 5)
            },
        ),
        (&wave, IntegratorKind::LightTrace, caustics(16, 5)),
        (&wave, IntegratorKind::PhotonMapping, tdpm),
        (&wave, IntegratorKind::PhotonDifferentialSplatting, tpd),
    ];
    for (scene, kind, opts) in cases {
        let on = |threads: usize, opts: &RenderOptions| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| run(scene, kind, opts))
        };
        let one = on(1, &opts);
        let two = on(2, &opts);
        assert_eq!(bits(&one), bits(&two), "{kind:?}: 1 and 2 threads differ");
        assert!(
            one.data.iter().any(|p| p[1] > 0.0),
            "{kind:?}: nothing rendered"
        );
        let other = on(2, &RenderOptions { seed: 6, ..opts });
        assert_ne!(bits(&one), bits(&other), "{kind:?}: the seed has no effect");
    }
}
