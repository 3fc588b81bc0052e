//! Temporal photon differentials (seed 003; seed 000 ch. 7) and time-dependent photon mapping:
//! the time column against finite differences of photons traced at two instants, the
//! reduction to ordinary photon differentials in a static scene, flux conservation of the
//! space-time footprint, pds = pdm with time, and the agreement of pdm/pds `--temporal` with the
//! motion-blurred light tracer on the moving wave.

use caustica_core::image_io::Image;
use caustica_core::sampling::{Sampler, SamplerKind};
use caustica_core::{Spectrum, Vec3};
use caustica_density::kernel::Kernel;
use caustica_differentials::Footprint;
use caustica_loader::builtin_scene;
use caustica_render::photon::differential::footprint::{sweep_mass, sweep_mass_by_quadrature};
use caustica_render::photon::differential::photons_from_landings;
use caustica_render::photon::differential::{
    DiffPhoton, FootprintFilter, Landing, LandingTracer, TEMPORAL_PARAMS, unit_budget,
};
use caustica_render::{
    FootprintSettings, IntegratorKind, PathLimits, PhotonOptions, RenderControl, RenderOptions,
    RenderStats, ShutterAlign, Smoothing, SweepRule, render,
};
use caustica_scene::{Scene, Shutter};

/// A built-in scene at `w` × `h` pixels with the shutter `[open, open + length]`.
fn scene_at(name: &str, w: u32, h: u32, open: f32, length: f32) -> Scene {
    let mut b = builtin_scene(name).unwrap();
    let mut camera = b.camera().unwrap().clone();
    (camera.width, camera.height) = (w, h);
    b.set_camera(camera);
    b.set_shutter(Shutter::new(open, length).unwrap());
    b.build().unwrap()
}

fn temporal_settings(s: f32) -> FootprintSettings {
    FootprintSettings {
        smoothing: Smoothing::new(s).unwrap(),
        temporal: true,
        ..Default::default()
    }
}

/// The landings of light paths `0..n` of `scene` with three differential parameters.
fn landings(scene: &Scene, n: u64) -> Vec<(u64, Landing<TEMPORAL_PARAMS>)> {
    landings_with(scene, n, &temporal_settings(1.0))
}

/// [`landings`] with the footprint settings `settings` (their alignment chooses the instant).
fn landings_with(
    scene: &Scene,
    n: u64,
    settings: &FootprintSettings,
) -> Vec<(u64, Landing<TEMPORAL_PARAMS>)> {
    let tracer = LandingTracer::new(scene, &unit_budget(Smoothing::ONE)).with_time(settings, scene);
    let limits = PathLimits {
        max_depth: 16,
        ..PathLimits::default()
    };
    let mut sampler = Sampler::new(SamplerKind::Independent, 3);
    let mut st = RenderStats::default();
    let mut out = Vec::new();
    for path in 0..n {
        let mut l = Vec::new();
        sampler.start_path(1, path);
        tracer.trace::<TEMPORAL_PARAMS>(&mut sampler, &limits, &mut l, &mut st);
        out.extend(l.into_iter().map(|x| (path, x)));
    }
    out
}

/// TT2 through the renderer: the same light paths traced at the frame instant τ = 0 and at
/// τ = δ (a scene whose shutter opens δ frames later) land `δ · D_t x / e` apart, to O(δ²) —
/// through refraction at the moving Phong wave and the landing on the floor. A time column
/// with the wrong sign, without the exposure or without the vertex normals' motion fails.
#[test]
fn landings_move_as_their_time_differential_predicts() {
    let e = 1.0;
    let base = landings(&scene_at("moving-wave", 16, 16, 4.0, e), 2000);
    assert!(base.len() > 300, "{} landings", base.len());
    let mut worst = [0.0f32; 2];
    for (k, delta) in [0.02f32, 0.01].into_iter().enumerate() {
        let moved: std::collections::HashMap<u64, Landing<TEMPORAL_PARAMS>> =
            landings(&scene_at("moving-wave", 16, 16, 4.0 + delta, e), 2000)
                .into_iter()
                .collect();
        let mut errs = Vec::new();
        for (path, a) in &base {
            let Some(b) = moved.get(path) else { continue };
            let dt = a.dp.unwrap()[TEMPORAL_PARAMS - 1];
            let predicted = dt * (delta / e);
            let actual = b.p - a.p;
            // Relative to the predicted step (photons near a fold move fastest).
            errs.push((actual - predicted).length() / predicted.length().max(1e-4));
        }
        assert!(
            errs.len() * 10 > base.len() * 9,
            "{} of {}",
            errs.len(),
            base.len()
        );
        errs.sort_by(f32::total_cmp);
        worst[k] = errs[errs.len() * 9 / 10];
        eprintln!("δ = {delta}: 90th percentile relative error {}", worst[k]);
    }
    // First order: the error at δ is O(δ) relative, and halves with δ.
    assert!(worst[0] < 0.1, "{worst:?}");
    assert!(worst[1] < 0.6 * worst[0] + 1e-3, "{worst:?}");
}

