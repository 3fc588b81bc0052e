//! Spectral mode (issue 22): the per-wavelength white furnace, with and without a dispersive
//! glass ball in it; agreement of spectral and RGB renders where the scene is spectrally flat;
//! the prism's colours landing where Snell's law with the glass's Sellmeier IOR puts them; and
//! the light tracer and pds agreeing on the prism's table caustic.

mod common;

use caustica_core::sampling::{Sampler, SamplerKind};
use caustica_core::spectral::{SampledWavelengths, linear_srgb_to_xyz};
use caustica_core::{Channels, Spectrum, Vec2, Vec3};
use caustica_loader::builtin::prism;
use caustica_render::integrator::path::{PathOnly, radiance_with};
use caustica_render::transport::light_walk::{LightEvent, walk_light_path};
use caustica_render::{
    IntegratorKind, PathLimits, RenderControl, RenderOptions, RenderStats, Smoothing, render,
};
use caustica_scene::Scene;
use caustica_scene::dispersion::Dispersion;
use caustica_scene::material::Material;

/// The white furnace (`common::furnace`, 16 × 16) in spectral mode.
fn furnace(material: Material) -> Scene {
    let mut scene = common::furnace(material, 16);
    scene.set_spectral(true).unwrap();
    scene
}

/// Luminance Y of a linear-sRGB value.
fn y_of(c: Spectrum) -> f64 {
    linear_srgb_to_xyz(c.to_rgb())[1] as f64
}

/// For every 20 nm bin of [380, 780] nm: camera paths through the centre pixel (which sees the
/// ball) whose three wavelengths all lie in the bin return, on average, the environment's
/// radiance at those wavelengths — the luminance of the path's estimate over that of the
/// environment's value in the same lanes is 1 within 1 %.
fn furnace_per_bin(scene: &Scene, paths: u32) {
    let opts = RenderOptions {
        limits: PathLimits {
            max_depth: 1000,
            ..PathLimits::default()
        },
        ..Default::default()
    };
    let mut stats = RenderStats::default();
    let mut sampler = Sampler::new(SamplerKind::Independent, 7);
    let env = Spectrum::ONE;
    let mut bin = 380.0f32;
    while bin < 780.0 {
        let (mut got, mut want) = (0.0f64, 0.0f64);
        for i in 0..paths {
            sampler.start_pixel_sample(8, 8, i);
            let u =
                |k: u32| bin + 20.0 * ((i as f32 + 0.5 + k as f32 / 3.0) / paths as f32).fract();
            let wl = SampledWavelengths {
                lambda: [u(0), u(1), u(2)],
                pdf: [1.0; 3],
            };
            let ch = Channels::Spectral(wl);
            let ray = scene
                .camera
                .generate_ray(Vec2::new(8.0, 8.0), Vec2::splat(0.5))
                .ray;
            let l = radiance_with(scene, ray, &mut sampler, &opts, &mut stats, &PathOnly, ch);
            got += y_of(l);
            want += y_of(ch.to_rgb(ch.illuminant(env)));
        }
        let ratio = got / want;
        assert!(
            (ratio - 1.0).abs() < 0.01,
            "{}–{} nm: furnace ratio {ratio}",
            bin,
            bin + 20.0
        );
        bin += 20.0;
    }
}

#[test]
fn white_furnace_at_every_wavelength() {
    let white = Material::Diffuse {
        reflectance: caustica_scene::texture::Texture::Constant(Spectrum::ONE),
    };
    furnace_per_bin(&furnace(white), 4096);
}

/// A dispersive glass ball (F2) in the furnace is invisible at every wavelength: the hero alone
/// carries on after the first refraction (the secondary wavelengths ended), and its estimate is
/// still the environment's radiance.
#[test]
fn dispersive_glass_furnace_at_every_wavelength() {
    let law = Dispersion::named("F2").unwrap();
    let glass = Material::Dielectric {
        ior: law.ior_d(),
        absorption: Spectrum::ZERO,
        dispersion: Some(law),
    };
    furnace_per_bin(&furnace(glass), 2048);
}

