//! The photon tracer shared by every photon method.
//!
//! Photons are energy packets (seed 001 ch. 2): a light path emitted with throughput β (W, see
//! [`crate::transport::light_walk`]) deposits at each non-delta surface it reaches a photon of flux
//! Φ = β / N, where N is the number of paths emitted for that map. The sum of the fluxes of the
//! photons in a surface region estimates the flux incident on it, so a density estimate of Φ
//! per area gives irradiance (W/m²), and Σ f_r Φ / area reflected radiance (W/m²/sr), eq. 3.1–3.2
//! of seed 000.
//!
//! Paths are numbered and traced in fixed chunks ([`crate::photon::plan`]) whose photons are
//! concatenated in path order, so the maps depend on the seed only, not on the thread count.

use crate::options::EmissionStrategy;
use crate::options::RenderOptions;
use crate::photon::adaptive::{chain_steps, run_chains};
use crate::photon::plan::{PathStream, PhotonBudget, trace_budget};
use crate::photon::visible_points::VisiblePoints;
use crate::stats::RenderStats;
use crate::transport::Emission;
use crate::transport::light_walk::{
    LightEvent, LightMediumVertex, LightScatter, LightVisitor, walk_light_path_at,
};
use caustica_core::sampling::Sampler;
use caustica_core::{Spectrum, Vec3};
use caustica_scene::Scene;

/// A stored photon.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Photon {
    /// Hit point (m).
    pub p: Vec3,
    /// Unit direction toward where the photon came from (away from the surface, pbrt's ωi).
    pub wi: Vec3,
    /// Geometric normal at the hit, on the side the photon arrived from (unit).
    pub n: Vec3,
    /// Flux (W): path throughput divided by the number of emitted paths.
    pub flux: Spectrum,
    /// Edges from the light (1 = direct illumination).
    pub depth: u16,
    /// True for caustic photons: every earlier scattering vertex was delta, L S+ D.
    pub caustic: bool,
}

/// Which photons a tracing pass keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapKind {
    /// Paths L S+ D only.
    Caustic,
    /// Every non-delta hit, L (S|D)* D.
    Global,
    /// Every real scattering event in a participating medium, L (S|D|M)* M (seed 000 sec.
    /// 8.2: position, incident direction and flux, `n` zero).
    Volume,
}

impl MapKind {
    /// The emission rule of this map's light paths: `--emission` for caustic photons, uniform
    /// for the others (guided emission aims at specular surfaces; a global or volume map needs
    /// every direction).
    pub fn emission(self, opts: &RenderOptions) -> Emission {
        match self {
            MapKind::Caustic => opts.photons.emission.caustic_rule(),
            MapKind::Global | MapKind::Volume => Emission::Uniform,
        }
    }
}

/// Photons of one map and how they were made.
pub struct TracedPhotons {
    /// Photons in path order, fluxes already divided by `paths`.
    pub photons: Vec<Photon>,
    /// Light paths emitted (the N of Φ = β/N).
    pub paths: u64,
    pub stats: RenderStats,
    /// Set when fewer photons than requested were found (no caustic paths, no diffuse surfaces).
    pub warning: Option<String>,
    /// A fact for the render notes (the adaptive sampler's acceptance and normalisation).
    pub note: Option<String>,
}

/// Emits light paths of `stream` under `budget` — until `n` photons of `kind` are stored, cut at
/// the path where the count reaches `n` (so every emitted path contributes all of its photons
/// and N counts exactly those paths), or exactly `N_e` paths — and returns their photons with
/// flux β/N. `stream` separates the random numbers of different maps with the same seed.
/// `progress(fraction)` after each wave of paths. Deterministic for a given seed whatever the
/// thread count.
pub fn trace_photons(
    scene: &Scene,
    budget: PhotonBudget,
    kind: MapKind,
    stream: u64,
    opts: &RenderOptions,
    progress: &mut dyn FnMut(f64) -> bool,
) -> TracedPhotons {
    if kind == MapKind::Caustic && opts.photons.emission == EmissionStrategy::Adaptive {
        return trace_adaptive(scene, budget, stream, opts, progress);
    }
    let (mut photons, paths, stats) = trace_budget(
        budget,
        &PathStream::new(opts, stream),
        opts.photons.first_path,
        progress,
        |_, sampler, out, st| trace_one(scene, sampler, opts, kind, out, st),
    );
    let inv_n = 1.0 / paths.max(1) as f32;
    for p in &mut photons {
        p.flux *= inv_n;
    }
    let what = match kind {
        MapKind::Caustic => "caustic",
        MapKind::Global => "global",
        MapKind::Volume => "volume",
    };
    let warning = shortfall(what, photons.len(), paths, budget).map(|w| {
        if photons.is_empty() {
            format!(
                "{w}: {}",
                match kind {
                    MapKind::Caustic => NO_CAUSTIC_PATHS,
                    MapKind::Global => "the scene has no non-specular surface lit by its lights",
                    MapKind::Volume => "no light scatters in a participating medium",
                }
            )
        } else {
            w
        }
    });
    TracedPhotons {
        photons,
        paths,
        stats,
        warning,
        note: None,
    }
}

