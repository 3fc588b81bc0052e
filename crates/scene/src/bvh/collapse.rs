//! Collapses obvhs's binary tree into a wide one by the surface area heuristic: of every way to
//! cut the binary tree into nodes of at most `W` children and leaves of whole binary subtrees of
//! at most [`LEAF_PRIMS`] primitives (runs of [`Packet`]s, filled four at a time), the one of
//! least expected cost (Ylitie, Karras and Laine 2017, sec. 3.1, by dynamic programming over
//! the binary nodes). Leaves are whole subtrees taken in the binary tree's order, so the BVH
//! order of the primitives, and with it the tie rule of the traversals, does not depend on the
//! cut: every hit is the one the greedy collapse before it found (docs/performance.md, ninth
//! session).

use super::packet::{EMPTY, PACKET_LANES, Packet};
use super::traverse::{MAX_RUN, WideNode, leaf_ref};
use caustica_core::Vec3;

/// The wide tree's parts: inner nodes (the root first), packets, and BVH order → index of the
/// primitive in the build input.
pub(super) struct Collapsed<N> {
    pub nodes: Vec<N>,
    pub packets: Vec<Packet>,
    pub order: Vec<u32>,
}

/// Collapses `bvh2` (leaves of at most [`LEAF_PRIMS`] primitives; [`super::binary_tree`]
/// builds them of one) into nodes of `W` children.
pub(super) fn collapse<N: WideNode<W>, const W: usize>(
    bvh2: &obvhs::bvh2::Bvh2,
    triangles: &[Option<[Vec3; 3]>],
) -> Collapsed<N> {
    let count = subtree_counts(bvh2);
    let first = first_in_order(bvh2, &count);
    let mut c = Collapse {
        bvh2,
        triangles,
        out: Collapsed {
            nodes: Vec::new(),
            packets: Vec::new(),
            order: vec![EMPTY; count[0] as usize],
        },
        sah: Sah::new(bvh2, &count, W),
        first,
    };
    c.run::<W>();
    c.out
}

/// Primitives in the subtree of each binary node, by an explicit post-order walk (trees may
/// be deep).
fn subtree_counts(bvh2: &obvhs::bvh2::Bvh2) -> Vec<u32> {
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
    count
}

/// The BVH order of the first primitive under each binary node: primitives are numbered in
/// the binary tree's depth-first order (first child first), which does not depend on the
/// width of the collapsed tree. Leaves are whole binary subtrees, so each holds consecutive
/// numbers, four to a packet in lane order.
fn first_in_order(bvh2: &obvhs::bvh2::Bvh2, count: &[u32]) -> Vec<u32> {
    let nodes = &bvh2.nodes;
    let mut first = vec![0u32; nodes.len()];
    let mut stack = vec![0usize];
    while let Some(i) = stack.pop() {
        let n = &nodes[i];
        if !n.is_leaf() {
            let c = n.first_index as usize;
            first[c] = first[i];
            first[c + 1] = first[i] + count[c];
            stack.extend([c, c + 1]);
        }
    }
    first
}

/// Most primitives in one leaf: a run of two packets at most. Against leaves of one packet,
/// leaves of up to eight removed the tree's last level of nodes and traced 2–14 % more rays per
/// second on the benchmark's 1 M triangles (docs/performance.md, first session).
const LEAF_PRIMS: usize = 8;
const _: () = assert!(LEAF_PRIMS.div_ceil(PACKET_LANES) <= MAX_RUN);

struct Collapse<'a, N> {
    bvh2: &'a obvhs::bvh2::Bvh2,
    triangles: &'a [Option<[Vec3; 3]>],
    /// BVH order of the first primitive under each binary node.
    first: Vec<u32>,
    /// Where the binary tree is cut.
    sah: Sah,
    out: Collapsed<N>,
}

