//! The two traversals (closest hit, any hit), written once for every node width.

use super::WideHit;
use super::counts;
use super::packet::{Fast, Packet};
use super::prefetch;
use super::stack::{STACK, Stack, StackBuf};
use crate::shape::mesh::TriangleRay;
use caustica_core::Vec3;
use std::mem::MaybeUninit;

/// Child references with this bit set are leaves: a run of packets; the others are nodes.
pub(super) const LEAF: u32 = 1 << 31;
/// A leaf reference's bits 28–30: the number of packets in its run, less one.
const RUN_SHIFT: u32 = 28;
/// A leaf reference's low bits: its first packet.
const FIRST_MASK: u32 = (1 << RUN_SHIFT) - 1;
/// Most packets in one leaf.
pub(super) const MAX_RUN: usize = 1 << (31 - RUN_SHIFT);

/// The reference of the leaf made of packets `first .. first + n` (`1 ≤ n ≤ MAX_RUN`, `first`
/// below 2²⁸: the builder's invariants).
pub(super) fn leaf_ref(first: usize, n: usize) -> u32 {
    debug_assert!((1..=MAX_RUN).contains(&n) && first <= FIRST_MASK as usize);
    LEAF | ((n as u32 - 1) << RUN_SHIFT) | first as u32
}

/// The packets of leaf reference `leaf`.
#[inline(always)]
pub(super) fn leaf_packets(packets: &[Packet], leaf: u32) -> &[Packet] {
    let first = (leaf & FIRST_MASK) as usize;
    let n = ((leaf >> RUN_SHIFT) & (MAX_RUN as u32 - 1)) as usize + 1;
    packets.get(first..first + n).unwrap_or(&[])
}

/// 1 + 2γ₃ (pbrt-v4, ε = 2⁻²⁴): the factor on a slab test's far distance that makes it
/// conservative under rounding.
pub(super) const ROBUST: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// Asks the CPU to bring node or leaf `child` into the cache: its node's lines, or its run's
/// packets' lines (two at most). Called for every child a ray enters, when the node is tested,
/// so that the loads of the children visited later overlap the work on the nearest one (on
/// incoherent rays through a tree far larger than the caches, +27 % rays per second on the
/// benchmark's random rays, +7 % on diffuse bounces, nothing on camera rays:
/// docs/performance.md).
#[inline(always)]
fn prefetch_child<N>(nodes: &[N], packets: &[Packet], child: u32) {
    // Nodes and packets are aligned to cache lines.
    let (p, bytes): (*const u8, usize) = if child & LEAF == 0 {
        (
            nodes.as_ptr().wrapping_add(child as usize).cast(),
            std::mem::size_of::<N>(),
        )
    } else {
        let run = ((child >> RUN_SHIFT) & (MAX_RUN as u32 - 1)) as usize + 1;
        (
            packets
                .as_ptr()
                .wrapping_add((child & FIRST_MASK) as usize)
                .cast(),
            run.min(2) * std::mem::size_of::<Packet>(),
        )
    };
    prefetch::lines(p, bytes);
}

/// An inner node of `W` children whose boxes one ray tests at once.
pub(super) trait WideNode<const W: usize>: Sized {
    /// A ray prepared for [`Self::hit`].
    type Ray;
    fn ray(o: Vec3, d: Vec3) -> Self::Ray;
    /// A node whose lanes are all empty (no ray hits them).
    fn empty() -> Self;
    /// Lane `lane` holds the box `[min, max]` of child `child`.
    fn set_lane(&mut self, lane: usize, min: Vec3, max: Vec3, child: u32);
    fn child(&self, lane: usize) -> u32;
    /// The lanes whose boxes the ray meets within `[0, t_max]` (bit `l` for lane `l`), and
    /// the entry distances (clamped to 0).
    ///
    /// # Safety
    /// The CPU must support the instructions of the node's kind (none beyond x86_64 for four
    /// lanes; AVX for eight).
    unsafe fn hit(&self, ray: &Self::Ray, t_max: f32) -> (u32, [f32; W]);
}

