//! Photon differentials along the walker's light paths: emission (seed 002 eq. 1–6), transfer,
//! reflection and refraction at delta vertices (seed 000 app. B) and the landing on the first
//! non-delta surface, for any number of differential parameters (see the module docs of
//! [`super`]).

use super::footprint::{DiffPhoton, Landing, SweepColumn, photons_from_landings};
use crate::options::{EmissionStrategy, FootprintSettings, RenderOptions, Smoothing};
use crate::photon::adaptive::{chain_steps, run_chains};
use crate::photon::plan::{PathStream, PhotonBudget, trace_budget};
use crate::photon::tracer::{NO_CAUSTIC_PATHS, shortfall};
use crate::photon::visible_points::VisiblePoints;
use crate::stats::RenderStats;
use crate::transport::Emission;
use crate::transport::light_walk::{
    LightEvent, LightMediumVertex, LightScatter, LightStart, LightVertex, LightVisitor,
    walk_light_path_at,
};
use crate::transport::limits::PathLimits;
use crate::transport::time::PathTime;
use crate::transport::vertex::Vertex;
use caustica_core::sampling::Sampler;
use caustica_core::spectral::visible_pdf;
use caustica_core::{Ray, Vec3};
use caustica_differentials::{
    DiffError, EmissionBasis, EmissionBudget, FlatTriangle, PhongTriangle, RayDiff, SurfaceHit,
    Transferred, TriangleMotion, emission_basis, emit_with_basis, emit_with_lengths,
    transfer_to_fixed_plane,
};
use caustica_scene::bsdf::BsdfFlags;
use caustica_scene::light::EmissionDensity;
use caustica_scene::phase::PhaseSample;
use caustica_scene::shape::ShapeGeometry;
use caustica_scene::{Scene, SurfaceInteraction};

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
    /// Footprints widened by the minimum semi-axis.
    pub widened: u64,
    pub stats: RenderStats,
    pub warning: Option<String>,
    /// A fact for the render notes (the adaptive sampler's acceptance and normalisation).
    pub note: Option<String>,
}

impl TracedDiffPhotons {
    /// `photons` from `paths` light paths with nothing dropped, widened, noted or warned
    /// about: a map built from given footprints (tests, benchmarks).
    pub fn given(photons: Vec<DiffPhoton>, paths: u64) -> Self {
        Self {
            landings: photons.len(),
            photons,
            paths,
            collapsed: 0,
            failed: 0,
            widened: 0,
            stats: RenderStats::default(),
            warning: None,
            note: None,
        }
    }
}

/// Traces the light paths of `stream` under `budget` — until that many caustic landings
/// (L S+ D) are found, the paths of [`crate::photon::tracer::trace_photons`] with
/// `MapKind::Caustic` and the same `stream`, or exactly `N_e` paths — and returns their photon
/// differentials' footprints for smoothing `smoothing` (seed 002's `s`). `progress(fraction)`
/// after each wave. Deterministic for a given seed whatever the thread count.
pub fn trace_photon_differentials(
    scene: &Scene,
    budget: PhotonBudget,
    smoothing: Smoothing,
    stream: u64,
    opts: &RenderOptions,
    progress: &mut dyn FnMut(f64) -> bool,
) -> TracedDiffPhotons {
    let tracer = LandingTracer::new(scene, &unit_budget(smoothing))
        .with_time(&opts.photons.footprints, scene)
        .with_wavelength(&opts.photons.footprints, scene)
        .with_emission(opts.photons.emission.caustic_rule());
    let stream = PathStream::new(opts, stream);
    // Visibility-driven adaptive photon tracing: chains toward landings the camera sees.
    let visible = (opts.photons.emission == EmissionStrategy::Adaptive)
        .then(|| VisiblePoints::from_camera(scene, opts));
    let visible = visible.as_ref();
    // Two parameters (emission), or three with time (seed 003) or wavelength.
    let floor = opts.photons.footprints.min_semi_axis;
    let (made, landings, paths, stats, note) = if tracer.has_third_column() {
        let (landings, paths, stats, note) =
            trace_landings::<TEMPORAL_PARAMS>(&tracer, budget, &stream, opts, visible, progress);
        let made = photons_from_landings(&landings, paths, tracer.sweep_column(), floor);
        (made, landings.len(), paths, stats, note)
    } else {
        let (landings, paths, stats, note) =
            trace_landings::<EMISSION_PARAMS>(&tracer, budget, &stream, opts, visible, progress);
        let made = photons_from_landings(&landings, paths, tracer.sweep_column(), floor);
        (made, landings.len(), paths, stats, note)
    };
    // Adaptive tracing stores repeated states once: its landings are not the budget's count.
    let budget_check = if visible.is_some() {
        PhotonBudget::Paths(paths)
    } else {
        budget
    };
    let warning = shortfall("caustic", landings, paths, budget_check).map(|w| {
        if landings == 0 {
            format!("{w}: {NO_CAUSTIC_PATHS}")
        } else {
            w
        }
    });
    TracedDiffPhotons {
        photons: made.photons,
        paths,
        landings,
        collapsed: made.collapsed,
        failed: made.failed,
        widened: made.widened,
        stats,
        warning,
        note,
    }
}