/// The whole furnace image in spectral mode (wavelengths drawn per sample) is (1, 1, 1).
#[test]
fn dispersive_glass_furnace_image_is_white() {
    let law = Dispersion::named("BK7").unwrap();
    let scene = furnace(Material::Dielectric {
        ior: law.ior_d(),
        absorption: Spectrum::ZERO,
        dispersion: Some(law),
    });
    let img = common::render_image(&scene, IntegratorKind::Path, 512, 3);
    let n = img.data.len() as f64;
    let mut mean = [0.0f64; 3];
    for p in &img.data {
        for k in 0..3 {
            mean[k] += p[k] as f64 / n;
        }
    }
    for (k, m) in mean.iter().enumerate() {
        assert!((m - 1.0).abs() < 0.01, "channel {k}: {m}");
    }
}

/// Per channel: the mean image value over 4 seeds from `first_seed` and its standard error
/// (caustics alone for the methods that can isolate them: less noise).
fn seeds_mean(scene: &Scene, kind: IntegratorKind, spp: u32, first_seed: u64) -> [(f64, f64); 3] {
    let runs: Vec<[f64; 3]> = (0..4)
        .map(|i| {
            let opts = RenderOptions {
                spp,
                seed: first_seed + i,
                caustics_only: kind != IntegratorKind::Path,
                ..Default::default()
            };
            let out = render(scene, kind, &opts, &RenderControl::silent()).unwrap();
            common::mean_rgb(&out.film.to_image())
        })
        .collect();
    common::mean_and_standard_error(&runs)
}

/// `scene` (in RGB mode) renders the same in spectral mode with each of `kinds`: the means over
/// 4 seeds agree within 4 standard errors of their difference (estimated from the seeds'
/// spread) plus the upsampling's 0.5 %, and that tolerance is a few per cent at most.
fn assert_modes_agree(mut scene: Scene, kinds: &[(IntegratorKind, u32)]) {
    let rgb: Vec<_> = kinds
        .iter()
        .map(|&(k, spp)| seeds_mean(&scene, k, spp, 1))
        .collect();
    scene.set_spectral(true).unwrap();
    for (&(kind, spp), rgb) in kinds.iter().zip(&rgb) {
        let spectral = seeds_mean(&scene, kind, spp, 101);
        for k in 0..3 {
            let ((a, sa), (b, sb)) = (spectral[k], rgb[k]);
            let tol = 4.0 * (sa * sa + sb * sb).sqrt() + 0.005 * b;
            assert!(
                (a - b).abs() < tol,
                "{}: {kind:?} channel {k}: spectral {a} ± {sa} vs RGB {b} ± {sb}",
                scene.name
            );
            assert!(tol < 0.05 * b, "{kind:?}: noise too large ({tol} of {b})");
        }
    }
}

/// A spectrally flat scene (grey materials, white lights, clear glass without dispersion)
/// renders the same in both modes: the glass ball's caustic on a grey floor by the light tracer
/// and the path tracer's image (pds in spectral mode is checked against the light tracer on the
/// prism, below).
#[test]
fn glass_ball_same_in_rgb_and_spectral_mode() {
    assert_modes_agree(
        common::ball_on_floor(0.5, 20.0, 4.0, true, 32),
        &[
            (IntegratorKind::LightTrace, 256),
            (IntegratorKind::Path, 16),
        ],
    );
}

/// The water wave's caustic (directional light through water onto a grey floor) by the light
/// tracer, the same in both modes.
#[test]
fn water_wave_same_in_rgb_and_spectral_mode() {
    let mut b = caustica_loader::builtin_scene("water-wave").unwrap();
    let mut cam = b.camera().unwrap().clone();
    (cam.width, cam.height) = (32, 32);
    b.set_camera(cam);
    assert_modes_agree(b.build().unwrap(), &[(IntegratorKind::LightTrace, 64)]);
}

