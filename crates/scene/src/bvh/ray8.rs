//! Eight rays traced together through the 8-wide tree (AVX2, x86_64): each node's boxes and
//! each packet's triangles are fetched once for the eight rays, which pays where rays are
//! coherent (camera rays, a tile's eye paths), the tree being far larger than the caches.
//! Each node is visited with the rays that entered its box; where few of them are left, each
//! goes on through the one-ray traversal ([`ONE_BY_ONE`]).
//!
//! Every ray gets exactly the hit the one-ray traversal gives it: the box test is the
//! one-ray test's arithmetic lane by lane (entry and exit per axis the min and max of the two
//! planes' distances), the triangle test is the watertight test's operations lane by lane
//! (rays exactly on an edge fall back to the scalar test, as there), and ties at equal
//! distance go to the first primitive in BVH order, as there. Only the order of the visit
//! differs, which the tie rule makes invisible. The rays of a packet must share the triangle
//! test's axis permutation (the dominant axis of their directions); the caller traces the
//! others one by one.

use super::WideHit;
use super::node8::{Node8, Ray8};
use super::packet::Packet;
use super::stack::{STACK, Stack, StackBuf};
use super::traverse::{self, LEAF, ROBUST, Start, WideNode, leaf_packets};
use crate::shape::mesh::TriangleRay;
use caustica_core::{Ray, Vec3};
use std::arch::x86_64::*;
use std::mem::MaybeUninit;

/// Eight rays as structure of arrays, prepared for the box and triangle tests.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(super) struct Rays8 {
    o: [[f32; 8]; 3],
    /// Reciprocal directions, as [`super::node4::safe_inverse3`] makes them.
    inv: [[f32; 8]; 3],
    sx: [f32; 8],
    sy: [f32; 8],
    sz: [f32; 8],
    t_max: [f32; 8],
    /// The shared axis permutation of the triangle test.
    k: [usize; 3],
    /// Lanes holding a ray of the packet.
    active: u32,
    /// The rays' frustum, where their directions agree in sign on every axis.
    frustum: Option<Frustum>,
}

/// Bounds on the slab distances of a packet's rays whose directions have the same sign along
/// each axis (after Reshetov et al. 2005 and Embree's coherent traversal): with `o` and `inv`
/// ranging over the rays' origins and reciprocal directions, along an axis of positive
/// directions a box's near plane `lo` gives each ray a distance `(lo − o) · inv` no less than
/// `min((lo − o_max) · inv_min, (lo − o_max) · inv_max)` and its far plane `hi` one no greater
/// than `max((hi − o_min) · inv_min, (hi − o_min) · inv_max)` (the planes and the origin
/// bounds swap along an axis of negative directions). Rounding is monotonic, so the bounds hold
/// for the rounded distances [`Slabs::test`] computes too: a box the frustum misses, every ray
/// misses.
#[derive(Clone, Copy, Debug)]
struct Frustum {
    /// Per axis, the near planes' side (0: the boxes' minima, for positive directions).
    near: [usize; 3],
    /// Per axis, the origin bound for the near plane (the greatest origin for positive
    /// directions, the least for negative) and for the far plane (the other).
    o_near: [f32; 3],
    o_far: [f32; 3],
    /// Per axis, the least and greatest reciprocal direction.
    inv_min: [f32; 3],
    inv_max: [f32; 3],
}

impl Frustum {
    /// All bounds zero, filled in by the constructors.
    const ZERO: Self = Frustum {
        near: [0; 3],
        o_near: [0.0; 3],
        o_far: [0.0; 3],
        inv_min: [0.0; 3],
        inv_max: [0.0; 3],
    };

    /// The frustum of the rays in `lanes` of `o` and `inv`, or `None` where some axis has
    /// directions of both signs (or no ray is given). NaN components are left out of the
    /// bounds (a ray with one meets no box).
    ///
    /// # Safety
    /// The CPU supports AVX2.
    #[target_feature(enable = "avx2")]
    fn new(o: &[[f32; 8]; 3], inv: &[[f32; 8]; 3], lanes: u32) -> Option<Self> {
        if lanes == 0 {
            return None;
        }
        let mut f = Self::ZERO;
        let on = lane_mask(lanes);
        let (inf, neg_inf) = (
            _mm256_set1_ps(f32::INFINITY),
            _mm256_set1_ps(f32::NEG_INFINITY),
        );
        // Lanes without a ray, and NaN components, count as +∞ for the least and −∞ for the
        // greatest.
        let bounds = |row: &[f32; 8]| {
            let v = load(row);
            let keep = _mm256_and_ps(on, _mm256_cmp_ps::<_CMP_ORD_Q>(v, v));
            (
                hmin(_mm256_blendv_ps(inf, v, keep)),
                hmax(_mm256_blendv_ps(neg_inf, v, keep)),
            )
        };
        for a in 0..3 {
            let (i_lo, i_hi) = bounds(&inv[a]);
            // Reciprocals are never zero (`safe_inverse3`).
            let positive = if i_lo > 0.0 {
                true
            } else if i_hi < 0.0 {
                false
            } else {
                return None;
            };
            let (o_lo, o_hi) = bounds(&o[a]);
            f.near[a] = if positive { 0 } else { 1 };
            (f.o_near[a], f.o_far[a]) = if positive { (o_hi, o_lo) } else { (o_lo, o_hi) };
            (f.inv_min[a], f.inv_max[a]) = (i_lo, i_hi);
        }
        Some(f)
    }

    /// The frustum as the scalar loop finds it: the reference the unit tests hold
    /// [`Self::new`] to.
    #[cfg(test)]
    fn scalar(o: &[[f32; 8]; 3], inv: &[[f32; 8]; 3], lanes: u32) -> Option<Self> {
        let mut f = Self::ZERO;
        if lanes == 0 {
            return None;
        }
        for a in 0..3 {
            // Lanes without a ray count as ±∞ (`f32::min` and `max` leave NaN out).
            let (mut o_lo, mut o_hi) = (f32::INFINITY, f32::NEG_INFINITY);
            let (mut i_lo, mut i_hi) = (f32::INFINITY, f32::NEG_INFINITY);
            for i in 0..8 {
                let on = lanes >> i & 1 == 1;
                let pick = |x: f32, none: f32| if on { x } else { none };
                o_lo = o_lo.min(pick(o[a][i], f32::INFINITY));
                o_hi = o_hi.max(pick(o[a][i], f32::NEG_INFINITY));
                i_lo = i_lo.min(pick(inv[a][i], f32::INFINITY));
                i_hi = i_hi.max(pick(inv[a][i], f32::NEG_INFINITY));
            }
            let positive = if i_lo > 0.0 {
                true
            } else if i_hi < 0.0 {
                false
            } else {
                return None;
            };
            f.near[a] = if positive { 0 } else { 1 };
            (f.o_near[a], f.o_far[a]) = if positive { (o_hi, o_lo) } else { (o_lo, o_hi) };
            (f.inv_min[a], f.inv_max[a]) = (i_lo, i_hi);
        }
        Some(f)
    }

