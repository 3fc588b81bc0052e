//! Settings of the photon-mapping family: `pm`, `dpm`, `pdm` and `pds`.

use crate::error::OptionError;
use crate::options::value::{
    Bandwidth, Diffusivity, NoiseScale, NormalDistance, Smoothing, Steepness,
};
use crate::photon::map::EstimateOptions;
use crate::photon::plan::PhotonBudget;
use crate::photon::volume_map::VolumeSettings;
use caustica_density::kernel::Kernel;

/// Settings of the photon-mapping integrators.
#[derive(Clone, Debug, PartialEq)]
pub struct PhotonOptions {
    /// Caustic photons (L S+ D) the caustic pass stores or splats: light paths are emitted until
    /// it holds this many; ≥ 1. Ignored when `light_paths` is set.
    pub caustic_photons: usize,
    /// A fixed number of light paths for the caustic pass instead (seed 002's N_e): exactly this
    /// many are emitted, whatever they store; ≥ 1.
    pub light_paths: Option<u64>,
    /// Photons stored in the global map (every non-delta hit); 0 = no indirect light.
    /// Ignored when `global_light_paths` is set.
    pub global_photons: usize,
    /// A fixed number of light paths for the global pass instead (a progressive iteration's
    /// budget); ≥ 1.
    pub global_light_paths: Option<u64>,
    /// The first light path of every photon pass: each stream's paths from `first_path` on are
    /// traced (0 for a one-shot render; an iteration's window for the progressive methods, so
    /// iterations use disjoint, independent light paths).
    pub first_path: u64,
    /// A fixed gather radius (m) for the global map's estimate instead of its k-NN radius
    /// (the progressive methods shrink it with the caustic bandwidth, so the global estimate
    /// is consistent too).
    pub global_bandwidth: Option<Bandwidth>,
    /// The photon-map radiance estimate (k, maximum radius, kernel, bias controls), used for
    /// both maps.
    pub estimate: EstimateOptions,
    /// Photons per estimate in the global map, when it should differ from `estimate.k` (the
    /// caustic map's); `None` = the same k; ≥ 1.
    pub global_k: Option<usize>,
    /// Final-gather rays per camera sample; 0 = visualise the global map directly.
    pub final_gather: u32,
    /// The density estimator of `pm`'s caustic map; `None` = the integrator's own (k-NN for
    /// `pm`, diffusion for `dpm`; `pdm` and `pds` estimate caustics from footprints and refuse
    /// any other).
    pub caustic_estimator: Option<CausticEstimator>,
    /// Fixed bandwidth h (m) of the `fixed` and diffusion estimators; `None` = the median
    /// distance from a caustic photon to its k-th nearest neighbour (k = `estimate.k`).
    pub bandwidth: Option<Bandwidth>,
    /// Parameters of the diffusion estimator (`dpm`).
    pub diffusion: DiffusionSettings,
    /// Photon-differential footprints (`pdm`, `pds`).
    pub footprints: FootprintSettings,
    /// Which bandwidths the render chooses from the traced photons
    /// ([`crate::photon::bandwidth_choice`]) instead of taking the value above. Off by default:
    /// a library caller gets exactly the values it sets; the command line turns each on when
    /// neither it nor the scene gives that value.
    pub auto: AutoBandwidth,
    /// The volume photon map of scenes with scattering media (every photon method): how many
    /// photons, which estimate along camera rays, its k, radius, kernel and step.
    pub volume: VolumeSettings,
    /// Time-dependent photon mapping (Cammarano and Jensen 2002 as seed 000 sec. 7.2 and seed
    /// 003 sec. 3 use it): in a moving scene the photon maps' light paths are traced at
    /// `1 + n` evenly spaced times over the shutter (`n` in-between frames; 0 = plain photon
    /// mapping at the frame instant), each path at one of them, and the k-NN estimate pools
    /// all of them. `None`: each path at a time uniform over the shutter (the continuous
    /// limit).
    pub in_between_frames: Option<u32>,
    /// The progressive methods' iterations and schedule (`pppm`, `ppds`, `ppdm`).
    pub progressive: super::ProgressiveSettings,
    /// Photon cone focusing's own settings (`pcf`; its iterations are `progressive`'s).
    pub pcf: super::PcfSettings,
    /// How the caustic passes (and the light tracer's `--caustics-only` mode) emit their light
    /// paths (`--emission`); global and volume photons are always emitted uniformly.
    pub emission: EmissionStrategy,
    /// The `hybrid` integrator's share of a time budget for its light tracer
    /// (`--light-share`).
    pub light_share: super::LightShare,
}

