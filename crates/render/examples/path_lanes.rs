//! Feasibility study for issue 26 (deliverable 3): how fast would the path tracer be if its
//! paths lived in SIMD lanes from the camera ray to the spawned ray, as Mitsuba 3's
//! `llvm_ad_rgb` runs them? (The renderer's version, built after this study and bit for bit
//! the scalar path tracer's estimator, is `caustica_render::integrator::path_lanes`.) A
//! prototype, not the renderer: the Cornell box only (Lambertian
//! surfaces, one area light of triangles, no media, RGB), eight paths side by side in arrays
//! of eight floats that the compiler vectorises, each lane's random numbers from its own PCG
//! state in the lanes, the closest hit, the material's albedo, the light's triangle and the
//! shadow ray per lane through the scene's own queries, everything else (emission with MIS,
//! next-event estimation with MIS, the frame, cosine sampling, roulette, the spawned ray) in
//! the lanes. A lane whose path ends takes the next sample of the image.
//!
//! It prints its wall time and the image's mean radiance for `--spp` samples per pixel on one
//! thread, to set beside `caustica render cornell-box --integrator path --spp N --max-depth 8
//! --sampler independent --threads 1` (the estimator is the same; the random numbers, the
//! shading frame's tangent and the sine and cosine differ, so the images agree in the mean, not
//! in the bits).
//!
//! ```text
//! cargo run --release -p caustica-render --example path_lanes -- [spp]
//! ```

// Loops over the lane number read as the SIMD code they become (one operation, eight lanes).
#![allow(clippy::needless_range_loop)]

use caustica_core::sampling::warp::power_heuristic;
use caustica_core::{Channels, INV_PI, PI, Ray, Vec2, Vec3};
use caustica_loader::builtin_scene;
use caustica_scene::Scene;
use caustica_scene::bsdf::Bsdf;
use caustica_scene::intersection::NONE;
use caustica_scene::light::Light;
use std::time::Instant;

/// Paths side by side.
const W: usize = 8;
type F = [f32; W];
const MAX_DEPTH: u32 = 8;
const RR_DEPTH: u32 = 5;

/// Lane-wise `f(k)` for every lane.
#[inline(always)]
fn lanes(f: impl FnMut(usize) -> f32) -> F {
    std::array::from_fn(f)
}

/// PCG32 in every lane (O'Neill), one state per path.
struct Rng {
    state: [u64; W],
    inc: [u64; W],
}

impl Rng {
    const MULT: u64 = 6_364_136_223_846_793_005;
    /// A uniform number in [0, 1) for every lane.
    #[inline(always)]
    fn next(&mut self) -> F {
        let mut out = [0.0; W];
        for k in 0..W {
            let old = self.state[k];
            self.state[k] = old.wrapping_mul(Self::MULT).wrapping_add(self.inc[k]);
            let x = (((old >> 18) ^ old) >> 27) as u32;
            let r = x.rotate_right((old >> 59) as u32);
            out[k] = (r >> 8) as f32 * (1.0 / 16_777_216.0);
        }
        out
    }
    /// Lane `k` starts the stream of sample `id`.
    fn start(&mut self, k: usize, id: u64) {
        let mut z = id.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        self.inc[k] = (id << 1) | 1;
        self.state[k] = (z ^ (z >> 31)).wrapping_add(self.inc[k]);
    }
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
    fn set(&mut self, k: usize, v: Vec3) {
        (self.x[k], self.y[k], self.z[k]) = (v.x, v.y, v.z);
    }
    #[inline(always)]
    fn get(&self, k: usize) -> Vec3 {
        Vec3::new(self.x[k], self.y[k], self.z[k])
    }
    #[inline(always)]
    fn dot(&self, o: &V) -> F {
        lanes(|k| self.x[k] * o.x[k] + self.y[k] * o.y[k] + self.z[k] * o.z[k])
    }
}

/// The paths in the lanes.
#[derive(Default)]
struct Paths {
    alive: [bool; W],
    pixel: [usize; W],
    depth: [u32; W],
    o: V,
    d: V,
    beta: V,
    l: V,
    prev_pdf: F,
    prev_p: V,
}

fn main() {
    let spp: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(16);
    let scene = builtin_scene("cornell-box")
        .expect("the built-in Cornell box")
        .build()
        .expect("the built-in Cornell box builds");
    let (w, h) = (scene.camera.width as usize, scene.camera.height as usize);
    let start = Instant::now();
    let (film, rays) = render(&scene, w, h, spp);
    let secs = start.elapsed().as_secs_f64();
    let n = (w * h) as f64;
    let mean = film.iter().fold([0.0f64; 3], |m, p| {
        [m[0] + p[0] / n, m[1] + p[1] / n, m[2] + p[2] / n]
    });
    println!(
        "path_lanes: {w}x{h}, {spp} spp, one thread: {secs:.3} s, {:.2} M rays/s, mean radiance [{:.5} {:.5} {:.5}]",
        rays as f64 / secs / 1e6,
        mean[0],
        mean[1],
        mean[2]
    );
}

