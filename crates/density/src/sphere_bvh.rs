//! A bounding volume hierarchy over spheres with their own radii, queried by ray segment: "which
//! spheres does this segment cross?" — the photon gather of the beam radiance estimate (seed 000
//! eq. 8.4, [`crate::beam`]), one query per eye-ray segment instead of one per sample point.
//!
//! # Why our own
//!
//! The beam estimate needs *every* sphere a segment meets, visited through a callback without
//! allocating, with the segment's `[t0, t1]` (not a whole ray) culling the tree. The `bvh`
//! crate's traversal returns a freshly allocated `Vec` of candidate shapes per ray, is built on
//! its own vector types (nalgebra) and does not clip to a segment; `obvhs` is built around
//! closest-hit traversal of triangles and a `glam` version of its own. The hierarchy here is
//! small (one binary tree, a stack of node indices) and answers exactly this query.
//!
//! # Layout and build
//!
//! A binary BVH in depth-first order: node `i`'s left child is `i + 1`, its right child is
//! stored. A node is 32 bytes (an axis-aligned box and two `u32`); the spheres are stored once
//! in leaf order as `(centre, radius)` (16 bytes) with their original index (4 bytes). The SAH
//! makes leaves of about two spheres on average, so there is about one node per sphere: about
//! 50 bytes per sphere in all ([`SphereBvh::memory_bytes`]; the benchmark prints it).
//!
//! Nodes are split by the surface-area heuristic over [`BINS`] bins of the centroids along the
//! axis of largest centroid extent (traversal cost 1, sphere test cost 1); ranges with no
//! better split than a leaf become leaves when they have at most [`MAX_LEAF`] spheres, and
//! ranges with coincident centroids or depth beyond [`SAH_MAX_DEPTH`] are split at the median,
//! so the tree's depth stays below the traversal stack's [`STACK`] entries. The build is
//! single-threaded and deterministic: the tree depends only on the input.
//!
//! # Query and order
//!
//! [`SphereBvh::for_each_crossing`] calls `f(i, centre, radius)` for each sphere `i` whose open
//! ball the closed segment `{o + tω : t0 <= t <= t1}` meets (closest point of the segment to the
//! centre at distance `< r`), each exactly once, in **tree order**: a fixed permutation of the
//! spheres that depends only on the build input, not on the segment (subtrees are always
//! visited left before right). A renderer that sums f32 contributions in callback order is
//! therefore reproducible for a fixed photon map. Spheres whose centre or radius is not finite, or whose
//! radius is not positive, are left out.
//!
//! Box tests use the slab method with the far distance enlarged by `2γ₃` (Pharr, Jakob and
//! Humphreys, *PBRT* 3rd ed., sec. 3.9.2), so that rounding never culls a box the segment
//! touches; the leaves then test each sphere exactly.

use caustica_core::Vec3;

use crate::beam::RaySegment;

/// Largest number of spheres in a leaf.
pub const MAX_LEAF: usize = 4;
/// Number of SAH bins per split.
pub const BINS: usize = 16;
/// Depth beyond which ranges are split at the median (at most 32 more levels follow).
pub const SAH_MAX_DEPTH: usize = 64;
/// Traversal stack entries: more than the deepest possible tree.
const STACK: usize = SAH_MAX_DEPTH + 40;

/// `2γ₃ = 6ε/(1 − 3ε)` with `ε` half an ulp of 1 (PBRT's conservative ray–box test).
const SLAB_ENLARGE: f32 = 1.0 + 2.0 * (3.0 * 0.5 * f32::EPSILON) / (1.0 - 3.0 * 0.5 * f32::EPSILON);

/// Relative padding of the spheres' boxes, 2⁻²¹ (four ulps of 1).
const BOX_PAD: f32 = 1.0 / (1u32 << 21) as f32;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
struct Node {
    lo: [f32; 3],
    /// Leaf: first sphere; inner node: index of the right child.
    offset: u32,
    hi: [f32; 3],
    /// Number of spheres of a leaf; 0 for an inner node.
    count: u32,
}

#[derive(Clone, Copy, Debug)]
struct Item {
    c: [f32; 3],
    r: f32,
    index: u32,
}

