//! Photon differentials for caustics (seed 002 sec. 3; seed 000 ch. 5): caustic photons that
//! carry a first-order [`RayDiff`] from the light to the diffuse surface where they land, the
//! elliptic [`Footprint`] each covers there, and the radiance estimate of seed 002 eq. 10 =
//! seed 000 eq. 5.14 over those footprints.
//!
//! # Tracing
//!
//! The photon differentials follow exactly the light paths of the caustic photon tracer
//! ([`crate::photon::tracer`]): the same walker ([`walk_light_path_with`]), stream and chunks, so
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
//! **Minimum footprint** (`FootprintSettings::min_semi_axis`, `--min-footprint`, off by
//! default as in seed 002). Near a caustic fold a footprint's area `|D_u x × D_v x|` goes to zero
//! and its irradiance `Φ/A` to infinity wherever it meets an eye point: a firefly. With a floor
//! every principal semi-axis is raised to it (`Footprint::widened`; the flux is kept, so the
//! estimate is still normalised) and collapsed landings are rescued instead of dropped; the
//! progressive methods shrink the floor with the smoothing, so it vanishes in the limit.
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
//! not slow every query. `pds` splats the same terms ([`crate::photon::eye_map`] and the eye-splat driver).
//!
//! # Files
//!
//! * [`trace`] — photon differentials along the walker's light paths ([`LandingTracer`],
//!   [`trace_photon_differentials`]), generic in the number of differential parameters (the two
//!   of emission; time adds a third).
//! * [`footprint`] — a landing's footprint ([`DiffPhoton`], [`photons_from_landings`]) and
//!   [`FootprintFilter`], the one rule for a footprint's weight at a point.
//! * [`map`] — [`PdmMap`], the gathering estimate of `pdm`.
//! * [`counting`] — [`count_caustic_paths`], the light paths that yield a number of landings
//!   (`pds` must know them before its first splat).

pub mod counting;
pub mod footprint;
pub mod map;
pub mod trace;
pub mod volume_trace;

pub use counting::{CausticPaths, RECORD_LANDING_PATHS, count_adaptive, count_caustic_paths};
pub use footprint::{
    DiffPhoton, FootprintFilter, Landing, MadePhotons, SweepColumn, photons_from_landings,
    widened_note,
};
pub use map::PdmMap;
pub use trace::{
    EMISSION_PARAMS, LandingTracer, TEMPORAL_PARAMS, TracedDiffPhotons, trace_photon_differentials,
    unit_budget,
};