/// How caustic light paths are emitted (`--emission`; docs/emission.md). The default is
/// projection maps, measured best (docs/results/emission-equal-time).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EmissionStrategy {
    /// Light by power, uniform over its directions and area.
    Uniform,
    /// Projection maps (Jensen 1996): mostly into the emission cells that reach mirrors, glass
    /// and smooth metal, with a defensive uniform share (unbiased).
    #[default]
    Projection,
    /// Visibility-driven adaptive photon tracing (Hachisuka and Jensen 2011) over projection
    /// emission: Markov chains in primary sample space toward paths that reach visible points.
    Adaptive,
}

impl EmissionStrategy {
    /// The names `--emission` accepts, in order.
    pub const NAMES: [&'static str; 3] = ["uniform", "projection", "adaptive"];

    /// Parses a name of [`Self::NAMES`].
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "uniform" => Some(Self::Uniform),
            "projection" => Some(Self::Projection),
            "adaptive" => Some(Self::Adaptive),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Uniform => "uniform",
            Self::Projection => "projection",
            Self::Adaptive => "adaptive",
        }
    }

    /// The walker's emission rule for caustic light paths (the adaptive sampler's chains run
    /// over projection emission).
    pub fn caustic_rule(self) -> crate::transport::Emission {
        match self {
            Self::Uniform => crate::transport::Emission::Uniform,
            Self::Projection | Self::Adaptive => crate::transport::Emission::Projection,
        }
    }
}

impl PhotonOptions {
    /// The time rule of the photon maps' light paths ([`Self::in_between_frames`]).
    pub fn photon_time(&self) -> crate::transport::PathTime {
        match self.in_between_frames {
            Some(n) => crate::transport::PathTime::Slices(n.saturating_add(1)),
            None => crate::transport::PathTime::Shutter,
        }
    }
}

/// Bandwidths chosen automatically, by least-squares cross-validation of the image
/// ([`crate::photon::bandwidth_choice`]); each flag replaces one fixed value.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AutoBandwidth {
    /// `estimate.k` of the caustic map (`pm` with the k-NN or variable estimator); the global
    /// map keeps the fixed k.
    pub k: bool,
    /// `bandwidth` (`pm --estimator fixed`, `dpm`).
    pub bandwidth: bool,
    /// `diffusion.q` (`dpm`).
    pub q: bool,
    /// `footprints.smoothing` (`pdm`, `pds`).
    pub smoothing: bool,
}

impl AutoBandwidth {
    /// Every bandwidth automatic.
    pub const ALL: AutoBandwidth = AutoBandwidth {
        k: true,
        bandwidth: true,
        q: true,
        smoothing: true,
    };

    /// True if any bandwidth is automatic.
    pub fn any(self) -> bool {
        self.k || self.bandwidth || self.q || self.smoothing
    }
}

impl Default for PhotonOptions {
    fn default() -> Self {
        Self {
            caustic_photons: 200_000,
            light_paths: None,
            global_photons: 100_000,
            global_light_paths: None,
            first_path: 0,
            global_bandwidth: None,
            estimate: EstimateOptions::default(),
            global_k: None,
            final_gather: 16,
            caustic_estimator: None,
            bandwidth: None,
            diffusion: DiffusionSettings::default(),
            footprints: FootprintSettings::default(),
            auto: AutoBandwidth::default(),
            volume: VolumeSettings::default(),
            in_between_frames: None,
            progressive: Default::default(),
            pcf: Default::default(),
            emission: EmissionStrategy::default(),
            light_share: super::LightShare::DEFAULT,
        }
    }
}

impl PhotonOptions {
    /// How many light paths the caustic pass emits.
    pub fn caustic_budget(&self) -> PhotonBudget {
        match self.light_paths {
            Some(n) => PhotonBudget::Paths(n),
            None => PhotonBudget::Records(self.caustic_photons),
        }
    }

    /// How many light paths the global pass emits.
    pub fn global_budget(&self) -> PhotonBudget {
        match self.global_light_paths {
            Some(n) => PhotonBudget::Paths(n),
            None => PhotonBudget::Records(self.global_photons),
        }
    }

    /// One kernel for every density estimate: the photon maps' (eq. 3.2) and the footprints'
    /// (seed 002 eq. 10). Without it each keeps its default (Epanechnikov, Silverman).
    pub fn set_kernel(&mut self, kernel: Kernel) {
        self.estimate.kernel = kernel;
        self.footprints.kernel = kernel;
    }

