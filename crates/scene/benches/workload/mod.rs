//! The BVH benchmark workload, shared by `crates/scene/benches/bvh.rs` (criterion, against
//! obvhs) and `bench/embree` (against Embree 3), so the two can never drift apart: the mesh and
//! every ray set are made here and only here.
//!
//! * [`displaced_sphere`]`(1024, 512)`: 1,046,528 triangles.
//! * [`camera_rays`]`(512, 512)`: coherent pinhole camera rays, row-major.
//! * [`diffuse_bounce_rays`]: one cosine-weighted bounce off every camera ray's hit
//!   (incoherent directions from coherent origins, a path tracer's second segment).
//! * [`incoherent_rays`]: random origins inside the bounds, uniformly random directions.
//! * [`shadow_rays`]: segments between two random points inside the bounds.
//!
//! Each user calls only some of these (the criterion bench has no bounce set), hence the
//! `dead_code` allowance on the module's items.
#![allow(dead_code)]

use caustica_core::sampling::Pcg32;
use caustica_core::sampling::warp::square_to_cosine_hemisphere;
use caustica_core::{Frame, PI, Ray, Vec2, Vec3};
use caustica_scene::geometry::Geometry;
use caustica_scene::shape::{Aabb, TriangleMesh};

/// Seeds of the random ray sets (the values the criterion bench has always used).
pub const INCOHERENT_SEED: u64 = 1;
pub const SHADOW_SEED: u64 = 2;
pub const BOUNCE_SEED: u64 = 3;

/// The tessellation `(NPHI, NTHETA)` of [`displaced_sphere`] given as the program's two
/// arguments, or `default` when there are none (examples that measure the traversal). Exits
/// with `usage` on anything else.
pub fn tessellation_from_args(default: Option<(u32, u32)>, usage: &str) -> (u32, u32) {
    let args: Option<Vec<u32>> = std::env::args().skip(1).map(|a| a.parse().ok()).collect();
    match (args.as_deref(), default) {
        (Some(&[p, t]), _) if p >= 3 && t >= 2 => (p, t),
        (Some([]), Some(d)) => d,
        _ => {
            eprintln!("usage: {usage} (NPHI ≥ 3, NTHETA ≥ 2)");
            std::process::exit(2)
        }
    }
}

/// A sphere displaced by a few sinusoids, tessellated into `2·nphi·(ntheta − 1)` triangles.
pub fn displaced_sphere(nphi: u32, ntheta: u32) -> TriangleMesh {
    let mut m = TriangleMesh::default();
    for j in 0..=ntheta {
        let theta = PI * j as f32 / ntheta as f32;
        for i in 0..nphi {
            let phi = 2.0 * PI * i as f32 / nphi as f32;
            let r = 1.0
                + 0.08 * (7.0 * theta).sin() * (9.0 * phi).cos()
                + 0.03 * (31.0 * theta + 13.0 * phi).sin()
                + 0.01 * (97.0 * theta).sin() * (61.0 * phi).sin();
            m.positions.push(
                r * Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                ),
            );
        }
    }
    let idx = |i: u32, j: u32| j * nphi + i % nphi;
    for j in 0..ntheta {
        for i in 0..nphi {
            let (a, b, c, d) = (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
            if j != 0 {
                m.indices.push([a, c, b]);
            }
            if j != ntheta - 1 {
                m.indices.push([a, d, c]);
            }
        }
    }
    m
}

/// Pinhole camera rays (w×h, row-major: pixel (x, y) is ray `y·w + x`) looking at the mesh
/// from outside.
pub fn camera_rays(w: u32, h: u32) -> Vec<Ray> {
    let eye = Vec3::new(0.3, -3.2, 0.8);
    let fwd = (Vec3::ZERO - eye).normalize();
    let right = fwd.cross(Vec3::Z).normalize();
    let up = right.cross(fwd);
    let tan = (40.0f32.to_radians() * 0.5).tan();
    let mut rays = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let sx = (2.0 * (x as f32 + 0.5) / w as f32 - 1.0) * tan;
            let sy = (1.0 - 2.0 * (y as f32 + 0.5) / h as f32) * tan * h as f32 / w as f32;
            rays.push(Ray::new(eye, (fwd + right * sx + up * sy).normalize()));
        }
    }
    rays
}

fn rand_point(rng: &mut Pcg32, b: &Aabb) -> Vec3 {
    let u = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
    b.min + u * (b.max - b.min)
}

fn rand_dir(rng: &mut Pcg32) -> Vec3 {
    let z = 1.0 - 2.0 * rng.next_f32();
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * rng.next_f32();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Random origins inside the bounds, uniformly random directions.
pub fn incoherent_rays(n: usize, b: &Aabb, seed: u64) -> Vec<Ray> {
    let mut rng = Pcg32::new(seed, 0);
    (0..n)
        .map(|_| Ray::new(rand_point(&mut rng, b), rand_dir(&mut rng)))
        .collect()
}

/// Segments between two random points inside the bounds.
pub fn shadow_rays(n: usize, b: &Aabb, seed: u64) -> Vec<Ray> {
    let mut rng = Pcg32::new(seed, 1);
    (0..n)
        .map(|_| {
            let (p, q) = (rand_point(&mut rng, b), rand_point(&mut rng, b));
            let d = q - p;
            let len = d.length();
            Ray::with_t_max(p, d / len, len)
        })
        .collect()
}

/// Diffuse-bounce rays: `primary` traced with [`Geometry::intersect`]; at each hit, in the
/// order of `primary`, one cosine-weighted direction about the geometric normal on the
/// incoming side (`ng_toward(−d)`), leaving by the hit's own spawn rule
/// ([`SurfaceInteraction::spawn_ray`](caustica_scene::intersection::SurfaceInteraction::spawn_ray):
/// the origin pushed off the surface along ±ng by 1e-4·(1 + max |p|)). Misses emit nothing.
pub fn diffuse_bounce_rays(geo: &Geometry, primary: &[Ray], seed: u64) -> Vec<Ray> {
    let mut rng = Pcg32::new(seed, 2);
    primary
        .iter()
        .filter_map(|r| {
            let si = geo.intersect(r)?;
            let n = si.ng_toward(-r.d);
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let d = Frame::from_normal(n)
                .to_world(square_to_cosine_hemisphere(u))
                .normalize();
            Some(si.spawn_ray(d))
        })
        .collect()
}
