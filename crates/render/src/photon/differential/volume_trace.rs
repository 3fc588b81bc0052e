//! Photon differentials of volume photons (seed 000 sec. 8.4): the light paths of the volume
//! photon tracer ([`crate::photon::tracer`] with `MapKind::Volume`: same walker, stream and
//! chunks, so with the same seed the photons are at the same events with the same flux), each
//! carrying a [`RayDiff`] from the light through every event of the path:
//!
//! * emission as for caustics (seed 002 eq. 1–6, [`DiffRay`]);
//! * free flight to a scattering event, eq. 8.19–8.22 ([`free_flight`]); at the event the
//!   photon is stored with its two positional vectors;
//! * scattering in a medium: rotation into the sampled direction and `√k`, `k = 1/(4π p)`
//!   (eq. 8.23–8.24, [`scatter`]);
//! * delta reflection and refraction as for caustics (app. B, [`DiffRay::scatter_delta`]);
//! * any other surface scattering (diffuse, glossy: sampled by importance): transfer onto the
//!   tangent plane (eq. B.13–B.16), projection onto the plane ⊥ the incident direction, rotation
//!   and `√k`, `k = 1/(2π p)` (eq. 8.25–8.26 and seed notes Q-M5, [`reflect_sampled`]).
//!
//! The paths are traced with the budget `N_e = 1` and the vectors scaled by `1/√(N pmf)`
//! afterwards, as for caustic landings ([`super`], "The budget N_e"): every map above is linear
//! in the differential vectors (the rotation and `√k` too), so the scaling commutes with them.
//! At storage the photon gets its third vector and its ellipsoid ([`volume_kernel`]).

use super::trace::{DiffRay, LandingTracer, unit_budget};
use crate::options::{RenderOptions, Smoothing};
use crate::photon::plan::{PathStream, PhotonBudget, trace_budget};
use crate::photon::tracer::{Photon, shortfall};
use crate::stats::RenderStats;
use crate::transport::light_walk::{
    LightEvent, LightMediumVertex, LightScatter, LightVisitor, walk_light_path_with,
};
use caustica_core::sampling::Sampler;
use caustica_core::{Mat3, Spectrum, Vec3};
use caustica_density::beam::{axes_bounding_radius, ellipsoid_volume, filter_matrix};
use caustica_differentials::medium::widen_ellipse;
use caustica_differentials::{
    AxesRule, RayDiff, free_flight, phase_area_factor, reflect_sampled, scatter, spread_collimated,
    surface_area_factor, volume_axes,
};
use caustica_scene::Scene;
use caustica_scene::phase::PhaseSample;
use rayon::prelude::*;

/// A volume photon before the path count is known: the event, its throughput and the two
/// positional differential vectors for `N_e = 1`.
#[derive(Clone, Copy, Debug)]
pub struct VolumeLanding {
    /// Event position (m).
    pub p: Vec3,
    /// Unit direction toward where the photon came from.
    pub wi: Vec3,
    /// Path throughput β (W, not yet divided by the path count).
    pub beta: Spectrum,
    pub depth: u16,
    /// Selection probability of the path's light.
    pub pmf: f32,
    /// `D_u x`, `D_v x` at the event for `N_e = 1`; `None` if the differential could not be
    /// propagated to it.
    pub dp: Option<[Vec3; 2]>,
}

/// A volume photon's kernel: the ellipsoid `{x : |M(x − c)| < 1}` (sec. 8.3–8.4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipsoid {
    /// Filter matrix `M = (½[D_u x D_v x D_w x])⁻¹` (m⁻¹).
    pub m: Mat3,
    /// `1/V`, `V = (π/6)|(D_u x × D_v x)·D_w x|` (eq. 8.16) (m⁻³).
    pub inv_volume: f32,
    /// Radius (m) of the smallest sphere about the centre holding the ellipsoid (its largest
    /// semi-axis).
    pub bound: f32,
}

/// Volume photon differentials of one map and how they were made.
pub struct TracedVolumeDiffs {
    /// Photons in path order, flux β/N (W).
    pub photons: Vec<Photon>,
    /// Their kernels, one per photon.
    pub kernels: Vec<Ellipsoid>,
    /// Light paths emitted.
    pub paths: u64,
    /// Scattering events found (stored + collapsed + failed).
    pub events: usize,
    /// Events dropped because their kernel is flat (coplanar vectors).
    pub collapsed: u64,
    /// Events dropped because the differential could not be propagated to them.
    pub failed: u64,
    /// Kernels widened by the minimum semi-axis.
    pub widened: u64,
    pub stats: RenderStats,
    pub warning: Option<String>,
}

