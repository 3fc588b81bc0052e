//! A 4-wide BVH traversed four boxes and four triangles at a time with SSE (glam's `Vec4`).
//!
//! The tree comes from the `obvhs` crate's binary PLOC build (with reinsertion, single threaded,
//! so it is the same whatever the thread count), collapsed here to four children per node:
//! every subtree of at most four primitives becomes one leaf [`Packet`], and a node takes its
//! binary children, repeatedly replacing the child of largest surface area by that child's two
//! children until it has four.
//!
//! * **Boxes**: one node holds its four child boxes as structure of arrays, and a ray tests all
//!   four with one slab test (near and far planes chosen by the ray's octant; the far distance
//!   grown by `1 + 2γ₃` as in pbrt-v4 so rounding cannot lose a hit). Closest-hit queries visit
//!   the hit children near to far and skip stack entries farther than the closest hit so far;
//!   shadow queries stop at the first hit.
//! * **Triangles**: a packet holds up to four triangles as structure of arrays, tested with the
//!   watertight test of [`TriangleRay`] lane by lane: the same operations in the same order as the
//!   scalar test, so the hits are bit-identical to it (the scalar test also decides the rare lanes
//!   exactly on an edge, which need double precision). Spheres and disks sit in packet lanes too
//!   and are tested by the caller's function.

use crate::shape::Aabb;
use crate::shape::mesh::TriangleRay;
use caustica_core::Vec3;
use glam::{BVec4A, Vec3A, Vec4};
use std::mem::MaybeUninit;

/// Child reference of an unused lane.
const EMPTY: u32 = u32::MAX;
/// Child references with this bit set are packets (leaves); the others are nodes.
const LEAF: u32 = 1 << 31;
/// Most primitives per packet (leaf).
const LANES: usize = 4;
/// 1 + 2γ₃ (pbrt-v4, ε = 2⁻²⁴): the factor on a slab test's far distance that makes it
/// conservative under rounding.
const ROBUST: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// An inner node: the boxes of its four children, one lane per child.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Node {
    /// `bounds[axis][0]` holds the minima of the four boxes along `axis`, `[1]` the maxima.
    /// Unused lanes hold the empty box (+∞, −∞), which no ray hits.
    bounds: [[Vec4; 2]; 3],
    child: [u32; 4],
}

/// Up to four primitives of one leaf. Triangle vertices are stored as structure of arrays
/// `v[vertex][axis]`, one lane per triangle (axis 3 is unused padding, so an axis index `& 3`
/// needs no bounds check).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Packet {
    v: [[Vec4; 4]; 3],
    /// Primitive index (BVH order) of each lane; [`EMPTY`] for unused lanes.
    prim: [u32; 4],
    /// Bit `l` set: lane `l` is a triangle.
    tri_mask: u32,
    /// Bit `l` set: lane `l` is another primitive, tested by the caller's function.
    other_mask: u32,
}

/// A hit found by a traversal: distance, primitive (BVH order) and barycentrics `(b1, b2)`
/// (zero for non-triangles).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WideHit {
    pub t: f32,
    pub prim: u32,
    pub b1: f32,
    pub b2: f32,
}

/// The 4-wide BVH over a scene's primitives.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WideBvh {
    nodes: Vec<Node>,
    packets: Vec<Packet>,
    /// BVH order → index of the primitive in the build input.
    order: Vec<u32>,
}

/// A ray prepared for the slab tests: origin, reciprocal direction (components of magnitude
/// below 1e-20 replaced by ±1e-20, so the reciprocal stays finite) and, per axis, which of a
/// box's two planes it meets first.
#[derive(Clone, Copy, Debug)]
pub struct BoxRay {
    o: [Vec4; 3],
    inv: [Vec4; 3],
    near: [usize; 3],
}