/// Exact path of a ray through the prism by the vector form of Snell's law at its two planar
/// faces (independent of the renderer's BVH and BSDF code): where it meets the screen plane.
fn snell_landing(o: Vec3, d: Vec3, n: f32, screen_p: Vec3, screen_n: Vec3) -> Option<Vec3> {
    snell_path(o, d, n, screen_p, screen_n).map(|(p, _)| p)
}

/// [`snell_landing`] with the direction the ray leaves the prism in.
fn snell_path(o: Vec3, d: Vec3, n: f32, screen_p: Vec3, screen_n: Vec3) -> Option<(Vec3, Vec3)> {
    let [l, r, t] = prism::prism_corners();
    let face = |a: (f32, f32), b: (f32, f32)| {
        let pa = Vec3::new(a.0, 0.0, a.1);
        let e = Vec3::new(b.0 - a.0, 0.0, b.1 - a.1);
        // Outward normal: away from the centroid (the origin).
        let mut nrm = Vec3::new(e.z, 0.0, -e.x).normalize();
        if nrm.dot(pa) < 0.0 {
            nrm = -nrm;
        }
        (pa, nrm)
    };
    let refract = |d: Vec3, nrm: Vec3, eta: f32| -> Option<Vec3> {
        // nrm faces the incoming side; eta = n_i / n_t.
        let cos_i = -d.dot(nrm);
        let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
        (k >= 0.0).then(|| (eta * d + (eta * cos_i - k.sqrt()) * nrm).normalize())
    };
    let hit = |o: Vec3, d: Vec3, p: Vec3, nrm: Vec3| o + d * ((p - o).dot(nrm) / d.dot(nrm));
    let (p1, n1) = face(l, t);
    let (p2, n2) = face(r, t);
    let a = hit(o, d, p1, n1);
    let d1 = refract(d, n1, 1.0 / n)?;
    let b = hit(a, d1, p2, n2);
    let d2 = refract(d1, -n2, n)?;
    Some((hit(b, d2, screen_p, screen_n), d2))
}

/// Where a light path of the levelled prism first meets the screen (after the two faces).
struct ScreenLanding {
    /// Emitted ray.
    origin: Vec3,
    dir: Vec3,
    /// Landing point, screen normal, direction the light arrived in, hero wavelength (nm).
    p: Vec3,
    ng: Vec3,
    arrival: Vec3,
    hero: f32,
}

/// The landings of `paths` light paths (seed 11) of the prism with its beam levelled onto the
/// screen, in spectral mode.
fn screen_landings(paths: u32) -> Vec<ScreenLanding> {
    let mut scene = prism::prism_with_slope(0.0).unwrap().build().unwrap();
    scene.set_spectral(true).unwrap();
    let screen_mat = scene
        .material_names
        .iter()
        .position(|n| n == "screen")
        .unwrap() as u32;
    let mut stats = RenderStats::default();
    let mut sampler = Sampler::new(SamplerKind::Independent, 11);
    let mut out = Vec::new();
    for i in 0..paths {
        sampler.start_pixel_sample(0, 0, i);
        let mut origin = None;
        let mut landed = None;
        walk_light_path(
            &scene,
            &mut sampler,
            &PathLimits::default(),
            &mut stats,
            |event, _, _| match event {
                LightEvent::Start(s) => origin = Some((s.emission.ray.o, s.emission.ray.d)),
                LightEvent::Vertex(v) => {
                    if landed.is_none() && v.v.si.material == screen_mat && v.depth == 3 {
                        landed = Some((v.v.si.p, v.v.si.ng, -v.wo, v.v.channels.hero()));
                    }
                }
                LightEvent::Medium(_) => {}
            },
        );
        if let (Some((origin, dir)), Some((p, ng, arrival, Some(hero)))) = (origin, landed) {
            out.push(ScreenLanding {
                origin,
                dir,
                p,
                ng,
                arrival,
                hero,
            });
        }
    }
    out
}

