//! Next-event estimation four vertices at a time: SIMD across the vertices of paths (issue 26,
//! deliverable 3).
//!
//! The path tracer defers the estimate at a vertex the lanes cover — a Lambertian surface, a
//! path in RGB, a triangle area light, a point light or a directional light picked, a scene
//! without media — and [`DirectBatch`] computes the waiting ones in SSE lanes (glam's `Vec4`,
//! structure of arrays) four at a time, the estimates of consecutive paths side by side. Each
//! lane repeats the arithmetic of [`super::direct::direct_with`] in the same order (the light's
//! `sample_li`: `AreaLight`'s area sampling, `PointLight`'s inverse square law,
//! `DirectionalLight`'s constant irradiance; the Lambertian BSDF's value and density, the
//! same-side test, the power heuristic for area lights, `SurfaceInteraction::spawn_ray_to` or
//! `spawn_ray`), so an estimate is the scalar one bit for bit; and a
//! path's [`PathSum`] adds its terms in the order the path found them, so its radiance is bit for
//! bit the same too. The shadow rays are traced one by one (docs/performance.md, issue 26).

use crate::stats::RenderStats;
use crate::transport::vertex::Vertex;
use caustica_core::{Channels, INV_PI, Ray, Spectrum, Vec2, Vec3};
use caustica_scene::Scene;
use caustica_scene::bsdf::Bsdf;
use caustica_scene::light::{AreaShape, Light};
use glam::{BVec4A, Vec3A, Vec4};

/// Estimates computed together.
pub(crate) const LANES: usize = 4;

/// The waiting estimates' inputs, lane `k` for the `k`-th: the vertex as the lanes read it and
/// the light sample's choices, stored in place (structure of arrays) as each is deferred.
#[derive(Clone, Copy, Default)]
pub(crate) struct Lanes {
    /// Position (m), geometric normal, shading frame.
    pub(crate) p: V3,
    pub(crate) ng: V3,
    pub(crate) s: V3,
    pub(crate) t: V3,
    pub(crate) n: V3,
    /// Direction back along the incoming ray, local frame.
    pub(crate) wo: V3,
    /// The Lambertian BSDF's value, albedo / π (sr⁻¹), per channel.
    pub(crate) f: V3,
    /// The picked light's probability.
    pub(crate) pmf: Vec4,
    /// The light's kind ([`LightLane::kind`]) and the fields of [`LightLane`] of that name.
    pub(crate) kind: Vec4,
    pub(crate) tri: [V3; 4],
    pub(crate) ux: Vec4,
    pub(crate) uy: Vec4,
    pub(crate) radiance: V3,
    pub(crate) area: Vec4,
    pub(crate) two_sided: Vec4,
    /// Scene time of the vertex (frames).
    pub(crate) time: Vec4,
}

/// [`LightLane::kind`] of a triangle area light.
const AREA: f32 = 0.0;
/// [`LightLane::kind`] of a point light.
const POINT: f32 = 1.0;
/// [`LightLane::kind`] of a directional light.
const DISTANT: f32 = 2.0;

/// The light a next-event estimate picked, as a lane of the kernel holds it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LightLane {
    /// The picked light's probability.
    pub(crate) pmf: f32,
    /// 0: a triangle of an area light; 1: a point light; 2: a directional light.
    pub(crate) kind: f32,
    /// An area light's triangle: vertices and unit normal. A point light's position, or the
    /// unit direction toward a directional light, in the first.
    pub(crate) tri: [Vec3A; 4],
    /// The point of the square the triangle warp maps (area lights).
    pub(crate) ux: f32,
    pub(crate) uy: f32,
    /// An area light's radiance (W/m²/sr), a point light's intensity (W/sr) or a directional
    /// light's irradiance (W/m²), RGB.
    pub(crate) radiance: [f32; 3],
    /// An area light's total area (m²) and sidedness (1 for two-sided); 1 and 0 for the others.
    pub(crate) area: f32,
    pub(crate) two_sided: f32,
}