impl BoxRay {
    #[inline(always)]
    pub fn new(o: Vec3, d: Vec3) -> Self {
        let inv = |x: f32| {
            let x = if x.abs() < 1e-20 {
                1e-20f32.copysign(x)
            } else {
                x
            };
            1.0 / x
        };
        let i = [inv(d.x), inv(d.y), inv(d.z)];
        Self {
            o: [Vec4::splat(o.x), Vec4::splat(o.y), Vec4::splat(o.z)],
            inv: [Vec4::splat(i[0]), Vec4::splat(i[1]), Vec4::splat(i[2])],
            near: [
                (i[0] < 0.0) as usize,
                (i[1] < 0.0) as usize,
                (i[2] < 0.0) as usize,
            ],
        }
    }

    /// Lanes of `node` whose boxes the ray meets within `[0, t_max]`, and the entry distances.
    #[inline(always)]
    fn hit_node(&self, node: &Node, t_max: f32) -> (u32, Vec4) {
        let slab = |a: usize| {
            let n = self.near[a] & 1;
            let b = &node.bounds[a];
            (
                (b[n] - self.o[a]) * self.inv[a],
                (b[n ^ 1] - self.o[a]) * self.inv[a],
            )
        };
        let (x0, x1) = slab(0);
        let (y0, y1) = slab(1);
        let (z0, z1) = slab(2);
        let t0 = x0.max(y0).max(z0.max(Vec4::ZERO));
        let t1 = x1.min(y1).min(z1.min(Vec4::splat(t_max))) * ROBUST;
        (t0.cmple(t1).bitmask(), t0)
    }
}

/// Entries of the traversal stack kept in place before it spills to the heap.
const STACK: usize = 64;

/// The traversal stack: `(entry distance, child)` in a fixed array, spilling to the heap only
/// for very deep trees. The array is left uninitialised: zeroing it cost more per ray than a
/// shallow tree's whole traversal.
struct Stack<'a> {
    buf: &'a mut [MaybeUninit<(f32, u32)>; STACK],
    /// Entries `buf[..len]` are initialised (the invariant every method keeps).
    len: usize,
    spill: Vec<(f32, u32)>,
}

/// A stack's uninitialised storage, declared by the caller (building it inside `Stack::new`
/// made the compiler copy the whole array on every query).
type StackBuf = [MaybeUninit<(f32, u32)>; STACK];

impl<'a> Stack<'a> {
    #[inline(always)]
    fn new(buf: &'a mut StackBuf) -> Self {
        Self {
            buf,
            len: 0,
            spill: Vec::new(),
        }
    }

    #[inline(always)]
    fn push(&mut self, e: (f32, u32)) {
        // Once spilled, later entries go to the heap too, so pops stay last-in first-out.
        match self.buf.get_mut(self.len) {
            Some(slot) if self.spill.is_empty() => {
                slot.write(e);
                self.len += 1;
            }
            _ => self.spill.push(e),
        }
    }

    #[inline(always)]
    fn pop(&mut self) -> Option<(f32, u32)> {
        if let Some(e) = self.spill.pop() {
            return Some(e);
        }
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        // SAFETY: `len` counts the initialised prefix of `buf`: `push` writes `buf[len]` before
        // incrementing `len`, and only `pop` decrements it. Before this decrement `len ≥ 1`
        // entries were initialised, so `buf[len]` (the last of them) is initialised. The index
        // is in bounds because `len ≤ STACK` always holds (`push` only writes through `get_mut`).
        Some(unsafe { self.buf[self.len].assume_init() })
    }
}

impl Packet {
    /// The closest triangle lane hit with `t ∈ (0, t_max)`: `(t, lane, b1, b2)`. Ties go to the
    /// lower lane, as a scalar loop over the lanes in order would decide.
    #[inline(always)]
    fn closest_triangle(&self, tr: &TriangleRay, t_max: f32) -> Option<(f32, usize, f32, f32)> {
        if self.tri_mask == 0 {
            return None;
        }
        let (kx, ky, kz) = (tr.kx & 3, tr.ky & 3, tr.kz & 3);
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
            return self.closest_triangle_scalar(tr, t_max);
        }
        let neg = u.cmplt(zero) | v.cmplt(zero) | w.cmplt(zero);
        let pos = u.cmpgt(zero) | v.cmpgt(zero) | w.cmpgt(zero);
        let det = u + v + w;
        let inv = Vec4::ONE / det;
        let t = Vec4::splat(tr.sz) * (u * az + v * bz + w * cz) * inv;
        let ok: BVec4A =
            !(neg & pos) & det.cmpne(zero) & t.cmpgt(zero) & t.cmplt(Vec4::splat(t_max));
        let mut mask = ok.bitmask() & self.tri_mask;
        if mask == 0 {
            return None;
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
        Some((ts[lane], lane, b1[lane], b2[lane]))
    }