/// The caustic landings of `budget`'s light paths, the path count N, the statistics and, for
/// adaptive photon tracing (`visible` given), its note: the chains' states with their landings'
/// throughputs times the repeat count, and N the chains' equivalent base paths
/// ([`crate::photon::adaptive`]).
fn trace_landings<const N: usize>(
    tracer: &LandingTracer,
    budget: PhotonBudget,
    stream: &PathStream,
    opts: &RenderOptions,
    visible: Option<&VisiblePoints>,
    progress: &mut dyn FnMut(f64) -> bool,
) -> (Vec<Landing<N>>, u64, RenderStats, Option<String>) {
    let limits = opts.limits;
    let Some(visible) = visible else {
        let (landings, paths, stats) = trace_budget(
            budget,
            stream,
            opts.photons.first_path,
            progress,
            |_, sm, out, st| tracer.trace::<N>(sm, &limits, out, st),
        );
        return (landings, paths, stats, None);
    };
    let run = run_chains(
        stream,
        opts.photons.first_path,
        chain_steps(budget),
        false,
        &|ls: &[Landing<N>]| ls.iter().any(|l| visible.near(l.p)),
        &|sm, out, st| tracer.trace::<N>(sm, &limits, out, st),
    );
    progress(1.0);
    let landings = run.weighted_records(|l, count| Landing {
        beta: l.beta * count,
        ..*l
    });
    (landings, run.paths(), run.stats, Some(run.note(visible)))
}

/// The differential parameters of a photon at emission: the two of seed 002 eq. 1–6 (position
/// on the light and direction, or the two directions of a point light). Temporal photon
/// differentials (seed 003) trace `EMISSION_PARAMS + 1`.
pub const EMISSION_PARAMS: usize = 2;

/// The differential parameters of a temporal photon differential: emission's two and time
/// (seed 003 eq. 1–2: the third columns `D_t x`, `D_t ω`). Wavelength photon differentials use
/// the same count, with wavelength as the third parameter.
pub const TEMPORAL_PARAMS: usize = EMISSION_PARAMS + 1;

/// The budget of [`trace_photon_differentials`] and [`LandingTracer`] (`N_e = 1`, see the
/// module docs) for smoothing `s`.
pub fn unit_budget(smoothing: Smoothing) -> EmissionBudget {
    EmissionBudget::new(1, smoothing.get()).expect("one photon and a valid smoothing parameter")
}

