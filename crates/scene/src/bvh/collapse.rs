//! Collapses obvhs's binary tree into a wide one: every subtree of at most [`LEAF_PRIMS`]
//! primitives reached as a child becomes one leaf (a run of [`Packet`]s, filled four at a
//! time), and a node of width `W` takes its binary children, repeatedly replacing the child of
//! largest surface area by that child's two children until it has `W`.

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

/// Collapses `bvh2` (leaves of one primitive or more) into nodes of `W` children.
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
        count,
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

/// Most primitives in one leaf: a subtree of at most eight primitives reached as a child
/// becomes a leaf (a run of two packets at most). A node still opens every child of more than
/// four primitives while it has free lanes, so runs of two packets are left only where a node
/// is full (keeping children of five to eight primitives as leaves instead made a ray test
/// 45 % more packets: docs/performance.md). Against leaves of one packet this removes the
/// tree's last level of nodes (106 059 → 58 600 eight-wide nodes on the benchmark's 1 M
/// triangles) and traced 2–14 % more rays per second there (docs/performance.md).
const LEAF_PRIMS: usize = 8;
const _: () = assert!(LEAF_PRIMS.div_ceil(PACKET_LANES) <= MAX_RUN);

struct Collapse<'a, N> {
    bvh2: &'a obvhs::bvh2::Bvh2,
    triangles: &'a [Option<[Vec3; 3]>],
    /// Primitives under each binary node.
    count: Vec<u32>,
    /// BVH order of the first primitive under each binary node.
    first: Vec<u32>,
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
            let child = if self.count[b] as usize <= LEAF_PRIMS && parent != EMPTY {
                self.leaf(b)
            } else {
                let id = self.out.nodes.len() as u32;
                let kids = self.children(b, W);
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

    /// The binary nodes that become the children of a wide node replacing binary node `b`.
    fn children(&self, b: usize, width: usize) -> Vec<usize> {
        let nodes = &self.bvh2.nodes;
        let mut kids = vec![b];
        while kids.len() < width {
            // Open the largest child that cannot be a packet; else the largest inner child.
            let pick = |must_open: bool| {
                kids.iter()
                    .enumerate()
                    .filter(|&(_, &k)| {
                        !nodes[k].is_leaf() && (!must_open || self.count[k] as usize > PACKET_LANES)
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
