//! Guided caustic emission (`--emission projection`) against uniform emission on the case
//! scenes: the caustic photon map's total flux agrees within its standard error (the map is
//! unbiased), the yield rises from under 1 % to over 30 % on the glass sphere, the light tracer's
//! caustic image agrees, and photon differentials keep their footprints (seed 002 eq. 5–6 with
//! the emission density): the footprint areas and the `pds` image at equal photons are those of
//! uniform emission.

use caustica_core::image_io::Image;
use caustica_loader::builtin_scene;
use caustica_render::photon::caustic::CAUSTIC_STREAM;
use caustica_render::photon::differential::trace_photon_differentials;
use caustica_render::photon::plan::PhotonBudget;
use caustica_render::photon::tracer::{MapKind, trace_photons};
use caustica_render::{
    EmissionStrategy, FootprintSettings, IntegratorKind, PathLimits, PhotonOptions, RenderControl,
    RenderOptions, Smoothing, render,
};
use caustica_scene::Scene;

fn small_builtin(name: &str, w: u32, h: u32) -> Scene {
    let mut b = builtin_scene(name).unwrap();
    let mut camera = b.camera().unwrap().clone();
    (camera.width, camera.height) = (w, h);
    b.set_camera(camera);
    b.build().unwrap()
}

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