/// How stored volume photons get their kernels.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct KernelRule {
    pub axes: AxesRule,
    /// The smallest semi-axis (m) a kernel may have (none by default, as the thesis): the
    /// cross-section's principal semi-axes and `D_w x`'s are raised to it.
    pub min_semi_axis: Option<f32>,
    /// With a smoothing `S`: collimated photons (beam and directional lights) get the
    /// directional vectors of a point light's photon at smoothing `S` (eq. 6, `ω_e = 4π`) at
    /// their first non-delta scattering ([`spread_collimated`]; an extension, off by default
    /// as in the thesis). A smoothing of its own: a narrow beam needs a large `s` for its
    /// positional vectors, which as an angular spread would be radians wide.
    pub spread_collimated: Option<Smoothing>,
}

/// The ellipsoid of a photon with traced vectors `du`, `dv` (m, already scaled for the
/// budget) travelling along unit `dir` (sec. 8.4, eq. 8.16, [`volume_axes`]), and whether the
/// minimum semi-axis widened it; `None` for a flat or non-finite kernel.
pub fn volume_kernel(du: Vec3, dv: Vec3, dir: Vec3, rule: KernelRule) -> Option<(Ellipsoid, bool)> {
    let [mut du, mut dv, mut dw] = volume_axes(du, dv, dir, rule.axes).ok()?;
    let mut widened = false;
    if let Some(r) = rule.min_semi_axis {
        // The cross-section ellipse's principal semi-axes raised to r (as surface footprints'
        // are); D_w x = max(|D_u x|, |D_v x|) follows.
        if let Some([a, b]) = widen_ellipse(du, dv, dir, r) {
            widened = true;
            dw = dw.try_normalize().unwrap_or(dir) * a.length();
            (du, dv) = (a, b);
        }
    }
    let m = filter_matrix(du, dv, dw)?;
    // Eq. 8.16, V = (π/6)|(D_u x × D_v x)·D_w x| (= (4π/3)/|det M|).
    let inv_volume = 1.0 / ellipsoid_volume(du, dv, dw);
    let bound = match rule.axes {
        // D_w x ⊥ D_u x, D_v x and |D_w x| = max(|D_u x|, |D_v x|) ≤ the cross-section's major
        // axis: the largest semi-axis is the cross-section ellipse's (closed form, 2 × 2).
        // (Widened kernels too: their D_w x has the widened major axis' length.)
        AxesRule::Projected => cross_section_major_semi_axis(du, dv)?,
        AxesRule::PaperLiteral => axes_bounding_radius(du, dv, dw)?,
    };
    (inv_volume.is_finite() && inv_volume > 0.0 && bound > 0.0).then_some((
        Ellipsoid {
            m,
            inv_volume,
            bound,
        },
        widened,
    ))
}

/// The major semi-axis (m) of the ellipse with conjugate diameters `du`, `dv` (m): half the
/// square root of the larger eigenvalue of their 2 × 2 Gram matrix, rounded up by a few ulps
/// so that the f32 kernel lies inside its bounding sphere. `None` if not finite.
fn cross_section_major_semi_axis(du: Vec3, dv: Vec3) -> Option<f32> {
    let (a, b) = (du.as_dvec3(), dv.as_dvec3());
    let (g11, g22, g12) = (a.dot(a), b.dot(b), a.dot(b));
    let half_diff = 0.5 * (g11 - g22);
    let lambda = 0.5 * (g11 + g22) + (half_diff * half_diff + g12 * g12).sqrt();
    let r = (0.5 * lambda.sqrt()) as f32 * (1.0 + 8.0 * f32::EPSILON);
    (r.is_finite() && r > 0.0).then_some(r)
}

