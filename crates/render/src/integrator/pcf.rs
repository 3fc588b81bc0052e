//! Photon cone focusing, `pcf` (seed 001 ch. 3–4, Alg. 1): iterations of (1) light paths
//! whose every surface vertex stores photon cones (`pcf::tracer`), (2) a cone map, (3) a
//! camera pass that path-traces each camera path up to a lookup vertex and takes the cone
//! map's estimate there (eq. 3.14, `pcf::split`), the 4-D kernel shrinking by eq. 3.27 between
//! iterations (`pcf::kernel`); the image is the equal-weight mean of the iterations (the KZ
//! proof's average, spec notes Q19), only one iteration's cones alive at a time. The conical
//! importon map is traced once before the loop (Alg. 1 line 3).
//!
//! Built on the shared walkers and drivers: the light walker with a cone visitor, the path
//! tracer's loop under a [`CameraRule`], the progressive iteration driver (time budget,
//! Ctrl-C, checkpoints, `--resume`) and the pixel driver.

use super::IntegratorKind;
use super::path::{CameraRule, Direct, Lookup, radiance_deferred};
use crate::control::Stage;
use crate::driver::iteration_state::{IterationState, resume_pooled};
use crate::driver::iterations::{run_iterations, shard_iterations};
use crate::driver::pixels::render_pixels_batched;
use crate::error::OptionError;
use crate::film::Film;
use crate::filter::Filter;
use crate::options::{
    ConeSurfaces, ConeTechniques, DiffuseAperture, Nesting, PcfSettings, RenderOptions,
};
use crate::pcf::importon::ImportonRule;
use crate::pcf::techniques::CameraLobe;
use crate::pcf::{
    Aperture, ConeRule, ConeSchedule, ConeSet, DiskCapKernel, ImportonMap, LookupStats, PathSplit,
    PhotonCone, PhotonConeMap, trace_cones,
};
use crate::stats::RenderStats;
use crate::transport::vertex::Vertex;
use caustica_core::{Channels, Spectrum};
use caustica_scene::Scene;
use caustica_scene::bsdf::Bsdf;

/// σ₁ when not given: this fraction of the scene's bounding-box diagonal (0.05 m in the 2 m
/// Cornell box). Seed 001 sec. 4.1.2 suggests "≈ 0.1" in its own scene units; 3 % (0.1 m here)
/// gave 1.3–2.8× the whole-image RMSE of 1.5 % at 20 s on the three study scenes (docs/pcf.md).
pub const DEFAULT_SIGMA1_FRACTION: f32 = 0.015;

/// The camera side of an iteration: the split and the cone map under its kernel.
struct PcfCamera<'a> {
    map: &'a PhotonConeMap,
    kernel: DiskCapKernel,
    split: PathSplit,
    surfaces: ConeSurfaces,
    diffuse: DiffuseAperture,
}

impl PcfCamera<'_> {
    fn estimate(&self, v: &Vertex, set: ConeSet, stats: &mut RenderStats) -> Spectrum {
        let mut st = LookupStats::default();
        let w = v.frame.to_world(v.wo);
        // A Lambertian surface's radiance is the same in every direction: no cap
        // (`Aperture::Cosine`). A material property, not a BSDF evaluation.
        let aperture = match (self.diffuse, &v.bsdf) {
            (DiffuseAperture::Cosine, Bsdf::Lambertian(_)) => {
                Aperture::Cosine(if v.si.ng.dot(w) < 0.0 {
                    -v.si.ng
                } else {
                    v.si.ng
                })
            }
            _ => Aperture::Cap(w),
        };
        let surface = match self.surfaces {
            ConeSurfaces::Any => None,
            ConeSurfaces::Same => Some((v.si.shape, v.si.ng)),
        };
        let l = self
            .map
            .estimate(v.si.p, aperture, &self.kernel, set, surface, &mut st);
        stats.cone_lookups += st.lookups;
        stats.cones_scanned += st.scanned;
        stats.cones_inside += st.inside;
        l
    }
}

impl CameraRule for PcfCamera<'_> {
    fn lookup(&self, v: &Vertex, depth: u32, stats: &mut RenderStats) -> Option<Lookup> {
        let flags = v.bsdf.flags();
        self.split.is_lookup(depth, flags).then(|| Lookup {
            radiance: self.estimate(v, self.split.lookup_set(flags), stats),
            nee: self.split.nee_at_lookup(flags),
        })
    }
    fn direct(&self, v: &Vertex, _depth: u32, stats: &mut RenderStats) -> Direct {
        match self.split.direct_at(v.bsdf.flags()) {
            Direct::Nee => Direct::Nee,
            Direct::Add(_) => Direct::Add(self.estimate(v, ConeSet::DirectFromDeltaLights, stats)),
            Direct::Replace(_) => Direct::Replace(self.estimate(v, ConeSet::Direct, stats)),
        }
    }
}

