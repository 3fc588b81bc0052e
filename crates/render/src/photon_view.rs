//! Photons drawn as points over an image of the scene, for debugging (seed 000 fig. 6.4b).

use crate::photon::tracer::Photon;
use caustica_core::image_io::Image;
use caustica_core::{Ray, Spectrum, Vec2};
use caustica_scene::Scene;

/// Marks every photon of `photons` that the camera sees (pinhole through the lens centre, not
/// occluded) by setting its pixel of `img` to `color`. Returns how many were drawn.
pub fn draw_photons(scene: &Scene, photons: &[Photon], color: Spectrum, img: &mut Image) -> usize {
    let cam = &scene.camera;
    let mut drawn = 0;
    for ph in photons {
        let Some(cs) = cam.sample_wi(ph.p, Vec2::splat(0.5)) else {
            continue;
        };
        // Only photons on the side of their surface that faces the camera.
        if cs.wi.dot(ph.n) <= 0.0 {
            continue;
        }
        let o = ph.p + ph.n * (1e-4 * (1.0 + ph.p.abs().max_element()));
        let shadow = Ray::with_t_max(o, cs.wi, (cs.lens_p - o).length() * (1.0 - 1e-4));
        if scene.occluded(&shadow) {
            continue;
        }
        let (x, y) = (cs.raster.x.floor(), cs.raster.y.floor());
        if x >= 0.0 && y >= 0.0 && (x as usize) < img.width && (y as usize) < img.height {
            img.set(x as usize, y as usize, color.to_rgb());
            drawn += 1;
        }
    }
    drawn
}
