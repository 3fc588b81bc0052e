//! Integrators, selected by name.

pub mod light_tracer;
pub mod path;
pub mod photon_mapping;
pub mod photon_splatting;

use crate::film::Film;
use crate::filter::Filter;
use crate::image_loop::render_pixels;
use crate::options::{CausticEstimator, RenderControl, RenderOptions};
use crate::splat_loop::render_paths;
use crate::stats::RenderStats;
use caustica_density::estimator::Estimator;
use caustica_scene::Scene;
use std::time::{Duration, Instant};

/// The available integrators.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntegratorKind {
    /// Unidirectional path tracer with NEE and MIS.
    Path,
    /// Light tracer connecting light-path vertices to the camera.
    LightTrace,
    /// Photon mapping: caustic and global maps, final gathering.
    PhotonMapping,
    /// Diffusion-based photon mapping (seed 000 ch. 4): `pm` with the caustic map estimated by
    /// the anisotropic diffusion estimate eq. 4.19.
    DiffusionPhotonMapping,
    /// Photon differential mapping (seed 002; seed 000 ch. 5, eq. 5.14): `pm` with the caustic
    /// photons traced as photon differentials and estimated by their footprints (seed 002
    /// eq. 10); direct light by NEE and indirect light by final gathering as in `pm`.
    PhotonDifferentialMapping,
    /// Photon differential splatting (seed 002 sec. 3.3): `pdm`'s estimate evaluated by
    /// splatting each caustic photon's footprint onto an eye-path map built first; no photon
    /// map is stored.
    PhotonDifferentialSplatting,
}

impl IntegratorKind {
    pub const NAMES: &'static [&'static str] = &["path", "lighttrace", "pm", "dpm", "pdm", "pds"];
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Path => "path",
            IntegratorKind::LightTrace => "lighttrace",
            IntegratorKind::PhotonMapping => "pm",
            IntegratorKind::DiffusionPhotonMapping => "dpm",
            IntegratorKind::PhotonDifferentialMapping => "pdm",
            IntegratorKind::PhotonDifferentialSplatting => "pds",
        }
    }

    /// True for the integrators that trace photon maps first.
    pub fn uses_photons(self) -> bool {
        matches!(
            self,
            IntegratorKind::PhotonMapping
                | IntegratorKind::DiffusionPhotonMapping
                | IntegratorKind::PhotonDifferentialMapping
                | IntegratorKind::PhotonDifferentialSplatting
        )
    }

    /// True for the integrators built on photon differentials (`--smoothing` applies).
    pub fn uses_photon_differentials(self) -> bool {
        matches!(
            self,
            IntegratorKind::PhotonDifferentialMapping | IntegratorKind::PhotonDifferentialSplatting
        )
    }
}

impl std::str::FromStr for IntegratorKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "path" => Ok(Self::Path),
            "lighttrace" | "ptracer" | "light" => Ok(Self::LightTrace),
            "pm" | "photonmapper" => Ok(Self::PhotonMapping),
            "dpm" => Ok(Self::DiffusionPhotonMapping),
            "pdm" => Ok(Self::PhotonDifferentialMapping),
            "pds" => Ok(Self::PhotonDifferentialSplatting),
            _ => Err(format!(
                "unknown integrator '{s}' (expected one of: {})",
                Self::NAMES.join(", ")
            )),
        }
    }
}

/// A finished (or stopped) render.
pub struct RenderOutput {
    pub film: Film,
    pub stats: RenderStats,
    pub elapsed: Duration,
    /// Lines for the user: what a photon pass did, and warnings.
    pub notes: Vec<String>,
}