/// Traces the light paths of `stream` under `budget` (volume photons, as the volume photon
/// tracer) as photon differentials with smoothing `smoothing`, and returns the stored photons
/// with their kernels ([`trace_volume_landings`], then [`kernels_from_landings`]).
/// `progress(fraction)` after each wave. Deterministic for a given seed whatever the thread
/// count.
pub fn trace_volume_differentials(
    scene: &Scene,
    budget: PhotonBudget,
    smoothing: Smoothing,
    rule: KernelRule,
    stream: u64,
    opts: &RenderOptions,
    progress: &mut dyn FnMut(f64) -> bool,
) -> TracedVolumeDiffs {
    let traced = trace_volume_landings(scene, budget, smoothing, rule, stream, opts, progress);
    kernels_from_landings(traced, budget, rule)
}

/// The scattering events of the light paths and their differentials, before the path count
/// scales them and the kernels are built (the tracing half of [`trace_volume_differentials`]).
pub struct VolumeLandings {
    pub landings: Vec<VolumeLanding>,
    /// Light paths emitted.
    pub paths: u64,
    pub stats: RenderStats,
}

/// The tracing half of [`trace_volume_differentials`]: every scattering event of the light
/// paths with its differential for `N_e = 1` (the rule's collimated spread applied on the way).
pub fn trace_volume_landings(
    scene: &Scene,
    budget: PhotonBudget,
    smoothing: Smoothing,
    rule: KernelRule,
    stream: u64,
    opts: &RenderOptions,
    progress: &mut dyn FnMut(f64) -> bool,
) -> VolumeLandings {
    let tracer = LandingTracer::new(scene, &unit_budget(smoothing));
    // Eq. 6 with ω_e = 4π for the unit budget: a point light's directional vector length.
    let point_length = rule.spread_collimated.and_then(|s| {
        unit_budget(s)
            .differential_length(4.0 * std::f32::consts::PI)
            .ok()
    });
    let limits = opts.limits;
    let (landings, paths, stats) = trace_budget(
        budget,
        &PathStream::new(opts, stream),
        opts.photons.first_path,
        progress,
        |_, sampler, out, st| {
            let mut v = VolumeDiffVisitor::<2> {
                ray: DiffRay::new(tracer.scene, &tracer.lights),
                out,
                point_length,
                pending: None,
            };
            walk_light_path_with(tracer.scene, sampler, &limits, st, &mut v);
        },
    );
    VolumeLandings {
        landings,
        paths,
        stats,
    }
}

/// The kernel half of [`trace_volume_differentials`]: each landing's vectors scaled for the path
/// count (`1/√(N pmf)`, eq. 5–6) and its ellipsoid built by `rule` ([`volume_kernel`]), in
/// parallel and collected in path order.
pub fn kernels_from_landings(
    traced: VolumeLandings,
    budget: PhotonBudget,
    rule: KernelRule,
) -> TracedVolumeDiffs {
    let VolumeLandings {
        landings,
        paths,
        stats,
    } = traced;
    let n = paths.max(1) as f64;
    // Kernels in parallel, collected in path order (deterministic).
    let built: Vec<Built> = landings
        .par_iter()
        .map(|l| {
            let Some(dp) = l.dp else {
                return Built::Failed;
            };
            // N_e of this light = N · pmf; vectors scale as 1/√N_e (eq. 5–6).
            let scale = (1.0 / (n * l.pmf as f64).sqrt()) as f32;
            let flux = l.beta / n as f32;
            if !flux.is_finite() {
                return Built::Failed;
            }
            match volume_kernel(dp[0] * scale, dp[1] * scale, -l.wi, rule) {
                Some((k, widened)) => Built::Kept(
                    Photon {
                        p: l.p,
                        wi: l.wi,
                        n: Vec3::ZERO,
                        flux,
                        depth: l.depth,
                        caustic: false,
                    },
                    k,
                    widened,
                ),
                None => Built::Collapsed,
            }
        })
        .collect();
    let mut photons = Vec::with_capacity(built.len());
    let mut kernels = Vec::with_capacity(built.len());
    let (mut collapsed, mut failed, mut widened) = (0u64, 0u64, 0u64);
    for b in built {
        match b {
            Built::Kept(p, k, w) => {
                widened += w as u64;
                photons.push(p);
                kernels.push(k);
            }
            Built::Collapsed => collapsed += 1,
            Built::Failed => failed += 1,
        }
    }
    let warning = shortfall("volume", landings.len(), paths, budget).map(|w| {
        if landings.is_empty() {
            format!("{w}: no light scatters in a participating medium")
        } else {
            w
        }
    });
    TracedVolumeDiffs {
        photons,
        kernels,
        paths,
        events: landings.len(),
        collapsed,
        failed,
        widened,
        stats,
        warning,
    }
}

