//! Points that each carry their own support radius, searched by "whose ball contains x?".
//!
//! Variable-bandwidth estimates (eq. 2.13, each point's own pilot bandwidth) and photon
//! differential footprints (seed 002 eq. 10, each footprint's own gather radius) both need the
//! points whose support covers a query. Radii span orders of magnitude (a lone photon far from
//! the others, a footprint spread by a grazing exit), so one range query at the largest radius
//! would visit the whole set. Instead the points are grouped by radius octave [2ᵉ, 2ᵉ⁺¹) with a
//! k-d tree each, and each tree is searched at its own largest radius: a query visits only
//! points within twice their own radius. Points with a radius that is not positive and finite
//! are left out.

use crate::kdtree::KdTree;
use caustica_core::Vec3;

/// Points grouped by support radius (see the [module docs](self)).
#[derive(Clone, Debug, Default)]
pub struct RadiusBuckets {
    /// (largest radius in the octave, tree over its points, index of each tree point).
    buckets: Vec<(f32, KdTree, Vec<u32>)>,
}

impl RadiusBuckets {
    /// Groups point `i` (position `positions[i]`, radius `radii[i]`, same lengths) by octave.
    /// Deterministic: buckets in octave order, points in index order within each.
    pub fn build(positions: &[Vec3], radii: &[f32]) -> Self {
        let mut keys: Vec<(i32, u32)> = radii
            .iter()
            .enumerate()
            .filter(|(_, r)| r.is_finite() && **r > 0.0)
            .map(|(i, r)| (r.log2().floor() as i32, i as u32))
            .collect();
        keys.sort_unstable();
        let buckets = keys
            .chunk_by(|a, b| a.0 == b.0)
            .map(|group| {
                let index: Vec<u32> = group.iter().map(|e| e.1).collect();
                let pos: Vec<Vec3> = index.iter().map(|&i| positions[i as usize]).collect();
                let rmax = index.iter().map(|&i| radii[i as usize]).fold(0.0, f32::max);
                (rmax, KdTree::build(&pos), index)
            })
            .collect();
        Self { buckets }
    }

    /// This grouping with its points renumbered by *slot*: the buckets laid end to end in
    /// octave order, each in its tree's order. Also returns the original index of each slot.
    /// A caller that permutes its records by that order reads the candidates of a query from
    /// short contiguous runs instead of scattered records (neighbours in a tree are neighbours
    /// in memory). The candidates of every query, and their order, are unchanged: only their
    /// numbers are (`for_each_candidate` then yields slots).
    pub fn into_slot_order(self) -> (Self, Vec<u32>) {
        let mut order: Vec<u32> = Vec::new();
        let buckets = self
            .buckets
            .into_iter()
            .map(|(rmax, tree, index)| {
                let (tree, by_tree) = tree.into_tree_order();
                let first = order.len() as u32;
                order.extend(by_tree.iter().map(|&local| index[local as usize]));
                (rmax, tree, (first..order.len() as u32).collect())
            })
            .collect();
        (Self { buckets }, order)
    }

    /// Calls `f(i)` for every point `i` within its bucket's largest radius of `x` (a superset of
    /// the points whose own ball contains `x`: the caller tests its exact support).
    pub fn for_each_candidate(&self, x: Vec3, mut f: impl FnMut(u32)) {
        self.for_each_candidate_at(x, |i, _| f(i));
    }

    /// [`Self::for_each_candidate`] with each candidate's squared distance to `x`, `f(i, d²)`
    /// (m²), which the search computed anyway: a caller can reject by its own radius before
    /// reading anything else of the point.
    pub fn for_each_candidate_at(&self, x: Vec3, mut f: impl FnMut(u32, f32)) {
        for (rmax, tree, index) in &self.buckets {
            tree.range(x, rmax * rmax, |local, d2| f(index[local as usize], d2));
        }
    }

    /// Number of octaves.
    pub fn octaves(&self) -> usize {
        self.buckets.len()
    }

    /// Heap bytes of the trees and index maps.
    pub fn memory_bytes(&self) -> usize {
        self.buckets
            .iter()
            .map(|(_, t, idx)| t.memory_bytes() + idx.capacity() * 4)
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::Pcg32;

    /// Slot order: the same candidates in the same order, numbered by slot; the order maps
    /// each slot back to its point, each point (with a usable radius) once.
    #[test]
    fn slot_order_keeps_every_query() {
        let mut rng = Pcg32::new(8, 1);
        let n = 3000;
        let pos: Vec<Vec3> = (0..n)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()))
            .collect();
        let mut radii: Vec<f32> = (0..n)
            .map(|_| 0.01 * 2f32.powf(5.0 * rng.next_f32()))
            .collect();
        radii[7] = f32::INFINITY;
        let b = RadiusBuckets::build(&pos, &radii);
        let (slots, order) = b.clone().into_slot_order();
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(
            sorted,
            (0..n as u32).filter(|&i| i != 7).collect::<Vec<_>>()
        );
        // A renumbering indeed: the slots are not the original indices.
        assert!(order.iter().zip(0..).any(|(&i, s)| i != s));
        let mut found = 0;
        for j in 0..200 {
            let x = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            let (mut a, mut c) = (Vec::new(), Vec::new());
            b.for_each_candidate(x, |i| a.push(i));
            slots.for_each_candidate_at(x, |s, d2| {
                let i = order[s as usize];
                assert_eq!(d2, pos[i as usize].distance_squared(x));
                c.push(i)
            });
            assert_eq!(a, c, "query {j}");
            found += a.len();
        }
        assert!(found > 1000, "{found}");
    }

    /// The candidates include every point whose ball contains the query (brute force), for
    /// radii spanning six octaves; non-positive and NaN radii are never returned.
    #[test]
    fn candidates_cover_every_containing_ball() {
        let mut rng = Pcg32::new(3, 5);
        let n = 2000;
        let pos: Vec<Vec3> = (0..n)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), 0.0))
            .collect();
        let mut radii: Vec<f32> = (0..n)
            .map(|_| 0.005 * 2f32.powf(6.0 * rng.next_f32()))
            .collect();
        radii[0] = 0.0;
        radii[1] = f32::NAN;
        let b = RadiusBuckets::build(&pos, &radii);
        assert!(b.octaves() >= 6);
        for j in 0..50 {
            let x = Vec3::new(0.02 * j as f32, 0.5, 0.0);
            let mut got = Vec::new();
            b.for_each_candidate(x, |i| got.push(i));
            assert!(!got.contains(&0) && !got.contains(&1));
            for i in 2..n as u32 {
                if (pos[i as usize] - x).length() < radii[i as usize] {
                    assert!(got.contains(&i), "point {i} missed at {x}");
                }
            }
            // Each candidate lies within twice its own radius (the octave bound).
            for &i in &got {
                assert!((pos[i as usize] - x).length() < 2.0 * radii[i as usize]);
            }
        }
    }
}
