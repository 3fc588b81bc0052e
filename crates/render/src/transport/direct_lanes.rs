//! Next-event estimation four vertices at a time: SIMD across the vertices of a path (issue 26,
//! deliverable 3).
//!
//! The path tracer defers the estimate at a vertex the lanes cover — a Lambertian surface, a
//! path in RGB, a triangle area light picked, a scene without media — and [`PathSum`] computes
//! the waiting ones in SSE lanes (glam's `Vec4`, structure of arrays) when four wait or the path
//! ends. Each lane repeats the arithmetic of [`super::direct::direct_with`] in the same order
//! (`AreaLight::sample_li`'s area sampling, the Lambertian BSDF's value and density, the
//! same-side test, the power heuristic, `SurfaceInteraction::spawn_ray_to`), so an estimate is
//! the scalar one bit for bit; and [`PathSum`] adds a path's terms in the order the path found
//! them, so its radiance is bit for bit the same too. The shadow rays are traced one by one:
//! eight-ray streams would need eight estimates, more than a path has (docs/performance.md,
//! issue 26, sixth session).

use crate::stats::RenderStats;
use crate::transport::vertex::Vertex;
use caustica_core::{Channels, INV_PI, Ray, Spectrum, Vec2, Vec3};
use caustica_scene::Scene;
use caustica_scene::bsdf::Bsdf;
use caustica_scene::light::Light;
use glam::{BVec4A, Vec4};

/// Estimates computed together.
const LANES: usize = 4;
/// Terms a [`PathSum`] holds after its first waiting estimate before it computes them.
const TAIL: usize = 16;

/// The waiting estimates' inputs, lane `k` for the `k`-th: the vertex as the lanes read it and
/// the light sample's choices, stored in place (structure of arrays) as each is deferred.
#[derive(Clone, Copy, Default)]
struct Lanes {
    /// Position (m), geometric normal, shading frame.
    p: V3,
    ng: V3,
    s: V3,
    t: V3,
    n: V3,
    /// Direction back along the incoming ray, local frame.
    wo: V3,
    /// The Lambertian BSDF's value, albedo / π (sr⁻¹), per channel.
    f: V3,
    /// The picked light's probability.
    pmf: Vec4,
    /// The light's triangle: vertices and unit normal.
    tri: [V3; 4],
    /// The point of the square the triangle warp maps.
    ux: Vec4,
    uy: Vec4,
    /// The light's radiance (W/m²/sr), total area (m²) and sidedness (1 for two-sided).
    radiance: V3,
    area: Vec4,
    two_sided: Vec4,
    /// Scene time of the vertex (frames).
    time: Vec4,
}

/// Lane `k` of `v`, by its address: glam's `Index` matches on the lane, a jump through a
/// table that a varying `k` mispredicts.
#[inline(always)]
fn get(v: Vec4, k: usize) -> f32 {
    v.to_array()[k & (LANES - 1)]
}

/// Sets lane `k` of `v` to `x` ([`get`]'s way).
#[inline(always)]
fn set(v: &mut Vec4, k: usize, x: f32) {
    let a: &mut [f32; 4] = v.as_mut();
    // `k < LANES`; the mask spares a bounds check per store.
    a[k & (LANES - 1)] = x;
}

/// Three coordinates in four lanes.
#[derive(Clone, Copy, Default)]
struct V3 {
    x: Vec4,
    y: Vec4,
    z: Vec4,
}

