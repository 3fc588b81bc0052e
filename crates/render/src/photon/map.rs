//! A photon map: photons in a kd-tree, and the radiance estimate of seed 000 eq. 3.2.

use crate::photon::tracer::Photon;
use crate::transport::vertex::Vertex;
use caustica_core::{Spectrum, Vec3};
use caustica_density::estimate::{disc_test, project_to_tangent_plane};
use caustica_density::estimator::{Estimator, PointSet, Query, Scratch};
use caustica_density::kdtree::KdTree;
use caustica_density::kernel::Kernel;
use caustica_scene::bsdf::TransportMode;

/// Settings of the radiance estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EstimateOptions {
    /// Photons per estimate (k nearest), ≥ 1.
    pub k: usize,
    /// Largest gather radius (m); `None` = unbounded.
    pub max_radius: Option<f32>,
    pub kernel: Kernel,
    /// Project photons along their incoming direction onto the tangent plane at the estimation
    /// point before measuring their distance (seed 000 app. A, eq. A.1–A.2).
    pub tangent_projection: bool,
    /// Reject photons whose surface normal differs from the query's (cos < 0.9) or that lie
    /// farther than 10 % of the gather radius from its tangent plane (topological and occlusion
    /// bias near corners and thin objects).
    pub disc_test: bool,
}

impl Default for EstimateOptions {
    fn default() -> Self {
        Self {
            k: 50,
            max_radius: None,
            kernel: Kernel::Epanechnikov,
            tangent_projection: false,
            disc_test: false,
        }
    }
}

/// Photons with a kd-tree over their positions.
pub struct PhotonMap {
    pub photons: Vec<Photon>,
    tree: KdTree,
    /// Number of light paths whose photons the map holds (the N of Φ = β/N).
    pub paths: u64,
}

impl PhotonMap {
    pub fn new(mut photons: Vec<Photon>, paths: u64) -> Self {
        photons.shrink_to_fit();
        let positions: Vec<Vec3> = photons.iter().map(|p| p.p).collect();
        Self {
            tree: KdTree::build(&positions),
            photons,
            paths,
        }
    }

    pub fn len(&self) -> usize {
        self.photons.len()
    }

    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }

    /// Bytes held by the photons and the tree.
    pub fn memory_bytes(&self) -> usize {
        self.photons.capacity() * std::mem::size_of::<Photon>() + self.tree.memory_bytes()
    }

    /// The photons as a point set for density estimators, filtered and projected as `opts`
    /// says (side test always; disc test and tangent projection when asked).
    pub fn points<'a>(&'a self, opts: &'a EstimateOptions) -> PhotonPoints<'a> {
        PhotonPoints { map: self, opts }
    }

    /// The k-NN estimator (eq. 3.2) that `opts` describes.
    pub fn knn_estimator(opts: &EstimateOptions) -> Estimator {
        Estimator::Knn {
            k: opts.k,
            max_radius: opts.max_radius,
            kernel: opts.kernel,
        }
    }

    /// Reflected radiance (W/m²/sr) at vertex `v` toward its `wo`, eq. 3.2 of seed 000:
    /// L̂(x, ω) = Σ_i K(d_i²/h²)/h² · f_r(x, ω_i, ω) Φ_i with the kernel normalised in 2-D
    /// (`Kernel::eval(·, Dim::Two)` = K_Table5.1/π), h the distance to the k-th nearest photon
    /// (or the maximum radius when fewer are found within it). Only photons that arrived on the
    /// side of the surface the query looks from count. `scratch` is reusable scratch space.
    pub fn estimate(&self, v: &Vertex, opts: &EstimateOptions, scratch: &mut Scratch) -> Spectrum {
        self.estimate_with(v, opts, &Self::knn_estimator(opts), scratch)
    }

    /// Reflected radiance (W/m²/sr) at vertex `v` toward its `wo` with any density estimator
    /// `est` prepared for this map ([`Estimator::prepare`] on [`PhotonMap::points`]):
    /// L̂(x, ω) = Σ_i w_i f_r(x, ω_i, ω) Φ_i, the w_i (1/m²) the estimator's weights (eq. 3.2
    /// for k-NN, eq. 4.19 for the diffusion estimate).
    pub fn estimate_with(
        &self,
        v: &Vertex,
        opts: &EstimateOptions,
        est: &Estimator,
        scratch: &mut Scratch,
    ) -> Spectrum {
        if self.photons.is_empty() {
            return Spectrum::ZERO;
        }
        let q = Query::new(v.si.p, v.facing_normal());
        let mut sum = Spectrum::ZERO;
        est.weights(&self.points(opts), &q, scratch, |i, w| {
            let ph = &self.photons[i as usize];
            let f = v
                .bsdf
                .eval(v.wo, v.frame.to_local(ph.wi), TransportMode::Radiance);
            sum += f * ph.flux * w;
        });
        sum
    }
}