/// Traces light paths as photon differentials for one budget (normally [`unit_budget`]): the
/// lengths of each light's initial vectors (eq. 5–6) are computed once here, not per photon,
/// and so is the basis (eq. 2–3) of each collimated light.
pub struct LandingTracer<'a> {
    pub(crate) scene: &'a Scene,
    /// Per light: the lengths and fixed basis of [`LightEmission`].
    pub(crate) lights: Vec<LightEmission>,
    /// When the light paths happen.
    pub(crate) time: PathTime,
    /// Seed 003's exposure e (frames): the time differential's offset, `D_t q = e (q_{f+1} −
    /// q_f)` (eq. 5); 0 for ordinary photon differentials.
    pub(crate) exposure: f32,
    /// Where the traced instant lies on the shutter (temporal photon differentials).
    pub(crate) align: crate::options::ShutterAlign,
    /// How the light paths are emitted (uniform unless [`Self::with_emission`]).
    pub(crate) emission: Emission,
    /// The smoothing s of the budget the tracer was made with.
    smoothing: f32,
    /// Wavelength photon differentials: `K s` of `Δλ = K s / (N_e p(λ))`
    /// ([`FootprintSettings::wavelength_spread`]); the third column is then wavelength.
    wavelength: Option<f32>,
}

/// What every photon differential of one light shares.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LightEmission {
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
        Self {
            scene,
            lights,
            time: PathTime::Shutter,
            exposure: 0.0,
            align: crate::options::ShutterAlign::Forward,
            emission: Emission::Uniform,
            smoothing: budget.smoothing(),
            wavelength: None,
        }
    }

    /// The tracer with wavelength photon differentials when `settings` ask for them and the
    /// scene is spectral (in RGB mode nothing disperses: no third column).
    pub fn with_wavelength(mut self, settings: &FootprintSettings, scene: &Scene) -> Self {
        self.wavelength = settings
            .wavelength_spread
            .filter(|_| scene.spectral)
            .map(|k| k * self.smoothing);
        self
    }

    /// True if the differentials carry a third column (time or wavelength).
    pub fn has_third_column(&self) -> bool {
        self.is_temporal() || self.wavelength.is_some()
    }

    /// What the third column is, for [`photons_from_landings`].
    pub fn sweep_column(&self) -> SweepColumn {
        if self.wavelength.is_some() {
            SweepColumn::Wavelength
        } else {
            SweepColumn::Time(self.align)
        }
    }

    /// The tracer emitting its light paths by `emission` (guided emission shrinks the photon
    /// differentials' initial vectors where it emits densely, see
    /// [`caustica_scene::light::projection_map`]).
    pub fn with_emission(mut self, emission: Emission) -> Self {
        self.emission = emission;
        self
    }

    /// The tracer with the time rule of `settings`: temporal photon differentials trace at the
    /// shutter's opening with the shutter's length as exposure (only where the scene moves;
    /// a static scene gives ordinary photon differentials exactly), else photons at times
    /// uniform over the shutter.
    pub fn with_time(mut self, settings: &FootprintSettings, scene: &Scene) -> Self {
        self.time = settings.path_time();
        self.exposure = if settings.temporal && scene.has_motion() {
            scene.shutter.length
        } else {
            0.0
        };
        self.align = settings.sweep.align;
        self
    }

    /// The shutter alignment photons are made with ([`photons_from_landings`]).
    pub fn align(&self) -> crate::options::ShutterAlign {
        self.align
    }

    /// True if the differentials carry a time column.
    pub fn is_temporal(&self) -> bool {
        self.exposure > 0.0
    }

    /// Traces one light path (the sampler positioned on it) and pushes its caustic landings
    /// with their photon differentials in `N ≥ 2` parameters (the emission's two first).
    pub fn trace<const N: usize>(
        &self,
        sampler: &mut Sampler,
        limits: &PathLimits,
        out: &mut Vec<Landing<N>>,
        stats: &mut RenderStats,
    ) {
        let mut v = DiffVisitor {
            ray: DiffRay::new(self.scene, &self.lights)
                .with_exposure(self.exposure)
                .with_wavelength(self.wavelength.is_some()),
            out,
            wavelength: self.wavelength,
        };
        walk_light_path_at(
            self.scene,
            sampler,
            limits,
            stats,
            &mut v,
            self.time,
            self.emission,
        );
    }
}

