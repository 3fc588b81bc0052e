//! Integrators, selected by name.

pub mod hybrid;
pub mod light_tracer;
pub mod path;
pub mod path_lanes;
pub mod pcf;
pub mod photon_mapping;
pub mod photon_splatting;
pub mod progressive;
pub mod sppm;

use crate::control::{Clock, RenderControl};
use crate::driver::light_paths::{CHUNK as LIGHT_CHUNK, render_paths};
use crate::driver::pixels::{render_pixels_batched, render_pixels_rows};
use crate::error::{OptionError, RenderError};
use crate::film::Film;
use crate::filter::Filter;
use crate::memory;
use crate::options::{CausticEstimator, RenderOptions};
use crate::photon::volume_map::VolumeEstimate;
use crate::shard::{RowSet, Shard, ShardUnit};
use crate::stats::RenderStats;
use caustica_scene::Scene;
use caustica_scene::material::Material;
use photon_mapping::PhotonMaps;
use std::time::Duration;

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
    /// Volumetric photon mapping (Jensen and Christensen 1998; seed 000 eq. 8.3): `pm` with
    /// the volume photons gathered by ray marching camera rays, a k-NN estimate per step.
    VolumetricPhotonMapping,
    /// `pm` with the volume photons gathered by the beam radiance estimate (Jarosz et al. 2008;
    /// seed 000 eq. 8.4): one query per camera ray, exact chord integrals of the kernels.
    BeamRadianceEstimate,
    /// Photon differentials in participating media (seed 000 ch. 8.3–8.4): `pdm` for surfaces,
    /// and volume photons traced as photon differentials whose ellipsoidal kernels every camera
    /// and gather ray integrates exactly (eq. 8.4, 8.14–8.16).
    VolumePhotonDifferentials,
    /// Probabilistic progressive photon mapping (Knaus and Zwicker 2011; seed 001 sec. 2.5,
    /// eq. 3.27): independent `pm` iterations at a shrinking global radius, averaged.
    ProgressivePhotonMapping,
    /// Progressive photon differential splatting: `pds` iterations whose smoothing shrinks by
    /// eq. 3.27 applied to the footprint area, averaged.
    ProgressiveSplatting,
    /// Progressive photon differential mapping: the same schedule over `pdm`.
    ProgressiveDifferentialMapping,
    /// Progressive diffusion-based photon mapping: `dpm` iterations whose bandwidth h shrinks
    /// by eq. 3.27 (`h²` the kernel's area), averaged.
    ProgressiveDiffusion,
    /// Stochastic progressive photon mapping (Hachisuka and Jensen 2009): a new camera pass
    /// per iteration, photons gathered at visible points with per-pixel statistics.
    StochasticProgressivePhotonMapping,
    /// Progressive photon mapping (Hachisuka et al. 2008): the hit points of one camera pass
    /// (`--spp` per pixel), photons gathered there with per-pixel statistics.
    ProgressivePhotonMappingHitPoints,
    /// Photon cone focusing (seed 001 ch. 3–4): photon cones on every surface, delta ones
    /// included, estimated by a 4-D position × direction kernel that shrinks by eq. 3.27;
    /// camera paths path-traced up to a lookup vertex.
    PhotonConeFocusing,
    /// A guided light tracer for the paths whose first scattering is delta and whose camera end
    /// is not (L S … D E: caustics and their diffuse reflections) and a path tracer for every
    /// other path, into one film ([`hybrid`]).
    Hybrid,
}