/// The caustic photons of visibility-driven adaptive photon tracing ([`super::adaptive`]):
/// `budget`'s count as chain steps (about one photon each), toward photons near the camera's
/// visible points. A state repeated by rejected mutations is stored once with its flux times
/// the repeat count (repeated points would collapse a k-NN radius to zero). The path count is
/// the chains' equivalent number of base light paths, `M / V_c`.
fn trace_adaptive(
    scene: &Scene,
    budget: PhotonBudget,
    stream: u64,
    opts: &RenderOptions,
    progress: &mut dyn FnMut(f64) -> bool,
) -> TracedPhotons {
    let visible = VisiblePoints::from_camera(scene, opts);
    let run = run_chains(
        &PathStream::new(opts, stream),
        opts.photons.first_path,
        chain_steps(budget),
        false,
        &|recs: &[Photon]| recs.iter().any(|p| visible.near(p.p)),
        &|sampler, out, st| trace_one(scene, sampler, opts, MapKind::Caustic, out, st),
    );
    progress(1.0);
    let n_eff = run.equivalent_paths();
    let inv_n = if n_eff > 0.0 {
        (1.0 / n_eff) as f32
    } else {
        0.0
    };
    let photons = run.weighted_records(|p, count| Photon {
        flux: p.flux * (count * inv_n),
        ..*p
    });
    let warning = if run.visible == 0 {
        Some(format!(
            "adaptive photon tracing: none of {} light paths stored a caustic photon near a visible point; the caustic map is empty",
            run.uniform
        ))
    } else {
        None
    };
    TracedPhotons {
        photons,
        paths: run.paths(),
        note: Some(run.note(&visible)),
        stats: run.stats,
        warning,
    }
}

/// Why a caustic pass found nothing.
pub(crate) const NO_CAUSTIC_PATHS: &str =
    "no light reaches a diffuse surface through glass or mirrors";

/// The warning of a pass that stored `found` `what` photons from `paths` light paths under
/// `budget`, when it found fewer than asked for (or none from a fixed number of paths).
pub(crate) fn shortfall(
    what: &str,
    found: usize,
    paths: u64,
    budget: PhotonBudget,
) -> Option<String> {
    match budget {
        PhotonBudget::Records(target) => (found < target).then(|| {
            format!(
                "only {found} {what} photons stored after {paths} light paths (requested {target})"
            )
        }),
        PhotonBudget::Paths(_) => {
            (found == 0).then(|| format!("no {what} photons stored in {paths} light paths"))
        }
    }
}

/// Stores the photons of one light path: at every non-delta vertex (global map) or at those
/// reached through delta vertices only (caustic map). A caustic map's path ends at its first
/// non-delta bounce, after which no vertex can receive caustic light (L S+ D): the same photons,
/// fewer rays.
pub(crate) fn trace_one(
    scene: &Scene,
    sampler: &mut Sampler,
    opts: &RenderOptions,
    kind: MapKind,
    out: &mut Vec<Photon>,
    stats: &mut RenderStats,
) {
    struct Store<'a> {
        kind: MapKind,
        out: &'a mut Vec<Photon>,
    }
    impl LightVisitor for Store<'_> {
        fn event(&mut self, event: LightEvent, _: &mut Sampler, stats: &mut RenderStats) {
            let lv = match event {
                LightEvent::Vertex(lv) => lv,
                LightEvent::Medium(lm) if self.kind == MapKind::Volume => {
                    // Linear sRGB, as surface photons (the identity in RGB mode).
                    let flux = lm.v.channels.to_rgb(lm.beta);
                    if !flux.is_finite() {
                        stats.nonfinite += 1;
                        return;
                    }
                    self.out.push(Photon {
                        p: lm.v.p,
                        wi: lm.v.wo,
                        n: Vec3::ZERO,
                        flux,
                        depth: lm.depth.min(u16::MAX as u32) as u16,
                        caustic: lm.after_specular_chain,
                    });
                    return;
                }
                _ => return,
            };
            let stored = match self.kind {
                MapKind::Caustic => lv.is_caustic(),
                MapKind::Global => lv.v.bsdf.flags().is_smooth(),
                MapKind::Volume => false,
            };
            if !stored {
                return;
            }
            // Stored in linear sRGB (the estimate is RGB; in spectral mode the photon's
            // wavelengths become its tristimulus flux here).
            let flux = lv.v.channels.to_rgb(lv.beta);
            if !flux.is_finite() {
                stats.nonfinite += 1;
                return;
            }
            self.out.push(Photon {
                p: lv.v.si.p,
                wi: lv.wo,
                n: lv.v.si.ng_toward(lv.wo),
                flux,
                depth: lv.depth.min(u16::MAX as u32) as u16,
                caustic: lv.after_specular_chain,
            });
        }
        fn scatter(&mut self, sc: &LightScatter, _: &mut RenderStats) -> bool {
            self.kind != MapKind::Caustic || sc.keeps_caustic()
        }
        fn scatter_in_medium(
            &mut self,
            _: &LightMediumVertex,
            _: &caustica_scene::phase::PhaseSample,
        ) -> bool {
            self.kind != MapKind::Caustic
        }
    }
    walk_light_path_at(
        scene,
        sampler,
        &opts.limits,
        stats,
        &mut Store { kind, out },
        opts.photons.photon_time(),
        kind.emission(opts),
    );
}
