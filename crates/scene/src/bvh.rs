//! Bounding volume hierarchy (binned SAH build, stack traversal).
//!
//! The tree is built over primitive bounding boxes only; what a primitive *is* stays with the
//! caller ([`crate::geometry::Geometry`] stores its triangles, spheres and disks in the BVH's
//! primitive order so leaves read contiguous memory). Build: binned surface area heuristic
//! ([`BINS`] bins on each of the three axes, leaves of at most [`MAX_LEAF`] primitives), with
//! the top levels built in parallel by rayon. Nodes are flattened depth-first into 32-byte
//! [`BvhNode`]s (left child right after its parent). Traversal: slab tests with a precomputed
//! inverse direction, nearer child first, far child on a fixed-size stack together with its
//! entry distance so that stale entries are skipped.

use crate::shape::Aabb;
use caustica_core::{Vec3, Vec3A};
use glam::Vec4;
use rayon::prelude::*;

/// SAH bins per axis.
pub const BINS: usize = 16;
/// Largest leaf the SAH may create (leaves are forced to split above it).
pub const MAX_LEAF: usize = 4;
/// Subtrees at least this large are built in parallel.
const PARALLEL_THRESHOLD: usize = 16 * 1024;
/// Below this depth SAH splits; deeper nodes use median splits (bounds the stack depth).
const MAX_SAH_DEPTH: u32 = 48;
/// Traversal stack size; the build guarantees the depth stays below it.
const STACK_SIZE: usize = 96;
/// Relative cost of a node traversal step against one primitive test.
const TRAVERSAL_COST: f32 = 1.0;

/// One flattened node (32 bytes, two SIMD registers). `lo = (min, index)`,
/// `hi = (max, count)` with the integers stored as raw bits in the `w` lanes. Leaves have
/// `count > 0` primitives starting at `index` in the BVH primitive order; interior nodes have
/// `count == 0`, their left child at `self + 1` and the right child at `index`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct BvhNode {
    lo: Vec4,
    hi: Vec4,
}

const _: () = assert!(std::mem::size_of::<BvhNode>() == 32);

impl BvhNode {
    #[inline]
    fn new(bounds: Aabb, index: u32, count: u32) -> Self {
        Self {
            lo: bounds.min.extend(f32::from_bits(index)),
            hi: bounds.max.extend(f32::from_bits(count)),
        }
    }
    /// First primitive (leaf) or right child (interior node).
    #[inline(always)]
    pub fn index(&self) -> u32 {
        self.lo.w.to_bits()
    }
    /// Number of primitives; 0 for interior nodes.
    #[inline(always)]
    pub fn count(&self) -> u32 {
        self.hi.w.to_bits()
    }
    #[inline]
    fn set_index(&mut self, i: u32) {
        self.lo.w = f32::from_bits(i);
    }
    #[inline(always)]
    pub fn is_leaf(&self) -> bool {
        self.count() > 0
    }
    pub fn bounds(&self) -> Aabb {
        Aabb {
            min: self.lo.truncate(),
            max: self.hi.truncate(),
        }
    }

    /// Entry distance of the ray into the box if it overlaps `(0, t_max)`, else +∞.
    #[inline(always)]
    fn slab(&self, o: Vec3A, inv_d: Vec3A, t_max: f32) -> f32 {
        let t0 = (Vec3A::from_vec4(self.lo) - o) * inv_d;
        let t1 = (Vec3A::from_vec4(self.hi) - o) * inv_d;
        let t_near = t0.min(t1).max_element().max(0.0);
        // Conservative far distance (pbrt's 1 + 2γ₃) so rounding never skips a hit.
        let t_far = t0.max(t1).min_element() * (1.0 + 3.0 * f32::EPSILON);
        if t_near <= t_far && t_near < t_max {
            t_near
        } else {
            f32::INFINITY
        }
    }
}

/// A BVH over primitive bounding boxes.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    /// Flattened nodes; `nodes[0]` is the root. Empty when there are no primitives.
    pub nodes: Vec<BvhNode>,
    /// `prim_order[k]` is the index (into the slice given to [`Bvh::build`]) of the `k`-th
    /// primitive in BVH order; leaves refer to positions `k` in this order.
    pub prim_order: Vec<u32>,
}

