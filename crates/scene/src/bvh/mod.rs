//! The BVH every query of a scene goes through: a wide tree whose nodes test four or eight
//! child boxes at once, with leaves of up to eight primitives, held as runs of packets
//! ([`packet`]) of up to four primitives tested at once.
//!
//! The tree comes from the `obvhs` crate's binary PLOC build (with reinsertion, single
//! threaded, so it is the same whatever the thread count), collapsed ([`collapse`], by the
//! surface area heuristic) to the node width the CPU runs best ([`BvhWidth::detect`]): eight
//! children per node with AVX2 ([`node8`], x86_64), four with SSE everywhere else ([`node4`],
//! the fallback). Both widths run the same traversals ([`traverse`]), whose box tests are
//! conservative (the far distance grown by `1 + 2γ₃`, pbrt-v4) and whose triangle tests are
//! bit-identical to the scalar watertight test, so both find the same closest hit: only the
//! order of the visit differs, and ties at equal distance go to the primitive first in BVH
//! order (see
//! [`WideBvh::closest`]), so not even they show it.

mod collapse;
pub mod counts;
mod node4;
#[cfg(target_arch = "x86_64")]
mod node8;
mod packet;
pub(crate) mod prefetch;
#[cfg(target_arch = "x86_64")]
mod ray8;
mod stack;
mod traverse;

use crate::shape::Aabb;
use crate::shape::mesh::TriangleRay;
use caustica_core::{Ray, Vec3};
use glam::Vec3A;
use node4::Node4;
#[cfg(target_arch = "x86_64")]
use node8::Node8;
use packet::Packet;
use traverse::WideNode;

/// A hit found by a traversal: distance, primitive (BVH order) and barycentrics `(b1, b2)`
/// (zero for non-triangles).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WideHit {
    pub t: f32,
    pub prim: u32,
    pub b1: f32,
    pub b2: f32,
}

/// Children per inner node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BvhWidth {
    /// Four (SSE): every CPU.
    Four,
    /// Eight (AVX2): x86_64 CPUs that have it.
    Eight,
}

impl BvhWidth {
    /// The widest layout this CPU runs: eight where AVX2 is detected at run time, else four.
    /// The environment variable `CAUSTICA_BVH_WIDTH=4` forces the fallback (to test it, or to
    /// compare the two on one machine).
    pub fn detect() -> Self {
        static WIDTH: std::sync::OnceLock<BvhWidth> = std::sync::OnceLock::new();
        *WIDTH.get_or_init(|| {
            let forced_four = std::env::var("CAUSTICA_BVH_WIDTH").is_ok_and(|v| v.trim() == "4");
            if !forced_four && Self::Eight.supported() {
                Self::Eight
            } else {
                Self::Four
            }
        })
    }

    /// True if this CPU can traverse nodes of this width.
    pub fn supported(self) -> bool {
        match self {
            Self::Four => true,
            #[cfg(target_arch = "x86_64")]
            Self::Eight => std::arch::is_x86_feature_detected!("avx2"),
            #[cfg(not(target_arch = "x86_64"))]
            Self::Eight => false,
        }
    }
}

/// The inner nodes, of the width chosen at build time.
#[derive(Clone, Debug, PartialEq)]
enum Nodes {
    Four(Vec<Node4>),
    /// Only ever built after [`BvhWidth::supported`] confirmed AVX2: the invariant that makes
    /// the 8-wide traversal's `unsafe` calls sound.
    #[cfg(target_arch = "x86_64")]
    Eight(Vec<Node8>),
}

/// The wide BVH over a scene's primitives.
#[derive(Clone, Debug, PartialEq)]
pub struct WideBvh {
    nodes: Nodes,
    packets: Vec<Packet>,
    /// BVH order → index of the primitive in the build input.
    order: Vec<u32>,
}

impl Default for WideBvh {
    fn default() -> Self {
        Self {
            nodes: Nodes::Four(Vec::new()),
            packets: Vec::new(),
            order: Vec::new(),
        }
    }
}