    /// [`Self::closest_triangle`] by the scalar test, lane by lane.
    #[cold]
    fn closest_triangle_scalar(
        &self,
        tr: &TriangleRay,
        mut t_max: f32,
    ) -> Option<(f32, usize, f32, f32)> {
        let mut best = None;
        let mut mask = self.tri_mask;
        while mask != 0 {
            let l = mask.trailing_zeros() as usize & 3;
            mask &= mask - 1;
            if let Some((t, b1, b2)) = tr.intersect(
                t_max,
                self.vertex(0, l),
                self.vertex(1, l),
                self.vertex(2, l),
            ) {
                t_max = t;
                best = Some((t, l, b1, b2));
            }
        }
        best
    }

    /// Vertex `k` of the triangle in lane `l`.
    #[inline]
    fn vertex(&self, k: usize, l: usize) -> Vec3 {
        let p = &self.v[k];
        Vec3::new(p[0][l], p[1][l], p[2][l])
    }
}

impl WideBvh {
    /// Builds the tree over primitives with the given (conservative) bounds; `triangles[i]` holds
    /// the vertices of primitive `i` if it is a triangle. Deterministic: the same input gives the
    /// same tree whatever the thread count.
    pub fn build(bounds: &[Aabb], triangles: &[Option<[Vec3; 3]>]) -> Self {
        debug_assert_eq!(bounds.len(), triangles.len());
        if bounds.is_empty() {
            return Self::default();
        }
        let oboxes: Vec<obvhs::aabb::Aabb> = bounds
            .iter()
            .map(|b| obvhs::aabb::Aabb::new(Vec3A::from(b.min), Vec3A::from(b.max)))
            .collect();
        let params = obvhs::BvhBuildParams {
            // Leaves of one primitive: packets are formed below from whole subtrees.
            max_prims_per_leaf: 1,
            ..obvhs::BvhBuildParams::medium_build()
        };
        let bvh2 =
            obvhs::bvh2::builder::build_bvh2(&oboxes, params, &mut std::time::Duration::default());
        Collapse::new(&bvh2, triangles).run()
    }

    /// Inner nodes (four children each).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Leaf packets (up to four primitives each).
    pub fn packet_count(&self) -> usize {
        self.packets.len()
    }

