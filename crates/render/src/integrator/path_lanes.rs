//! The path tracer with eight camera paths side by side in SIMD lanes (issue 26, deliverable
//! 3): a wavefront over a row's samples, as Mitsuba 3's vectorised variants run their paths.
//! Each lane holds one path from its camera ray to its end and then takes the row's next
//! sample. Per vertex, the closest hits, the material's albedo, the light's triangle and the
//! shadow rays are found lane by lane through the scene's scalar queries (a vertex's seven
//! random numbers drawn at once per lane, [`Sampler::next_1d_array`]); the shading frame,
//! the direction back, next-event estimation ([`direct_lanes::estimate`], four lanes at a
//! time), cosine sampling (glibc's sine and cosine still lane by lane), the same-side test,
//! roulette and the spawned rays are computed in the lanes (arrays of eight floats that the
//! compiler vectorises). Measured in docs/performance.md (issue 26, tenth session): the
//! Cornell box in 0.79× the scalar loop's time.
//!
//! It is the estimator of [`super::path::radiance_deferred`] with [`super::path::PathOnly`],
//! the same bits: each lane repeats the scalar loop's operations in its order and draws its
//! numbers from its own sampler in the scalar loop's order, and a path's terms are added in the
//! order the path finds them. The film's exact sums do not depend on the order in which samples
//! end, so the image is the scalar loop's bit for bit (tested). The `path` integrator uses the
//! lanes for scenes rendered in RGB without participating media whose lights are all area
//! lights made of triangles, point lights or directional lights ([`covers`]), and the scalar
//! loop for the others. A path stays in the lanes while it meets diffuse surfaces; at its first
//! other surface (glass, metal, …), or when it leaves a scene with an environment light, the
//! scalar loop finishes it from where it is ([`continue_path`] with its state and the sum of its
//! terms). Next-event estimates the four-lane kernel does not cover (a spot light, a light that
//! is not a triangle list, an environment, no light) are computed per lane by [`direct_with`].

// Loops over the lane number read as the SIMD code they become (one operation, eight lanes).
#![allow(clippy::needless_range_loop)]

use super::path::{PathOnly, PathState, continue_path, emission_mis};
use crate::driver::pixels::{PixelStream, RowSamples, WAITING_SAMPLES};
use crate::filter::Filter;
use crate::options::RenderOptions;
use crate::stats::RenderStats;
use crate::transport::direct::direct_with;
use crate::transport::direct_lanes::{self, DirectBatch, LANES, Lanes};
use crate::transport::medium::{Segment, interior_transmittance};
use crate::transport::vertex::{Scatterer, Vertex};
use caustica_core::sampling::Sampler;
use caustica_core::{Channels, Frame, INV_PI, PI, Ray, Spectrum, Vec2, Vec3};
use caustica_scene::Scene;
use caustica_scene::intersection::{NONE, SurfaceInteraction};
use caustica_scene::light::Light;
use caustica_scene::material::Material;
use glam::Vec4;

/// Paths side by side.
const W: usize = 8;
/// Every lane's bit.
const ALL: u32 = (1 << W) - 1;
/// One float per lane.
type F = [f32; W];

/// `f(k)` for every lane `k`.
#[inline(always)]
fn lanes(f: impl FnMut(usize) -> f32) -> F {
    std::array::from_fn(f)
}

/// The lanes whose bits are set in a mask, lowest first. A loop over them branches on its end
/// alone, where testing each of the eight bits is a coin flip the branch predictor often
/// loses (callgrind's branch simulation, docs/performance.md, sixteenth session).
#[derive(Clone, Copy)]
struct Bits(u32);

impl Iterator for Bits {
    type Item = usize;
    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.0 == 0 {
            return None;
        }
        let k = self.0.trailing_zeros() as usize % W;
        self.0 &= self.0 - 1;
        Some(k)
    }
}

/// The mask of the lanes `k` where `f(k)`.
#[inline(always)]
fn mask(f: impl Fn(usize) -> bool) -> u32 {
    (0..W).fold(0, |m, k| m | (f(k) as u32) << k)
}

/// Three coordinates in the lanes.
#[derive(Clone, Copy, Default)]
struct V {
    x: F,
    y: F,
    z: F,
}

impl V {
    #[inline(always)]
    fn get(&self, k: usize) -> Vec3 {
        Vec3::new(self.x[k], self.y[k], self.z[k])
    }
    #[inline(always)]
    fn set(&mut self, k: usize, v: Vec3) {
        (self.x[k], self.y[k], self.z[k]) = (v.x, v.y, v.z);
    }
    /// glam's `Vec3::dot`: `(x x' + y y') + z z'`.
    #[inline(always)]
    fn dot(&self, o: &V) -> F {
        lanes(|k| self.x[k] * o.x[k] + self.y[k] * o.y[k] + self.z[k] * o.z[k])
    }
    /// Lanes `4h .. 4h + 4` for the four-lane kernel.
    #[inline(always)]
    fn half(&self, h: usize) -> direct_lanes::V3 {
        direct_lanes::V3 {
            x: half(&self.x, h),
            y: half(&self.y, h),
            z: half(&self.z, h),
        }
    }
}

