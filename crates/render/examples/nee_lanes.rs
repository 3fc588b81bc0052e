//! A feasibility measurement for issue 26's deliverable 3 (SIMD across paths): next-event
//! estimation in the Cornell box one vertex at a time, as the path tracer does it
//! (`transport::sample_direct`), against four vertices at a time in SSE lanes (glam's `Vec4`,
//! structure of arrays) with their shadow rays traced as streams of eight
//! (`Geometry::occluded_stream`).
//!
//! The vertices are the first hits of 2¹² camera rays off the light (Lambertian surfaces; few
//! enough to stay in the caches); each gets the three numbers its independent sampler draws for
//! next-event estimation. The lane
//! kernel is written for this scene only: one light, a quad (two triangles, one-sided),
//! Lambertian BSDFs, RGB, no media. It repeats the scalar code's arithmetic in the same order,
//! and its contributions must equal the scalar ones bit for bit (the example stops otherwise).
//! Prints nanoseconds per vertex, the best of `reps` passes of 16 rounds:
//! - scalar next-event estimation with its shadow ray, less the sampler's start and draws;
//! - the vertices gathered into lanes and the lane kernel, alone and with the shadow rays and
//!   the final products.
//!
//! ```text
//! cargo run --release -p caustica-render --example nee_lanes -- [reps]
//! ```

use caustica_core::sampling::{Distribution1D, Pcg32, Sampler, SamplerKind};
use caustica_core::{INV_PI, Ray, Spectrum, Vec2, Vec3};
use caustica_loader::builtin_scene;
use caustica_render::RenderStats;
use caustica_render::transport::{Vertex, sample_direct};
use caustica_scene::bsdf::TransportMode;
use caustica_scene::intersection::NONE;
use caustica_scene::light::{AreaShape, Light};
use glam::{BVec4A, Vec4};
use std::time::Instant;

/// Passes over the vertices per timing (they fit the caches: 2¹² vertices).
const ROUNDS: usize = 16;

/// Three coordinates of four lanes.
#[derive(Clone, Copy)]
struct V3 {
    x: Vec4,
    y: Vec4,
    z: Vec4,
}