#[derive(Clone, Copy)]
struct PrimRef {
    min: Vec3,
    max: Vec3,
    index: u32,
}

impl PrimRef {
    #[inline]
    fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    count: u32,
}

const EMPTY_BIN: Bin = Bin {
    bounds: Aabb::EMPTY,
    count: 0,
};

type Bins = [[Bin; BINS]; 3];

/// Bounds of the primitives and of their centroids.
fn ref_bounds(refs: &[PrimRef]) -> (Aabb, Aabb) {
    let fold = |(mut b, mut c): (Aabb, Aabb), r: &PrimRef| {
        b.min = b.min.min(r.min);
        b.max = b.max.max(r.max);
        c.grow(r.centroid());
        (b, c)
    };
    let merge = |a: (Aabb, Aabb), b: (Aabb, Aabb)| (a.0.union(&b.0), a.1.union(&b.1));
    if refs.len() >= PARALLEL_THRESHOLD {
        refs.par_chunks(4096)
            .map(|ch| ch.iter().fold((Aabb::EMPTY, Aabb::EMPTY), fold))
            .reduce(|| (Aabb::EMPTY, Aabb::EMPTY), merge)
    } else {
        refs.iter().fold((Aabb::EMPTY, Aabb::EMPTY), fold)
    }
}

#[inline]
fn bin_of(c: f32, cmin: f32, scale: f32) -> usize {
    (((c - cmin) * scale) as usize).min(BINS - 1)
}

fn fill_bins(refs: &[PrimRef], cmin: Vec3, scale: Vec3) -> Bins {
    let fold = |mut bins: Bins, r: &PrimRef| {
        let c = r.centroid();
        for a in 0..3 {
            let b = &mut bins[a][bin_of(c[a], cmin[a], scale[a])];
            b.bounds.min = b.bounds.min.min(r.min);
            b.bounds.max = b.bounds.max.max(r.max);
            b.count += 1;
        }
        bins
    };
    let merge = |mut a: Bins, b: Bins| {
        for ax in 0..3 {
            for i in 0..BINS {
                a[ax][i].bounds = a[ax][i].bounds.union(&b[ax][i].bounds);
                a[ax][i].count += b[ax][i].count;
            }
        }
        a
    };
    let empty = [[EMPTY_BIN; BINS]; 3];
    if refs.len() >= PARALLEL_THRESHOLD {
        refs.par_chunks(8192)
            .map(|ch| ch.iter().fold(empty, fold))
            .reduce(|| empty, merge)
    } else {
        refs.iter().fold(empty, fold)
    }
}

/// Best SAH split: (axis, last bin of the left side, cost relative to one primitive test).
fn best_split(bins: &Bins, axes: [bool; 3], parent_area: f32) -> Option<(usize, usize, f32)> {
    let mut best: Option<(usize, usize, f32)> = None;
    for (a, bins) in bins.iter().enumerate() {
        if !axes[a] {
            continue;
        }
        // Right-to-left sweep: area·count of bins (i+1..BINS).
        let mut right_cost = [0.0f32; BINS];
        let mut acc = Aabb::EMPTY;
        let mut n = 0u32;
        for i in (1..BINS).rev() {
            acc = acc.union(&bins[i].bounds);
            n += bins[i].count;
            right_cost[i - 1] = acc.surface_area() * n as f32;
        }
        let mut acc = Aabb::EMPTY;
        let mut n = 0u32;
        for i in 0..BINS - 1 {
            acc = acc.union(&bins[i].bounds);
            n += bins[i].count;
            let cost = TRAVERSAL_COST
                + (acc.surface_area() * n as f32 + right_cost[i])
                    / parent_area.max(f32::MIN_POSITIVE);
            if best.is_none_or(|b| cost < b.2) {
                best = Some((a, i, cost));
            }
        }
    }
    best
}

/// In-place partition; returns the number of elements for which `left` holds.
fn partition(refs: &mut [PrimRef], left: impl Fn(&PrimRef) -> bool) -> usize {
    let mut i = 0;
    let mut j = refs.len();
    while i < j {
        if left(&refs[i]) {
            i += 1;
        } else {
            j -= 1;
            refs.swap(i, j);
        }
    }
    i
}

fn leaf(bounds: Aabb, first: usize, count: usize) -> BvhNode {
    BvhNode::new(bounds, first as u32, count as u32)
}