/// True for a vertex where a caustic photon lands: a non-delta surface reached through one or
/// more delta vertices (L S+ D), with a finite throughput. The one rule of the tracer
/// and of the counting pass ([`super::counting`]).
pub(crate) fn is_caustic_landing(lv: &LightVertex) -> bool {
    lv.is_caustic() && lv.beta.is_finite()
}

/// Per-path state of the caustic tracer: the differential along the current ray.
struct DiffVisitor<'a, const N: usize> {
    ray: DiffRay<'a, N>,
    out: &'a mut Vec<Landing<N>>,
    /// [`LandingTracer::wavelength`].
    wavelength: Option<f32>,
}

/// The photon differential along a light path, shared by the caustic tracer and the volume
/// tracer ([`super::volume_trace`]): the emission sample, kept until the differential is first
/// needed, and the differential of the ray being traced.
pub(crate) struct DiffRay<'a, const N: usize> {
    scene: &'a Scene,
    /// [`LandingTracer::lights`].
    lights: &'a [LightEmission],
    /// The emission sample's ray and normal and the light's index, kept until the emitted
    /// differential is first needed (most caustic paths never reach a delta surface, so their
    /// differentials are never computed).
    emission: (Ray, Option<Vec3>, usize),
    /// The emission's relative density (guided emission): the initial vectors shrink by it.
    density: EmissionDensity,
    /// The differential of the ray being traced (origin at the last vertex, direction the
    /// sampled one); `None` until computed.
    pub(crate) ray: Option<Result<RayDiff<N>, DiffError>>,
    /// Selection probability of the path's light.
    pub(crate) pmf: f32,
    /// Exposure (frames) scaling the time column (`N − 1`) of moving triangles; 0: none.
    exposure: f32,
    /// True if column `N − 1` is wavelength (nm): dispersive refractions feed it.
    wavelength: bool,
}

impl<'a, const N: usize> DiffRay<'a, N> {
    pub(crate) fn new(scene: &'a Scene, lights: &'a [LightEmission]) -> Self {
        Self {
            scene,
            lights,
            emission: (Ray::new(Vec3::ZERO, Vec3::Z), None, 0),
            density: EmissionDensity::UNIFORM,
            ray: None,
            pmf: 1.0,
            exposure: 0.0,
            wavelength: false,
        }
    }

    /// With the last of the `N` parameters wavelength (nm): dispersive interfaces give it
    /// `∂η/∂λ` ([`caustica_differentials::refract_dispersive`]).
    pub(crate) fn with_wavelength(mut self, on: bool) -> Self {
        self.wavelength = on && N > EMISSION_PARAMS;
        self
    }

    /// With the last of the `N` parameters time over `exposure` frames (seed 003 eq. 5).
    pub(crate) fn with_exposure(mut self, exposure: f32) -> Self {
        self.exposure = exposure;
        self
    }

    /// A new path starts at `start`.
    pub(crate) fn start(&mut self, start: &LightStart) {
        self.pmf = start.pmf;
        self.emission = (start.ray, start.emission.normal, start.light);
        self.density = start.density;
        self.ray = None;
    }

    /// The differential of the ray being traced (the emitted one computed on first use).
    pub(crate) fn ray(&mut self) -> Result<RayDiff<N>, DiffError> {
        *self.ray.get_or_insert_with(|| {
            let (ray, normal, light) = self.emission;
            let Some(le) = self.lights.get(light) else {
                return Err(DiffError::NonFinite);
            };
            let lengths = guided_lengths(le.lengths?, self.density);
            let emitted = match le.fixed {
                // The light's one basis, for the exact direction and normal it was made from.
                Some((d, n, b)) if d == ray.d && n == normal => emit_with_basis(ray.o, &b, lengths),
                _ => emit_with_lengths(ray.o, ray.d, normal, lengths),
            };
            emitted.map(|r| r.widen::<N>())
        })
    }

    /// The differential transferred onto the surface at `si`, with the normal that scatters it.
    fn hit_at(&mut self, si: &SurfaceInteraction) -> Result<SurfaceHit<N>, DiffError> {
        surface_hit(self.scene, si, &self.ray()?, self.exposure)
    }

