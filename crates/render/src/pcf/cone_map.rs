//! The photon cone map (seed 001 sec. 4.1.1): a 3-D k-d tree over the cones' positions and a
//! linear scan of the directions of those within σ (the seed's choice: no 5-D tree, whose
//! curse of dimensionality and build cost it judged not worth it). A lookup evaluates no
//! material (the cones carry the BSDF already), which is PCF's point: it works on any BSDF,
//! delta ones included.
//!
//! The radiance estimate (eq. 3.11 with the box kernel eq. 3.6):
//!
//! ```text
//! L̂(x, ω) = 1/(N_L C_σ) Σ_{j : ‖X_j − x‖ < σ, ∠(ω_j, ω) < t(σ)} P_{Λ,j}      (W/m²/sr)
//! ```
//!
//! normalised by the number of light paths N_L, not of cones (eq. 2.25; spec notes Q3).

use super::cone::PhotonCone;
use super::kernel::{Aperture, DiskCapKernel};
use caustica_core::{Spectrum, Vec3};
use caustica_density::KdTree;

/// An iteration's cones.
pub struct PhotonConeMap {
    tree: KdTree,
    cones: Vec<PhotonCone>,
    /// N_L, the light paths the cones came from.
    light_paths: u64,
}

/// Which cones a lookup sums.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConeSet {
    /// Every light-path length: the estimate at the lookup vertex.
    All,
    /// Length 1 (direct light): nested PCF's `all`.
    Direct,
    /// Length 1 from delta lights: nested PCF's `delta-lights`.
    DirectFromDeltaLights,
    /// Lengths ≥ 2: at a lookup whose direct light comes from next-event estimation.
    Indirect,
}

impl ConeSet {
    /// True if a cone of light-path `length` (from a delta light or not) is in the set.
    #[inline]
    pub fn admits_length(self, length: u32, delta_light: bool) -> bool {
        match self {
            ConeSet::All => true,
            ConeSet::Direct => length == 1,
            ConeSet::DirectFromDeltaLights => length == 1 && delta_light,
            ConeSet::Indirect => length >= 2,
        }
    }

    #[inline]
    fn admits(self, c: &PhotonCone) -> bool {
        self.admits_length(c.length as u32, c.delta_light)
    }
}

/// What lookups did (for the render notes).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LookupStats {
    pub lookups: u64,
    /// Cones that passed the spatial test (and were scanned for their direction).
    pub scanned: u64,
    /// Cones inside the 4-D kernel.
    pub inside: u64,
}

impl PhotonConeMap {
    /// The map of `cones` traced from `light_paths` light paths. The cones are stored in the
    /// k-d tree's order, so a range query reads them from contiguous memory (1.6× faster
    /// lookups, `benches/pcf.rs`); cones at non-finite positions are dropped (no query can
    /// find them).
    pub fn build(cones: Vec<PhotonCone>, light_paths: u64) -> Self {
        let points: Vec<Vec3> = cones.iter().map(|c| c.p).collect();
        let (tree, order) = KdTree::build(&points).into_tree_order();
        let cones = order.iter().map(|&i| cones[i as usize]).collect();
        Self {
            tree,
            cones,
            light_paths,
        }
    }

    pub fn len(&self) -> usize {
        self.cones.len()
    }

    pub fn is_empty(&self) -> bool {
        self.cones.is_empty()
    }

    pub fn light_paths(&self) -> u64 {
        self.light_paths
    }

    pub fn cones(&self) -> &[PhotonCone] {
        &self.cones
    }

    /// Bytes held (cones and tree).
    pub fn memory_bytes(&self) -> usize {
        self.tree.memory_bytes() + self.cones.capacity() * std::mem::size_of::<PhotonCone>()
    }

    /// L̂(x, ω) (W/m²/sr) with kernel `k`: the radiance leaving `x` in the direction the
    /// `aperture` looks at (its cap around ω, or a Lambertian surface's hemisphere). `set`: which light-path lengths and lights count ([`ConeSet`]).
    /// `surface`: only cones on this shape whose geometric normal agrees with this one
    /// (n_j·n_x > 0; `ConeSurfaces::Same`); `None`: every cone in the ball (seed 001's
    /// estimator).
    pub fn estimate(
        &self,
        x: Vec3,
        aperture: Aperture,
        k: &DiskCapKernel,
        set: ConeSet,
        surface: Option<(u32, Vec3)>,
        stats: &mut LookupStats,
    ) -> Spectrum {
        let mut sum = Spectrum::ZERO;
        let (mut scanned, mut inside) = (0u64, 0u64);
        self.tree.range(x, k.sigma * k.sigma, |i, d2| {
            let c = &self.cones[i as usize];
            scanned += 1;
            let on_surface = match surface {
                None => true,
                Some((shape, n)) => c.shape == shape && c.ng.dot(n) > 0.0,
            };
            if k.in_disc(d2) && set.admits(c) && on_surface {
                let a = aperture.weight(k, c.dir);
                if a > 0.0 {
                    inside += 1;
                    sum += c.value * a;
                }
            }
        });
        stats.lookups += 1;
        stats.scanned += scanned;
        stats.inside += inside;
        if self.light_paths == 0 {
            return Spectrum::ZERO;
        }
        sum * (k.scale(&aperture) / self.light_paths as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cone(p: Vec3, shape: u32, ng: Vec3) -> PhotonCone {
        PhotonCone {
            p,
            dir: Vec3::Y,
            value: Spectrum::ONE,
            length: 1,
            delta_light: false,
            shape,
            ng,
        }
    }

    #[test]
    fn surface_filter_keeps_the_query_surface_only() {
        // A plate (shape 0, normal +y) with a parallel sheet 1 cm below (shape 1) and the
        // plate's underside (shape 0, normal −y): "any" gathers all three, "same" the plate.
        let mut cones = Vec::new();
        for i in 0..10 {
            let x = i as f32 * 0.001;
            cones.push(cone(Vec3::new(x, 0.0, 0.0), 0, Vec3::Y));
            cones.push(cone(Vec3::new(x, -0.01, 0.0), 1, Vec3::Y));
            cones.push(cone(Vec3::new(x, -0.005, 0.0), 0, -Vec3::Y));
        }
        let map = PhotonConeMap::build(cones, 1);
        let k = DiskCapKernel::new(0.1, 0.3);
        let at = |map: &PhotonConeMap, surface| {
            let mut st = LookupStats::default();
            map.estimate(
                Vec3::ZERO,
                Aperture::Cap(Vec3::Y),
                &k,
                ConeSet::All,
                surface,
                &mut st,
            )
        };
        let any = at(&map, None);
        let same = at(&map, Some((0, Vec3::Y)));
        assert!((any.c[0] / k.inv_volume - 30.0).abs() < 1e-3);
        assert!((same.c[0] / k.inv_volume - 10.0).abs() < 1e-3);
        // Normalised by light paths: twice the paths, half the estimate.
        let map2 = PhotonConeMap::build(map.cones().to_vec(), 2);
        let half = at(&map2, None);
        assert!((half.c[0] * 2.0 - any.c[0]).abs() < 1e-3 * any.c[0]);
    }
}
