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
    /// The footprints in gathering order ([`RadiusBuckets::into_slot_order`]: a query reads
    /// them from short contiguous runs), then those no query can reach (no positive, finite
    /// reach radius). `traced_index[i]` is photon `i`'s index in the traced photons.
    pub photons: Vec<DiffPhoton>,
    pub traced_index: Vec<u32>,
    /// Per photon (in `photons`' order), the square of [`FootprintFilter::reach_radius`] (m²):
    /// beyond it from the reach centre [`FootprintFilter::weight`] is `None`.
    reach2: Vec<f32>,
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
        let traced_photons = traced.photons;
        let centres: Vec<Vec3> = traced_photons.iter().map(|p| p.reach_center()).collect();
        // Searched out to the filter's reach, off-plane points near the rim included (the
        // footprints' own reach radius missed those: up to 3 % of the radius at the default
        // normal distance).
        let radii: Vec<f32> = traced_photons
            .iter()
            .map(|p| filter.reach_radius(p))
            .collect();
        // Records in the order the queries read them: the random reads of 132-byte records
        // were most of a gather's time (docs/performance.md, "pdm gathering in slot order").
        let (buckets, mut traced_index) = RadiusBuckets::build(&centres, &radii).into_slot_order();
        let mut held = vec![false; traced_photons.len()];
        for &i in &traced_index {
            held[i as usize] = true;
        }
        traced_index.extend((0..traced_photons.len() as u32).filter(|&i| !held[i as usize]));
        let photons: Vec<DiffPhoton> = traced_index
            .iter()
            .map(|&i| traced_photons[i as usize])
            .collect();
        let reach2 = traced_index
            .iter()
            .map(|&i| radii[i as usize].powi(2))
            .collect();
        Self {
            photons,
            traced_index,
            reach2,
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
        self.photons
            .iter()
            .map(|p| p.footprint.gather_radius())
            .filter(|r| r.is_finite())
            .fold(0.0, f32::max)
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
        self.photons.capacity() * std::mem::size_of::<DiffPhoton>()
            + (self.traced_index.capacity() + self.reach2.capacity()) * 4
            + self.buckets.memory_bytes()
    }

    /// Calls `f(photon, π K(|M_p (x − x_p)|) / A_p)` (1/m²) for every footprint that reaches
    /// `x` on a surface with unit normal `n` (oriented toward the viewer) by
    /// [`FootprintFilter::weight`], in a deterministic order.
    pub fn for_each(&self, x: Vec3, n: Vec3, mut f: impl FnMut(&DiffPhoton, f32)) {
        if !(x.is_finite() && n.is_finite()) {
            return;
        }
        self.buckets.for_each_candidate_at(x, |i, d2| {
            // Beyond the bound no record needs reading (most candidates of a bucket, whose
            // search radius is up to twice their own).
            if d2 >= self.reach2[i as usize] {
                return;
            }
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

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_core::sampling::Pcg32;
    use caustica_differentials::Footprint;

    /// The gathering's distance bound never drops a footprint the filter accepts: every query
    /// gets exactly the footprints and weights of a brute-force pass over all photons, in the
    /// same order up to the permutation. Queries sit inside ellipses, up to the normal-distance
    /// limit off their planes, on tilted and on moving footprints (the bound's two terms).
    #[test]
    fn gathering_finds_what_a_brute_force_pass_finds() {
        let mut rng = Pcg32::new(12, 7);
        let mut u = || rng.next_f32();
        let mut photons = Vec::new();
        for i in 0..600 {
            let c = Vec3::new(u(), u() * 0.2, u());
            let n = Vec3::new(u() - 0.5, 2.0, u() - 0.5).normalize();
            let t = n.cross(Vec3::X).normalize();
            let b = n.cross(t);
            // Elongated ellipses over three octaves of size.
            let s = 0.01 * 8f32.powf(u());
            let du = (t * (0.5 + 2.0 * u()) + b * (u() - 0.5)) * s;
            let dv = b * s * (0.3 + u());
            let Ok(footprint) = Footprint::new(c, du, dv, n) else {
                continue;
            };
            let dt = if i % 3 == 0 {
                Vec3::new(u() - 0.5, 0.0, u() - 0.5) * 0.05
            } else {
                Vec3::ZERO
            };
            photons.push(DiffPhoton {
                footprint,
                wi: n,
                n,
                flux: Spectrum::ONE,
                depth: 2,
                dt,
            });
        }
        let filter = FootprintFilter::default();
        let map = PdmMap::with_filter(TracedDiffPhotons::given(photons.clone(), 600), filter);
        assert_eq!(map.len(), photons.len());
        let mut found = 0;
        for (k, ph) in photons.iter().enumerate() {
            let fp = &ph.footprint;
            // A point near the rim of the swept ellipse, pushed off its plane by up to the
            // normal-distance limit (the farthest points the filter still accepts).
            let [du, dv] = fp.differentials();
            let a = k as f32 * 2.4;
            let off = fp.normal() * filter.normal_distance * fp.gather_radius() * 0.999;
            let x = fp.center() + ph.dt + (du * a.cos() + dv * a.sin()) * 0.49 + off;
            let n = fp.normal();
            let mut brute = Vec::new();
            for (j, q) in photons.iter().enumerate() {
                if let Some(w) = filter.weight(q, x, n) {
                    brute.push((j as u32, w.to_bits()));
                }
            }
            let mut got = Vec::new();
            map.for_each(x, n, |q, w| {
                let i = map.photons.iter().position(|p| std::ptr::eq(p, q)).unwrap();
                got.push((map.traced_index[i], w.to_bits()));
            });
            got.sort_unstable();
            assert_eq!(got, brute, "query {k} at {x}");
            found += got.len();
        }
        assert!(found >= photons.len(), "{found}");
    }
}