/// Renders `scene` with integrator `kind`.
pub fn render(
    scene: &Scene,
    kind: IntegratorKind,
    opts: &RenderOptions,
    ctl: &RenderControl,
) -> RenderOutput {
    let start = Instant::now();
    let cam = &scene.camera;
    let mut film = Film::new(cam.width as usize, cam.height as usize);
    let filter = Filter::new(scene.settings.filter);
    let mut notes = Vec::new();
    let stats = match kind {
        IntegratorKind::Path => {
            render_pixels(&mut film, &filter, opts, ctl, |sampler, raster, st| {
                let u_lens = sampler.next_2d();
                let ray = cam.generate_ray(raster, u_lens).ray;
                path::radiance(scene, ray, sampler, opts, st)
            })
        }
        IntegratorKind::LightTrace => {
            let total = opts.spp as u64 * cam.width as u64 * cam.height as u64;
            render_paths(&mut film, total, opts, ctl, |sampler, out, st| {
                light_tracer::trace_light_path(scene, sampler, opts, &filter, out, st)
            })
        }
        IntegratorKind::PhotonDifferentialSplatting => {
            photon_splatting::render(scene, opts, ctl, &mut film, &filter, &mut notes)
        }
        IntegratorKind::PhotonMapping
        | IntegratorKind::DiffusionPhotonMapping
        | IntegratorKind::PhotonDifferentialMapping => {
            let mut pm_opts;
            let opts = if kind == IntegratorKind::DiffusionPhotonMapping {
                pm_opts = opts.clone();
                pm_opts.photons.caustic_estimator = CausticEstimator::Diffusion;
                &pm_opts
            } else {
                opts
            };
            let t = Instant::now();
            let maps = if kind == IntegratorKind::PhotonDifferentialMapping {
                photon_mapping::PhotonMaps::build_differential(scene, opts)
            } else {
                photon_mapping::PhotonMaps::build(scene, opts)
            };
            let secs = t.elapsed().as_secs_f64().max(1e-9);
            let (caustic_len, caustic_bytes) = match &maps.differential {
                Some(d) => (d.len(), d.memory_bytes()),
                None => (maps.caustic.len(), maps.caustic.memory_bytes()),
            };
            notes.push(format!(
                "photons: caustic {} from {} paths, global {} from {} paths, in {secs:.2} s ({:.2} M paths/s), {:.1} MB",
                caustic_len,
                maps.caustic.paths,
                maps.global.len(),
                maps.global.paths,
                (maps.caustic.paths + maps.global.paths) as f64 / secs / 1e6,
                (caustic_bytes + maps.global.memory_bytes()) as f64 / 1e6,
            ));
            if let Some(d) = &maps.differential {
                notes.push(format!(
                    "photon differentials: smoothing s = {}, {} caustic landings, {} stored, {} dropped with a collapsed footprint, {} dropped where the differential could not be propagated; gather radius median {:.4} m, max {:.4} m",
                    opts.photons.smoothing,
                    d.landings,
                    d.len(),
                    d.collapsed,
                    d.failed,
                    d.median_gather_radius(),
                    d.max_gather_radius(),
                ));
            }
            if let Estimator::Diffusion(d) = &maps.caustic_estimator {
                let p = d.params();
                notes.push(format!(
                    "diffusion estimate: bandwidth {:.4}, noise scale {:.4}, q {}, alpha {}{}; pre-passes {:.2} s (included above)",
                    p.bandwidth,
                    p.noise_scale,
                    p.q,
                    p.alpha,
                    if p.isotropic { ", isotropic" } else { "" },
                    maps.prepare_secs
                ));
            }
            notes.extend(maps.warnings.iter().map(|w| format!("warning: {w}")));
            let mut st = render_pixels(&mut film, &filter, opts, ctl, |sampler, raster, st| {
                let u_lens = sampler.next_2d();
                let ray = cam.generate_ray(raster, u_lens).ray;
                photon_mapping::radiance(scene, &maps, ray, sampler, opts, st)
            });
            st.rays += maps.stats.rays;
            st
        }
    };
    RenderOutput {
        film,
        stats,
        elapsed: start.elapsed(),
        notes,
    }
}
