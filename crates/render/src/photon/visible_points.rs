//! Visible points: where the camera sees a non-delta surface, with a radius of influence — the
//! target of visibility-driven adaptive photon tracing ([`super::adaptive`]): a photon path
//! "contributes" when one of its stored photons lies within that radius of a visible point.
//!
//! The points come from the camera: the pds eye map, or a camera pre-pass for the photon-map
//! methods ([`VisiblePoints::from_camera`]: one ray per pixel through mirrors and glass to its
//! first non-delta vertex, as the camera pass will walk it). The radius is a multiple of the
//! pixel footprint at the median distance, so neighbouring points' discs overlap and the union
//! covers what the image sees.

use crate::crop::CropWindow;
use crate::options::RenderOptions;
use crate::stats::RenderStats;
use crate::transport::eye_walk::{EyeEvent, Flow, walk_eye};
use caustica_core::Vec3;
use caustica_core::sampling::Sampler;
use caustica_scene::Scene;
use rayon::prelude::*;
use std::collections::HashMap;

/// Pixel footprints in the radius of influence: wide enough that the discs of neighbouring
/// pixels' points overlap (and a photon map's gather radius of a few pixels mostly lies inside
/// the union, see docs/emission.md).
pub const RADIUS_IN_PIXELS: f32 = 4.0;

/// Visible points in a uniform hash grid of cell side `radius`.
pub struct VisiblePoints {
    radius: f32,
    cells: HashMap<(i32, i32, i32), Vec<Vec3>>,
    count: usize,
}

impl VisiblePoints {
    /// The points `points` with radius of influence `radius` (m, > 0).
    pub fn new(points: &[Vec3], radius: f32) -> Self {
        let radius = radius.max(1e-6);
        let mut cells: HashMap<(i32, i32, i32), Vec<Vec3>> = HashMap::new();
        let mut count = 0;
        for &p in points.iter().filter(|p| p.is_finite()) {
            cells.entry(cell(p, radius)).or_default().push(p);
            count += 1;
        }
        Self {
            radius,
            cells,
            count,
        }
    }

    /// One camera ray per pixel of the render's window through the pixel centre, followed
    /// through delta vertices to its first non-delta vertex; the radius is
    /// [`RADIUS_IN_PIXELS`] pixel footprints at the median camera distance of the points.
    pub fn from_camera(scene: &Scene, opts: &RenderOptions) -> Self {
        let cam = &scene.camera;
        let window = opts
            .crop
            .unwrap_or_else(|| CropWindow::full(cam.width, cam.height));
        let rows: Vec<Vec<Vec3>> = (window.y..window.y + window.height)
            .into_par_iter()
            .map(|y| {
                let mut sampler = Sampler::new(opts.sampler, opts.seed);
                let mut stats = RenderStats::default();
                let mut out = Vec::new();
                for x in window.x..window.x + window.width {
                    sampler.start_pixel_sample(x, y, 0);
                    let raster = caustica_core::Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                    let ray = cam
                        .generate_ray(raster, caustica_core::Vec2::splat(0.5))
                        .ray;
                    walk_eye(
                        scene,
                        ray,
                        scene.camera_medium,
                        &mut sampler,
                        opts.limits.max_depth,
                        &mut stats,
                        |ev, _, _| {
                            if let EyeEvent::Vertex { v, .. } = ev
                                && v.bsdf.flags().is_smooth()
                            {
                                out.push(v.si.p);
                            }
                            Flow::Continue
                        },
                    );
                }
                out
            })
            .collect();
        let points: Vec<Vec3> = rows.into_iter().flatten().collect();
        let mut dist: Vec<f32> = points
            .iter()
            .map(|p| (*p - cam.position()).length())
            .collect();
        let median = if dist.is_empty() {
            1.0
        } else {
            let k = dist.len() / 2;
            *dist.select_nth_unstable_by(k, f32::total_cmp).1
        };
        // A pixel's width at distance `median`: the image plane at unit distance is
        // 2 × half-extent wide.
        let pixel = 2.0 * cam.screen_half_extent().x / cam.width.max(1) as f32 * median;
        Self::new(&points, RADIUS_IN_PIXELS * pixel)
    }

    /// Radius of influence (m).
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.count
    }

    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// True if some point lies within the radius of `p`.
    pub fn near(&self, p: Vec3) -> bool {
        let (cx, cy, cz) = cell(p, self.radius);
        let r2 = self.radius * self.radius;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(v) = self.cells.get(&(cx + dx, cy + dy, cz + dz))
                        && v.iter().any(|q| (*q - p).length_squared() <= r2)
                    {
                        return true;
                    }
                }
            }
        }
        false
    }
}

fn cell(p: Vec3, side: f32) -> (i32, i32, i32) {
    let c = (p / side).floor();
    (c.x as i32, c.y as i32, c.z as i32)
}
