//! Two independent estimators of the same image must agree: the path tracer (camera paths with
//! NEE + MIS) and the light tracer (light paths connected to the camera).

mod common;

use caustica_render::IntegratorKind;

/// On a diffuse-only scene with an area light, the path tracer and the light tracer agree in
/// mean (relative difference < 2 %) and per 4×4 block within their noise: the squared z-scores
/// of block differences, with each estimator's variance measured from two independent seeds,
/// average below 2 (≈1 expected when only noise separates them).
#[test]
fn path_tracer_and_light_tracer_agree_on_diffuse_scene() {
    let scene = common::diffuse_box(32, 32);
    let pt = [
        common::render_image(&scene, IntegratorKind::Path, 256, 1),
        common::render_image(&scene, IntegratorKind::Path, 256, 2),
    ];
    let lt = [
        common::render_image(&scene, IntegratorKind::LightTrace, 256, 1),
        common::render_image(&scene, IntegratorKind::LightTrace, 256, 2),
    ];
    let mean = |img: &caustica_core::image_io::Image| {
        img.data.iter().map(|p| common::lum(*p)).sum::<f64>() / img.data.len() as f64
    };
    let (mp, ml) = (
        (mean(&pt[0]) + mean(&pt[1])) / 2.0,
        (mean(&lt[0]) + mean(&lt[1])) / 2.0,
    );
    let rel = (mp - ml).abs() / mp;
    assert!(mp > 0.01, "image is black: mean {mp}");
    assert!(
        rel < 0.02,
        "mean radiance: path {mp:.5}, light tracer {ml:.5}, relative difference {rel:.4}"
    );

    let b = 4;
    let (p1, p2) = (common::blocks(&pt[0], b), common::blocks(&pt[1], b));
    let (l1, l2) = (common::blocks(&lt[0], b), common::blocks(&lt[1], b));
    // Variance of the two-seed average: var(a) ≈ (a1 − a2)²/2 for one seed, /2 again for the mean.
    // Single-pair variance estimates are noisy, so pool them over all blocks relative to the mean.
    let mut z2 = 0.0;
    let (mut vp, mut vl) = (0.0, 0.0);
    for i in 0..p1.len() {
        vp += (p1[i] - p2[i]).powi(2) / 4.0;
        vl += (l1[i] - l2[i]).powi(2) / 4.0;
    }
    let n = p1.len() as f64;
    let (vp, vl) = (vp / n, vl / n);
    for i in 0..p1.len() {
        let d = (p1[i] + p2[i]) / 2.0 - (l1[i] + l2[i]) / 2.0;
        z2 += d * d / (vp + vl);
    }
    let mean_z2 = z2 / n;
    assert!(
        mean_z2 < 2.0,
        "block differences exceed the noise: mean z² = {mean_z2:.2} (pooled variances {vp:.2e}, {vl:.2e})"
    );
}