/// The wave moves only along its vertical: D_t x is non-zero and lies in the floor's plane.
#[test]
fn time_differentials_lie_in_the_receiving_plane() {
    let l = landings(&scene_at("moving-wave", 16, 16, 0.0, 1.0), 200);
    let mut moving = 0;
    for (_, x) in &l {
        let dt = x.dp.unwrap()[TEMPORAL_PARAMS - 1];
        assert!(dt.y.abs() < 1e-5 * (1.0 + dt.length()), "{dt}");
        moving += (dt.length() > 1e-3) as usize;
    }
    assert!(moving * 10 > l.len() * 9, "{moving} of {}", l.len());
}

fn caustic_opts(kind_photons: usize, s: f32, temporal: bool) -> RenderOptions {
    RenderOptions {
        spp: 2,
        seed: 7,
        caustics_only: true,
        limits: PathLimits {
            max_depth: 16,
            ..PathLimits::default()
        },
        photons: PhotonOptions {
            caustic_photons: kind_photons,
            footprints: FootprintSettings {
                temporal,
                ..temporal_settings(s)
            },
            ..Default::default()
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

/// TT1: in a static scene temporal photon differentials are ordinary ones, to the byte.
#[test]
fn a_static_scene_renders_the_same_bytes_with_and_without_time() {
    let scene = scene_at("water-wave", 32, 32, 0.0, 1.0);
    for kind in [
        IntegratorKind::PhotonDifferentialMapping,
        IntegratorKind::PhotonDifferentialSplatting,
    ] {
        let a = run(&scene, kind, &caustic_opts(2000, 4.0, false));
        let b = run(&scene, kind, &caustic_opts(2000, 4.0, true));
        assert_eq!(a.data, b.data, "{kind:?}");
    }
}

/// pds evaluates pdm's sum the other way round, with time too (1e-5 of the peak).
#[test]
fn temporal_pds_equals_temporal_pdm() {
    let scene = scene_at("moving-wave", 40, 40, 0.0, 1.0);
    let opts = caustic_opts(2000, 4.0, true);
    let a = run(&scene, IntegratorKind::PhotonDifferentialMapping, &opts);
    let b = run(&scene, IntegratorKind::PhotonDifferentialSplatting, &opts);
    let peak = a.data.iter().flatten().fold(0.0f32, |m, &x| m.max(x));
    assert!(peak > 0.0);
    let d = a
        .data
        .iter()
        .flatten()
        .zip(b.data.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0f32, f32::max);
    assert!(d < 1e-5 * peak, "{d} of {peak}");
}

/// TT7: a swept footprint's weights integrate over the receiving plane to 1 (its flux), for
/// the uniform, Epanechnikov and Silverman kernels, for motions short and long against the
/// footprint and oblique to its axes; the closed-form sweep masses agree with quadrature.
#[test]
fn every_space_time_footprint_integrates_to_its_flux() {
    for k in [
        Kernel::Uniform,
        Kernel::Epanechnikov,
        Kernel::Silverman,
        Kernel::Cubic,
    ] {
        let q = sweep_mass_by_quadrature(k, 4000);
        assert!(
            (sweep_mass(k) - q).abs() < 1e-3 * q,
            "{k:?}: {} vs {q}",
            sweep_mass(k)
        );
    }
    let du = Vec3::new(0.2, 0.0, 0.05);
    let dv = Vec3::new(-0.02, 0.0, 0.08);
    let fp = Footprint::new(Vec3::ZERO, du, dv, Vec3::Y).unwrap();
    for kernel in [Kernel::Uniform, Kernel::Epanechnikov, Kernel::Silverman] {
        let filter = FootprintFilter {
            kernel,
            normal_distance: 0.25,
            ..Default::default()
        };
        for dt in [
            Vec3::new(0.03, 0.0, 0.01),
            Vec3::new(0.5, 0.0, 0.7),
            Vec3::new(-0.05, 0.0, 0.4),
        ] {
            let ph = DiffPhoton {
                footprint: fp,
                wi: Vec3::Y,
                n: Vec3::Y,
                flux: Spectrum::ONE,
                depth: 2,
                dt,
            };
            let (lo, hi) = filter.bounds(&ph).unwrap();
            let n = 600;
            let (sx, sz) = ((hi.x - lo.x) / n as f32, (hi.z - lo.z) / n as f32);
            let mut sum = 0.0f64;
            for i in 0..n {
                for j in 0..n {
                    let x = Vec3::new(
                        lo.x + (i as f32 + 0.5) * sx,
                        0.0,
                        lo.z + (j as f32 + 0.5) * sz,
                    );
                    if let Some(w) = filter.weight(&ph, x, Vec3::Y) {
                        sum += w as f64;
                    }
                }
            }
            let total = sum * (sx * sz) as f64;
            assert!(
                (total - 1.0).abs() < 0.01,
                "{kernel:?} dt = {dt}: ∫ = {total}"
            );
        }
    }
}

/// The Euclidean closest point of the text (seed 000 sec. 7.1.1 read literally) loses energy
/// on elongated footprints: the support the filter-space rule covers is the stadium of
/// eq. 7.7 (this fails if `swept_weight` measured the closest point in world space).
#[test]
fn the_swept_support_is_the_area_of_eq_7_7() {
    let du = Vec3::new(2.0, 0.0, 0.0);
    let dv = Vec3::new(0.0, 0.0, 0.3);
    let dt = Vec3::new(0.7, 0.0, 0.7);
    let fp = Footprint::new(Vec3::ZERO, du, dv, Vec3::Y).unwrap();
    let ph = DiffPhoton {
        footprint: fp,
        wi: Vec3::Y,
        n: Vec3::Y,
        flux: Spectrum::ONE,
        depth: 2,
        dt,
    };
    let filter = FootprintFilter {
        kernel: Kernel::Uniform,
        normal_distance: 0.25,
        ..Default::default()
    };
    let (lo, hi) = filter.bounds(&ph).unwrap();
    let n = 800;
    let (sx, sz) = ((hi.x - lo.x) / n as f32, (hi.z - lo.z) / n as f32);
    let mut support = 0usize;
    for i in 0..n {
        for j in 0..n {
            let x = Vec3::new(
                lo.x + (i as f32 + 0.5) * sx,
                0.0,
                lo.z + (j as f32 + 0.5) * sz,
            );
            support += filter.weight(&ph, x, Vec3::Y).is_some() as usize;
        }
    }
    let area = support as f32 * sx * sz;
    // eq. 7.7: (π/4)|D_u × D_v| + l |D_t x|, l the ellipse's width across the motion.
    let nperp = Vec3::new(-dt.z, 0.0, dt.x).normalize();
    let l = ((du.dot(nperp)).powi(2) + (dv.dot(nperp)).powi(2)).sqrt();
    let eq77 = std::f32::consts::FRAC_PI_4 * du.cross(dv).length() + l * dt.length();
    assert!(
        (area - eq77).abs() < 0.01 * eq77,
        "support {area} vs eq. 7.7 {eq77}"
    );
}

/// The method on the moving wave: pds `--temporal` with few photons and the motion-blurred
/// light tracer agree in mean over the lit floor, and TPD's image is much closer to the
/// blurred reference than the unblurred instant's caustic is (so the blur is where the light
/// tracer puts it). Tolerances: the light tracer's per-pixel noise at this sample count is
/// ~25 %; band means over 16 columns are within a few percent.
#[test]
fn temporal_splatting_matches_the_motion_blurred_light_tracer() {
    let scene = scene_at("moving-wave", 48, 48, 0.0, 1.0);
    let mut lt = caustic_opts(0, 1.0, false);
    lt.spp = 512;
    let reference = run(&scene, IntegratorKind::LightTrace, &lt);
    let tpd = run(
        &scene,
        IntegratorKind::PhotonDifferentialSplatting,
        &caustic_opts(4000, 4.0, true),
    );
    let instant = run(
        &scene_at("moving-wave", 48, 48, 0.0, 0.0),
        IntegratorKind::PhotonDifferentialSplatting,
        &caustic_opts(4000, 4.0, true),
    );
    // Column profiles (the wave travels along x, the image's x).
    let profile = |im: &Image| -> Vec<f64> {
        (0..im.width)
            .map(|x| {
                (0..im.height)
                    .map(|y| im.data[y * im.width + x][1] as f64)
                    .sum::<f64>()
            })
            .collect()
    };
    let (r, t, i) = (profile(&reference), profile(&tpd), profile(&instant));
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let rel = (mean(&t) - mean(&r)) / mean(&r);
    assert!(rel.abs() < 0.05, "TPD mean {rel:+}");
    let l2 = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let (dt, di) = (l2(&t, &r), l2(&i, &r));
    eprintln!("profile distance to the blurred reference: TPD {dt}, unblurred {di}");
    assert!(dt < 0.5 * di, "TPD {dt} vs unblurred instant {di}");
}

fn centred() -> FootprintSettings {
    FootprintSettings {
        sweep: SweepRule {
            align: ShutterAlign::Centred,
            ..Default::default()
        },
        ..temporal_settings(1.0)
    }
}

/// The centred shutter alignment (seed 000 Q-T8): photons are traced at the shutter's middle,
/// stored with their segment `[x − D_t x/2, x + D_t x/2]`, and that segment's ends are closer
/// to where the photon really is when the shutter opens and closes than the forward segment's
/// far end is (midpoint rule: second order, about a quarter of the forward error).
#[test]
fn the_centred_alignment_sweeps_around_the_shutters_middle() {
    let (open, e) = (4.0, 1.0);
    let n = 1500;
    let mid = landings_with(&scene_at("moving-wave", 16, 16, open, e), n, &centred());
    // Traced at the middle: the same landings as a forward shutter opening there.
    let at_mid: Vec<_> = landings(&scene_at("moving-wave", 16, 16, open + 0.5 * e, e), n);
    assert_eq!(mid.len(), at_mid.len());
    for ((pa, a), (pb, b)) in mid.iter().zip(&at_mid) {
        assert_eq!((pa, a.p, a.dp), (pb, b.p, b.dp));
    }
    // Stored with the segment start at x − D_t x/2.
    let only: Vec<_> = mid.iter().map(|(_, l)| *l).collect();
    let photons = photons_from_landings(&only, 1, ShutterAlign::Centred, None).photons;
    let forward = photons_from_landings(&only, 1, ShutterAlign::Forward, None).photons;
    assert_eq!(photons.len(), only.len());
    for ((c, f), l) in photons.iter().zip(&forward).zip(&only) {
        let dt = l.dp.unwrap()[TEMPORAL_PARAMS - 1];
        assert!((c.footprint.center() - (l.p - 0.5 * dt)).length() < 1e-6);
        assert_eq!(f.footprint.center(), l.p);
        assert_eq!(c.dt, dt);
    }
    // Where the photons are at the shutter's opening and closing.
    let truth = |t: f32| -> std::collections::HashMap<u64, Vec3> {
        landings(&scene_at("moving-wave", 16, 16, t, e), n)
            .into_iter()
            .map(|(k, l)| (k, l.p))
            .collect()
    };
    let (start, end) = (truth(open), truth(open + e));
    let fwd: std::collections::HashMap<u64, _> =
        landings(&scene_at("moving-wave", 16, 16, open, e), n)
            .into_iter()
            .collect();
    let (mut err_c, mut err_f) = (Vec::new(), Vec::new());
    for (k, l) in &mid {
        let (Some(s0), Some(s1), Some(f)) = (start.get(k), end.get(k), fwd.get(k)) else {
            continue;
        };
        let span = (*s1 - *s0).length().max(1e-4);
        let dt = l.dp.unwrap()[TEMPORAL_PARAMS - 1];
        let c = ((l.p - 0.5 * dt - *s0).length()).max((l.p + 0.5 * dt - *s1).length());
        let fdt = f.dp.unwrap()[TEMPORAL_PARAMS - 1];
        err_c.push(c / span);
        err_f.push((f.p + fdt - *s1).length() / span);
    }
    assert!(err_c.len() > 300, "{}", err_c.len());
    for v in [&mut err_c, &mut err_f] {
        v.sort_by(f32::total_cmp);
    }
    let (c90, f90) = (err_c[err_c.len() * 9 / 10], err_f[err_f.len() * 9 / 10]);
    eprintln!("segment end error, 90th percentile: centred {c90}, forward {f90}");
    assert!(c90 < 0.5 * f90, "centred {c90} vs forward {f90}");
}

/// Flux conservation with the time filter (seed 000 eq. 7.9 normalised, Q-T4/Q-T5): every
/// footprint integrates to its flux for three footprint kernels, two time kernels and both
/// alignments; a uniform time kernel is no filter at all; the filter weighs the traced instant
/// most; and eq. 7.7's literal area over-counts a non-uniform kernel (it is exact only for the
/// uniform one).
#[test]
fn time_filtered_footprints_integrate_to_their_flux() {
    let du = Vec3::new(0.2, 0.0, 0.05);
    let dv = Vec3::new(-0.02, 0.0, 0.08);
    let fp = Footprint::new(Vec3::ZERO, du, dv, Vec3::Y).unwrap();
    let photon = |dt| DiffPhoton {
        footprint: fp,
        wi: Vec3::Y,
        n: Vec3::Y,
        flux: Spectrum::ONE,
        depth: 2,
        dt,
    };
    let integral = |filter: &FootprintFilter, ph: &DiffPhoton| {
        let (lo, hi) = filter.bounds(ph).unwrap();
        let n = 500;
        let (sx, sz) = ((hi.x - lo.x) / n as f32, (hi.z - lo.z) / n as f32);
        let mut sum = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let x = Vec3::new(
                    lo.x + (i as f32 + 0.5) * sx,
                    0.0,
                    lo.z + (j as f32 + 0.5) * sz,
                );
                sum += filter.weight(ph, x, Vec3::Y).unwrap_or(0.0) as f64;
            }
        }
        sum * (sx * sz) as f64
    };
    let dts = [Vec3::new(0.03, 0.0, 0.01), Vec3::new(0.5, 0.0, 0.7)];
    for kernel in [Kernel::Uniform, Kernel::Epanechnikov, Kernel::Silverman] {
        for time in [Kernel::Epanechnikov, Kernel::Biweight] {
            for align in [ShutterAlign::Forward, ShutterAlign::Centred] {
                let filter = FootprintFilter {
                    kernel,
                    normal_distance: 0.25,
                    sweep: SweepRule {
                        align,
                        time_filter: Some(time),
                        paper_area: false,
                    },
                };
                for dt in dts {
                    let total = integral(&filter, &photon(dt));
                    assert!(
                        (total - 1.0).abs() < 0.01,
                        "{kernel:?}, time {time:?}, {align:?}, dt = {dt}: ∫ = {total}"
                    );
                }
            }
        }
    }
    // A uniform time kernel weighs every instant alike: the same weights as no filter.
    let plain = FootprintFilter {
        kernel: Kernel::Silverman,
        normal_distance: 0.25,
        ..Default::default()
    };
    let uniform = FootprintFilter {
        sweep: SweepRule {
            time_filter: Some(Kernel::Uniform),
            ..Default::default()
        },
        ..plain
    };
    let ph = photon(dts[1]);
    for k in 0..50 {
        let x = Vec3::new(0.012 * k as f32, 0.0, 0.014 * k as f32 - 0.02);
        let (a, b) = (
            plain.weight(&ph, x, Vec3::Y),
            uniform.weight(&ph, x, Vec3::Y),
        );
        match (a, b) {
            (Some(a), Some(b)) => assert!((a - b).abs() <= 1e-5 * a, "{a} vs {b}"),
            (a, b) => assert_eq!(a.is_some(), b.is_some()),
        }
    }
    // The filtered weight along the segment peaks at the traced instant: the hit (forward)
    // or the segment's middle (centred).
    for (align, peak) in [(ShutterAlign::Forward, 0.0), (ShutterAlign::Centred, 0.5)] {
        let f = FootprintFilter {
            sweep: SweepRule {
                align,
                time_filter: Some(Kernel::Epanechnikov),
                paper_area: false,
            },
            ..plain
        };
        let at = |tau: f32| {
            f.weight(&ph, ph.footprint.center() + ph.dt * tau, Vec3::Y)
                .unwrap()
        };
        let best = (0..=10)
            .map(|i| i as f32 / 10.0)
            .max_by(|a, b| at(*a).total_cmp(&at(*b)));
        assert_eq!(best, Some(peak), "{align:?}");
        assert!(at(0.95) < 0.2 * at(peak), "{align:?}");
    }
    // eq. 7.7 literally: exact for the uniform kernel, too much energy for Epanechnikov's
    // (at most 4/3 of the flux).
    let paper = |kernel| FootprintFilter {
        kernel,
        normal_distance: 0.25,
        sweep: SweepRule {
            paper_area: true,
            ..Default::default()
        },
    };
    assert!((integral(&paper(Kernel::Uniform), &ph) - 1.0).abs() < 0.01);
    let over = integral(&paper(Kernel::Epanechnikov), &ph);
    assert!(over > 1.15 && over < 4.0 / 3.0, "{over}");
}