/// The prism with a level beam: every light path's first landing on the screen, by its hero
/// wavelength, lies where Snell's law with F2's Sellmeier IOR at that wavelength sends the
/// same emitted ray — within a tenth of a millimetre, far below a pixel of the camera there
/// (about 1 mm) — and the colours fan out in order (blue deviated most).
#[test]
fn prism_colours_land_where_snell_puts_them() {
    let law = prism::prism_dispersion();
    let landings = screen_landings(4000);
    let checked = landings.len();
    let mut worst = 0.0f32;
    for l in &landings {
        let want = snell_landing(l.origin, l.dir, law.ior(l.hero), l.p, l.ng).unwrap();
        worst = worst.max((want - l.p).length());
    }
    let by_colour: Vec<(f32, Vec3)> = landings.iter().map(|l| (l.hero, l.p)).collect();
    assert!(checked > 3000, "only {checked} paths reached the screen");
    assert!(worst < 1e-4, "worst landing error {worst} m");
    // Blue lands farther along the deviation than red: project on the screen's horizontal.
    let az = prism::prism_incident_azimuth_deg().to_radians();
    let across = Vec3::new(az.sin(), 0.0, az.cos());
    let mean_at = |lo: f32, hi: f32| {
        let v: Vec<f32> = by_colour
            .iter()
            .filter(|(l, _)| (lo..hi).contains(l))
            .map(|(_, p)| p.dot(across))
            .collect();
        v.iter().sum::<f32>() / v.len() as f32
    };
    let (blue, green, red) = (
        mean_at(440.0, 460.0),
        mean_at(540.0, 560.0),
        mean_at(640.0, 660.0),
    );
    assert!(
        (blue - green) * (green - red) > 0.0,
        "colours out of order: {blue} {green} {red}"
    );
}

/// Wavelength photon differentials (issue 22): the column `D_λ x` the tracer carries to the
/// screen of the level prism — refracted at both faces with `∂η/∂λ` from F2's Sellmeier law
/// (`refract_dispersive`) — equals the central difference over ±0.5 nm of where Snell's law
/// with that law sends the same emitted ray (an independent computation), within 1 %; and
/// without the `∂η/∂λ` term the column would be zero (the emitted ray does not depend on λ).
#[test]
fn wavelength_differentials_follow_the_dispersion_fan() {
    use caustica_core::spectral::visible_pdf;
    use caustica_render::FootprintSettings;
    use caustica_render::photon::differential::{Landing, LandingTracer, unit_budget};
    let law = prism::prism_dispersion();
    let mut scene = prism::prism_with_slope(0.0).unwrap().build().unwrap();
    scene.set_spectral(true).unwrap();
    let k = 1.0;
    let s = 4.0;
    let settings = FootprintSettings {
        wavelength_spread: Some(k),
        ..Default::default()
    };
    let tracer = LandingTracer::new(&scene, &unit_budget(Smoothing::new(s).unwrap()))
        .with_wavelength(&settings, &scene);
    assert!(tracer.has_third_column());
    let limits = PathLimits::default();
    let mut stats = RenderStats::default();
    let mut sampler = Sampler::new(SamplerKind::Independent, 11);
    let (mut checked, mut worst) = (0, 0.0f32);
    for i in 0..400 {
        let mut landings: Vec<Landing<3>> = Vec::new();
        sampler.start_pixel_sample(0, 0, i);
        tracer.trace::<3>(&mut sampler, &limits, &mut landings, &mut stats);
        // The same path again (same numbers) through the plain walker: its emitted ray and hero.
        sampler.start_pixel_sample(0, 0, i);
        let mut start = None;
        let mut hero = None;
        walk_light_path(
            &scene,
            &mut sampler,
            &limits,
            &mut stats,
            |event, _, _| match event {
                LightEvent::Start(st) => start = Some((st.emission.ray.o, st.emission.ray.d)),
                LightEvent::Vertex(v) => {
                    if hero.is_none() {
                        hero = v.v.channels.hero();
                    }
                }
                LightEvent::Medium(_) => {}
            },
        );
        let (Some(l), Some((o, d)), Some(hero)) = (landings.first(), start, hero) else {
            continue;
        };
        let Some(dp) = l.dp else { continue };
        if l.depth != 3 {
            continue; // the screen behind the two faces
        }
        // The tracer's column is D_λ x · K s / p(λ) (m) for N_e = 1.
        let dx_dl = dp[2] * (visible_pdf(hero) / (k * s));
        let h = 2.0;
        let at = |lambda: f32| snell_landing(o, d, law.ior(lambda), l.p, l.n).unwrap();
        let fd = (at(hero + h) - at(hero - h)) / (2.0 * h);
        assert!(fd.length() > 1e-5, "the fan moves {} m/nm", fd.length());
        worst = worst.max((dx_dl - fd).length() / fd.length());
        checked += 1;
    }
    assert!(checked > 200, "only {checked} screen landings");
    assert!(worst < 0.01, "D_λ x off the fan by {:.2} %", worst * 100.0);
}

