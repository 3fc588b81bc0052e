//! Photon differentials for caustics (seed 002 sec. 3; seed 000 ch. 5): caustic photons that
//! carry a first-order [`RayDiff<2>`] from the light to the diffuse surface where they land, the
//! elliptic [`Footprint`] each covers there, and the radiance estimate of seed 002 eq. 10 =
//! seed 000 eq. 5.14 over those footprints.
//!
//! # Tracing
//!
//! The photon differentials follow exactly the light paths of the caustic photon tracer
//! ([`crate::photon_tracer`]): the same walker ([`walk_light_path_with`]), stream and chunks, so
//! with the same seed a landing here is a caustic photon there (same position, same flux
//! Φ = β/N). Along the path the differential is
//!
//! * emitted with the differentials crate's [`emit`] (seed 002 eq. 1–6) from the light's
//!   [`emission_extent`](caustica_scene::light::Light::emission_extent) `(A_e, ω_e)` and the
//!   emission sample's normal;
//! * transferred onto every surface hit and reflected or refracted at every delta vertex with
//!   the lobe the walker sampled (`BsdfSample::flags`, relative IOR `1/eta`): on meshes with
//!   vertex normals by the Phong triangle model (eq. B.35–B.55), on meshes without by the flat
//!   triangle (eq. B.24–B.34), on analytic spheres by the exact sphere normal `N = (Q − c)/r`
//!   with `dN = dQ/r` (the tangent-plane transfer is first-order exact on the sphere and
//!   `dQ` is tangent), on disks by their plane (`dN = 0`);
//! * at each caustic landing (a non-delta surface reached through one or more delta vertices,
//!   L S+ D) turned into a footprint on the hit's tangent plane (eq. 4, 12).
//!
//! **The budget N_e.** Seed 002 eq. 5–6 size the initial vectors by the number `N_e` of photons
//! *emitted* from the light, so that their footprints tile `s² A_e` (and solid angles `s² ω_e`).
//! The caustic map is grown until it holds the requested number of landings, so `N_e` is only
//! known at the end: the paths are traced with the budget `N_e = 1` and, since every operation
//! of the first-order algebra is linear in the differential vectors, the landed vectors are
//! scaled afterwards by `1/√N_l`, `N_l = N · pmf_l` the expected number of the `N` emitted
//! paths that start at light `l` (light selection is proportional to power). The requested
//! photon count is therefore the number of caustic landings (as for `pm`'s caustic map); `N` the
//! light paths emitted to find them. Collapse is scale invariant, so nothing else changes.
//!
//! **Dropped photons.** A landing whose footprint has collapsed (`DiffError::CollapsedFootprint`,
//! seed 002 sec. 3.3) is dropped and counted; so is one whose differential could not be
//! propagated (ray parallel to a plane, total internal reflection of the differential where the
//! sampled lobe refracted, overflow, or a differential direction more than ~8° from the
//! direction the walker sampled — a shading normal the surface model does not reproduce).
//! Dropping loses their energy; the counts are in the render notes.
//!
//! # Estimate
//!
//! `L(x, ω) = Σ_p f_r(x, ω_p, ω) π K(|M_p (x − x_p)|) Φ_p / A_p` (eq. 10–12, Silverman's kernel,
//! [`Footprint::irradiance_at`]), over the footprints that contain `x`, arrived on the query's
//! side, lie on a surface whose normal is within ~25° of the query's (cos ≥ 0.9) and whose
//! tangent plane passes within the normal-distance threshold (seed 002 sec. 3.3; by default a
//! quarter of the footprint's gather radius) of `x` (the filter of eq. 12 ignores the normal
//! offset; these two tests keep footprints from leaking onto nearby surfaces of another
//! orientation, like the disc test of `pm`): [`FootprintFilter::weight`], the one rule of `pdm`
//! and `pds`. `pdm` gathers: footprints are bucketed by gather radius (powers of two) with one
//! k-d tree per bucket, queried within that bucket's largest radius, so a few huge footprints do
//! not slow every query. `pds` splats the same terms ([`crate::eye_map`]).

