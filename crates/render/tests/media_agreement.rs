//! The volumetric path tracer and the light tracer, two independent estimators of the same
//! radiative transfer, agree on the built-in fog box (homogeneous chromatic fog, isotropic and
//! Henyey–Greenstein) and the smoke plume (a voxel grid): the whole image within 2 % and every
//! 8×8 block within 4σ, the noise measured from two renders per side.

mod common;

use caustica_core::image_io::Image;
use caustica_loader::builtin_scene;
use caustica_render::IntegratorKind;
use caustica_scene::Scene;
use caustica_scene::scene::FilterKind;

const SIZE: u32 = 32;

fn scene(name: &str) -> Scene {
    let mut b = builtin_scene(name).unwrap();
    let mut camera = b.camera().unwrap().clone();
    (camera.width, camera.height) = (SIZE, SIZE);
    b.set_camera(camera);
    let mut scene = b.build().unwrap();
    // One-pixel box: pixel noise is independent, so a block's variance is its pixels'.
    scene.settings.filter = FilterKind::Box;
    scene
}

/// Block means of the average of two renders and the variance of those means, from the pixels'
/// differences (per channel).
fn blocks(a: &Image, b: &Image, block: u32) -> Vec<([f64; 3], [f64; 3])> {
    let n = SIZE / block;
    let mut out = Vec::new();
    for by in 0..n {
        for bx in 0..n {
            let mut m = [0.0; 3];
            let mut v = [0.0; 3];
            for y in by * block..(by + 1) * block {
                for x in bx * block..(bx + 1) * block {
                    let i = (y * SIZE + x) as usize;
                    for c in 0..3 {
                        let (p, q) = (a.data[i][c] as f64, b.data[i][c] as f64);
                        m[c] += 0.5 * (p + q);
                        v[c] += (p - q).powi(2) / 2.0; // per-pixel variance estimate
                    }
                }
            }
            let k = (block * block) as f64;
            out.push((m.map(|x| x / k), v.map(|x| x / k / (2.0 * k))));
        }
    }
    out
}

fn agree(name: &str, pt_spp: u32, lt_spp: u32) {
    let scene = scene(name);
    let pt =
        [1, 2].map(|s| common::render_image_depth(&scene, IntegratorKind::Path, pt_spp, s, 64));
    let lt = [3, 4]
        .map(|s| common::render_image_depth(&scene, IntegratorKind::LightTrace, lt_spp, s, 64));
    let bp = blocks(&pt[0], &pt[1], 8);
    let bl = blocks(&lt[0], &lt[1], 8);
    let (mut sp, mut sl) = ([0.0; 3], [0.0; 3]);
    for ((mp, vp), (ml, vl)) in bp.iter().zip(&bl) {
        for c in 0..3 {
            let z = (mp[c] - ml[c]) / (vp[c] + vl[c]).sqrt().max(1e-12);
            assert!(
                z.abs() < 4.0,
                "{name} channel {c}: block path {} vs light {} (z = {z:.2})",
                mp[c],
                ml[c]
            );
            sp[c] += mp[c];
            sl[c] += ml[c];
        }
    }
    for c in 0..3 {
        assert!(
            (sp[c] / sl[c] - 1.0).abs() < 0.02,
            "{name} channel {c}: image mean path {} vs light {}",
            sp[c],
            sl[c]
        );
    }
}

#[test]
fn path_and_light_tracers_agree_in_the_fog_box() {
    agree("fog-box", 64, 64);
}

#[test]
fn path_and_light_tracers_agree_in_the_fog_box_with_forward_scattering() {
    agree("fog-box-hg", 64, 64);
}

#[test]
fn path_and_light_tracers_agree_in_the_smoke_plume() {
    // The light is outside the smoke's box: connections cross its null boundary.
    agree("smoke-plume", 64, 64);
}
