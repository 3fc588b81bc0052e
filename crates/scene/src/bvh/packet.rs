//! A leaf: up to four primitives, triangles tested four at a time with SSE (glam's `Vec4`).
//!
//! Triangles use the watertight test of [`TriangleRay`] lane by lane: the same operations in
//! the same order as the scalar test, so the hits are bit-identical to it (the scalar test
//! also decides the rare lanes exactly on an edge, which need double precision). Spheres and
//! disks sit in packet lanes too and are tested by the caller's function.

use crate::shape::mesh::TriangleRay;
use caustica_core::Vec3;
use glam::{BVec4A, Vec4};

/// Primitive reference of an unused lane.
pub(super) const EMPTY: u32 = u32::MAX;
/// Most primitives per packet.
pub(super) const PACKET_LANES: usize = 4;

/// What [`Packet::closest_triangle_fast`] finds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Fast {
    /// No triangle lane is hit closer than the bound.
    Miss,
    /// The closest: `(t, lane, b1, b2)`.
    Hit(f32, usize, f32, f32),
    /// The ray passes exactly through an edge of some triangle lane: the scalar test decides
    /// ([`Packet::closest_triangle`]).
    Scalar,
}

/// Up to four primitives of one leaf: 168 bytes in three cache lines (aligned to a line, so
/// never four; the traversal is bound by the latency of these loads). The masks and
/// primitive indices come first, then the triangle vertices as structure of arrays
/// `v[vertex][axis]`, one lane per triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub(super) struct Packet {
    /// Bit `l` set: lane `l` is a triangle.
    pub(super) tri_mask: u32,
    /// Bit `l` set: lane `l` is another primitive, tested by the caller's function.
    pub(super) other_mask: u32,
    /// Primitive index (BVH order) of each lane; [`EMPTY`] for unused lanes.
    pub(super) prim: [u32; 4],
    pub(super) v: [[Vec4; 3]; 3],
}

const _: () = assert!(std::mem::size_of::<Packet>() == 192);

impl Packet {
    /// A packet with no primitive.
    pub(super) const EMPTY_PACKET: Packet = Packet {
        tri_mask: 0,
        other_mask: 0,
        prim: [EMPTY; 4],
        v: [[Vec4::ZERO; 3]; 3],
    };

    /// The closest triangle lane hit with `t ∈ (0, t_max)`, or at `t = t_max` exactly for lanes
    /// whose primitive (BVH order) is below `tie_below`: `(t, lane, b1, b2)`. Ties inside the
    /// packet go to the lower lane (lanes are in BVH order). With `tie_below` the primitive of
    /// the closest hit so far (0 if none), the closest hit of a traversal is the one of least
    /// BVH order among those at the least distance, whatever the order of the visit.
    #[inline(always)]
    pub(super) fn closest_triangle(
        &self,
        tr: &TriangleRay,
        t_max: f32,
        tie_below: u32,
    ) -> Option<(f32, usize, f32, f32)> {
        match self.closest_triangle_fast(tr, t_max, tie_below) {
            Fast::Miss => None,
            Fast::Hit(t, l, b1, b2) => Some((t, l, b1, b2)),
            Fast::Scalar => self.closest_triangle_scalar(tr, t_max, tie_below),
        }
    }

