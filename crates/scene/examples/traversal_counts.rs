//! Nodes and leaf packets a single ray visits, on average, on the BVH benchmark's workload
//! (the 1 M-triangle displaced sphere and its ray sets, `benches/workload`): a measure of the
//! tree's shape that does not depend on the machine's load, for judging builds and collapses.
//!
//!     cargo run --release -p caustica-scene --features traversal-counts --example traversal_counts
//!
//! `CAUSTICA_BVH_WIDTH=4` measures the four-wide tree; two arguments `NPHI NTHETA` choose
//! another tessellation of the same sphere (`64 32`: 4 032 triangles, a tree in the caches).

#[path = "../benches/workload/mod.rs"]
mod workload;

use caustica_core::Ray;
use caustica_scene::bvh::counts;
use caustica_scene::geometry::Geometry;
use caustica_scene::shape::{Shape, ShapeGeometry};
use std::hint::black_box;
use workload::{
    BOUNCE_SEED, INCOHERENT_SEED, SHADOW_SEED, camera_rays, diffuse_bounce_rays, displaced_sphere,
    incoherent_rays, shadow_rays,
};

fn main() {
    let (nphi, ntheta) =
        workload::tessellation_from_args(Some((1024, 512)), "traversal_counts [NPHI NTHETA]");
    let mesh = displaced_sphere(nphi, ntheta);
    let geo = Geometry::build(vec![Shape::new(ShapeGeometry::Mesh(mesh), 0)]);
    let bounds = geo.bounds();
    let camera = camera_rays(512, 512);
    let bounce = diffuse_bounce_rays(&geo, &camera, BOUNCE_SEED);
    let random = incoherent_rays(200_000, &bounds, INCOHERENT_SEED);
    let shadow = shadow_rays(200_000, &bounds, SHADOW_SEED);
    println!(
        "displaced_sphere({nphi}, {ntheta}): {} triangles; {:?} BVH: {} nodes, {} leaf packets\n",
        2 * nphi * (ntheta - 1),
        geo.bvh.width(),
        geo.bvh.node_count(),
        geo.bvh.packet_count()
    );
    println!("| ray set | query | nodes / ray | packets / ray |\n|---|---|---:|---:|");
    let sets: [(&str, &[Ray], bool); 4] = [
        ("coherent primary", &camera, false),
        ("diffuse bounce", &bounce, false),
        ("random incoherent", &random, false),
        ("shadow", &shadow, true),
    ];
    for (name, rays, shadow) in sets {
        counts::take();
        for r in rays {
            if shadow {
                black_box(geo.occluded(r));
            } else {
                black_box(geo.hit_distance(r));
            }
        }
        let c = counts::take();
        let n = rays.len() as f64;
        println!(
            "| {name} | {} | {:.2} | {:.2} |",
            if shadow { "any hit" } else { "closest hit" },
            c.nodes as f64 / n,
            c.packets as f64 / n
        );
    }
}