/// `if c[k] != 0 { a[k] } else { b[k] }` in every lane `k`, by four-lane blends. Written lane
/// by lane, the compiler may make each choice a branch around its operands' work (a division,
/// say), which the branch predictor loses half the time.
#[inline(always)]
fn blend(c: &F, a: &F, b: &F) -> F {
    let mut out = [0.0; W];
    for h in 0..W / LANES {
        let m = half(c, h).cmpne(Vec4::ZERO);
        Vec4::select(m, half(a, h), half(b, h)).write_to_slice(&mut out[LANES * h..]);
    }
    out
}

/// Lanes `4h .. 4h + 4` of `a`.
#[inline(always)]
fn half(a: &F, h: usize) -> Vec4 {
    Vec4::from_slice(&a[LANES * h..LANES * (h + 1)])
}

/// True if the `path` integrator renders `scene` in the lanes: RGB without participating media
/// (what [`render_row`] needs to give the scalar loop's image), and every light one whose
/// next-event estimates the four-lane kernel computes (an area light made of triangles, a point
/// light, a directional light: [`direct_lanes::kernel_covers`]). With other lights each
/// estimate falls back to the scalar code one lane at a time and the lanes cost more than they
/// save (the metal ring under its directional light, before the kernel covered it: 1.06× the
/// scalar loop's time, docs/performance.md).
pub fn covers(scene: &Scene) -> bool {
    renders(scene)
        && !scene.lights.is_empty()
        && scene.lights.iter().all(direct_lanes::kernel_covers)
}

/// True if a path that leaves `scene` finds no light: its infinite lights, if any, are
/// directional (delta) lights. The scalar loop adds each infinite light's `le` times an MIS
/// weight at an escape, a directional light's `le` is zero and the weight finite (0 or the
/// power heuristic against its pdf of zero), so it adds +0 to sums of non-negative terms and
/// changes no bit: such a path can end in the lanes.
fn escapes_find_no_light(scene: &Scene) -> bool {
    scene
        .infinite_lights
        .iter()
        .all(|&li| matches!(scene.lights.get(li as usize), Some(Light::Directional(_))))
}

/// True if [`render_row`] renders `scene` bit for bit as the scalar loop: RGB, no media.
fn renders(scene: &Scene) -> bool {
    !scene.has_media && !scene.spectral
}

/// The paths in the lanes.
struct Paths<'s> {
    samplers: [Sampler; W],
    /// The next-event estimates of the paths the scalar loop finishes wait here, four at a
    /// time across paths, as in the per-sample driver; `waiting` holds the film column of
    /// each path whose radiance waits.
    batch: DirectBatch<'s>,
    waiting: Vec<usize>,
    /// Bit `k`: lane `k` holds a path.
    alive: u32,
    /// True if a path that leaves the scene finds no light there ([`escapes_find_no_light`]).
    escape_ends: bool,
    /// The film column of each lane's sample.
    x: [usize; W],
    /// Edges traced so far.
    depth: [u32; W],
    /// The ray each lane traces next (at the sample's time).
    ray: [Ray; W],
    /// Throughput (dimensionless) and radiance so far (W/m²/sr), RGB.
    beta: V,
    l: V,
    /// The previous vertex, for MIS of emission found by BSDF sampling.
    prev_delta: [bool; W],
    prev_pdf: F,
    prev_p: V,
}

/// What a vertex's lanes read: the hits, the numbers drawn there and the light sampled.
struct Hits {
    /// Bit `k`: lane `k` shades a vertex.
    shade: u32,
    /// Bit `k`: lane `k`'s next-event estimate is the four-lane kernel's; the other shading
    /// lanes compute theirs by [`direct_with`].
    nee: u32,
    si: [Option<SurfaceInteraction>; W],
    p: V,
    ng: V,
    ns: V,
    dpdu: V,
    albedo: V,
    /// The numbers of next-event estimation, then those of the BSDF and of roulette.
    u_light: F,
    u_nee: [F; 2],
    u_bsdf: [F; 2],
    u_rr: F,
    /// The light sample for the kernel ([`direct_lanes::Lanes`]' fields).
    pmf: F,
    kind: F,
    tri: [V; 4],
    ux: F,
    uy: F,
    radiance: V,
    area: F,
    two_sided: F,
}