impl WideBvh {
    /// Builds the tree over primitives with the given (conservative) bounds, in the width of
    /// [`BvhWidth::detect`]; `triangles[i]` holds the vertices of primitive `i` if it is a
    /// triangle. Deterministic: the same input gives the same tree whatever the thread count.
    pub fn build(bounds: &[Aabb], triangles: &[Option<[Vec3; 3]>]) -> Self {
        Self::build_with_width(bounds, triangles, BvhWidth::detect())
    }

    /// [`Self::build`] with nodes of the given width (four if this CPU cannot run eight).
    pub fn build_with_width(
        bounds: &[Aabb],
        triangles: &[Option<[Vec3; 3]>],
        width: BvhWidth,
    ) -> Self {
        debug_assert_eq!(bounds.len(), triangles.len());
        if bounds.is_empty() {
            return Self::default();
        }
        let bvh2 = binary_tree(bounds);
        match width {
            #[cfg(target_arch = "x86_64")]
            BvhWidth::Eight if width.supported() => {
                let c = collapse::collapse::<Node8, 8>(&bvh2, triangles);
                Self {
                    nodes: Nodes::Eight(c.nodes),
                    packets: c.packets,
                    order: c.order,
                }
            }
            _ => {
                let c = collapse::collapse::<Node4, 4>(&bvh2, triangles);
                Self {
                    nodes: Nodes::Four(c.nodes),
                    packets: c.packets,
                    order: c.order,
                }
            }
        }
    }

    /// The width of the inner nodes.
    pub fn width(&self) -> BvhWidth {
        match self.nodes {
            Nodes::Four(_) => BvhWidth::Four,
            #[cfg(target_arch = "x86_64")]
            Nodes::Eight(_) => BvhWidth::Eight,
        }
    }

    /// Inner nodes.
    pub fn node_count(&self) -> usize {
        match &self.nodes {
            Nodes::Four(n) => n.len(),
            #[cfg(target_arch = "x86_64")]
            Nodes::Eight(n) => n.len(),
        }
    }

    /// Leaf packets (up to four primitives each).
    pub fn packet_count(&self) -> usize {
        self.packets.len()
    }

    /// Bytes of nodes and packets.
    pub fn memory_bytes(&self) -> usize {
        let nodes = match &self.nodes {
            Nodes::Four(n) => std::mem::size_of_val(n.as_slice()),
            #[cfg(target_arch = "x86_64")]
            Nodes::Eight(n) => std::mem::size_of_val(n.as_slice()),
        };
        nodes + std::mem::size_of_val(self.packets.as_slice())
    }

    /// BVH order → index of the primitive in the build input.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// The closest hit along the ray `o + t d` (`tr` prepared from it) with `t ∈ (0, t_max)`. Triangles are
    /// tested here; every other primitive `k` (BVH order) by `other(k, t)`, which returns
    /// `(t, b1, b2)` of a hit closer than `t`. Of triangles hit at exactly the same distance (a
    /// ray through an edge two triangles share), the one first in BVH order wins, whatever the
    /// order of the visit, so both widths name the same primitive. `on_hit(k)` hears of each
    /// triangle that becomes the closest hit so far, while the traversal goes on.
    #[inline(always)]
    pub fn closest(
        &self,
        o: Vec3,
        d: Vec3,
        tr: &TriangleRay,
        t_max: f32,
        other: impl FnMut(u32, f32) -> Option<(f32, f32, f32)>,
        on_hit: impl FnMut(u32),
    ) -> Option<WideHit> {
        match &self.nodes {
            Nodes::Four(n) if n.is_empty() => None,
            // SAFETY: four-wide nodes need nothing beyond the target's baseline; the builder's
            // child references index into `n` and `self.packets`.
            Nodes::Four(n) => unsafe { closest4(n, &self.packets, tr, o, d, t_max, other, on_hit) },
            // SAFETY: eight-wide nodes exist only where AVX2 was detected (`Nodes::Eight`).
            #[cfg(target_arch = "x86_64")]
            Nodes::Eight(n) => unsafe {
                closest8(
                    n,
                    &self.packets,
                    tr,
                    &Node8::ray(o, d),
                    t_max,
                    other,
                    on_hit,
                )
            },
        }
    }

