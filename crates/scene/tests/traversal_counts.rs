//! `bvh::counts` (feature `traversal-counts`; `cargo test -p caustica-scene --features
//! traversal-counts --test traversal_counts`): the counts the `traversal_counts` example
//! reports are the nodes and packets a traversal really visits.
#![cfg(feature = "traversal-counts")]

use caustica_core::{Ray, Vec3};
use caustica_scene::bvh::counts;
use caustica_scene::geometry::Geometry;
use caustica_scene::shape::{Shape, ShapeGeometry, TriangleMesh};

/// `n` unit triangles in the plane z = 0, side by side along x, 3 m apart.
fn row(n: u32) -> Geometry {
    let mut m = TriangleMesh::default();
    for t in 0..n {
        let c = Vec3::new(t as f32 * 3.0, 0.0, 0.0);
        m.positions.extend([
            c + Vec3::new(-1.0, -1.0, 0.0),
            c + Vec3::new(1.0, -1.0, 0.0),
            c + Vec3::new(0.0, 1.0, 0.0),
        ]);
        m.indices.push([3 * t, 3 * t + 1, 3 * t + 2]);
    }
    Geometry::build(vec![Shape::new(ShapeGeometry::Mesh(m), 0)])
}

/// (nodes, packets) visited since the last call.
fn visits() -> (u64, u64) {
    let c = counts::take();
    (c.nodes, c.packets)
}

#[test]
fn one_triangle_is_one_node_and_one_packet_and_a_miss_of_the_root_tests_no_packet() {
    let geo = row(1);
    counts::take();
    assert!(
        geo.hit_distance(&Ray::new(Vec3::new(0.0, 0.0, 1.0), -Vec3::Z))
            .is_some()
    );
    assert_eq!(visits(), (1, 1));
    assert!(!geo.occluded(&Ray::new(Vec3::new(0.0, 5.0, 1.0), -Vec3::Z)));
    assert_eq!(visits(), (1, 0));
}

#[test]
fn a_ray_past_far_apart_triangles_visits_fewer_packets_than_there_are() {
    // 64 triangles in 16 packets at least; a ray down onto one of them needs only its leaf.
    let geo = row(64);
    counts::take();
    assert!(
        geo.hit_distance(&Ray::new(Vec3::new(30.0, 0.0, 1.0), -Vec3::Z))
            .is_some()
    );
    let c = counts::take();
    assert!(c.nodes >= 1 && c.packets >= 1, "{c:?}");
    assert!(c.packets < geo.bvh.packet_count() as u64 / 2, "{c:?}");
    // Counts add up over queries until taken.
    for _ in 0..3 {
        geo.hit_distance(&Ray::new(Vec3::new(30.0, 0.0, 1.0), -Vec3::Z));
    }
    let three = counts::take();
    assert_eq!((three.nodes, three.packets), (3 * c.nodes, 3 * c.packets));
}