use crate::light_path::{
    LightEvent, LightScatter, LightVertex, LightVisitor, walk_light_path_with,
};
use crate::options::RenderOptions;
use crate::photon_tracer::trace_paths;
use crate::stats::RenderStats;
use crate::surface::Vertex;
use caustica_core::sampling::Sampler;
use caustica_core::{Ray, Spectrum, Vec3};
use caustica_density::kernel::{Dim, Kernel};
use caustica_density::radius_buckets::RadiusBuckets;
use caustica_differentials::{
    DiffError, EmissionBasis, EmissionBudget, FlatTriangle, Footprint, PhongTriangle, RayDiff,
    SurfaceHit, Transferred, emission_basis, emit_with_basis, emit_with_lengths,
    transfer_to_fixed_plane,
};
use caustica_scene::bsdf::{BsdfFlags, TransportMode};
use caustica_scene::shape::ShapeGeometry;
use caustica_scene::{Scene, SurfaceInteraction};

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

/// A caustic landing before the budget is known: its differential vectors for `N_e = 1`.
#[derive(Clone, Copy, Debug)]
pub struct Landing {
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
    pub dp: Option<[Vec3; 2]>,
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

/// Photon differentials of one caustic map and how they were made.
pub struct TracedDiffPhotons {
    /// Stored photons in path order.
    pub photons: Vec<DiffPhoton>,
    /// Light paths emitted (the N of Φ = β/N).
    pub paths: u64,
    /// Caustic landings found (stored + collapsed + failed).
    pub landings: usize,
    /// Landings dropped because their footprint collapsed.
    pub collapsed: u64,
    /// Landings dropped because the differential could not be propagated.
    pub failed: u64,
    pub stats: RenderStats,
    pub warning: Option<String>,
}

/// Traces light paths until `target` caustic landings (L S+ D) are found — the paths of
/// [`crate::photon_tracer::trace_photons`] with `MapKind::Caustic` and the same `stream` — and
/// returns their photon differentials' footprints for smoothing `smoothing` (seed 002's `s`).
/// Deterministic for a given seed whatever the thread count.
pub fn trace_photon_differentials(
    scene: &Scene,
    target: usize,
    smoothing: f32,
    stream: u64,
    opts: &RenderOptions,
) -> TracedDiffPhotons {
    // `PhotonOptions::validate` rejects a bad s; a caller that skipped it gets s = 1 and a warning.
    let (budget, bad_smoothing) = match unit_budget(smoothing) {
        Some(b) => (b, None),
        None => (
            unit_budget(1.0).expect("a budget of one photon with s = 1 is valid"),
            Some(format!(
                "smoothing s = {smoothing} is not a positive number; used s = 1"
            )),
        ),
    };
    let tracer = LandingTracer::new(scene, &budget);
    let (landings, paths, stats) =
        trace_paths(target, stream, opts, &mut |_| {}, |_, sampler, out, st| {
            tracer.trace(sampler, opts, out, st)
        });
    let (photons, collapsed, failed) = photons_from_landings(&landings, paths);
    let short = (landings.len() < target).then(|| {
        format!(
            "only {} caustic photon differentials found after {paths} light paths (requested {target}){}",
            landings.len(),
            if landings.is_empty() {
                ": no light reaches a diffuse surface through glass or mirrors"
            } else {
                ""
            }
        )
    });
    let warning = match (bad_smoothing, short) {
        (Some(a), Some(b)) => Some(format!("{a}; {b}")),
        (a, b) => a.or(b),
    };
    TracedDiffPhotons {
        photons,
        paths,
        landings: landings.len(),
        collapsed,
        failed,
        stats,
        warning,
    }
}

/// The budget of [`trace_photon_differentials`] and [`LandingTracer`] (`N_e = 1`, see the
/// module docs) for smoothing `s`, or `None` when `s` is not a positive number.
pub fn unit_budget(smoothing: f32) -> Option<EmissionBudget> {
    EmissionBudget::new(1, smoothing).ok()
}

/// Traces light paths as photon differentials for one budget (normally [`unit_budget`]): the
/// lengths of each light's initial vectors (eq. 5–6) are computed once here, not per photon,
/// and so is the basis (eq. 2–3) of each collimated light.
pub struct LandingTracer<'a> {
    scene: &'a Scene,
    /// Per light: the lengths and fixed basis of [`LightEmission`].
    lights: Vec<LightEmission>,
}

/// What every photon differential of one light shares.
#[derive(Clone, Copy, Debug)]
struct LightEmission {
    /// `(|D_u x|, |D_θ ω|)` (eq. 5–6), or why the light cannot emit photon differentials.
    lengths: Result<(f32, f32), DiffError>,
    /// For a collimated light: its direction, normal and their basis (eq. 2–3), used for every
    /// emitted ray with exactly that direction and normal.
    fixed: Option<(Vec3, Option<Vec3>, EmissionBasis)>,
}

