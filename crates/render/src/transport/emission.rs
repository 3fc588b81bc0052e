//! How a light path starts: which light, which emitted ray, with what flux.
//!
//! Uniform emission chooses a light in proportion to power and gives the light's own
//! `sample_emission` uniform primary samples. Guided emission ([`Emission::Projection`]) draws
//! the same numbers from the scene's projection maps
//! ([`caustica_scene::light::projection_map`]): most light paths go where the first surface
//! is a mirror, glass or smooth metal, with their flux divided by the relative density, so
//! every estimate keeps its expectation (the caustic passes use it; global photons stay
//! uniform, a map of diffuse interreflection needs every direction).

use caustica_core::Vec2;
use caustica_scene::Scene;
use caustica_scene::light::{EmissionDensity, EmissionSample};

/// The emission rule of a light path.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Emission {
    /// Light by power, uniform primary samples.
    #[default]
    Uniform,
    /// The projection maps' defensive mixture (uniform where the scene's map is empty).
    Projection,
}

/// The render note of a caustic pass that stored `photons` from `paths` light paths emitted by
/// `rule`: the rule, the projection map's size and build time, and the caustic yield (photons
/// per light path). Warnings of the map (no marked cell, lights skipped) follow as
/// `warning:` notes.
pub fn caustic_emission_notes(
    scene: &Scene,
    rule: Emission,
    photons: usize,
    paths: u64,
) -> Vec<String> {
    let yield_ = format!(
        "caustic yield {:.2} % ({photons} photons from {paths} light paths)",
        100.0 * photons as f64 / paths.max(1) as f64
    );
    match rule {
        Emission::Uniform => vec![format!("caustic emission: uniform; {yield_}")],
        Emission::Projection => {
            let map = scene.projection_map();
            let mut notes = vec![format!(
                "caustic emission: projection map, {} of {} cells marked ({:.2} % of the emitted power), built in {:.2} s from {} test rays; {yield_}",
                map.marked_cells(),
                map.total_cells(),
                100.0 * map.marked_fraction(),
                map.build_secs,
                map.test_rays,
            )];
            notes.extend(map.warnings.iter().map(|w| format!("warning: {w}")));
            notes
        }
    }
}

/// A light path's start before the walker traces it.
pub struct Emitted {
    pub light: usize,
    /// Probability of the light under uniform (power-proportional) choice.
    pub pmf: f32,
    /// The light's sample: `weight` is already divided by the relative density.
    pub es: EmissionSample,
    /// The guided emission's relative density against uniform (1, 1 for uniform emission).
    pub density: EmissionDensity,
}

/// The start of a light path for primary samples `u_light`, `u_pos`, `u_dir` under `rule`;
/// `None` when the scene has no light with power or the sample carries nothing.
pub fn emit(
    scene: &Scene,
    rule: Emission,
    u_light: f32,
    u_pos: Vec2,
    u_dir: Vec2,
) -> Option<Emitted> {
    let dist = scene.light_distribution.as_ref()?;
    let guided = match rule {
        Emission::Uniform => None,
        Emission::Projection => scene.projection_map().sample(dist, u_light, u_pos, u_dir),
    };
    let (light, pmf, u_pos, u_dir, density) = match guided {
        Some(g) => (g.light, g.pmf, g.u_pos, g.u_dir, g.density),
        None => {
            let (li, pmf, _) = dist.sample(u_light);
            (li, pmf, u_pos, u_dir, EmissionDensity::UNIFORM)
        }
    };
    let mut es = scene.lights[light].sample_emission(u_pos, u_dir);
    let p = density.total();
    if es.pdf_pos <= 0.0 || es.pdf_dir <= 0.0 || es.weight.is_black() || p <= 0.0 || p.is_nan() {
        return None;
    }
    es.weight /= p;
    Some(Emitted {
        light,
        pmf,
        es,
        density,
    })
}