    /// The differential transferred onto the plane where the photon lands at `si`: only the
    /// position and direction differentials, which the footprint needs (not the normal and
    /// barycentrics of [`Self::hit_at`], which only scattering needs).
    pub(crate) fn landing_at(
        &mut self,
        si: &SurfaceInteraction,
    ) -> Result<Transferred<N>, DiffError> {
        // The plane through the hit with the geometric normal: a flat or Phong triangle's own
        // plane (eq. B.24–B.29, B.36–B.40; the transfer depends on neither the normal's sign nor
        // its length), a sphere's or disk's tangent plane.
        transfer_to_fixed_plane(&self.ray()?, si.p, si.ng)
    }

    /// The differential after the delta scattering `sc` (reflection eq. B.17–B.18 or
    /// refraction eq. B.19–B.23 with the sampled lobe), re-anchored on the walker's path.
    pub(crate) fn scatter_delta(&mut self, sc: &LightScatter) {
        let flags = sc.sample.flags;
        let eta = sc.sample.eta;
        let deta = if self.wavelength && flags.intersects(BsdfFlags::TRANSMISSION) {
            self.dispersion_column(sc)
        } else {
            None
        };
        let out = self.hit_at(&sc.v.si).and_then(|h| {
            let out = if let Some(deta) = deta {
                h.refract_dispersive(1.0 / eta, &deta)?
            } else if flags.intersects(BsdfFlags::TRANSMISSION) {
                h.refract(1.0 / eta)? // eq. B.19–B.23 take n_incident / n_transmitted
            } else {
                h.reflect()? // eq. B.17–B.18
            };
            follow(out, sc.v, sc.wi)
        });
        self.ray = Some(out);
    }
}

impl<const N: usize> DiffRay<'_, N> {
    /// `∂η/∂θ` of a refraction at a dispersive interface for the relative IOR the differential
    /// refracts with, `η = n_incident / n_transmitted = 1 / sample.eta`, with wavelength the last
    /// parameter; `None` where nothing disperses (no dispersion law, or RGB lanes). The glass's
    /// law gives n(λ) at the hero wavelength the walker refracted with; entering (the
    /// dielectric's convention: `wo` on the +z side) `η = 1/n`, `∂η/∂λ = −n′/n²`; leaving
    /// `η = n`, `∂η/∂λ = n′`.
    fn dispersion_column(&self, sc: &LightScatter) -> Option<[f32; N]> {
        let material = self.scene.materials.get(sc.v.si.material as usize)?;
        let law = material.dispersion()?;
        let hero = sc.v.channels.hero()?;
        let (n, dn) = (law.ior(hero), law.dior_dlambda(hero));
        let deta = if sc.v.wo.z > 0.0 { -dn / (n * n) } else { dn };
        let mut col = [0.0; N];
        col[N - 1] = deta;
        Some(col)
    }
}

/// The initial lengths `(|D_u x|, |D_θ ω|)` of eq. 5–6 for a photon emitted with relative
/// density `density` (guided emission): `N_e` photons at `p_rel` times uniform density stand
/// for `p_rel` times smaller shares, the origins' share shrinking with `p_pos` and the
/// directions' with `p_dir` (`p_rel = p_pos p_dir`), so each length is divided by the square
/// root of its density ([`caustica_scene::light::projection_map`]). Uniform emission: unchanged.
#[inline]
pub(crate) fn guided_lengths((lx, lw): (f32, f32), density: EmissionDensity) -> (f32, f32) {
    if density == EmissionDensity::UNIFORM {
        return (lx, lw);
    }
    (lx / density.pos.sqrt(), lw / density.dir.sqrt())
}

/// Cosine between the differential's scattered direction and the walker's below which the
/// propagation counts as failed (~8°).
const DIRECTION_COS: f32 = 0.99;

