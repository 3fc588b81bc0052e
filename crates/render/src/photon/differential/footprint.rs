//! A caustic photon's footprint where it lands (seed 002 eq. 4, 10–12) and the one rule for its
//! weight at a point, shared by `pdm` (gathering) and `pds` (splatting).

use crate::options::{FootprintSettings, ShutterAlign, SweepRule};
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
    /// `D_t x` (m): the footprint's displacement over the exposure on the receiving plane
    /// (seed 003 eq. 1, 5; seed 000 eq. 7.1), zero for ordinary photon differentials. The
    /// space-time footprint is the ellipse swept from the centre to `centre + dt`.
    pub dt: Vec3,
}

impl DiffPhoton {
    /// Centre of the footprint's reach (m): the middle of its motion segment; the radius
    /// around it is [`FootprintFilter::reach_radius`].
    pub fn reach_center(&self) -> Vec3 {
        self.footprint.center() + self.dt * 0.5
    }
}

/// A caustic landing before the budget is known: its differential vectors for `N_e = 1`, for
/// `N` differential parameters (2: the emission's; 3: and time, seed 003).
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
    /// `D_u x`, `D_v x` (and `D_t x` for temporal photon differentials) on the receiving plane
    /// for `N_e = 1`; `None` when the differential could not be propagated to it.
    pub dp: Option<[Vec3; N]>,
}

/// What the third differential column of a landing is, which decides how
/// [`photons_from_landings`] sweeps its footprint along it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SweepColumn {
    /// Time (seed 003): `D_t x` over the exposure, independent of the budget, swept from
    /// the segment start of the shutter alignment.
    Time(ShutterAlign),
    /// Wavelength: `D_λ x Δλ` for `N_e = 1` (the tracer applied `K s / p(λ)`), divided by the
    /// light's `N_e` here and swept centred on the photon's wavelength.
    Wavelength,
}

impl From<ShutterAlign> for SweepColumn {
    fn from(align: ShutterAlign) -> Self {
        SweepColumn::Time(align)
    }
}

/// The photons made from a batch of landings ([`photons_from_landings`]) and what happened to
/// the others.
#[derive(Debug)]
pub struct MadePhotons {
    pub photons: Vec<DiffPhoton>,
    /// Landings dropped because their footprint collapsed (never with a minimum semi-axis).
    pub collapsed: u64,
    /// Landings dropped because their differential could not be propagated.
    pub failed: u64,
    /// Footprints whose minor semi-axis the minimum semi-axis raised.
    pub widened: u64,
}

/// The photons of `landings` from `paths` emitted light paths: flux β/N, vectors scaled by
/// `1/√(N pmf)` (eq. 5–6 with the light's share of the paths), footprints built on the
/// landings' planes, each principal semi-axis raised to `min_semi_axis` (m) when given
/// ([`Footprint::widened`]; none by default, as seed 002). A third column is `D_t x`
/// ([`SweepColumn::Time`]), which does not depend on the emission budget (it starts at zero and
/// only moving geometry feeds it), so it is kept unscaled; the footprint's centre is put at the
/// start of its motion segment, `x + align.segment_start() · D_t x` (the hit itself for the
/// forward alignment). Or it is wavelength ([`SweepColumn::Wavelength`]): a photon's share of
/// the spectrum is `1/N_e` of the unit budget's, so the column is divided by `N pmf` and the
/// sweep centred on the hit. Returns them
/// with the counts of landings dropped for a collapsed footprint and for a failed propagation
/// (no vectors, or vectors that are not finite), and of footprints widened.
pub fn photons_from_landings<const N: usize>(
    landings: &[Landing<N>],
    paths: u64,
    column: impl Into<SweepColumn>,
    min_semi_axis: Option<f32>,
) -> MadePhotons {
    let column = column.into();
    let start = match column {
        SweepColumn::Time(align) => align.segment_start(),
        SweepColumn::Wavelength => -0.5,
    };
    let n = paths.max(1) as f64;
    let mut photons = Vec::with_capacity(landings.len());
    let (mut collapsed, mut failed, mut widened) = (0u64, 0u64, 0u64);
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
        let dt = match column {
            _ if N <= 2 => Vec3::ZERO,
            SweepColumn::Time(_) => dp[N - 1],
            SweepColumn::Wavelength => dp[N - 1] * (1.0 / (n * l.pmf as f64)) as f32,
        };
        if !dt.is_finite() {
            failed += 1;
            continue;
        }
        let centre = if start != 0.0 { l.p + dt * start } else { l.p };
        let (du, dv) = (dp[0] * scale, dp[1] * scale);
        let made = Footprint::widened(centre, du, dv, l.n, min_semi_axis).map(|(f, w)| {
            widened += u64::from(w);
            f
        });
        match made {
            Ok(footprint) => photons.push(DiffPhoton {
                footprint,
                wi: l.wi,
                n: l.n,
                flux,
                depth: l.depth,
                dt,
            }),
            Err(DiffError::CollapsedFootprint) => collapsed += 1,
            Err(_) => failed += 1,
        }
    }
    MadePhotons {
        photons,
        collapsed,
        failed,
        widened,
    }
}

