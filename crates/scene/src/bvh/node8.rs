//! Inner nodes of eight children, their boxes tested at once with AVX (x86_64 only). Used
//! where the CPU has AVX2 ([`super::BvhWidth::detect`]); the operations are those of
//! [`super::node4`]'s SSE test, lane for lane and in the same order, so a box is hit or missed
//! identically by both.

use super::node4::safe_inverse3;
use super::traverse::{ROBUST, WideNode};
use caustica_core::Vec3;
use std::arch::x86_64::*;

/// An inner node: the boxes of its eight children, one lane per child: 228 bytes, aligned to
/// a cache line (so four whole lines).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub(super) struct Node8 {
    /// `bounds[axis][0]` holds the minima of the eight boxes along `axis`, `[1]` the maxima.
    /// Unused lanes hold the empty box (+∞, −∞). Each row of eight is 32-byte aligned (the
    /// struct is 64-byte aligned and rows are 32 bytes), for aligned loads.
    bounds: [[[f32; 8]; 2]; 3],
    child: [u32; 8],
    /// Bit `l` set: lane `l` holds a child (as [`super::node4::Node4`]'s).
    used: u32,
}

/// A ray prepared for the slab tests, as [`super::node4::Ray4`] (broadcast to eight lanes in
/// the test, where the compiler hoists the broadcasts out of the traversal loop).
#[derive(Clone, Copy, Debug)]
pub(super) struct Ray8 {
    o: [f32; 3],
    inv: [f32; 3],
}

impl Ray8 {
    /// The prepared ray of origin `o` and reciprocal direction `inv` (as
    /// [`super::node4::safe_inverse3`] makes it).
    #[inline(always)]
    pub(super) fn from_parts(o: [f32; 3], inv: [f32; 3]) -> Self {
        Self { o, inv }
    }
}

impl Node8 {
    /// The eight boxes' planes along `axis`: their minima (`side` 0) or maxima (`side` 1).
    #[inline(always)]
    pub(super) fn planes(&self, axis: usize, side: usize) -> &[f32; 8] {
        &self.bounds[axis % 3][side & 1]
    }

    /// The lanes that hold a child (bit `l` for lane `l`).
    #[inline(always)]
    pub(super) fn used(&self) -> u32 {
        self.used
    }

    /// The box of lane `lane`: `(min, max)`.
    #[inline(always)]
    pub(super) fn lane_box(&self, lane: usize) -> ([f32; 3], [f32; 3]) {
        let l = lane & 7;
        let b = &self.bounds;
        (
            [b[0][0][l], b[1][0][l], b[2][0][l]],
            [b[0][1][l], b[1][1][l], b[2][1][l]],
        )
    }
}

impl WideNode<8> for Node8 {
    type Ray = Ray8;

    #[inline(always)]
    fn ray(o: Vec3, d: Vec3) -> Ray8 {
        Ray8 {
            o: o.to_array(),
            inv: safe_inverse3(d),
        }
    }

    fn empty() -> Self {
        Self {
            bounds: [[[f32::INFINITY; 8], [f32::NEG_INFINITY; 8]]; 3],
            child: [super::packet::EMPTY; 8],
            used: 0,
        }
    }

    fn set_lane(&mut self, lane: usize, min: Vec3, max: Vec3, child: u32) {
        for a in 0..3 {
            self.bounds[a][0][lane] = min[a];
            self.bounds[a][1][lane] = max[a];
        }
        self.child[lane] = child;
        self.used |= 1 << lane;
    }

    #[inline(always)]
    fn child(&self, lane: usize) -> u32 {
        self.child[lane & 7]
    }

