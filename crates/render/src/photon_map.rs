//! A photon map: photons in a kd-tree, and the radiance estimate of seed 000 eq. 3.2.

use crate::photon_tracer::Photon;
use crate::surface::Vertex;
use caustica_core::{Spectrum, Vec3};
use caustica_density::estimate::{disc_test, project_to_tangent_plane};
use caustica_density::kdtree::{KdTree, Neighbor};
use caustica_density::kernel::{Dim, Kernel};
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

    /// Reflected radiance (W/m²/sr) at vertex `v` toward its `wo`, eq. 3.2 of seed 000:
    /// L̂(x, ω) = Σ_i K(d_i²/h²)/h² · f_r(x, ω_i, ω) Φ_i with the kernel normalised in 2-D
    /// (`Kernel::eval(·, Dim::Two)` = K_Table5.1/π), h the distance to the k-th nearest photon
    /// (or the maximum radius when fewer are found within it). Only photons that arrived on the
    /// side of the surface the query looks from count. `buf` is scratch space.
    pub fn estimate(
        &self,
        v: &Vertex,
        opts: &EstimateOptions,
        buf: &mut Vec<Neighbor>,
    ) -> Spectrum {
        if self.photons.is_empty() {
            return Spectrum::ZERO;
        }
        let x = v.si.p;
        let max_r2 = opts.max_radius.map_or(f32::INFINITY, |r| r * r);
        // Heap order: buf[0] is the farthest of the k, which sets the bandwidth.
        self.tree.knn_unsorted(x, opts.k, max_r2, buf);
        let Some(farthest) = buf.first() else {
            return Spectrum::ZERO;
        };
        let h2 = if buf.len() < opts.k && max_r2.is_finite() {
            max_r2
        } else {
            farthest.dist2
        };
        if h2 <= 0.0 {
            return Spectrum::ZERO;
        }
        let wo_world = v.frame.to_world(v.wo);
        let ng = v.si.ng;
        let side = ng.dot(wo_world);
        let n_query = if side >= 0.0 { ng } else { -ng };
        let h = h2.sqrt();
        let mut sum = Spectrum::ZERO;
        for nb in buf.iter() {
            let ph = &self.photons[nb.index as usize];
            // Photons from the other side of the surface do not light this side.
            if ph.wi.dot(ng) * side <= 0.0 {
                continue;
            }
            if opts.disc_test && !disc_test(x, n_query, ph.p, ph.n, 0.1 * h, 0.9) {
                continue;
            }
            let d2 = if opts.tangent_projection {
                // Eq. A.1–A.2: move the photon along its incoming line into the tangent plane.
                match project_to_tangent_plane(x, n_query, ph.p, ph.wi) {
                    Some(q) => (q - x).length_squared(),
                    None => continue,
                }
            } else {
                nb.dist2
            };
            let w = opts.kernel.eval(d2 / h2, Dim::Two);
            if w <= 0.0 {
                continue;
            }
            let f = v
                .bsdf
                .eval(v.wo, v.frame.to_local(ph.wi), TransportMode::Radiance);
            sum += f * ph.flux * w;
        }
        sum / h2
    }
}