#[derive(Clone, Copy, Debug)]
struct Aabb {
    lo: [f32; 3],
    hi: [f32; 3],
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        lo: [f32::INFINITY; 3],
        hi: [f32::NEG_INFINITY; 3],
    };

    fn grow_box(&mut self, o: &Aabb) {
        for d in 0..3 {
            self.lo[d] = self.lo[d].min(o.lo[d]);
            self.hi[d] = self.hi[d].max(o.hi[d]);
        }
    }

    fn grow_point(&mut self, p: &[f32; 3]) {
        self.grow_box(&Aabb { lo: *p, hi: *p });
    }

    /// The sphere's box, padded by a few ulps of its coordinates so that the rounding of
    /// `c ± r` cannot cut off a point the exact sphere test accepts.
    fn of_sphere(it: &Item) -> Aabb {
        let mag = it.c[0].abs().max(it.c[1].abs()).max(it.c[2].abs()) + it.r;
        let r = it.r + mag * BOX_PAD;
        Aabb {
            lo: [it.c[0] - r, it.c[1] - r, it.c[2] - r],
            hi: [it.c[0] + r, it.c[1] + r, it.c[2] + r],
        }
    }

    /// Half the surface area (the SAH's relative probability of a hit); 0 if empty.
    fn half_area(&self) -> f32 {
        let e = [
            (self.hi[0] - self.lo[0]).max(0.0),
            (self.hi[1] - self.lo[1]).max(0.0),
            (self.hi[2] - self.lo[2]).max(0.0),
        ];
        e[0] * e[1] + e[1] * e[2] + e[2] * e[0]
    }
}

/// A BVH over spheres, queried by ray segment (see the [module docs](self)).
#[derive(Clone, Debug, Default)]
pub struct SphereBvh {
    nodes: Vec<Node>,
    /// `(centre, radius)` in leaf order.
    spheres: Vec<[f32; 4]>,
    /// Original index of each entry of `spheres`.
    index: Vec<u32>,
}

impl SphereBvh {
    /// Builds the hierarchy over sphere `i` with centre `centres[i]` (m) and radius `radii[i]`
    /// (m); spheres with a non-finite centre or a radius that is not positive and finite are
    /// left out (see the [module docs](self)).
    ///
    /// # Panics
    ///
    /// If the slices differ in length, or there are more than `u32::MAX` spheres.
    pub fn build(centres: &[Vec3], radii: &[f32]) -> Self {
        assert_eq!(
            centres.len(),
            radii.len(),
            "SphereBvh::build: one radius per centre"
        );
        assert!(u32::try_from(centres.len()).is_ok(), "too many spheres");
        let mut items: Vec<Item> = centres
            .iter()
            .zip(radii)
            .enumerate()
            .filter(|(_, (c, r))| c.is_finite() && r.is_finite() && **r > 0.0)
            .map(|(i, (c, r))| Item {
                c: c.to_array(),
                r: *r,
                index: i as u32,
            })
            .collect();
        let mut nodes = Vec::with_capacity(2 * items.len() / MAX_LEAF.max(1) + 1);
        if !items.is_empty() {
            build_rec(&mut items, 0, 0, &mut nodes);
        }
        nodes.shrink_to_fit();
        Self {
            nodes,
            spheres: items
                .iter()
                .map(|it| [it.c[0], it.c[1], it.c[2], it.r])
                .collect(),
            index: items.iter().map(|it| it.index).collect(),
        }
    }

    /// Number of spheres in the hierarchy (those with a valid centre and radius).
    pub fn len(&self) -> usize {
        self.spheres.len()
    }

    /// Whether the hierarchy holds no sphere.
    pub fn is_empty(&self) -> bool {
        self.spheres.is_empty()
    }