/// A wavelength column becomes a sweep centred on the hit and divided by the light's `N_e`
/// (`N pmf`, a photon's share of the spectrum), where a time column is kept as it is and swept
/// forward from the hit.
#[test]
fn wavelength_column_sweeps_centred_over_the_photons_share() {
    use caustica_render::ShutterAlign;
    use caustica_render::photon::differential::{Landing, SweepColumn, photons_from_landings};
    let landing = Landing::<3> {
        p: Vec3::new(0.5, 0.0, -0.25),
        wi: Vec3::Y,
        n: Vec3::Y,
        beta: Spectrum::splat(3.0),
        depth: 3,
        pmf: 0.5,
        dp: Some([
            Vec3::new(0.2, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 0.2),
            Vec3::new(0.8, 0.0, 0.4),
        ]),
    };
    let paths = 100;
    let w = photons_from_landings(&[landing], paths, SweepColumn::Wavelength, None).photons[0];
    let t = photons_from_landings(&[landing], paths, ShutterAlign::Forward, None).photons[0];
    let share = 1.0 / (paths as f32 * 0.5);
    assert!(
        (w.dt - Vec3::new(0.8, 0.0, 0.4) * share).length() < 1e-7,
        "{:?}",
        w.dt
    );
    assert!((w.footprint.center() - (landing.p - w.dt * 0.5)).length() < 1e-7);
    assert!((w.reach_center() - landing.p).length() < 1e-7);
    assert_eq!(t.dt, Vec3::new(0.8, 0.0, 0.4));
    assert_eq!(t.footprint.center(), landing.p);
    assert_eq!(w.flux, t.flux);
    // The footprint itself (emission columns) is the same for both.
    assert!((w.footprint.area() - t.footprint.area()).abs() < 1e-9);
}

