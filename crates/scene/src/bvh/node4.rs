//! Inner nodes of four children, their boxes tested at once with SSE (glam's `Vec4`): the
//! layout every CPU runs, and the fallback where AVX2 is missing.

use super::traverse::{ROBUST, WideNode};
use caustica_core::{Vec3, Vec3A};
use glam::Vec4;

/// An inner node: the boxes of its four children, one lane per child. Aligned to a cache
/// line, so its 116 bytes never straddle three.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub(super) struct Node4 {
    /// `bounds[axis][0]` holds the minima of the four boxes along `axis`, `[1]` the maxima.
    /// Unused lanes hold the empty box (+∞, −∞).
    bounds: [[Vec4; 2]; 3],
    child: [u32; 4],
    /// Bit `l` set: lane `l` holds a child (the test's answer is masked with it, as its
    /// min/max form would see the empty box as the whole space).
    used: u32,
}

/// A ray prepared for the slab tests: origin and reciprocal direction (components of
/// magnitude below 1e-20 replaced by ±1e-20, so the reciprocal stays finite).
#[derive(Clone, Copy, Debug)]
pub(super) struct Ray4 {
    o: [Vec4; 3],
    inv: [Vec4; 3],
}

/// The reciprocal of a direction component, kept finite (see [`Ray4`]): the scalar reference
/// the vector forms ([`safe_inverse3`], the packets' set-up) are tested against.
#[cfg(test)]
pub(super) fn safe_inverse(x: f32) -> f32 {
    let x = if x.abs() < 1e-20 {
        1e-20f32.copysign(x)
    } else {
        x
    };
    1.0 / x
}

/// The reciprocals of the three components of `d`, kept finite (see [`Ray4`]), at once (one
/// SSE division; the same operations lane by lane, so the same bits).
#[inline(always)]
pub(super) fn safe_inverse3(d: Vec3) -> [f32; 3] {
    let d = Vec3A::from(d);
    let tiny = Vec3A::splat(1e-20);
    let x = Vec3A::select(d.abs().cmplt(tiny), tiny.copysign(d), d);
    (Vec3A::ONE / x).to_array()
}

impl WideNode<4> for Node4 {
    type Ray = Ray4;

    #[inline(always)]
    fn ray(o: Vec3, d: Vec3) -> Ray4 {
        let i = safe_inverse3(d);
        Ray4 {
            o: [Vec4::splat(o.x), Vec4::splat(o.y), Vec4::splat(o.z)],
            inv: [Vec4::splat(i[0]), Vec4::splat(i[1]), Vec4::splat(i[2])],
        }
    }

