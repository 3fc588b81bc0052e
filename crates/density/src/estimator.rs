//! One interface for every density estimator, used alike by the 2-D testbed, by the photon
//! maps of 3-D scenes and (with volume queries) by volume photons in participating media.
//!
//! An estimator turns a [`Query`] into **weights**: it calls `visit(i, wᵢ)` for every point `i`
//! of a [`PointSet`] that contributes, with `wᵢ` in 1/m^d, so that `Σᵢ wᵢ mᵢ` estimates the
//! density of the masses `mᵢ` per m^d. The query's [`Domain`] sets `d`:
//!
//! * **Surface** (`d = 2`, [`Query::new`]: a point with a tangent frame): with photon fluxes Φᵢ
//!   (W) as masses the estimate is irradiance (W/m²); with BRDF values (sr⁻¹) in the sum it is
//!   the radiance estimate eq. 3.2 (W/m²/sr); with masses `1/n` a probability density (1/m²).
//! * **Volume** (`d = 3`, [`Query::volume`]: a point in a medium, no normal): with fluxes the
//!   estimate is W/m³; with phase-function values (sr⁻¹) in the sum it is the in-scattered
//!   radiance of seed 000 eq. 8.3 (W/m³/sr, to be multiplied by σ_s (1/m) along a ray); with
//!   masses `1/n` a probability density (1/m³).
//!
//! The estimators (Schjøth 2009, ch. 2 and 4), `h^d` the bandwidth to the query's dimension:
//!
//! | [`EstimatorSpec`] | weight of point i | equation | domains |
//! |---|---|---|---|
//! | `Fixed { h }` | `K_d(dᵢ²/h²) / h^d` | 2.15 | surface, volume |
//! | `Knn { k }` | `K_d(dᵢ²/h(x)²) / h(x)^d`, `h(x)` the distance to the k-th nearest point | 2.12, 3.2, 8.3 | surface, volume |
//! | `Variable { k }` | `K_d(dᵢ²/hᵢ²) / hᵢ^d`, `hᵢ` the k-NN distance at xᵢ (the pilot) | 2.13, fig. 2.5b | surface, volume |
//! | `Diffusion(..)` | `K₂(dᵢᵀD⁻¹dᵢ/h²) / (h² √det D)`, D from the structure tensor | 4.19, see [`crate::diffusion`] | surface only |
//!
//! `K_d` is the kernel normalised over the d-dimensional unit ball ([`Kernel::eval`] with
//! [`Query::dim`]) and `dᵢ` the point's offset from the query as the point set defines it
//! ([`PointSet::offset`]: plain difference, or a tangent-plane projection, eq. A.1–A.2). A
//! point set can also veto a point (photons from the other side of a surface, the disc test,
//! surface photons seen from a volume query). With the uniform kernel `K_d = 1/V_d` the k-NN
//! estimate is the classic `k / V_d(h)`: `k/(π r²)` on a surface, `k/(4/3 π r³)` in a volume
//! ([`Dim::ball_volume`]).
//!
//! The diffusion estimator smooths along structures of the density *in a tangent plane*
//! (its structure tensor is 2×2, its gradients tangent vectors); a volume query is a
//! [`DensityError::SurfaceOnly`] from [`Estimator::try_weights`] (and a panic from
//! [`Estimator::weights`]). Check [`Estimator::supports`] / [`EstimatorSpec::supports`] when
//! configuring a volume photon map. The surface path of every estimator computes exactly the
//! floating-point operations it did before queries had a dimension (`tests/surface_identity.rs`).
//!
//! Estimators that need per-point data (the pilot bandwidths, the photon-map gradients) are
//! prepared once per point set by [`Estimator::prepare`]; the others are ready at once. The
//! preparation is deterministic: it does not depend on the number of threads.

use crate::DensityError;
use crate::diffusion::{DiffusionEstimator, DiffusionParams};
use crate::kdtree::{KdTree, Neighbor};
use crate::kernel::{Dim, Kernel};
use crate::radius_buckets::RadiusBuckets;
use caustica_core::{Frame, Vec2, Vec3};
use rayon::prelude::*;

/// What a query's density is a density over, and so its dimension.
#[derive(Clone, Copy, Debug)]
pub enum Domain {
    /// A surface, `d = 2`: densities per m², kernels normalised over the unit disc. The tangent
    /// frame's `s`, `t` span the tangent plane (where the disc test, the tangent-plane
    /// projection eq. A.1–A.2 and the diffusion estimator work) and its normal `frame.n` (unit)
    /// points to the side the density is wanted for.
    Surface {
        /// Tangent frame at the query point.
        frame: Frame,
    },
    /// A volume (participating media, seed 000 ch. 8), `d = 3`: densities per m³, kernels
    /// normalised over the unit ball, distances measured in 3-D; no normal, no side.
    Volume,
}

impl Domain {
    /// The dimension of the densities estimated over this domain.
    #[inline]
    pub fn dim(&self) -> Dim {
        match self {
            Domain::Surface { .. } => Dim::Two,
            Domain::Volume => Dim::Three,
        }
    }
}

/// Where a density is estimated: a point and its [`Domain`] (a surface with its tangent frame,
/// or a volume).
#[derive(Clone, Copy, Debug)]
pub struct Query {
    /// Position (m).
    pub p: Vec3,
    /// Surface (with tangent frame) or volume.
    pub domain: Domain,
}

/// Coordinates (m) of a world-space offset `d` in the tangent plane of `frame`.
#[inline]
pub(crate) fn tangent_coords(frame: &Frame, d: Vec3) -> Vec2 {
    Vec2::new(d.dot(frame.s), d.dot(frame.t))
}

impl Query {
    /// A surface query at `p` with unit normal `n` (the tangent axes are chosen from `n` alone):
    /// densities per m².
    pub fn new(p: Vec3, n: Vec3) -> Self {
        Self::with_frame(p, Frame::from_normal(n))
    }