    /// The children of `node` whose boxes some ray of the frustum may meet within
    /// `[0, t_far]` (`t_far` no less than any of those rays' own): [`Slabs::test`]'s entry
    /// and exit, bounded below and above ([`Frustum`]), compared alike.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn hit(&self, node: &Node8, t_far: f32) -> u32 {
        let zero = _mm256_setzero_ps();
        let mut t0 = zero;
        let mut t1 = _mm256_set1_ps(t_far);
        for a in 0..3 {
            // (Broadcasts the compiler hoists out of the traversal loop, or reloads as a spill
            // would be.)
            let (inv_min, inv_max) = (
                _mm256_set1_ps(self.inv_min[a]),
                _mm256_set1_ps(self.inv_max[a]),
            );
            let near = load(node.planes(a, self.near[a]));
            let far = load(node.planes(a, 1 - self.near[a]));
            let dn = _mm256_sub_ps(near, _mm256_set1_ps(self.o_near[a]));
            let df = _mm256_sub_ps(far, _mm256_set1_ps(self.o_far[a]));
            let lo = _mm256_min_ps(_mm256_mul_ps(dn, inv_min), _mm256_mul_ps(dn, inv_max));
            let hi = _mm256_max_ps(_mm256_mul_ps(df, inv_min), _mm256_mul_ps(df, inv_max));
            t0 = _mm256_max_ps(t0, lo);
            t1 = _mm256_min_ps(t1, hi);
        }
        let t1 = _mm256_mul_ps(t1, _mm256_set1_ps(ROBUST));
        _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OS>(t0, t1)) as u32 & node.used()
    }
}

impl Rays8 {
    /// A packet without rays: what its lanes hold where no ray is taken (origin 0, direction
    /// 1 and so reciprocal 1, the rest 0).
    const EMPTY: Self = Rays8 {
        o: [[0.0; 8]; 3],
        inv: [[1.0; 8]; 3],
        sx: [0.0; 8],
        sy: [0.0; 8],
        sz: [0.0; 8],
        t_max: [0.0; 8],
        k: [0, 1, 2],
        active: 0,
        frustum: None,
    };

    /// A packet of the rays of `rays` (at most eight) that [`crate::geometry::Geometry`]
    /// traces (`t_max > 0`) and whose triangle test permutation equals the first such ray's;
    /// returns the packet and the mask of the lanes it took. Each lane's fields are those of
    /// [`TriangleRay::new`] and [`super::node4::safe_inverse3`], by the same operations on eight
    /// lanes at once, so the packet is bit for bit the one the rays prepared one by one make
    /// (a unit test checks it against such a reference, `Rays8::new`). Where it would take
    /// `min_rays` or fewer rays, it stops before the reciprocals and the frustum and takes none
    /// (mask 0): a packet traversal would hand every ray over at the root where
    /// `min_rays` is [`ONE_BY_ONE`], and the caller traces them one by one anyway.
    ///
    /// # Safety
    /// The CPU supports AVX2.
    #[target_feature(enable = "avx2")]
    pub(super) fn from_rays(rays: &[Ray], min_rays: u32) -> (Self, u32) {
        let mut o = [[0.0f32; 8]; 3];
        let mut d = [[1.0f32; 8]; 3];
        let mut t_max = [0.0f32; 8];
        let mut present = 0u32;
        for (i, r) in rays.iter().take(8).enumerate() {
            let i = i & 7;
            for a in 0..3 {
                o[a][i] = r.o[a];
                d[a][i] = r.d[a];
            }
            t_max[i] = r.t_max;
            present |= 1 << i;
        }
        let zero = _mm256_setzero_ps();
        let sign = _mm256_set1_ps(-0.0);
        // `Geometry` traces rays with `t_max > 0` (not NaN).
        let valid =
            _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_GT_OQ>(load(&t_max), zero)) as u32 & present;
        // The permutation, as `TriangleRay::new`: `kz` the first axis of greatest |d|
        // (glam's `max_position`: y if |dy| > |dx|, then z if |dz| exceeds that), `kx` and
        // `ky` the next two, swapped where `d_kz < 0`.
        let (dx, dy, dz) = (load(&d[0]), load(&d[1]), load(&d[2]));
        let (ax, ay, az) = (
            _mm256_andnot_ps(sign, dx),
            _mm256_andnot_ps(sign, dy),
            _mm256_andnot_ps(sign, dz),
        );
        let y_gt = _mm256_cmp_ps::<_CMP_GT_OQ>(ay, ax);
        let z_gt = _mm256_cmp_ps::<_CMP_GT_OQ>(az, _mm256_blendv_ps(ax, ay, y_gt));
        let d_kz = _mm256_blendv_ps(_mm256_blendv_ps(dx, dy, y_gt), dz, z_gt);
        let (yb, zb) = (
            _mm256_movemask_ps(y_gt) as u32,
            _mm256_movemask_ps(z_gt) as u32,
        );
        let negative = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LT_OQ>(d_kz, zero)) as u32;
        let on_axis = [!yb & !zb, yb & !zb, zb];
        let mut r = Self::EMPTY;
        if valid == 0 {
            return (r, 0);
        }
        let first = valid.trailing_zeros();
        let kz = if zb >> first & 1 == 1 {
            2
        } else if yb >> first & 1 == 1 {
            1
        } else {
            0
        };
        let flip = negative >> first & 1 == 1;
        let active = valid & on_axis[kz] & if flip { negative } else { !negative };
        if active.count_ones() <= min_rays {
            return (r, 0);
        }
        let mut kx = if kz == 2 { 0 } else { kz + 1 };
        let mut ky = if kx == 2 { 0 } else { kx + 1 };
        if flip {
            std::mem::swap(&mut kx, &mut ky);
        }
        // Lanes not taken hold what `new` leaves in them: origin 0, direction 1, the rest 0.
        let on = lane_mask(active);
        let keep = |v: __m256, none: __m256| _mm256_blendv_ps(none, v, on);
        let one = _mm256_set1_ps(1.0);
        let dirs = [keep(dx, one), keep(dy, one), keep(dz, one)];
        let tiny = _mm256_set1_ps(1e-20);
        for a in 0..3 {
            r.o[a] = store(keep(load(&o[a]), zero));
            // As `safe_inverse3`: |d| < 1e-20 replaced by ±1e-20, then 1 / d.
            let da = dirs[a];
            let small = _mm256_cmp_ps::<_CMP_LT_OQ>(_mm256_andnot_ps(sign, da), tiny);
            let clamped = _mm256_or_ps(_mm256_and_ps(da, sign), tiny);
            r.inv[a] = store(_mm256_div_ps(one, _mm256_blendv_ps(da, clamped, small)));
        }
        // `TriangleRay::new`: sz = 1 / d_kz, sx = d_kx · sz, sy = d_ky · sz.
        let sz = _mm256_div_ps(one, dirs[kz]);
        r.sz = store(keep(sz, zero));
        r.sx = store(keep(_mm256_mul_ps(dirs[kx], sz), zero));
        r.sy = store(keep(_mm256_mul_ps(dirs[ky], sz), zero));
        r.t_max = store(keep(load(&t_max), zero));
        r.k = [kx, ky, kz];
        r.active = active;
        r.frustum = Frustum::new(&r.o, &r.inv, active);
        (r, active)
    }

    /// A packet of the rays `(o, d, t_max, prepared triangle ray)` of `lanes` (at most eight)
    /// whose triangle test permutation equals the first one's; returns the packet and the
    /// mask of the lanes it took (the reference [`Self::from_rays`] is tested against).
    #[cfg(test)]
    pub(super) fn new(lanes: &[Option<(Vec3, Vec3, f32, TriangleRay)>]) -> (Self, u32) {
        let mut r = Self::EMPTY;
        let mut d = [[1.0f32; 8]; 3];
        let mut first: Option<[usize; 3]> = None;
        for (i, lane) in lanes.iter().enumerate().take(8) {
            let Some((o, dir, t_max, tr)) = lane else {
                continue;
            };
            let k = [tr.kx, tr.ky, tr.kz];
            if *first.get_or_insert(k) != k {
                continue;
            }
            for a in 0..3 {
                r.o[a][i] = o[a];
                d[a][i] = dir[a];
            }
            (r.sx[i], r.sy[i], r.sz[i]) = (tr.sx, tr.sy, tr.sz);
            r.t_max[i] = *t_max;
            r.active |= 1 << i;
        }
        // All lanes at once (vectorised); the empty lanes' direction 1 gives 1.
        for (inv, d) in r.inv.iter_mut().zip(&d) {
            for (inv, &d) in inv.iter_mut().zip(d) {
                *inv = super::node4::safe_inverse(d);
            }
        }
        if let Some(k) = first {
            r.k = k;
        }
        r.frustum = Frustum::scalar(&r.o, &r.inv, r.active);
        let taken = r.active;
        (r, taken)
    }

    /// Lane `i`'s prepared triangle ray (`None` for a lane without a ray): the one it was
    /// given, rebuilt from the packet's fields.
    #[inline]
    fn triangle_ray(&self, i: usize) -> Option<TriangleRay> {
        let i = i & 7;
        (self.active >> i & 1 == 1).then(|| TriangleRay {
            o: Vec3::new(self.o[0][i], self.o[1][i], self.o[2][i]),
            kx: self.k[0],
            ky: self.k[1],
            kz: self.k[2],
            sx: self.sx[i],
            sy: self.sy[i],
            sz: self.sz[i],
        })
    }
}

