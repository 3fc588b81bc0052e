//! Conical importons (seed 001 sec. 4.2.3): camera importance traced once before the loop
//! (Alg. 1 line 3) into a map that guides cone directions toward where the camera looks,
//! including through shiny surfaces (its Fig. 4.6: cones on the ground should point toward the
//! reflection of the view in a metal sphere).
//!
//! The seed leaves the details open; ours follow the spec notes (Q9): camera paths with the
//! camera pass's depth and roulette; at each non-delta camera vertex j ≥ 2 (j ≥ 1 when camera
//! NEE is off, which already aims at the camera from first hits) an importon of position, unit
//! direction back toward the previous camera vertex (where radiance must leave to be seen) and
//! one float of importance, the luminance of the camera-path throughput. A light vertex draws
//! from its k nearest importons within a fixed radius, in proportion to importance, a direction
//! uniform in a fixed cap around the importon's (the seed does not adapt the cap: "we do not
//! reproject (splat) the samples").

use super::techniques::ImportonMixture;
use crate::integrator::path::{CameraRule, Direct, radiance_with};
use crate::options::RenderOptions;
use crate::photon::plan::{PathStream, trace_path_range};
use crate::stats::RenderStats;
use crate::transport::vertex::Vertex;
use caustica_core::{Channels, Spectrum, Vec2, Vec3};
use caustica_density::{KdTree, Neighbor};
use caustica_scene::Scene;
use std::cell::RefCell;

/// The random-number stream of the importon paths.
pub const IMPORTON_STREAM: u64 = 0x1A90;

/// A conical importon.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConicalImporton {
    /// Position (m).
    pub p: Vec3,
    /// Unit direction toward the previous camera vertex (world space).
    pub dir: Vec3,
    /// Importance (dimensionless luminance of the camera-path throughput).
    pub importance: f32,
}

/// Where importons are stored.
#[derive(Clone, Copy, Debug)]
pub struct ImportonRule {
    /// The first camera vertex that stores one (1 or 2).
    pub first_vertex: u32,
}

/// The camera-path rule that records importons: at each non-delta vertex from `first_vertex`
/// on, the vertex, the direction back along the path and the luminance of the throughput; no
/// direct light is computed (its sampler draws are kept, so the path is the camera pass's).
struct Recorder {
    first_vertex: u32,
    out: RefCell<Vec<ConicalImporton>>,
}

impl CameraRule for Recorder {
    fn visit(&self, v: &Vertex, depth: u32, beta: Spectrum) {
        if depth < self.first_vertex || !v.bsdf.flags().is_smooth() {
            return;
        }
        let importance = beta.luminance();
        if importance > 0.0 && importance.is_finite() {
            self.out.borrow_mut().push(ConicalImporton {
                p: v.si.p,
                dir: v.frame.to_world(v.wo),
                importance,
            });
        }
    }
    fn direct(&self, _: &Vertex, _: u32, _: &mut RenderStats) -> Direct {
        Direct::Replace(Spectrum::ZERO)
    }
}

/// The importons of a scene and how a light vertex queries them.
pub struct ImportonMap {
    tree: KdTree,
    importons: Vec<ConicalImporton>,
    /// Paths traced.
    pub paths: u64,
    radius2: f32,
    k: usize,
    cos_cap: f32,
}

impl ImportonMap {
    /// Traces `paths` camera paths of `opts`' seed (uniform over the film) and keeps their
    /// importons; queries take the `k` nearest within `radius` (m) and caps of half-angle
    /// `angle` (rad).
    #[allow(clippy::too_many_arguments)]
    pub fn trace(
        scene: &Scene,
        opts: &RenderOptions,
        paths: u64,
        rule: ImportonRule,
        k: usize,
        radius: f32,
        angle: f32,
        on_wave: &mut dyn FnMut(u64) -> bool,
    ) -> (Self, RenderStats) {
        let stream = PathStream::new(opts, IMPORTON_STREAM);
        let cam = &scene.camera;
        let (w, h) = (cam.width as f32, cam.height as f32);
        let (importons, done, stats) =
            trace_path_range(0..paths, &stream, on_wave, |_, sampler, out, st| {
                // The camera pass's own path (depth, roulette), recording instead of shading.
                let u = sampler.next_2d();
                let u_lens = sampler.next_2d();
                let time = scene.sample_time(|| sampler.next_1d());
                let ray = cam
                    .generate_ray(Vec2::new(u.x * w, u.y * h), u_lens)
                    .ray
                    .at_time(time);
                let recorder = Recorder {
                    first_vertex: rule.first_vertex,
                    out: RefCell::new(std::mem::take(out)),
                };
                radiance_with(scene, ray, sampler, opts, st, &recorder, Channels::Rgb);
                *out = recorder.out.into_inner();
            });
        let points: Vec<Vec3> = importons.iter().map(|i| i.p).collect();
        (
            Self {
                tree: KdTree::build(&points),
                importons,
                paths: done,
                radius2: radius * radius,
                k,
                cos_cap: angle.cos(),
            },
            stats,
        )
    }

    /// Number of importons.
    pub fn len(&self) -> usize {
        self.importons.len()
    }

    pub fn is_empty(&self) -> bool {
        self.importons.is_empty()
    }

    /// Bytes held.
    pub fn memory_bytes(&self) -> usize {
        self.tree.memory_bytes() + self.importons.len() * std::mem::size_of::<ConicalImporton>()
    }

    /// Fills `mixture` with the one a light vertex at `x` draws from (empty when no importon
    /// is near): the `k` nearest importons within the radius, in a fixed order, so its density
    /// can be evaluated again for MIS. `neighbours` is scratch space.
    pub fn mixture_at(
        &self,
        x: Vec3,
        neighbours: &mut Vec<Neighbor>,
        mixture: &mut ImportonMixture,
    ) {
        self.tree.knn(x, self.k, self.radius2, neighbours);
        let lobes = neighbours.iter().map(|n| {
            let i = &self.importons[n.index as usize];
            (i.dir, i.importance)
        });
        mixture.refill(lobes, self.cos_cap);
    }
}