impl IntegratorKind {
    pub const NAMES: &'static [&'static str] = &[
        "path",
        "lighttrace",
        "pm",
        "dpm",
        "pdm",
        "pds",
        "vpm",
        "beam",
        "vpd",
        "pppm",
        "ppds",
        "ppdm",
        "pdpm",
        "sppm",
        "ppm",
        "pcf",
        "hybrid",
    ];
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Path => "path",
            IntegratorKind::LightTrace => "lighttrace",
            IntegratorKind::PhotonMapping => "pm",
            IntegratorKind::DiffusionPhotonMapping => "dpm",
            IntegratorKind::PhotonDifferentialMapping => "pdm",
            IntegratorKind::PhotonDifferentialSplatting => "pds",
            IntegratorKind::VolumetricPhotonMapping => "vpm",
            IntegratorKind::BeamRadianceEstimate => "beam",
            IntegratorKind::VolumePhotonDifferentials => "vpd",
            IntegratorKind::ProgressivePhotonMapping => "pppm",
            IntegratorKind::ProgressiveSplatting => "ppds",
            IntegratorKind::ProgressiveDifferentialMapping => "ppdm",
            IntegratorKind::ProgressiveDiffusion => "pdpm",
            IntegratorKind::StochasticProgressivePhotonMapping => "sppm",
            IntegratorKind::ProgressivePhotonMappingHitPoints => "ppm",
            IntegratorKind::PhotonConeFocusing => "pcf",
            IntegratorKind::Hybrid => "hybrid",
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
                | IntegratorKind::VolumetricPhotonMapping
                | IntegratorKind::BeamRadianceEstimate
                | IntegratorKind::VolumePhotonDifferentials
                | IntegratorKind::ProgressivePhotonMapping
                | IntegratorKind::ProgressiveSplatting
                | IntegratorKind::ProgressiveDifferentialMapping
                | IntegratorKind::ProgressiveDiffusion
                | IntegratorKind::StochasticProgressivePhotonMapping
                | IntegratorKind::ProgressivePhotonMappingHitPoints
                | IntegratorKind::PhotonConeFocusing
        )
    }

    /// True for the progressive methods (iterations whose bandwidths shrink).
    pub fn is_progressive(self) -> bool {
        progressive::one_shot(self).is_some()
            || self == IntegratorKind::StochasticProgressivePhotonMapping
            || self == IntegratorKind::ProgressivePhotonMappingHitPoints
            || self == IntegratorKind::PhotonConeFocusing
    }

    /// True for the progressive methods that can continue from a state file (`--resume`).
    pub fn resumable(self) -> bool {
        self.is_progressive()
    }

    /// A one-line description (for `--help` and `caustica` listings).
    pub fn description(self) -> &'static str {
        match self {
            IntegratorKind::Path => "path tracer with next-event estimation and MIS",
            IntegratorKind::LightTrace => {
                "light tracer (the reference for caustics from point lights)"
            }
            IntegratorKind::PhotonMapping => {
                "photon mapping: caustic and global maps, final gathering"
            }
            IntegratorKind::DiffusionPhotonMapping => {
                "diffusion-based photon mapping (seed 000 ch. 4)"
            }
            IntegratorKind::PhotonDifferentialMapping => {
                "photon differential mapping (seed 002, seed 000 ch. 5)"
            }
            IntegratorKind::PhotonDifferentialSplatting => {
                "photon differential splatting (seed 002 sec. 3.3)"
            }
            IntegratorKind::VolumetricPhotonMapping => {
                "volumetric photon mapping: pm with ray-marched volume photons (seed 000 eq. 8.3)"
            }
            IntegratorKind::BeamRadianceEstimate => {
                "pm with the beam radiance estimate of volume photons (seed 000 eq. 8.4)"
            }
            IntegratorKind::VolumePhotonDifferentials => {
                "photon differentials in media: pdm with ellipsoidal volume photons (seed 000 ch. 8)"
            }
            IntegratorKind::ProgressivePhotonMapping => {
                "probabilistic progressive photon mapping: pm iterations at a shrinking radius (Knaus and Zwicker 2011)"
            }
            IntegratorKind::ProgressiveSplatting => {
                "progressive photon differential splatting: pds iterations at a shrinking smoothing"
            }
            IntegratorKind::ProgressiveDifferentialMapping => {
                "progressive photon differential mapping: pdm iterations at a shrinking smoothing"
            }
            IntegratorKind::ProgressiveDiffusion => {
                "progressive diffusion-based photon mapping: dpm iterations at a shrinking bandwidth"
            }
            IntegratorKind::StochasticProgressivePhotonMapping => {
                "stochastic progressive photon mapping: per-pixel radii, a camera pass per iteration (Hachisuka and Jensen 2009)"
            }
            IntegratorKind::ProgressivePhotonMappingHitPoints => {
                "progressive photon mapping: the fixed hit points of one camera pass, per-pixel radii (Hachisuka et al. 2008)"
            }
            IntegratorKind::PhotonConeFocusing => {
                "photon cone focusing: cones on every surface, a 4-D kernel shrinking per iteration (seed 001 ch. 3-4)"
            }
            IntegratorKind::Hybrid => {
                "path tracer + guided light tracer for the caustics and their reflections (L S ... D E), no path counted twice"
            }
        }
    }

    /// Every integrator, in the order of [`IntegratorKind::NAMES`].
    pub const ALL: [IntegratorKind; 17] = [
        IntegratorKind::Path,
        IntegratorKind::LightTrace,
        IntegratorKind::PhotonMapping,
        IntegratorKind::DiffusionPhotonMapping,
        IntegratorKind::PhotonDifferentialMapping,
        IntegratorKind::PhotonDifferentialSplatting,
        IntegratorKind::VolumetricPhotonMapping,
        IntegratorKind::BeamRadianceEstimate,
        IntegratorKind::VolumePhotonDifferentials,
        IntegratorKind::ProgressivePhotonMapping,
        IntegratorKind::ProgressiveSplatting,
        IntegratorKind::ProgressiveDifferentialMapping,
        IntegratorKind::ProgressiveDiffusion,
        IntegratorKind::StochasticProgressivePhotonMapping,
        IntegratorKind::ProgressivePhotonMappingHitPoints,
        IntegratorKind::PhotonConeFocusing,
        IntegratorKind::Hybrid,
    ];

    /// Checks that this integrator can render with `opts` (the values themselves are valid by
    /// their types and [`crate::PhotonOptions::validate`]); the message says what to change.
    pub fn check(self, opts: &RenderOptions) -> Result<(), OptionError> {
        if let Some(shard) = opts.shard {
            ShardUnit::of(self)?;
            if opts.time_limit.is_some() {
                return Err(OptionError::Conflict(format!(
                    "--shard {shard} cannot be combined with a time budget (--time): the work a \
                     shard does would depend on its machine's speed, and the merge would not be \
                     one render; give the work instead (--spp, --photons, --iterations)"
                )));
            }
            if opts.resume.is_some() {
                return Err(OptionError::Conflict(format!(
                    "--shard {shard} cannot resume a state file: a shard renders its own \
                     iterations from the start; merge finished shards with `caustica merge`"
                )));
            }
        }
        if self.uses_photons() {
            opts.photons.validate()?;
        }
        if self.is_progressive() {
            opts.photons.progressive.validate()?;
            if opts.volume_only {
                return Err(OptionError::Conflict(format!(
                    "--integrator {} does not trace volume photons yet: for --volume-only use vpm, beam or vpd",
                    self.name()
                )));
            }
        }
        if self == IntegratorKind::PhotonConeFocusing {
            opts.photons.pcf.validate()?;
            if opts.caustics_only {
                return Err(OptionError::Conflict(
                    "--caustics-only is not available with --integrator pcf: its cones do not separate caustic paths; use lighttrace, pm, dpm, pdm or pds".into(),
                ));
            }
        }
        if self == IntegratorKind::Hybrid && (opts.caustics_only || opts.volume_only) {
            return Err(OptionError::Conflict(
                "--integrator hybrid renders every path; for --caustics-only use --integrator lighttrace (with --emission), for --volume-only lighttrace or vpm, beam, vpd".into(),
            ));
        }
        if self == IntegratorKind::Hybrid {
            // Its --light-paths and --emission are the photon options'.
            opts.photons.validate()?;
        }
        if opts.caustics_only && self == IntegratorKind::Path {
            return Err(OptionError::Conflict(
                "--caustics-only needs --integrator lighttrace, pm, dpm, pdm or pds: the path tracer cannot isolate L S+ D E paths".into(),
            ));
        }
        if opts.volume_only && self == IntegratorKind::Path {
            return Err(OptionError::Conflict(
                "--volume-only needs --integrator lighttrace or a photon method (vpm, beam, vpd): the path tracer does not isolate paths ... M E".into(),
            ));
        }
        if opts.volume_only && opts.caustics_only {
            return Err(OptionError::Conflict(
                "--volume-only and --caustics-only select disjoint paths (... M E and L S+ D E); give one".into(),
            ));
        }
        // pm, dpm and pdm show the global map directly when they do not gather: without global
        // photons that image would be black but for nothing, silently.
        if matches!(
            self,
            IntegratorKind::PhotonMapping
                | IntegratorKind::DiffusionPhotonMapping
                | IntegratorKind::PhotonDifferentialMapping
        ) && opts.photons.final_gather == 0
            && opts.photons.global_photons == 0
            && !opts.caustics_only
            && !opts.volume_only
        {
            return Err(OptionError::Conflict(format!(
                "--integrator {} with --final-gather 0 shows the global photon map directly, and \
                 --global-photons 0 leaves it empty (a black image): give global photons, or \
                 final-gather rays, or --caustics-only",
                self.name()
            )));
        }
        match (self, opts.photons.caustic_estimator) {
            (
                IntegratorKind::DiffusionPhotonMapping | IntegratorKind::ProgressiveDiffusion,
                Some(e),
            ) if e != CausticEstimator::Diffusion => Err(OptionError::Conflict(format!(
                "--integrator {} uses the diffusion estimator; for --estimator {} use --integrator pm",
                self.name(),
                e.name()
            ))),
            (
                IntegratorKind::ProgressivePhotonMapping
                | IntegratorKind::StochasticProgressivePhotonMapping
                | IntegratorKind::ProgressivePhotonMappingHitPoints,
                Some(e),
            ) => Err(OptionError::Conflict(format!(
                "--integrator {} uses a radius that shrinks per iteration; --estimator {} is for --integrator pm",
                self.name(),
                e.name()
            ))),
            (
                IntegratorKind::PhotonDifferentialMapping
                | IntegratorKind::PhotonDifferentialSplatting
                | IntegratorKind::ProgressiveSplatting
                | IntegratorKind::ProgressiveDifferentialMapping,
                Some(e),
            ) => Err(OptionError::Conflict(format!(
                "--integrator {} estimates caustics from photon-differential footprints; for --estimator {} use --integrator pm",
                self.name(),
                e.name()
            ))),
            _ => Ok(()),
        }
    }

    /// Checks that this integrator can render `scene`: the photon methods need a light.
    pub fn check_scene(self, scene: &Scene) -> Result<(), RenderError> {
        if self.uses_photons() && scene.lights.is_empty() {
            return Err(RenderError::NoLights {
                scene: scene.name.clone(),
            });
        }
        if self.is_progressive() && scene.media.iter().any(|m| !m.sigma_s.is_black()) {
            return Err(RenderError::Option(OptionError::Conflict(format!(
                "scene '{}' has scattering media, which --integrator {} does not trace yet (no progressive volume photons); use vpm, beam or vpd",
                scene.name,
                self.name()
            ))));
        }
        Ok(())
    }

    /// A warning when this integrator cannot render the scene's main light transport: the
    /// path tracer cannot find caustics from delta lights (point, spot, directional, beam)
    /// through mirrors, glass or smooth metal (paths L S+ D E: no NEE connection reaches a
    /// delta light through a delta vertex, and no camera path hits the light itself).
    pub fn blind_spot(self, scene: &Scene) -> Option<String> {
        if self != IntegratorKind::Path {
            return None;
        }
        let delta_lights = scene.lights.iter().filter(|l| l.is_delta()).count();
        let specular = scene.materials.iter().any(|m| {
            matches!(
                m,
                Material::Mirror { .. } | Material::Dielectric { .. } | Material::Conductor { .. }
            )
        });
        (delta_lights > 0 && specular).then(|| {
            let which = if delta_lights == scene.lights.len() {
                "all its lights are"
            } else {
                "it has lights that are"
            };
            format!(
                "scene '{}' has mirrors, glass or smooth metal and {which} point-like or \
                 directional: the path tracer cannot render their caustics (paths L S+ D E); \
                 use --integrator hybrid (or pds, pm, pdm, dpm, lighttrace)",
                scene.name
            )
        })
    }

    /// True for the integrators built on photon differentials (`--smoothing` applies).
    pub fn uses_photon_differentials(self) -> bool {
        matches!(
            self,
            IntegratorKind::PhotonDifferentialMapping
                | IntegratorKind::PhotonDifferentialSplatting
                | IntegratorKind::VolumePhotonDifferentials
                | IntegratorKind::ProgressiveSplatting
                | IntegratorKind::ProgressiveDifferentialMapping
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
            "vpm" => Ok(Self::VolumetricPhotonMapping),
            "beam" | "bre" => Ok(Self::BeamRadianceEstimate),
            "vpd" => Ok(Self::VolumePhotonDifferentials),
            "pppm" => Ok(Self::ProgressivePhotonMapping),
            "ppds" => Ok(Self::ProgressiveSplatting),
            "ppdm" => Ok(Self::ProgressiveDifferentialMapping),
            "pdpm" => Ok(Self::ProgressiveDiffusion),
            "sppm" => Ok(Self::StochasticProgressivePhotonMapping),
            "ppm" => Ok(Self::ProgressivePhotonMappingHitPoints),
            "pcf" => Ok(Self::PhotonConeFocusing),
            "hybrid" => Ok(Self::Hybrid),
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
    /// Complete iterations in the film (progressive methods; 0 when only an interrupted first
    /// iteration is there).
    pub iterations: Option<u64>,
    /// The progressive render's state after its last complete iteration (for `--resume`).
    pub state: Option<crate::driver::iteration_state::IterationState>,
    /// A sharded render's part of the work, in words (for its manifest).
    pub shard: Option<String>,
}

/// Renders `scene` with integrator `kind`, after [`IntegratorKind::check`]ing the options.
/// One clock covers the whole render: a time budget is shared by all its passes.
pub fn render(
    scene: &Scene,
    kind: IntegratorKind,
    opts: &RenderOptions,
    ctl: &RenderControl,
) -> Result<RenderOutput, RenderError> {
    kind.check(opts)?;
    kind.check_scene(scene)?;
    let window = opts.window(&scene.camera)?;
    check_memory(kind, scene, opts)?;
    let clock = Clock::start(opts);
    let stage = clock.stage(ctl);
    let cam = &scene.camera;
    // Only the window's pixels; the camera, the light paths and the photons are the full film's.
    let mut film = Film::cropped(window, cam.width as usize, cam.height as usize);
    let filter = Filter::new(scene.settings.filter);
    let mut notes = Vec::new();
    // A shard of a method split by rows adds camera samples to its rows only.
    if let Some(shard) = opts.shard
        && matches!(
            ShardUnit::of(kind)?,
            ShardUnit::PixelRows | ShardUnit::SplatChunks
        )
    {
        film.restrict_rows(RowSet::of(shard));
    }
    // Automatic bandwidths first, in a small share of the progress bar (and of a time budget);
    // without any the stage is untouched, so explicit values render exactly as before.
    let chosen;
    // Volume-only renders shade no surface: no surface bandwidth to choose.
    let (opts, stage) =
        if crate::photon::bandwidth_choice::chooses(kind, &opts.photons) && !opts.volume_only {
            let choice_stage = stage
                .part(0.0, CHOICE_SHARE)
                .labelled("choosing bandwidths");
            let c = crate::photon::bandwidth_choice::choose(scene, kind, opts, &mut |f| {
                choice_stage.report_and_go_on(f)
            });
            notes.extend(c.note);
            chosen = c.opts;
            (&chosen, stage.part(CHOICE_SHARE, 1.0))
        } else {
            (opts, stage)
        };
    let mut iterations = None;
    let mut state = None;
    let stats: RenderStats = match kind {
        IntegratorKind::ProgressivePhotonMapping
        | IntegratorKind::ProgressiveSplatting
        | IntegratorKind::ProgressiveDifferentialMapping
        | IntegratorKind::ProgressiveDiffusion => {
            let (st, s) =
                progressive::render(scene, kind, opts, &stage, &mut film, &filter, &mut notes)?;
            iterations = Some(s.as_ref().map_or(0, |s| s.iterations));
            state = s;
            st
        }
        IntegratorKind::StochasticProgressivePhotonMapping
        | IntegratorKind::ProgressivePhotonMappingHitPoints => {
            let visible = if kind == IntegratorKind::StochasticProgressivePhotonMapping {
                sppm::Visible::PerIteration
            } else {
                sppm::Visible::Fixed
            };
            let (st, s) =
                sppm::render(scene, visible, opts, &stage, &mut film, &filter, &mut notes)?;
            iterations = Some(s.as_ref().map_or(0, |s| s.iterations));
            state = s;
            st
        }
        IntegratorKind::PhotonConeFocusing => {
            let (st, s) = pcf::render(scene, opts, &stage, &mut film, &filter, &mut notes)?;
            iterations = Some(s.as_ref().map_or(0, |s| s.iterations));
            state = s;
            st
        }
        IntegratorKind::Path if path_lanes::covers(scene) => {
            let stage = stage.labelled("path tracing");
            render_pixels_rows(&mut film, opts, &stage, |r, st, add| {
                path_lanes::render_row(scene, opts, &filter, r, st, add)
            })
        }
        IntegratorKind::Path => {
            let stage = stage.labelled("path tracing");
            let ext = scene.camera.screen_half_extent();
            render_pixels_batched(
                &mut film,
                &filter,
                opts,
                &stage,
                |sampler, raster, b, st| {
                    let rule = &path::PathOnly;
                    path::camera_radiance(scene, raster, ext, sampler, opts, st, rule, b)
                },
            )
        }
        IntegratorKind::Hybrid => {
            hybrid::render(scene, opts, &stage, &mut film, &filter, &mut notes)
        }
        IntegratorKind::LightTrace => {
            // Per pixel of the full film, cropped or not: the same paths, splats outside the
            // window dropped.
            let stage = stage.labelled("tracing light paths");
            let paths = light_path_range(light_paths(scene, opts), opts.shard);
            render_paths(&mut film, paths, opts, &stage, |sampler, out, st| {
                light_tracer::trace_light_path(scene, sampler, opts, &filter, out, st)
            })
        }
        IntegratorKind::PhotonDifferentialSplatting => {
            photon_splatting::render(scene, opts, &stage, &mut film, &filter, &mut notes)
        }
        IntegratorKind::PhotonMapping
        | IntegratorKind::DiffusionPhotonMapping
        | IntegratorKind::PhotonDifferentialMapping => {
            photon_mapping::render(scene, opts, &stage, &mut film, &filter, &mut notes, |p| {
                PhotonMaps::for_integrator(scene, kind, opts, p)
            })
        }
        IntegratorKind::VolumetricPhotonMapping
        | IntegratorKind::BeamRadianceEstimate
        | IntegratorKind::VolumePhotonDifferentials => {
            let mut o = opts.clone();
            let (estimate, surfaces) = match kind {
                IntegratorKind::VolumetricPhotonMapping => {
                    (VolumeEstimate::March, IntegratorKind::PhotonMapping)
                }
                IntegratorKind::BeamRadianceEstimate => {
                    (VolumeEstimate::Beam, IntegratorKind::PhotonMapping)
                }
                _ => (VolumeEstimate::Differentials, kind),
            };
            o.photons.volume.estimate = estimate;
            let o = &o;
            photon_mapping::render(scene, o, &stage, &mut film, &filter, &mut notes, |p| {
                PhotonMaps::for_integrator(scene, surfaces, o, p)
            })
        }
    };
    Ok(RenderOutput {
        shard: opts.shard.map(|s| shard_work(scene, kind, opts, s)),
        film,
        stats,
        elapsed: clock.elapsed(),
        notes,
        iterations,
        state,
    })
}

/// The light paths of a light-tracer render: `spp` per pixel of the full film (as Mitsuba's
/// `ptracer` counts them).
fn light_paths(scene: &Scene, opts: &RenderOptions) -> u64 {
    opts.spp as u64 * scene.camera.width as u64 * scene.camera.height as u64
}

/// The light paths of a light-tracer render of `total` paths that `shard` traces: whole chunks
/// of the light-path driver, so every chunk's splat buffer is the unsharded render's.
fn light_path_range(total: u64, shard: Option<Shard>) -> std::ops::Range<u64> {
    match shard {
        None => 0..total,
        Some(s) => {
            let chunks = s.range(total.div_ceil(LIGHT_CHUNK));
            (chunks.start * LIGHT_CHUNK).min(total)..(chunks.end * LIGHT_CHUNK).min(total)
        }
    }
}

/// What `shard` of a `kind` render does, for its manifest ("light-path chunks 3..6 of 12 (paths
/// 49152..98304)").
fn shard_work(scene: &Scene, kind: IntegratorKind, opts: &RenderOptions, shard: Shard) -> String {
    let Ok(unit) = ShardUnit::of(kind) else {
        return String::new();
    };
    let rows = |h: u64| {
        let (i, n) = (shard.index(), shard.count());
        let k = RowSet::of(shard).count(h as usize);
        match n {
            1 => format!("pixel rows 0..{h}"),
            _ => format!("pixel rows {i}, {}, … (one in {n}): {k} of {h}", i + n),
        }
    };
    let height = opts
        .window(&scene.camera)
        .map_or(scene.camera.height, |w| w.height) as u64;
    match unit {
        ShardUnit::PixelRows => rows(height),
        ShardUnit::LightPathChunks => {
            let total = light_paths(scene, opts);
            let chunks = total.div_ceil(LIGHT_CHUNK);
            let c = shard.range(chunks);
            let p = light_path_range(total, Some(shard));
            format!(
                "light-path chunks {}..{} of {chunks} (paths {}..{} of {total})",
                c.start, c.end, p.start, p.end
            )
        }
        ShardUnit::SplatChunks if kind == IntegratorKind::Hybrid => {
            let total = hybrid::light_paths(scene, opts);
            let p = light_path_range(total, Some(shard));
            format!(
                "light paths {}..{} of {total}, and the camera samples of {}",
                p.start,
                p.end,
                rows(height)
            )
        }
        ShardUnit::SplatChunks => format!(
            "share {shard} of the splatting pass's light-path chunks, and of the eye pass {}",
            rows(height)
        ),
        ShardUnit::Iterations => {
            let total = opts
                .photons
                .progressive
                .max_iterations(opts)
                .unwrap_or_default();
            let r = shard.range(total);
            if r.is_empty() {
                format!("no iteration (more shards than the {total} iterations)")
            } else {
                format!("iterations {}..={} of {total}", r.start + 1, r.end)
            }
        }
    }
}

/// Share of the progress bar (and of a time budget) of the automatic bandwidth choice.
const CHOICE_SHARE: f64 = 0.05;

/// Refuses a render whose estimated allocations ([`memory::estimate`]) exceed the budget, naming
/// the largest part and the option that lowers it.
pub fn check_memory(
    kind: IntegratorKind,
    scene: &Scene,
    opts: &RenderOptions,
) -> Result<(), RenderError> {
    let Some(limit) = opts.memory_limit else {
        return Ok(());
    };
    let m = memory::estimate(kind, scene, opts);
    if m.total() <= limit {
        return Ok(());
    }
    let hint = match m.largest().map(|p| p.what) {
        Some("eye map") => {
            "pds keeps one eye vertex per camera sample: lower --spp or --width/--height"
        }
        Some("global map") => "lower --global-photons",
        Some("cone map") | Some("importon map") => {
            "pcf keeps one iteration's cones: lower --photons-per-iteration (or --importons)"
        }
        Some("film") => "lower the resolution (--width/--height)",
        _ => "lower --photons or --light-paths",
    };
    Err(RenderError::Memory {
        estimate: m.to_string(),
        limit: memory::human_bytes(limit),
        hint,
    })
}