/// Loads eight lanes (unaligned).
#[inline]
#[target_feature(enable = "avx2")]
fn load(a: &[f32; 8]) -> __m256 {
    // SAFETY: `a` is eight readable f32; the unaligned load needs no alignment.
    unsafe { _mm256_loadu_ps(a.as_ptr()) }
}

/// Stores eight lanes.
#[inline]
#[target_feature(enable = "avx2")]
fn store(v: __m256) -> [f32; 8] {
    let mut out = [0.0f32; 8];
    // SAFETY: `out` is eight writable f32; the unaligned store needs no alignment.
    unsafe { _mm256_storeu_ps(out.as_mut_ptr(), v) };
    out
}

/// The eight rays' origins and reciprocal directions in registers.
#[derive(Clone, Copy)]
struct Slabs {
    o: [__m256; 3],
    inv: [__m256; 3],
}

impl Slabs {
    #[inline]
    #[target_feature(enable = "avx2")]
    fn new(rays: &Rays8) -> Self {
        Self {
            o: [load(&rays.o[0]), load(&rays.o[1]), load(&rays.o[2])],
            inv: [load(&rays.inv[0]), load(&rays.inv[1]), load(&rays.inv[2])],
        }
    }

    /// The one-ray slab test for eight rays against the box `[lo, hi]`: `(plane − o) · inv`
    /// per axis for both planes, their min and max the entry and exit, the far distance
    /// capped at `t_far` and grown by `1 + 2γ₃`. Returns the entry distances and the mask of
    /// the rays that enter (all bits of a lane set).
    #[inline]
    #[target_feature(enable = "avx2")]
    fn test(&self, lo: [f32; 3], hi: [f32; 3], t_far: __m256) -> (__m256, __m256) {
        let zero = _mm256_setzero_ps();
        let mut near = [zero; 3];
        let mut far = [zero; 3];
        for a in 0..3 {
            let tl = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(lo[a]), self.o[a]), self.inv[a]);
            let th = _mm256_mul_ps(_mm256_sub_ps(_mm256_set1_ps(hi[a]), self.o[a]), self.inv[a]);
            // The operand order of `Node8::hit`'s min and max.
            near[a] = _mm256_min_ps(tl, th);
            far[a] = _mm256_max_ps(tl, th);
        }
        let t0 = _mm256_max_ps(
            _mm256_max_ps(near[0], near[1]),
            _mm256_max_ps(near[2], zero),
        );
        let t1 = _mm256_mul_ps(
            _mm256_min_ps(_mm256_min_ps(far[0], far[1]), _mm256_min_ps(far[2], t_far)),
            _mm256_set1_ps(ROBUST),
        );
        (t0, _mm256_cmp_ps::<_CMP_LE_OS>(t0, t1))
    }
}