impl<N> Collapse<'_, N> {
    fn run<const W: usize>(&mut self)
    where
        N: WideNode<W>,
    {
        // The root is always a node (a lone packet goes in its first lane).
        let mut work = vec![(0usize, EMPTY, 0usize)];
        while let Some((b, parent, lane)) = work.pop() {
            let child = if self.sah.leaf[b] && parent != EMPTY {
                self.leaf(b)
            } else {
                let id = self.out.nodes.len() as u32;
                let kids = self.sah.children(self.bvh2, b, W);
                self.out.nodes.push(N::empty());
                // Reverse order so lane 0's subtree is laid out first (depth first).
                for (l, &k) in kids.iter().enumerate().rev() {
                    work.push((k, id, l));
                }
                id
            };
            if parent != EMPTY {
                let bb = self.bvh2.nodes[b].aabb();
                self.out.nodes[parent as usize].set_lane(
                    lane,
                    Vec3::from(bb.min),
                    Vec3::from(bb.max),
                    child,
                );
            }
        }
    }

    /// A leaf of every primitive under binary node `b` (at most [`LEAF_PRIMS`]): a run of
    /// packets filled four at a time with the primitives in BVH order (the binary tree's
    /// depth-first order), so a leaf of `n` primitives takes ⌈n/4⌉ packets.
    fn leaf(&mut self, b: usize) -> u32 {
        let nodes = &self.bvh2.nodes;
        let mut inputs = Vec::with_capacity(LEAF_PRIMS);
        let mut stack = vec![b];
        while let Some(i) = stack.pop() {
            let n = &nodes[i];
            if n.is_leaf() {
                let first = n.first_index as usize;
                inputs.extend_from_slice(
                    &self.bvh2.primitive_indices[first..first + n.prim_count as usize],
                );
            } else {
                stack.extend([n.first_index as usize + 1, n.first_index as usize]);
            }
        }
        let first_packet = self.out.packets.len();
        for (c, chunk) in inputs.chunks(PACKET_LANES).enumerate() {
            self.packet(self.first[b] + (c * PACKET_LANES) as u32, chunk);
        }
        leaf_ref(first_packet, self.out.packets.len() - first_packet)
    }

    /// A packet of the primitives `inputs` (indices in the build input, at most four), numbered
    /// `k0, k0 + 1, …` in BVH order, lane by lane.
    fn packet(&mut self, k0: u32, inputs: &[u32]) {
        let mut pk = Packet::EMPTY_PACKET;
        for (lane, &input) in inputs.iter().enumerate() {
            let k = k0 + lane as u32;
            self.out.order[k as usize] = input;
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
        }
        self.out.packets.push(pk);
    }
}

/// Relative costs of a node's box test and of a packet's triangle test, per ray that reaches
/// them. Equal costs gave the fewest instructions per ray on the benchmark's meshes of 4 K and
/// 65 K triangles; a packet cost from 0.7 to 1.2 node tests was within 1.1 % of it, and from
/// 1.35 up the 65 K mesh took 7–12 % more (docs/performance.md, ninth session).
const COST_NODE: f32 = 1.0;
const COST_PACKET: f32 = 1.0;

/// The SAH-optimal collapse of a binary tree into nodes of at most `W` (≤ 8) children (Ylitie,
/// Karras and Laine 2017, sec. 3.1): the cost of a subtree cut into at most `i` roots, from its
/// two children's, in post order. A root costs its half area times [`COST_PACKET`] per packet
/// as a leaf, or times [`COST_NODE`] plus the cost of its `W` children as a node (the chance
/// that a ray reaching the parent reaches it is its area over the parent's, as in every SAH).
/// About 48 bytes per binary node while the tree is collapsed.
struct Sah {
    /// `cost[n][i − 1]`: the least cost of binary node `n`'s subtree as at most `i` roots.
    cost: Vec<[f32; 8]>,
    /// `roots[n][i − 1]`: how many roots that least cost uses (1: `n` itself).
    roots: Vec<[u8; 8]>,
    /// `split[n][j − 1]`: of `j` roots under `n` (opened), how many its first child takes.
    split: Vec<[u8; 8]>,
    /// `n` as a single root is a leaf (else a node).
    leaf: Vec<bool>,
}