impl<'a> LandingTracer<'a> {
    pub fn new(scene: &'a Scene, budget: &EmissionBudget) -> Self {
        let lights = scene
            .lights
            .iter()
            .map(|l| {
                let (area, solid_angle) = l.emission_extent();
                LightEmission {
                    lengths: budget.emission_lengths(area, solid_angle),
                    fixed: l
                        .fixed_emission_direction()
                        .and_then(|(d, n)| emission_basis(d, n).ok().map(|b| (d, n, b))),
                }
            })
            .collect();
        Self { scene, lights }
    }

    /// Traces one light path (the sampler positioned on it) and pushes its caustic landings
    /// with their photon differentials.
    pub fn trace(
        &self,
        sampler: &mut Sampler,
        opts: &RenderOptions,
        out: &mut Vec<Landing>,
        stats: &mut RenderStats,
    ) {
        let mut v = DiffVisitor {
            scene: self.scene,
            lights: &self.lights,
            out,
            emission: (Ray::new(Vec3::ZERO, Vec3::Z), None, 0),
            ray: None,
            pmf: 1.0,
        };
        walk_light_path_with(self.scene, sampler, opts, stats, &mut v);
    }
}

/// True for a vertex where a caustic photon lands: a non-delta surface reached through one or
/// more delta vertices (L S+ D), with a finite throughput. The one rule of both tracers below.
fn is_caustic_landing(lv: &LightVertex) -> bool {
    lv.v.bsdf.flags().is_smooth() && lv.after_specular_chain && lv.beta.is_finite()
}

/// The light paths [`trace_photon_differentials`] emits to find `target` caustic landings
/// with a given stream, found without differentials (see [`count_caustic_paths`]).
pub struct CausticPaths {
    /// `N`: the paths emitted (the N of Φ = β/N and of eq. 5–6).
    pub paths: u64,
    /// Caustic landings in them (`target` unless the scene yields fewer).
    pub landings: usize,
    /// The indices (ascending) of the paths with at least one landing, when recorded.
    pub landing_paths: Option<Vec<u64>>,
    pub stats: RenderStats,
}

/// Photon counts up to which photon differential splatting records the landing paths (8 bytes
/// per landing: ≤ 16 MB) so as to re-trace only those; above it, memory stays bounded and
/// every path is traced twice.
pub const RECORD_LANDING_PATHS: usize = 1 << 21;

/// The light paths [`trace_photon_differentials`] emits to find `target` caustic landings with
/// this `stream`, traced without differentials and without storing photons: photon
/// differential splatting must know their number `N` before the first splat, since the
/// footprints scale with `1/√N` (eq. 5–6). With `record` it also returns which paths landed,
/// so that only those need tracing again (8 bytes per landing). `progress` receives the
/// fraction of `target` found so far after each wave of paths.
pub fn count_caustic_paths(
    scene: &Scene,
    target: usize,
    stream: u64,
    opts: &RenderOptions,
    record: bool,
    progress: &mut dyn FnMut(f64),
) -> CausticPaths {
    let mut on_wave = |found: usize| progress(found as f64 / target.max(1) as f64);
    /// Pushes `record` once per caustic landing of the path.
    struct Count<'a, P> {
        out: &'a mut Vec<P>,
        record: P,
    }
    impl<P: Copy> LightVisitor for Count<'_, P> {
        fn event(&mut self, event: LightEvent, _: &mut Sampler, _: &mut RenderStats) {
            if let LightEvent::Vertex(lv) = event
                && is_caustic_landing(lv)
            {
                self.out.push(self.record);
            }
        }
        fn scatter(&mut self, sc: &LightScatter, _: &mut RenderStats) -> bool {
            sc.sample.flags.is_delta() // as DiffVisitor::scatter
        }
    }
    if record {
        let (mut found, paths, stats) = trace_paths(
            target,
            stream,
            opts,
            &mut on_wave,
            |path, sampler, out, st| {
                walk_light_path_with(scene, sampler, opts, st, &mut Count { out, record: path })
            },
        );
        let landings = found.len();
        found.dedup();
        return CausticPaths {
            paths,
            landings,
            landing_paths: Some(found),
            stats,
        };
    }
    // Too many to record: count only (a zero-sized record per landing).
    let (found, paths, stats) =
        trace_paths(target, stream, opts, &mut on_wave, |_, sampler, out, st| {
            walk_light_path_with(scene, sampler, opts, st, &mut Count { out, record: () })
        });
    CausticPaths {
        paths,
        landings: found.len(),
        landing_paths: None,
        stats,
    }
}