    /// Checks the counts (the other values are valid by their types); the message names the
    /// offending option.
    pub fn validate(&self) -> Result<(), OptionError> {
        let at_least_one = |what: &'static str, n: u64| {
            if n >= 1 {
                Ok(())
            } else {
                Err(OptionError::Invalid {
                    what,
                    rule: "at least 1",
                    got: n.to_string(),
                })
            }
        };
        at_least_one(
            "the number of caustic photons (--photons)",
            self.caustic_photons as u64,
        )?;
        if let Some(n) = self.light_paths {
            at_least_one("the number of light paths (--light-paths)", n)?;
        }
        at_least_one("the photons per estimate (--k)", self.estimate.k as u64)?;
        if let Some(k) = self.global_k {
            at_least_one(
                "the photons per estimate of the global map (--global-k)",
                k as u64,
            )?;
        }
        at_least_one(
            "the number of volume photons (--volume-photons)",
            self.volume.photons as u64,
        )?;
        at_least_one(
            "the photons per volume estimate (--volume-k)",
            self.volume.k as u64,
        )?;
        for (what, v) in [
            (
                "the volume photon radius (--volume-radius)",
                self.volume.radius,
            ),
            ("the march step (--march-step)", self.volume.step),
        ] {
            if let Some(r) = v
                && !(r.is_finite() && r > 0.0)
            {
                return Err(OptionError::Invalid {
                    what,
                    rule: "a positive finite length",
                    got: r.to_string(),
                });
            }
        }
        if let Some(r) = self.estimate.max_radius
            && !(r.is_finite() && r > 0.0)
        {
            return Err(OptionError::Invalid {
                what: "the maximum radius (--max-radius)",
                rule: "a positive finite length",
                got: r.to_string(),
            });
        }
        Ok(())
    }

    /// The estimate of the global map: the caustic map's, with `global_k` if set.
    pub fn global_estimate(&self) -> EstimateOptions {
        let mut est = self.estimate;
        if let Some(k) = self.global_k {
            est.k = k;
        }
        est
    }
}

/// Density estimators the caustic map can use (all behind `caustica_density::Estimator`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CausticEstimator {
    /// k-th nearest neighbour, eq. 3.2 (`pm`).
    #[default]
    Knn,
    /// Fixed bandwidth, eq. 2.15.
    Fixed,
    /// Variable bandwidth with a k-NN pilot (k = `estimate.k`), eq. 2.13.
    Variable,
    /// Diffusion-based photon mapping, eq. 4.19 (`dpm`).
    Diffusion,
}

impl CausticEstimator {
    pub const NAMES: &'static [&'static str] = &["knn", "fixed", "variable", "diffusion"];

    pub fn name(self) -> &'static str {
        match self {
            CausticEstimator::Knn => "knn",
            CausticEstimator::Fixed => "fixed",
            CausticEstimator::Variable => "variable",
            CausticEstimator::Diffusion => "diffusion",
        }
    }
}

impl std::str::FromStr for CausticEstimator {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "knn" => Ok(Self::Knn),
            "fixed" => Ok(Self::Fixed),
            "variable" => Ok(Self::Variable),
            "diffusion" | "dpm" => Ok(Self::Diffusion),
            _ => Err(format!(
                "unknown estimator '{s}' (expected one of: {})",
                Self::NAMES.join(", ")
            )),
        }
    }
}

/// Settings of diffusion-based photon mapping (seed 000 ch. 4); the bandwidth is
/// [`PhotonOptions::bandwidth`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffusionSettings {
    /// Noise scale σ (m) of the gradient pre-pass; `None` = half the bandwidth.
    pub noise_scale: Option<NoiseScale>,
    /// Diffusivity coefficient q (eq. 4.15).
    pub q: Diffusivity,
    /// Steepness α (eq. 4.15).
    pub alpha: Steepness,
    /// Isotropic diffusion (sec. 4.3.3).
    pub isotropic: bool,
}

impl Default for DiffusionSettings {
    /// q = 0.2, α = 1 as in seed 000 fig. 4.6.
    fn default() -> Self {
        Self {
            noise_scale: None,
            q: Diffusivity::new(0.2).expect("0.2 is positive"),
            alpha: Steepness::new(1.0).expect("1 is positive"),
            isotropic: false,
        }
    }
}