/// What became of one event.
enum Built {
    Kept(Photon, Ellipsoid, bool),
    Collapsed,
    Failed,
}

/// Per-path state: the differential along the current ray and the events found.
struct VolumeDiffVisitor<'a, const N: usize> {
    ray: DiffRay<'a, N>,
    out: &'a mut Vec<VolumeLanding>,
    /// The unit budget's point-light directional length when collimated photons are spread at
    /// their first non-delta scattering ([`KernelRule::spread_collimated`]).
    point_length: Option<f32>,
    /// The last diffuse scattering, not yet applied ([`Pending`]).
    pending: Option<Pending>,
}

impl<const N: usize> VolumeDiffVisitor<'_, N> {
    /// The ray about to scatter diffusely, spread if it is collimated and the rule asks for it.
    fn before_scattering(&self, r: RayDiff<N>) -> RayDiff<N> {
        match self.point_length {
            Some(l) => spread_collimated(&r, l),
            None => r,
        }
    }
}

impl<const N: usize> LightVisitor for VolumeDiffVisitor<'_, N> {
    fn event(&mut self, event: LightEvent, _: &mut Sampler, stats: &mut RenderStats) {
        match event {
            LightEvent::Start(start) => {
                self.pending = None;
                self.ray.start(start)
            }
            LightEvent::Vertex(_) => {}
            LightEvent::Medium(lm) => {
                self.settle();
                // Eq. 8.19–8.22: the flight from the ray's origin (the last vertex) to the event.
                let at = self.ray.ray().and_then(|r: RayDiff<N>| {
                    let s = (lm.v.p - r.p).dot(r.v);
                    free_flight(&r, s)
                });
                self.ray.ray = Some(at);
                // Stored in linear sRGB, as every photon (the identity in RGB mode).
                let beta = lm.v.channels.to_rgb(lm.beta);
                if !beta.is_finite() {
                    stats.nonfinite += 1;
                    return;
                }
                self.out.push(VolumeLanding {
                    p: lm.v.p,
                    wi: lm.v.wo,
                    beta,
                    depth: lm.depth.min(u16::MAX as u32) as u16,
                    pmf: self.ray.pmf,
                    dp: at.ok().map(|r| [r.dp[0], r.dp[1]]),
                });
            }
        }
    }

    fn scatter_in_medium(&mut self, _: &LightMediumVertex, ps: &PhaseSample) -> bool {
        self.settle();
        self.pending = Some(Pending::Phase {
            wi: ps.wi,
            pdf: ps.pdf,
        });
        true
    }

    fn scatter(&mut self, sc: &LightScatter, _: &mut RenderStats) -> bool {
        self.settle();
        if sc.sample.flags.is_delta() {
            self.ray.scatter_delta(sc);
        } else {
            self.pending = Some(Pending::Sampled {
                hit: sc.v.si.p,
                wi: sc.wi,
                pdf: sc.sample.pdf,
            });
        }
        true
    }
}

/// A diffuse scattering whose differential is not computed until a later event needs it: the
/// last one of a path that stores no further photon (most paths in thin media end on a diffuse
/// bounce) then costs nothing. Applying it later gives the same values as applying it at once.
#[derive(Clone, Copy, Debug)]
enum Pending {
    /// A phase-function sample at the ray's current origin (the event): eq. 8.23–8.24.
    Phase { wi: Vec3, pdf: f32 },
    /// An importance-sampled surface reflection at `hit` (m): eq. 8.25–8.26.
    Sampled { hit: Vec3, wi: Vec3, pdf: f32 },
}