/// Rays of a packet that reach a node or leaf only this many or fewer go on one by one from
/// there, each through the one-ray traversal (Embree's hybrid traversal, after Benthin et al.
/// 2012, "Combining single and packet-ray tracing for arbitrary ray distributions on the Intel
/// MIC architecture"). Eight rays cost one box test per child of a node and one triangle
/// test per triangle of a leaf, whatever number of them reach it; one ray costs one node test
/// for all eight children and one packet test for four triangles, so a packet pays only where
/// most of its rays are together.
pub(super) const ONE_BY_ONE: u32 = 5;

/// At a leaf the hand-over is cheaper in lanes: a ray handed over pays a whole one-ray
/// traversal's set-up (its prepared rays in registers, its stack) besides the packet tests,
/// while the eight-lane triangle test costs the same for two rays as for eight. So rays reaching
/// a leaf together are tested there in lanes, and only a ray alone goes on by itself. (On the
/// benchmark's camera streams through 3 968 triangles: 758 → 691 instructions per ray against
/// handing over up to [`ONE_BY_ONE`] rays at leaves too, and 710 / 696 for thresholds of 3 and
/// 0; through 1 M triangles, where a leaf is rarely reached by two camera rays, within 0.2 %.)
const LEAF_ONE_BY_ONE: u32 = 1;

/// The most rays handed over one by one at node or leaf `cur` (`SWITCH` at an inner node).
#[inline(always)]
fn one_by_one_at<const SWITCH: u32>(cur: u32) -> u32 {
    if cur & LEAF != 0 {
        SWITCH.min(LEAF_ONE_BY_ONE)
    } else {
        SWITCH
    }
}

/// The lanes of `bits` as a vector mask (all bits of a lane set).
#[inline]
#[target_feature(enable = "avx2")]
fn lane_mask(bits: u32) -> __m256 {
    let lanes = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    let set = _mm256_and_si256(_mm256_set1_epi32(bits as i32), lanes);
    _mm256_castsi256_ps(_mm256_cmpeq_epi32(set, lanes))
}

/// Ray `i`'s prepared rays for the one-ray traversal (`None` for a lane without a ray).
#[inline]
fn one_ray(rays: &Rays8, i: usize) -> Option<(TriangleRay, Ray8)> {
    let tr = rays.triangle_ray(i)?;
    let (o, inv) = (&rays.o, &rays.inv);
    let i = i & 7;
    let br = Ray8::from_parts(
        [o[0][i], o[1][i], o[2][i]],
        [inv[0][i], inv[1][i], inv[2][i]],
    );
    Some((tr, br))
}

/// The closest hit of each ray of `rays` (lanes not in `rays.active` get `None`); `other(i,
/// k, t)` tests non-triangle primitive `k` (BVH order) for the ray in lane `i`, as
/// [`super::traverse::closest`]'s `other` does. Each node or leaf is visited with the mask of
/// the rays that entered its box; where they are `SWITCH` or fewer (at a leaf, fewer than two
/// and at most `SWITCH`: [`LEAF_ONE_BY_ONE`]), each goes on alone (the renderer's `SWITCH` is
/// [`ONE_BY_ONE`]; 0 keeps the rays together to the leaves, 8 traces
/// them one by one from the root).
///
/// # Safety
/// The CPU supports AVX2; `nodes` is non-empty and its child references index into `nodes`
/// and `packets` (indexing is checked anyway).
#[target_feature(enable = "avx2")]
pub(super) unsafe fn closest8<const SWITCH: u32>(
    nodes: &[Node8],
    packets: &[Packet],
    rays: &Rays8,
    mut other: impl FnMut(usize, u32, f32) -> Option<(f32, f32, f32)>,
) -> [Option<WideHit>; 8] {
    let mut t_best = load(&rays.t_max);
    // Per ray: the primitive of its closest hit so far (0 before any: no tie can win), its
    // barycentrics, and whether it has a hit.
    let mut prim = [0u32; 8];
    let mut b1 = [0.0f32; 8];
    let mut b2 = [0.0f32; 8];
    let mut found = 0u32;
    let slabs = Slabs::new(rays);
    let robust = _mm256_set1_ps(ROBUST);
    let frustum = rays.frustum.as_ref();
    // Entries: the least entry distance of the rays that entered the child, the child, and
    // those rays.
    let mut buf: StackBuf<(f32, u32, u32)> = [const { MaybeUninit::uninit() }; STACK];
    let mut stack = Stack::new(&mut buf);
    let (mut cur, mut rays_in) = (0u32, rays.active);
    loop {
        if rays_in.count_ones() <= one_by_one_at::<SWITCH>(cur) {
            // Each ray on its own from here, with its closest hit so far (so ties resolve as
            // in its own traversal).
            let mut tb = store(t_best);
            let mut bits = rays_in;
            while bits != 0 {
                let i = bits.trailing_zeros() as usize & 7;
                bits &= bits - 1;
                let Some((tr, br)) = one_ray(rays, i) else {
                    continue;
                };
                let start = Start {
                    node: cur,
                    t_max: tb[i],
                    best: (found >> i & 1 == 1).then_some(WideHit {
                        t: tb[i],
                        prim: prim[i],
                        b1: b1[i],
                        b2: b2[i],
                    }),
                };
                // SAFETY: this function's contract, and `cur` is a reference of the tree.
                let hit = unsafe {
                    traverse::closest::<Node8, 8>(
                        nodes,
                        packets,
                        &tr,
                        &br,
                        start,
                        |k, t| other(i, k, t),
                        |_| {},
                    )
                };
                if let Some(h) = hit {
                    tb[i] = h.t;
                    prim[i] = h.prim;
                    (b1[i], b2[i]) = (h.b1, h.b2);
                    found |= 1 << i;
                }
            }
            t_best = load(&tb);
        } else if cur & LEAF == 0 {
            let node = &nodes[cur as usize];
            let mut hits = [(0.0f32, 0u32, 0u32); 8];
            let n = entered_children::<true>(node, frustum, &slabs, rays_in, t_best, &mut hits);
            // Near to far by key (stable: lanes in order).
            for k in 1..n {
                let e = hits[k & 7];
                let mut j = k;
                while j > 0 && hits[j - 1].0 > e.0 {
                    hits[j] = hits[j - 1];
                    j -= 1;
                }
                hits[j & 7] = e;
            }
            if n > 0 {
                for &e in hits[1..n].iter().rev() {
                    stack.push(e);
                }
                (cur, rays_in) = (hits[0].1, hits[0].2);
                continue;
            }
        } else {
            for pk in leaf_packets(packets, cur) {
                let mut tris = pk.tri_mask;
                while tris != 0 {
                    let l = tris.trailing_zeros() as usize & 3;
                    tris &= tris - 1;
                    let p = pk.prim[l];
                    let mut on_edge = 0;
                    let accept = triangle8(pk, l, rays, t_best, rays_in, &mut on_edge);
                    // Rays exactly on an edge: the scalar test, as the one-ray traversal does.
                    let mut edge = on_edge & rays_in;
                    if accept.is_none() && edge == 0 {
                        continue;
                    }
                    let tb = store(t_best);
                    let mut t_new = tb;
                    while edge != 0 {
                        let i = edge.trailing_zeros() as usize & 7;
                        edge &= edge - 1;
                        // `intersect` keeps `t < bound`: ask for `t ≤ tb[i]`, then the tie rule.
                        if let Some((t, u1, u2)) = scalar_test(rays, i, pk, l, tb[i].next_up())
                            && (t < tb[i] || (found >> i & 1 == 1 && p < prim[i]))
                        {
                            t_new[i] = t;
                            prim[i] = p;
                            (b1[i], b2[i]) = (u1, u2);
                            found |= 1 << i;
                        }
                    }
                    if let Some(Accept8 {
                        t,
                        b1: v1,
                        b2: v2,
                        less,
                        equal,
                    }) = accept
                    {
                        // Ties (equal distance) win only against a later primitive of a ray's
                        // own.
                        let mut take = less & rays_in & !on_edge;
                        let mut ties = equal & rays_in & !on_edge & found;
                        while ties != 0 {
                            let i = ties.trailing_zeros() as usize & 7;
                            ties &= ties - 1;
                            if p < prim[i] {
                                take |= 1 << i;
                            }
                        }
                        let mut bits = take;
                        while bits != 0 {
                            let i = bits.trailing_zeros() as usize & 7;
                            bits &= bits - 1;
                            t_new[i] = t[i];
                            prim[i] = p;
                            (b1[i], b2[i]) = (v1[i], v2[i]);
                        }
                        found |= take;
                    }
                    t_best = load(&t_new);
                }
                let mut others = pk.other_mask;
                while others != 0 {
                    let l = others.trailing_zeros() as usize & 3;
                    others &= others - 1;
                    let mut tb = store(t_best);
                    let mut lanes = rays_in;
                    while lanes != 0 {
                        let i = lanes.trailing_zeros() as usize & 7;
                        lanes &= lanes - 1;
                        if let Some((t, u1, u2)) = other(i, pk.prim[l], tb[i]) {
                            tb[i] = t;
                            prim[i] = pk.prim[l];
                            (b1[i], b2[i]) = (u1, u2);
                            found |= 1 << i;
                        }
                    }
                    t_best = load(&tb);
                }
            }
        }
        // Next stacked child some ray may still find a closer hit in: of the rays that entered
        // it, those whose closest hit is not nearer than the least entry distance (a ray's own
        // entry distance is no less, so the others would miss its box now).
        let reach = _mm256_mul_ps(t_best, robust);
        loop {
            match stack.pop() {
                None => {
                    let tb = store(t_best);
                    let mut out = [None; 8];
                    for (i, slot) in out.iter_mut().enumerate() {
                        if found >> i & 1 == 1 {
                            *slot = Some(WideHit {
                                t: tb[i],
                                prim: prim[i],
                                b1: b1[i],
                                b2: b2[i],
                            });
                        }
                    }
                    return out;
                }
                Some((key, c, m)) => {
                    let within = _mm256_cmp_ps::<_CMP_LE_OS>(_mm256_set1_ps(key), reach);
                    let m = m & _mm256_movemask_ps(within) as u32;
                    if m != 0 {
                        (cur, rays_in) = (c, m);
                        break;
                    }
                }
            }
        }
    }
}

