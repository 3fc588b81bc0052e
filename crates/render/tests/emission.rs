//! Guided caustic emission (`--emission projection`) against uniform emission on the case
//! scenes: the caustic photon map's total flux agrees within its standard error (the map is
//! unbiased), the yield rises from under 1 % to over 30 % on the glass sphere, the light tracer's
//! caustic image agrees, and photon differentials keep their footprints (seed 002 eq. 5–6 with
//! the emission density): the footprint areas and the `pds` image at equal photons are those of
//! uniform emission.

use caustica_core::Vec3;
mod common;

use caustica_core::image_io::Image;
use caustica_render::photon::caustic::CAUSTIC_STREAM;
use caustica_render::photon::differential::trace_photon_differentials;
use caustica_render::photon::plan::PhotonBudget;
use caustica_render::photon::tracer::{MapKind, trace_photons};
use caustica_render::photon::visible_points::VisiblePoints;
use caustica_render::{
    EmissionStrategy, FootprintSettings, IntegratorKind, PathLimits, PhotonOptions, RenderControl,
    RenderOptions, Smoothing, render,
};
use caustica_scene::Scene;
use common::small_builtin;

fn opts(emission: EmissionStrategy, seed: u64) -> RenderOptions {
    RenderOptions {
        seed,
        caustics_only: true,
        limits: PathLimits {
            max_depth: 16,
            ..PathLimits::default()
        },
        photons: PhotonOptions {
            emission,
            footprints: FootprintSettings {
                smoothing: Smoothing::new(2.0).unwrap(),
                ..Default::default()
            },
            ..Default::default()
        },
        ..Default::default()
    }
}

/// Total flux (W, mean of the channels) of the caustic photons of `paths` light paths, its
/// standard error, and the yield (photons per path). A caustic path stores at most one photon
/// (it ends at its first non-delta vertex), so the per-path terms are the photons' fluxes times
/// N and zeros: var(Φ̂) = (Σ f² − Φ̂²/N).
fn caustic_flux(scene: &Scene, emission: EmissionStrategy, paths: u64) -> (f64, f64, f64) {
    let t = trace_photons(
        scene,
        PhotonBudget::Paths(paths),
        MapKind::Caustic,
        CAUSTIC_STREAM,
        &opts(emission, 3),
        &mut |_| true,
    );
    assert_eq!(t.paths, paths);
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for p in &t.photons {
        let f = p.flux.average() as f64;
        sum += f;
        sum2 += f * f;
    }
    let var = (sum2 - sum * sum / paths as f64).max(0.0);
    (sum, var.sqrt(), t.photons.len() as f64 / paths as f64)
}

/// The caustic map's flux with projection maps equals uniform emission's within 4.5 combined
/// standard errors on the glass sphere (point light), the water wave (point light) and the gold
/// ring (area light), the metal ring (directional light) too; and the glass sphere's yield
/// rises from < 1 % to > 30 %.
#[test]
fn projection_caustic_flux_agrees_with_uniform_and_raises_the_yield() {
    // (scene, uniform paths, projection paths): about 10⁴ uniform photons each.
    for (name, n_u, n_p) in [
        ("glass-sphere", 2_500_000u64, 40_000u64),
        ("water-wave", 40_000, 20_000),
        ("gold-ring", 2_000_000, 60_000),
        ("metal-ring", 200_000, 40_000),
    ] {
        let scene = small_builtin(name, 8, 8);
        let (fu, su, yu) = caustic_flux(&scene, EmissionStrategy::Uniform, n_u);
        let (fp, sp, yp) = caustic_flux(&scene, EmissionStrategy::Projection, n_p);
        let z = (fp - fu) / (su * su + sp * sp).sqrt();
        eprintln!(
            "{name}: flux uniform {fu:.5} ± {su:.5} (yield {:.2} %), projection {fp:.5} ± {sp:.5} (yield {:.2} %), z = {z:+.2}",
            100.0 * yu,
            100.0 * yp
        );
        assert!(
            z.abs() < 4.5,
            "{name}: caustic flux {fp} ± {sp} (projection) vs {fu} ± {su} (uniform), z = {z}"
        );
        assert!(yp > yu, "{name}: yield {yp} not above uniform's {yu}");
        if name == "glass-sphere" {
            assert!(yu < 0.01 && yp > 0.30, "glass sphere yields {yu} → {yp}");
        }
    }
}