/// The resolved parameters of a `pcf` render.
pub struct PcfPlan {
    pub settings: PcfSettings,
    /// The cone techniques ([`PcfSettings::techniques_for`] the scene).
    pub techniques: ConeTechniques,
    pub sigma1: f32,
    pub schedule: ConeSchedule,
    /// Light paths per iteration (N_L).
    pub paths: u64,
}

impl PcfPlan {
    /// Camera paths traced for the importon map.
    pub fn importon_paths(&self) -> u64 {
        self.settings.importon_paths.unwrap_or(self.paths)
    }

    pub fn new(scene: &Scene, opts: &RenderOptions) -> Result<Self, OptionError> {
        let settings = opts.photons.pcf;
        settings.validate()?;
        let sigma1 = settings.sigma1.unwrap_or_else(|| {
            (scene.geometry.bounds().extent().length() * DEFAULT_SIGMA1_FRACTION).max(1e-6)
        });
        let schedule = ConeSchedule::new(
            sigma1 as f64,
            (settings.theta1_deg as f64).to_radians(),
            settings.order,
            settings.alpha(),
        )
        .map_err(|e| OptionError::Invalid {
            what: "the pcf schedule",
            rule: "alpha in (0, 1) and a positive sigma_1",
            got: e.to_string(),
        })?;
        Ok(Self {
            settings,
            techniques: settings.techniques_for(scene),
            sigma1,
            schedule,
            paths: opts.photons.progressive.paths_per_iteration,
        })
    }
}

/// Iteration `i`'s cone map of `plan`: light paths `(i − 1) N_L … i N_L − 1` of the cone
/// stream with the cones [`cone_rule`] makes; `on_wave(paths done)` after each wave returns
/// false to stop there.
pub fn iteration_map(
    scene: &Scene,
    opts: &RenderOptions,
    plan: &PcfPlan,
    importons: Option<&ImportonMap>,
    i: u64,
    on_wave: &mut dyn FnMut(u64) -> bool,
) -> (PhotonConeMap, RenderStats) {
    let rule = cone_rule(scene, plan, importons, &plan.schedule.kernel(i));
    let first = (i.max(1) - 1).saturating_mul(plan.paths);
    let (cones, n, st) = trace_cones(
        scene,
        opts,
        &rule,
        first..first.saturating_add(plan.paths),
        on_wave,
    );
    (PhotonConeMap::build(cones, n), st)
}

/// How cones are made in an iteration whose kernel is `kernel` (the camera-NEE exponent
/// follows its cap unless given).
pub fn cone_rule<'a>(
    scene: &Scene,
    plan: &PcfPlan,
    importons: Option<&'a ImportonMap>,
    kernel: &DiskCapKernel,
) -> ConeRule<'a> {
    let s = &plan.settings;
    ConeRule {
        techniques: plan.techniques,
        mis: s.mis,
        camera: scene.camera.position(),
        camera_exponent: s
            .camera_exponent
            .unwrap_or_else(|| CameraLobe::exponent_for_cap(kernel.theta)),
        camera_mirror: s.camera_mirror,
        importons: if plan.techniques.importons {
            importons
        } else {
            None
        },
    }
}

/// The importon map of `plan` (traced once, before the iterations), if its technique is on.
pub fn importon_map(
    scene: &Scene,
    opts: &RenderOptions,
    plan: &PcfPlan,
    on_wave: &mut dyn FnMut(u64) -> bool,
) -> Option<(ImportonMap, RenderStats)> {
    let s = &plan.settings;
    if !plan.techniques.importons {
        return None;
    }
    Some(ImportonMap::trace(
        scene,
        opts,
        plan.importon_paths(),
        ImportonRule {
            first_vertex: if plan.techniques.camera { 2 } else { 1 },
        },
        s.importon_k,
        s.importon_radius.unwrap_or(plan.sigma1),
        s.importon_angle_deg.unwrap_or(s.theta1_deg).to_radians(),
        on_wave,
    ))
}

