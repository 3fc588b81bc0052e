//! A caustic photon's footprint where it lands (seed 002 eq. 4, 10–12) and the one rule for its
//! weight at a point, shared by `pdm` (gathering) and `pds` (splatting).

use crate::options::FootprintSettings;
use caustica_core::{Spectrum, Vec3};
use caustica_density::kernel::{Dim, Kernel};
use caustica_differentials::{DiffError, Footprint};

/// A caustic photon with its footprint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffPhoton {
    /// The footprint on the tangent plane of the hit (centre = hit point).
    pub footprint: Footprint,
    /// Unit direction toward where the photon came from.
    pub wi: Vec3,
    /// Geometric normal at the hit, on the side the photon arrived from (unit).
    pub n: Vec3,
    /// Flux Φ_p = β/N (W).
    pub flux: Spectrum,
    /// Edges from the light.
    pub depth: u16,
}

/// A caustic landing before the budget is known: its differential vectors for `N_e = 1`, for
/// `N` differential parameters (2: the emission's).
#[derive(Clone, Copy, Debug)]
pub struct Landing<const N: usize = 2> {
    /// Hit point (m).
    pub p: Vec3,
    /// Unit direction toward where the photon came from.
    pub wi: Vec3,
    /// Geometric normal on the arrival side (unit).
    pub n: Vec3,
    /// Path throughput β (W, not yet divided by the path count).
    pub beta: Spectrum,
    pub depth: u16,
    /// Selection probability of the light the path started at.
    pub pmf: f32,
    /// `D_u x`, `D_v x` on the receiving plane for `N_e = 1`; `None` when the differential
    /// could not be propagated to it.
    pub dp: Option<[Vec3; N]>,
}

/// The photons of `landings` from `paths` emitted light paths: flux β/N, vectors scaled by
/// `1/√(N pmf)` (eq. 5–6 with the light's share of the paths), footprints built on the
/// landings' planes. Returns them with the counts of landings dropped for a collapsed footprint
/// and for a failed propagation (no vectors, or vectors that are not finite).
pub fn photons_from_landings(landings: &[Landing], paths: u64) -> (Vec<DiffPhoton>, u64, u64) {
    let n = paths.max(1) as f64;
    let mut photons = Vec::with_capacity(landings.len());
    let (mut collapsed, mut failed) = (0u64, 0u64);
    for l in landings {
        let Some(dp) = l.dp else {
            failed += 1;
            continue;
        };
        // N_e of this light = N · pmf; vectors scale as 1/√N_e (eq. 5–6).
        let scale = (1.0 / (n * l.pmf as f64).sqrt()) as f32;
        let flux = l.beta / n as f32;
        if !flux.is_finite() {
            failed += 1;
            continue;
        }
        match Footprint::new(l.p, dp[0] * scale, dp[1] * scale, l.n) {
            Ok(footprint) => photons.push(DiffPhoton {
                footprint,
                wi: l.wi,
                n: l.n,
                flux,
                depth: l.depth,
            }),
            Err(DiffError::CollapsedFootprint) => collapsed += 1,
            Err(_) => failed += 1,
        }
    }
    (photons, collapsed, failed)
}

/// Footprints whose surface normal is farther than this cosine from the query's are ignored.
pub(crate) const NORMAL_COS: f32 = 0.9;

/// How footprints are evaluated at a point: the one rule of `pdm` (gathering) and `pds`
/// (splatting), so the two evaluation orders give the same sum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FootprintFilter {
    /// Radial kernel over the unit disc of filter space (Silverman's, eq. 11, by default).
    pub kernel: Kernel,
    /// Normal-distance threshold (seed 002 sec. 3.3) as a fraction of the gather radius.
    pub normal_distance: f32,
}

impl FootprintFilter {
    /// `π K(|M_p (x − x_p)|) / A_p` (1/m², eq. 10–12 without the BRDF and flux) of photon `ph`
    /// at `x` on a surface with unit normal `n` oriented toward the viewer, or `None` when the
    /// footprint does not reach `x`: outside the ellipse, arrived on the other side, a surface
    /// normal more than ~25° from `n` (cos < 0.9), or `x` farther from the footprint's tangent
    /// plane than `normal_distance` times its gather radius (the filter of eq. 12 ignores the
    /// normal offset; these tests keep footprints off nearby surfaces of another orientation,
    /// like the disc test of `pm`).
    #[inline]
    pub fn weight(&self, ph: &DiffPhoton, x: Vec3, n: Vec3) -> Option<f32> {
        let fp = &ph.footprint;
        // Inside the ellipse: |M_p (x − x_p)| < 1 (eq. 12), the cheapest and most selective test.
        let u2 = fp.to_filter(x).length_squared();
        if u2.is_nan() || u2 >= 1.0 || ph.wi.dot(n) <= 0.0 || ph.n.dot(n) < NORMAL_COS {
            return None;
        }
        if (x - fp.center()).dot(fp.normal()).abs() > self.normal_distance * fp.gather_radius() {
            return None;
        }
        // π K(|M_p (x − x_p)|) / A_p, eq. 10 per W (= `Footprint::irradiance_at_with`).
        let w = std::f32::consts::PI * self.kernel.eval(u2, Dim::Two) / fp.area();
        (w > 0.0 && w.is_finite()).then_some(w)
    }
}

impl FootprintFilter {
    /// The filter of `settings`.
    pub fn new(settings: &FootprintSettings) -> Self {
        Self {
            kernel: settings.kernel,
            normal_distance: settings.normal_distance.get(),
        }
    }

    /// The box `[lo, hi]` of the points photon `ph` can reach under this filter: the ellipse's
    /// bounding box, `x_p ± √(u² + v²)` per axis for the conjugate semi-diameters
    /// `u = ½ D_u x`, `v = ½ D_v x` (tighter than the sphere of the gather radius for elongated
    /// footprints), widened along `n_p` by the normal-distance threshold (at most the gather
    /// radius). `None` if it is not finite.
    pub fn bounds(&self, ph: &DiffPhoton) -> Option<(Vec3, Vec3)> {
        let fp = &ph.footprint;
        let [u, v] = fp.conjugate_semi_diameters();
        let slab = fp.normal().abs() * (self.normal_distance.min(1.0) * fp.gather_radius());
        let half = (u * u + v * v).sqrt() + slab;
        let c = fp.center();
        (half.is_finite() && c.is_finite()).then_some((c - half, c + half))
    }
}

impl Default for FootprintFilter {
    fn default() -> Self {
        Self::new(&FootprintSettings::default())
    }
}
