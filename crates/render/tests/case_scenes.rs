//! The case-study scenes of `docs/scenes.md` rendered small: the light tracer's image of
//! `water-wave` shows the two caustic bands where geometric optics puts them.

use caustica_core::{Vec2, Vec3};
use caustica_loader::builtin::{WATER_IOR, WATER_WAVE};
use caustica_loader::builtin_scene;
use caustica_render::{IntegratorKind, RenderControl, RenderOptions, render};

/// Where a vertical ray refracted by the analytic surface at `x` meets the floor y = 0.
fn landing(x: f64) -> f64 {
    let [nx, ny, _] = WATER_WAVE.normal(x);
    let eta = 1.0 / WATER_IOR as f64;
    let k = (1.0 - eta * eta * (1.0 - ny * ny)).sqrt();
    let (tx, ty) = (nx * (eta * ny - k), -eta + ny * (eta * ny - k));
    x + WATER_WAVE.height(x) * tx / -ty
}

/// x of the fold caustic on the floor's +x side: the largest local extremum of `landing`.
fn fold() -> f64 {
    let n = 100_000;
    let l: Vec<f64> = (0..=n)
        .map(|i| landing(-1.0 + 2.0 * i as f64 / n as f64))
        .collect();
    (1..n)
        .filter(|&i| (l[i] - l[i - 1]) * (l[i + 1] - l[i]) <= 0.0)
        .map(|i| l[i])
        .fold(f64::NEG_INFINITY, f64::max)
}

#[test]
fn water_wave_light_tracer_shows_two_bands_at_the_geometric_folds() {
    let mut b = builtin_scene("water-wave").unwrap();
    let mut camera = b.camera().unwrap().clone();
    (camera.width, camera.height) = (64, 64);
    b.set_camera(camera);
    let scene = b.build().unwrap();
    let opts = RenderOptions {
        spp: 256,
        seed: 5,
        ..Default::default()
    };
    let img = render(
        &scene,
        IntegratorKind::LightTrace,
        &opts,
        &RenderControl::silent(),
    )
    .expect("valid options")
    .film
    .to_image();
    // The wave is constant along z and the camera looks straight down with x to the right, so
    // every row sees the same profile: average the rows.
    let columns: Vec<f64> = (0..img.width)
        .map(|x| {
            (0..img.height)
                .map(|y| img.get(x, y).iter().map(|&c| c as f64).sum::<f64>() / 3.0)
                .sum::<f64>()
                / img.height as f64
        })
        .collect();
    let f = fold() as f32;
    assert!((0.15..0.22).contains(&f), "fold at {f}");
    let column_of = |x: f32| {
        let cs = scene
            .camera
            .sample_wi(Vec3::new(x, 0.0, 0.0), Vec2::splat(0.5))
            .expect("the floor point projects into the image");
        cs.raster.x
    };
    let (left, right) = (column_of(-f), column_of(f));
    assert!(left < right, "x must grow to the image's right");
    let brightest = |r: std::ops::Range<usize>| {
        r.max_by(|&a, &b| columns[a].total_cmp(&columns[b]))
            .unwrap()
    };
    let half = img.width / 2;
    let (bl, br) = (brightest(0..half), brightest(half..img.width));
    // The band is a fold caustic: the pixel column containing it, or its neighbour on the lit
    // side of the fold, is the brightest.
    for (found, predicted) in [(bl, left), (br, right)] {
        assert!(
            (found as f32 + 0.5 - predicted).abs() <= 1.0,
            "brightest column {found}, fold at column {predicted:.2}; columns {columns:.3?}"
        );
    }
    // Between the bands brighter than outside them, and dimmer than the bands.
    let mean =
        |r: std::ops::Range<usize>| r.clone().map(|i| columns[i]).sum::<f64>() / r.len() as f64;
    let inside = mean(half - 4..half + 4);
    let outside = 0.5 * (mean(2..bl - 4) + mean(br + 5..img.width - 2));
    assert!(
        inside > 2.0 * outside,
        "between the bands {inside:.3}, outside {outside:.3}"
    );
    assert!(
        columns[bl].min(columns[br]) > 1.5 * inside,
        "bands {:.3} and {:.3}, between {inside:.3}",
        columns[bl],
        columns[br]
    );
}