/// Where a closest-hit traversal starts: at the root with nothing found, or (the eight-ray
/// traversal handing a ray over) at a node or leaf below it with the ray's closest hit so far.
#[derive(Clone, Copy, Debug)]
pub(super) struct Start {
    /// The node or leaf reference the traversal starts from.
    pub(super) node: u32,
    /// Hits count only with `t < t_max` (or `t = t_max` and a primitive before `best`'s).
    pub(super) t_max: f32,
    /// The closest hit so far, at `t_max` (`None`: no hit yet).
    pub(super) best: Option<WideHit>,
}

impl Start {
    /// From the root, nothing found, hits closer than `t_max`.
    #[inline(always)]
    pub(super) fn root(t_max: f32) -> Self {
        Self {
            node: 0,
            t_max,
            best: None,
        }
    }
}

/// The closest hit with `t ∈ (0, start.t_max)` below `start.node` (or `start.best`):
/// triangles tested here, every other primitive `k` (BVH order) by `other(k, t)`, which
/// returns `(t, b1, b2)` of a hit closer than `t`. Visits the hit children near to far and
/// skips stacked entries farther than the closest hit so far. Of triangles hit at exactly the
/// least distance (a ray through a vertex or an edge they share), the one first in BVH order
/// wins, so the result does not depend on the order of the visit, and the two node widths,
/// which share the BVH order, agree bit for bit. `on_hit(k)` is told of every triangle that
/// becomes the closest hit so far, while the traversal goes on (so a caller can prefetch what
/// it will read about the final hit).
///
/// # Safety
/// As [`WideNode::hit`]. `nodes` is non-empty, and child references index into `nodes` and
/// `packets` (the builder's invariant; indexing is checked anyway).
#[inline(always)]
pub(super) unsafe fn closest<N: WideNode<W>, const W: usize>(
    nodes: &[N],
    packets: &[Packet],
    tr: &TriangleRay,
    br: &N::Ray,
    start: Start,
    mut other: impl FnMut(u32, f32) -> Option<(f32, f32, f32)>,
    mut on_hit: impl FnMut(u32),
) -> Option<WideHit> {
    let (mut cur, mut t_max, mut best) = (start.node, start.t_max, start.best);
    let mut buf: StackBuf = [const { MaybeUninit::uninit() }; STACK];
    let mut stack: Stack = Stack::new(&mut buf);
    let prefetch = prefetch::worth(nodes);
    loop {
        // The hot loop calls nothing, so that the compiler can keep the prepared rays in
        // registers (every vector register is saved around a call). It leaves for what is
        // rare: a full stack array, a packet with other primitives or a ray exactly through an
        // edge, an empty stack array.
        let leave = 'hot: loop {
            if cur & LEAF == 0 {
                let node = &nodes[cur as usize];
                // SAFETY: the caller's contract.
                let (mut mask, t0) = unsafe { node.hit(br, t_max) };
                if mask != 0 {
                    let first = mask.trailing_zeros() as usize % W;
                    mask &= mask - 1;
                    if mask == 0 {
                        counts::node();
                        cur = node.child(first);
                        continue;
                    }
                    if stack.room() < W {
                        // (The node is tested again after the spill.)
                        break 'hot Leave::Full;
                    }
                    counts::node();
                    // Two or more children: visit the nearest, stack the rest far to near; ask
                    // for all of them from memory now.
                    if prefetch {
                        prefetch_child(nodes, packets, node.child(first));
                        let mut m = mask;
                        while m != 0 {
                            let l = m.trailing_zeros() as usize % W;
                            m &= m - 1;
                            prefetch_child(nodes, packets, node.child(l));
                        }
                    }
                    let second = mask.trailing_zeros() as usize % W;
                    mask &= mask - 1;
                    let (a, b) = (
                        (t0[first], node.child(first)),
                        (t0[second], node.child(second)),
                    );
                    // Of equal entry distances the lower lane goes first, as the sort below
                    // keeps.
                    let (near, far) = if b.0 < a.0 { (b, a) } else { (a, b) };
                    if mask == 0 {
                        // Two children, the commonest case: no sort.
                        stack.push_within(far);
                        cur = near.1;
                        continue;
                    }
                    // Three or more: insertion sort by entry distance (stable: lanes in order).
                    let mut hits = [near; W];
                    hits[1] = far;
                    let mut n = 2;
                    while mask != 0 {
                        let l = mask.trailing_zeros() as usize % W;
                        mask &= mask - 1;
                        let e = (t0[l], node.child(l));
                        let mut j = n;
                        while j > 0 && hits[j - 1].0 > e.0 {
                            hits[j] = hits[j - 1];
                            j -= 1;
                        }
                        hits[j % W] = e;
                        n += 1;
                    }
                    for &e in hits[1..n].iter().rev() {
                        stack.push_within(e);
                    }
                    cur = hits[0].1;
                    continue;
                }
                counts::node();
            } else {
                for (j, pk) in leaf_packets(packets, cur).iter().enumerate() {
                    if pk.other_mask != 0 {
                        break 'hot Leave::Leaf(j);
                    }
                    let tie_below = best.map_or(0, |h: WideHit| h.prim);
                    match pk.closest_triangle_fast(tr, t_max, tie_below) {
                        Fast::Miss => {}
                        Fast::Hit(t, l, b1, b2) => {
                            t_max = t;
                            on_hit(pk.prim[l]);
                            best = Some(WideHit {
                                t,
                                prim: pk.prim[l],
                                b1,
                                b2,
                            });
                        }
                        Fast::Scalar => break 'hot Leave::Leaf(j),
                    }
                    counts::packet();
                }
            }
            match next_within(&mut stack, t_max) {
                Some(c) => cur = c,
                None => break 'hot Leave::Empty,
            }
        };
        match leave {
            Leave::Full => {
                stack.spill_half();
                continue;
            }
            Leave::Leaf(j) => {
                // The rest of the leaf, from packet `j`, with every test.
                let run = leaf_packets(packets, cur);
                for pk in run.get(j..).unwrap_or(&[]) {
                    counts::packet();
                    let tie_below = best.map_or(0, |h: WideHit| h.prim);
                    if let Some((t, l, b1, b2)) = pk.closest_triangle(tr, t_max, tie_below) {
                        t_max = t;
                        on_hit(pk.prim[l]);
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
            }
            Leave::Empty => {}
        }
        // Next stacked child that may still hold a closer hit, refilling the array from the
        // spill.
        loop {
            if let Some(c) = next_within(&mut stack, t_max) {
                cur = c;
                break;
            }
            if !stack.refill() {
                return best;
            }
        }
    }
}

/// Why a traversal's hot loop left it.
enum Leave {
    /// The stack array has no room for a node's children: spill.
    Full,
    /// Packet `j` of the current leaf and those after it need the calls: other primitives,
    /// or the scalar test of a ray exactly through an edge.
    Leaf(usize),
    /// The stack array is empty: refill it, or the traversal is done.
    Empty,
}

/// The next stacked child that may still hold a hit closer than `t_max` (entries farther are
/// dropped); `None` when the stack array is empty.
#[inline(always)]
fn next_within(stack: &mut Stack, t_max: f32) -> Option<u32> {
    loop {
        match stack.pop_within() {
            None => return None,
            Some((t, c)) if t <= t_max * ROBUST => return Some(c),
            Some(_) => {}
        }
    }
}

/// True if any primitive below node or leaf `start` (the root: 0) is hit with
/// `t ∈ (0, t_max)`; `other` as for [`closest`] (only whether it returns a hit matters). Stops
/// at the first hit.
///
/// # Safety
/// As [`closest`].
#[inline(always)]
pub(super) unsafe fn any<N: WideNode<W>, const W: usize>(
    nodes: &[N],
    packets: &[Packet],
    tr: &TriangleRay,
    br: &N::Ray,
    t_max: f32,
    start: u32,
    mut other: impl FnMut(u32, f32) -> Option<(f32, f32, f32)>,
) -> bool {
    let mut buf: StackBuf = [const { MaybeUninit::uninit() }; STACK];
    let mut stack: Stack = Stack::new(&mut buf);
    let mut cur = start;
    let prefetch = prefetch::worth(nodes);
    loop {
        // The hot loop calls nothing, as in `closest`.
        let leave = 'hot: loop {
            if cur & LEAF == 0 {
                let node = &nodes[cur as usize];
                // SAFETY: the caller's contract.
                let (mut mask, _) = unsafe { node.hit(br, t_max) };
                if mask != 0 {
                    let first = mask.trailing_zeros() as usize % W;
                    mask &= mask - 1;
                    if mask != 0 && stack.room() < W {
                        // (The node is tested again after the spill.)
                        break 'hot Leave::Full;
                    }
                    counts::node();
                    while mask != 0 {
                        let l = mask.trailing_zeros() as usize % W;
                        mask &= mask - 1;
                        if prefetch {
                            prefetch_child(nodes, packets, node.child(l));
                        }
                        stack.push_within((0.0, node.child(l)));
                    }
                    cur = node.child(first);
                    continue;
                }
                counts::node();
            } else {
                for (j, pk) in leaf_packets(packets, cur).iter().enumerate() {
                    if pk.other_mask != 0 {
                        break 'hot Leave::Leaf(j);
                    }
                    match pk.closest_triangle_fast(tr, t_max, 0) {
                        Fast::Miss => {}
                        Fast::Hit(..) => return true,
                        Fast::Scalar => break 'hot Leave::Leaf(j),
                    }
                    counts::packet();
                }
            }
            match stack.pop_within() {
                Some((_, c)) => cur = c,
                None => break 'hot Leave::Empty,
            }
        };
        match leave {
            Leave::Full => {
                stack.spill_half();
                continue;
            }
            Leave::Leaf(j) => {
                let run = leaf_packets(packets, cur);
                for pk in run.get(j..).unwrap_or(&[]) {
                    counts::packet();
                    if pk.closest_triangle(tr, t_max, 0).is_some() {
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
            }
            Leave::Empty => {}
        }
        loop {
            if let Some((_, c)) = stack.pop_within() {
                cur = c;
                break;
            }
            if !stack.refill() {
                return false;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{BvhWidth, WideBvh};
    use crate::shape::mesh::TriangleRay;
    use caustica_core::Vec3;
    use caustica_core::sampling::Pcg32;

    #[test]
    fn traversals_that_spill_find_what_a_scan_finds() {
        // A soup of large, overlapping triangles: rays enter many boxes at once, so the unit
        // tests' 16-entry stack array spills and refills. Every hit must be the brute-force
        // scan's (least distance, then least BVH order), at both widths.
        let mut rng = Pcg32::new(21, 4);
        let mut u = || rng.next_f32() * 2.0 - 1.0;
        let tris: Vec<[Vec3; 3]> = (0..3000)
            .map(|_| {
                let c = Vec3::new(u(), u(), u());
                [
                    c + Vec3::new(u(), u(), u()) * 0.6,
                    c + Vec3::new(u(), u(), u()) * 0.6,
                    c + Vec3::new(u(), u(), u()) * 0.6,
                ]
            })
            .collect();
        for width in [BvhWidth::Four, BvhWidth::Eight] {
            let bvh = WideBvh::over_triangles(&tris, width);
            let order = bvh.order().to_vec();
            let (mut hits, mut blocked) = (0, 0);
            for i in 0..400 {
                let o = Vec3::new(u(), u(), u()) * 2.0;
                let Some(d) = Vec3::new(u(), u(), u()).try_normalize() else {
                    continue;
                };
                let t_max = if i % 4 == 0 { 0.3 } else { f32::INFINITY };
                let tr = TriangleRay::new(o, d);
                // The scan in BVH order keeps the first of equal distances.
                let mut expected = None;
                let mut tm = t_max;
                for (k, &input) in order.iter().enumerate() {
                    let [a, b, c] = tris[input as usize];
                    if let Some((t, b1, b2)) = tr.intersect(tm, a, b, c) {
                        tm = t;
                        expected = Some((t.to_bits(), k as u32, b1.to_bits(), b2.to_bits()));
                    }
                }
                let got = bvh
                    .closest(o, d, &tr, t_max, |_, _| None, |_| {})
                    .map(|h| (h.t.to_bits(), h.prim, h.b1.to_bits(), h.b2.to_bits()));
                assert_eq!(got, expected, "{width:?} ray {i}");
                let any = bvh.any(o, d, &tr, t_max, |_, _| None);
                assert_eq!(any, expected.is_some(), "{width:?} ray {i}");
                hits += got.is_some() as u32;
                blocked += any as u32;
            }
            assert!(hits > 100 && blocked > 100, "{width:?}: hits {hits}");
        }
    }
}