    /// [`Self::closest_triangle`] without calls: where the ray passes exactly through an edge
    /// of some triangle, it leaves the packet to the scalar test ([`Fast::Scalar`]), which
    /// the traversals call outside their hot loops.
    #[inline(always)]
    pub(super) fn closest_triangle_fast(
        &self,
        tr: &TriangleRay,
        t_max: f32,
        tie_below: u32,
    ) -> Fast {
        if self.tri_mask == 0 {
            return Fast::Miss;
        }
        // `min(2)` proves the axis indices in range (they are 0, 1, 2) without a bounds check.
        let (kx, ky, kz) = (tr.kx.min(2), tr.ky.min(2), tr.kz.min(2));
        let o = tr.o.extend(0.0).to_array();
        let (ox, oy, oz) = (Vec4::splat(o[kx]), Vec4::splat(o[ky]), Vec4::splat(o[kz]));
        let (sx, sy) = (Vec4::splat(tr.sx), Vec4::splat(tr.sy));
        // The scalar test's operations, lane by lane: translate, permute, shear.
        let vert = |k: usize| {
            let p = &self.v[k];
            let z = p[kz] - oz;
            (p[kx] - ox - sx * z, p[ky] - oy - sy * z, z)
        };
        let (ax, ay, az) = vert(0);
        let (bx, by, bz) = vert(1);
        let (cx, cy, cz) = vert(2);
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        let zero = Vec4::ZERO;
        let on_edge = (u.cmpeq(zero) | v.cmpeq(zero) | w.cmpeq(zero)).bitmask() & self.tri_mask;
        if on_edge != 0 {
            return Fast::Scalar;
        }
        let neg = u.cmplt(zero) | v.cmplt(zero) | w.cmplt(zero);
        let pos = u.cmpgt(zero) | v.cmpgt(zero) | w.cmpgt(zero);
        // Most packets a ray reaches have every triangle beside it (edge functions of both
        // signs): stop before the division and the distances, as Embree's test does. A lane
        // outside here is outside in `inside` below, so the result is the same.
        if (!(neg & pos)).bitmask() & self.tri_mask == 0 {
            return Fast::Miss;
        }
        let det = u + v + w;
        let inv = Vec4::ONE / det;
        let t = Vec4::splat(tr.sz) * (u * az + v * bz + w * cz) * inv;
        let inside: BVec4A = !(neg & pos) & det.cmpne(zero) & t.cmpgt(zero);
        let t_max4 = Vec4::splat(t_max);
        let mut mask = (inside & t.cmplt(t_max4)).bitmask() & self.tri_mask;
        let ties = (inside & t.cmpeq(t_max4)).bitmask() & self.tri_mask;
        if ties != 0 {
            mask |= self.lanes_below(ties, tie_below);
        }
        if mask == 0 {
            return Fast::Miss;
        }
        let ts = t.to_array();
        let mut lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        while mask != 0 {
            let l = mask.trailing_zeros() as usize;
            if ts[l & 3] < ts[lane & 3] {
                lane = l;
            }
            mask &= mask - 1;
        }
        let lane = lane & 3;
        let (b1, b2) = ((v * inv).to_array(), (w * inv).to_array());
        Fast::Hit(ts[lane], lane, b1[lane], b2[lane])
    }

    /// The lanes of `lanes` whose primitive is below `bound` (the rare ties of a hit distance;
    /// inline, so the fast test calls nothing).
    #[inline(always)]
    fn lanes_below(&self, mut lanes: u32, bound: u32) -> u32 {
        let mut below = 0;
        while lanes != 0 {
            let l = lanes.trailing_zeros() as usize & 3;
            lanes &= lanes - 1;
            if self.prim[l] < bound {
                below |= 1 << l;
            }
        }
        below
    }

    /// [`Self::closest_triangle`] by the scalar test, lane by lane.
    #[cold]
    fn closest_triangle_scalar(
        &self,
        tr: &TriangleRay,
        mut t_max: f32,
        mut tie_below: u32,
    ) -> Option<(f32, usize, f32, f32)> {
        let mut best = None;
        let mut mask = self.tri_mask;
        while mask != 0 {
            let l = mask.trailing_zeros() as usize & 3;
            mask &= mask - 1;
            // `intersect` keeps `t < bound`: ask for `t ≤ t_max`, then apply the tie rule.
            if let Some((t, b1, b2)) = tr.intersect(
                t_max.next_up(),
                self.vertex(0, l),
                self.vertex(1, l),
                self.vertex(2, l),
            ) && (t < t_max || self.prim[l] < tie_below)
            {
                t_max = t;
                // Later lanes are later in BVH order: a tie with this hit no longer wins.
                tie_below = self.prim[l];
                best = Some((t, l, b1, b2));
            }
        }
        best
    }