/// The prism's table caustic, in spectral mode: the light tracer and pds put the same energy in
/// the region around the streak (within 5 %: noise of both and pds's footprint blur at the
/// streak's sharp edges), and the streak is coloured (its red and blue ends differ).
#[test]
fn prism_table_caustic_light_tracer_and_pds_agree() {
    let mut b = prism::prism_with_slope(prism::PRISM_BEAM_SLOPE_DEG).unwrap();
    let cam = b.camera().unwrap().clone();
    let mut cam = cam;
    (cam.width, cam.height) = (100, 75);
    b.set_camera(cam);
    let mut scene = b.build().unwrap();
    scene.set_spectral(true).unwrap();
    let opts = |spp| RenderOptions {
        spp,
        seed: 5,
        caustics_only: true,
        ..Default::default()
    };
    let lt = render(
        &scene,
        IntegratorKind::LightTrace,
        &opts(256),
        &RenderControl::silent(),
    )
    .unwrap()
    .film
    .to_image();
    let mut o = opts(2);
    o.photons.caustic_photons = 100_000;
    // The smoothing the command line's cross-validation picks for this view (s ≈ 23).
    o.photons.footprints.smoothing = Smoothing::new(23.0).unwrap();
    let pds = render(
        &scene,
        IntegratorKind::PhotonDifferentialSplatting,
        &o,
        &RenderControl::silent(),
    )
    .unwrap()
    .film
    .to_image();
    let (a, b) = (common::mean_rgb(&lt), common::mean_rgb(&pds));
    let (ya, yb) = (a.iter().sum::<f64>(), b.iter().sum::<f64>());
    assert!(ya > 0.0, "the light tracer found no caustic");
    assert!(
        (yb / ya - 1.0).abs() < 0.05,
        "pds {b:?} vs light tracer {a:?}"
    );
    // Coloured: the streak's pixels are saturated spectral colours (1 − min/max of the linear
    // sRGB above 0.8 for most of them; a path that kept its three wavelengths through the prism
    // would land them together, a pastel mix), and its red and blue ends differ.
    let bright = 0.2 * 3.0 * ya as f32 * 100.0;
    let streak: Vec<[f32; 3]> = lt
        .data
        .iter()
        .filter(|p| p[0] + p[1] + p[2] > bright)
        .copied()
        .collect();
    assert!(streak.len() > 4, "no streak pixels");
    let saturation = |p: &[f32; 3]| {
        let hi = p[0].max(p[1]).max(p[2]);
        1.0 - p[0].min(p[1]).min(p[2]).max(0.0) / hi
    };
    let saturated = streak.iter().filter(|p| saturation(p) > 0.8).count();
    assert!(
        saturated * 2 > streak.len(),
        "{saturated} of {} streak pixels saturated",
        streak.len()
    );
    let mut ratios: Vec<f32> = streak
        .iter()
        .map(|p| p[0] / (p[2].max(0.0) + 1e-3))
        .collect();
    ratios.sort_by(f32::total_cmp);
    assert!(
        ratios[ratios.len() - 1] > 4.0 * ratios[0],
        "streak not coloured: {ratios:?}"
    );
}

/// The measured angular positions of the colours on the screen (docs/results/spectral): for
/// 20 nm bins, the mean deviation of the rendered light paths (angle between the beam and the
/// ray reaching the screen, degrees) against Snell's law for the beam's axis at the bin's mean
/// wavelength, and the landing's mean horizontal position on the screen. Run with
/// `cargo test --release -p caustica-render --test spectral prism_deviation_report -- --ignored
/// --nocapture`.
#[test]
#[ignore]
fn prism_deviation_report() {
    let law = prism::prism_dispersion();
    let d0 = prism::prism_beam_direction(0.0);
    let az = prism::prism_incident_azimuth_deg().to_radians();
    let across = Vec3::new(az.sin(), 0.0, az.cos());
    let mut bins = vec![(0u32, 0.0f64, 0.0f64, 0.0f64); 16];
    for l in screen_landings(200_000) {
        let k = ((l.hero - 400.0) / 20.0).floor();
        if !(0.0..16.0).contains(&k) {
            continue;
        }
        let b = &mut bins[k as usize];
        b.0 += 1;
        b.1 += l.hero as f64;
        b.2 += l.arrival.dot(d0).clamp(-1.0, 1.0).acos().to_degrees() as f64;
        b.3 += l.p.dot(across) as f64;
    }
    let target = prism::prism_beam_target();
    println!(
        "| λ bin (nm) | paths | mean λ | deviation, rendered (°) | deviation, Snell (°) | difference (°) | position across the screen (mm) |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (k, b) in bins.iter().enumerate() {
        if b.0 == 0 {
            continue;
        }
        let n = b.0 as f64;
        let l = (b.1 / n) as f32;
        // Snell for the beam's axis at the mean wavelength (the deviation is the same for every
        // ray of the parallel beam).
        let (_, d2) = snell_path(target - d0, d0, law.ior(l), Vec3::ZERO, Vec3::X).unwrap();
        let snell = d2.dot(d0).clamp(-1.0, 1.0).acos().to_degrees() as f64;
        println!(
            "| {}–{} | {} | {:.1} | {:.4} | {:.4} | {:+.4} | {:.2} |",
            400 + 20 * k,
            420 + 20 * k,
            b.0,
            l,
            b.2 / n,
            snell,
            b.2 / n - snell,
            1e3 * b.3 / n
        );
    }
}