    /// BVH order → index of the primitive in the build input.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// The closest hit with `t ∈ (0, t_max)`. Triangles are tested here; every other primitive
    /// `k` (BVH order) by `other(k, t)`, which returns `(t, b1, b2)` of a hit closer than `t`.
    #[inline(always)]
    pub fn closest(
        &self,
        tr: &TriangleRay,
        br: &BoxRay,
        mut t_max: f32,
        mut other: impl FnMut(u32, f32) -> Option<(f32, f32, f32)>,
    ) -> Option<WideHit> {
        if self.nodes.is_empty() {
            return None;
        }
        let mut best = None;
        let mut buf: StackBuf = [const { MaybeUninit::uninit() }; STACK];
        let mut stack = Stack::new(&mut buf);
        let mut cur = 0u32;
        loop {
            if cur & LEAF == 0 {
                let node = &self.nodes[cur as usize];
                let (mut mask, t0) = br.hit_node(node, t_max);
                if mask != 0 {
                    let first = mask.trailing_zeros() as usize & 3;
                    mask &= mask - 1;
                    if mask == 0 {
                        cur = node.child[first];
                        continue;
                    }
                    // Two to four children: visit the nearest, stack the rest far to near.
                    let t0 = t0.to_array();
                    let mut hits = [(t0[first], node.child[first]); 4];
                    let mut n = 1;
                    while mask != 0 {
                        let l = mask.trailing_zeros() as usize & 3;
                        mask &= mask - 1;
                        let e = (t0[l], node.child[l]);
                        let mut j = n;
                        while j > 0 && hits[j - 1].0 > e.0 {
                            hits[j] = hits[j - 1];
                            j -= 1;
                        }
                        hits[j] = e;
                        n += 1;
                    }
                    for &e in hits[1..n].iter().rev() {
                        stack.push(e);
                    }
                    cur = hits[0].1;
                    continue;
                }
            } else {
                let pk = &self.packets[(cur & !LEAF) as usize];
                if let Some((t, l, b1, b2)) = pk.closest_triangle(tr, t_max) {
                    t_max = t;
                    best = Some(WideHit {
                        t,
                        prim: pk.prim[l],
                        b1,
                        b2,
                    });
                }
                let mut others = pk.other_mask;
                while others != 0 {
                    let l = others.trailing_zeros() as usize & 3;
                    others &= others - 1;
                    if let Some((t, b1, b2)) = other(pk.prim[l], t_max) {
                        t_max = t;
                        best = Some(WideHit {
                            t,
                            prim: pk.prim[l],
                            b1,
                            b2,
                        });
                    }
                }
            }
            // Next stacked child that may still hold a closer hit.
            loop {
                match stack.pop() {
                    None => return best,
                    Some((t, c)) if t <= t_max * ROBUST => {
                        cur = c;
                        break;
                    }
                    Some(_) => {}
                }
            }
        }
    }

    /// True if any primitive is hit with `t ∈ (0, t_max)`; `other` as for [`Self::closest`]
    /// (only whether it returns a hit matters).
    #[inline(always)]
    pub fn any(
        &self,
        tr: &TriangleRay,
        br: &BoxRay,
        t_max: f32,
        mut other: impl FnMut(u32, f32) -> Option<(f32, f32, f32)>,
    ) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let mut buf: StackBuf = [const { MaybeUninit::uninit() }; STACK];
        let mut stack = Stack::new(&mut buf);
        let mut cur = 0u32;
        loop {
            if cur & LEAF == 0 {
                let node = &self.nodes[cur as usize];
                let (mut mask, _) = br.hit_node(node, t_max);
                if mask != 0 {
                    let first = mask.trailing_zeros() as usize & 3;
                    mask &= mask - 1;
                    while mask != 0 {
                        let l = mask.trailing_zeros() as usize & 3;
                        mask &= mask - 1;
                        stack.push((0.0, node.child[l]));
                    }
                    cur = node.child[first];
                    continue;
                }
            } else {
                let pk = &self.packets[(cur & !LEAF) as usize];
                if pk.closest_triangle(tr, t_max).is_some() {
                    return true;
                }
                let mut others = pk.other_mask;
                while others != 0 {
                    let l = others.trailing_zeros() as usize & 3;
                    others &= others - 1;
                    if other(pk.prim[l], t_max).is_some() {
                        return true;
                    }
                }
            }
            match stack.pop() {
                None => return false,
                Some((_, c)) => cur = c,
            }
        }
    }
}

/// Collapses obvhs's binary tree into a [`WideBvh`].
struct Collapse<'a> {
    bvh2: &'a obvhs::bvh2::Bvh2,
    triangles: &'a [Option<[Vec3; 3]>],
    /// Primitives in the subtree of each binary node.
    count: Vec<u32>,
    out: WideBvh,
}

impl<'a> Collapse<'a> {
    fn new(bvh2: &'a obvhs::bvh2::Bvh2, triangles: &'a [Option<[Vec3; 3]>]) -> Self {
        // Subtree primitive counts by an explicit post-order walk (trees may be deep).
        let nodes = &bvh2.nodes;
        let mut count = vec![0u32; nodes.len()];
        let mut stack = vec![(0usize, false)];
        while let Some((i, children_done)) = stack.pop() {
            let n = &nodes[i];
            if n.is_leaf() {
                count[i] = n.prim_count;
            } else if children_done {
                let c = n.first_index as usize;
                count[i] = count[c] + count[c + 1];
            } else {
                let c = n.first_index as usize;
                stack.extend([(i, true), (c, false), (c + 1, false)]);
            }
        }
        Self {
            bvh2,
            triangles,
            count,
            out: WideBvh::default(),
        }
    }