    /// Heap bytes of the nodes, spheres and index map.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.capacity() * std::mem::size_of::<Node>()
            + self.spheres.capacity() * std::mem::size_of::<[f32; 4]>()
            + self.index.capacity() * std::mem::size_of::<u32>()
    }

    /// Calls `f(i, centre, radius)` once for every sphere `i` (its position in the slices given
    /// to [`SphereBvh::build`]) whose open ball the segment meets, in tree order (see the
    /// [module docs](self#query-and-order)). The centre and radius come from the tree's own
    /// copy, which is in cache (looking them up by `i` is a random access). `seg.dir` need not
    /// be unit length here; a segment with `t0 > t1` or a NaN meets nothing.
    pub fn for_each_crossing(&self, seg: &RaySegment, mut f: impl FnMut(u32, Vec3, f32)) {
        // False for NaN bounds.
        let ordered = seg.t0 <= seg.t1;
        if self.nodes.is_empty() || !ordered {
            return;
        }
        let o = seg.origin.to_array();
        let w = seg.dir.to_array();
        let inv = [1.0 / w[0], 1.0 / w[1], 1.0 / w[2]];
        let inv_w2 = 1.0 / seg.dir.length_squared();
        if !inv_w2.is_finite() {
            return;
        }
        let mut stack = [0u32; STACK];
        let mut sp = 0usize;
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            if slab_hit(n, &o, &inv, seg.t0, seg.t1) {
                if n.count == 0 {
                    stack[sp] = n.offset;
                    sp += 1;
                    node += 1;
                    continue;
                }
                let first = n.offset as usize;
                for k in first..first + n.count as usize {
                    let s = &self.spheres[k];
                    if segment_meets_ball(s, &o, &w, inv_w2, seg.t0, seg.t1) {
                        f(self.index[k], Vec3::new(s[0], s[1], s[2]), s[3]);
                    }
                }
            }
            if sp == 0 {
                return;
            }
            sp -= 1;
            node = stack[sp] as usize;
        }
    }
}

/// Whether the closed segment `o + t w`, `t ∈ [t0, t1]`, meets the open ball `s = (c, r)`:
/// the segment's closest point to `c` is at distance `< r`. `inv_w2 = 1/|w|²`.
#[inline(always)]
pub(crate) fn segment_meets_ball(
    s: &[f32; 4],
    o: &[f32; 3],
    w: &[f32; 3],
    inv_w2: f32,
    t0: f32,
    t1: f32,
) -> bool {
    let d = [s[0] - o[0], s[1] - o[1], s[2] - o[2]];
    let t = ((d[0] * w[0] + d[1] * w[1] + d[2] * w[2]) * inv_w2).clamp(t0, t1);
    let e = [d[0] - t * w[0], d[1] - t * w[1], d[2] - t * w[2]];
    e[0] * e[0] + e[1] * e[1] + e[2] * e[2] < s[3] * s[3]
}

/// Conservative slab test of the segment against the node's box.
#[inline(always)]
fn slab_hit(n: &Node, o: &[f32; 3], inv: &[f32; 3], t0: f32, t1: f32) -> bool {
    let mut near = t0;
    let mut far = t1;
    for d in 0..3 {
        let a = (n.lo[d] - o[d]) * inv[d];
        let b = (n.hi[d] - o[d]) * inv[d];
        // NaN is 0·∞: the segment is parallel to the slab and lies in one of its planes, so
        // inside it; that axis does not constrain t.
        let (ta, tb) = if a <= b {
            (a, b)
        } else if b < a {
            (b, a)
        } else {
            continue;
        };
        near = near.max(ta);
        far = far.min(tb * SLAB_ENLARGE);
    }
    near <= far
}

/// Builds the subtree of `items` (which start at position `first` of the final sphere array)
/// into `nodes`, depth-first.
fn build_rec(items: &mut [Item], first: usize, depth: usize, nodes: &mut Vec<Node>) {
    let mut bounds = Aabb::EMPTY;
    let mut cbounds = Aabb::EMPTY;
    for it in items.iter() {
        bounds.grow_box(&Aabb::of_sphere(it));
        cbounds.grow_point(&it.c);
    }
    let me = nodes.len();
    nodes.push(Node {
        lo: bounds.lo,
        offset: first as u32,
        hi: bounds.hi,
        count: items.len() as u32,
    });
    let n = items.len();
    if n <= 1 {
        return;
    }
    let ext = [
        cbounds.hi[0] - cbounds.lo[0],
        cbounds.hi[1] - cbounds.lo[1],
        cbounds.hi[2] - cbounds.lo[2],
    ];
    let axis = if ext[0] >= ext[1] && ext[0] >= ext[2] {
        0
    } else if ext[1] >= ext[2] {
        1
    } else {
        2
    };
    let mid = if ext[axis] > 0.0 && depth < SAH_MAX_DEPTH {
        match sah_split(items, &cbounds, axis, bounds.half_area()) {
            Some(mid) => mid,
            None if n <= MAX_LEAF => return,
            None => median_split(items, axis),
        }
    } else if n <= MAX_LEAF {
        return;
    } else {
        median_split(items, axis)
    };
    // An inner node: fix up the node pushed above.
    nodes[me].count = 0;
    let (left, right) = items.split_at_mut(mid);
    build_rec(left, first, depth + 1, nodes);
    nodes[me].offset = nodes.len() as u32;
    build_rec(right, first + mid, depth + 1, nodes);
}