/// Whether each ray of `rays` (lanes in `rays.active`) hits anything before its `t_max`;
/// `other` as for [`closest8`] (only whether it returns a hit matters). Nodes and leaves are
/// visited with the rays that entered them and are not yet blocked, one by one where they are
/// `SWITCH` or fewer, as in [`closest8`].
///
/// # Safety
/// As [`closest8`].
#[target_feature(enable = "avx2")]
pub(super) unsafe fn any8<const SWITCH: u32>(
    nodes: &[Node8],
    packets: &[Packet],
    rays: &Rays8,
    mut other: impl FnMut(usize, u32, f32) -> Option<(f32, f32, f32)>,
) -> u32 {
    // Rays not yet blocked.
    let mut active = rays.active;
    let mut occluded = 0u32;
    let t_max = load(&rays.t_max);
    let slabs = Slabs::new(rays);
    let frustum = rays.frustum.as_ref();
    // Entries: a child and the rays that entered it.
    let mut buf: StackBuf<(u32, u32)> = [const { MaybeUninit::uninit() }; STACK];
    let mut stack = Stack::new(&mut buf);
    let (mut cur, mut rays_in) = (0u32, active);
    loop {
        if rays_in.count_ones() <= one_by_one_at::<SWITCH>(cur) {
            let mut bits = rays_in;
            while bits != 0 {
                let i = bits.trailing_zeros() as usize & 7;
                bits &= bits - 1;
                let Some((tr, br)) = one_ray(rays, i) else {
                    continue;
                };
                // SAFETY: this function's contract, and `cur` is a reference of the tree.
                let hit = unsafe {
                    traverse::any::<Node8, 8>(
                        nodes,
                        packets,
                        &tr,
                        &br,
                        rays.t_max[i],
                        cur,
                        |k, t| other(i, k, t),
                    )
                };
                if hit {
                    occluded |= 1 << i;
                    active &= !(1 << i);
                }
            }
        } else if cur & LEAF == 0 {
            let node = &nodes[cur as usize];
            let mut hits = [(0.0f32, 0u32, 0u32); 8];
            let n = entered_children::<false>(node, frustum, &slabs, rays_in, t_max, &mut hits);
            if n > 0 {
                // The first child next, the others stacked (any order finds whether some hit
                // exists).
                for &(_, child, m) in &hits[1..n] {
                    stack.push((child, m));
                }
                (cur, rays_in) = (hits[0].1, hits[0].2);
                continue;
            }
        } else {
            for pk in leaf_packets(packets, cur) {
                let mut tris = pk.tri_mask;
                while tris != 0 && rays_in != 0 {
                    let l = tris.trailing_zeros() as usize & 3;
                    tris &= tris - 1;
                    let mut on_edge = 0;
                    let less =
                        triangle8(pk, l, rays, t_max, rays_in, &mut on_edge).map_or(0, |a| a.less);
                    let mut hit = less & rays_in & !on_edge;
                    let mut edge = on_edge & rays_in;
                    while edge != 0 {
                        let i = edge.trailing_zeros() as usize & 7;
                        edge &= edge - 1;
                        if scalar_test(rays, i, pk, l, rays.t_max[i]).is_some() {
                            hit |= 1 << i;
                        }
                    }
                    occluded |= hit;
                    active &= !hit;
                    rays_in &= !hit;
                }
                let mut others = pk.other_mask;
                while others != 0 && rays_in != 0 {
                    let l = others.trailing_zeros() as usize & 3;
                    others &= others - 1;
                    let mut lanes = rays_in;
                    while lanes != 0 {
                        let i = lanes.trailing_zeros() as usize & 7;
                        lanes &= lanes - 1;
                        if other(i, pk.prim[l], rays.t_max[i]).is_some() {
                            occluded |= 1 << i;
                            active &= !(1 << i);
                            rays_in &= !(1 << i);
                        }
                    }
                }
            }
        }
        if active == 0 {
            return occluded;
        }
        // Next stacked child some ray that entered it and is not yet blocked has to visit.
        loop {
            match stack.pop() {
                None => return occluded,
                Some((c, m)) if m & active != 0 => {
                    (cur, rays_in) = (c, m & active);
                    break;
                }
                Some(_) => {}
            }
        }
    }
}

