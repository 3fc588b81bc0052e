//! The traversal's work per ray for `bench/traversal_instructions.sh`, which runs this under
//! callgrind and reads the instructions of each `trace_*` function: a count that, unlike a
//! timing, does not move with the machine's load. Each function traces one ray set of the BVH
//! benchmark's workload (`benches/workload`) on `displaced_sphere(NPHI, NTHETA)`, with 16 384
//! rays per set; the printed checksums (hit distances and primitives) show that a change to the
//! traversal kept every hit. The camera rays and the shadow segments are also traced eight at a
//! time (`intersect_stream`, `occluded_stream`; the camera's in row order, eight pixels of a row
//! to a packet).
//!
//!     cargo run --release -p caustica-scene --example traversal_instructions -- 64 32

#[path = "../benches/workload/mod.rs"]
mod workload;

use caustica_core::Ray;
use caustica_scene::geometry::Geometry;
use caustica_scene::shape::{Shape, ShapeGeometry};

/// Rays per set (the camera's are 128 × 128).
const RAYS: usize = 16_384;

/// Closest hits of camera rays (`hit_distance`): a checksum of their distances.
#[inline(never)]
fn trace_camera(geo: &Geometry, rays: &[Ray]) -> u64 {
    distances(geo, rays)
}

/// Closest hits of random rays (`hit_distance`). (Negated so that the linker cannot fold it
/// into `trace_camera`, which callgrind would then count for both.)
#[inline(never)]
fn trace_random(geo: &Geometry, rays: &[Ray]) -> u64 {
    !distances(geo, rays)
}

#[inline(always)]
fn distances(geo: &Geometry, rays: &[Ray]) -> u64 {
    rays.iter()
        .filter_map(|r| geo.hit_distance(r))
        .fold(0u64, |s, t| s.wrapping_add(u64::from(t.to_bits())))
}

/// Full hit records of random rays (`intersect`): distances and primitives.
#[inline(never)]
fn trace_intersect(geo: &Geometry, rays: &[Ray]) -> u64 {
    rays.iter()
        .filter_map(|r| geo.intersect(r))
        .fold(0u64, |s, si| {
            s.wrapping_add(u64::from(si.t.to_bits()) ^ u64::from(si.prim))
        })
}

/// Shadow segments (`occluded`): how many are blocked.
#[inline(never)]
fn trace_shadow(geo: &Geometry, rays: &[Ray]) -> u64 {
    rays.iter().filter(|r| geo.occluded(r)).count() as u64
}

/// Full hit records of camera rays traced eight at a time (`intersect_stream`): distances and
/// primitives.
#[inline(never)]
fn trace_camera_stream(geo: &Geometry, rays: &[Ray]) -> u64 {
    let mut out = Vec::with_capacity(rays.len());
    geo.intersect_stream(rays, &mut out);
    out.iter().flatten().fold(0u64, |s, si| {
        s.wrapping_add(u64::from(si.t.to_bits()) ^ u64::from(si.prim))
    })
}

/// Shadow segments eight at a time (`occluded_stream`): how many are blocked.
#[inline(never)]
fn trace_shadow_stream(geo: &Geometry, rays: &[Ray]) -> u64 {
    let mut out = Vec::with_capacity(rays.len());
    geo.occluded_stream(rays, &mut out);
    out.iter().filter(|&&b| b).count() as u64
}

fn main() {
    let (nphi, ntheta) =
        workload::tessellation_from_args(None, "traversal_instructions NPHI NTHETA");
    let geo = Geometry::build(vec![Shape::new(
        ShapeGeometry::Mesh(workload::displaced_sphere(nphi, ntheta)),
        0,
    )]);
    let bounds = geo.bounds();
    let camera = workload::camera_rays(128, 128);
    let random = workload::incoherent_rays(RAYS, &bounds, workload::INCOHERENT_SEED);
    let shadow = workload::shadow_rays(RAYS, &bounds, workload::SHADOW_SEED);
    println!(
        "checksums: camera {} random {} intersect {} shadow {} camera-stream {} shadow-stream {}",
        trace_camera(&geo, &camera),
        !trace_random(&geo, &random),
        trace_intersect(&geo, &random),
        trace_shadow(&geo, &shadow),
        trace_camera_stream(&geo, &camera),
        trace_shadow_stream(&geo, &shadow)
    );
}