impl V3 {
    /// Stores `v` in lane `k`.
    #[inline(always)]
    fn set(&mut self, k: usize, v: [f32; 3]) {
        set(&mut self.x, k, v[0]);
        set(&mut self.y, k, v[1]);
        set(&mut self.z, k, v[2]);
    }
    #[inline(always)]
    fn lane(&self, l: usize) -> Vec3 {
        Vec3::new(get(self.x, l), get(self.y, l), get(self.z, l))
    }
    /// glam's `Vec3::dot`: `(x x' + y y') + z z'`.
    #[inline(always)]
    fn dot(self, o: V3) -> Vec4 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline(always)]
    fn add(self, o: V3) -> V3 {
        V3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
    #[inline(always)]
    fn sub(self, o: V3) -> V3 {
        V3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
    #[inline(always)]
    fn scale(self, s: Vec4) -> V3 {
        V3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
    #[inline(always)]
    fn div(self, s: Vec4) -> V3 {
        V3 {
            x: self.x / s,
            y: self.y / s,
            z: self.z / s,
        }
    }
    #[inline(always)]
    fn mul(self, o: V3) -> V3 {
        V3 {
            x: self.x * o.x,
            y: self.y * o.y,
            z: self.z * o.z,
        }
    }
    /// Lanes of `self` where `m`, else zero (`Spectrum::ZERO`'s +0).
    #[inline(always)]
    fn keep(self, m: BVec4A) -> V3 {
        V3 {
            x: Vec4::select(m, self.x, Vec4::ZERO),
            y: Vec4::select(m, self.y, Vec4::ZERO),
            z: Vec4::select(m, self.z, Vec4::ZERO),
        }
    }
    /// True in the lanes where some coordinate is not zero (`!Spectrum::is_black`).
    #[inline(always)]
    fn nonzero(self) -> BVec4A {
        self.x.cmpne(Vec4::ZERO) | self.y.cmpne(Vec4::ZERO) | self.z.cmpne(Vec4::ZERO)
    }
}

/// The four lanes' estimates (W/m²/sr) when their shadow rays are unblocked, and the shadow
/// rays: origins, directions, lengths, and (bit `k`) whether lane `k` needs one.
struct Estimates {
    c: V3,
    o: V3,
    dir: V3,
    t_max: Vec4,
    ray: u32,
}

/// Next-event estimation in the four lanes of `r`.
#[inline(never)]
fn estimate(r: &Lanes) -> Estimates {
    let zero = Vec4::ZERO;
    let Lanes {
        p, ng, s, t, n, wo, ..
    } = *r;
    let [p0, p1, p2, ln] = r.tri;
    let (ux, uy) = (r.ux, r.uy);

    // `warp::square_to_uniform_triangle`: s/2 and l − s/2 for the smaller and larger coordinate.
    let lt = ux.cmplt(uy);
    let (small, large) = (Vec4::select(lt, ux, uy), Vec4::select(lt, uy, ux));
    let h = small / 2.0;
    let m = large - h;
    let (b0, b1) = (Vec4::select(lt, h, m), Vec4::select(lt, m, h));
    let (bx, by) = (b1, Vec4::ONE - b0 - b1);
    // `AreaLight::sample_area`: p0 (1 − b1 − b2) + p1 b1 + p2 b2.
    let lp = p0
        .scale(Vec4::ONE - bx - by)
        .add(p1.scale(bx))
        .add(p2.scale(by));
    // `AreaLight::sample_li`.
    let d = lp.sub(p);
    let d2 = d.dot(d);
    let dist = d2.sqrt();
    let wi = d.div(dist);
    let cos = ln.dot(wi).abs();
    // `AreaLight::emits(n, −wi)`.
    let c_emit = ln.x * -wi.x + ln.y * -wi.y + ln.z * -wi.z;
    let two_sided = r.two_sided.cmpne(zero);
    let emits = (two_sided & c_emit.cmpne(zero)) | (!two_sided & c_emit.cmpgt(zero));
    let pdf = d2 / (cos * r.area);
    let mut ok = d2.cmpgt(zero) & cos.cmpgt(zero) & emits;
    ok &= pdf.cmpgt(zero) & pdf.cmplt(Vec4::splat(f32::INFINITY));
    // `Spectrum / f32` multiplies by the reciprocal.
    let weight = r.radiance.scale(Vec4::ONE / pdf);
    ok &= weight.nonzero();
    // `Scatterer::eval`: the Lambertian BSDF in the shading frame, both sides mirrored up when
    // `wo` is below, then the geometric same-side test.
    let wl = V3 {
        x: wi.dot(s),
        y: wi.dot(t),
        z: wi.dot(n),
    };
    let below = wo.z.cmplt(zero);
    let (wo_up, wi_up) = (
        Vec4::select(below, -wo.z, wo.z),
        Vec4::select(below, -wl.z, wl.z),
    );
    let front = wo_up.cmpgt(zero) & wi_up.cmpgt(zero);
    let f = r.f.keep(front);
    ok &= f.nonzero();
    let wo_world = s.scale(wo.x).add(t.scale(wo.y)).add(n.scale(wo.z));
    let geo = (wo_world.dot(ng) * wi.dot(ng)).cmpgt(zero);
    let shade = (wo.z * wl.z).cmpgt(zero);
    ok &= !(geo ^ shade);
    // f |cos θi| times the shading-normal correction, 1 in radiance mode.
    let f = f.scale(wl.z.abs() * Vec4::ONE);
    ok &= f.nonzero();
    // `power_heuristic` against the Lambertian BSDF's density.
    let bsdf_pdf = Vec4::select(front, wi_up * INV_PI, zero);
    let a = r.pmf * pdf;
    let (a2, b2) = (a * a, bsdf_pdf * bsdf_pdf);
    let mis = Vec4::select(
        a2.cmpeq(zero) & b2.cmpeq(zero),
        zero,
        Vec4::select(
            a2.cmpeq(Vec4::splat(f32::INFINITY)),
            Vec4::ONE,
            a2 / (a2 + b2),
        ),
    );
    // f · tr · Le · (mis / pmf) with tr = 1: `f * 1` is `f`.
    let c = f.mul(weight).scale(mis / r.pmf).keep(ok);
    // `SurfaceInteraction::spawn_ray_to(lp)`.
    let side = Vec4::select(d.dot(ng).cmpge(zero), Vec4::ONE, -Vec4::ONE);
    let offset = Vec4::splat(1e-4) * (Vec4::ONE + p.x.abs().max(p.y.abs()).max(p.z.abs()));
    let o = p.add(ng.scale(side * offset));
    let to = lp.sub(o);
    let len = to.dot(to).sqrt();
    Estimates {
        c,
        o,
        dir: to.div(len),
        t_max: len * (1.0 - 1e-4),
        ray: ok.bitmask(),
    }
}

/// A path's radiance (W/m²/sr) as the sum of its terms in the order the path finds them, with
/// next-event estimates waiting for the lanes: the terms after the first waiting estimate are
/// held until it is computed, then added in order, so the sum is bit for bit `l += term`'s.
pub struct PathSum<'a> {
    scene: &'a Scene,
    /// The terms before the first waiting estimate, summed.
    sum: Spectrum,
    /// The terms after it: a value, or (`true`) the throughput of a waiting estimate.
    tail: [(Spectrum, bool); TAIL],
    len: usize,
    lanes: Lanes,
    count: usize,
    /// Shadow rays traced.
    rays: u64,
}

impl<'a> PathSum<'a> {
    pub fn new(scene: &'a Scene) -> Self {
        Self {
            scene,
            sum: Spectrum::ZERO,
            tail: [(Spectrum::ZERO, false); TAIL],
            len: 0,
            lanes: Lanes::default(),
            count: 0,
            rays: 0,
        }
    }

    /// Adds `term`.
    #[inline]
    pub fn add(&mut self, term: Spectrum) {
        if self.len == 0 {
            self.sum += term;
        } else {
            self.push((term, false));
        }
    }

    /// Adds `beta` times next-event estimation at `v` with the numbers `u_light`, `u` (those
    /// [`super::direct::sample_direct`] draws), to be computed in the lanes; false, adding
    /// nothing, when the lanes do not cover it (a scene with media, whose shadow rays draw
    /// numbers of their own; not a Lambertian surface; not RGB; not a triangle light). Inlined
    /// into the path loop: out of line it cost 1 % more instructions on the Cornell box.
    #[inline(always)]
    pub fn defer_direct(&mut self, beta: Spectrum, v: &Vertex, u_light: f32, u: Vec2) -> bool {
        if self.scene.has_media {
            return false;
        }
        let Bsdf::Lambertian(lambertian) = &v.bsdf else {
            return false;
        };
        if v.channels != Channels::Rgb {
            return false;
        }
        let Some(dist) = &self.scene.light_distribution else {
            return false;
        };
        let (li, pmf, _) = dist.sample(u_light);
        let Some(Light::Area(light)) = self.scene.lights.get(li) else {
            return false;
        };
        let Some((tri, w)) = light.triangle_sample(u) else {
            return false;
        };
        let (k, r) = (self.count, &mut self.lanes);
        let v3 = |v: Vec3| v.to_array();
        r.p.set(k, v3(v.si.p));
        r.ng.set(k, v3(v.si.ng));
        r.s.set(k, v3(v.frame.s));
        r.t.set(k, v3(v.frame.t));
        r.n.set(k, v3(v.frame.n));
        r.wo.set(k, v3(v.wo));
        // `Lambertian::eval`'s value.
        r.f.set(k, (lambertian.albedo * INV_PI).c);
        set(&mut r.pmf, k, pmf);
        for (lane, corner) in r.tri.iter_mut().zip(tri) {
            lane.set(k, [corner.x, corner.y, corner.z]);
        }
        set(&mut r.ux, k, w.x);
        set(&mut r.uy, k, w.y);
        r.radiance.set(k, light.radiance.c);
        set(&mut r.area, k, light.area());
        set(&mut r.two_sided, k, light.two_sided as u8 as f32);
        set(&mut r.time, k, v.si.time);
        self.count += 1;
        self.push((beta, true));
        if self.count == LANES {
            self.flush();
        }
        true
    }

    #[inline]
    fn push(&mut self, entry: (Spectrum, bool)) {
        self.tail[self.len % TAIL] = entry;
        self.len += 1;
        if self.len == TAIL {
            self.flush();
        }
    }

    /// Computes the waiting estimates and adds the held terms.
    fn flush(&mut self) {
        if self.len == 0 {
            return;
        }
        let mut est = [Spectrum::ZERO; LANES];
        if self.count > 0 {
            let e = estimate(&self.lanes);
            // The lanes that wait and need a shadow ray (the others hold stale inputs).
            let mut rays = e.ray & ((1 << self.count) - 1);
            while rays != 0 {
                let k = rays.trailing_zeros() as usize & (LANES - 1);
                rays &= rays - 1;
                self.rays += 1;
                let ray = Ray::with_t_max(e.o.lane(k), e.dir.lane(k), get(e.t_max, k))
                    .at_time(get(self.lanes.time, k));
                if !self.scene.occluded(&ray) {
                    let c = e.c.lane(k);
                    est[k] = Spectrum::new(c.x, c.y, c.z);
                }
            }
        }
        let mut k = 0;
        for &(term, waiting) in &self.tail[..self.len] {
            if waiting {
                self.sum += term * est[k];
                k += 1;
            } else {
                self.sum += term;
            }
        }
        self.len = 0;
        self.count = 0;
    }

    /// The path's radiance; the shadow rays traced are counted in `stats`. (By reference: a
    /// move would copy the lanes.)
    pub fn total(&mut self, stats: &mut RenderStats) -> Spectrum {
        self.flush();
        stats.rays += std::mem::take(&mut self.rays);
        self.sum
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::transport::direct::direct_with;
    use crate::transport::vertex::Scatterer;
    use caustica_core::sampling::{Pcg32, Sampler, SamplerKind};
    use caustica_loader::builtin_scene;
    use caustica_scene::intersection::NONE;

    /// Vertices of the Cornell box seen from everywhere: hits of rays from random points inside
    /// it in random directions (both sides of the walls' shading frames, the light itself).
    fn vertices(scene: &Scene, n: usize, rng: &mut Pcg32) -> Vec<Vertex> {
        let b = scene.geometry.bounds();
        let mut out = Vec::with_capacity(n);
        while out.len() < n {
            let u = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            let o = b.min + (b.max - b.min) * (u * 0.9 + 0.05);
            let d = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5;
            let Some(d) = d.try_normalize() else { continue };
            let ray = Ray::new(o, d);
            if let Some(si) = scene.geometry.intersect(&ray) {
                out.push(Vertex::rgb(scene, si, &ray));
            }
        }
        out
    }

    /// Paths of one to seven estimates with up to seven terms before each: the lanes' sum equals
    /// `l += term` with the scalar estimates, bit for bit, for one- and two-sided lights.
    #[test]
    fn lanes_give_the_scalar_estimates_and_sum_bit_for_bit() {
        let mut scene = builtin_scene("cornell-box").unwrap().build().unwrap();
        let mut rng = Pcg32::new(9, 4);
        let mut sampler = Sampler::new(SamplerKind::Independent, 1);
        let mut stats = RenderStats::default();
        let (mut lit, mut deferred, mut rays) = (0, 0, 0);
        for two_sided in [false, true] {
            let Some(Light::Area(light)) = scene.lights.first_mut() else {
                panic!("the Cornell box's light")
            };
            light.two_sided = two_sided;
            let verts = vertices(&scene, 3000, &mut rng);
            for path in verts.chunks(7) {
                let mut l = Spectrum::ZERO;
                let mut lanes = PathSum::new(&scene);
                let mut scalar_rays = 0;
                for v in path {
                    // Zero to seven terms before each estimate: the held terms also fill the
                    // tail (sixteen) before four estimates wait.
                    for _ in 0..(rng.next_u32() % 8) {
                        let term = Spectrum::new(rng.next_f32(), rng.next_f32(), 0.0);
                        l += term;
                        lanes.add(term);
                    }
                    let beta = Spectrum::new(rng.next_f32(), 1.0, rng.next_f32() * 4.0);
                    let (u_light, u) = (rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32()));
                    let at = Scatterer::Surface { v, medium: NONE };
                    let mut st = RenderStats::default();
                    let e = direct_with(&scene, at, u_light, u, &mut sampler, &mut st, true);
                    scalar_rays += st.rays;
                    l += beta * e;
                    lit += !e.is_black() as u32;
                    if lanes.defer_direct(beta, v, u_light, u) {
                        deferred += 1;
                    } else {
                        lanes.add(beta * e);
                    }
                }
                let before = stats.rays;
                let got = lanes.total(&mut stats);
                assert_eq!(
                    got.c.map(f32::to_bits),
                    l.c.map(f32::to_bits),
                    "{got:?} {l:?}"
                );
                assert_eq!(stats.rays - before, scalar_rays, "shadow rays");
                rays += scalar_rays;
            }
        }
        // In a scene with media the shadow rays draw numbers of their own: nothing waits.
        let fog = builtin_scene("fog-box").unwrap().build().unwrap();
        let mut l = PathSum::new(&fog);
        for v in &vertices(&fog, 50, &mut rng) {
            assert!(!l.defer_direct(Spectrum::ONE, v, 0.5, Vec2::splat(0.5)));
        }
        // Most vertices are deferred and many lit: the comparison covers the lanes.
        assert!(
            deferred > 5000 && lit > 2500 && rays > 3000,
            "{deferred} {lit} {rays}"
        );
    }
}