    /// Vertex `k` of the triangle in lane `l`.
    #[inline]
    pub(super) fn vertex(&self, k: usize, l: usize) -> Vec3 {
        let p = &self.v[k];
        Vec3::new(p[0][l], p[1][l], p[2][l])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::Pcg32;

    fn rand_vec(rng: &mut Pcg32, lo: f32, hi: f32) -> Vec3 {
        let mut c = || lo + (hi - lo) * rng.next_f32();
        Vec3::new(c(), c(), c())
    }

    /// A packet of the given triangles (at most four).
    fn packet(tris: &[[Vec3; 3]]) -> Packet {
        let mut pk = Packet::EMPTY_PACKET;
        for (l, t) in tris.iter().enumerate() {
            for (k, p) in t.iter().enumerate() {
                for a in 0..3 {
                    pk.v[k][a][l] = p[a];
                }
            }
            pk.prim[l] = l as u32;
            pk.tri_mask |= 1 << l;
        }
        pk
    }

    #[test]
    fn packet_test_is_bit_identical_to_the_scalar_test() {
        // Random triangles, and triangles sharing edges and vertices with rays aimed at those
        // (the lanes that fall back to the scalar test in double precision).
        let mut rng = Pcg32::new(17, 5);
        let mut hits = 0;
        for i in 0..20_000 {
            let n = 1 + (i % 4);
            let shared = i % 3 == 0;
            let base = [
                rand_vec(&mut rng, -1.0, 1.0),
                rand_vec(&mut rng, -1.0, 1.0),
                rand_vec(&mut rng, -1.0, 1.0),
            ];
            let tris: Vec<[Vec3; 3]> = (0..n)
                .map(|k| {
                    if shared {
                        // A fan around base[0]: neighbours share an edge.
                        [
                            base[0],
                            base[1] + Vec3::splat(k as f32 * 0.3),
                            base[2] + Vec3::splat(k as f32 * 0.3 + 0.3),
                        ]
                    } else {
                        [
                            rand_vec(&mut rng, -1.0, 1.0),
                            rand_vec(&mut rng, -1.0, 1.0),
                            rand_vec(&mut rng, -1.0, 1.0),
                        ]
                    }
                })
                .collect();
            let o = rand_vec(&mut rng, -3.0, 3.0);
            let target = if shared {
                // On the shared vertex or on a shared edge.
                let s = rng.next_f32();
                if i % 2 == 0 {
                    base[0]
                } else {
                    base[0] + (tris[0][1] - base[0]) * s
                }
            } else {
                rand_vec(&mut rng, -1.0, 1.0)
            };
            let Some(d) = (target - o).try_normalize() else {
                continue;
            };
            let tr = TriangleRay::new(o, d);
            let t_max = if i % 5 == 0 { 2.0 } else { f32::INFINITY };
            let mut expected = None;
            let mut tm = t_max;
            for (l, t) in tris.iter().enumerate() {
                if let Some((t, b1, b2)) = tr.intersect(tm, t[0], t[1], t[2]) {
                    tm = t;
                    expected = Some((t.to_bits(), l, b1.to_bits(), b2.to_bits()));
                }
            }
            let got = packet(&tris)
                .closest_triangle(&tr, t_max, 0)
                .map(|(t, l, b1, b2)| (t.to_bits(), l, b1.to_bits(), b2.to_bits()));
            assert_eq!(got, expected, "case {i}");
            hits += got.is_some() as u32;
        }
        assert!(hits > 3000, "hits {hits}");

        // Rays straight down onto the shared edge x = 0 and the shared vertices of two
        // triangles in z = 0: every quantity is an exact small dyadic number, so an edge
        // function is exactly zero and the packet must take the scalar (double-precision)
        // fallback. The hit must exist (no crack) and match the scalar test bit for bit.
        let a = [
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-1.0, 0.0, 0.0),
        ];
        let b = [
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
        ];
        for y in [-1.0, -0.5, 0.0, 0.25, 0.5, 1.0] {
            let tr = TriangleRay::new(Vec3::new(0.0, y, 1.0), -Vec3::Z);
            let mut expected = None;
            let mut tm = f32::INFINITY;
            for (l, t) in [a, b].iter().enumerate() {
                if let Some((t, b1, b2)) = tr.intersect(tm, t[0], t[1], t[2]) {
                    tm = t;
                    expected = Some((t.to_bits(), l, b1.to_bits(), b2.to_bits()));
                }
            }
            assert!(expected.is_some(), "the shared edge at y = {y} leaks");
            let got = packet(&[a, b])
                .closest_triangle(&tr, f32::INFINITY, 0)
                .map(|(t, l, b1, b2)| (t.to_bits(), l, b1.to_bits(), b2.to_bits()));
            assert_eq!(got, expected, "y = {y}");
        }
    }
}