/// Builds the subtree over `refs` (which start at position `first` of the primitive order),
/// appending its nodes to `nodes` (indices relative to `nodes`' start).
fn build_node(refs: &mut [PrimRef], first: usize, depth: u32, nodes: &mut Vec<BvhNode>) {
    let n = refs.len();
    let (bounds, cbounds) = ref_bounds(refs);
    if n == 1 {
        nodes.push(leaf(bounds, first, 1));
        return;
    }
    let ext = cbounds.extent();
    let axes = [ext.x > 0.0, ext.y > 0.0, ext.z > 0.0];
    let mut mid = 0;
    if depth < MAX_SAH_DEPTH && axes.iter().any(|&a| a) {
        let scale = Vec3::select(
            ext.cmpgt(Vec3::ZERO),
            (BINS as f32 * (1.0 - 1e-4)) / ext,
            Vec3::ZERO,
        );
        let bins = fill_bins(refs, cbounds.min, scale);
        if let Some((axis, split, cost)) = best_split(&bins, axes, bounds.surface_area()) {
            if n <= MAX_LEAF && n as f32 <= cost {
                nodes.push(leaf(bounds, first, n));
                return;
            }
            let (cmin, s) = (cbounds.min[axis], scale[axis]);
            mid = partition(refs, |r| bin_of(r.centroid()[axis], cmin, s) <= split);
        }
    } else if n <= MAX_LEAF {
        nodes.push(leaf(bounds, first, n));
        return;
    }
    if mid == 0 || mid == n {
        // No usable SAH split (all centroids in one bin, or too deep): median split.
        let axis = ext.max_position();
        mid = n / 2;
        refs.select_nth_unstable_by(mid, |a, b| {
            a.centroid()[axis].total_cmp(&b.centroid()[axis])
        });
    }
    let parent = nodes.len();
    nodes.push(BvhNode::new(bounds, 0, 0));
    let (left, right) = refs.split_at_mut(mid);
    if n >= PARALLEL_THRESHOLD {
        let (ln, rn) = rayon::join(
            || {
                let mut v = Vec::new();
                build_node(left, first, depth + 1, &mut v);
                v
            },
            || {
                let mut v = Vec::new();
                build_node(right, first + mid, depth + 1, &mut v);
                v
            },
        );
        append_shifted(nodes, ln);
        let right_index = nodes.len();
        append_shifted(nodes, rn);
        nodes[parent].set_index(right_index as u32);
    } else {
        build_node(left, first, depth + 1, nodes);
        let right_index = nodes.len() as u32;
        nodes[parent].set_index(right_index);
        build_node(right, first + mid, depth + 1, nodes);
    }
}

fn append_shifted(nodes: &mut Vec<BvhNode>, sub: Vec<BvhNode>) {
    let off = nodes.len() as u32;
    nodes.extend(sub.into_iter().map(|mut nd| {
        if !nd.is_leaf() {
            nd.set_index(nd.index() + off);
        }
        nd
    }));
}

impl Bvh {
    /// Builds the hierarchy over the boxes `bounds[i]`. Empty or non-finite boxes are left out
    /// (they can never be hit).
    pub fn build(bounds: &[Aabb]) -> Self {
        let mut refs: Vec<PrimRef> = bounds
            .par_iter()
            .enumerate()
            .filter(|(_, b)| !b.is_empty() && b.min.is_finite() && b.max.is_finite())
            .map(|(i, b)| PrimRef {
                min: b.min,
                max: b.max,
                index: i as u32,
            })
            .collect();
        let mut nodes = Vec::new();
        if !refs.is_empty() {
            nodes.reserve(refs.len() / 2 * 2);
            build_node(&mut refs, 0, 0, &mut nodes);
        }
        let prim_order = refs.iter().map(|r| r.index).collect();
        Self { nodes, prim_order }
    }