/// The children of `node` that rays of `rays_in` enter within their `t_far` (per lane): the
/// frustum, where the packet has one, picks those worth testing ray by ray. Written to `out` in
/// lane order as `(key, child, rays)`, where `key` is the least entry distance of those rays
/// when `KEY` (the closest-hit traversal's order), else 0; returns how many.
#[inline]
#[target_feature(enable = "avx2")]
fn entered_children<const KEY: bool>(
    node: &Node8,
    frustum: Option<&Frustum>,
    slabs: &Slabs,
    rays_in: u32,
    t_far: __m256,
    out: &mut [(f32, u32, u32); 8],
) -> usize {
    let entered = lane_mask(rays_in);
    let mut children = match frustum {
        Some(f) => f.hit(
            node,
            hmax(_mm256_blendv_ps(
                _mm256_set1_ps(f32::NEG_INFINITY),
                t_far,
                entered,
            )),
        ),
        None => node.used(),
    };
    let mut n = 0;
    while children != 0 {
        let c = children.trailing_zeros() as usize & 7;
        children &= children - 1;
        let (lo, hi) = node.lane_box(c);
        let (t0, le) = slabs.test(lo, hi, t_far);
        let le = _mm256_and_ps(le, entered);
        let m = _mm256_movemask_ps(le) as u32;
        if m == 0 {
            continue;
        }
        let key = if KEY {
            hmin(_mm256_blendv_ps(_mm256_set1_ps(f32::INFINITY), t0, le))
        } else {
            0.0
        };
        out[n & 7] = (key, node.child(c), m);
        n += 1;
    }
    n
}

/// The scalar watertight test of ray `i` of `rays` against triangle `l` of `pk` (for rays
/// exactly on an edge, as the one-ray traversal decides them): `(t, b1, b2)` with `t < bound`.
#[inline]
fn scalar_test(
    rays: &Rays8,
    i: usize,
    pk: &Packet,
    l: usize,
    bound: f32,
) -> Option<(f32, f32, f32)> {
    let tr = rays.triangle_ray(i)?;
    tr.intersect(bound, pk.vertex(0, l), pk.vertex(1, l), pk.vertex(2, l))
}

/// What [`triangle8`] finds for eight rays: per lane the distance and barycentrics, and the
/// masks of the hits with `t > 0` inside the triangle that are closer than the ray's best
/// (`less`) or as close (`equal`).
struct Accept8 {
    t: [f32; 8],
    b1: [f32; 8],
    b2: [f32; 8],
    less: u32,
    equal: u32,
}

/// The watertight test of triangle `l` of `pk` against the eight rays, lane by lane the
/// scalar test's operations ([`Accept8`]), and in `on_edge` the rays exactly on an edge (an edge
/// function exactly zero), which the caller decides with the scalar test. `None` when every
/// ray of `active` off an edge passes beside the triangle (edge functions of both signs): then
/// none of them can hit it, and the test stops before its division, as the one-ray packet
/// test does.
#[inline]
#[target_feature(enable = "avx2")]
fn triangle8(
    pk: &Packet,
    l: usize,
    rays: &Rays8,
    t_best: __m256,
    active: u32,
    on_edge: &mut u32,
) -> Option<Accept8> {
    let [kx, ky, kz] = rays.k.map(|k| k.min(2));
    let (ox, oy, oz) = (load(&rays.o[kx]), load(&rays.o[ky]), load(&rays.o[kz]));
    let (sx, sy, sz) = (load(&rays.sx), load(&rays.sy), load(&rays.sz));
    // Translate, permute, shear, as `TriangleRay::intersect` does per ray.
    let vert = |k: usize| {
        let p = &pk.v[k];
        let (px, py, pz) = (
            _mm256_set1_ps(p[kx][l]),
            _mm256_set1_ps(p[ky][l]),
            _mm256_set1_ps(p[kz][l]),
        );
        let z = _mm256_sub_ps(pz, oz);
        (
            _mm256_sub_ps(_mm256_sub_ps(px, ox), _mm256_mul_ps(sx, z)),
            _mm256_sub_ps(_mm256_sub_ps(py, oy), _mm256_mul_ps(sy, z)),
            z,
        )
    };
    let (ax, ay, az) = vert(0);
    let (bx, by, bz) = vert(1);
    let (cx, cy, cz) = vert(2);
    let u = _mm256_sub_ps(_mm256_mul_ps(cx, by), _mm256_mul_ps(cy, bx));
    let v = _mm256_sub_ps(_mm256_mul_ps(ax, cy), _mm256_mul_ps(ay, cx));
    let w = _mm256_sub_ps(_mm256_mul_ps(bx, ay), _mm256_mul_ps(by, ax));
    let zero = _mm256_setzero_ps();
    let eq0 = |x| _mm256_cmp_ps::<_CMP_EQ_OQ>(x, zero);
    let lt0 = |x| _mm256_cmp_ps::<_CMP_LT_OS>(x, zero);
    let gt0 = |x| _mm256_cmp_ps::<_CMP_GT_OS>(x, zero);
    *on_edge = _mm256_movemask_ps(_mm256_or_ps(_mm256_or_ps(eq0(u), eq0(v)), eq0(w))) as u32;
    let neg = _mm256_or_ps(_mm256_or_ps(lt0(u), lt0(v)), lt0(w));
    let pos = _mm256_or_ps(_mm256_or_ps(gt0(u), gt0(v)), gt0(w));
    let beside = _mm256_movemask_ps(_mm256_and_ps(neg, pos)) as u32;
    if active & !beside & !*on_edge == 0 {
        return None;
    }
    let det = _mm256_add_ps(_mm256_add_ps(u, v), w);
    let inv = _mm256_div_ps(_mm256_set1_ps(1.0), det);
    let sum = _mm256_add_ps(
        _mm256_add_ps(_mm256_mul_ps(u, az), _mm256_mul_ps(v, bz)),
        _mm256_mul_ps(w, cz),
    );
    let t = _mm256_mul_ps(_mm256_mul_ps(sz, sum), inv);
    let inside = _mm256_andnot_ps(
        _mm256_and_ps(neg, pos),
        _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_NEQ_UQ>(det, zero),
            _mm256_cmp_ps::<_CMP_GT_OS>(t, zero),
        ),
    );
    let less = _mm256_and_ps(inside, _mm256_cmp_ps::<_CMP_LT_OS>(t, t_best));
    let equal = _mm256_and_ps(inside, _mm256_cmp_ps::<_CMP_EQ_OQ>(t, t_best));
    Some(Accept8 {
        t: store(t),
        b1: store(_mm256_mul_ps(v, inv)),
        b2: store(_mm256_mul_ps(w, inv)),
        less: _mm256_movemask_ps(less) as u32,
        equal: _mm256_movemask_ps(equal) as u32,
    })
}

