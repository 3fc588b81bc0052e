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

    /// Calls `f(i)` for every point `i` within its bucket's largest radius of `x` (a superset of
    /// the points whose own ball contains `x`: the caller tests its exact support).
    pub fn for_each_candidate(&self, x: Vec3, mut f: impl FnMut(u32)) {
        for (rmax, tree, index) in &self.buckets {
            tree.range(x, rmax * rmax, |local, _| f(index[local as usize]));
        }
    }

    /// Largest radius of any point (0 if none).
    pub fn max_radius(&self) -> f32 {
        self.buckets.iter().map(|b| b.0).fold(0.0, f32::max)
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