    fn run(mut self) -> WideBvh {
        // The root is always a node (a lone packet goes in its first lane).
        let mut work = vec![(0usize, EMPTY, 0usize)];
        while let Some((b, parent, lane)) = work.pop() {
            let child = if self.count[b] as usize <= LANES && parent != EMPTY {
                self.packet(b)
            } else {
                let id = self.out.nodes.len() as u32;
                let kids = self.children(b);
                let mut node = Node {
                    bounds: [[Vec4::splat(f32::INFINITY), Vec4::splat(f32::NEG_INFINITY)]; 3],
                    child: [EMPTY; 4],
                };
                for (l, &k) in kids.iter().enumerate() {
                    let bb = self.bvh2.nodes[k].aabb();
                    for a in 0..3 {
                        node.bounds[a][0][l] = bb.min[a];
                        node.bounds[a][1][l] = bb.max[a];
                    }
                }
                self.out.nodes.push(node);
                // Reverse order so lane 0's subtree is laid out first (depth first).
                for (l, &k) in kids.iter().enumerate().rev() {
                    work.push((k, id, l));
                }
                id
            };
            if parent != EMPTY {
                self.out.nodes[parent as usize].child[lane] = child;
            }
        }
        self.out
    }

    /// The binary nodes that become the children of a wide node replacing binary node `b`.
    fn children(&self, b: usize) -> Vec<usize> {
        let nodes = &self.bvh2.nodes;
        let mut kids = vec![b];
        while kids.len() < LANES {
            // Open the largest child that cannot be a packet; else the largest inner child.
            let pick = |must_open: bool| {
                kids.iter()
                    .enumerate()
                    .filter(|&(_, &k)| {
                        !nodes[k].is_leaf() && (!must_open || self.count[k] as usize > LANES)
                    })
                    .max_by(|a, b| {
                        let (ha, hb) = (
                            nodes[*a.1].aabb().half_area(),
                            nodes[*b.1].aabb().half_area(),
                        );
                        ha.total_cmp(&hb).then(b.0.cmp(&a.0))
                    })
                    .map(|(i, _)| i)
            };
            let Some(i) = pick(true).or_else(|| if kids.len() == 1 { pick(false) } else { None })
            else {
                break;
            };
            let c = nodes[kids[i]].first_index as usize;
            kids.splice(i..=i, [c, c + 1]);
        }
        kids
    }

    /// A packet of every primitive under binary node `b` (at most four).
    fn packet(&mut self, b: usize) -> u32 {
        let nodes = &self.bvh2.nodes;
        let mut pk = Packet {
            v: [[Vec4::ZERO; 4]; 3],
            prim: [EMPTY; 4],
            tri_mask: 0,
            other_mask: 0,
        };
        let mut lane = 0;
        let mut stack = vec![b];
        while let Some(i) = stack.pop() {
            let n = &nodes[i];
            if !n.is_leaf() {
                stack.extend([n.first_index as usize + 1, n.first_index as usize]);
                continue;
            }
            let first = n.first_index as usize;
            for &input in &self.bvh2.primitive_indices[first..first + n.prim_count as usize] {
                let k = self.out.order.len() as u32;
                self.out.order.push(input);
                pk.prim[lane] = k;
                match self.triangles[input as usize] {
                    Some(tri) => {
                        for (vk, p) in tri.iter().enumerate() {
                            for a in 0..3 {
                                pk.v[vk][a][lane] = p[a];
                            }
                        }
                        pk.tri_mask |= 1 << lane;
                    }
                    None => pk.other_mask |= 1 << lane,
                }
                lane += 1;
            }
        }
        let id = self.out.packets.len() as u32;
        self.out.packets.push(pk);
        LEAF | id
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

    #[test]
    fn stack_spills_and_stays_last_in_first_out() {
        let mut buf: StackBuf = [const { MaybeUninit::uninit() }; STACK];
        let mut s = Stack::new(&mut buf);
        // Fill past the array, pop some, push again: pops must mirror pushes exactly.
        let mut model = Vec::new();
        for round in 0..3u32 {
            for i in 0..(STACK as u32 + 20) {
                let e = (i as f32, round * 1000 + i);
                s.push(e);
                model.push(e);
            }
            for _ in 0..30 {
                assert_eq!(s.pop(), model.pop());
            }
        }
        while let Some(e) = model.pop() {
            assert_eq!(s.pop(), Some(e));
        }
        assert_eq!(s.pop(), None);
    }

    /// A packet of the given triangles (at most four).
    fn packet(tris: &[[Vec3; 3]]) -> Packet {
        let mut pk = Packet {
            v: [[Vec4::ZERO; 4]; 3],
            prim: [EMPTY; 4],
            tri_mask: 0,
            other_mask: 0,
        };
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
                .closest_triangle(&tr, t_max)
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
                .closest_triangle(&tr, f32::INFINITY)
                .map(|(t, l, b1, b2)| (t.to_bits(), l, b1.to_bits(), b2.to_bits()));
            assert_eq!(got, expected, "y = {y}");
        }
    }

