//! What a render will allocate, estimated before it allocates anything (bytes), so that a render
//! too large for the machine is refused with the figure and the option that lowers it instead
//! of aborting in the allocator.
//!
//! The estimate is an upper bound of the large allocations, each from its count and the size of
//! its record: the film (per pixel), the photon maps (the photon pass reserves its target up
//! front, [`crate::photon::plan::Cut`]), the footprints of `pdm` (landings and photons alive
//! together while the map is built) and the eye map of `pds` (at most one vertex per camera
//! sample; the records and the tiles built from them are alive together, plus one accumulator
//! per vertex). Film and eye map count the crop window's pixels only. Scene geometry is already allocated when a render starts, so it is not counted.

use crate::integrator::IntegratorKind;
use crate::options::RenderOptions;
use crate::photon::bandwidth_choice as choice;
use crate::photon::differential::volume_trace::{Ellipsoid, VolumeLanding};
use crate::photon::differential::{DiffPhoton, Landing, RECORD_LANDING_PATHS};
use crate::photon::eye_map::EyeVertex;
use crate::photon::plan::PhotonBudget;
use crate::photon::tracer::Photon;
use caustica_scene::Scene;
use std::fmt;

/// A film pixel: Σ L and the splat sum (3 exact sums each) and the sample count (u32).
const FILM_PIXEL_BYTES: u64 = 2 * size_of::<[crate::ExactSum; 3]>() as u64 + 4;
use std::mem::size_of;

/// k-d tree bytes per stored point (index and split data; measured: 17 for the photon map).
const TREE_BYTES_PER_POINT: u64 = 24;
/// Per-photon data of the diffusion estimator's pre-pass (gradient, tensors, bandwidths).
const DIFFUSION_BYTES_PER_PHOTON: u64 = 64;

/// The large allocations of a render: `(what, count, bytes)` each, and their sum.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MemoryEstimate {
    pub parts: Vec<MemoryPart>,
}

/// One allocation: `count` records of `bytes_each` bytes, for `what`.
#[derive(Clone, Debug, PartialEq)]
pub struct MemoryPart {
    pub what: &'static str,
    pub count: u64,
    pub bytes_each: u64,
}

impl MemoryPart {
    /// Bytes of this part (saturating).
    pub fn bytes(&self) -> u64 {
        self.count.saturating_mul(self.bytes_each)
    }
}

impl MemoryEstimate {
    /// The sum of the parts (bytes, saturating).
    pub fn total(&self) -> u64 {
        self.parts
            .iter()
            .fold(0u64, |a, p| a.saturating_add(p.bytes()))
    }

    /// The largest part.
    pub fn largest(&self) -> Option<&MemoryPart> {
        self.parts.iter().max_by_key(|p| p.bytes())
    }

    fn add(&mut self, what: &'static str, count: u64, bytes_each: u64) {
        self.parts.push(MemoryPart {
            what,
            count,
            bytes_each,
        });
    }
}

/// `bytes` for people: "1.2 GB", "35.0 MB", "512 kB".
pub fn human_bytes(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else if b >= 1e6 {
        format!("{:.1} MB", b / 1e6)
    } else {
        format!("{:.0} kB", b / 1e3)
    }
}

impl fmt::Display for MemoryEstimate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "about {}", human_bytes(self.total()))?;
        let parts: Vec<String> = self
            .parts
            .iter()
            .filter(|p| p.bytes() > 0)
            .map(|p| {
                format!(
                    "{} {} ({} × {} B)",
                    p.what,
                    human_bytes(p.bytes()),
                    p.count,
                    p.bytes_each
                )
            })
            .collect();
        if !parts.is_empty() {
            write!(f, ": {}", parts.join(", "))?;
        }
        Ok(())
    }
}