/// The light next-event estimation picks with the numbers `u_light`, `u` (those
/// [`super::direct::sample_direct`] draws), when the kernel covers it: a triangle of an area
/// light, a point light or a directional light. `None` for the others (spot lights, lights
/// of other shapes, environments), and where the scene has no light.
#[inline(always)]
pub(crate) fn light_lane(scene: &Scene, u_light: f32, u: Vec2) -> Option<LightLane> {
    let dist = scene.light_distribution.as_ref()?;
    let (li, pmf, _) = dist.sample(u_light);
    let unit = |kind: f32, at: Vec3, c: [f32; 3]| LightLane {
        pmf,
        kind,
        tri: [Vec3A::from(at), Vec3A::ZERO, Vec3A::ZERO, Vec3A::ZERO],
        ux: 0.0,
        uy: 0.0,
        radiance: c,
        area: 1.0,
        two_sided: 0.0,
    };
    match scene.lights.get(li)? {
        Light::Area(light) => {
            let (tri, w) = light.triangle_sample(u)?;
            Some(LightLane {
                pmf,
                kind: AREA,
                tri: *tri,
                ux: w.x,
                uy: w.y,
                radiance: light.radiance.c,
                area: light.area(),
                two_sided: light.two_sided as u8 as f32,
            })
        }
        // `PointLight::sample_li` and `DirectionalLight::sample_li` (toward the light: minus
        // the direction it shines in).
        Light::Point(light) => Some(unit(POINT, light.position, light.intensity.c)),
        Light::Directional(light) => Some(unit(DISTANT, -light.direction, light.irradiance.c)),
        _ => None,
    }
}

/// True if the kernel computes next-event estimates toward `light` ([`light_lane`]).
pub(crate) fn kernel_covers(light: &Light) -> bool {
    match light {
        Light::Area(a) => matches!(a.shape, AreaShape::Triangles(_)),
        Light::Point(_) | Light::Directional(_) => true,
        _ => false,
    }
}