    /// True if any primitive is hit with `t ∈ (0, t_max)`; `other` as for [`Self::closest`]
    /// (only whether it returns a hit matters).
    #[inline(always)]
    pub fn any(
        &self,
        o: Vec3,
        d: Vec3,
        tr: &TriangleRay,
        t_max: f32,
        other: impl FnMut(u32, f32) -> Option<(f32, f32, f32)>,
    ) -> bool {
        match &self.nodes {
            Nodes::Four(n) if n.is_empty() => false,
            // SAFETY: as in `closest`.
            Nodes::Four(n) => unsafe { any4(n, &self.packets, tr, o, d, t_max, other) },
            // SAFETY: as in `closest`.
            #[cfg(target_arch = "x86_64")]
            Nodes::Eight(n) => unsafe { any8(n, &self.packets, tr, o, d, t_max, other) },
        }
    }
}

impl WideBvh {
    /// The tree over triangles `tris` (the unit tests' trees).
    #[cfg(test)]
    fn over_triangles(tris: &[[Vec3; 3]], width: BvhWidth) -> Self {
        let bounds: Vec<Aabb> = tris
            .iter()
            .map(|t| Aabb {
                min: t[0].min(t[1]).min(t[2]),
                max: t[0].max(t[1]).max(t[2]),
            })
            .collect();
        let prims: Vec<Option<[Vec3; 3]>> = tris.iter().copied().map(Some).collect();
        Self::build_with_width(&bounds, &prims, width)
    }
}

/// obvhs's binary tree over `bounds` (non-empty), one primitive per leaf: packets are formed by
/// the collapse from whole subtrees.
fn binary_tree(bounds: &[Aabb]) -> obvhs::bvh2::Bvh2 {
    let oboxes: Vec<obvhs::aabb::Aabb> = bounds
        .iter()
        .map(|b| obvhs::aabb::Aabb::new(Vec3A::from(b.min), Vec3A::from(b.max)))
        .collect();
    let params = obvhs::BvhBuildParams {
        max_prims_per_leaf: 1,
        ..obvhs::BvhBuildParams::medium_build()
    };
    obvhs::bvh2::builder::build_bvh2(&oboxes, params, &mut std::time::Duration::default())
}

/// A ray of a packet of eight as the unit tests give it: origin, direction, `t_max` and the
/// prepared triangle ray.
#[cfg(test)]
type PacketRay = (Vec3, Vec3, f32, TriangleRay);

impl WideBvh {
    /// The closest hits of up to eight rays traced together (the first eight of `rays`), each
    /// exactly the hit [`Self::closest`] gives it; `other(i, k, t)` tests non-triangle
    /// primitive `k` for ray `i`. Returns the hits and the mask of the lanes traced: rays
    /// without `t_max > 0`, rays whose triangle-test axis permutation differs from the first
    /// traced ray's, all rays where no more than [`ray8::ONE_BY_ONE`] would be left (the
    /// packet would hand each over at the root) and all rays where nodes are 4-wide are left
    /// to the caller (bit clear).
    pub fn closest_packet(
        &self,
        rays: &[Ray],
        other: impl FnMut(usize, u32, f32) -> Option<(f32, f32, f32)>,
    ) -> ([Option<WideHit>; 8], u32) {
        match &self.nodes {
            #[cfg(target_arch = "x86_64")]
            Nodes::Eight(n) if !n.is_empty() => {
                // SAFETY (both calls): eight-wide nodes exist only where AVX2 was detected; the
                // builder's child references index into `n` and `self.packets`.
                let (rays, taken) = unsafe { ray8::Rays8::from_rays(rays, ray8::ONE_BY_ONE) };
                if taken == 0 {
                    return ([None; 8], 0);
                }
                let hits = unsafe {
                    ray8::closest8::<{ ray8::ONE_BY_ONE }>(n, &self.packets, &rays, other)
                };
                (hits, taken)
            }
            _ => ([None; 8], 0),
        }
    }