/// Settings of photon-differential footprints (`pdm`, `pds`; seed 002 sec. 3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FootprintSettings {
    /// Radial kernel of the footprints; seed 002 eq. 11's Silverman kernel by default.
    pub kernel: Kernel,
    /// Smoothing parameter s (seed 002 eq. 5–6).
    pub smoothing: Smoothing,
    /// Normal-distance threshold against topological bias (seed 002 sec. 3.3): a footprint
    /// does not reach a point farther than this fraction of its gather radius from its tangent
    /// plane, `|n_p · (x − x_p)| > t · r_max`.
    pub normal_distance: NormalDistance,
    /// The smallest principal semi-axis a footprint may have (m): narrower footprints are
    /// widened to it ([`caustica_differentials::Footprint::widened`]; against fireflies from
    /// footprints collapsed near a caustic fold). None by default, as seed 002. The progressive
    /// methods shrink it with the smoothing.
    pub min_semi_axis: Option<f32>,
    /// Temporal photon differentials (seed 003; seed 000 ch. 7): photons traced at the shutter's
    /// opening carry `D_t x` over the shutter's length (seed 003's exposure e, frames), and
    /// their footprints are swept along it. Off: in a moving scene each photon has a time
    /// uniform over the shutter.
    pub temporal: bool,
    /// How temporal footprints are swept and weighted along their motion (alignment, time
    /// filter, area): seed 000 eq. 7.7–7.9.
    pub sweep: SweepRule,
    /// Wavelength photon differentials (issue 22; spectral mode): `Some(K)` gives each caustic
    /// photon a third differential parameter, its wavelength, so that past a dispersive
    /// interface its footprint is swept along the dispersion fan over its share of the
    /// spectrum, `Δλ = K s / (N_e p(λ))` (the one-dimensional reading of seed 002 eq. 5–6:
    /// `N_e p(λ)` photons per nm near λ, times the smoothing s), centred on its wavelength.
    /// `K = 1` is that rule; larger K trade colour noise for spectral blur. Off by default.
    pub wavelength_spread: Option<f32>,
}

/// Where the shutter lies relative to the instant temporal photon differentials are traced at
/// (seed 000 Q-T8).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShutterAlign {
    /// Seed 003 eq. 5: photons traced at the shutter's opening, the footprint swept forward
    /// from the hit, `[x, x + D_t x]`.
    #[default]
    Forward,
    /// Photons traced at the middle of the shutter, the footprint swept over
    /// `[x − D_t x/2, x + D_t x/2]` (seed 000 sec. 7.1.2: "we could just as well have placed
    /// the time dependent kernel centered over the photon intersection point"); first-order
    /// error O(e²) instead of O(e) for accelerating motion.
    Centred,
}

impl ShutterAlign {
    /// Start of the motion segment in units of `D_t x` from the photon's hit: 0 or −½.
    pub fn segment_start(self) -> f32 {
        match self {
            ShutterAlign::Forward => 0.0,
            ShutterAlign::Centred => -0.5,
        }
    }

    /// Where the time of the traced instant lies on the segment `τ ∈ [0, 1]`: 0 or ½.
    pub fn instant_on_segment(self) -> f32 {
        -self.segment_start()
    }
}

/// How a temporal footprint is weighted along its motion segment.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SweepRule {
    /// The shutter's alignment (forward, eq. 5, by default).
    pub align: ShutterAlign,
    /// The time filter of seed 000 eq. 7.9: a univariate kernel (Table 2.1) of the segment
    /// parameter, peaking at the traced instant and normalised over the segment (Q-T4/Q-T5), so
    /// the part of the footprint closest in time to the photon weighs most; `None`: eq. 7.8.
    pub time_filter: Option<Kernel>,
    /// Divide by eq. 7.7's area `A + l |D_t x|` for every kernel, as the text does, instead of
    /// the swept mass of the kernel (which conserves each photon's flux; eq. 7.7 over-counts
    /// non-uniform kernels by up to 4/3 for Epanechnikov and 8/5 for Silverman). For
    /// comparisons with the paper only.
    pub paper_area: bool,
}

impl Default for FootprintSettings {
    fn default() -> Self {
        Self {
            kernel: Kernel::Silverman,
            smoothing: Smoothing::ONE,
            normal_distance: NormalDistance::QUARTER,
            min_semi_axis: None,
            temporal: false,
            sweep: SweepRule::default(),
            wavelength_spread: None,
        }
    }
}

impl FootprintSettings {
    /// The time rule of the caustic light paths: the frame instant (or the shutter's middle,
    /// centred) for temporal photon differentials, else uniform over the shutter.
    pub fn path_time(&self) -> crate::transport::PathTime {
        if self.temporal {
            match self.sweep.align {
                ShutterAlign::Forward => crate::transport::PathTime::Instant,
                ShutterAlign::Centred => crate::transport::PathTime::Middle,
            }
        } else {
            crate::transport::PathTime::Shutter
        }
    }
}