/// The part of a render note that says how many footprints the minimum semi-axis widened
/// (empty without one).
pub fn widened_note(widened: u64, min_semi_axis: Option<f32>) -> String {
    min_semi_axis.map_or(String::new(), |r| {
        format!(", {widened} widened to the minimum semi-axis {r:.5} m")
    })
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
    /// How footprints with a motion segment are weighted along it (temporal photon
    /// differentials; no effect on photons without `D_t x`).
    pub sweep: SweepRule,
}

/// The largest `f32` below 1: time weights are evaluated at `min(u², ONE_BELOW)` so a segment's
/// end gets the kernel's limit there (1/2 for the uniform kernel), not the 0 of outside.
const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;

impl SweepRule {
    /// The time weight `w(τ)` at the segment parameter `τ ∈ [0, 1]` (seed 000 eq. 7.9's `K_t`,
    /// normalised to `∫₀¹ w dτ = 1`, Q-T5): `w(τ) = 2 K₁(u²)` for the univariate kernel `K₁`
    /// (Table 2.1, ∫₋₁¹ = 1), with `u = τ` for the forward alignment (the traced instant at
    /// `τ = 0`, the half-line of Q-T5) and `u = 2τ − 1` centred. 1 without a time filter.
    #[inline]
    pub fn time_weight(&self, tau: f32) -> f32 {
        let Some(k) = self.time_filter else {
            return 1.0;
        };
        let u = match self.align {
            ShutterAlign::Forward => tau,
            ShutterAlign::Centred => 2.0 * tau - 1.0,
        };
        2.0 * k.eval((u * u).min(ONE_BELOW), Dim::One)
    }

    /// The swept footprint's mass over its ellipse's, `A_eff / A_p`, for a footprint kernel
    /// `k` and the filter-space motion length `λ = |M D_t x|`: the two half-discs at the
    /// segment's ends weighted by `w(0)`, `w(1)` and the strip between them by `∫ w = 1`,
    /// `(w(0) + w(1))/2 + c₁ λ/π` (seed 000 Q-T4; `1 + c₁ λ/π` without a time filter, eq. 7.7
    /// for the uniform kernel). With `paper_area`: eq. 7.7, `1 + 2λ/π`, for every kernel.
    #[inline]
    pub fn area_factor(&self, k: Kernel, lambda: f32) -> f32 {
        if self.paper_area {
            return 1.0 + 2.0 * lambda / std::f32::consts::PI;
        }
        let ends = if self.time_filter.is_some() {
            0.5 * (self.time_weight(0.0) + self.time_weight(1.0))
        } else {
            1.0
        };
        ends + sweep_mass(k) * lambda / std::f32::consts::PI
    }
}

/// `c₁ = ∫₋₁¹ π K(s²) ds` for the 2-D kernel `k` (normalised to 1 over the unit disc, so `π K`
/// has mean 1 there): the kernel mass per unit of filter-space length that sweeping a
/// footprint adds (seed 000 Q-T4). Closed forms: uniform 2, Epanechnikov `2(1 − y)` 8/3,
/// Silverman (= biweight) `3(1 − y)²` 16/5, cubic `4(1 − y)³` 128/35, cone
/// `(1 − √y/g)/(1 − 2/(3g))` `(2 − 1/g)/(1 − 2/(3g))`; the truncated Gaussian by quadrature.
#[inline]
pub fn sweep_mass(k: Kernel) -> f32 {
    match k {
        Kernel::Uniform => 2.0,
        Kernel::Epanechnikov => 8.0 / 3.0,
        Kernel::Biweight | Kernel::Silverman => 16.0 / 5.0,
        Kernel::Cubic => 128.0 / 35.0,
        Kernel::Cone { g } => (2.0 - 1.0 / g) / (1.0 - 2.0 / (3.0 * g)),
        Kernel::Gaussian => {
            static GAUSSIAN: std::sync::OnceLock<f32> = std::sync::OnceLock::new();
            *GAUSSIAN.get_or_init(|| sweep_mass_by_quadrature(k, 2000))
        }
    }
}