    /// Whether each of up to eight rays is blocked before its `t_max`, as [`Self::any`]; the
    /// rays as for [`Self::closest_packet`]. Returns the occluded mask and the traced mask.
    pub fn any_packet(
        &self,
        rays: &[Ray],
        other: impl FnMut(usize, u32, f32) -> Option<(f32, f32, f32)>,
    ) -> (u32, u32) {
        match &self.nodes {
            #[cfg(target_arch = "x86_64")]
            Nodes::Eight(n) if !n.is_empty() => {
                // SAFETY (both calls): as in `closest_packet`.
                let (rays, taken) = unsafe { ray8::Rays8::from_rays(rays, ray8::ONE_BY_ONE) };
                if taken == 0 {
                    return (0, 0);
                }
                let hit =
                    unsafe { ray8::any8::<{ ray8::ONE_BY_ONE }>(n, &self.packets, &rays, other) };
                (hit, taken)
            }
            _ => (0, 0),
        }
    }
}

/// The 4-wide closest-hit traversal (the fallback), out of line like [`closest8`], so the
/// queries that dispatch to either stay small: inlined, its registers and stack were saved and
/// set up on every query, whichever width ran.
///
/// # Safety
/// As [`traverse::closest`] for four-wide nodes (nothing beyond the target's baseline).
#[inline(never)]
#[allow(clippy::too_many_arguments)]
unsafe fn closest4(
    nodes: &[Node4],
    packets: &[Packet],
    tr: &TriangleRay,
    o: Vec3,
    d: Vec3,
    t_max: f32,
    other: impl FnMut(u32, f32) -> Option<(f32, f32, f32)>,
    on_hit: impl FnMut(u32),
) -> Option<WideHit> {
    // SAFETY: the caller's contract.
    unsafe {
        traverse::closest::<Node4, 4>(
            nodes,
            packets,
            tr,
            &Node4::ray(o, d),
            traverse::Start::root(t_max),
            other,
            on_hit,
        )
    }
}

/// The 4-wide any-hit traversal, out of line as [`closest4`].
///
/// # Safety
/// As [`closest4`].
#[inline(never)]
unsafe fn any4(
    nodes: &[Node4],
    packets: &[Packet],
    tr: &TriangleRay,
    o: Vec3,
    d: Vec3,
    t_max: f32,
    other: impl FnMut(u32, f32) -> Option<(f32, f32, f32)>,
) -> bool {
    // SAFETY: the caller's contract.
    unsafe { traverse::any::<Node4, 4>(nodes, packets, tr, &Node4::ray(o, d), t_max, 0, other) }
}

/// The 8-wide closest-hit traversal, compiled for AVX2 (so the node test inlines).
///
/// # Safety
/// The CPU supports AVX2; `nodes` is non-empty.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn closest8(
    nodes: &[Node8],
    packets: &[Packet],
    tr: &TriangleRay,
    br: &<Node8 as WideNode<8>>::Ray,
    t_max: f32,
    other: impl FnMut(u32, f32) -> Option<(f32, f32, f32)>,
    on_hit: impl FnMut(u32),
) -> Option<WideHit> {
    // SAFETY: the caller's contract.
    unsafe {
        traverse::closest::<Node8, 8>(
            nodes,
            packets,
            tr,
            br,
            traverse::Start::root(t_max),
            other,
            on_hit,
        )
    }
}

/// The 8-wide any-hit traversal, compiled for AVX2.
///
/// # Safety
/// As [`closest8`].
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn any8(
    nodes: &[Node8],
    packets: &[Packet],
    tr: &TriangleRay,
    o: Vec3,
    d: Vec3,
    t_max: f32,
    other: impl FnMut(u32, f32) -> Option<(f32, f32, f32)>,
) -> bool {
    // SAFETY: the caller's contract.
    unsafe { traverse::any::<Node8, 8>(nodes, packets, tr, &Node8::ray(o, d), t_max, 0, other) }
}