impl V3 {
    fn splat(v: Vec3) -> Self {
        Self {
            x: Vec4::splat(v.x),
            y: Vec4::splat(v.y),
            z: Vec4::splat(v.z),
        }
    }
    fn gather(v: [Vec3; 4]) -> Self {
        Self {
            x: Vec4::new(v[0].x, v[1].x, v[2].x, v[3].x),
            y: Vec4::new(v[0].y, v[1].y, v[2].y, v[3].y),
            z: Vec4::new(v[0].z, v[1].z, v[2].z, v[3].z),
        }
    }
    fn lane(&self, l: usize) -> Vec3 {
        Vec3::new(self.x[l], self.y[l], self.z[l])
    }
    fn dot(self, o: V3) -> Vec4 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    fn sub(self, o: V3) -> V3 {
        V3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
    fn add(self, o: V3) -> V3 {
        V3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
    fn scale(self, s: Vec4) -> V3 {
        V3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
    fn div(self, s: Vec4) -> V3 {
        V3 {
            x: self.x / s,
            y: self.y / s,
            z: self.z / s,
        }
    }
    fn select(m: BVec4A, a: V3, b: V3) -> V3 {
        V3 {
            x: Vec4::select(m, a.x, b.x),
            y: Vec4::select(m, a.y, b.y),
            z: Vec4::select(m, a.z, b.z),
        }
    }
}

/// What the kernel reads of a vertex, gathered four at a time.
struct Lanes {
    p: V3,
    ng: V3,
    s: V3,
    t: V3,
    n: V3,
    wo: V3,
    /// Albedo / π (the Lambertian BSDF's value), per channel.
    f: V3,
    u_light: Vec4,
    u: [Vec4; 2],
}

/// The scene's one quad light.
struct Quad {
    cdf: [f32; 3],
    pmf: [f32; 2],
    tri: [[Vec3; 4]; 2],
    area: f32,
    radiance: Vec3,
    light_pmf: f32,
    light_cdf0: f32,
}

/// The contributions (before the shadow test) and shadow rays of four vertices.
fn kernel(q: &Quad, v: &Lanes) -> (V3, [Option<Ray>; 4]) {
    let zero = Vec4::ZERO;
    let one_minus_eps = Vec4::splat(1.0 - f32::EPSILON / 2.0);
    // The light: the one-entry table's remapped number is not used; its pmf is.
    let _ = ((v.u_light - Vec4::splat(q.light_cdf0)) / Vec4::splat(q.light_pmf))
        .clamp(zero, one_minus_eps);
    // The triangle: the two-entry table's count of cdf entries below u.
    let ux = v.u[0];
    let below = |c: f32| Vec4::splat(c).cmple(ux);
    let (b0, b1, b2) = (below(q.cdf[0]), below(q.cdf[1]), below(q.cdf[2]));
    // below >= 2 with three sorted entries: the second is below (then the first is too).
    let second = b1 & b0 | b1 & b2 | b0 & b2;
    let pk = Vec4::select(second, Vec4::splat(q.pmf[1]), Vec4::splat(q.pmf[0]));
    let ck = Vec4::select(second, Vec4::splat(q.cdf[1]), Vec4::splat(q.cdf[0]));
    let ux = ((ux - ck) / pk).clamp(zero, one_minus_eps);
    let tri = |k: usize| V3::select(second, V3::splat(q.tri[1][k]), V3::splat(q.tri[0][k]));
    let (p0, p1, p2, ln) = (tri(0), tri(1), tri(2), tri(3));
    // Heitz's triangle map.
    let uy = v.u[1];
    let lt = ux.cmplt(uy);
    let (s, l) = (Vec4::select(lt, ux, uy), Vec4::select(lt, uy, ux));
    let h = s / 2.0;
    let m = l - h;
    let (bb0, bb1) = (Vec4::select(lt, h, m), Vec4::select(lt, m, h));
    let (bx, by) = (bb1, Vec4::ONE - bb0 - bb1);
    let lp = p0
        .scale(Vec4::ONE - bx - by)
        .add(p1.scale(bx))
        .add(p2.scale(by));
    // Toward the light.
    let d = lp.sub(v.p);
    let d2 = d.dot(d);
    let dist = d2.sqrt();
    let wi = d.div(dist);
    let cos = ln.dot(wi).abs();
    let emits = ln.x * -wi.x + ln.y * -wi.y + ln.z * -wi.z;
    let pdf = d2 / (cos * Vec4::splat(q.area));
    let mut ok = d2.cmpgt(zero) & cos.cmpgt(zero) & emits.cmpgt(zero) & pdf.cmpgt(zero);
    ok &= pdf.cmplt(Vec4::splat(f32::INFINITY));
    // The BSDF in the shading frame.
    let wl = V3 {
        x: wi.dot(v.s),
        y: wi.dot(v.t),
        z: wi.dot(v.n),
    };
    let flip = v.wo.z.cmplt(zero);
    let (woz, wiz) = (
        Vec4::select(flip, -v.wo.z, v.wo.z),
        Vec4::select(flip, -wl.z, wl.z),
    );
    ok &= woz.cmpgt(zero) & wiz.cmpgt(zero);
    let wo_world =
        v.s.scale(v.wo.x)
            .add(v.t.scale(v.wo.y))
            .add(v.n.scale(v.wo.z));
    let geo = (wo_world.dot(v.ng) * wi.dot(v.ng)).cmpgt(zero);
    let shade = (v.wo.z * wl.z).cmpgt(zero);
    ok &= !(geo ^ shade);
    let cosi = wl.z.abs();
    let f = v.f.scale(cosi);
    // MIS against the cosine-weighted BSDF sample, power heuristic.
    let a = Vec4::splat(q.light_pmf) * pdf;
    let bpdf = wiz * INV_PI;
    let (a2, b2) = (a * a, bpdf * bpdf);
    let mis = a2 / (a2 + b2);
    // `Spectrum / f32` multiplies by the reciprocal.
    let weight = V3::splat(q.radiance).scale(Vec4::ONE / pdf);
    let c = V3 {
        x: f.x * weight.x,
        y: f.y * weight.y,
        z: f.z * weight.z,
    }
    .scale(mis / Vec4::splat(q.light_pmf));
    let c = V3::select(ok, c, V3::splat(Vec3::ZERO));
    // Shadow rays off the surface toward the light point.
    let side = Vec4::select(d.dot(v.ng).cmpge(zero), Vec4::ONE, -Vec4::ONE);
    let ax = v.p.x.abs().max(v.p.y.abs()).max(v.p.z.abs());
    let off = Vec4::splat(1e-4) * (Vec4::ONE + ax);
    let o = v.p.add(v.ng.scale(side * off));
    let to = lp.sub(o);
    let tl = to.dot(to).sqrt();
    let dir = to.div(tl);
    let t_max = tl * (1.0 - 1e-4);
    let okm = ok.bitmask();
    let rays = std::array::from_fn(|l| {
        (okm & (1 << l) != 0).then(|| Ray::with_t_max(o.lane(l), dir.lane(l), t_max[l]))
    });
    (c, rays)
}

fn main() {
    let scene = builtin_scene("cornell-box")
        .expect("the built-in Cornell box")
        .build()
        .expect("the built-in Cornell box builds");
    let reps: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(7);
    let Some(Light::Area(light)) = scene.lights.first() else {
        panic!("the Cornell box has one area light")
    };
    let AreaShape::Triangles(tris) = &light.shape else {
        panic!("a quad light")
    };
    let areas: Vec<f32> = tris
        .iter()
        .map(|t| 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length())
        .collect();
    let tri_dist = Distribution1D::new(&areas).expect("two triangles");
    let dist = scene.light_distribution.as_ref().expect("a light");
    let tri_cdf = tri_dist.cdf();
    let quad = Quad {
        cdf: [tri_cdf[0], tri_cdf[1], tri_cdf[2]],
        pmf: [tri_dist.pmf(0), tri_dist.pmf(1)],
        tri: [0, 1].map(|k| {
            let t = tris[k];
            [
                t[0],
                t[1],
                t[2],
                (t[1] - t[0]).cross(t[2] - t[0]).normalize_or_zero(),
            ]
        }),
        area: light.area(),
        radiance: Vec3::new(light.radiance[0], light.radiance[1], light.radiance[2]),
        light_pmf: dist.pmf(0),
        light_cdf0: dist.cdf()[0],
    };
    // Vertices: first hits of camera rays, off the light.
    let mut rng = Pcg32::new(7, 3);
    let n = 1 << 12;
    let mut verts: Vec<Vertex> = Vec::with_capacity(n);
    while verts.len() < n {
        let raster = Vec2::new(rng.next_f32() * 256.0, rng.next_f32() * 256.0);
        let ray = scene.camera.generate_ray(raster, Vec2::ZERO).ray;
        if let Some(si) = scene.geometry.intersect(&ray)
            && si.light == NONE
        {
            verts.push(Vertex::rgb(&scene, si, &ray));
        }
    }
    let mut sampler = Sampler::new(SamplerKind::Independent, 1);
    let numbers: Vec<[f32; 3]> = (0..n)
        .map(|i| {
            sampler.start_pixel_sample(i as u32, 0, 0);
            [sampler.next_1d(), sampler.next_1d(), sampler.next_1d()]
        })
        .collect();
    // The Lambertian BSDFs' value (albedo / π), read once: a wide shader would read it from the
    // BSDF where this example can only evaluate it.
    let albedo: Vec<Vec3> = verts
        .iter()
        .map(|v| {
            let up = Vec3::new(v.wo.x, v.wo.y, v.wo.z.abs());
            let f = v.bsdf.eval(up, Vec3::Z, TransportMode::Radiance);
            Vec3::new(f[0], f[1], f[2])
        })
        .collect();
    // Four vertices into lanes (structure of arrays): part of the lanes' timing.
    let gather = |k: usize| {
        let (v, u, f) = (&verts[4 * k..], &numbers[4 * k..], &albedo[4 * k..]);
        let g = |get: &dyn Fn(&Vertex) -> Vec3| V3::gather(std::array::from_fn(|l| get(&v[l])));
        Lanes {
            p: g(&|v| v.si.p),
            ng: g(&|v| v.si.ng),
            s: g(&|v| v.frame.s),
            t: g(&|v| v.frame.t),
            n: g(&|v| v.frame.n),
            wo: g(&|v| v.wo),
            f: V3::gather([f[0], f[1], f[2], f[3]]),
            u_light: Vec4::from_array(std::array::from_fn(|l| u[l][0])),
            u: [1, 2].map(|k| Vec4::from_array(std::array::from_fn(|l| u[l][k]))),
        }
    };

    // Scalar, as the path tracer: the sampler's start and draws are timed apart and taken off.
    let scalar = |out: &mut Vec<Spectrum>| {
        out.clear();
        let mut stats = RenderStats::default();
        for (i, v) in verts.iter().enumerate() {
            let mut s = Sampler::new(SamplerKind::Independent, 1);
            s.start_pixel_sample(i as u32, 0, 0);
            out.push(sample_direct(&scene, v, NONE, &mut s, &mut stats, true));
        }
    };
    let draws_only = || {
        let mut acc = 0.0;
        for i in 0..n {
            let mut s = Sampler::new(SamplerKind::Independent, 1);
            s.start_pixel_sample(i as u32, 0, 0);
            acc += s.next_1d() + s.next_1d() + s.next_1d();
        }
        acc
    };
    let lanes_full = |out: &mut Vec<Spectrum>| {
        out.clear();
        let mut rays: Vec<Ray> = Vec::with_capacity(8);
        let mut slots: Vec<(usize, usize)> = Vec::with_capacity(8);
        let mut blocked = Vec::with_capacity(8);
        for pair in 0..n / 8 {
            let base = out.len();
            rays.clear();
            slots.clear();
            for g in 0..2 {
                let (c, r) = kernel(&quad, &gather(2 * pair + g));
                for (l, r) in r.into_iter().enumerate() {
                    out.push(Spectrum::new(c.x[l], c.y[l], c.z[l]));
                    if let Some(r) = r {
                        rays.push(r);
                        slots.push((g, l));
                    }
                }
            }
            scene.geometry.occluded_stream(&rays, &mut blocked);
            for (&(g, l), &b) in slots.iter().zip(&blocked) {
                if b {
                    out[base + 4 * g + l] = Spectrum::ZERO;
                }
            }
        }
    };
    let kernel_only = || {
        let mut acc = Vec4::ZERO;
        for k in 0..n / 4 {
            let (c, r) = kernel(&quad, &gather(k));
            let t: [f32; 4] =
                std::array::from_fn(|l| r[l].map_or(0.0, |r| r.t_max + r.o.x + r.d.x));
            acc += c.x + c.y + c.z + Vec4::from_array(t);
        }
        acc
    };

    // Agreement.
    let (mut a, mut b) = (Vec::new(), Vec::new());
    scalar(&mut a);
    lanes_full(&mut b);
    let (mut same_bits, mut close, mut lit) = (0, 0, 0);
    for (x, y) in a.iter().zip(&b) {
        let bits = |s: &Spectrum| [s[0].to_bits(), s[1].to_bits(), s[2].to_bits()];
        same_bits += (bits(x) == bits(y)) as usize;
        lit += (!x.is_black()) as usize;
        let ok = (0..3).all(|k| (x[k] - y[k]).abs() <= 1e-5 * x[k].abs().max(1e-20));
        close += ok as usize;
    }
    println!(
        "{n} vertices, {lit} lit: lanes equal to scalar bit for bit in {same_bits}, within 1e-5 in {close}"
    );
    assert_eq!(same_bits, n, "the lanes must repeat the scalar arithmetic");

    let mut best = [f64::MAX; 4];
    let mut out = Vec::with_capacity(n);
    for _ in 0..reps {
        let t = Instant::now();
        for _ in 0..ROUNDS {
            scalar(&mut out);
        }
        best[0] = best[0].min(t.elapsed().as_secs_f64());
        let t = Instant::now();
        for _ in 0..ROUNDS {
            std::hint::black_box(draws_only());
        }
        best[1] = best[1].min(t.elapsed().as_secs_f64());
        let t = Instant::now();
        for _ in 0..ROUNDS {
            std::hint::black_box(kernel_only());
        }
        best[2] = best[2].min(t.elapsed().as_secs_f64());
        let t = Instant::now();
        for _ in 0..ROUNDS {
            lanes_full(&mut out);
        }
        best[3] = best[3].min(t.elapsed().as_secs_f64());
    }
    let ns = |s: f64| s * 1e9 / (n * ROUNDS) as f64;
    println!(
        "scalar next-event estimation with its shadow ray {:.1} ns (sampler start and draws {:.1} ns taken off); \
         four lanes: gather and kernel {:.1} ns, with shadow streams and products {:.1} ns (per vertex, best of {reps})",
        ns(best[0] - best[1]),
        ns(best[1]),
        ns(best[2]),
        ns(best[3])
    );
}