/// Per-path state: the emission sample and the differential along the current ray.
struct DiffVisitor<'a> {
    scene: &'a Scene,
    /// [`LandingTracer::lights`].
    lights: &'a [LightEmission],
    out: &'a mut Vec<Landing>,
    /// The emission sample's ray and normal and the light's index, kept until the emitted
    /// differential is first needed (most paths never reach a delta surface, so their
    /// differentials are never computed).
    emission: (Ray, Option<Vec3>, usize),
    /// The differential of the ray being traced (origin at the last vertex, direction the
    /// sampled one); `None` until computed.
    ray: Option<Result<RayDiff<2>, DiffError>>,
    pmf: f32,
}

impl DiffVisitor<'_> {
    /// The differential of the ray being traced (the emitted one computed on first use).
    fn ray(&mut self) -> Result<RayDiff<2>, DiffError> {
        *self.ray.get_or_insert_with(|| {
            let (ray, normal, light) = self.emission;
            let Some(le) = self.lights.get(light) else {
                return Err(DiffError::NonFinite);
            };
            match le.fixed {
                // The light's one basis, for the exact direction and normal it was made from.
                Some((d, n, b)) if d == ray.d && n == normal => {
                    emit_with_basis(ray.o, &b, le.lengths?)
                }
                _ => emit_with_lengths(ray.o, ray.d, normal, le.lengths?),
            }
        })
    }

    /// The differential transferred onto the surface at `si`, with the normal that scatters it.
    fn hit_at(&mut self, si: &SurfaceInteraction) -> Result<SurfaceHit<2>, DiffError> {
        surface_hit(self.scene, si, &self.ray()?)
    }

    /// The differential transferred onto the plane where the photon lands at `si`: only the
    /// position and direction differentials, which the footprint needs (not the normal and
    /// barycentrics of [`Self::hit_at`], which only scattering needs).
    fn landing_at(&mut self, si: &SurfaceInteraction) -> Result<Transferred<2>, DiffError> {
        // The plane through the hit with the geometric normal: a flat or Phong triangle's own
        // plane (eq. B.24–B.29, B.36–B.40; the transfer depends on neither the normal's sign nor
        // its length), a sphere's or disk's tangent plane.
        transfer_to_fixed_plane(&self.ray()?, si.p, si.ng)
    }
}

/// Cosine between the differential's scattered direction and the walker's below which the
/// propagation counts as failed (~8°).
const DIRECTION_COS: f32 = 0.99;

impl LightVisitor for DiffVisitor<'_> {
    fn event(&mut self, event: LightEvent, _: &mut Sampler, _: &mut RenderStats) {
        match event {
            LightEvent::Start(start) => {
                let es = start.emission;
                self.pmf = start.pmf;
                self.emission = (start.ray, es.normal, start.light);
                self.ray = None;
            }
            LightEvent::Vertex(lv) => {
                // Non-finite throughputs are skipped (the photon tracer counts them).
                if !is_caustic_landing(lv) {
                    return;
                }
                let dp = self.landing_at(&lv.v.si).ok().map(|t| t.ray.dp);
                let ng = lv.v.si.ng;
                self.out.push(Landing {
                    p: lv.v.si.p,
                    wi: lv.wo,
                    n: if ng.dot(lv.wo) >= 0.0 { ng } else { -ng },
                    beta: lv.beta,
                    depth: lv.depth.min(u16::MAX as u32) as u16,
                    pmf: self.pmf,
                    dp,
                });
            }
        }
    }

    fn scatter(&mut self, sc: &LightScatter, _: &mut RenderStats) -> bool {
        let flags = sc.sample.flags;
        if !flags.is_delta() {
            // After a non-delta bounce no later vertex can receive caustic light (L S+ D).
            return false;
        }
        let eta = sc.sample.eta;
        let out = self.hit_at(&sc.v.si).and_then(|h| {
            let out = if flags.intersects(BsdfFlags::TRANSMISSION) {
                h.refract(1.0 / eta)? // eq. B.19–B.23 take n_incident / n_transmitted
            } else {
                h.reflect()? // eq. B.17–B.18
            };
            follow(out, sc.v, sc.wi)
        });
        self.ray = Some(out);
        true
    }
}