/// Lane `k` of `v`, by its address: glam's `Index` matches on the lane, a jump through a
/// table that a varying `k` mispredicts.
#[inline(always)]
pub(crate) fn get(v: Vec4, k: usize) -> f32 {
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
pub(crate) struct V3 {
    pub(crate) x: Vec4,
    pub(crate) y: Vec4,
    pub(crate) z: Vec4,
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
    pub(crate) fn lane(&self, l: usize) -> Vec3 {
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
    /// `a` in the lanes of `m`, else `b`.
    #[inline(always)]
    fn select(m: BVec4A, a: V3, b: V3) -> V3 {
        V3 {
            x: Vec4::select(m, a.x, b.x),
            y: Vec4::select(m, a.y, b.y),
            z: Vec4::select(m, a.z, b.z),
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
pub(crate) struct Estimates {
    pub(crate) c: V3,
    pub(crate) o: V3,
    pub(crate) dir: V3,
    pub(crate) t_max: Vec4,
    pub(crate) ray: u32,
}

/// Next-event estimation in the four lanes of `r`: where every lane holds an area light's
/// triangle (the commonest case), without the selects the delta lights need.
#[inline(never)]
pub(crate) fn estimate(r: &Lanes) -> Estimates {
    if r.kind.cmpeq(Vec4::splat(AREA)).all() {
        estimate_kinds::<false>(r)
    } else {
        estimate_kinds::<true>(r)
    }
}

/// [`estimate`] for lanes that may hold delta lights (`DELTA`) or hold only area lights.
#[inline(always)]
fn estimate_kinds<const DELTA: bool>(r: &Lanes) -> Estimates {
    let zero = Vec4::ZERO;
    let Lanes {
        p, ng, s, t, n, wo, ..
    } = *r;
    let [p0, p1, p2, ln] = r.tri;
    let (ux, uy) = (r.ux, r.uy);
    let area = r.kind.cmpeq(Vec4::splat(AREA));
    let point = r.kind.cmpeq(Vec4::splat(POINT));
    let distant = r.kind.cmpeq(Vec4::splat(DISTANT));
    // `b` in the lanes of `m` (a mask of delta lights' lanes, which only `DELTA` has), `a` in
    // the others.
    let by_kind = |a: V3, b: V3, m: BVec4A| if DELTA { V3::select(m, b, a) } else { a };

    // `warp::square_to_uniform_triangle`: s/2 and l − s/2 for the smaller and larger coordinate.
    let lt = ux.cmplt(uy);
    let (small, large) = (Vec4::select(lt, ux, uy), Vec4::select(lt, uy, ux));
    let h = small / 2.0;
    let m = large - h;
    let (b0, b1) = (Vec4::select(lt, h, m), Vec4::select(lt, m, h));
    let (bx, by) = (b1, Vec4::ONE - b0 - b1);
    // `AreaLight::sample_area`: p0 (1 − b1 − b2) + p1 b1 + p2 b2.
    let on_triangle = p0
        .scale(Vec4::ONE - bx - by)
        .add(p1.scale(bx))
        .add(p2.scale(by));
    // The light's point: on the triangle, or a point light's position (a directional light's
    // lanes compute it but use only `wi`).
    let lp = by_kind(on_triangle, p0, !area);
    // `AreaLight::sample_li`; `PointLight::sample_li`'s `toward` the same way; a directional
    // light's `wi` is the direction toward it.
    let d = lp.sub(p);
    let d2 = d.dot(d);
    let dist = d2.sqrt();
    let wi = by_kind(d.div(dist), p0, distant);
    let cos = ln.dot(wi).abs();
    // `AreaLight::emits(n, −wi)`.
    let c_emit = ln.x * -wi.x + ln.y * -wi.y + ln.z * -wi.z;
    let two_sided = r.two_sided.cmpne(zero);
    let emits = (two_sided & c_emit.cmpne(zero)) | (!two_sided & c_emit.cmpgt(zero));
    let pdf = d2 / (cos * r.area);
    let inf = Vec4::splat(f32::INFINITY);
    let ok_area = d2.cmpgt(zero) & cos.cmpgt(zero) & emits & pdf.cmpgt(zero) & pdf.cmplt(inf);
    // `toward`: `d2 > 0` and finite. A directional light always gives its sample.
    let ok_point = d2.cmpgt(zero) & d2.cmplt(inf);
    let mut ok = if DELTA {
        (area & ok_area) | (point & ok_point) | distant
    } else {
        ok_area
    };
    // `Spectrum / f32` multiplies by the reciprocal: radiance / pdf, intensity / d² (the
    // delta lights' pdf is 1); a directional light's irradiance as it is (times 1/1).
    let denominator = if DELTA {
        Vec4::select(area, pdf, Vec4::select(point, d2, Vec4::ONE))
    } else {
        pdf
    };
    let weight = r.radiance.scale(Vec4::ONE / denominator);
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
    // `power_heuristic` against the Lambertian BSDF's density; 1 for delta lights.
    let bsdf_pdf = Vec4::select(front, wi_up * INV_PI, zero);
    let a = r.pmf * pdf;
    let (a2, b2) = (a * a, bsdf_pdf * bsdf_pdf);
    let mis = Vec4::select(
        a2.cmpeq(zero) & b2.cmpeq(zero),
        zero,
        Vec4::select(a2.cmpeq(inf), Vec4::ONE, a2 / (a2 + b2)),
    );
    let mis = if DELTA {
        Vec4::select(area, mis, Vec4::ONE)
    } else {
        mis
    };
    // f · tr · Le · (mis / pmf) with tr = 1: `f * 1` is `f`.
    let c = f.mul(weight).scale(mis / r.pmf).keep(ok);
    // `SurfaceInteraction::spawn_ray_to(lp)`; `spawn_ray(wi)` toward a directional light.
    let side = Vec4::select(
        by_kind(d, wi, distant).dot(ng).cmpge(zero),
        Vec4::ONE,
        -Vec4::ONE,
    );
    let offset = Vec4::splat(1e-4) * (Vec4::ONE + p.x.abs().max(p.y.abs()).max(p.z.abs()));
    let o = p.add(ng.scale(side * offset));
    let to = lp.sub(o);
    let len = to.dot(to).sqrt();
    Estimates {
        c,
        o,
        dir: by_kind(to.div(len), wi, distant),
        t_max: if DELTA {
            Vec4::select(distant, inf, len * (1.0 - 1e-4))
        } else {
            len * (1.0 - 1e-4)
        },
        ray: ok.bitmask(),
    }
}

/// A term a path holds after its first waiting estimate: a value, or (`slot` not [`PLAIN`]) the
/// throughput by which the estimate of that slot is multiplied.
#[derive(Clone, Copy)]
struct Term {
    value: Spectrum,
    slot: u32,
}

/// The slot of a [`Term`] that is a value.
const PLAIN: u32 = u32::MAX;

/// Paths whose next-event estimates share the lanes. The estimates of consecutive paths fill
/// them (a Cornell-box path has 3.15 on average, a lane call takes four), and the radiance of a
/// path that left one waiting is known at [`Self::finish`]. The pixel driver keeps one per row
/// and finishes it every few dozen waiting paths and at the row's end; the film's sums do not
/// depend on the order the samples arrive in.
///
/// Each path's terms are added in the order the path found them, the scalar code's `l += term`,
/// so its radiance is bit for bit what it would be without the lanes.
#[derive(Default)]
pub struct DirectBatch<'a> {
    /// The scene of the waiting estimates (their shadow rays).
    scene: Option<&'a Scene>,
    /// False: nothing waits, every estimate is computed at once ([`Self::one_by_one`]).
    off: bool,
    lanes: Lanes,
    /// Lanes filled: lane `k` holds the estimate of slot `est.len() − count + k`.
    count: usize,
    /// Each waiting estimate (W/m²/sr, before the path's throughput), once computed.
    est: Vec<Spectrum>,
    /// The terms of the waiting paths after their first waiting estimate.
    terms: Vec<Term>,
    /// Each waiting path: the sum of its terms before its first waiting estimate, and its run
    /// of `terms`.
    paths: Vec<(Spectrum, u32, u32)>,
    /// Shadow rays traced since the last [`Self::finish`].
    rays: u64,
}

impl<'a> DirectBatch<'a> {
    /// A batch that holds nothing back: its paths compute every estimate where they find it and
    /// their [`PathSum::total`] is always known (for callers that need a radiance at once).
    pub fn one_by_one() -> Self {
        Self {
            off: true,
            ..Self::default()
        }
    }

    /// The sum of a new path's terms. A batch serves one scene: the last path's.
    #[inline]
    pub fn path(&mut self, scene: &'a Scene) -> PathSum<'_, 'a> {
        self.scene = Some(scene);
        let start = self.terms.len() as u32;
        PathSum {
            scene,
            batch: self,
            sum: Spectrum::ZERO,
            waiting: false,
            start,
        }
    }

    /// Paths waiting for [`Self::finish`].
    pub fn waiting(&self) -> usize {
        self.paths.len()
    }

    /// Computes the estimates in the lanes and traces their shadow rays.
    fn compute(&mut self, scene: &Scene) {
        let e = estimate(&self.lanes);
        let base = self.est.len() - self.count;
        // The lanes that wait and need a shadow ray (the others hold stale inputs).
        let mut rays = e.ray & ((1 << self.count) - 1);
        while rays != 0 {
            let k = rays.trailing_zeros() as usize & (LANES - 1);
            rays &= rays - 1;
            self.rays += 1;
            let ray = Ray::with_t_max(e.o.lane(k), e.dir.lane(k), get(e.t_max, k))
                .at_time(get(self.lanes.time, k));
            if !scene.occluded(&ray) {
                let c = e.c.lane(k);
                self.est[base + k] = Spectrum::new(c.x, c.y, c.z);
            }
        }
        self.count = 0;
    }

    /// Computes what waits and gives `deliver(i, radiance)` (W/m²/sr) for the `i`-th waiting
    /// path (in the order their [`PathSum::total`] returned `None`); the shadow rays traced are
    /// counted in `stats`. The batch is then empty. Out of line: it runs once per few dozen paths.
    #[inline(never)]
    pub fn finish(&mut self, stats: &mut RenderStats, mut deliver: impl FnMut(usize, Spectrum)) {
        if self.count > 0
            && let Some(scene) = self.scene
        {
            self.compute(scene);
        }
        for (i, &(mut sum, start, end)) in self.paths.iter().enumerate() {
            for t in &self.terms[start as usize..end as usize] {
                if t.slot == PLAIN {
                    sum += t.value;
                } else {
                    sum += t.value * self.est[t.slot as usize];
                }
            }
            deliver(i, sum);
        }
        self.est.clear();
        self.terms.clear();
        self.paths.clear();
        stats.rays += std::mem::take(&mut self.rays);
    }
}

/// A path's radiance (W/m²/sr) as the sum of its terms in the order the path finds them, with
/// next-event estimates waiting for the lanes of its [`DirectBatch`]: the terms after the first
/// waiting estimate are held until it is computed, then added in order, so the sum is bit for
/// bit `l += term`'s.
pub struct PathSum<'b, 'a> {
    scene: &'a Scene,
    batch: &'b mut DirectBatch<'a>,
    /// The terms before the first waiting estimate, summed.
    sum: Spectrum,
    /// True once an estimate waits: terms go to the batch.
    waiting: bool,
    /// The path's first term in the batch's terms.
    start: u32,
}

impl<'b, 'a> PathSum<'b, 'a> {
    /// Adds `term`.
    #[inline]
    pub fn add(&mut self, term: Spectrum) {
        if self.waiting {
            self.batch.terms.push(Term {
                value: term,
                slot: PLAIN,
            });
        } else {
            self.sum += term;
        }
    }

    /// Adds `beta` times next-event estimation at `v` with the numbers `u_light`, `u` (those
    /// [`super::direct::sample_direct`] draws), to be computed in the lanes; false, adding
    /// nothing, when the lanes do not cover it (a scene with media, whose shadow rays draw
    /// numbers of their own; not a Lambertian surface; not RGB; a light [`light_lane`] does
    /// not cover) or the batch computes one by one. Inlined into the path loop: out of line it cost 1 % more
    /// instructions on the Cornell box.
    #[inline(always)]
    pub fn defer_direct(&mut self, beta: Spectrum, v: &Vertex, u_light: f32, u: Vec2) -> bool {
        if self.scene.has_media || self.batch.off {
            return false;
        }
        let Bsdf::Lambertian(lambertian) = &v.bsdf else {
            return false;
        };
        if v.channels != Channels::Rgb {
            return false;
        }
        let Some(light) = light_lane(self.scene, u_light, u) else {
            return false;
        };
        let b = &mut *self.batch;
        let (k, r) = (b.count, &mut b.lanes);
        let v3 = |v: Vec3| v.to_array();
        r.p.set(k, v3(v.si.p));
        r.ng.set(k, v3(v.si.ng));
        r.s.set(k, v3(v.frame.s));
        r.t.set(k, v3(v.frame.t));
        r.n.set(k, v3(v.frame.n));
        r.wo.set(k, v3(v.wo));
        // `Lambertian::eval`'s value.
        r.f.set(k, (lambertian.albedo * INV_PI).c);
        set(&mut r.pmf, k, light.pmf);
        set(&mut r.kind, k, light.kind);
        for (lane, corner) in r.tri.iter_mut().zip(light.tri) {
            lane.set(k, corner.to_array());
        }
        set(&mut r.ux, k, light.ux);
        set(&mut r.uy, k, light.uy);
        r.radiance.set(k, light.radiance);
        set(&mut r.area, k, light.area);
        set(&mut r.two_sided, k, light.two_sided);
        set(&mut r.time, k, v.si.time);
        b.terms.push(Term {
            value: beta,
            slot: b.est.len() as u32,
        });
        b.est.push(Spectrum::ZERO);
        b.count += 1;
        self.waiting = true;
        if b.count == LANES {
            b.compute(self.scene);
        }
        true
    }

    /// The path's radiance, or `None` when an estimate waits: the batch's
    /// [`DirectBatch::finish`] gives it then.
    pub fn total(self) -> Option<Spectrum> {
        if !self.waiting {
            return Some(self.sum);
        }
        let end = self.batch.terms.len() as u32;
        self.batch.paths.push((self.sum, self.start, end));
        None
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
    use caustica_scene::light::{DirectionalLight, PointLight, SpotLight};

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

    /// Paths of zero to seven estimates with up to seven terms before each and after the last,
    /// sharing a batch finished after every one to nine paths: each path's radiance equals
    /// `l += term` with the scalar estimates, bit for bit, for one- and two-sided area lights
    /// and for point and directional lights mixed with them in the lanes, and arrives for the
    /// right path.
    #[test]
    fn lanes_give_the_scalar_estimates_and_sum_bit_for_bit() {
        let mut scene = builtin_scene("cornell-box").unwrap().build().unwrap();
        let mut rng = Pcg32::new(9, 4);
        let mut sampler = Sampler::new(SamplerKind::Independent, 1);
        let (mut lit, mut deferred, mut rays, mut paths, mut waited) = (0, 0, 0, 0, 0);
        // The box with a point, a directional and a spot light beside its own: the kernel's
        // lanes mix the three kinds it computes, and the spot light's estimates stay scalar.
        let mut builder = builtin_scene("cornell-box").unwrap();
        builder.add_light(Light::Point(PointLight::new(
            Vec3::new(0.3, 0.5, 0.2),
            Spectrum::new(0.4, 0.3, 0.2),
        )));
        builder.add_light(Light::Directional(DirectionalLight::new(
            Vec3::new(0.3, -0.6, -1.0),
            Spectrum::new(0.5, 0.6, 0.7),
        )));
        builder.add_light(Light::Spot(SpotLight::new(
            Vec3::new(0.0, 0.6, 0.0),
            Vec3::new(0.1, -1.0, 0.2),
            Spectrum::new(0.8, 0.8, 0.5),
            40.0,
            25.0,
        )));
        let mixed = builder.build().unwrap();
        let (mut mixed_deferred, mut mixed_lit, mut mixed_scalar) = (0, 0, 0);
        for case in 0..3 {
            if let Some(Light::Area(light)) = scene.lights.first_mut() {
                light.two_sided = case == 1;
            }
            let scene = if case < 2 { &scene } else { &mixed };
            let verts = vertices(scene, 3000, &mut rng);
            let mut batch = DirectBatch::default();
            // The scalar sums of the paths waiting in `batch`, and the shadow rays they traced.
            let (mut want, mut scalar_rays) = (Vec::new(), 0);
            let mut finish_after = 1;
            let mut verts = verts.iter();
            loop {
                let n = rng.next_u32() as usize % 8;
                let path: Vec<&Vertex> = verts.by_ref().take(n).collect();
                if path.len() < n {
                    break;
                }
                paths += 1;
                let mut l = Spectrum::ZERO;
                let mut lanes = batch.path(scene);
                let terms = |l: &mut Spectrum, lanes: &mut PathSum, rng: &mut Pcg32| {
                    for _ in 0..(rng.next_u32() % 8) {
                        let term = Spectrum::new(rng.next_f32(), rng.next_f32(), 0.0);
                        *l += term;
                        lanes.add(term);
                    }
                };
                for v in path {
                    terms(&mut l, &mut lanes, &mut rng);
                    let beta = Spectrum::new(rng.next_f32(), 1.0, rng.next_f32() * 4.0);
                    let (u_light, u) = (rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32()));
                    let at = Scatterer::Surface { v, medium: NONE };
                    let mut st = RenderStats::default();
                    let e = direct_with(scene, at, u_light, u, &mut sampler, &mut st, true);
                    l += beta * e;
                    lit += !e.is_black() as u32;
                    let lanes_took = lanes.defer_direct(beta, v, u_light, u);
                    if lanes_took {
                        deferred += 1;
                        // The batch traces the rays of the estimates it took.
                        scalar_rays += st.rays;
                    } else {
                        lanes.add(beta * e);
                    }
                    if case == 2 {
                        mixed_deferred += lanes_took as u32;
                        mixed_scalar += !lanes_took as u32;
                        mixed_lit += (lanes_took && !e.is_black()) as u32;
                    }
                }
                terms(&mut l, &mut lanes, &mut rng);
                let bits = |s: Spectrum| s.c.map(f32::to_bits);
                match lanes.total() {
                    Some(got) => assert_eq!(bits(got), bits(l), "{got:?} {l:?}"),
                    None => want.push(l),
                }
                if batch.waiting() >= finish_after {
                    let mut stats = RenderStats::default();
                    let mut got = Vec::new();
                    batch.finish(&mut stats, |i, l| got.push((i, l)));
                    assert_eq!(got.len(), want.len());
                    for ((i, got), (j, l)) in got.into_iter().zip(want.iter().enumerate()) {
                        assert_eq!((i, bits(got)), (j, bits(*l)), "{got:?} {l:?}");
                    }
                    assert_eq!(stats.rays, scalar_rays, "shadow rays");
                    assert_eq!(batch.waiting(), 0);
                    waited += want.len();
                    rays += scalar_rays;
                    (want, scalar_rays) = (Vec::new(), 0);
                    finish_after = 1 + rng.next_u32() as usize % 9;
                }
            }
        }
        // In a scene with media the shadow rays draw numbers of their own, and a batch that
        // computes one by one holds nothing back: nothing waits.
        let fog = builtin_scene("fog-box").unwrap().build().unwrap();
        let mut batch = DirectBatch::default();
        let mut l = batch.path(&fog);
        for v in &vertices(&fog, 50, &mut rng) {
            assert!(!l.defer_direct(Spectrum::ONE, v, 0.5, Vec2::splat(0.5)));
        }
        let mut one_by_one = DirectBatch::one_by_one();
        let mut l = one_by_one.path(&scene);
        for v in &vertices(&scene, 50, &mut rng) {
            assert!(!l.defer_direct(Spectrum::ONE, v, 0.5, Vec2::splat(0.5)));
        }
        // With the four lights the kernel took the three kinds it covers (the area light alone
        // gets about a third of the picks), lit most of them, and left the spot light's.
        assert!(
            mixed_deferred > 1500 && mixed_lit > 800 && mixed_scalar > 100,
            "{mixed_deferred} {mixed_lit} {mixed_scalar}"
        );
        // Most vertices are deferred and many lit, most paths wait: the comparison covers the
        // lanes.
        assert!(
            deferred > 5000 && lit > 2500 && rays > 3000 && waited > paths / 2,
            "{deferred} {lit} {rays} {waited} of {paths}"
        );
    }
}
