//! Photon cones from light paths (seed 001 Alg. 1 lines 5–8): the shared light walker, and at
//! every surface vertex it reaches (delta ones included: "all surface types are valid") the
//! cones of [`ConeRule::cones_at`]. The path goes on by its own BSDF sample; the cone
//! directions are fresh samples (spec notes Q7). No cones on the emitter itself: the camera
//! path's emission term covers directly seen emitters (Q5).
//!
//! Cone values (spec notes sec. 2.2, Q15). A photon of flux β arriving from ω_i stands for
//! irradiance over the geometric area, so to estimate L_o(ω) = ∫ f(ω, ω_i) L_i |ω_i·n_s| dω_i
//! a cone carries β f(ω_o, ω_i) |ω_i·n_s| / (|ω_i·n_g| p(ω_o)) (the shading-normal factor is 1
//! on flat geometry), with f the radiance-mode BSDF (its η² included for rough refraction):
//! no cosine at the cone, which carries radiance. At a delta vertex the BSDF's sample in
//! importance mode has weight W = F/P (Fresnel over the lobe's probability, no η²), and the
//! cone carries β W |ω_i·n_s| / (|ω_i·n_g| |ω_o·n_s|): the delta written in the ω_o measure,
//! whose Jacobian through refraction, (η_i/η_o)² cos θ_i/cos θ_o, turns the kernel's angular
//! compression into the η² radiance gain (so no η² factor appears; test T-8b catches a wrong
//! one).

use super::cone::PhotonCone;
use super::importon::ImportonMap;
use super::techniques::{CameraLobe, ImportonMixture, power_weight};
use crate::options::{ConeTechniques, RenderOptions};
use crate::photon::plan::{PathStream, trace_path_range};
use crate::stats::RenderStats;
use crate::transport::light_walk::{LightEvent, LightVertex, walk_light_path};
use caustica_core::sampling::{Sampler, warp};
use caustica_core::{Spectrum, Vec3};
use caustica_density::Neighbor;
use caustica_scene::Scene;
use caustica_scene::bsdf::{BsdfFlags, TransportMode};
use std::ops::Range;

/// The random-number stream of the cone light paths.
pub const CONE_STREAM: u64 = 0xC0E5;

/// How cones are made at a light vertex.
pub struct ConeRule<'a> {
    pub techniques: ConeTechniques,
    /// Power-heuristic weights (off: every technique's cone at full weight).
    pub mis: bool,
    /// The camera position (m) and the camera-NEE exponent.
    pub camera: Vec3,
    pub camera_exponent: f32,
    /// Fold camera-NEE samples into the upper side of reflection-only BSDFs.
    pub camera_mirror: bool,
    /// The importon map (when the technique is on).
    pub importons: Option<&'a ImportonMap>,
}

/// Buffers reused from light vertex to light vertex (the importon query's neighbours and
/// mixture).
#[derive(Default)]
pub struct ConeScratch {
    neighbours: Vec<Neighbor>,
    mixture: ImportonMixture,
}

/// Index of each technique in the density arrays.
const BSDF: usize = 0;
const CAMERA: usize = 1;
const IMPORTON: usize = 2;
const UNIFORM: usize = 3;