    /// Bounds of everything in the tree.
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, BvhNode::bounds)
    }

    /// Depth of the tree (0 when empty, 1 for a single leaf).
    pub fn depth(&self) -> usize {
        fn rec(nodes: &[BvhNode], i: usize) -> usize {
            let n = &nodes[i];
            if n.is_leaf() {
                1
            } else {
                1 + rec(nodes, i + 1).max(rec(nodes, n.index() as usize))
            }
        }
        if self.nodes.is_empty() {
            0
        } else {
            rec(&self.nodes, 0)
        }
    }

    /// Closest-hit traversal of `o + t d`, `t ∈ (0, t_max)`. `hit(k, t_max)` tests the
    /// primitive at position `k` of the BVH order and returns its distance if it is hit closer
    /// than `t_max`; the search then shrinks to that distance. Returns the final `t_max`.
    #[inline]
    pub fn closest_hit(
        &self,
        o: Vec3,
        d: Vec3,
        mut t_max: f32,
        mut hit: impl FnMut(u32, f32) -> Option<f32>,
    ) -> f32 {
        let Some(root) = self.nodes.first() else {
            return t_max;
        };
        let (o, inv_d) = (Vec3A::from(o), Vec3A::from(d).recip());
        if root.slab(o, inv_d, t_max) == f32::INFINITY {
            return t_max;
        }
        let mut stack = [(0u32, 0.0f32); STACK_SIZE];
        let mut sp = 0usize;
        let mut node = 0usize;
        loop {
            let nd = &self.nodes[node];
            if nd.is_leaf() {
                let first = nd.index();
                for k in first..first + nd.count() {
                    if let Some(t) = hit(k, t_max) {
                        t_max = t;
                    }
                }
            } else {
                let l = node + 1;
                let r = nd.index() as usize;
                let tl = self.nodes[l].slab(o, inv_d, t_max);
                let tr = self.nodes[r].slab(o, inv_d, t_max);
                match (tl < f32::INFINITY, tr < f32::INFINITY) {
                    (true, true) => {
                        let (near, far, tfar) = if tl <= tr { (l, r, tr) } else { (r, l, tl) };
                        stack[sp] = (far as u32, tfar);
                        sp += 1;
                        node = near;
                        continue;
                    }
                    (true, false) => {
                        node = l;
                        continue;
                    }
                    (false, true) => {
                        node = r;
                        continue;
                    }
                    (false, false) => {}
                }
            }
            // Pop the next entry that can still hold a closer hit.
            loop {
                if sp == 0 {
                    return t_max;
                }
                sp -= 1;
                let (n, t_entry) = stack[sp];
                if t_entry < t_max {
                    node = n as usize;
                    break;
                }
            }
        }
    }

    /// Any-hit traversal: true as soon as `hit(k, t_max)` reports a hit for some primitive
    /// whose box the ray `o + t d`, `t ∈ (0, t_max)`, passes through.
    #[inline]
    pub fn any_hit(
        &self,
        o: Vec3,
        d: Vec3,
        t_max: f32,
        mut hit: impl FnMut(u32, f32) -> bool,
    ) -> bool {
        let Some(root) = self.nodes.first() else {
            return false;
        };
        let (o, inv_d) = (Vec3A::from(o), Vec3A::from(d).recip());
        if root.slab(o, inv_d, t_max) == f32::INFINITY {
            return false;
        }
        let mut stack = [0u32; STACK_SIZE];
        let mut sp = 0usize;
        let mut node = 0usize;
        loop {
            let nd = &self.nodes[node];
            if nd.is_leaf() {
                let first = nd.index();
                for k in first..first + nd.count() {
                    if hit(k, t_max) {
                        return true;
                    }
                }
            } else {
                let l = node + 1;
                let r = nd.index() as usize;
                let hl = self.nodes[l].slab(o, inv_d, t_max) < f32::INFINITY;
                let hr = self.nodes[r].slab(o, inv_d, t_max) < f32::INFINITY;
                match (hl, hr) {
                    (true, true) => {
                        stack[sp] = r as u32;
                        sp += 1;
                        node = l;
                        continue;
                    }
                    (true, false) => {
                        node = l;
                        continue;
                    }
                    (false, true) => {
                        node = r;
                        continue;
                    }
                    (false, false) => {}
                }
            }
            if sp == 0 {
                return false;
            }
            sp -= 1;
            node = stack[sp] as usize;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::Pcg32;

    fn random_boxes(n: usize, seed: u64) -> Vec<Aabb> {
        let mut rng = Pcg32::new(seed, 0);
        (0..n)
            .map(|_| {
                let c = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 100.0;
                let e = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                Aabb {
                    min: c - e,
                    max: c + e,
                }
            })
            .collect()
    }

    fn contains(outer: &Aabb, inner: &Aabb) -> bool {
        outer.min.cmple(inner.min).all() && outer.max.cmpge(inner.max).all()
    }

    /// Checks structure: children inside parents, leaves small, primitives covered once.
    fn check(bvh: &Bvh, boxes: &[Aabb]) {
        let mut covered = vec![0u32; bvh.prim_order.len()];
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let n = bvh.nodes[i];
            if n.is_leaf() {
                assert!(n.count() as usize <= MAX_LEAF.max(1));
                for k in n.index()..n.index() + n.count() {
                    covered[k as usize] += 1;
                    let b = boxes[bvh.prim_order[k as usize] as usize];
                    assert!(contains(&n.bounds(), &b));
                }
            } else {
                let (l, r) = (i + 1, n.index() as usize);
                assert!(r > l && r < bvh.nodes.len());
                assert!(contains(&n.bounds(), &bvh.nodes[l].bounds()));
                assert!(contains(&n.bounds(), &bvh.nodes[r].bounds()));
                stack.extend([l, r]);
            }
        }
        assert!(covered.iter().all(|&c| c == 1));
    }

    #[test]
    fn node_is_32_bytes_and_round_trips_integers() {
        assert_eq!(std::mem::size_of::<BvhNode>(), 32);
        let b = Aabb {
            min: Vec3::ZERO,
            max: Vec3::ONE,
        };
        // Bit patterns that are NaNs as floats must survive.
        let n = BvhNode::new(b, 0x7fc0_0001, 0xffff_fff0);
        assert_eq!((n.index(), n.count()), (0x7fc0_0001, 0xffff_fff0));
        assert_eq!(n.bounds(), b);
    }

    #[test]
    fn structure_is_valid_sequential_and_parallel() {
        for n in [1usize, 2, 5, 100, 3000, 40_000] {
            let boxes = random_boxes(n, n as u64);
            let bvh = Bvh::build(&boxes);
            assert_eq!(bvh.prim_order.len(), n);
            check(&bvh, &boxes);
        }
    }

    #[test]
    fn empty_and_invalid_boxes() {
        let bvh = Bvh::build(&[]);
        assert!(bvh.nodes.is_empty() && bvh.bounds().is_empty());
        assert_eq!(bvh.depth(), 0);
        assert!(!bvh.any_hit(Vec3::ZERO, Vec3::X, f32::INFINITY, |_, _| true));
        let mut boxes = random_boxes(10, 1);
        boxes.push(Aabb::EMPTY);
        boxes.push(Aabb {
            min: Vec3::splat(f32::NAN),
            max: Vec3::ONE,
        });
        let bvh = Bvh::build(&boxes);
        assert_eq!(bvh.prim_order.len(), 10);
        check(&bvh, &boxes);
    }

    #[test]
    fn identical_boxes_stay_shallow() {
        let boxes = vec![
            Aabb {
                min: Vec3::ZERO,
                max: Vec3::ONE
            };
            10_000
        ];
        let bvh = Bvh::build(&boxes);
        check(&bvh, &boxes);
        // Median splits: depth ≈ log2(10000 / 4) + 1.
        assert!(bvh.depth() <= 14, "depth {}", bvh.depth());
    }

    #[test]
    fn closest_hit_visits_boxes_in_order() {
        // Boxes along +x; the traversal must report the nearest one first and then prune.
        let boxes: Vec<Aabb> = (0..64)
            .map(|i| Aabb {
                min: Vec3::new(i as f32 * 2.0, -0.5, -0.5),
                max: Vec3::new(i as f32 * 2.0 + 1.0, 0.5, 0.5),
            })
            .collect();
        let bvh = Bvh::build(&boxes);
        let mut tested = 0;
        let o = Vec3::new(-1.0, 0.0, 0.0);
        let t = bvh.closest_hit(o, Vec3::X, f32::INFINITY, |k, t_max| {
            tested += 1;
            let b = boxes[bvh.prim_order[k as usize] as usize];
            let t = b.min.x - o.x;
            (t < t_max).then_some(t)
        });
        assert_eq!(t, 1.0);
        assert!(tested <= 2 * MAX_LEAF, "tested {tested} primitives");
    }
}