/// The image (mean radiance per pixel, W/m²/sr) and the rays traced.
fn render(scene: &Scene, w: usize, h: usize, spp: usize) -> (Vec<[f64; 3]>, u64) {
    let mut film = vec![[0.0f64; 3]; w * h];
    let total = w * h * spp;
    let mut next = 0usize;
    let mut rays = 0u64;
    let mut p = Paths::default();
    let mut rng = Rng {
        state: [0; W],
        inc: [1; W],
    };
    let dist = scene.light_distribution.as_ref().expect("a light");
    let inv_spp = 1.0 / spp as f64;
    loop {
        // New samples in the lanes whose paths ended.
        for k in 0..W {
            if p.alive[k] || next >= total {
                continue;
            }
            let (pixel, s) = (next / spp, next % spp);
            next += 1;
            rng.start(k, (pixel * spp + s) as u64);
            let u = rng.next();
            let v = rng.next();
            let raster = Vec2::new((pixel % w) as f32 + u[k], (pixel / w) as f32 + v[k]);
            let ray = scene.camera.generate_ray(raster, Vec2::ZERO).ray;
            p.o.set(k, ray.o);
            p.d.set(k, ray.d);
            p.beta.set(k, Vec3::ONE);
            p.l.set(k, Vec3::ZERO);
            (p.alive[k], p.pixel[k], p.depth[k], p.prev_pdf[k]) = (true, pixel, 0, 0.0);
        }
        if !p.alive.iter().any(|&a| a) {
            break;
        }
        // The closest hits, the albedos and any emission found, lane by lane.
        let (mut pos, mut ng, mut ns, mut albedo) =
            (V::default(), V::default(), V::default(), V::default());
        let (mut le, mut light_pdf) = (V::default(), [0.0f32; W]);
        let mut hit = [false; W];
        for k in 0..W {
            if !p.alive[k] {
                continue;
            }
            rays += 1;
            let ray = Ray::new(p.o.get(k), p.d.get(k));
            let Some(si) = scene.intersect(&ray) else {
                continue;
            };
            hit[k] = true;
            pos.set(k, si.p);
            ng.set(k, si.ng);
            ns.set(k, si.ns);
            let mut ch = Channels::Rgb;
            let Bsdf::Lambertian(lam) = scene.materials[si.material as usize].bsdf(&si, &mut ch)
            else {
                panic!("the prototype knows Lambertian surfaces only");
            };
            albedo.set(k, Vec3::from_array(lam.albedo.c));
            if si.light != NONE {
                let light = &scene.lights[si.light as usize];
                le.set(k, Vec3::from_array(light.le(si.ng, -ray.d).c));
                light_pdf[k] =
                    scene.light_pmf(si.light) * light.pdf_li(p.prev_p.get(k), ray.d, si.p, si.ng);
            }
        }
        // Emission, MIS-weighted against the light sampling of the previous vertex.
        for k in 0..W {
            let (a, b) = (p.prev_pdf[k], light_pdf[k]);
            let wgt = if p.depth[k] == 0 {
                1.0
            } else {
                power_heuristic(a, b)
            };
            p.l.x[k] += p.beta.x[k] * le.x[k] * wgt;
            p.l.y[k] += p.beta.y[k] * le.y[k] * wgt;
            p.l.z[k] += p.beta.z[k] * le.z[k] * wgt;
        }
        // Paths that missed or reached the last vertex end here.
        for k in 0..W {
            if !p.alive[k] {
                continue;
            }
            p.depth[k] += 1;
            if !hit[k] || p.depth[k] >= MAX_DEPTH {
                end(&mut p, k, &mut film, inv_spp);
            }
        }
        // The shading frame (Duff et al. 2017) and the direction back along the ray.
        let sign = lanes(|k| 1.0f32.copysign(ns.z[k]));
        let a = lanes(|k| -1.0 / (sign[k] + ns.z[k]));
        let b = lanes(|k| ns.x[k] * ns.y[k] * a[k]);
        let s = V {
            x: lanes(|k| 1.0 + sign[k] * ns.x[k] * ns.x[k] * a[k]),
            y: lanes(|k| sign[k] * b[k]),
            z: lanes(|k| -sign[k] * ns.x[k]),
        };
        let t = V {
            x: b,
            y: lanes(|k| sign[k] + ns.y[k] * ns.y[k] * a[k]),
            z: lanes(|k| -ns.y[k]),
        };
        let wo_z = lanes(|k| -(p.d.x[k] * ns.x[k] + p.d.y[k] * ns.y[k] + p.d.z[k] * ns.z[k]));
        // Next-event estimation: the light's triangle per lane, the rest in the lanes.
        let u_light = rng.next();
        let (u1, u2) = (rng.next(), rng.next());
        let mut tri = [V::default(), V::default(), V::default(), V::default()];
        let (mut pmf, mut area, mut ux, mut uy) = ([1.0f32; W], [1.0f32; W], [0.0; W], [0.0; W]);
        let mut radiance = V::default();
        for k in 0..W {
            let (li, pm, _) = dist.sample(u_light[k]);
            let Some(Light::Area(light)) = scene.lights.get(li) else {
                panic!("the prototype knows area lights only");
            };
            let Some((t3, wv)) = light.triangle_sample(Vec2::new(u1[k], u2[k])) else {
                continue;
            };
            for (c, v) in tri.iter_mut().zip(t3) {
                c.set(k, Vec3::from(*v));
            }
            (pmf[k], area[k], ux[k], uy[k]) = (pm, light.area(), wv.x, wv.y);
            radiance.set(k, Vec3::from_array(light.radiance.c));
        }
        let lt = lanes(|k| (ux[k] < uy[k]) as u32 as f32);
        let small = lanes(|k| if lt[k] > 0.0 { ux[k] } else { uy[k] });
        let large = lanes(|k| if lt[k] > 0.0 { uy[k] } else { ux[k] });
        let b0 = lanes(|k| {
            let h = small[k] / 2.0;
            if lt[k] > 0.0 { h } else { large[k] - h }
        });
        let b1 = lanes(|k| {
            let h = small[k] / 2.0;
            if lt[k] > 0.0 { large[k] - h } else { h }
        });
        let (bx, by) = (b1, lanes(|k| 1.0 - b0[k] - b1[k]));
        let lp = V {
            x: lanes(|k| {
                tri[0].x[k] * (1.0 - bx[k] - by[k]) + tri[1].x[k] * bx[k] + tri[2].x[k] * by[k]
            }),
            y: lanes(|k| {
                tri[0].y[k] * (1.0 - bx[k] - by[k]) + tri[1].y[k] * bx[k] + tri[2].y[k] * by[k]
            }),
            z: lanes(|k| {
                tri[0].z[k] * (1.0 - bx[k] - by[k]) + tri[1].z[k] * bx[k] + tri[2].z[k] * by[k]
            }),
        };
        let dv = V {
            x: lanes(|k| lp.x[k] - pos.x[k]),
            y: lanes(|k| lp.y[k] - pos.y[k]),
            z: lanes(|k| lp.z[k] - pos.z[k]),
        };
        let d2 = dv.dot(&dv);
        let dist_l = lanes(|k| d2[k].sqrt());
        let wi = V {
            x: lanes(|k| dv.x[k] / dist_l[k]),
            y: lanes(|k| dv.y[k] / dist_l[k]),
            z: lanes(|k| dv.z[k] / dist_l[k]),
        };
        let cos_l =
            lanes(|k| -(tri[3].x[k] * wi.x[k] + tri[3].y[k] * wi.y[k] + tri[3].z[k] * wi.z[k]));
        let cos_s = wi.dot(&ns);
        let same = lanes(|k| ((cos_s[k] * wo_z[k]) > 0.0) as u32 as f32);
        let pdf_l = lanes(|k| pmf[k] * d2[k] / (cos_l[k] * area[k]));
        let f_cos = lanes(|k| cos_s[k].abs() * INV_PI);
        let ok = lanes(|k| {
            (p.alive[k] && cos_l[k] > 0.0 && same[k] > 0.0 && pdf_l[k] > 0.0) as u32 as f32
        });
        let c = lanes(|k| {
            let mis = power_heuristic(pdf_l[k], f_cos[k]);
            if ok[k] > 0.0 {
                f_cos[k] * mis / pdf_l[k]
            } else {
                0.0
            }
        });
        let offset =
            lanes(|k| 1e-4 * (1.0 + pos.x[k].abs().max(pos.y[k].abs()).max(pos.z[k].abs())));
        for k in 0..W {
            if c[k] <= 0.0 {
                continue;
            }
            let (pk, nk) = (pos.get(k), ng.get(k));
            let side = if dv.get(k).dot(nk) >= 0.0 { 1.0 } else { -1.0 };
            let o = pk + nk * (side * offset[k]);
            let to = lp.get(k) - o;
            let len = to.length();
            rays += 1;
            if !scene.occluded(&Ray::with_t_max(o, to / len, len * (1.0 - 1e-4))) {
                let e = albedo.get(k) * radiance.get(k) * c[k];
                p.l.x[k] += p.beta.x[k] * e.x;
                p.l.y[k] += p.beta.y[k] * e.y;
                p.l.z[k] += p.beta.z[k] * e.z;
            }
        }
        // Cosine-weighted sampling (Malley: the concentric disk lifted), in the lanes.
        let (v1, v2, u_rr) = (rng.next(), rng.next(), rng.next());
        let ox = lanes(|k| 2.0 * v1[k] - 1.0);
        let oy = lanes(|k| 2.0 * v2[k] - 1.0);
        let around_x = lanes(|k| (ox[k].abs() > oy[k].abs()) as u32 as f32);
        let r = lanes(|k| if around_x[k] > 0.0 { ox[k] } else { oy[k] });
        let q = lanes(|k| {
            let (num, den) = if around_x[k] > 0.0 {
                (oy[k], ox[k])
            } else {
                (ox[k], oy[k])
            };
            if den == 0.0 {
                0.0
            } else {
                0.25 * PI * num / den
            }
        });
        let z2 = lanes(|k| q[k] * q[k]);
        let sn = lanes(|k| {
            ((-1.951_529_6e-4 * z2[k] + 8.332_161e-3) * z2[k] - 1.666_665_5e-1) * z2[k] * q[k]
                + q[k]
        });
        let cs = lanes(|k| {
            ((2.443_315_7e-5 * z2[k] - 1.388_731_6e-3) * z2[k] + 4.166_664_6e-2) * z2[k] * z2[k]
                - 0.5 * z2[k]
                + 1.0
        });
        let lx = lanes(|k| r[k] * if around_x[k] > 0.0 { cs[k] } else { sn[k] });
        let ly = lanes(|k| r[k] * if around_x[k] > 0.0 { sn[k] } else { cs[k] });
        let lz = lanes(|k| {
            let z = (1.0 - lx[k] * lx[k] - ly[k] * ly[k]).max(0.0).sqrt();
            if wo_z[k] < 0.0 { -z } else { z }
        });
        p.prev_pdf = lanes(|k| lz[k].abs() * INV_PI);
        p.prev_p = pos;
        p.d = V {
            x: lanes(|k| s.x[k] * lx[k] + t.x[k] * ly[k] + ns.x[k] * lz[k]),
            y: lanes(|k| s.y[k] * lx[k] + t.y[k] * ly[k] + ns.y[k] * lz[k]),
            z: lanes(|k| s.z[k] * lx[k] + t.z[k] * ly[k] + ns.z[k] * lz[k]),
        };
        p.beta = V {
            x: lanes(|k| p.beta.x[k] * albedo.x[k]),
            y: lanes(|k| p.beta.y[k] * albedo.y[k]),
            z: lanes(|k| p.beta.z[k] * albedo.z[k]),
        };
        // Russian roulette (Mitsuba's rule), then the spawned rays.
        let qq = lanes(|k| p.beta.x[k].max(p.beta.y[k]).max(p.beta.z[k]).min(0.95));
        let rr = lanes(|k| (p.depth[k] >= RR_DEPTH) as u32 as f32);
        let survive = lanes(|k| (rr[k] == 0.0 || u_rr[k] < qq[k]) as u32 as f32);
        let scale = lanes(|k| if rr[k] > 0.0 { 1.0 / qq[k] } else { 1.0 });
        p.beta = V {
            x: lanes(|k| p.beta.x[k] * scale[k]),
            y: lanes(|k| p.beta.y[k] * scale[k]),
            z: lanes(|k| p.beta.z[k] * scale[k]),
        };
        let side = lanes(|k| {
            if p.d.x[k] * ng.x[k] + p.d.y[k] * ng.y[k] + p.d.z[k] * ng.z[k] >= 0.0 {
                offset[k]
            } else {
                -offset[k]
            }
        });
        p.o = V {
            x: lanes(|k| pos.x[k] + ng.x[k] * side[k]),
            y: lanes(|k| pos.y[k] + ng.y[k] * side[k]),
            z: lanes(|k| pos.z[k] + ng.z[k] * side[k]),
        };
        for k in 0..W {
            if p.alive[k] && survive[k] == 0.0 {
                end(&mut p, k, &mut film, inv_spp);
            }
        }
    }
    (film, rays)
}

/// Ends lane `k`'s path: its radiance to its pixel.
fn end(p: &mut Paths, k: usize, film: &mut [[f64; 3]], inv_spp: f64) {
    let px = &mut film[p.pixel[k]];
    px[0] += p.l.x[k] as f64 * inv_spp;
    px[1] += p.l.y[k] as f64 * inv_spp;
    px[2] += p.l.z[k] as f64 * inv_spp;
    p.alive[k] = false;
}