impl ConeRule<'_> {
    /// Cones at light vertex `lv` (pushed to `out`). Sampler use: 3 numbers for the BSDF
    /// technique, 2 for camera NEE, 3 for importons, 2 for uniform, each when enabled (fixed
    /// per vertex).
    pub fn cones_at(
        &self,
        lv: &LightVertex,
        delta_light: bool,
        sampler: &mut Sampler,
        scratch: &mut ConeScratch,
        out: &mut Vec<PhotonCone>,
    ) {
        let v = lv.v;
        let wi = lv.wo; // toward the light
        let ns = v.si.ns;
        let ng = v.si.ng;
        let cos_ig = wi.dot(ng).abs();
        if cos_ig <= 0.0 || lv.beta.is_black() {
            return;
        }
        let shade_in = wi.dot(ns).abs() / cos_ig;
        let p = v.si.p;
        let site = Site {
            p,
            length: lv.depth.min(255) as u8,
            delta_light,
            shape: v.si.shape,
            ng,
        };
        let flags = v.bsdf.flags();
        let t = self.techniques;
        // Fixed draws per vertex.
        let u_bsdf = t.bsdf.then(|| (sampler.next_1d(), sampler.next_2d()));
        let u_cam = t.camera.then(|| sampler.next_2d());
        let u_imp = t.importons.then(|| (sampler.next_1d(), sampler.next_2d()));
        let u_uni = t.uniform.then(|| sampler.next_2d());

        if flags.is_delta() && !flags.is_smooth() {
            // Delta lobes only: the BSDF's sample is the one direction with f > 0.
            let (uc, u) = u_bsdf.unwrap_or_else(|| (sampler.next_1d(), sampler.next_2d()));
            let Some(bs) = v.bsdf.sample(v.wo, uc, u, TransportMode::Importance) else {
                return;
            };
            let wo = v.frame.to_world(bs.wi);
            if !v.same_side_consistent(wi, wo, bs.wi) {
                return;
            }
            let cos_os = wo.dot(ns).abs();
            if cos_os <= 0.0 {
                return;
            }
            let value = lv.v.channels.to_rgb(lv.beta * bs.weight) * (shade_in / cos_os);
            push(out, &site, wo, value);
            return;
        }

        let local_in = v.wo;
        // f(ω_o, ω_i) in radiance mode, 0 where the sides disagree.
        let f_at = |wo: Vec3| -> Spectrum {
            let l = v.frame.to_local(wo);
            if !v.same_side_consistent(wi, wo, l) {
                return Spectrum::ZERO;
            }
            v.bsdf.eval(l, local_in, TransportMode::Radiance)
        };
        let camera = if t.camera {
            let to = self.camera - p;
            let len = to.length();
            (len > 0.0).then(|| CameraLobe {
                axis: to / len,
                exponent: self.camera_exponent,
                fold: (self.camera_mirror && !flags.contains(BsdfFlags::TRANSMISSION))
                    .then(|| v.si.ng_toward(wi)),
            })
        } else {
            None
        };
        let mixture = &mut scratch.mixture;
        match (t.importons, self.importons) {
            (true, Some(map)) => map.mixture_at(p, &mut scratch.neighbours, mixture),
            _ => mixture.refill(std::iter::empty(), 1.0),
        }
        let mixture = &*mixture;
        let pdfs = |w: Vec3| -> [f32; 4] {
            [
                if t.bsdf {
                    v.bsdf
                        .pdf(local_in, v.frame.to_local(w), TransportMode::Importance)
                } else {
                    0.0
                },
                camera.as_ref().map_or(0.0, |c| c.pdf(w)),
                if t.importons { mixture.pdf(w) } else { 0.0 },
                if t.uniform {
                    warp::uniform_sphere_pdf()
                } else {
                    0.0
                },
            ]
        };
        let mut emit = |which: usize, w: Option<Vec3>| {
            let Some(w) = w else { return };
            let f = f_at(w);
            if f.is_black() {
                return;
            }
            let d = pdfs(w);
            let pt = d[which];
            if !(pt > 0.0 && pt.is_finite()) {
                return;
            }
            let weight = if self.mis {
                power_weight(&d, which)
            } else {
                1.0
            };
            let value = lv.v.channels.to_rgb(lv.beta * f) * (weight * shade_in / pt);
            push(out, &site, w, value);
        };
        if let Some((uc, u)) = u_bsdf {
            let w = v
                .bsdf
                .sample(local_in, uc, u, TransportMode::Importance)
                .filter(|bs| !bs.flags.is_delta())
                .map(|bs| v.frame.to_world(bs.wi).normalize());
            emit(BSDF, w);
        }
        if let (Some(u), Some(c)) = (u_cam, camera.as_ref()) {
            emit(CAMERA, Some(c.sample(u)));
        }
        if let Some((uc, u)) = u_imp {
            emit(IMPORTON, mixture.sample(uc, u));
        }
        if let Some(u) = u_uni {
            emit(UNIFORM, Some(warp::square_to_uniform_sphere(u)));
        }
    }
}

#[inline]
fn push(out: &mut Vec<PhotonCone>, at: &Site, dir: Vec3, value: Spectrum) {
    if value.is_black() || !value.c.iter().all(|c| c.is_finite()) {
        return;
    }
    out.push(PhotonCone {
        p: at.p,
        dir,
        value,
        length: at.length,
        delta_light: at.delta_light,
        shape: at.shape,
        ng: at.ng,
    });
}

/// Where the cones of a vertex are made.
struct Site {
    p: Vec3,
    length: u8,
    delta_light: bool,
    shape: u32,
    ng: Vec3,
}

/// Traces light paths `paths` of the cone stream and returns their cones in path order, the
/// number of paths traced (all unless `on_wave` stopped) and the statistics.
pub fn trace_cones(
    scene: &Scene,
    opts: &RenderOptions,
    rule: &ConeRule,
    paths: Range<u64>,
    on_wave: &mut dyn FnMut(u64) -> bool,
) -> (Vec<PhotonCone>, u64, RenderStats) {
    let stream = PathStream::new(opts, CONE_STREAM);
    trace_path_range(paths, &stream, on_wave, |_, sampler, out, st| {
        let mut scratch = ConeScratch::default();
        let mut delta_light = false;
        walk_light_path(scene, sampler, &opts.limits, st, |ev, s, _| match ev {
            LightEvent::Start(start) => delta_light = scene.lights[start.light].is_delta(),
            LightEvent::Vertex(lv) => rule.cones_at(lv, delta_light, s, &mut scratch, out),
            LightEvent::Medium(_) => {}
        });
    })
}