/// A photon map seen by a density estimator ([`PointSet`]): masses are flux luminances (W);
/// photons that arrived from the other side of the query's surface never count; with
/// [`EstimateOptions::disc_test`] photons off the tangent plane (farther than 0.1 h) or with a
/// normal more than ~25° off are rejected; with [`EstimateOptions::tangent_projection`] a
/// photon's offset is measured after moving it along its incoming line into the tangent plane
/// (eq. A.1–A.2).
pub struct PhotonPoints<'a> {
    map: &'a PhotonMap,
    opts: &'a EstimateOptions,
}

impl PointSet for PhotonPoints<'_> {
    fn tree(&self) -> &KdTree {
        &self.map.tree
    }
    fn len(&self) -> usize {
        self.map.photons.len()
    }
    fn position(&self, i: u32) -> Vec3 {
        self.map.photons[i as usize].p
    }
    fn normal(&self, i: u32) -> Vec3 {
        self.map.photons[i as usize].n
    }
    fn mass(&self, i: u32) -> f32 {
        self.map.photons[i as usize].flux.luminance()
    }
    fn offset(&self, q: &Query, i: u32, h: f32) -> Option<Vec3> {
        let ph = &self.map.photons[i as usize];
        // Surface photons never count for a volume query (which has no normal).
        let n = q.n()?;
        // Photons from the other side of the surface do not light this side.
        if ph.wi.dot(n) <= 0.0 {
            return None;
        }
        if self.opts.disc_test && !disc_test(q.p, n, ph.p, ph.n, 0.1 * h, 0.9) {
            return None;
        }
        if self.opts.tangent_projection {
            // Eq. A.1–A.2: move the photon along its incoming line into the tangent plane.
            project_to_tangent_plane(q.p, n, ph.p, ph.wi).map(|x| x - q.p)
        } else {
            Some(ph.p - q.p)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Surface photons are not in-scattering events: a volume query over a surface photon map
    /// gets no weight, whatever the filters, while the surface query there sees the photons.
    #[test]
    fn surface_photons_do_not_count_for_volume_queries() {
        let photons: Vec<Photon> = (0..100)
            .map(|i| Photon {
                p: Vec3::new((i % 10) as f32 * 0.01, (i / 10) as f32 * 0.01, 0.0),
                wi: Vec3::Z,
                n: Vec3::Z,
                flux: Spectrum::ONE,
                depth: 1,
                caustic: true,
            })
            .collect();
        let map = PhotonMap::new(photons, 1);
        let mut scratch = Scratch::default();
        for (disc, proj) in [(false, false), (true, true)] {
            let opts = EstimateOptions {
                k: 10,
                disc_test: disc,
                tangent_projection: proj,
                ..EstimateOptions::default()
            };
            let est = PhotonMap::knn_estimator(&opts);
            let points = map.points(&opts);
            let p = Vec3::new(0.045, 0.045, 0.0);
            assert!(est.density(&points, &Query::new(p, Vec3::Z), &mut scratch) > 0.0);
            let mut visited = 0;
            est.weights(&points, &Query::volume(p), &mut scratch, |_, _| {
                visited += 1
            });
            assert_eq!(visited, 0);
        }
    }
}