/// Photons a pass may store under `budget`: its target, or for a fixed number of light paths
/// `per_path` per path (a caustic path ends at its first non-delta vertex: one photon).
fn photon_count(budget: PhotonBudget, per_path: u64) -> u64 {
    match budget {
        PhotonBudget::Records(n) => n as u64,
        PhotonBudget::Paths(n) => n.saturating_mul(per_path),
    }
}

/// The estimate for rendering `scene` with `kind` and `opts`.
pub fn estimate(kind: IntegratorKind, scene: &Scene, opts: &RenderOptions) -> MemoryEstimate {
    if let Some(one_shot) = crate::integrator::progressive::one_shot(kind) {
        // One iteration alive at a time, plus the pooled film.
        let mut m = estimate(
            one_shot,
            scene,
            &opts.photons.progressive.iteration_options(opts, 1),
        );
        let pixels = opts.window(&scene.camera).map_or(
            scene.camera.width as u64 * scene.camera.height as u64,
            |w| w.pixels(),
        );
        m.add("pooled film", pixels, FILM_PIXEL_BYTES);
        return m;
    }
    let mut m = MemoryEstimate::default();
    if matches!(
        kind,
        IntegratorKind::StochasticProgressivePhotonMapping
            | IntegratorKind::ProgressivePhotonMappingHitPoints
    ) {
        let pixels = opts.window(&scene.camera).map_or(
            scene.camera.width as u64 * scene.camera.height as u64,
            |w| w.pixels(),
        );
        // The pooled and the iteration's film, the visible points (records and tiles) with
        // their accumulators, and the statistics (R², N, τ) of every pixel.
        m.add("films", pixels, 2 * FILM_PIXEL_BYTES);
        m.add(
            "visible points",
            pixels.saturating_mul(opts.spp as u64),
            2 * size_of::<EyeVertex>() as u64 + 32,
        );
        m.add("pixel statistics", pixels, 40);
        return m;
    }
    // The pixels rendered: the crop window's (an invalid window is refused before rendering).
    let pixels = opts.window(&scene.camera).map_or(
        scene.camera.width as u64 * scene.camera.height as u64,
        |w| w.pixels(),
    );
    m.add("film", pixels, FILM_PIXEL_BYTES);
    if !kind.uses_photons() {
        return m;
    }
    let p = &opts.photons;
    if kind == IntegratorKind::PhotonConeFocusing {
        // About three vertices per light path and a cone per technique at each (an upper
        // estimate for the triplet), each with its k-d tree entry and axis byte; the
        // iteration's film; the importon map (about two per camera path).
        let paths = p.progressive.paths_per_iteration;
        m.add("iteration film", pixels, FILM_PIXEL_BYTES);
        m.add(
            "cone map",
            paths.saturating_mul(9),
            size_of::<crate::pcf::PhotonCone>() as u64 + 17,
        );
        if p.pcf.techniques_for(scene).importons {
            m.add(
                "importon map",
                p.pcf.importon_paths.unwrap_or(paths).saturating_mul(2),
                size_of::<crate::pcf::ConicalImporton>() as u64 + 17,
            );
        }
        return m;
    }
    let photon = size_of::<Photon>() as u64 + TREE_BYTES_PER_POINT;
    if (p.global_photons > 0 || p.global_light_paths.is_some())
        && !opts.caustics_only
        && !opts.volume_only
    {
        // A path stores a photon at each non-delta hit; Russian roulette ends most within a
        // few bounces (an estimate, not a bound, for fixed path budgets).
        m.add("global map", photon_count(p.global_budget(), 4), photon);
    }
    let caustic = if opts.volume_only {
        0
    } else {
        photon_count(p.caustic_budget(), 1)
    };
    if !opts.caustics_only && scene.media.iter().any(|m| !m.sigma_s.is_black()) {
        if kind == IntegratorKind::VolumePhotonDifferentials {
            // Record while tracing, photon, ellipsoid, bound and about two BVH nodes per photon.
            m.add(
                "volume photon differentials",
                p.volume.photons as u64,
                (size_of::<VolumeLanding>() + size_of::<Photon>() + size_of::<Ellipsoid>()) as u64
                    + 4
                    + 2 * 32,
            );
        } else {
            // Photon, radius, k-d tree node and about two BVH nodes per photon.
            m.add("volume map", p.volume.photons as u64, photon + 4 + 2 * 32);
        }
    }
    match kind {
        IntegratorKind::PhotonMapping
        | IntegratorKind::VolumetricPhotonMapping
        | IntegratorKind::BeamRadianceEstimate => m.add("caustic map", caustic, photon),
        IntegratorKind::DiffusionPhotonMapping => m.add(
            "caustic map with diffusion data",
            caustic,
            photon + DIFFUSION_BYTES_PER_PHOTON,
        ),
        IntegratorKind::PhotonDifferentialMapping | IntegratorKind::VolumePhotonDifferentials => m
            .add(
                "caustic footprints",
                caustic,
                (size_of::<Landing>() + size_of::<DiffPhoton>()) as u64 + TREE_BYTES_PER_POINT,
            ),
        IntegratorKind::PhotonDifferentialSplatting => {
            let samples = pixels.saturating_mul(opts.spp as u64);
            // Records and tiles alive together while the map is built, and an accumulator each.
            m.add(
                "eye map",
                samples,
                2 * size_of::<EyeVertex>() as u64
                    + size_of::<crate::integrator::photon_splatting::ChunkedSum>() as u64,
            );
            if let PhotonBudget::Records(n) = p.caustic_budget()
                && n <= RECORD_LANDING_PATHS
            {
                // The landing paths noted by the count (8 bytes each, one per landing at most).
                m.add("landing paths", n as u64, 8);
            }
        }
        IntegratorKind::Path
        | IntegratorKind::LightTrace
        | IntegratorKind::Hybrid
        | IntegratorKind::ProgressivePhotonMapping
        | IntegratorKind::ProgressiveSplatting
        | IntegratorKind::ProgressiveDifferentialMapping
        | IntegratorKind::ProgressiveDiffusion => {}
        IntegratorKind::StochasticProgressivePhotonMapping
        | IntegratorKind::ProgressivePhotonMappingHitPoints => {}
        IntegratorKind::PhotonConeFocusing => {}
    }
    if choice::chooses(kind, p) && !opts.volume_only {
        // The automatic bandwidth choice (freed before the photon pass; counted anyway, as an
        // upper bound): the pilot map (footprints for pdm and pds), the scored camera vertices,
        // and the hold-out image with the splat buffers of one wave.
        let pilot = (caustic.min(choice::PILOT_PHOTONS as u64), {
            if kind.uses_photon_differentials() {
                2 * size_of::<DiffPhoton>() as u64 + TREE_BYTES_PER_POINT
            } else {
                photon + DIFFUSION_BYTES_PER_PHOTON
            }
        });
        m.add("bandwidth choice: pilot photons", pilot.0, pilot.1);
        m.add(
            "bandwidth choice: camera vertices",
            pixels.min(choice::SCORED_PIXELS as u64) * choice::RAYS_PER_PIXEL as u64,
            choice::CELL_BYTES,
        );
        m.add(
            "bandwidth choice: hold-out images",
            pixels,
            choice::HOLDOUT_WAVE * size_of::<[f32; 3]>() as u64
                + 2 * size_of::<[f64; 3]>() as u64
                + 4
                + size_of::<[f32; 3]>() as u64,
        );
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_add_up_and_saturate() {
        let mut m = MemoryEstimate::default();
        m.add("a", 10, 3);
        m.add("b", 2, 5);
        assert_eq!(m.total(), 40);
        assert_eq!(m.largest().map(|p| p.what), Some("a"));
        m.add("huge", u64::MAX, 2);
        assert_eq!(m.total(), u64::MAX);
        assert_eq!(human_bytes(1_500_000_000), "1.5 GB");
        assert_eq!(human_bytes(35_000_000), "35.0 MB");
    }
}