/// Renders with `pcf` into `film`.
pub(crate) fn render(
    scene: &Scene,
    opts: &RenderOptions,
    stage: &Stage,
    film: &mut Film,
    filter: &Filter,
    notes: &mut Vec<String>,
) -> Result<(RenderStats, Option<IterationState>), OptionError> {
    let kind = IntegratorKind::PhotonConeFocusing;
    let plan = PcfPlan::new(scene, opts)?;
    let s = plan.settings;
    notes.extend(s.warnings());
    let p = &opts.photons.progressive;
    let max = p.max_iterations(opts);
    // The importon map, before the loop (a small share of the bar).
    let pre = stage.part(0.0, 0.02).labelled("tracing importons");
    let mut stats = RenderStats::default();
    let importon_paths = plan.importon_paths().max(1) as f64;
    let importons = importon_map(scene, opts, &plan, &mut |done| {
        pre.report_and_go_on(done as f64 / importon_paths)
    });
    let importons = match importons {
        Some((map, st)) => {
            stats += st;
            if map.is_empty() {
                notes.push(
                    "warning: no importons were stored (no non-delta surface seen by the camera beyond the first hit): the importon technique draws nothing".into(),
                );
            }
            Some(map)
        }
        None => None,
    };
    let stage = stage.part(0.02, 1.0);
    let (first, fp) = resume_pooled(scene, kind, opts, film, notes)?;
    let (first, max) = shard_iterations(opts, first, max);
    let snapshot = |f: &Film, i: u64| IterationState::pooled(&fp, i, f);
    let mut cones_total = 0u64;
    let mut cone_bytes = 0usize;
    // Delta-light nesting looks the map up at every delta camera vertex; without delta
    // lights it can find nothing there (the same image, without the lookups).
    let nested = match s.nested {
        Nesting::DeltaLights if !scene.lights.iter().any(|l| l.is_delta()) => Nesting::Off,
        n => n,
    };
    let split = PathSplit {
        rule: s.lookup,
        nested,
        lookup_nee: s.lookup_nee,
    };
    let run = run_iterations(film, &stage, first, max, None, &snapshot, |i, st, f| {
        let o = p.iteration_options(opts, i);
        let kernel = plan.schedule.kernel(i);
        let trace = st.part(0.0, 0.5).labelled("tracing cones");
        let (map, mut stats) =
            iteration_map(scene, &o, &plan, importons.as_ref(), i, &mut |done| {
                trace.report_and_go_on(done as f64 / plan.paths.max(1) as f64)
            });
        cones_total += map.len() as u64;
        cone_bytes = cone_bytes.max(map.memory_bytes());
        let camera = PcfCamera {
            map: &map,
            kernel,
            split,
            surfaces: s.surfaces,
            diffuse: s.diffuse_aperture,
        };
        let pixels = st.part(0.5, 1.0).labelled("looking up cones");
        stats += render_pixels_batched(f, filter, &o, &pixels, |sampler, raster, b, sst| {
            let u_lens = sampler.next_2d();
            let time = scene.sample_time(|| sampler.next_1d());
            let ray = scene.camera.generate_ray(raster, u_lens).ray.at_time(time);
            radiance_deferred(scene, ray, sampler, &o, sst, &camera, Channels::Rgb, b)
        });
        stats
    });
    stats += run.stats;
    let done = if run.iterations > 0 {
        run.last
    } else {
        first - 1
    };
    let k1 = plan.schedule.kernel(1);
    let kn = plan.schedule.kernel(done.max(1));
    let traced = run.iterations.max(1);
    let l = LookupStats {
        lookups: stats.cone_lookups,
        scanned: stats.cones_scanned,
        inside: stats.cones_inside,
    };
    notes.push(format!(
        "pcf: {done} iterations of {} light paths and {} spp; sigma {:.4} -> {:.4} m, t {:.2} -> {:.2} deg (theta_1 {}, p {}, alpha {}); techniques {}{}; lookup {} (direct light there from {}), nested {}; cone surfaces {}; Lambertian lookups {}",
        plan.paths,
        opts.spp,
        k1.sigma,
        kn.sigma,
        (k1.theta as f64).to_degrees(),
        (kn.theta as f64).to_degrees(),
        s.theta1_deg,
        s.order,
        s.alpha(),
        plan.techniques.names(),
        if s.mis { " (MIS, power heuristic)" } else { " (no MIS)" },
        s.lookup.name(),
        if s.lookup_nee { "NEE" } else { "cones" },
        s.nested.name(),
        s.surfaces.name(),
        s.diffuse_aperture.name(),
    ));
    notes.push(format!(
        "pcf: {:.0} cones per iteration ({:.2} per light path, {} B per cone with its tree, {:.1} MB at most); {} lookups, {:.1} cones scanned and {:.2} inside the kernel per lookup{}",
        cones_total as f64 / traced as f64,
        cones_total as f64 / (traced * plan.paths.max(1)) as f64,
        std::mem::size_of::<PhotonCone>() + 17,
        cone_bytes as f64 / 1e6,
        l.lookups,
        l.scanned as f64 / l.lookups.max(1) as f64,
        l.inside as f64 / l.lookups.max(1) as f64,
        importons.as_ref().map_or(String::new(), |m| format!(
            "; {} importons from {} camera paths ({:.1} MB)",
            m.len(),
            m.paths,
            m.memory_bytes() as f64 / 1e6
        )),
    ));
    if let Some(why) = run.stopped {
        notes.push(format!("pcf: stopped {why}"));
    }
    let state = (done > 0).then(|| snapshot(film, done));
    Ok((stats, state))
}