impl<const N: usize> VolumeDiffVisitor<'_, N> {
    /// Applies the pending scattering, if any, to the differential.
    fn settle(&mut self) {
        let Some(p) = self.pending.take() else {
            return;
        };
        let out = self.ray.ray().and_then(|r| match p {
            // Eq. 8.23–8.24 (the ray is at the event since `event`).
            Pending::Phase { wi, pdf } => {
                scatter(&self.before_scattering(r), wi, phase_area_factor(pdf)?)
            }
            // Eq. 8.25–8.26 with the projection ⊥ the incident direction (Q-M5). The transfer
            // onto the tangent plane (eq. B.13–B.16) differs from the free flight to the hit
            // only along V (the ds V term), which the projection removes: the flight is the
            // cheaper way there.
            Pending::Sampled { hit, wi, pdf } => {
                let at = self.before_scattering(free_flight(&r, (hit - r.p).dot(r.v))?);
                let mut r = reflect_sampled(&at, wi, surface_area_factor(pdf)?)?;
                r.p = hit;
                Ok(r)
            }
        });
        self.ray.ray = Some(out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use caustica_density::beam::ball_volume;

    #[test]
    fn equal_orthogonal_vectors_give_the_ball() {
        // TM10 and the reduction of eq. 8.16 to the ball: D_u, D_v ⊥ ω of equal length 2h give
        // M = I/h, V = 4πh³/3 and bound h.
        let dir = Vec3::new(0.3, -0.4, 0.866).normalize();
        let f = caustica_core::Frame::from_normal(dir);
        let h = 0.07;
        let (k, widened) =
            volume_kernel(f.s * 2.0 * h, f.t * 2.0 * h, dir, KernelRule::default()).unwrap();
        assert!(!widened);
        assert!((1.0 / k.inv_volume - ball_volume(h)).abs() < 1e-5 * ball_volume(h));
        assert!((k.bound - h).abs() < 1e-5 * h);
        for v in [Vec3::X, Vec3::Y, Vec3::Z, dir] {
            assert!(((k.m * v).length() - v.length() / h).abs() < 1e-3 / h);
        }
    }

    #[test]
    fn the_closed_form_bound_is_the_largest_semi_axis() {
        // The projected rule's 2 × 2 bound against the general Gram-matrix one, for random
        // vectors (widened or not).
        let mut rng = caustica_core::sampling::Pcg32::new(2, 7);
        let mut u = || 2.0 * rng.next_f32() - 1.0;
        for i in 0..2000 {
            let dir = Vec3::new(u(), u(), u()).normalize();
            let (du, dv) = (Vec3::new(u(), u(), u()), Vec3::new(u(), u(), u()) * 0.3);
            let rule = KernelRule {
                min_semi_axis: (i % 2 == 0).then_some(0.2),
                ..KernelRule::default()
            };
            let Some((k, _)) = volume_kernel(du, dv, dir, rule) else {
                continue;
            };
            let [a, b, c] = volume_axes(du, dv, dir, AxesRule::Projected).unwrap();
            let general = if rule.min_semi_axis.is_some() {
                // Widened: the bound must contain the unit filter ball's image.
                caustica_density::beam::filter_bounding_radius(k.m).unwrap()
            } else {
                axes_bounding_radius(a, b, c).unwrap()
            };
            assert!(
                (k.bound - general).abs() <= 1e-4 * general,
                "{} vs {general}",
                k.bound
            );
        }
    }

    #[test]
    fn the_minimum_semi_axis_widens_thin_kernels_only() {
        let dir = Vec3::Z;
        let rule = KernelRule {
            min_semi_axis: Some(0.01),
            ..KernelRule::default()
        };
        // A thin cross-section 0.2 × 0.002 m: widened to semi-axes 0.1 × 0.01 (and 0.1 along ω).
        let (k, widened) = volume_kernel(Vec3::X * 0.2, Vec3::Y * 0.002, dir, rule).unwrap();
        assert!(widened);
        let v = 1.0 / k.inv_volume;
        let want = 4.0 / 3.0 * std::f32::consts::PI * 0.1 * 0.01 * 0.1;
        assert!((v - want).abs() < 1e-4 * want, "{v} vs {want}");
        // A collapsed one (parallel vectors) becomes a finite kernel, counted.
        let (k, widened) = volume_kernel(Vec3::X * 0.2, Vec3::X * 0.1, dir, rule).unwrap();
        assert!(widened && k.inv_volume.is_finite());
        // Without the rule the collapsed one is refused and a fat one is left alone.
        assert!(volume_kernel(Vec3::X * 0.2, Vec3::X * 0.1, dir, KernelRule::default()).is_none());
        let (_, widened) = volume_kernel(Vec3::X * 0.2, Vec3::Y * 0.1, dir, rule).unwrap();
        assert!(!widened);
    }
}