/// The scattered differential re-anchored on the walker's path: origin at the hit, direction
/// the sampled one, `dv` made perpendicular to it (eq. B.1b keeps `v · dv = 0`). An error if the
/// directions disagree by more than [`DIRECTION_COS`].
fn follow(out: RayDiff<2>, v: &Vertex, wi: Vec3) -> Result<RayDiff<2>, DiffError> {
    let cos = out.v.dot(wi);
    if cos.is_nan() || cos < DIRECTION_COS {
        return Err(DiffError::NonFinite);
    }
    let dv = out.dv.map(|d| d - wi * wi.dot(d));
    let r = RayDiff::new(v.si.p, wi, out.dp, dv);
    if r.is_finite() {
        Ok(r)
    } else {
        Err(DiffError::NonFinite)
    }
}

/// Transfers `ray` onto the surface at `si` with the surface model of the hit shape (see the
/// module docs): Phong or flat triangles, the sphere's curvature, the disk's plane.
fn surface_hit(
    scene: &Scene,
    si: &SurfaceInteraction,
    ray: &RayDiff<2>,
) -> Result<SurfaceHit<2>, DiffError> {
    if let Some(tri) = scene.geometry.triangle_vertices(si) {
        return match tri.n {
            Some(n) => PhongTriangle { q: tri.p, n }.hit(ray),
            None => FlatTriangle { q: tri.p }.hit(ray),
        };
    }
    match scene
        .geometry
        .shapes
        .get(si.shape as usize)
        .map(|s| &s.geometry)
    {
        Some(ShapeGeometry::Sphere(s)) => {
            let n_out = (si.p - s.center) / s.radius;
            let inv_r = 1.0 / s.radius;
            tangent_plane_hit(ray, si.p, n_out, |dq| dq * inv_r)
        }
        // Disks (and, defensively, a bad shape index): the tangent plane, dN = 0.
        _ => tangent_plane_hit(ray, si.p, si.ng, |_| Vec3::ZERO),
    }
}

/// Transfer onto the plane through `p` with normal `n` (unit, any orientation) whose normal
/// changes with the hit point as `dN = dn(dQ)` for the orientation `n`.
fn tangent_plane_hit(
    ray: &RayDiff<2>,
    p: Vec3,
    n: Vec3,
    dn: impl Fn(Vec3) -> Vec3,
) -> Result<SurfaceHit<2>, DiffError> {
    let t = transfer_to_fixed_plane(ray, p, n)?;
    // Orientation of eq. B.30: V · N < 0; dN flips with N.
    let sign = if n.dot(ray.v) > 0.0 { -1.0 } else { 1.0 };
    let normal = sign * n;
    let dnormal = t.ray.dp.map(|dq| sign * dn(dq));
    if dnormal.iter().any(|d| !d.is_finite()) {
        return Err(DiffError::NonFinite);
    }
    Ok(SurfaceHit {
        ray: t.ray,
        s: t.s,
        ds: t.ds,
        geometric_normal: normal,
        dgeometric_normal: dnormal,
        normal,
        dnormal,
        barycentrics: [0.0; 3],
        dbarycentrics: [[0.0; 3]; 2],
    })
}

/// Footprints whose surface normal is farther than this cosine from the query's are ignored.
const NORMAL_COS: f32 = 0.9;

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

impl Default for FootprintFilter {
    fn default() -> Self {
        Self {
            kernel: Kernel::Silverman,
            normal_distance: 0.25,
        }
    }
}

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
        let centres: Vec<Vec3> = photons.iter().map(|p| p.footprint.center()).collect();
        let radii: Vec<f32> = photons
            .iter()
            .map(|p| p.footprint.gather_radius())
            .collect();
        let buckets = RadiusBuckets::build(&centres, &radii);
        Self {
            photons,
            paths: traced.paths,
            landings: traced.landings,
            collapsed: traced.collapsed,
            failed: traced.failed,
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
        let wo_world = v.frame.to_world(v.wo);
        let ng = v.si.ng;
        let n = if ng.dot(wo_world) >= 0.0 { ng } else { -ng };
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