fn render_image(scene: &Scene, kind: IntegratorKind, o: &RenderOptions) -> Image {
    render(scene, kind, o, &RenderControl::silent())
        .expect("valid options")
        .film
        .to_image()
}

fn image_sum(img: &Image) -> f64 {
    img.data
        .iter()
        .map(|p| p.iter().map(|&x| x as f64).sum::<f64>())
        .sum()
}

/// The light tracer's caustics-only image (L S+ D E) with projection maps agrees with the plain
/// light tracer's: the image totals of four seeds each agree within 4.5 standard errors (from
/// the spread of the seeds).
#[test]
fn light_tracer_with_projection_maps_agrees_with_the_plain_light_tracer() {
    let scene = small_builtin("glass-sphere", 32, 32);
    let totals = |emission, spp| -> (f64, f64) {
        let xs: Vec<f64> = (0..4)
            .map(|seed| {
                let o = RenderOptions {
                    spp,
                    ..opts(emission, 10 + seed)
                };
                image_sum(&render_image(&scene, IntegratorKind::LightTrace, &o))
            })
            .collect();
        let m = xs.iter().sum::<f64>() / 4.0;
        let var = xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / 3.0;
        (m, (var / 4.0).sqrt())
    };
    let (mu, su) = totals(EmissionStrategy::Uniform, 1024);
    let (mp, sp) = totals(EmissionStrategy::Projection, 64);
    let z = (mp - mu) / (su * su + sp * sp).sqrt();
    eprintln!(
        "light tracer totals: uniform {mu:.4} ± {su:.4}, projection {mp:.4} ± {sp:.4}, z = {z:+.2}"
    );
    assert!(mu > 0.0 && z.abs() < 4.5, "z = {z}");
    // At 1/16 of the paths, guided emission is no noisier.
    assert!(sp < 1.5 * su, "projection s.e. {sp} vs uniform {su}");
}

/// Footprints keep their size: on the glass sphere (point light, relative density ≈ 150 in the
/// marked cells) the median footprint area of 4000 caustic photon differentials with projection
/// maps is uniform emission's within 15 % (without the density correction of the initial
/// vectors it would be ≈ 150 times larger; the two medians of independent samples of one law
/// differ by a few %).
#[test]
fn photon_differential_footprints_keep_their_size_under_guided_emission() {
    let scene = small_builtin("glass-sphere", 8, 8);
    let median_area = |emission| {
        let o = opts(emission, 4);
        let t = trace_photon_differentials(
            &scene,
            PhotonBudget::Records(4000),
            o.photons.footprints.smoothing,
            CAUSTIC_STREAM,
            &o,
            &mut |_| true,
        );
        let mut a: Vec<f32> = t.photons.iter().map(|p| p.footprint.area()).collect();
        assert!(a.len() > 3000, "{} photons", a.len());
        a.sort_by(f32::total_cmp);
        a[a.len() / 2] as f64
    };
    let u = median_area(EmissionStrategy::Uniform);
    let p = median_area(EmissionStrategy::Projection);
    eprintln!("median footprint area: uniform {u:e} m², projection {p:e} m²");
    assert!((p / u - 1.0).abs() < 0.15, "median areas {p} vs {u}");
}

