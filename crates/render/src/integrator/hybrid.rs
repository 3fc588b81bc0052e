//! The hybrid integrator: a guided light tracer and a path tracer adding into one film, each
//! counting the paths it samples best and no path counted twice (a partition of path space, as
//! `pm` partitions it between its caustic map and its camera side). A path is cut by its two
//! ends:
//!
//! * the light tracer counts the paths whose first scattering from the light is delta and whose
//!   vertex seen by the camera is not, L S … D E ([`Connect::SpecularFirst`]): the caustics seen
//!   directly (L S+ D E) and their diffuse interreflections (L S+ D D E, …). Its light paths are
//!   emitted by `--emission` (projection maps by default: most of them toward mirrors, glass and
//!   smooth metal, their flux divided by the relative density, so the estimate keeps its
//!   expectation), and end after a first scattering that is not delta;
//! * the path tracer (NEE and MIS) counts every other path: emission a camera path reaches right
//!   after a delta bounce, when its first vertex scattered by a non-delta lobe (E D … S L), is
//!   dropped ([`CameraRule::light_tracer_beside`]). By the same sampled lobes and the same edge
//!   count these are exactly the light tracer's paths read from the other end. Every path the
//!   light tracer cannot connect (the camera sees a delta surface first) or whose last vertex
//!   before the light is non-delta (NEE's) stays the path tracer's.
//!
//! With delta lights (point, spot, directional, beam) the path tracer never reaches the light
//! after a delta bounce, so its half is the plain path tracer's image and the light tracer adds
//! what it cannot find; with area and environment lights BSDF sampling does reach them, and
//! without the rule those paths would be counted twice. Both halves are unbiased, so their sum
//! is. The film holds the sum already: a pixel is its camera samples' mean (W/m²/sr) plus the
//! light paths' splats divided by their number.
//!
//! Work: under a time budget the light tracer has the first `--light-share` of it (0.5 by
//! default, measured in docs/results/hybrid) and the path tracer the rest; with a fixed amount
//! of work, `--light-paths` light paths (by default [`LIGHT_PATHS_PER_SAMPLE`] per camera sample)
//! and `--spp` camera samples per pixel. Shards split the light paths by chunks and the camera
//! samples by rows ([`crate::shard::ShardUnit::SplatChunks`]).

use super::light_tracer::{Connect, trace_light_path_with};
use super::path::{CameraRule, camera_radiance};
use crate::control::Stage;
use crate::driver::light_paths::render_paths;
use crate::driver::pixels::render_pixels_batched;
use crate::film::Film;
use crate::filter::Filter;
use crate::options::RenderOptions;
use crate::stats::RenderStats;
use crate::transport::emission::caustic_emission_notes;
use caustica_scene::Scene;
use std::time::Instant;

/// Light paths per camera sample when `--light-paths` is not given.
pub const LIGHT_PATHS_PER_SAMPLE: f64 = 0.5;

/// The camera side's rule: the path tracer without the light tracer's paths E D … S L.
pub struct BesideLightTracer;

impl CameraRule for BesideLightTracer {
    fn light_tracer_beside(&self) -> bool {
        true
    }
}

/// The light paths of a render with a fixed amount of work: `--light-paths`, or
/// [`LIGHT_PATHS_PER_SAMPLE`] per camera sample of the full film (at least one).
pub fn light_paths(scene: &Scene, opts: &RenderOptions) -> u64 {
    opts.photons.light_paths.unwrap_or_else(|| {
        let samples = opts.spp as f64 * scene.camera.width as f64 * scene.camera.height as f64;
        ((samples * LIGHT_PATHS_PER_SAMPLE).round() as u64).max(1)
    })
}

/// Renders `scene` into `film`: the light paths first, then the camera samples.
pub fn render(
    scene: &Scene,
    opts: &RenderOptions,
    stage: &Stage,
    film: &mut Film,
    filter: &Filter,
    notes: &mut Vec<String>,
) -> RenderStats {
    let share = opts.photons.light_share.get() as f64;
    let started = Instant::now();
    let paths = super::light_path_range(light_paths(scene, opts), opts.shard);
    let light_stage = stage.part(0.0, share).labelled("tracing light paths");
    let mut stats = render_paths(film, paths, opts, &light_stage, |sampler, out, st| {
        trace_light_path_with(
            scene,
            sampler,
            opts,
            Connect::SpecularFirst,
            filter,
            out,
            st,
        )
    });
    let light_secs = started.elapsed().as_secs_f64();
    let traced = film.light_paths();
    let rule = opts.photons.emission.caustic_rule();
    notes.extend(caustic_emission_notes(
        scene,
        rule,
        stats.caustic_vertices as usize,
        traced,
    ));
    let started = Instant::now();
    let camera_stage = stage.part(share, 1.0).labelled("path tracing");
    let ext = scene.camera.screen_half_extent();
    stats += render_pixels_batched(
        film,
        filter,
        opts,
        &camera_stage,
        |sampler, raster, b, st| {
            camera_radiance(scene, raster, ext, sampler, opts, st, &BesideLightTracer, b)
        },
    );
    notes.push(format!(
        "hybrid: {traced} light paths in {light_secs:.2} s, {:.1} camera samples per pixel in {:.2} s",
        film.mean_samples(),
        started.elapsed().as_secs_f64()
    ));
    stats
}