/// The greatest lane of `v` (lanes not to count hold −∞ already).
#[inline]
#[target_feature(enable = "avx2")]
fn hmax(v: __m256) -> f32 {
    let m = _mm_max_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps::<1>(v));
    let m = _mm_max_ps(m, _mm_movehl_ps(m, m));
    let m = _mm_max_ss(m, _mm_shuffle_ps::<0b01>(m, m));
    _mm_cvtss_f32(m)
}

/// The least lane of `v` (lanes not to count hold +∞ already).
#[inline]
#[target_feature(enable = "avx2")]
fn hmin(v: __m256) -> f32 {
    let m = _mm_min_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps::<1>(v));
    let m = _mm_min_ps(m, _mm_movehl_ps(m, m));
    let m = _mm_min_ss(m, _mm_shuffle_ps::<0b01>(m, m));
    _mm_cvtss_f32(m)
}

#[cfg(test)]
mod tests {
    use super::super::{BvhWidth, Nodes, PacketRay, WideBvh};
    use super::*;
    use caustica_core::sampling::Pcg32;

    /// A closed UV sphere of radius 1: neighbours share edges and vertices (ties).
    fn sphere(nphi: usize, ntheta: usize) -> Vec<[Vec3; 3]> {
        let p = |i: usize, j: usize| {
            let (phi, theta) = (
                std::f32::consts::TAU * (i % nphi) as f32 / nphi as f32,
                std::f32::consts::PI * j as f32 / ntheta as f32,
            );
            Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            )
        };
        let mut tris = Vec::new();
        for j in 0..ntheta {
            for i in 0..nphi {
                tris.push([p(i, j), p(i, j + 1), p(i + 1, j + 1)]);
                tris.push([p(i, j), p(i + 1, j + 1), p(i + 1, j)]);
            }
        }
        tris
    }

    /// The rays as `Geometry` prepared them one by one: `None` where it traces nothing.
    fn prepared(rays: &[Ray]) -> Vec<Option<PacketRay>> {
        rays.iter()
            .map(|r| (r.t_max > 0.0).then(|| (r.o, r.d, r.t_max, TriangleRay::new(r.o, r.d))))
            .collect()
    }

    /// Every field of a packet, as bits.
    fn bits(r: &Rays8) -> Vec<u64> {
        let rows =
            r.o.iter()
                .chain(&r.inv)
                .chain([&r.sx, &r.sy, &r.sz, &r.t_max]);
        let mut out: Vec<u64> = rows.flatten().map(|x| u64::from(x.to_bits())).collect();
        out.extend(r.k.map(|k| k as u64));
        out.push(u64::from(r.active));
        out.push(r.frustum.is_some() as u64);
        out
    }

    /// A frustum's numbers as values (its bounds are minima and maxima, which may differ from
    /// the scalar loop's in the sign of a zero bound; no comparison sees it).
    fn frustum_values(r: &Rays8) -> Option<([f32; 12], [usize; 3])> {
        r.frustum.map(|f| {
            let mut v = [0.0; 12];
            for (i, x) in [f.o_near, f.o_far, f.inv_min, f.inv_max]
                .iter()
                .flatten()
                .enumerate()
            {
                v[i] = *x;
            }
            (v, f.near)
        })
    }

    #[test]
    fn the_vector_set_up_makes_the_packet_the_prepared_rays_make() {
        if !BvhWidth::Eight.supported() {
            return;
        }
        let mut rng = Pcg32::new(17, 4);
        let mut u = || rng.next_f32();
        // Components that test each rule: ties in |d| between axes (the first axis wins), tiny
        // components (kept finite), signed zeros, NaN, and t_max that `Geometry` does not trace.
        let special = [
            0.0,
            -0.0,
            1e-21,
            -1e-21,
            1e-20,
            0.5,
            -0.5,
            1.0,
            -1.0,
            f32::NAN,
        ];
        let (mut partial, mut frusta, mut taken_total, mut few_total) = (0, 0, 0, 0);
        for case in 0..4000 {
            let n = if case % 9 == 0 { 1 + case % 8 } else { 8 };
            let mut pick = |scale: f32| {
                if u() < 0.3 {
                    special[(u() * special.len() as f32) as usize % special.len()]
                } else {
                    (u() - 0.5) * scale
                }
            };
            // Mostly one octant (as bundles are), sometimes any direction.
            let base = Vec3::new(pick(2.0), pick(2.0), pick(2.0));
            let rays: Vec<Ray> = (0..n)
                .map(|_| {
                    let o = Vec3::new(pick(10.0), pick(10.0), pick(10.0));
                    let d = if case % 4 == 0 {
                        Vec3::new(pick(2.0), pick(2.0), pick(2.0))
                    } else {
                        base + 0.05 * Vec3::new(pick(1.0), pick(1.0), pick(1.0))
                    };
                    let t_max = match (pick(20.0).abs() * 2.0) as u32 {
                        0 => 0.0,
                        1 => -1.0,
                        2 => f32::NAN,
                        3 => 2.5,
                        _ => f32::INFINITY,
                    };
                    Ray::with_t_max(o, d, t_max)
                })
                .collect();
            let want = Rays8::new(&prepared(&rays));
            // SAFETY: AVX2 was detected.
            let got = unsafe { Rays8::from_rays(&rays, 0) };
            assert_eq!(got.1, want.1, "case {case}: lanes taken");
            assert_eq!(bits(&got.0), bits(&want.0), "case {case}");
            assert_eq!(
                frustum_values(&got.0),
                frustum_values(&want.0),
                "case {case}"
            );
            // With a least count, a packet that would take that many rays or fewer takes none;
            // the others are the same packet.
            // SAFETY: AVX2 was detected.
            let few = unsafe { Rays8::from_rays(&rays, ONE_BY_ONE) };
            if want.1.count_ones() <= ONE_BY_ONE {
                assert_eq!(few.1, 0, "case {case}: a packet of few rays set up");
                few_total += 1;
            } else {
                assert_eq!(few.1, want.1, "case {case}: lanes taken with a least count");
                assert_eq!(bits(&few.0), bits(&want.0), "case {case}");
            }
            partial += (want.1 != 0 && want.1.count_ones() < n as u32) as u32;
            frusta += want.0.frustum.is_some() as u32;
            taken_total += want.1.count_ones();
        }
        // The cases reach every rule: packets that leave rays out, packets with a frustum.
        assert!(
            partial > 1000 && frusta > 500,
            "{partial} partial, {frusta} frusta"
        );
        assert!(taken_total > 10_000, "{taken_total} rays taken");
        assert!(few_total > 500, "{few_total} packets of few rays");
    }

    #[test]
    fn packets_kept_together_handed_over_or_one_by_one_give_each_ray_its_own_hit() {
        if !BvhWidth::Eight.supported() {
            return;
        }
        let tris = sphere(48, 24);
        let bvh = WideBvh::over_triangles(&tris, BvhWidth::Eight);
        let Nodes::Eight(nodes) = &bvh.nodes else {
            panic!("an eight-wide tree was asked for");
        };
        let mut rng = Pcg32::new(3, 11);
        let mut u = || rng.next_f32();
        let (mut full, mut hits, mut blocked, mut frusta) = (0, 0, 0, 0);
        for packet in 0..600 {
            // Bundles from one corner toward the sphere, from nearly parallel (the rays stay
            // together to the leaves) to wide (they part near the root); every third bundle
            // aims at the mesh's vertices (hits at equal distance on shared edges), and some
            // rays end inside the sphere.
            let spread = [0.002, 0.02, 0.2, 1.0][packet % 4];
            // Corners of every octant, so that directions are negative along some axes, and
            // every fifth packet from near the centre (directions of both signs: no frustum);
            // origins apart by up to `jitter` within a packet.
            let sign = |b: usize| if packet >> b & 1 == 1 { 1.0 } else { -1.0 };
            let corner = if packet % 5 == 4 {
                Vec3::new(0.1, -0.05, 0.02)
            } else {
                Vec3::new(2.5 * sign(2), 2.0 * sign(3), 3.0 * sign(4))
            };
            let jitter = [0.0, 0.05, 0.3][packet % 3];
            let aim = Vec3::new(u() - 0.5, u() - 0.5, u() - 0.5);
            let given: Vec<Ray> = (0..8)
                .map(|k| {
                    let o = corner + jitter * Vec3::new(u() - 0.5, u() - 0.5, u() - 0.5);
                    let target = if packet % 3 == 0 {
                        tris[(packet * 8 + k * 5) % tris.len()][k % 3]
                    } else {
                        aim + spread * Vec3::new(u() - 0.5, u() - 0.5, u() - 0.5)
                    };
                    let d = (target - o).normalize();
                    let t_max = if k == 7 { 3.2 } else { f32::INFINITY };
                    Ray::with_t_max(o, d, t_max)
                })
                .collect();
            let lanes = prepared(&given);
            // SAFETY: AVX2 was detected.
            let (rays, taken) = unsafe { Rays8::from_rays(&given, 0) };
            full += (taken == 0xff) as u32;
            frusta += rays.frustum.is_some() as u32;
            let none = |_: usize, _: u32, _: f32| None;
            // SAFETY: AVX2 was detected; the tree was built by the builder.
            let results = unsafe {
                [
                    (
                        closest8::<0>(nodes, &bvh.packets, &rays, none),
                        any8::<0>(nodes, &bvh.packets, &rays, none),
                    ),
                    (
                        closest8::<5>(nodes, &bvh.packets, &rays, none),
                        any8::<5>(nodes, &bvh.packets, &rays, none),
                    ),
                    (
                        closest8::<8>(nodes, &bvh.packets, &rays, none),
                        any8::<8>(nodes, &bvh.packets, &rays, none),
                    ),
                ]
            };
            for (i, lane) in lanes.iter().enumerate() {
                let Some((o, d, t_max, tr)) = lane else {
                    continue;
                };
                if taken >> i & 1 == 0 {
                    continue;
                }
                let one = bvh.closest(*o, *d, tr, *t_max, |_, _| None, |_| {});
                let one_any = bvh.any(*o, *d, tr, *t_max, |_, _| None);
                for (switch, (closest, any)) in [0, 5, 8].iter().zip(&results) {
                    let bits = |h: Option<WideHit>| {
                        h.map(|h| (h.t.to_bits(), h.prim, h.b1.to_bits(), h.b2.to_bits()))
                    };
                    assert_eq!(
                        bits(closest[i]),
                        bits(one),
                        "packet {packet} ray {i} switch {switch}"
                    );
                    assert_eq!(
                        any >> i & 1 == 1,
                        one_any,
                        "packet {packet} ray {i} switch {switch}"
                    );
                }
                hits += one.is_some() as u32;
                blocked += one_any as u32;
            }
        }
        assert!(full > 300, "full packets {full}");
        assert!(
            (200..560).contains(&frusta),
            "packets with a frustum {frusta}"
        );
        assert!(
            hits > 2000 && blocked > 2000,
            "hits {hits}, blocked {blocked}"
        );
    }
}