/// `pds` at equal photons: per pixel, the mean of six seeds with projection maps agrees with
/// uniform emission's within the seeds' noise (mean z² near 1; with the footprints left at
/// their uniform size it is ≈ 19), and so do the image totals, so the footprints, and with
/// them the estimate's bias, are the same. A minimum footprint (2 mm) keeps the totals' noise from
/// being dominated by the fireflies of footprints collapsed at the caustic's fold.
#[test]
fn pds_with_projection_maps_matches_uniform_at_equal_photons() {
    let scene = small_builtin("glass-sphere", 48, 48);
    let image = |emission, seed| {
        let base = opts(emission, seed);
        let o = RenderOptions {
            spp: 4,
            photons: PhotonOptions {
                caustic_photons: 20_000,
                footprints: FootprintSettings {
                    min_semi_axis: Some(0.002),
                    ..base.photons.footprints
                },
                ..base.photons
            },
            ..base
        };
        render_image(&scene, IntegratorKind::PhotonDifferentialSplatting, &o)
    };
    let u: Vec<Image> = (1..=6)
        .map(|s| image(EmissionStrategy::Uniform, s))
        .collect();
    let p: Vec<Image> = (1..=6)
        .map(|s| image(EmissionStrategy::Projection, s))
        .collect();
    // Per pixel: the difference of the seed means over its standard error (from the seeds'
    // spread); blurred or sharpened footprints would raise the mean square far above ~1.7 (a
    // t statistic with 5 degrees of freedom has variance 5/3).
    let pixel_stats = |imgs: &[Image], i: usize| {
        let xs: Vec<f64> = imgs
            .iter()
            .map(|im| im.data[i].iter().map(|&x| x as f64).sum())
            .collect();
        let m = xs.iter().sum::<f64>() / xs.len() as f64;
        let var = xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (xs.len() - 1) as f64;
        (m, var / xs.len() as f64)
    };
    let (mut z2, mut n) = (0.0f64, 0usize);
    for i in 0..u[0].data.len() {
        let ((mu, vu), (mp, vp)) = (pixel_stats(&u, i), pixel_stats(&p, i));
        if vu > 0.0 && vp > 0.0 {
            z2 += (mp - mu).powi(2) / (vu + vp);
            n += 1;
        }
    }
    let z2 = z2 / n.max(1) as f64;
    let stats = |imgs: &[Image]| {
        let xs: Vec<f64> = imgs.iter().map(image_sum).collect();
        let m = xs.iter().sum::<f64>() / xs.len() as f64;
        let var = xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (xs.len() - 1) as f64;
        (m, (var / xs.len() as f64).sqrt())
    };
    let ((mu, su), (mp, sp)) = (stats(&u), stats(&p));
    let z = (mp - mu) / (su * su + sp * sp).sqrt();
    eprintln!(
        "pds: mean z² over {n} caustic pixels = {z2:.3}; totals uniform {mu:.3} ± {su:.3}, projection {mp:.3} ± {sp:.3}, z = {z:+.2}"
    );
    assert!(
        n > 100 && z2 < 3.0,
        "per-pixel mean z² = {z2} over {n} pixels"
    );
    assert!(z.abs() < 4.5, "totals: z = {z}");
}

/// Flux (W, mean of channels) of the caustic photons of one pass, all or only those near the
/// camera's visible points.
fn map_flux(
    photons: &[caustica_render::photon::tracer::Photon],
    near: impl Fn(Vec3) -> bool,
) -> (f64, f64) {
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for p in photons.iter().filter(|p| near(p.p)) {
        let f = p.flux.average() as f64;
        sum += f;
        sum2 += f * f;
    }
    (sum, sum2)
}

