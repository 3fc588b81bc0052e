//! A crop window (`RenderOptions::crop`, `caustica render --crop`) renders a sub-image whose
//! pixels are, bit for bit, those of the uncropped render with the same seed: for the pixel
//! driver (path, pm, dpm, pdm), for the light tracer (the same light paths, splats outside the
//! window dropped, with a filter wider than a pixel so splats straddle the window's edges) and
//! for pds (the same photons splatted onto the window's eye vertices). The memory estimate
//! counts the window's pixels only.

use caustica_core::image_io::Image;
use caustica_loader::builtin_scene;
use caustica_render::{
    CropWindow, IntegratorKind, OptionError, PhotonOptions, RenderControl, RenderError,
    RenderOptions, memory, render,
};
use caustica_scene::Scene;
use caustica_scene::scene::FilterKind;

/// The built-in glass sphere (caustics under the sphere, diffuse walls) at 40 × 30 pixels with
/// a Gaussian filter of radius 1.5 pixels.
fn scene() -> Scene {
    let mut b = builtin_scene("glass-sphere").unwrap();
    let mut camera = b.camera().unwrap().clone();
    (camera.width, camera.height) = (40, 30);
    b.set_camera(camera);
    let mut scene = b.build().unwrap();
    scene.settings.filter = FilterKind::Gaussian {
        stddev: 0.5,
        radius: 1.5,
    };
    scene
}

fn opts(crop: Option<CropWindow>) -> RenderOptions {
    RenderOptions {
        spp: 2,
        seed: 5,
        photons: PhotonOptions {
            caustic_photons: 4000,
            global_photons: 2000,
            final_gather: 2,
            ..PhotonOptions::default()
        },
        crop,
        ..RenderOptions::default()
    }
}

fn run(scene: &Scene, kind: IntegratorKind, opts: &RenderOptions) -> Image {
    render(scene, kind, opts, &RenderControl::silent())
        .expect("valid options")
        .film
        .to_image()
}

fn window(x: u32, y: u32, width: u32, height: u32) -> CropWindow {
    CropWindow {
        x,
        y,
        width,
        height,
    }
}

/// Inside, at the bottom-right corner, one full row, one pixel at the top-left corner.
const WINDOWS: [(u32, u32, u32, u32); 4] = [
    (7, 9, 19, 13),
    (25, 18, 15, 12),
    (0, 21, 40, 1),
    (0, 0, 1, 1),
];

/// The pixels of `full` in `w`, as bits.
fn sub_image(full: &Image, w: CropWindow) -> Vec<[u32; 3]> {
    let mut out = Vec::new();
    for y in w.y..w.y + w.height {
        for x in w.x..w.x + w.width {
            out.push(full.data[y as usize * full.width + x as usize].map(f32::to_bits));
        }
    }
    out
}

fn bits(img: &Image) -> Vec<[u32; 3]> {
    img.data.iter().map(|p| p.map(f32::to_bits)).collect()
}

/// Every crop of [`WINDOWS`] of `kind`'s render is the sub-image of the full render, and the
/// crops are not black (`caustics_only` for the methods whose caustic is the point).
fn crops_are_sub_images(kind: IntegratorKind, caustics_only: bool) {
    let scene = scene();
    let full_opts = RenderOptions {
        caustics_only,
        ..opts(None)
    };
    let full = run(&scene, kind, &full_opts);
    let mut lit = 0.0f32;
    for (x, y, w, h) in WINDOWS {
        let win = window(x, y, w, h);
        let crop = run(
            &scene,
            kind,
            &RenderOptions {
                crop: Some(win),
                ..full_opts.clone()
            },
        );
        assert_eq!((crop.width, crop.height), (w as usize, h as usize));
        assert!(
            bits(&crop) == sub_image(&full, win),
            "{kind:?}: the crop {win} differs from the full render's pixels"
        );
        lit += crop.data.iter().flatten().sum::<f32>();
    }
    assert!(lit > 0.0, "{kind:?}: every crop is black");
}

#[test]
fn path_tracer_crops_are_sub_images() {
    crops_are_sub_images(IntegratorKind::Path, false);
}

#[test]
fn light_tracer_crops_are_sub_images() {
    crops_are_sub_images(IntegratorKind::LightTrace, false);
}

#[test]
fn photon_mapping_crops_are_sub_images() {
    crops_are_sub_images(IntegratorKind::PhotonMapping, false);
    crops_are_sub_images(IntegratorKind::DiffusionPhotonMapping, true);
    crops_are_sub_images(IntegratorKind::PhotonDifferentialMapping, true);
}

#[test]
fn pds_crops_are_sub_images() {
    crops_are_sub_images(IntegratorKind::PhotonDifferentialSplatting, true);
    crops_are_sub_images(IntegratorKind::PhotonDifferentialSplatting, false);
}

#[test]
fn a_window_outside_the_film_is_refused() {
    let scene = scene();
    for (x, y, w, h) in [(30, 0, 11, 1), (0, 29, 1, 2), (0, 0, 0, 1), (40, 0, 1, 1)] {
        let o = opts(Some(window(x, y, w, h)));
        match render(&scene, IntegratorKind::Path, &o, &RenderControl::silent()) {
            Err(RenderError::Option(e @ OptionError::Crop { .. })) => {
                assert!(e.to_string().contains("40x30"), "{e}")
            }
            Err(e) => panic!("{x},{y},{w},{h}: {e}"),
            Ok(_) => panic!("{x},{y},{w},{h} was rendered"),
        }
    }
}

#[test]
fn memory_counts_the_window_pixels() {
    let scene = scene();
    let kind = IntegratorKind::PhotonDifferentialSplatting;
    let part = |o: &RenderOptions, what: &str| {
        memory::estimate(kind, &scene, o)
            .parts
            .iter()
            .find(|p| p.what == what)
            .map(|p| p.count)
    };
    let crop = opts(Some(window(3, 4, 10, 5)));
    assert_eq!(part(&opts(None), "film"), Some(40 * 30));
    assert_eq!(part(&crop, "film"), Some(50));
    assert_eq!(part(&opts(None), "eye map"), Some(40 * 30 * 2));
    assert_eq!(part(&crop, "eye map"), Some(50 * 2));
}