    fn empty() -> Self {
        Self {
            bounds: [[Vec4::splat(f32::INFINITY), Vec4::splat(f32::NEG_INFINITY)]; 3],
            child: [super::packet::EMPTY; 4],
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
        self.child[lane & 3]
    }

    /// SSE2 is part of x86_64 (and glam is scalar elsewhere): nothing for the caller to check.
    #[inline(always)]
    unsafe fn hit(&self, r: &Ray4, t_max: f32) -> (u32, [f32; 4]) {
        // Per axis the distances to the two planes, (plane − o) · inv; the nearer is the
        // entry, the farther the exit. Rounding is monotonic, so min/max pick exactly the
        // plane the direction's sign would (pbrt-v4's slab test, without a per-ray plane
        // choice to keep in registers).
        let slab = |a: usize| {
            let b = &self.bounds[a];
            let (lo, hi) = ((b[0] - r.o[a]) * r.inv[a], (b[1] - r.o[a]) * r.inv[a]);
            (lo.min(hi), lo.max(hi))
        };
        let (x0, x1) = slab(0);
        let (y0, y1) = slab(1);
        let (z0, z1) = slab(2);
        let t0 = x0.max(y0).max(z0.max(Vec4::ZERO));
        let t1 = x1.min(y1).min(z1.min(Vec4::splat(t_max))) * ROBUST;
        (t0.cmple(t1).bitmask() & self.used, t0.to_array())
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    #[test]
    fn three_inverses_at_once_give_the_scalar_bits() {
        let specials = [
            0.0,
            -0.0,
            1e-20,
            -1e-20,
            9.9e-21,
            -9.9e-21,
            1e-45,
            -3.0,
            0.5,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            f32::MAX,
        ];
        let mut rng = caustica_core::sampling::Pcg32::new(5, 7);
        let mut values: Vec<f32> = specials.to_vec();
        values.extend((0..300).map(|i| (rng.next_f32() - 0.5) * 10f32.powi(i % 60 - 40)));
        for (i, &x) in values.iter().enumerate() {
            let (y, z) = (
                values[(i * 7 + 3) % values.len()],
                values[(i * 13 + 5) % values.len()],
            );
            let got = safe_inverse3(Vec3::new(x, y, z)).map(f32::to_bits);
            let want = [safe_inverse(x), safe_inverse(y), safe_inverse(z)].map(f32::to_bits);
            assert_eq!(got, want, "({x}, {y}, {z})");
        }
    }

    /// Lanes of `node` hit by the ray `(o, d)` within `t_max`, and the entry distances.
    pub(in crate::bvh) fn hits<N: WideNode<W>, const W: usize>(
        node: &N,
        o: Vec3,
        d: Vec3,
        t_max: f32,
    ) -> (u32, [f32; W]) {
        // SAFETY: only called with node kinds the test has checked the CPU supports.
        unsafe { node.hit(&N::ray(o, d), t_max) }
    }

    /// The slab test's cases, for any node width (the 8-wide test runs it too).
    pub(in crate::bvh) fn slab_cases<N: WideNode<W>, const W: usize>() {
        // Axis-parallel rays (zero direction components) just inside and just outside box
        // faces, rays stopped early, a ray starting inside a box, and rays that miss.
        let mut node = N::empty();
        let boxes = [
            (Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 1.0)),
            (Vec3::new(2.0, 0.0, 0.0), Vec3::new(3.0, 1.0, 1.0)),
            (Vec3::new(0.0, 5.0, 0.0), Vec3::new(1.0, 6.0, 1.0)),
        ];
        for (l, (lo, hi)) in boxes.iter().enumerate() {
            node.set_lane(l, *lo, *hi, l as u32);
        }
        // Along +x just inside the top edges of boxes 0 and 1, and just outside them. (A ray
        // lying exactly in a face plane may miss: `Geometry` pads every box by a few ulps.)
        let inside = 1.0 - 1e-6;
        let o = Vec3::new(-1.0, inside, inside);
        let inf = f32::INFINITY;
        assert_eq!(hits(&node, o, Vec3::X, inf).0, 0b011);
        let o2 = Vec3::new(-1.0, 1.0 + 1e-6, inside);
        assert_eq!(hits(&node, o2, Vec3::X, inf).0, 0);
        // The first ray (entering box 0 at t = 1, box 1 at t = 3) stopped earlier.
        assert_eq!(hits(&node, o, Vec3::X, 3.5).0, 0b011);
        assert_eq!(hits(&node, o, Vec3::X, 2.5).0, 0b001);
        assert_eq!(hits(&node, o, Vec3::X, 0.5).0, 0);
        let (_, t0) = hits(&node, o, Vec3::X, inf);
        assert_eq!((t0[0], t0[1]), (1.0, 3.0));
        // Along −y at x = 0.5, z = 0.5 from above box 2: boxes 2 and 0.
        let o = Vec3::new(0.5, 10.0, 0.5);
        assert_eq!(hits(&node, o, -Vec3::Y, inf).0, 0b101);
        // Starting inside box 0, going −z: box 0 only (entry distance clamped to 0).
        let (mask, t0) = hits(&node, Vec3::new(0.5, 0.5, 0.5), -Vec3::Z, inf);
        assert_eq!(mask, 0b001);
        assert_eq!(t0[0], 0.0);
        // Missing everything; the empty lanes are never hit.
        assert_eq!(hits(&node, Vec3::new(-1.0, 3.0, 0.5), Vec3::X, inf).0, 0);
        // A box in the last lane is found like any other.
        node.set_lane(W - 1, Vec3::new(0.0, 0.0, 10.0), Vec3::ONE * 11.0, 7);
        let (mask, t0) = hits(&node, Vec3::new(10.5, 10.5, 0.5), Vec3::Z, inf);
        assert_eq!(mask, 1 << (W - 1));
        assert_eq!(t0[W - 1], 9.5);
        assert_eq!(node.child(W - 1), 7);
    }

    #[test]
    fn slab_test_finds_the_boxes_a_ray_passes_through_and_no_others() {
        slab_cases::<Node4, 4>();
    }
}