impl Sah {
    fn new(bvh2: &obvhs::bvh2::Bvh2, count: &[u32], w: usize) -> Self {
        assert!(w <= 8, "nodes of at most eight children");
        let nodes = &bvh2.nodes;
        let n = nodes.len();
        let mut s = Self {
            cost: vec![[f32::INFINITY; 8]; n],
            roots: vec![[1; 8]; n],
            split: vec![[0; 8]; n],
            leaf: vec![false; n],
        };
        // Post order: children before parents.
        let mut stack = vec![(0usize, false)];
        while let Some((i, children_done)) = stack.pop() {
            let nd = &nodes[i];
            if !nd.is_leaf() && !children_done {
                let c = nd.first_index as usize;
                stack.extend([(i, true), (c, false), (c + 1, false)]);
                continue;
            }
            let area = nd.aabb().half_area();
            let packets = (count[i] as usize).div_ceil(PACKET_LANES) as f32;
            let c_leaf = if count[i] as usize <= LEAF_PRIMS {
                area * COST_PACKET * packets
            } else {
                f32::INFINITY
            };
            let mut dist = [f32::INFINITY; 8];
            if !nd.is_leaf() {
                let (l, r) = (nd.first_index as usize, nd.first_index as usize + 1);
                for j in 2..=w {
                    for k in 1..j {
                        let c = s.cost[l][k - 1] + s.cost[r][j - k - 1];
                        if c < dist[j - 1] {
                            dist[j - 1] = c;
                            s.split[i][j - 1] = k as u8;
                        }
                    }
                }
            }
            let c_node = area * COST_NODE + dist[w - 1];
            s.leaf[i] = c_leaf <= c_node;
            s.cost[i][0] = c_leaf.min(c_node);
            for j in 2..=w {
                if dist[j - 1] < s.cost[i][j - 2] {
                    s.cost[i][j - 1] = dist[j - 1];
                    s.roots[i][j - 1] = j as u8;
                } else {
                    s.cost[i][j - 1] = s.cost[i][j - 2];
                    s.roots[i][j - 1] = s.roots[i][j - 2];
                }
            }
        }
        s
    }

    /// The roots of binary node `b`'s subtree as at most `i` roots, in the binary tree's order.
    fn roots_of(&self, bvh2: &obvhs::bvh2::Bvh2, b: usize, i: usize, out: &mut Vec<usize>) {
        let j = self.roots[b][i - 1] as usize;
        if j <= 1 {
            out.push(b);
        } else {
            self.distribute(bvh2, b, j, out);
        }
    }

    /// Binary node `b` opened into `j` roots.
    fn distribute(&self, bvh2: &obvhs::bvh2::Bvh2, b: usize, j: usize, out: &mut Vec<usize>) {
        let c = bvh2.nodes[b].first_index as usize;
        let k = self.split[b][j - 1] as usize;
        self.roots_of(bvh2, c, k, out);
        self.roots_of(bvh2, c + 1, j - k, out);
    }