impl Default for Hits {
    fn default() -> Self {
        Self {
            shade: 0,
            nee: 0,
            si: [None; W],
            p: V::default(),
            ng: V::default(),
            ns: V::default(),
            dpdu: V::default(),
            albedo: V::default(),
            u_light: [0.0; W],
            u_nee: [[0.0; W]; 2],
            u_bsdf: [[0.0; W]; 2],
            u_rr: [0.0; W],
            pmf: [1.0; W],
            kind: [0.0; W],
            tri: [V::default(); 4],
            ux: [0.0; W],
            uy: [0.0; W],
            radiance: V::default(),
            area: [1.0; W],
            two_sided: [0.0; W],
        }
    }
}

/// Renders the samples of row `r` eight at a time, each sample's radiance (W/m²/sr, linear
/// sRGB) to `add(x, radiance)`: the scalar loop's, bit for bit, for any scene in RGB without
/// media (the `path` integrator uses it where it pays, [`covers`]).
pub fn render_row(
    scene: &Scene,
    opts: &RenderOptions,
    filter: &Filter,
    r: &RowSamples,
    stats: &mut RenderStats,
    add: &mut dyn FnMut(usize, Spectrum),
) {
    debug_assert!(renders(scene));
    let mut samples = r.iter();
    let mut paths = Paths {
        samplers: std::array::from_fn(|_| Sampler::new(opts.sampler, opts.seed)),
        batch: DirectBatch::default(),
        waiting: Vec::new(),
        alive: 0,
        escape_ends: escapes_find_no_light(scene),
        x: [0; W],
        depth: [0; W],
        ray: [Ray::new(Vec3::ZERO, Vec3::Z); W],
        beta: V::default(),
        l: V::default(),
        prev_delta: [true; W],
        prev_pdf: [0.0; W],
        prev_p: V::default(),
    };
    let mut hits = Hits::default();
    let ext = scene.camera.screen_half_extent();
    let mut stream = PixelStream::default();
    loop {
        // New samples in the lanes whose paths ended.
        for k in Bits(!paths.alive & ALL) {
            let Some((x, fx, s)) = samples.next() else {
                break;
            };
            let sampler = &mut paths.samplers[k];
            let raster = r.start(sampler, &mut stream, filter, opts, fx, s);
            let (ray, _) = super::path::camera_ray(scene, raster, ext, sampler);
            paths.alive |= 1 << k;
            paths.x[k] = x;
            paths.depth[k] = 0;
            paths.ray[k] = ray;
            paths.beta.set(k, Vec3::ONE);
            paths.l.set(k, Vec3::ZERO);
            paths.prev_delta[k] = true;
            paths.prev_pdf[k] = 0.0;
            paths.prev_p.set(k, Vec3::ZERO);
        }
        if paths.waiting.len() >= WAITING_SAMPLES {
            finish(&mut paths, stats, add);
        }
        if paths.alive == 0 {
            finish(&mut paths, stats, add);
            return;
        }
        trace(scene, opts, &mut paths, &mut hits, stats, add);
        shade(scene, opts.limits.rr_depth, &mut paths, &hits, stats, add);
    }
}

/// Lane `k`'s path finished by the scalar loop ([`continue_path`]) from its traced `segment`,
/// with the state and the sum of terms it has in the lanes; its radiance to its pixel.
#[inline(never)]
fn hand_over<'s>(
    scene: &'s Scene,
    opts: &RenderOptions,
    paths: &mut Paths<'s>,
    k: usize,
    segment: Segment,
    stats: &mut RenderStats,
    add: &mut dyn FnMut(usize, Spectrum),
) {
    let depth = paths.depth[k];
    let state = PathState {
        ray: paths.ray[k],
        medium: scene.camera_medium,
        beta: beta(paths, k),
        depth,
        prev_delta: paths.prev_delta[k],
        prev_pdf: paths.prev_pdf[k],
        prev_p: paths.prev_p.get(k),
        prev_direct_by_rule: false,
        // Every vertex before was diffuse.
        first_diffuse: (depth > 0).then_some(true),
        ch: Channels::Rgb,
    };
    let l = paths.l.get(k);
    let radiance = continue_path(
        scene,
        state,
        Some(segment),
        Some(Spectrum::new(l.x, l.y, l.z)),
        &mut paths.samplers[k],
        opts,
        stats,
        &PathOnly,
        &mut paths.batch,
    );
    match radiance {
        Some(l) => add(paths.x[k], l),
        None => paths.waiting.push(paths.x[k]),
    }
    paths.alive &= !(1 << k);
}

/// The radiance of the handed-over paths that wait in the batch, to their pixels.
fn finish(paths: &mut Paths, stats: &mut RenderStats, add: &mut dyn FnMut(usize, Spectrum)) {
    let waiting = &paths.waiting;
    paths.batch.finish(stats, |i, l| add(waiting[i], l));
    paths.waiting.clear();
}