/// [`sweep_mass`] by Simpson's rule with `n` (even) intervals.
pub fn sweep_mass_by_quadrature(k: Kernel, n: usize) -> f32 {
    let f = |i: usize| {
        let s = -1.0 + 2.0 * i as f64 / n as f64;
        std::f64::consts::PI * k.eval((s * s) as f32, Dim::Two) as f64
    };
    let h = 2.0 / n as f64;
    let mut sum = f(0) + f(n);
    for i in 1..n {
        sum += f(i) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    (sum * h / 3.0) as f32
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
        if ph.dt != Vec3::ZERO {
            return self.swept_weight(ph, x, n);
        }
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
    /// The space-time footprint's weight (seed 003 eq. 6–8; seed 000 eq. 7.6–7.8): the kernel
    /// centred at the point `x'_p = x_p + τ* D_t x` of the motion segment closest to `x` *in
    /// filter space*, `τ* = clamp(z·m / m·m, 0, 1)` with `z = M_p (x − x_p)`, `m = M_p D_t x`
    /// (the Euclidean closest point of the text loses up to half the energy of elongated
    /// footprints; seed 000 Q-T3), times the time filter `w(τ*)` (eq. 7.9; 1 without one),
    /// divided by the swept area `A_eff = A_p (1 + c₁ |m| / π)` ([`SweepRule::area_factor`]).
    /// For the uniform kernel `A_eff` is eq. 7.7, `A_p + l |D_t x|`, exactly; for other
    /// kernels it is the generalisation that keeps each footprint's integral equal to its flux
    /// (Q-T4; eq. 7.7 would over-count by up to 4/3 for Epanechnikov, 8/5 for Silverman).
    /// Same side, normal and plane tests as [`Self::weight`], measured from `x'_p`. Out of
    /// line, so that the common static test inlines into the gathering loops.
    #[inline(never)]
    fn swept_weight(&self, ph: &DiffPhoton, x: Vec3, n: Vec3) -> Option<f32> {
        let fp = &ph.footprint;
        let z = fp.to_filter(x);
        let m = fp.to_filter(fp.center() + ph.dt);
        let mm = m.length_squared();
        let tau = if mm > 0.0 {
            (z.dot(m) / mm).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let u2 = (z - m * tau).length_squared();
        if u2.is_nan() || u2 >= 1.0 || ph.wi.dot(n) <= 0.0 || ph.n.dot(n) < NORMAL_COS {
            return None;
        }
        let c = fp.center() + ph.dt * tau;
        if (x - c).dot(fp.normal()).abs() > self.normal_distance * fp.gather_radius() {
            return None;
        }
        let area = fp.area() * self.sweep.area_factor(self.kernel, mm.sqrt());
        let w = std::f32::consts::PI * self.kernel.eval(u2, Dim::Two) * self.sweep.time_weight(tau)
            / area;
        (w > 0.0 && w.is_finite()).then_some(w)
    }

    /// The filter of `settings`.
    pub fn new(settings: &FootprintSettings) -> Self {
        Self {
            kernel: settings.kernel,
            normal_distance: settings.normal_distance.get(),
            sweep: settings.sweep,
        }
    }

    /// The radius (m) around [`DiffPhoton::reach_center`] of the ball of the points photon `ph`
    /// can reach under this filter, the sphere counterpart of [`Self::bounds`]. A point
    /// [`Self::weight`] accepts lies in the footprint's plane inside its ellipse (eq. 12:
    /// within the gather radius r of the centre) and at most `normal_distance` r off that
    /// plane: within r √(1 + d²), d = min(`normal_distance`, 1) as in [`Self::bounds`], of a
    /// centre on the motion segment, itself within half the motion of the reach centre. The
    /// factor 1.001 covers the rounding of both tests (relative errors ~10⁻⁶). With a
    /// `normal_distance` above 1 the points farther than r off the plane, which the weight
    /// would accept, lie outside this ball, as they lie outside [`Self::bounds`]' box: gathering
    /// and splatting stop at the same slab.
    pub fn reach_radius(&self, ph: &DiffPhoton) -> f32 {
        let d = self.normal_distance.min(1.0);
        let r = ph.footprint.gather_radius() * (1.0 + d * d).sqrt() + 0.5 * ph.dt.length();
        r * 1.001
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
        let (lo, hi) = (c.min(c + ph.dt), c.max(c + ph.dt));
        (half.is_finite() && lo.is_finite() && hi.is_finite()).then_some((lo - half, hi + half))
    }
}

impl Default for FootprintFilter {
    fn default() -> Self {
        Self::new(&FootprintSettings::default())
    }
}