/// Visibility-driven adaptive photon tracing is unbiased for what the camera sees: the flux of
/// its caustic map (only visible photons) equals the flux of projection-map photons near the
/// visible points, within 4.5 standard errors (the adaptive side's from the spread of four
/// seeds: it includes the normalisation V_c's error and the chains' correlation). On the gold
/// ring only about a fifth of the caustic is in view; a crop of the glass sphere's caustic tail
/// sees under 0.1 % of it.
#[test]
fn adaptive_caustic_flux_agrees_with_the_visible_flux_of_projection_maps() {
    let crop = |x, y, w, h| caustica_render::crop::CropWindow {
        x,
        y,
        width: w,
        height: h,
    };
    for (name, w, h, window, n_p, steps) in [
        ("gold-ring", 64u32, 48u32, None, 200_000u64, 20_000usize),
        (
            "glass-sphere",
            256,
            256,
            Some(crop(90, 160, 32, 32)),
            4_000_000,
            4_000,
        ),
    ] {
        let scene = small_builtin(name, w, h);
        let with = |emission, seed| RenderOptions {
            crop: window,
            ..opts(emission, seed)
        };
        let visible = VisiblePoints::from_camera(&scene, &with(EmissionStrategy::Projection, 3));
        let t = trace_photons(
            &scene,
            PhotonBudget::Paths(n_p),
            MapKind::Caustic,
            CAUSTIC_STREAM,
            &with(EmissionStrategy::Projection, 3),
            &mut |_| true,
        );
        let (fp, sum2) = map_flux(&t.photons, |p| visible.near(p));
        let sp = (sum2 - fp * fp / n_p as f64).max(0.0).sqrt();
        let fa: Vec<f64> = (1..=4)
            .map(|seed| {
                let t = trace_photons(
                    &scene,
                    PhotonBudget::Records(steps),
                    MapKind::Caustic,
                    CAUSTIC_STREAM,
                    &with(EmissionStrategy::Adaptive, seed),
                    &mut |_| true,
                );
                assert!(t.note.is_some(), "the adaptive pass reports itself");
                map_flux(&t.photons, |_| true).0
            })
            .collect();
        let ma = fa.iter().sum::<f64>() / 4.0;
        let sa = (fa.iter().map(|x| (x - ma).powi(2)).sum::<f64>() / 3.0 / 4.0).sqrt();
        let z = (ma - fp) / (sa * sa + sp * sp).sqrt();
        eprintln!(
            "{name}: visible flux projection {fp:.5} ± {sp:.5}, adaptive {ma:.5} ± {sa:.5} (seeds {fa:?}), z = {z:+.2}"
        );
        assert!(fp > 0.0 && z.abs() < 4.5, "{name}: z = {z}");
    }
}

/// The adaptive sampler's chains give the same photons, bit for bit, on one thread and on two.
#[test]
fn adaptive_tracing_does_not_depend_on_the_thread_count() {
    let scene = small_builtin("gold-ring", 32, 24);
    let o = opts(EmissionStrategy::Adaptive, 9);
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                trace_photons(
                    &scene,
                    PhotonBudget::Records(3000),
                    MapKind::Caustic,
                    CAUSTIC_STREAM,
                    &o,
                    &mut |_| true,
                )
            })
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a.paths, b.paths);
    assert!(!a.photons.is_empty());
    assert!(
        a.photons == b.photons,
        "photons differ between 1 and 2 threads"
    );
}

/// pds's adaptive pass replays the chains' states: each state's numbers (lazily extended when
/// a mutated path drew more than its parent) retrace exactly the landings it recorded.
#[test]
fn adaptive_states_replay_their_landings_exactly() {
    use caustica_core::sampling::Sampler;
    use caustica_render::photon::differential::{
        EMISSION_PARAMS, Landing, LandingTracer, count_adaptive, unit_budget,
    };
    use caustica_render::photon::plan::PathStream;
    let scene = small_builtin("gold-ring", 32, 24);
    let o = opts(EmissionStrategy::Adaptive, 5);
    let tracer = LandingTracer::new(&scene, &unit_budget(Smoothing::ONE))
        .with_emission(EmissionStrategy::Adaptive.caustic_rule());
    let visible = VisiblePoints::from_camera(&scene, &o);
    let stream = PathStream::new(&o, CAUSTIC_STREAM);
    let run = count_adaptive(&tracer, 2000, &stream, 0, &o.limits, &visible);
    assert!(
        run.accepted > 0 && run.states.len() > 100,
        "{}",
        run.note(&visible)
    );
    let mut sampler = Sampler::new(o.sampler, o.seed);
    let mut stats = caustica_render::RenderStats::default();
    for (i, s) in run.states.iter().enumerate() {
        sampler.start_path(0xDEAD, i as u64);
        sampler.replay_primary(s.primary.clone());
        let mut out: Vec<Landing<EMISSION_PARAMS>> = Vec::new();
        tracer.trace::<EMISSION_PARAMS>(&mut sampler, &o.limits, &mut out, &mut stats);
        assert_eq!(
            sampler.take_primary().len(),
            s.primary.len(),
            "state {i} drew more numbers than it holds"
        );
        let got: Vec<Vec3> = out.iter().map(|l| l.p).collect();
        assert_eq!(got, s.records, "state {i} retraces other landings");
    }
}