    /// A surface query at `p` with the tangent frame `frame` (`frame.n` the unit normal of the
    /// query's side): densities per m².
    pub fn with_frame(p: Vec3, frame: Frame) -> Self {
        Self {
            p,
            domain: Domain::Surface { frame },
        }
    }

    /// A volume query at `p` (a point in a participating medium): densities per m³.
    pub fn volume(p: Vec3) -> Self {
        Self {
            p,
            domain: Domain::Volume,
        }
    }

    /// The dimension of the estimate: [`Dim::Two`] on a surface, [`Dim::Three`] in a volume.
    #[inline]
    pub fn dim(&self) -> Dim {
        self.domain.dim()
    }

    /// True for a surface query.
    #[inline]
    pub fn is_surface(&self) -> bool {
        matches!(self.domain, Domain::Surface { .. })
    }

    /// The tangent frame of a surface query; `None` for a volume query.
    #[inline]
    pub fn frame(&self) -> Option<&Frame> {
        match &self.domain {
            Domain::Surface { frame } => Some(frame),
            Domain::Volume => None,
        }
    }

    /// Unit normal of a surface query's side; `None` for a volume query (which has no side:
    /// a point set of surface points should contribute nothing to it).
    #[inline]
    pub fn n(&self) -> Option<Vec3> {
        self.frame().map(|f| f.n)
    }

    /// Coordinates (m) of a world-space offset `d` in a surface query's tangent plane; `None`
    /// for a volume query.
    #[inline]
    pub fn tangent(&self, d: Vec3) -> Option<Vec2> {
        self.frame().map(|f| tangent_coords(f, d))
    }
}

/// Points with masses in a k-d tree: what an estimator draws on.
pub trait PointSet: Sync {
    /// The tree over the points' positions (indices as in the other methods).
    fn tree(&self) -> &KdTree;
    /// Number of points (indices are `0..len`).
    fn len(&self) -> usize;
    /// True when the set holds no point.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Position of point `i` (m).
    fn position(&self, i: u32) -> Vec3;
    /// Unit surface normal at point `i`, on the side its mass arrived from; `Vec3::ZERO` for a
    /// point that lies on no surface (a volume sample).
    fn normal(&self, i: u32) -> Vec3;
    /// Scalar mass of point `i`, for estimators that look at the structure of the density (the
    /// photon-map gradient of the diffusion estimator): a photon's flux luminance (W), or `1/n`.
    fn mass(&self, i: u32) -> f32;
    /// Offset (m, world space) of point `i` from the query point at which to evaluate its kernel,
    /// or `None` when the point must not contribute to this query. `h` is the estimate's
    /// bandwidth (m) for this point. The plain choice is `position(i) − q.p`.
    ///
    /// Surface-only filters (the side test, the disc test, the tangent-plane projection) need
    /// the query's normal, [`Query::n`]; a volume query has none. A set of surface points (a
    /// surface photon map) should return `None` for a volume query — surface photons are not
    /// in-scattering events — and a set of volume points the plain difference.
    fn offset(&self, q: &Query, i: u32, h: f32) -> Option<Vec3>;
}

/// Points with unit masses or given masses and no filtering (the plain offset, for surface and
/// volume queries alike): the testbed's samples, and a reference implementation of
/// [`PointSet`].
pub struct WeightedPoints {
    tree: KdTree,
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    masses: Vec<f32>,
}

impl WeightedPoints {
    /// Points at `positions` with `normals` and `masses` (all of the same length).
    ///
    /// # Panics
    /// If the lengths differ (a programming error, not user input).
    pub fn new(positions: Vec<Vec3>, normals: Vec<Vec3>, masses: Vec<f32>) -> Self {
        assert_eq!(positions.len(), normals.len());
        assert_eq!(positions.len(), masses.len());
        Self {
            tree: KdTree::build(&positions),
            positions,
            normals,
            masses,
        }
    }

    /// Points in the plane z = 0 (normal +z), each of mass `1/n`: a probability density.
    pub fn planar(points: &[[f64; 2]]) -> Self {
        let n = points.len().max(1) as f32;
        let positions: Vec<Vec3> = points
            .iter()
            .map(|p| Vec3::new(p[0] as f32, p[1] as f32, 0.0))
            .collect();
        let len = positions.len();
        Self::new(positions, vec![Vec3::Z; len], vec![1.0 / n; len])
    }

    /// Points in space (volume samples: normals `Vec3::ZERO`) with masses `masses`.
    ///
    /// # Panics
    /// If the lengths differ.
    pub fn volume(positions: Vec<Vec3>, masses: Vec<f32>) -> Self {
        let len = positions.len();
        Self::new(positions, vec![Vec3::ZERO; len], masses)
    }
}

impl PointSet for WeightedPoints {
    fn tree(&self) -> &KdTree {
        &self.tree
    }
    fn len(&self) -> usize {
        self.positions.len()
    }
    fn position(&self, i: u32) -> Vec3 {
        self.positions[i as usize]
    }
    fn normal(&self, i: u32) -> Vec3 {
        self.normals[i as usize]
    }
    fn mass(&self, i: u32) -> f32 {
        self.masses[i as usize]
    }
    fn offset(&self, q: &Query, i: u32, _h: f32) -> Option<Vec3> {
        Some(self.positions[i as usize] - q.p)
    }
}

/// Reusable buffers of one thread's queries.
#[derive(Default)]
pub struct Scratch {
    pub(crate) neighbors: Vec<Neighbor>,
    /// (index, tangent-plane offset) of the points within the bandwidth.
    pub(crate) offsets: Vec<(u32, Vec2)>,
}