/// Splits at the median along `axis` (ties broken by index, so the result is determined).
fn median_split(items: &mut [Item], axis: usize) -> usize {
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |a, b| {
        a.c[axis].total_cmp(&b.c[axis]).then(a.index.cmp(&b.index))
    });
    mid
}

/// The best binned-SAH split along `axis`: partitions `items` and returns the size of the left
/// part, or `None` when no split is cheaper than a leaf (cost `n`).
fn sah_split(items: &mut [Item], cb: &Aabb, axis: usize, half_area: f32) -> Option<usize> {
    let lo = cb.lo[axis];
    let scale = BINS as f32 / (cb.hi[axis] - lo);
    let bin_of = |it: &Item| (((it.c[axis] - lo) * scale) as usize).min(BINS - 1);
    let mut count = [0usize; BINS];
    let mut boxes = [Aabb::EMPTY; BINS];
    for it in items.iter() {
        let b = bin_of(it);
        count[b] += 1;
        boxes[b].grow_box(&Aabb::of_sphere(it));
    }
    // Sweep from the right: area and count of bins [k, BINS).
    let mut right_area = [0.0f32; BINS];
    let mut right_count = [0usize; BINS];
    let mut acc = Aabb::EMPTY;
    let mut cnt = 0;
    for k in (1..BINS).rev() {
        acc.grow_box(&boxes[k]);
        cnt += count[k];
        right_area[k] = acc.half_area();
        right_count[k] = cnt;
    }
    let mut best = (f32::INFINITY, 0usize);
    let mut acc = Aabb::EMPTY;
    let mut cnt = 0;
    for k in 1..BINS {
        acc.grow_box(&boxes[k - 1]);
        cnt += count[k - 1];
        if cnt == 0 || right_count[k] == 0 {
            continue;
        }
        let cost = acc.half_area() * cnt as f32 + right_area[k] * right_count[k] as f32;
        if cost < best.0 {
            best = (cost, k);
        }
    }
    let n = items.len();
    if best.1 == 0 {
        return None;
    }
    // Relative cost of the split: 1 (traversal) + the expected sphere tests.
    let split_cost = 1.0 + best.0 / half_area.max(f32::MIN_POSITIVE);
    if n <= MAX_LEAF && split_cost >= n as f32 {
        return None;
    }
    let k = best.1;
    let mut mid = 0;
    for i in 0..n {
        if bin_of(&items[i]) < k {
            items.swap(i, mid);
            mid += 1;
        }
    }
    (mid > 0 && mid < n).then_some(mid)
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::Pcg32;

    /// Every sphere whose open ball the closed segment meets, by the segment's closest point
    /// to each centre computed in f64 (independently of the tree's own sphere test).
    fn brute_force(centres: &[Vec3], radii: &[f32], seg: &RaySegment) -> Vec<u32> {
        let (o, w) = (seg.origin.as_dvec3(), seg.dir.as_dvec3());
        let (t0, t1) = (f64::from(seg.t0), f64::from(seg.t1));
        (0..centres.len() as u32)
            .filter(|&i| {
                let (c, r) = (centres[i as usize], radii[i as usize]);
                if !(c.is_finite() && r.is_finite() && r > 0.0 && t0 <= t1) {
                    return false;
                }
                let d = c.as_dvec3() - o;
                let t = (d.dot(w) / w.length_squared()).clamp(t0, t1);
                (d - w * t).length() < f64::from(r)
            })
            .collect()
    }

    fn unit(rng: &mut Pcg32) -> Vec3 {
        loop {
            let v = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0;
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }

    /// Random spheres (clustered and spread, radii over three decades, some invalid) and
    /// segments (long, short, starting and ending inside spheres, axis-aligned, infinite):
    /// the BVH reports exactly the brute-force set, each sphere once, and the same order for
    /// the same segment.
    #[test]
    fn agrees_with_brute_force() {
        let mut rng = Pcg32::new(17, 19);
        let n = 3000;
        let centres: Vec<Vec3> = (0..n)
            .map(|i| {
                let p = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                if i % 3 == 0 { p * 0.1 + 0.45 } else { p }
            })
            .collect();
        let mut radii: Vec<f32> = (0..n)
            .map(|_| 0.001 * 1000f32.powf(rng.next_f32()) * 0.1)
            .collect();
        radii[0] = 0.0;
        radii[1] = f32::NAN;
        radii[2] = -1.0;
        radii[3] = f32::INFINITY;
        let mut centres = centres;
        centres[4] = Vec3::NAN;
        // Coincident centres (the median fallback).
        centres[5..40].fill(Vec3::splat(0.3));
        let bvh = SphereBvh::build(&centres, &radii);
        assert_eq!(bvh.len(), n - 5);
        let mut total = 0;
        for j in 0..600 {
            let seg = match j % 6 {
                // Through the volume from outside.
                0 => {
                    let o = Vec3::splat(0.5) - unit(&mut rng) * 2.0;
                    let target = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                    RaySegment::new(o, (target - o).normalize(), 0.0, 4.0)
                }
                // Starting at a sphere's centre (inside it), short.
                1 => {
                    let i = 5 + (rng.next_u32() as usize) % (n - 5);
                    RaySegment::new(centres[i], unit(&mut rng), 0.0, 0.05 * rng.next_f32())
                }
                // Ending inside a sphere: from far away to just short of a centre.
                2 => {
                    let i = 5 + (rng.next_u32() as usize) % (n - 5);
                    let w = unit(&mut rng);
                    let o = centres[i] - w * 0.7;
                    RaySegment::new(o, w, 0.2, 0.7 - 0.5 * radii[i].min(1.0))
                }
                // Axis-aligned (infinite reciprocals), infinite end.
                3 => {
                    let o = Vec3::new(rng.next_f32(), rng.next_f32(), -1.0);
                    RaySegment::new(o, Vec3::Z, 0.0, f32::INFINITY)
                }
                // Through the coincident cluster, not unit length.
                4 => RaySegment::new(Vec3::new(-1.0, 0.3, 0.3), Vec3::X * 3.0, 0.0, 1.0),
                // A point-like segment inside the volume.
                _ => {
                    let o = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                    RaySegment::new(o, unit(&mut rng), 0.5, 0.5)
                }
            };
            let mut got = Vec::new();
            bvh.for_each_crossing(&seg, |i, c, r| {
                assert_eq!((c, r), (centres[i as usize], radii[i as usize]));
                got.push(i)
            });
            let mut again = Vec::new();
            bvh.for_each_crossing(&seg, |i, _, _| again.push(i));
            assert_eq!(got, again, "order changed between identical queries");
            got.sort_unstable();
            let want = brute_force(&centres, &radii, &seg);
            assert_eq!(got, want, "segment #{j} {seg:?}");
            total += want.len();
        }
        assert!(total > 5000, "too few crossings to test: {total}");
        // Reversed and NaN segments meet nothing; an empty hierarchy answers nothing.
        let seg = RaySegment::new(Vec3::ZERO, Vec3::X, 1.0, 0.0);
        bvh.for_each_crossing(&seg, |_, _, _| panic!("reversed segment"));
        let seg = RaySegment::new(Vec3::ZERO, Vec3::X, f32::NAN, 1.0);
        bvh.for_each_crossing(&seg, |_, _, _| panic!("NaN segment"));
        SphereBvh::build(&[], &[]).for_each_crossing(&seg, |_, _, _| panic!("empty"));
    }

    /// The tree is a function of the input alone: two builds give the same nodes, and a query
    /// the same callback sequence.
    #[test]
    fn build_is_deterministic_and_bounded() {
        let mut rng = Pcg32::new(23, 29);
        let n = 20_000;
        let centres: Vec<Vec3> = (0..n)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32() * 0.01, rng.next_f32()))
            .collect();
        let radii: Vec<f32> = (0..n).map(|_| 0.002 + 0.02 * rng.next_f32()).collect();
        let a = SphereBvh::build(&centres, &radii);
        let b = SphereBvh::build(&centres, &radii);
        assert_eq!(a.nodes, b.nodes);
        assert_eq!(a.index, b.index);
        // Leaves hold at most MAX_LEAF spheres (coincident centroids are split at the median).
        assert!(a.nodes.iter().all(|n| n.count as usize <= MAX_LEAF));
        let bytes = a.memory_bytes() as f64 / n as f64;
        // About 20 bytes of spheres and 30 of nodes (see the module docs).
        assert!(bytes < 56.0, "{bytes} bytes per sphere");
    }
}