/// Ends lane `k`'s path: its radiance to its pixel.
#[inline]
fn end(paths: &mut Paths, k: usize, add: &mut dyn FnMut(usize, Spectrum)) {
    let l = paths.l.get(k);
    add(paths.x[k], Spectrum::new(l.x, l.y, l.z));
    paths.alive &= !(1 << k);
}

/// Adds `term` to lane `k`'s radiance (the scalar loop's `l += term`).
#[inline(always)]
fn add_term(paths: &mut Paths, k: usize, term: Spectrum) {
    paths.l.x[k] += term.c[0];
    paths.l.y[k] += term.c[1];
    paths.l.z[k] += term.c[2];
}

/// Lane `k`'s throughput.
#[inline(always)]
fn beta(paths: &Paths, k: usize) -> Spectrum {
    let b = paths.beta.get(k);
    Spectrum::new(b.x, b.y, b.z)
}

/// The lanes' closest hits, lane by lane: emission found there (MIS against the previous
/// vertex's BSDF sampling), the paths that end, and for the others the vertex, the numbers it
/// draws and the light its next-event estimate samples.
fn trace<'s>(
    scene: &'s Scene,
    opts: &RenderOptions,
    paths: &mut Paths<'s>,
    h: &mut Hits,
    stats: &mut RenderStats,
    add: &mut dyn FnMut(usize, Spectrum),
) {
    (h.shade, h.nee) = (0, 0);
    for k in Bits(paths.alive) {
        // `trace_segment` without media: the closest hit.
        stats.rays += 1;
        let Some(si) = scene.intersect(&paths.ray[k]) else {
            // A path that leaves finds only environment lights.
            if paths.escape_ends {
                end(paths, k, add);
            } else {
                let segment = Segment::Escaped {
                    transmittance: Spectrum::ONE,
                };
                hand_over(scene, opts, paths, k, segment, stats, add);
            }
            continue;
        };
        // A diffuse surface stays in the lanes (its transmittance is 1: no interior), and
        // `Material::bsdf` would give the Lambertian BSDF of albedo `reflectance(uv)` in RGB; a
        // path that reaches another surface is finished by the scalar loop.
        let Material::Diffuse { reflectance } = &scene.materials[si.material as usize] else {
            let transmittance = interior_transmittance(scene, &si, &paths.ray[k], &Channels::Rgb);
            let segment = Segment::Surface { si, transmittance };
            hand_over(scene, opts, paths, k, segment, stats, add);
            continue;
        };
        let ray = &paths.ray[k];
        paths.depth[k] += 1;
        if si.light != NONE {
            let light = &scene.lights[si.light as usize];
            let le =
                scene.light_emission(si.light as usize, light.le(si.ng, -ray.d), &Channels::Rgb);
            if !le.is_black() {
                let w = if paths.prev_delta[k] {
                    1.0
                } else {
                    let prev_p = paths.prev_p.get(k);
                    emission_mis(
                        scene,
                        si.light,
                        paths.prev_pdf[k],
                        prev_p,
                        ray.d,
                        si.p,
                        si.ng,
                    )
                };
                let term = beta(paths, k) * le * w;
                add_term(paths, k, term);
            }
        }
        if paths.depth[k] >= opts.limits.max_depth {
            end(paths, k, add);
            continue;
        }
        let albedo = reflectance.eval(si.uv);
        h.shade |= 1 << k;
        h.p.set(k, si.p);
        h.ng.set(k, si.ng);
        h.ns.set(k, si.ns);
        h.dpdu.set(k, si.dpdu);
        h.albedo.set(k, Vec3::from_array(albedo.c));
        // The scalar loop's numbers at a vertex: next-event estimation's three, the BSDF's
        // three (the first, the lobe number, the Lambertian BSDF ignores), roulette's one.
        let [u_light, u_nee_x, u_nee_y, _, u_bsdf_x, u_bsdf_y, u_rr] =
            paths.samplers[k].next_1d_array::<7>();
        h.u_light[k] = u_light;
        (h.u_nee[0][k], h.u_nee[1][k]) = (u_nee_x, u_nee_y);
        (h.u_bsdf[0][k], h.u_bsdf[1][k]) = (u_bsdf_x, u_bsdf_y);
        h.u_rr[k] = u_rr;
        if light_sample(scene, h, k, Vec2::new(u_nee_x, u_nee_y)) {
            h.nee |= 1 << k;
        } else {
            // Kept for `direct_with` (a record copied per vertex only where it is needed).
            h.si[k] = Some(si);
        }
    }
}

