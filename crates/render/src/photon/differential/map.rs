//! The footprints of `pdm` in a searchable map, and the gathering estimate of seed 002 eq. 10.

use super::footprint::{DiffPhoton, FootprintFilter};
use super::trace::TracedDiffPhotons;
use crate::transport::vertex::Vertex;
use caustica_core::{Spectrum, Vec3};
use caustica_density::kernel::Kernel;
use caustica_density::radius_buckets::RadiusBuckets;
use caustica_scene::bsdf::TransportMode;

/// Photon differentials with k-d trees over their footprint centres, and the estimate of seed
/// 002 eq. 10.
pub struct PdmMap {
    pub photons: Vec<DiffPhoton>,
    /// Light paths emitted (the N of Φ = β/N).
    pub paths: u64,
    /// Caustic landings found; `collapsed` and `failed` of them were dropped.
    pub landings: usize,
    pub collapsed: u64,
    pub failed: u64,
    /// Footprints widened by the minimum semi-axis.
    pub widened: u64,
    /// Footprint centres grouped by gather radius (one huge footprint must not slow every
    /// query).
    buckets: RadiusBuckets,
    /// How a footprint is evaluated at a point.
    filter: FootprintFilter,
}

impl PdmMap {
    /// The map of `traced`'s footprints, evaluated with `kernel` (normalised over the 2-D unit
    /// disc; `Kernel::Silverman` is seed 002's eq. 11) and the default normal-distance
    /// threshold.
    pub fn new(traced: TracedDiffPhotons, kernel: Kernel) -> Self {
        Self::with_filter(
            traced,
            FootprintFilter {
                kernel,
                ..FootprintFilter::default()
            },
        )
    }

    /// The map of `traced`'s footprints, evaluated with `filter`.
    pub fn with_filter(traced: TracedDiffPhotons, filter: FootprintFilter) -> Self {
        let photons = traced.photons;
        let centres: Vec<Vec3> = photons.iter().map(|p| p.reach_center()).collect();
        let radii: Vec<f32> = photons.iter().map(|p| p.reach_radius()).collect();
        let buckets = RadiusBuckets::build(&centres, &radii);
        Self {
            photons,
            paths: traced.paths,
            landings: traced.landings,
            collapsed: traced.collapsed,
            failed: traced.failed,
            widened: traced.widened,
            buckets,
            filter,
        }
    }

    pub fn len(&self) -> usize {
        self.photons.len()
    }

    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }

    /// Largest gather radius of any footprint (m), 0 for an empty map.
    pub fn max_gather_radius(&self) -> f32 {
        self.buckets.max_radius()
    }

    /// Median gather radius of the footprints (m), 0 for an empty map.
    pub fn median_gather_radius(&self) -> f32 {
        let mut r: Vec<f32> = self
            .photons
            .iter()
            .map(|p| p.footprint.gather_radius())
            .collect();
        if r.is_empty() {
            return 0.0;
        }
        let mid = r.len() / 2;
        *r.select_nth_unstable_by(mid, f32::total_cmp).1
    }

    /// Bytes held by the photons and the trees.
    pub fn memory_bytes(&self) -> usize {
        self.photons.capacity() * std::mem::size_of::<DiffPhoton>() + self.buckets.memory_bytes()
    }

    /// Calls `f(photon, π K(|M_p (x − x_p)|) / A_p)` (1/m²) for every footprint that reaches
    /// `x` on a surface with unit normal `n` (oriented toward the viewer) by
    /// [`FootprintFilter::weight`], in a deterministic order.
    pub fn for_each(&self, x: Vec3, n: Vec3, mut f: impl FnMut(&DiffPhoton, f32)) {
        if !(x.is_finite() && n.is_finite()) {
            return;
        }
        self.buckets.for_each_candidate(x, |i| {
            let ph = &self.photons[i as usize];
            if let Some(w) = self.filter.weight(ph, x, n) {
                f(ph, w);
            }
        });
    }

    /// Irradiance (W/m²) at `x` on a surface with unit normal `n` facing the light's side:
    /// `E(x) = Σ π K(|M_p (x − x_p)|) Φ_p / A_p` (seed 000 eq. 5.14 without the BRDF).
    pub fn irradiance(&self, x: Vec3, n: Vec3) -> Spectrum {
        let mut sum = Spectrum::ZERO;
        self.for_each(x, n, |ph, w| sum += ph.flux * w);
        if sum.is_finite() { sum } else { Spectrum::ZERO }
    }

    /// Reflected radiance (W/m²/sr) at vertex `v` toward its `wo`, seed 002 eq. 10:
    /// `Σ f_r(x, ω_p, ω) π K(|M_p (x − x_p)|) Φ_p / A_p`.
    pub fn radiance(&self, v: &Vertex) -> Spectrum {
        if self.photons.is_empty() {
            return Spectrum::ZERO;
        }
        let n = v.facing_normal();
        let mut sum = Spectrum::ZERO;
        self.for_each(v.si.p, n, |ph, w| {
            let f = v
                .bsdf
                .eval(v.wo, v.frame.to_local(ph.wi), TransportMode::Radiance);
            sum += f * ph.flux * w;
        });
        if sum.is_finite() { sum } else { Spectrum::ZERO }
    }
}