    /// The children of the wide node that replaces binary node `b`.
    fn children(&self, bvh2: &obvhs::bvh2::Bvh2, b: usize, w: usize) -> Vec<usize> {
        let mut out = Vec::with_capacity(w);
        if bvh2.nodes[b].is_leaf() {
            out.push(b);
        } else {
            self.distribute(bvh2, b, w, &mut out);
        }
        out
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::super::node4::Node4;
    use super::super::node8::Node8;
    use super::*;
    use crate::shape::Aabb;
    use caustica_core::sampling::Pcg32;

    /// `n` small random triangles in a 10 m cube and their binary tree.
    fn soup(n: usize) -> (obvhs::bvh2::Bvh2, Vec<Option<[Vec3; 3]>>) {
        let mut rng = Pcg32::new(21, 5);
        let mut v = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let tris: Vec<Option<[Vec3; 3]>> = (0..n)
            .map(|_| {
                let c = v() * 10.0;
                Some([c, c + v() * 0.4, c + v() * 0.4])
            })
            .collect();
        let bounds: Vec<Aabb> = tris
            .iter()
            .flatten()
            .map(|t| Aabb {
                min: t[0].min(t[1]).min(t[2]),
                max: t[0].max(t[1]).max(t[2]),
            })
            .collect();
        (super::super::binary_tree(&bounds), tris)
    }

    /// The binary tree's primitives, first child first: the BVH order every cut must keep.
    fn depth_first(bvh2: &obvhs::bvh2::Bvh2) -> Vec<u32> {
        let mut out = Vec::new();
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let n = &bvh2.nodes[i];
            if n.is_leaf() {
                let f = n.first_index as usize;
                out.extend_from_slice(&bvh2.primitive_indices[f..f + n.prim_count as usize]);
            } else {
                stack.extend([n.first_index as usize + 1, n.first_index as usize]);
            }
        }
        out
    }

    fn half_area(min: Vec3, max: Vec3) -> f32 {
        let d = max - min;
        d.x * d.y + d.y * d.z + d.z * d.x
    }

    /// The expected cost of the wide subtree under child reference `child` of box `(min, max)`,
    /// counting its leaves' packets, as [`Sah`] defines it.
    fn cost(c: &Collapsed<Node8>, child: u32, min: Vec3, max: Vec3, leaves: &mut usize) -> f64 {
        let area = half_area(min, max) as f64;
        if child & super::super::traverse::LEAF != 0 {
            *leaves += 1;
            let run = super::super::traverse::leaf_packets(&c.packets, child);
            assert!(
                (1..=2).contains(&run.len()),
                "a leaf of {} packets",
                run.len()
            );
            return area * (COST_PACKET as f64) * run.len() as f64;
        }
        let node = &c.nodes[child as usize];
        let mut sum = area * COST_NODE as f64;
        for lane in 0..8 {
            if node.child(lane) != EMPTY {
                let (lo, hi) = node.lane_box(lane);
                let (lo, hi) = (Vec3::from_array(lo), Vec3::from_array(hi));
                sum += cost(c, node.child(lane), lo, hi, leaves);
            }
        }
        sum
    }

    /// The cut keeps the binary tree's order of the primitives at both widths, and the wide tree
    /// it builds has the least cost the dynamic programme found (its leaves at most two
    /// packets): what the choices say is what the tree is.
    #[test]
    fn the_collapse_keeps_the_order_and_builds_the_least_cost_it_found() {
        for n in [1, 7, 9, 100, 3000] {
            let (bvh2, tris) = soup(n);
            let want = depth_first(&bvh2);
            let c8 = collapse::<Node8, 8>(&bvh2, &tris);
            let c4 = collapse::<Node4, 4>(&bvh2, &tris);
            assert_eq!(c8.order, want, "{n} triangles, eight wide");
            assert_eq!(c4.order, want, "{n} triangles, four wide");
            if n < 9 {
                continue; // The root could then be a leaf to the programme, never to the tree.
            }
            let sah = Sah::new(&bvh2, &subtree_counts(&bvh2), 8);
            let root = bvh2.nodes[0].aabb();
            let mut leaves = 0;
            let got = cost(
                &c8,
                0,
                Vec3::from(root.min),
                Vec3::from(root.max),
                &mut leaves,
            );
            let best = sah.cost[0][0] as f64;
            assert!(
                (got - best).abs() <= 1e-4 * best,
                "{n} triangles: the tree costs {got}, the programme found {best}"
            );
            // Fewer leaves than primitives: the programme does join primitives into packets.
            assert!(leaves < n, "{leaves} leaves for {n} triangles");
        }
    }
}