/// What estimator to use and its parameters (before any per-point preparation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EstimatorSpec {
    /// Fixed bandwidth `h` (m), eq. 2.15.
    Fixed { h: f32, kernel: Kernel },
    /// k-th nearest neighbour, eq. 2.12 / 3.2; the bandwidth is capped at `max_radius` (m).
    Knn {
        k: usize,
        max_radius: Option<f32>,
        kernel: Kernel,
    },
    /// Variable bandwidth with a k-NN pilot, eq. 2.13: each point's bandwidth is its distance to
    /// its k-th nearest other point (fig. 2.5b), capped at `max_radius` (m).
    Variable {
        k: usize,
        max_radius: Option<f32>,
        kernel: Kernel,
    },
    /// Diffusion-based estimate, eq. 4.19 (anisotropic, or isotropic with
    /// [`DiffusionParams::isotropic`]).
    Diffusion(DiffusionParams),
}

impl EstimatorSpec {
    /// Checks the parameters; the message names the offending one.
    pub fn validate(&self) -> Result<(), String> {
        let positive = |name: &str, v: f32| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!("{name} must be a positive finite number, got {v}"))
            }
        };
        match self {
            EstimatorSpec::Fixed { h, .. } => positive("the bandwidth h", *h),
            EstimatorSpec::Knn { k, max_radius, .. }
            | EstimatorSpec::Variable { k, max_radius, .. } => {
                if *k == 0 {
                    return Err("k (points per estimate) must be at least 1".into());
                }
                max_radius.map_or(Ok(()), |r| positive("the maximum radius", r))
            }
            EstimatorSpec::Diffusion(p) => p.validate(),
        }
    }

    /// Whether the estimator answers queries of dimension `dim`: every estimator on surfaces
    /// ([`Dim::Two`]); all but the diffusion estimator in volumes ([`Dim::Three`]); none on a
    /// line ([`Dim::One`], no query domain has it).
    pub fn supports(&self, dim: Dim) -> bool {
        match dim {
            Dim::Two => true,
            Dim::Three => !matches!(self, EstimatorSpec::Diffusion(_)),
            Dim::One => false,
        }
    }

    /// Short name for reports: `fixed`, `knn`, `variable`, `diffusion`, `isotropic-diffusion`.
    pub fn name(&self) -> &'static str {
        match self {
            EstimatorSpec::Fixed { .. } => "fixed",
            EstimatorSpec::Knn { .. } => "knn",
            EstimatorSpec::Variable { .. } => "variable",
            EstimatorSpec::Diffusion(p) if p.isotropic => "isotropic-diffusion",
            EstimatorSpec::Diffusion(_) => "diffusion",
        }
    }
}

/// A density estimator prepared for one point set (see the [module docs](self)).
#[derive(Clone, Debug)]
pub enum Estimator {
    Fixed {
        h: f32,
        kernel: Kernel,
    },
    Knn {
        k: usize,
        max_radius: Option<f32>,
        kernel: Kernel,
    },
    Variable(VariableBandwidth),
    Diffusion(DiffusionEstimator),
}

impl Estimator {
    /// Prepares `spec` for `points` (per-point pilot bandwidths or gradients, if it needs them).
    /// `spec` must be valid ([`EstimatorSpec::validate`]).
    pub fn prepare<P: PointSet>(spec: &EstimatorSpec, points: &P) -> Self {
        match *spec {
            EstimatorSpec::Fixed { h, kernel } => Estimator::Fixed { h, kernel },
            EstimatorSpec::Knn {
                k,
                max_radius,
                kernel,
            } => Estimator::Knn {
                k,
                max_radius,
                kernel,
            },
            EstimatorSpec::Variable {
                k,
                max_radius,
                kernel,
            } => Estimator::Variable(VariableBandwidth::new(points, k, max_radius, kernel)),
            EstimatorSpec::Diffusion(params) => {
                Estimator::Diffusion(DiffusionEstimator::new(points, params))
            }
        }
    }

    /// Whether the estimator answers queries of dimension `dim` (see
    /// [`EstimatorSpec::supports`]: the diffusion estimator is surface-only).
    pub fn supports(&self, dim: Dim) -> bool {
        match dim {
            Dim::Two => true,
            Dim::Three => !matches!(self, Estimator::Diffusion(_)),
            Dim::One => false,
        }
    }

    /// Calls `visit(i, wᵢ)` (wᵢ in 1/m^d, `d` = [`Query::dim`]: 1/m² on a surface, 1/m³ in a
    /// volume) for the points contributing to the estimate at `q`; the density estimate of
    /// masses mᵢ is `Σ wᵢ mᵢ` (per m^d). Each point is visited at most once.
    ///
    /// # Panics
    /// If the estimator does not support the query's domain (the diffusion estimator with a
    /// volume query: a configuration error, see [`Estimator::supports`]); use
    /// [`Estimator::try_weights`] to get it as [`DensityError::SurfaceOnly`].
    pub fn weights<P: PointSet>(
        &self,
        points: &P,
        q: &Query,
        scratch: &mut Scratch,
        visit: impl FnMut(u32, f32),
    ) {
        if let Err(e) = self.try_weights(points, q, scratch, visit) {
            panic!("{e}");
        }
    }

    /// [`Estimator::weights`], with [`DensityError::SurfaceOnly`] (and no point visited) when
    /// the estimator does not support the query's domain.
    pub fn try_weights<P: PointSet>(
        &self,
        points: &P,
        q: &Query,
        scratch: &mut Scratch,
        mut visit: impl FnMut(u32, f32),
    ) -> Result<(), DensityError> {
        if let (Estimator::Diffusion(_), Domain::Volume) = (self, &q.domain) {
            return Err(DensityError::SurfaceOnly("diffusion"));
        }
        if points.is_empty() || !q.p.is_finite() {
            return Ok(());
        }
        let dim = q.dim();
        match self {
            Estimator::Fixed { h, kernel } => {
                // Eq. 2.15 with H = h² I; divisor h^d (h² on a surface: the very same h2).
                let h2 = h * h;
                let hd = dim.bandwidth_volume_from(*h, h2);
                points.tree().range(q.p, h2, |i, _| {
                    if let Some(d) = points.offset(q, i, *h) {
                        let w = kernel.eval(d.length_squared() / h2, dim) / hd;
                        if w > 0.0 {
                            visit(i, w);
                        }
                    }
                });
            }
            Estimator::Knn {
                k,
                max_radius,
                kernel,
            } => knn_weights(points, q, *k, *max_radius, *kernel, scratch, visit),
            Estimator::Variable(v) => v.weights(points, q, visit),
            Estimator::Diffusion(d) => d.weights(points, q, scratch, visit)?,
        }
        Ok(())
    }