    /// # Safety
    /// The CPU must support AVX (every CPU with AVX2 does; [`super::WideBvh`] builds 8-wide
    /// nodes only after detecting AVX2).
    #[inline]
    #[target_feature(enable = "avx2")]
    unsafe fn hit(&self, r: &Ray8, t_max: f32) -> (u32, [f32; 8]) {
        // Each slab as in `Node4::hit`: (plane − o) · inv for both planes, min/max for entry
        // and exit, with the same operand order.
        let b = &self.bounds;
        let (ox, oy, oz) = (
            _mm256_set1_ps(r.o[0]),
            _mm256_set1_ps(r.o[1]),
            _mm256_set1_ps(r.o[2]),
        );
        let (ix, iy, iz) = (
            _mm256_set1_ps(r.inv[0]),
            _mm256_set1_ps(r.inv[1]),
            _mm256_set1_ps(r.inv[2]),
        );
        // SAFETY: every row `b[a][k]` is an `[f32; 8]` at a 32-byte aligned address (the node
        // is 64-byte aligned, rows are 32 bytes long and start at offsets 0, 32, …, 160).
        // (A macro, not a closure, so the intrinsic is inlined with this function's features.)
        macro_rules! load {
            ($row:expr) => {
                unsafe { _mm256_load_ps($row.as_ptr()) }
            };
        }
        let xl = _mm256_mul_ps(_mm256_sub_ps(load!(b[0][0]), ox), ix);
        let xh = _mm256_mul_ps(_mm256_sub_ps(load!(b[0][1]), ox), ix);
        let yl = _mm256_mul_ps(_mm256_sub_ps(load!(b[1][0]), oy), iy);
        let yh = _mm256_mul_ps(_mm256_sub_ps(load!(b[1][1]), oy), iy);
        let zl = _mm256_mul_ps(_mm256_sub_ps(load!(b[2][0]), oz), iz);
        let zh = _mm256_mul_ps(_mm256_sub_ps(load!(b[2][1]), oz), iz);
        let (x0, x1) = (_mm256_min_ps(xl, xh), _mm256_max_ps(xl, xh));
        let (y0, y1) = (_mm256_min_ps(yl, yh), _mm256_max_ps(yl, yh));
        let (z0, z1) = (_mm256_min_ps(zl, zh), _mm256_max_ps(zl, zh));
        let t0 = _mm256_max_ps(
            _mm256_max_ps(x0, y0),
            _mm256_max_ps(z0, _mm256_setzero_ps()),
        );
        let t1 = _mm256_mul_ps(
            _mm256_min_ps(
                _mm256_min_ps(x1, y1),
                _mm256_min_ps(z1, _mm256_set1_ps(t_max)),
            ),
            _mm256_set1_ps(ROBUST),
        );
        let mask = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OS>(t0, t1)) as u32 & self.used;
        let mut out = [0.0f32; 8];
        // SAFETY: `out` holds eight f32; the unaligned store needs no alignment.
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), t0) };
        (mask, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slab_test_finds_the_boxes_a_ray_passes_through_and_no_others() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            eprintln!("no AVX2 on this CPU: the 8-wide node is not used here");
            return;
        }
        super::super::node4::tests::slab_cases::<Node8, 8>();
    }

    #[test]
    fn eight_lanes_decide_like_four() {
        // The 8-wide test against two 4-wide ones on random boxes and rays, bit for bit.
        if !std::arch::is_x86_feature_detected!("avx2") {
            return;
        }
        use super::super::node4::Node4;
        use caustica_core::sampling::Pcg32;
        let mut rng = Pcg32::new(3, 9);
        let mut v = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 4.0 - 2.0;
        let mut hits = 0;
        for i in 0..20_000 {
            let mut n8 = Node8::empty();
            let mut n4 = [Node4::empty(), Node4::empty()];
            for l in 0..8 {
                let (a, b) = (v(), v());
                n8.set_lane(l, a.min(b), a.max(b), l as u32);
                n4[l / 4].set_lane(l % 4, a.min(b), a.max(b), l as u32);
            }
            let o = v() * 2.0;
            let mut d = v().normalize();
            if i % 7 == 0 {
                d.x = 0.0; // axis-parallel in x
            }
            let t_max = if i % 3 == 0 { 1.5 } else { f32::INFINITY };
            let (m8, t8) = super::super::node4::tests::hits(&n8, o, d, t_max);
            let (ma, ta) = super::super::node4::tests::hits(&n4[0], o, d, t_max);
            let (mb, tb) = super::super::node4::tests::hits(&n4[1], o, d, t_max);
            assert_eq!(m8, ma | mb << 4, "case {i}");
            for l in 0..8 {
                let t4 = if l < 4 { ta[l] } else { tb[l - 4] };
                assert_eq!(t8[l].to_bits(), t4.to_bits(), "case {i} lane {l}");
            }
            hits += m8.count_ones();
        }
        assert!(hits > 2_000, "{hits}"); // 3 662 of 160 000 lanes with this seed
    }
}