    #[test]
    fn slab_test_finds_the_boxes_a_ray_passes_through_and_no_others() {
        // Axis-parallel rays (zero direction components) just inside and just outside box
        // faces, rays stopped early, a ray starting inside a box, and rays that miss.
        let mut node = Node {
            bounds: [[Vec4::splat(f32::INFINITY), Vec4::splat(f32::NEG_INFINITY)]; 3],
            child: [EMPTY; 4],
        };
        let boxes = [
            (Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 1.0)),
            (Vec3::new(2.0, 0.0, 0.0), Vec3::new(3.0, 1.0, 1.0)),
            (Vec3::new(0.0, 5.0, 0.0), Vec3::new(1.0, 6.0, 1.0)),
        ];
        for (l, (lo, hi)) in boxes.iter().enumerate() {
            for a in 0..3 {
                node.bounds[a][0][l] = lo[a];
                node.bounds[a][1][l] = hi[a];
            }
        }
        // Along +x just inside the top edges of boxes 0 and 1, and just outside them. (A ray
        // lying exactly in a face plane may miss: `Geometry` pads every box by a few ulps.)
        let inside = 1.0 - 1e-6;
        let r = BoxRay::new(Vec3::new(-1.0, inside, inside), Vec3::X);
        assert_eq!(r.hit_node(&node, f32::INFINITY).0, 0b011);
        let r2 = BoxRay::new(Vec3::new(-1.0, 1.0 + 1e-6, inside), Vec3::X);
        assert_eq!(r2.hit_node(&node, f32::INFINITY).0, 0);
        // The first ray (entering box 0 at t = 1, box 1 at t = 3) stopped earlier.
        assert_eq!(r.hit_node(&node, 3.5).0, 0b011);
        assert_eq!(r.hit_node(&node, 2.5).0, 0b001);
        assert_eq!(r.hit_node(&node, 0.5).0, 0);
        // Along −y at x = 0.5, z = 0.5 from above box 2: boxes 2 and 0.
        let r = BoxRay::new(Vec3::new(0.5, 10.0, 0.5), -Vec3::Y);
        assert_eq!(r.hit_node(&node, f32::INFINITY).0, 0b101);
        // Starting inside box 0, going −z: box 0 only (entry distance clamped to 0).
        let r = BoxRay::new(Vec3::new(0.5, 0.5, 0.5), -Vec3::Z);
        let (mask, t0) = r.hit_node(&node, f32::INFINITY);
        assert_eq!(mask, 0b001);
        assert_eq!(t0[0], 0.0);
        // Missing everything; the empty fourth lane is never hit.
        let r = BoxRay::new(Vec3::new(-1.0, 3.0, 0.5), Vec3::X);
        assert_eq!(r.hit_node(&node, f32::INFINITY).0, 0);
    }
}