    /// Bytes of per-point data the preparation added.
    pub fn memory_bytes(&self) -> usize {
        match self {
            Estimator::Fixed { .. } | Estimator::Knn { .. } => 0,
            Estimator::Variable(v) => v.memory_bytes(),
            Estimator::Diffusion(d) => d.memory_bytes(),
        }
    }

    /// The density estimate of the points' own masses at `q` (`Σ wᵢ mᵢ`, per m² on a surface,
    /// per m³ in a volume).
    ///
    /// # Panics
    /// As [`Estimator::weights`]; [`Estimator::try_density`] returns the error instead.
    pub fn density<P: PointSet>(&self, points: &P, q: &Query, scratch: &mut Scratch) -> f32 {
        let mut sum = 0.0f32;
        self.weights(points, q, scratch, |i, w| sum += w * points.mass(i));
        sum
    }

    /// [`Estimator::density`], with [`DensityError::SurfaceOnly`] for an unsupported domain.
    pub fn try_density<P: PointSet>(
        &self,
        points: &P,
        q: &Query,
        scratch: &mut Scratch,
    ) -> Result<f32, DensityError> {
        let mut sum = 0.0f32;
        self.try_weights(points, q, scratch, |i, w| sum += w * points.mass(i))?;
        Ok(sum)
    }
}

/// Eq. 2.12 / 3.2 (surface) and 8.3 (volume): the bandwidth is the distance to the k-th nearest
/// point (or the maximum radius when fewer lie within it), the weight `K_d(dᵢ²/h²)/h^d`; with
/// the uniform kernel the estimate is `k / V_d(h)`, `V_d(h)` = `πh²` or `4/3 πh³`.
fn knn_weights<P: PointSet>(
    points: &P,
    q: &Query,
    k: usize,
    max_radius: Option<f32>,
    kernel: Kernel,
    scratch: &mut Scratch,
    mut visit: impl FnMut(u32, f32),
) {
    let max_r2 = max_radius.map_or(f32::INFINITY, |r| r * r);
    let buf = &mut scratch.neighbors;
    // Heap order: buf[0] is the farthest of the k, which sets the bandwidth.
    points.tree().knn_unsorted(q.p, k, max_r2, buf);
    let Some(farthest) = buf.first() else {
        return;
    };
    let h2 = if buf.len() < k && max_r2.is_finite() {
        max_r2
    } else {
        farthest.dist2
    };
    if h2 <= 0.0 || !h2.is_finite() {
        return;
    }
    let h = h2.sqrt();
    let dim = q.dim();
    // h^d: on a surface the k-th squared distance itself, as eq. 3.2 always divided by.
    let hd = dim.bandwidth_volume_from(h, h2);
    for nb in buf.iter() {
        let Some(d) = points.offset(q, nb.index, h) else {
            continue;
        };
        let w = kernel.eval(d.length_squared() / h2, dim) / hd;
        if w > 0.0 {
            visit(nb.index, w);
        }
    }
}

/// Eq. 2.13 with the k-NN pilot of fig. 2.5b: point i spreads its mass with its own bandwidth
/// hᵢ, the distance from xᵢ to its k-th nearest other point (in 3-D, whatever the query: the
/// pilot is a property of the points), with weight `K_d(dᵢ²/hᵢ²)/hᵢ^d` for a query of
/// dimension `d`. A query finds the points whose
/// ball of radius hᵢ contains it through [`RadiusBuckets`] (pilot bandwidths span orders of
/// magnitude, so one range query at max hᵢ would visit the whole map).
#[derive(Clone, Debug)]
pub struct VariableBandwidth {
    /// Per-point bandwidth hᵢ (m); 0 for points that cannot contribute.
    h: Vec<f32>,
    buckets: RadiusBuckets,
    kernel: Kernel,
}

impl VariableBandwidth {
    fn new<P: PointSet>(points: &P, k: usize, max_radius: Option<f32>, kernel: Kernel) -> Self {
        let cap = max_radius.unwrap_or(f32::INFINITY);
        let h: Vec<f32> = (0..points.len() as u32)
            .into_par_iter()
            .map_init(Vec::new, |buf, i| {
                // k + 1: the point itself is its own nearest neighbour.
                points
                    .tree()
                    .knn_unsorted(points.position(i), k + 1, f32::INFINITY, buf);
                let h = buf.first().map_or(0.0, |f| f.dist2.sqrt().min(cap));
                if h.is_finite() && h > 0.0 { h } else { 0.0 }
            })
            .collect();
        let positions: Vec<Vec3> = (0..points.len() as u32)
            .map(|i| points.position(i))
            .collect();
        let buckets = RadiusBuckets::build(&positions, &h);
        Self { h, buckets, kernel }
    }

    /// The pilot bandwidth of point `i` (m).
    pub fn bandwidth(&self, i: u32) -> f32 {
        self.h[i as usize]
    }

    /// Bytes of per-point data (bandwidths, octave trees and their index maps).
    fn memory_bytes(&self) -> usize {
        self.h.capacity() * 4 + self.buckets.memory_bytes()
    }

    fn weights<P: PointSet>(&self, points: &P, q: &Query, mut visit: impl FnMut(u32, f32)) {
        let dim = q.dim();
        self.buckets.for_each_candidate(q.p, |i| {
            let hi = self.h[i as usize];
            if let Some(d) = points.offset(q, i, hi) {
                let h2 = hi * hi;
                let hd = dim.bandwidth_volume_from(hi, h2);
                let w = self.kernel.eval(d.length_squared() / h2, dim) / hd;
                if w > 0.0 {
                    visit(i, w);
                }
            }
        });
    }
}