impl<const N: usize> LightVisitor for DiffVisitor<'_, N> {
    fn event(&mut self, event: LightEvent, _: &mut Sampler, _: &mut RenderStats) {
        match event {
            LightEvent::Start(start) => self.ray.start(start),
            LightEvent::Medium(_) => {}
            LightEvent::Vertex(lv) => {
                // Non-finite throughputs are skipped (the photon tracer counts them).
                if !is_caustic_landing(lv) {
                    return;
                }
                let mut dp = self.ray.landing_at(&lv.v.si).ok().map(|t| t.ray.dp);
                // Wavelength photon differentials: D_λ x (m/nm) times K s / p(λ), the photon's
                // share of the spectrum for N_e = 1 (`photons_from_landings` divides by N_e).
                if let (Some(ks), Some(dp), Some(hero)) =
                    (self.wavelength, dp.as_mut(), lv.v.channels.hero())
                {
                    dp[N - 1] *= ks / visible_pdf(hero);
                }
                self.out.push(Landing {
                    p: lv.v.si.p,
                    wi: lv.wo,
                    n: lv.v.si.ng_toward(lv.wo),
                    // Linear sRGB, as every stored photon (`Channels::to_rgb`).
                    beta: lv.v.channels.to_rgb(lv.beta),
                    depth: lv.depth.min(u16::MAX as u32) as u16,
                    pmf: self.ray.pmf,
                    dp,
                });
            }
        }
    }

    fn scatter_in_medium(&mut self, _: &LightMediumVertex, _: &PhaseSample) -> bool {
        false // not delta: no later vertex receives caustic light
    }

    fn scatter(&mut self, sc: &LightScatter, _: &mut RenderStats) -> bool {
        if !sc.keeps_caustic() {
            return false;
        }
        self.ray.scatter_delta(sc);
        true
    }
}

/// The scattered differential re-anchored on the walker's path: origin at the hit, direction
/// the sampled one, `dv` made perpendicular to it (eq. B.1b keeps `v · dv = 0`). An error if the
/// directions disagree by more than [`DIRECTION_COS`].
fn follow<const N: usize>(out: RayDiff<N>, v: &Vertex, wi: Vec3) -> Result<RayDiff<N>, DiffError> {
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
///
/// With `exposure > 0` and `N ≥ 3`, the last parameter is time: a moving triangle's vertices
/// and vertex normals get `D_t Q_k = e (q_{k,f+1} − q_{k,f})` and `D_t N_k = e (N_{k,f+1} −
/// N_{k,f})` (seed 003 eq. 5, the forward difference of the frame, backward on the last; the
/// normals' raw difference is the exact derivative of the linearly interpolated normals that
/// eq. B.42 then normalises, where seed 000 Q-T6 suggests projecting it), and the transfer is
/// eq. B.34 / B.37–B.51 with those columns (`hit_moving`). The emission columns see no motion
/// (vertices do not depend on u, v).
fn surface_hit<const N: usize>(
    scene: &Scene,
    si: &SurfaceInteraction,
    ray: &RayDiff<N>,
    exposure: f32,
) -> Result<SurfaceHit<N>, DiffError> {
    if let Some(tri) = scene.geometry.triangle_vertices(si) {
        if exposure > 0.0
            && N > EMISSION_PARAMS
            && let Some(vel) = scene.geometry.triangle_velocities(si)
            && vel.p != [Vec3::ZERO; 3]
        {
            let mut motion = TriangleMotion::<N>::stationary();
            for k in 0..3 {
                motion.dq[k][N - 1] = vel.p[k] * exposure;
                if let Some(dn) = vel.n {
                    motion.dn[k][N - 1] = dn[k] * exposure;
                }
            }
            return match tri.n {
                Some(n) => PhongTriangle { q: tri.p, n }.hit_moving(ray, &motion),
                None => FlatTriangle { q: tri.p }.hit_moving(ray, &motion),
            };
        }
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
fn tangent_plane_hit<const N: usize>(
    ray: &RayDiff<N>,
    p: Vec3,
    n: Vec3,
    dn: impl Fn(Vec3) -> Vec3,
) -> Result<SurfaceHit<N>, DiffError> {
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
        dbarycentrics: [[0.0; 3]; N],
    })
}