/// The light sample of lane `k`'s next-event estimate for the kernel, when the kernel covers it
/// (`PathSum::defer_direct`'s conditions): true once stored in `h`.
#[inline(always)]
fn light_sample(scene: &Scene, h: &mut Hits, k: usize, u_nee: Vec2) -> bool {
    let Some(light) = direct_lanes::light_lane(scene, h.u_light[k], u_nee) else {
        return false;
    };
    h.pmf[k] = light.pmf;
    h.kind[k] = light.kind;
    for (lane, corner) in h.tri.iter_mut().zip(light.tri) {
        lane.set(k, Vec3::from(corner));
    }
    (h.ux[k], h.uy[k]) = (light.ux, light.uy);
    h.radiance.set(k, Vec3::from_array(light.radiance));
    h.area[k] = light.area;
    h.two_sided[k] = light.two_sided;
    true
}

/// The vertices of the shading lanes: the frame, next-event estimation, the sampled direction,
/// roulette and the spawned rays; the paths that end there end.
fn shade(
    scene: &Scene,
    rr_depth: u32,
    paths: &mut Paths,
    h: &Hits,
    stats: &mut RenderStats,
    add: &mut dyn FnMut(usize, Spectrum),
) {
    if h.shade == 0 {
        return;
    }
    let (p, ng, ns, dpdu) = (&h.p, &h.ng, &h.ns, &h.dpdu);
    // `Frame::from_normal_tangent(ns, dpdu)`: dpdu made orthogonal to ns and normalised.
    let nd = ns.dot(dpdu);
    let s0 = V {
        x: lanes(|k| dpdu.x[k] - ns.x[k] * nd[k]),
        y: lanes(|k| dpdu.y[k] - ns.y[k] * nd[k]),
        z: lanes(|k| dpdu.z[k] - ns.z[k] * nd[k]),
    };
    let len2 = s0.dot(&s0);
    let len = lanes(|k| len2[k].sqrt());
    let mut s = V {
        x: lanes(|k| s0.x[k] / len[k]),
        y: lanes(|k| s0.y[k] / len[k]),
        z: lanes(|k| s0.z[k] / len[k]),
    };
    // `n.cross(s)` (glam's order of the products).
    let mut t = V {
        x: lanes(|k| ns.y[k] * s.z[k] - s.y[k] * ns.z[k]),
        y: lanes(|k| ns.z[k] * s.x[k] - s.z[k] * ns.x[k]),
        z: lanes(|k| ns.x[k] * s.y[k] - s.x[k] * ns.y[k]),
    };
    // A tangent along the normal: the frame of the normal alone (the lanes found first, so
    // that the loop does not branch on every lane).
    for k in Bits(h.shade & mask(|k| len2[k] < 1e-12)) {
        let f = Frame::from_normal(ns.get(k));
        s.set(k, f.s);
        t.set(k, f.t);
    }
    // `frame.to_local(−d)`.
    let back = V {
        x: lanes(|k| -paths.ray[k].d.x),
        y: lanes(|k| -paths.ray[k].d.y),
        z: lanes(|k| -paths.ray[k].d.z),
    };
    let time = lanes(|k| paths.ray[k].time);
    let wo = V {
        x: back.dot(&s),
        y: back.dot(&t),
        z: back.dot(ns),
    };

    // Next-event estimation: the kernel's lanes four at a time, the others one by one.
    let f = V {
        x: lanes(|k| h.albedo.x[k] * INV_PI),
        y: lanes(|k| h.albedo.y[k] * INV_PI),
        z: lanes(|k| h.albedo.z[k] * INV_PI),
    };
    for half_ in 0..W / LANES {
        let quad = h.nee >> (LANES * half_) & 0xF;
        if quad == 0 {
            continue;
        }
        let lanes_in = Lanes {
            p: p.half(half_),
            ng: ng.half(half_),
            s: s.half(half_),
            t: t.half(half_),
            n: ns.half(half_),
            wo: wo.half(half_),
            f: f.half(half_),
            pmf: half(&h.pmf, half_),
            kind: half(&h.kind, half_),
            tri: h.tri.map(|c| c.half(half_)),
            ux: half(&h.ux, half_),
            uy: half(&h.uy, half_),
            radiance: h.radiance.half(half_),
            area: half(&h.area, half_),
            two_sided: half(&h.two_sided, half_),
            time: half(&time, half_),
        };
        let e = direct_lanes::estimate(&lanes_in);
        for j in Bits(quad) {
            let k = LANES * half_ + j;
            let mut est = Spectrum::ZERO;
            if e.ray >> j & 1 == 1 {
                stats.rays += 1;
                let ray =
                    Ray::with_t_max(e.o.lane(j), e.dir.lane(j), direct_lanes::get(e.t_max, j))
                        .at_time(time[k]);
                if !scene.occluded(&ray) {
                    let c = e.c.lane(j);
                    est = Spectrum::new(c.x, c.y, c.z);
                }
            }
            let term = beta(paths, k) * est;
            add_term(paths, k, term);
        }
    }
    for k in Bits(h.shade & !h.nee) {
        let Some(si) = h.si[k] else { continue };
        let v = Vertex::new(scene, si, &paths.ray[k], &mut Channels::Rgb);
        let at = Scatterer::Surface {
            v: &v,
            medium: NONE,
        };
        let u = Vec2::new(h.u_nee[0][k], h.u_nee[1][k]);
        let e = direct_with(
            scene,
            at,
            h.u_light[k],
            u,
            &mut paths.samplers[k],
            stats,
            true,
        );
        let term = beta(paths, k) * e;
        add_term(paths, k, term);
    }

    // The Lambertian BSDF's sample (`sample_two_sided` around the concentric map lifted to the
    // hemisphere), in the local frame.
    let [u0, u1] = &h.u_bsdf;
    let ox = lanes(|k| 2.0 * u0[k] - 1.0);
    let oy = lanes(|k| 2.0 * u1[k] - 1.0);
    // `warp::square_to_disk_concentric`, both of its cases computed and one kept (no branch
    // for the CPU to mispredict); the sine and cosine lane by lane (glibc's). Calling the warp
    // itself lane by lane took 1.09x the time (docs/performance.md, tenth session).
    let around_x = lanes(|k| (ox[k].abs() > oy[k].abs()) as u32 as f32);
    let r = lanes(|k| if around_x[k] != 0.0 { ox[k] } else { oy[k] });
    // θ = π/4 · (oy / ox) around x, π/2 − π/4 · (ox / oy) around y: one quotient per lane of
    // the chosen operands (the same bits; a choice between the two quotients became a branch
    // per lane around its division, which the predictor lost half the time).
    let num = blend(&around_x, &oy, &ox);
    let den = blend(&around_x, &ox, &oy);
    let quarter = lanes(|k| 0.25 * PI * (num[k] / den[k]));
    let theta = blend(&around_x, &quarter, &lanes(|k| 0.5 * PI - quarter[k]));
    let mut lx = [0.0f32; W];
    let mut ly = [0.0f32; W];
    // The shading lanes' sines and cosines, those around x first: glibc's `sincosf` branches
    // on whether |θ| < π/4, which is whether the lane is around x, a coin flip when the lanes
    // come in order (the other lanes' values are not read).
    let x_lanes = mask(|k| around_x[k] != 0.0);
    for group in [h.shade & x_lanes, h.shade & !x_lanes] {
        for k in Bits(group) {
            (lx[k], ly[k]) = (r[k] * theta[k].cos(), r[k] * theta[k].sin());
        }
    }
    let centre = lanes(|k| (ox[k] == 0.0 && oy[k] == 0.0) as u32 as f32);
    let lx = lanes(|k| if centre[k] != 0.0 { 0.0 } else { lx[k] });
    let ly = lanes(|k| if centre[k] != 0.0 { 0.0 } else { ly[k] });
    let z = lanes(|k| (1.0 - (lx[k] * lx[k] + ly[k] * ly[k])).max(0.0).sqrt());
    let pdf = lanes(|k| z[k] * INV_PI);
    // Mirrored back below the surface when `wo` is.
    let lz = lanes(|k| if wo.z[k] < 0.0 { -z[k] } else { z[k] });
    // `frame.to_world(wi)`: (s x + t y) + n z.
    let wi = V {
        x: lanes(|k| s.x[k] * lx[k] + t.x[k] * ly[k] + ns.x[k] * lz[k]),
        y: lanes(|k| s.y[k] * lx[k] + t.y[k] * ly[k] + ns.y[k] * lz[k]),
        z: lanes(|k| s.z[k] * lx[k] + t.z[k] * ly[k] + ns.z[k] * lz[k]),
    };
    // `Vertex::same_side_consistent(−d, wi, wi_local)`.
    let back_ng = back.dot(ng);
    let wi_ng = wi.dot(ng);
    let consistent = lanes(|k| {
        let geo = back_ng[k] * wi_ng[k] > 0.0;
        let shade = wo.z[k] * lz[k] > 0.0;
        (geo == shade) as u32 as f32
    });
    // The BSDF's weight is its albedo.
    let beta = V {
        x: lanes(|k| paths.beta.x[k] * h.albedo.x[k]),
        y: lanes(|k| paths.beta.y[k] * h.albedo.y[k]),
        z: lanes(|k| paths.beta.z[k] * h.albedo.z[k]),
    };
    // `russian_roulette`: past `rr_depth`, survive with q = min(max β, 0.95), then β / q as
    // β · (1/q) (`Spectrum`'s division).
    let q = lanes(|k| beta.x[k].max(beta.y[k]).max(beta.z[k]).min(0.95));
    let inv_q = lanes(|k| 1.0 / q[k]);
    // `SurfaceInteraction::spawn_ray(wi)`: the origin off the surface along ±ng.
    let offset = lanes(|k| {
        let m = |a: f32, b: f32| if a > b { a } else { b };
        1e-4 * (1.0 + m(p.x[k].abs(), m(p.y[k].abs(), p.z[k].abs())))
    });
    let side = lanes(|k| if wi_ng[k] >= 0.0 { 1.0 } else { -1.0 });
    let o = V {
        x: lanes(|k| p.x[k] + ng.x[k] * (side[k] * offset[k])),
        y: lanes(|k| p.y[k] + ng.y[k] * (side[k] * offset[k])),
        z: lanes(|k| p.z[k] + ng.z[k] * (side[k] * offset[k])),
    };
    for k in Bits(h.shade) {
        // No sample for a grazing `wo` or a direction on the horizon; an inconsistent side.
        if wo.z[k] == 0.0 || z[k] <= 0.0 || consistent[k] == 0.0 {
            end(paths, k, add);
            continue;
        }
        paths.prev_delta[k] = false;
        paths.prev_pdf[k] = pdf[k];
        paths.prev_p.set(k, p.get(k));
        let mut b = beta.get(k);
        if b == Vec3::ZERO {
            end(paths, k, add);
            continue;
        }
        if paths.depth[k] >= rr_depth {
            if h.u_rr[k] >= q[k] {
                end(paths, k, add);
                continue;
            }
            b = Vec3::new(b.x * inv_q[k], b.y * inv_q[k], b.z * inv_q[k]);
        }
        paths.beta.set(k, b);
        paths.ray[k] = Ray::new(o.get(k), wi.get(k)).at_time(time[k]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{Clock, RenderControl};
    use crate::driver::pixels::{render_pixels_batched, render_pixels_rows};
    use crate::film::Film;
    use crate::integrator::path::{PathOnly, camera_radiance};
    use caustica_core::sampling::SamplerKind;
    use caustica_loader::builtin_scene;
    use caustica_scene::light::{DirectionalLight, EnvironmentLight, PointLight, SpotLight};

    /// The film and the rays traced of `scene` rendered by the lanes and by the scalar loop.
    fn both(scene: &Scene, opts: &RenderOptions, w: u32, h: u32) -> [(Film, u64); 2] {
        let filter = Filter::new(scene.settings.filter);
        let (clock, ctl) = (Clock::start(opts), RenderControl::silent());
        let stage = clock.stage(&ctl);
        let mut lanes = Film::new(w as usize, h as usize);
        let st = render_pixels_rows(&mut lanes, opts, &stage, |r, st, add| {
            render_row(scene, opts, &filter, r, st, add)
        });
        let mut scalar = Film::new(w as usize, h as usize);
        let ext = scene.camera.screen_half_extent();
        let st_scalar =
            render_pixels_batched(&mut scalar, &filter, opts, &stage, |s, raster, b, st| {
                camera_radiance(scene, raster, ext, s, opts, st, &PathOnly, b)
            });
        [(lanes, st.rays), (scalar, st_scalar.rays)]
    }

    /// The Cornell box at `w × h`; with a point light beside its area light and a thin lens in
    /// place of the pinhole when `point`.
    /// The Cornell box at `w × h` with `extra` lights beside its own (and a thin lens then).
    fn cornell(w: u32, h: u32, extra: &[Light]) -> Scene {
        let mut builder = builtin_scene("cornell-box").unwrap();
        let mut camera = builder.camera().unwrap().clone();
        (camera.width, camera.height) = (w, h);
        if !extra.is_empty() {
            camera.lens_radius = 0.05;
        }
        builder.set_camera(camera);
        for light in extra {
            builder.add_light(light.clone());
        }
        builder.build().unwrap()
    }

    /// The Cornell box's extra lights of the tests: none; a point light and a directional
    /// light (which the kernel computes beside the area light's triangles, mixed in its lanes);
    /// a spot light (whose estimates the lanes leave to `direct_with`).
    fn extra_lights() -> [Vec<Light>; 3] {
        let point = Light::Point(PointLight::new(
            Vec3::new(0.3, 0.5, 0.2),
            Spectrum::new(0.4, 0.3, 0.2),
        ));
        // Through the box's open front, at a slant, onto the floor and the walls.
        let sun = Light::Directional(DirectionalLight::new(
            Vec3::new(0.3, -0.6, -1.0),
            Spectrum::new(0.5, 0.6, 0.7),
        ));
        let spot = Light::Spot(SpotLight::new(
            Vec3::new(0.0, 0.6, 0.0),
            Vec3::new(0.1, -1.0, 0.2),
            Spectrum::new(0.8, 0.8, 0.5),
            40.0,
            25.0,
        ));
        [vec![], vec![point, sun], vec![spot]]
    }

    /// The lanes give the scalar loop's image bit for bit, and trace the same rays: with both
    /// samplers, short and long paths (roulette from the second vertex on), a pinhole and a
    /// thin lens, point and directional lights in the kernel's lanes beside the area light, and
    /// a spot light whose estimates the lanes leave to `direct_with`.
    #[test]
    fn the_lanes_render_the_scalar_loops_image_bit_for_bit() {
        let (w, h) = (23, 17);
        for extra in extra_lights() {
            let scene = cornell(w, h, &extra);
            let spot = extra.iter().any(|l| matches!(l, Light::Spot(_)));
            // With the spot light the integrator would choose the scalar loop; the lanes still
            // give its image.
            assert!(renders(&scene) && covers(&scene) != spot);
            for (sampler, max_depth, rr_depth) in [
                (SamplerKind::Independent, 8, 5),
                (SamplerKind::Sobol, 8, 5),
                (SamplerKind::Independent, 3, 1),
                (SamplerKind::Sobol, 40, 2),
            ] {
                let mut opts = RenderOptions {
                    spp: 5,
                    sampler,
                    seed: 3,
                    ..RenderOptions::default()
                };
                opts.limits.max_depth = max_depth;
                opts.limits.rr_depth = rr_depth;
                let [(lanes, rays), (scalar, scalar_rays)] = both(&scene, &opts, w, h);
                let case = format!(
                    "{} lights, {sampler:?}, depth {max_depth}",
                    scene.lights.len()
                );
                assert_eq!(lanes.count, scalar.count, "{case}");
                assert!(lanes.sum == scalar.sum, "{case}: the films differ");
                assert_eq!(rays, scalar_rays, "{case}");
                // The image is not black: the comparison covers lit paths.
                assert!(lanes.sum.iter().any(|p| p[0].to_f64() > 0.0), "{case}");
            }
        }
    }

    /// Scenes with glass and metal and an environment light (which the kernel does not
    /// sample): the paths that reach a surface that is not diffuse, or leave the scene, are
    /// finished by the scalar loop from where they are, and the image is still the scalar
    /// loop's bit for bit.
    #[test]
    fn paths_handed_over_to_the_scalar_loop_keep_the_bits() {
        let mut handed = 0;
        for name in [
            "caustic-box",
            "glass-sphere",
            "metal-ring",
            "shiny-pyramids",
        ] {
            let mut builder = builtin_scene(name).unwrap();
            let mut camera = builder.camera().unwrap().clone();
            (camera.width, camera.height) = (19, 14);
            builder.set_camera(camera);
            // Paths that leave the scene find it (MIS against the previous vertex).
            builder.add_light(Light::Environment(EnvironmentLight::constant(
                Spectrum::new(0.3, 0.2, 0.1),
            )));
            let scene = builder.build().unwrap();
            assert!(!scene.infinite_lights.is_empty());
            assert!(renders(&scene) && !covers(&scene), "{name}");
            handed += scene
                .materials
                .iter()
                .filter(|m| !matches!(m, Material::Diffuse { .. }))
                .count();
            for sampler in [SamplerKind::Independent, SamplerKind::Sobol] {
                let opts = RenderOptions {
                    spp: 6,
                    sampler,
                    seed: 5,
                    ..RenderOptions::default()
                };
                let [(lanes, rays), (scalar, scalar_rays)] = both(&scene, &opts, 19, 14);
                assert!(
                    lanes.sum == scalar.sum,
                    "{name} {sampler:?}: the films differ"
                );
                assert_eq!(rays, scalar_rays, "{name} {sampler:?}");
                assert!(lanes.sum.iter().any(|p| p[0].to_f64() > 0.0), "{name}");
            }
        }
        assert!(handed >= 4, "{handed} materials that are not diffuse");
    }

    /// Media, spectral rendering and lights the four-lane kernel does not sample go to the
    /// scalar loop.
    #[test]
    fn the_lanes_cover_rgb_scenes_without_media_lit_by_triangles_points_and_the_sun() {
        // Area lights; a directional light (the metal ring); a point light (the glass sphere).
        for name in [
            "cornell-box",
            "caustic-box",
            "gold-ring",
            "metal-ring",
            "glass-sphere",
        ] {
            assert!(
                covers(&builtin_scene(name).unwrap().build().unwrap()),
                "{name}"
            );
        }
        let [_, _, spot] = extra_lights();
        assert!(!covers(&cornell(8, 8, &spot)));
        // Media (environment lights: `paths_handed_over_to_the_scalar_loop_keep_the_bits`).
        assert!(!covers(&builtin_scene("fog-box").unwrap().build().unwrap()));
        let mut spectral = builtin_scene("cornell-box").unwrap().build().unwrap();
        spectral.set_spectral(true).unwrap();
        assert!(!covers(&spectral));
    }
}