/// A data-driven bandwidth (m): the median, over up to 1024 evenly spaced points, of the
/// distance from a point to its k-th nearest other point; `None` for an empty set. Used as the
/// default fixed bandwidth of the diffusion estimate (a fixed-bandwidth estimate that smooths
/// about as much as a k-NN estimate does in typical regions).
pub fn median_knn_radius<P: PointSet>(points: &P, k: usize) -> Option<f32> {
    let n = points.len();
    if n == 0 {
        return None;
    }
    let samples = n.min(1024);
    let mut buf = Vec::new();
    let mut radii: Vec<f32> = (0..samples)
        .filter_map(|j| {
            let i = (j * n / samples) as u32;
            points
                .tree()
                .knn_unsorted(points.position(i), k + 1, f32::INFINITY, &mut buf);
            buf.first()
                .map(|f| f.dist2.sqrt())
                .filter(|r| r.is_finite() && *r > 0.0)
        })
        .collect();
    if radii.is_empty() {
        return None;
    }
    let mid = radii.len() / 2;
    radii.select_nth_unstable_by(mid, f32::total_cmp);
    Some(radii[mid])
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::Pcg32;

    fn uniform_square(n: usize, seed: u64) -> WeightedPoints {
        let mut rng = Pcg32::new(seed, 1);
        let pts: Vec<[f64; 2]> = (0..n)
            .map(|_| [rng.next_f32() as f64, rng.next_f32() as f64])
            .collect();
        WeightedPoints::planar(&pts)
    }

    /// Every estimator recovers the uniform density 1 on the unit square in its middle, within
    /// a tolerance from the number of points it averages.
    #[test]
    fn estimators_recover_a_uniform_density() {
        let pts = uniform_square(40_000, 7);
        let kernel = Kernel::Epanechnikov;
        let specs = [
            EstimatorSpec::Fixed { h: 0.05, kernel },
            EstimatorSpec::Knn {
                k: 300,
                max_radius: None,
                kernel,
            },
            EstimatorSpec::Variable {
                k: 300,
                max_radius: None,
                kernel,
            },
            EstimatorSpec::Diffusion(DiffusionParams::new(0.05)),
        ];
        let mut scratch = Scratch::default();
        for spec in specs {
            let est = Estimator::prepare(&spec, &pts);
            // Average over a grid of interior queries: the mean is within ~1 %; each estimate
            // averages ≥ ~150 effective points, so single values are within ~35 % (4σ).
            let mut mean = 0.0;
            let m = 10;
            for a in 0..m {
                for b in 0..m {
                    let p = Vec3::new(
                        0.25 + 0.5 * a as f32 / m as f32,
                        0.25 + 0.5 * b as f32 / m as f32,
                        0.0,
                    );
                    let d = est.density(&pts, &Query::new(p, Vec3::Z), &mut scratch);
                    assert!((d - 1.0).abs() < 0.35, "{}: {d} at {p}", spec.name());
                    mean += d / (m * m) as f32;
                }
            }
            assert!((mean - 1.0).abs() < 0.03, "{}: mean {mean}", spec.name());
        }
    }

    /// The k-NN weights are exactly eq. 3.2's: K(d²/h²)/h² with h the k-th distance.
    #[test]
    fn knn_weights_match_the_definition() {
        let pts = uniform_square(1000, 3);
        let q = Query::new(Vec3::new(0.5, 0.5, 0.0), Vec3::Z);
        let est = Estimator::prepare(
            &EstimatorSpec::Knn {
                k: 20,
                max_radius: None,
                kernel: Kernel::Epanechnikov,
            },
            &pts,
        );
        let mut all: Vec<(f32, u32)> = (0..1000u32)
            .map(|i| ((pts.position(i) - q.p).length_squared(), i))
            .collect();
        all.sort_by(|a, b| a.0.total_cmp(&b.0));
        let h2 = all[19].0;
        let mut got = Vec::new();
        est.weights(&pts, &q, &mut Scratch::default(), |i, w| got.push((i, w)));
        got.sort_by_key(|g| g.0);
        let mut want: Vec<(u32, f32)> = all[..20]
            .iter()
            .map(|&(d2, i)| (i, Kernel::Epanechnikov.eval(d2 / h2, Dim::Two) / h2))
            .filter(|x| x.1 > 0.0)
            .collect();
        want.sort_by_key(|g| g.0);
        assert_eq!(got.len(), want.len());
        for (g, w) in got.iter().zip(&want) {
            assert_eq!(g.0, w.0);
            assert!((g.1 - w.1).abs() <= 1e-5 * w.1);
        }
    }

    /// The pilot bandwidth is the distance to the k-th nearest other point.
    #[test]
    fn variable_pilot_is_the_kth_neighbour_distance() {
        let pts = WeightedPoints::planar(&[[0.0, 0.0], [1.0, 0.0], [3.0, 0.0], [7.0, 0.0]]);
        let Estimator::Variable(v) = Estimator::prepare(
            &EstimatorSpec::Variable {
                k: 2,
                max_radius: None,
                kernel: Kernel::Uniform,
            },
            &pts,
        ) else {
            panic!("not a variable estimator");
        };
        assert_eq!(v.bandwidth(0), 3.0);
        assert_eq!(v.bandwidth(1), 2.0);
        assert_eq!(v.bandwidth(2), 3.0);
        assert_eq!(v.bandwidth(3), 6.0);
    }

    /// The octave search finds exactly the points a brute-force eq. 2.13 sums over, on points
    /// whose pilot bandwidths span orders of magnitude (a dense blob and sparse outliers).
    #[test]
    fn variable_weights_match_brute_force() {
        let mut rng = Pcg32::new(8, 8);
        let pts: Vec<[f64; 2]> = (0..3000)
            .map(|i| {
                let (a, b) = (rng.next_f32() as f64, rng.next_f32() as f64);
                if i % 20 == 0 {
                    [10.0 * a, 10.0 * b]
                } else {
                    [0.5 + 0.01 * a, 0.5 + 0.01 * b]
                }
            })
            .collect();
        let pts = WeightedPoints::planar(&pts);
        let spec = EstimatorSpec::Variable {
            k: 8,
            max_radius: None,
            kernel: Kernel::Epanechnikov,
        };
        let Estimator::Variable(v) = Estimator::prepare(&spec, &pts) else {
            panic!("not a variable estimator");
        };
        assert!(v.buckets.octaves() > 3, "{} octaves", v.buckets.octaves());
        let est = Estimator::Variable(v.clone());
        let mut scratch = Scratch::default();
        for j in 0..40 {
            let p = Vec3::new(0.25 * j as f32 % 10.0, 0.5 + 0.0003 * j as f32, 0.0);
            let q = Query::new(p, Vec3::Z);
            let got = est.density(&pts, &q, &mut scratch);
            let want: f32 = (0..pts.len() as u32)
                .map(|i| {
                    let h2 = v.bandwidth(i).powi(2);
                    let d2 = (pts.position(i) - p).length_squared();
                    Kernel::Epanechnikov.eval(d2 / h2, Dim::Two) / h2 * pts.mass(i)
                })
                .sum();
            assert!(
                (got - want).abs() <= 1e-4 * want.max(1e-6),
                "{got} vs {want} at {p}"
            );
        }
    }

    /// Points at dyadic positions (exact squared distances) around the origin of the plane
    /// z = 0: the k-NN and fixed-bandwidth weights of a surface query are, bit for bit, the
    /// closed forms `c₂ p(d²/h²) / h²` written out here (c₂ = 2/π for Epanechnikov, 4/π for
    /// the cubic kernel), in the order of operations eq. 3.2 has always used.
    #[test]
    fn surface_weights_match_the_closed_form_bit_for_bit() {
        let xy = [
            (0.125, 0.0),
            (0.0, 0.25),
            (-0.375, 0.0),
            (0.25, 0.25),
            (0.0, -0.5),
            (0.5, 0.5),
            (0.75, 0.0),
        ];
        let d2s: Vec<f32> = xy.iter().map(|&(x, y)| x * x + y * y).collect();
        let pts: Vec<[f64; 2]> = xy.iter().map(|&(x, y)| [x as f64, y as f64]).collect();
        let pts = WeightedPoints::planar(&pts);
        let q = Query::new(Vec3::ZERO, Vec3::Z);
        assert_eq!(q.dim(), Dim::Two);
        let pi = std::f64::consts::PI;
        let mut scratch = Scratch::default();
        // k = 5: the 5th smallest of 1/64, 1/16, 9/64, 1/8, 1/4, 1/2, 9/16 is h² = 1/4.
        let knn = Estimator::Knn {
            k: 5,
            max_radius: None,
            kernel: Kernel::Epanechnikov,
        };
        let c2 = (2.0 / pi) as f32;
        let h2 = 0.25f32;
        let mut seen = 0;
        knn.weights(&pts, &q, &mut scratch, |i, w| {
            let u2 = d2s[i as usize] / h2;
            let want = c2 * (1.0 - u2) / h2;
            assert_eq!(w.to_bits(), want.to_bits(), "point {i}: {w} vs {want}");
            seen += 1;
        });
        assert_eq!(seen, 4, "the 5th point is on the boundary (weight 0)");
        // Density of the masses 1/7 against eq. 3.2 in f64: 1/(πh²) Σ 2(1 − dᵢ²/h²) mᵢ.
        let want: f64 = d2s
            .iter()
            .filter(|&&d2| d2 < 0.25)
            .map(|&d2| 2.0 * (1.0 - 4.0 * f64::from(d2)) / (pi * 0.25) / 7.0)
            .sum();
        let got = f64::from(knn.density(&pts, &q, &mut scratch));
        assert!((got - want).abs() <= 1e-6 * want, "{got} vs {want}");
        // Fixed h = 0.6 with the cubic kernel: c₂ (1 − u²)³ / h², h² = 0.6·0.6 in f32.
        let fixed = Estimator::Fixed {
            h: 0.6,
            kernel: Kernel::Cubic,
        };
        let c2 = (4.0 / pi) as f32;
        let h2 = 0.6f32 * 0.6f32;
        seen = 0;
        fixed.weights(&pts, &q, &mut scratch, |i, w| {
            let a = 1.0 - d2s[i as usize] / h2;
            let want = c2 * (a * a * a) / h2;
            assert_eq!(w.to_bits(), want.to_bits(), "point {i}: {w} vs {want}");
            seen += 1;
        });
        assert_eq!(seen, 5, "d² < 0.36: all but 1/2 and 9/16");
    }

    /// The same in a volume: points at dyadic positions in 3-D, weights `c₃ p(d²/h²) / h³` with
    /// c₃ = 15/(8π) (Epanechnikov) and 3/(4π) (uniform), and the uniform k-NN density
    /// `k m / (4/3 π h³)` of eq. 8.3.
    #[test]
    fn volume_weights_match_the_closed_form() {
        let xyz = [
            Vec3::new(0.125, 0.0, 0.0),
            Vec3::new(0.0, 0.0, -0.25),
            Vec3::new(0.25, 0.25, 0.25),
            Vec3::new(0.0, 0.375, 0.0),
            Vec3::new(0.0, 0.0, 0.5),
            Vec3::new(0.5, 0.5, 0.0),
        ];
        let d2s: Vec<f32> = xyz.iter().map(|p| p.length_squared()).collect();
        let pts = WeightedPoints::volume(xyz.to_vec(), vec![0.5; xyz.len()]);
        let q = Query::volume(Vec3::ZERO);
        assert_eq!(q.dim(), Dim::Three);
        assert!(q.n().is_none() && q.frame().is_none() && q.tangent(Vec3::X).is_none());
        let pi = std::f64::consts::PI;
        let mut scratch = Scratch::default();
        // d² = 1/64, 1/16, 3/16, 9/64, 1/4, 1/2: the 5th nearest is at h = 0.5, h³ = 1/8.
        let knn = |kernel| Estimator::Knn {
            k: 5,
            max_radius: None,
            kernel,
        };
        let c3 = (15.0 / (8.0 * pi)) as f32;
        let mut seen = 0;
        knn(Kernel::Epanechnikov).weights(&pts, &q, &mut scratch, |i, w| {
            let u2 = d2s[i as usize] / 0.25;
            let want = c3 * (1.0 - u2) / 0.125;
            assert_eq!(w.to_bits(), want.to_bits(), "point {i}: {w} vs {want}");
            seen += 1;
        });
        assert_eq!(seen, 4);
        // Uniform: 4 points strictly inside (the 5th is on the boundary) of mass 1/2.
        let got = f64::from(knn(Kernel::Uniform).density(&pts, &q, &mut scratch));
        let want = 4.0 * 0.5 / (4.0 / 3.0 * pi * 0.125);
        assert!((got - want).abs() <= 1e-6 * want, "{got} vs {want}");
        // Fixed h = 0.4: h³ = 0.064; points within 0.4 (d² < 0.16): 1/64, 1/16, 9/64.
        let fixed = Estimator::Fixed {
            h: 0.4,
            kernel: Kernel::Uniform,
        };
        let got = f64::from(fixed.density(&pts, &q, &mut scratch));
        let want = 3.0 * 0.5 / (4.0 / 3.0 * pi * 0.4f64.powi(3));
        assert!((got - want).abs() <= 1e-6 * want, "{got} vs {want}");
    }

    /// `n` points uniform in the cube [0, side]³, each of mass `mass`.
    fn uniform_cube(n: usize, side: f32, mass: f32, seed: u64) -> WeightedPoints {
        let mut rng = Pcg32::new(seed, 2);
        let pts: Vec<Vec3> = (0..n)
            .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * side)
            .collect();
        WeightedPoints::volume(pts, vec![mass; n])
    }

    /// ∫ K₃² over the unit ball (the kernel's roughness R(K), 1/m³ for h = 1), by the
    /// midpoint rule in r: 4π ∫₀¹ K(r²)² r² dr.
    fn roughness_3d(k: Kernel) -> f64 {
        let n = 20_000;
        (0..n)
            .map(|i| {
                let r = (i as f64 + 0.5) / n as f64;
                let v = f64::from(k.eval((r * r) as f32, Dim::Three));
                4.0 * std::f64::consts::PI * v * v * r * r / n as f64
            })
            .sum()
    }

    /// Volume queries over points uniform in a 2 m cube recover its density (the points' total
    /// mass over 8 m³). The k-NN estimate averages about k points, so its relative standard
    /// deviation is `√(R(K) V₃ / k)` (R(K) = ∫K₃², V₃ = 4π/3), which is `1/√k` for the uniform
    /// kernel; a fixed-bandwidth estimate's is `√(R(K) / (N h³))` with N the points per m³.
    /// The 27 queries are 0.5 m apart, more than twice the gather radius, so independent: each
    /// must lie within 4σ, their mean within 4σ/√27 plus the k-NN bias 1/(k − 1). A 2-D
    /// normalisation (K₂/h²) is off by a factor ≈ 13 here, a 2-D constant with h³ by 16/15.
    #[test]
    fn volume_queries_recover_a_uniform_density_in_a_cube() {
        let n = 400_000;
        let side = 2.0f32;
        let total = 3.0f32;
        let density = f64::from(total) / f64::from(side).powi(3);
        let count_per_m3 = n as f64 / f64::from(side).powi(3);
        let pts = uniform_cube(n, side, total / n as f32, 31);
        let v3 = 4.0 / 3.0 * std::f64::consts::PI;
        let k = 400;
        let h = 0.12f32;
        let cases: Vec<(EstimatorSpec, f64, f64)> = vec![
            (
                EstimatorSpec::Knn {
                    k,
                    max_radius: None,
                    kernel: Kernel::Uniform,
                },
                (1.0 / k as f64).sqrt(),
                1.0 / (k as f64 - 1.0),
            ),
            (
                EstimatorSpec::Knn {
                    k,
                    max_radius: None,
                    kernel: Kernel::Epanechnikov,
                },
                (roughness_3d(Kernel::Epanechnikov) * v3 / k as f64).sqrt(),
                1.0 / (k as f64 - 1.0),
            ),
            (
                EstimatorSpec::Fixed {
                    h,
                    kernel: Kernel::Biweight,
                },
                (roughness_3d(Kernel::Biweight) / (count_per_m3 * f64::from(h).powi(3))).sqrt(),
                0.0,
            ),
        ];
        let m = 3;
        let mut scratch = Scratch::default();
        for (spec, sigma, bias) in cases {
            assert!(spec.supports(Dim::Three));
            let est = Estimator::prepare(&spec, &pts);
            let mut mean = 0.0f64;
            for a in 0..m {
                for b in 0..m {
                    for c in 0..m {
                        let p = Vec3::new(0.5 + 0.5 * a as f32, 0.5 + 0.5 * b as f32, 0.5)
                            + Vec3::Z * (0.5 * c as f32);
                        let q = Query::volume(p);
                        let d = f64::from(est.density(&pts, &q, &mut scratch)) / density;
                        assert!(
                            (d - 1.0).abs() < 4.0 * sigma + bias,
                            "{spec:?}: {d} of the density at {p} (σ = {sigma})"
                        );
                        mean += d / (m * m * m) as f64;
                    }
                }
            }
            let tol = 4.0 * sigma / ((m * m * m) as f64).sqrt() + bias;
            assert!(
                (mean - 1.0).abs() < tol,
                "{spec:?}: mean {mean}, tolerance {tol}"
            );
            // With the uniform kernel the estimate is k m / (4/3 π r³) exactly, r the k-th
            // distance found by brute force (Dim::ball_volume is not used here).
            if let EstimatorSpec::Knn {
                kernel: Kernel::Uniform,
                ..
            } = spec
            {
                let p = Vec3::new(1.0, 0.9, 1.1);
                let mut d2: Vec<f32> = (0..n as u32)
                    .map(|i| (pts.position(i) - p).length_squared())
                    .collect();
                d2.select_nth_unstable_by(k - 1, f32::total_cmp);
                let r3 = f64::from(d2[k - 1]).powf(1.5);
                // The k-th point itself sits on the boundary (weight 0): k − 1 count.
                let want = (k - 1) as f64 * f64::from(total / n as f32) / (v3 * r3);
                let got = f64::from(est.density(&pts, &Query::volume(p), &mut scratch));
                assert!((got - want).abs() < 1e-4 * want, "{got} vs {want}");
            }
        }
    }

    /// The variable-bandwidth estimate in a volume: each point spreads its mass with
    /// `K₃(d²/hᵢ²)/hᵢ³` over its own ball, so the mean over interior queries is the density; a
    /// single estimate averages about k points (tolerance as for k-NN).
    #[test]
    fn variable_bandwidth_recovers_a_uniform_density_in_a_volume() {
        let n = 60_000;
        let pts = uniform_cube(n, 1.0, 1.0 / n as f32, 5);
        let k = 60;
        let spec = EstimatorSpec::Variable {
            k,
            max_radius: None,
            kernel: Kernel::Epanechnikov,
        };
        let est = Estimator::prepare(&spec, &pts);
        let sigma = (roughness_3d(Kernel::Epanechnikov) * 4.0 / 3.0 * std::f64::consts::PI
            / k as f64)
            .sqrt();
        let mut scratch = Scratch::default();
        let mut mean = 0.0f64;
        let m = 4;
        for a in 0..m {
            for b in 0..m {
                for c in 0..m {
                    let p = Vec3::new(a as f32, b as f32, c as f32) * (0.4 / (m - 1) as f32)
                        + Vec3::splat(0.3);
                    let d = f64::from(est.density(&pts, &Query::volume(p), &mut scratch));
                    assert!((d - 1.0).abs() < 4.0 * sigma, "{d} at {p} (σ = {sigma})");
                    mean += d / (m * m * m) as f64;
                }
            }
        }
        // The queries are ~2 bandwidths apart (hᵢ ≈ (k/(n V₃))^⅓ ≈ 0.063 m): not quite
        // independent, so the mean is held to 4σ/√(m³/2).
        let tol = 4.0 * sigma / ((m * m * m) as f64 / 2.0).sqrt();
        assert!((mean - 1.0).abs() < tol, "mean {mean}, tolerance {tol}");
    }

    /// The diffusion estimator is surface-only: a volume query is a typed error (and a panic
    /// through `weights`), with no point visited; every other estimator answers it.
    #[test]
    fn diffusion_refuses_volume_queries() {
        let pts = uniform_cube(2000, 1.0, 1.0, 1);
        let spec = EstimatorSpec::Diffusion(DiffusionParams::new(0.1));
        assert!(spec.supports(Dim::Two) && !spec.supports(Dim::Three));
        let est = Estimator::prepare(&spec, &pts);
        assert!(!est.supports(Dim::Three));
        let q = Query::volume(Vec3::splat(0.5));
        let mut visited = 0;
        let r = est.try_weights(&pts, &q, &mut Scratch::default(), |_, _| visited += 1);
        assert_eq!(r, Err(crate::DensityError::SurfaceOnly("diffusion")));
        assert_eq!(visited, 0);
        assert!(est.try_density(&pts, &q, &mut Scratch::default()).is_err());
        assert!(r.unwrap_err().to_string().contains("volume"));
        let panicked = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            est.density(&pts, &q, &mut Scratch::default())
        }));
        assert!(panicked.is_err());
        for spec in [
            EstimatorSpec::Fixed {
                h: 0.1,
                kernel: Kernel::Uniform,
            },
            EstimatorSpec::Knn {
                k: 10,
                max_radius: None,
                kernel: Kernel::Uniform,
            },
            EstimatorSpec::Variable {
                k: 10,
                max_radius: None,
                kernel: Kernel::Uniform,
            },
        ] {
            let est = Estimator::prepare(&spec, &pts);
            assert!(est.supports(Dim::Three) && est.supports(Dim::Two));
            let d = est.try_density(&pts, &q, &mut Scratch::default()).unwrap();
            assert!(d > 0.0, "{spec:?}");
        }
    }

    #[test]
    fn validation_names_the_parameter() {
        let kernel = Kernel::Epanechnikov;
        assert!(
            EstimatorSpec::Fixed { h: 0.0, kernel }
                .validate()
                .unwrap_err()
                .contains("bandwidth")
        );
        assert!(
            EstimatorSpec::Knn {
                k: 0,
                max_radius: None,
                kernel
            }
            .validate()
            .unwrap_err()
            .contains("k ")
        );
        assert!(
            EstimatorSpec::Variable {
                k: 5,
                max_radius: Some(f32::NAN),
                kernel
            }
            .validate()
            .is_err()
        );
    }

    #[test]
    fn median_radius_of_a_lattice() {
        // A unit lattice: every interior point's 4th nearest other point is at distance 1.
        let pts: Vec<[f64; 2]> = (0..400)
            .map(|i| [(i % 20) as f64, (i / 20) as f64])
            .collect();
        let r = median_knn_radius(&WeightedPoints::planar(&pts), 4).unwrap();
        assert_eq!(r, 1.0);
        assert!(median_knn_radius(&WeightedPoints::planar(&[]), 4).is_none());
    }
}
