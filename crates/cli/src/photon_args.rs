//! Command-line settings of the photon-mapping integrators (`--integrator pm`).

use anyhow::Result;
use caustica_density::beam::BeamKernel;
use caustica_density::kernel::Kernel;
use caustica_render::{
    AutoBandwidth, Bandwidth, CausticEstimator, Diffusivity, EmissionStrategy, LightShare,
    NoiseScale, NormalDistance, PhotonOptions, Smoothing, Steepness,
};
use clap::Args;

#[derive(Args, Clone, Debug, Default)]
pub struct PhotonArgs {
    /// Caustic photons: stored in the caustic map (pm, dpm, pdm) or splatted (pds): light paths
    /// are emitted until this many land (default 200000; at least 1).
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Photon mapping",
        conflicts_with = "light_paths"
    )]
    pub photons: Option<usize>,
    /// Emit exactly N light paths for the caustic photons instead of --photons (N_e of Frisvad et al. 2014;
    /// at least 1). pds then needs no counting pass.
    #[arg(
        long,
        value_name = "N",
        allow_negative_numbers = true,
        help_heading = "Photon mapping"
    )]
    pub light_paths: Option<u64>,
    /// Photons stored in the global map (pm; default 100000; 0 = no indirect light).
    #[arg(long, allow_negative_numbers = true, help_heading = "Photon mapping")]
    pub global_photons: Option<usize>,
    /// Photons per radiance estimate, k nearest (at least 1). Default for the caustic map of pm:
    /// chosen from the traced photons by least-squares cross-validation (Rudemo 1982, Silverman
    /// 1986 eq. 3.39; see docs/automatic-bandwidths.md); 50 for the global map.
    #[arg(long, allow_negative_numbers = true, help_heading = "Photon mapping")]
    pub k: Option<usize>,
    /// Photons per estimate in the global map (default: the same as --k; at least 1).
    #[arg(long, allow_negative_numbers = true, help_heading = "Photon mapping")]
    pub global_k: Option<usize>,
    /// Largest gather radius in scene units (default: unbounded; a positive finite length).
    #[arg(long, allow_negative_numbers = true, help_heading = "Photon mapping")]
    pub max_radius: Option<f32>,
    /// Kernel of every density estimate: uniform, epanechnikov, biweight, gaussian, cone,
    /// cone:G (G >= 1), silverman, cubic. Default: epanechnikov for the photon maps, silverman
    /// for the footprints of pdm and pds.
    #[arg(long, help_heading = "Photon mapping")]
    pub kernel: Option<Kernel>,
    /// Final-gather rays per camera sample (default 16; 0 = show the global map directly).
    #[arg(long, allow_negative_numbers = true, help_heading = "Photon mapping")]
    pub final_gather: Option<u32>,
    /// Project photons onto the tangent plane before measuring distances (Schjøth 2009 app. A).
    #[arg(long, help_heading = "Photon mapping")]
    pub tangent_projection: bool,
    /// Reject photons whose normal or plane distance differs from the query's.
    #[arg(long, help_heading = "Photon mapping")]
    pub disc_test: bool,
    /// Density estimator of the caustic map: knn (pm's default), fixed, variable (k-NN pilot),
    /// diffusion (dpm's).
    #[arg(long, help_heading = "Photon mapping")]
    pub estimator: Option<CausticEstimator>,
    /// Fixed bandwidth h in scene units of the fixed and diffusion estimators (a positive finite
    /// length). Default: chosen from the traced photons by least-squares cross-validation
    /// (Silverman 1986 eq. 3.39; the median distance to the k-th nearest photon if interrupted).
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Diffusion photon mapping (dpm)"
    )]
    pub bandwidth: Option<Bandwidth>,
    /// Diffusivity coefficient q of Schjøth 2009 eq. 4.15 (large = no adaptation; > 0). Default:
    /// chosen with the bandwidth by least-squares cross-validation (0.2 if interrupted).
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Diffusion photon mapping (dpm)"
    )]
    pub q: Option<Diffusivity>,
    /// Steepness alpha of Schjøth 2009 eq. 4.15 (default 1; > 0).
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Diffusion photon mapping (dpm)"
    )]
    pub alpha: Option<Steepness>,
    /// Noise scale of the gradient pre-pass in scene units (default: half the bandwidth; a
    /// positive finite length).
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Diffusion photon mapping (dpm)"
    )]
    pub noise_scale: Option<NoiseScale>,
    /// Isotropic diffusion: a round kernel that shrinks near structure (Schjøth 2009 sec. 4.3.3).
    #[arg(long, help_heading = "Diffusion photon mapping (dpm)")]
    pub isotropic: bool,
    /// Smoothing parameter s of photon differentials (pdm, pds; Frisvad et al. 2014 eq. 5-6): the
    /// emitted footprints overlap s^2 times (a positive finite number). Default: chosen from the
    /// traced photons by least-squares cross-validation (Silverman 1986 eq. 3.39; 1 if
    /// interrupted).
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Photon differentials (pdm, pds)"
    )]
    pub smoothing: Option<Smoothing>,
    /// Normal-distance threshold against topological bias (Frisvad et al. 2014 sec. 3.3): a footprint
    /// does not reach points farther from its tangent plane than this fraction of its gather
    /// radius (default 0.25; >= 0; inf disables the test).
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Photon differentials (pdm, pds)"
    )]
    pub normal_distance: Option<NormalDistance>,
    /// Smallest principal semi-axis of a caustic photon's footprint, in metres: narrower
    /// footprints (those that collapse near a caustic fold and would splat fireflies) are widened
    /// to it, flux kept (default: none, as Frisvad et al. 2014). The progressive methods shrink
    /// it with the smoothing.
    #[arg(
        long,
        value_name = "R",
        allow_negative_numbers = true,
        help_heading = "Photon differentials (pdm, pds)"
    )]
    pub min_footprint: Option<f32>,
    /// With --spectral: wavelength photon differentials. Past a dispersive interface each
    /// caustic photon's footprint is swept along the dispersion fan over K times its share of
    /// the spectrum, K s / (N_e p(λ)) nm (K = 1: seed 002's rule read in one dimension; larger
    /// K trades colour noise for spectral blur). Default: off.
    #[arg(
        long,
        value_name = "K",
        allow_negative_numbers = true,
        help_heading = "Photon differentials (pdm, pds)"
    )]
    pub wavelength_spread: Option<f32>,
    /// Choose no bandwidth automatically: pm's k 50, dpm's bandwidth the median distance to the
    /// 50th nearest photon and q 0.2, pdm's and pds's s 1 (or the scene's smoothing).
    #[arg(long, help_heading = "Photon mapping")]
    pub no_auto_bandwidth: bool,
    /// Volume photons stored in scenes with scattering media (every photon method; default
    /// 100000; at least 1).
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Participating media"
    )]
    pub volume_photons: Option<usize>,
    /// Photons per k-NN volume estimate (vpm) and per pilot radius (beam estimate; default 32).
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Participating media"
    )]
    pub volume_k: Option<usize>,
    /// A fixed radius (m) for every volume photon instead of the k-NN one.
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Participating media"
    )]
    pub volume_radius: Option<f32>,
    /// Step (m) of vpm's ray marching (default: half the median photon radius).
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Participating media"
    )]
    pub march_step: Option<f32>,
    /// Kernel of the beam estimate: epanechnikov (default) or uniform.
    #[arg(long, help_heading = "Participating media")]
    pub beam_kernel: Option<String>,
    /// Smoothing s of the volume photon differentials (vpd; seed 002 eq. 5-6; a positive finite
    /// number; default: --smoothing, the surface footprints').
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Participating media"
    )]
    pub volume_smoothing: Option<Smoothing>,
    /// Smallest semi-axis (m) of a vpd kernel, against fireflies from collapsed footprints
    /// (default: none, as traced; the notes count the kernels it widens).
    #[arg(
        long,
        allow_negative_numbers = true,
        help_heading = "Participating media"
    )]
    pub min_semi_axis: Option<f32>,
    /// vpd kernels from the differential vectors as traced, not projected onto the plane
    /// across the photon's direction (seed 000 sec. 8.4 literally; default: projected).
    #[arg(long, help_heading = "Participating media")]
    pub paper_axes: bool,
    /// Beam estimates weight a kernel by its whole chord (eq. 8.11-8.15 as printed) even where
    /// the ray ends inside it (default: the part of the chord the ray covers).
    #[arg(long, help_heading = "Participating media")]
    pub whole_chord: bool,
    /// What beam and vpd kernels keep where they reach through a surface: open (the part
    /// beyond is lost, as in the thesis; default) or renormalise (each kernel divided by the
    /// fraction of its mass its photon sees: no darkening near walls, floors and the medium's
    /// boundary).
    #[arg(long, value_name = "RULE", help_heading = "Participating media")]
    pub volume_boundary: Option<String>,
    /// vpd photons of collimated light (beam and directional lights) spread like a point
    /// light's photons at smoothing S from their first diffuse or medium scattering on
    /// (default: their directional vectors stay zero, as in the thesis, and light scattered out
    /// of a laser keeps the laser's cross-section).
    #[arg(
        long,
        value_name = "S",
        allow_negative_numbers = true,
        help_heading = "Participating media"
    )]
    pub spread_collimated: Option<Smoothing>,
    /// Temporal photon differentials (seed 003): pdm and pds trace their caustic photons at the
    /// frame (--frame) with a time differential over the shutter (--shutter E frames) and sweep
    /// each footprint along it. Only caustic light is blurred this way; a static scene renders
    /// exactly as without it.
    #[arg(long, help_heading = "Motion")]
    pub temporal: bool,
    /// Time-dependent photon mapping (Cammarano and Jensen 2002, the seeds' baseline): the
    /// photon maps are traced at 1 + N evenly spaced times over the shutter and pooled
    /// (0 = plain photon mapping at the frame). Default: each light path at a time uniform over
    /// the shutter.
    #[arg(long, value_name = "N", help_heading = "Motion")]
    pub in_between_frames: Option<u32>,
    /// Progressive methods (pppm, ppds, ppdm, pdpm, sppm, ppm, pcf): iterations to run (default 16, or as many as
    /// --time allows). --spp is then the camera samples per pixel of each iteration (default 1).
    #[arg(
        long,
        value_name = "N",
        allow_negative_numbers = true,
        help_heading = "Progressive (pppm, ppds, ppdm, pdpm, sppm, ppm, pcf)"
    )]
    pub iterations: Option<u64>,
    /// Light paths each iteration traces for each photon map (default 100000).
    #[arg(
        long,
        value_name = "M",
        allow_negative_numbers = true,
        help_heading = "Progressive (pppm, ppds, ppdm, pdpm, sppm, ppm, pcf)"
    )]
    pub photons_per_iteration: Option<u64>,
    /// The schedule's alpha in (0, 1] (seed 001 eq. 3.27: the kernel's area shrinks by
    /// (i + alpha)/(i + 1) per iteration; default 2/3, Mitsuba 0.6 uses 0.7, 1 keeps it fixed;
    /// pcf: in (0, 1), default 0.5).
    #[arg(
        long,
        value_name = "ALPHA",
        allow_negative_numbers = true,
        help_heading = "Progressive (pppm, ppds, ppdm, pdpm, sppm, ppm, pcf)"
    )]
    pub ppm_alpha: Option<f64>,
    /// First-iteration gather radius in metres of pppm, sppm and ppm (and pdpm's bandwidth h;
    /// default: the median distance from a photon of the first iteration to its k-th nearest
    /// neighbour, --k).
    #[arg(
        long,
        value_name = "R",
        allow_negative_numbers = true,
        help_heading = "Progressive (pppm, ppds, ppdm, pdpm, sppm, ppm, pcf)"
    )]
    pub radius: Option<caustica_render::Radius>,
    /// With --temporal: where the shutter lies around the instant photons are traced at:
    /// forward (seed 003 eq. 5: traced at the shutter's opening, footprints swept forward) or
    /// centred (traced at its middle, swept both ways; second-order accurate).
    #[arg(long, value_name = "ALIGN", help_heading = "Motion", value_parser = ["forward", "centred", "centered"])]
    pub shutter_align: Option<String>,
    /// With --temporal: the time filter of seed 000 eq. 7.9, a kernel (uniform, epanechnikov,
    /// biweight, ...) along each footprint's motion peaking at the traced instant, normalised so
    /// every photon keeps its flux. Default: none (eq. 7.8).
    #[arg(long, value_name = "KERNEL", help_heading = "Motion")]
    pub time_filter: Option<Kernel>,
    /// With --temporal: divide swept footprints by eq. 7.7's area for every kernel, as printed
    /// (exact only for the uniform kernel; others then carry up to 4/3 or 8/5 of their flux).
    /// For comparisons with the paper.
    #[arg(long, help_heading = "Motion")]
    pub paper_area: bool,
    /// How caustic light paths are emitted (every photon method's caustic pass, and lighttrace
    /// --caustics-only): uniform (by power, over all directions), projection (projection maps:
    /// mostly toward mirrors, glass and smooth metal, unbiased; the default) or adaptive (Markov
    /// chains toward photons near what the camera sees; the light tracer uses projection maps
    /// for it). Global and volume photons are always uniform.
    #[arg(long, value_name = "RULE", help_heading = "Photon mapping", value_parser = EmissionStrategy::NAMES)]
    pub emission: Option<String>,
    /// The hybrid integrator's share of a time budget (--time) for its light tracer (the paths
    /// L S … D E: caustics and their reflections); the path tracer has the rest (strictly
    /// between 0 and 1; default 0.5). Without --time it traces --light-paths light paths
    /// (default: one per two camera samples).
    #[arg(
        long,
        value_name = "F",
        allow_negative_numbers = true,
        help_heading = "Hybrid (path + light tracer)"
    )]
    pub light_share: Option<LightShare>,
    #[command(flatten)]
    pub pcf: crate::pcf_args::PcfArgs,
}

impl PhotonArgs {
    /// The photon options these arguments select (defaults where not given), validated.
    pub fn options(&self) -> Result<PhotonOptions> {
        let mut o = PhotonOptions::default();
        if let Some(n) = self.photons {
            o.caustic_photons = n;
        }
        o.light_paths = self.light_paths;
        if let Some(f) = self.light_share {
            o.light_share = f;
        }
        if let Some(e) = self.emission.as_deref().and_then(EmissionStrategy::parse) {
            o.emission = e;
        }
        if let Some(n) = self.global_photons {
            o.global_photons = n;
        }
        if let Some(k) = self.k {
            o.estimate.k = k;
        }
        o.global_k = self.global_k;
        o.estimate.max_radius = self.max_radius;
        if let Some(kernel) = self.kernel {
            o.set_kernel(kernel);
        }
        if let Some(g) = self.final_gather {
            o.final_gather = g;
        }
        o.estimate.tangent_projection = self.tangent_projection;
        o.estimate.disc_test = self.disc_test;
        o.caustic_estimator = self.estimator;
        o.bandwidth = self.bandwidth;
        if let Some(q) = self.q {
            o.diffusion.q = q;
        }
        if let Some(a) = self.alpha {
            o.diffusion.alpha = a;
        }
        o.diffusion.noise_scale = self.noise_scale;
        o.diffusion.isotropic = self.isotropic;
        if let Some(s) = self.smoothing {
            o.footprints.smoothing = s;
        }
        if let Some(t) = self.normal_distance {
            o.footprints.normal_distance = t;
        }
        if let Some(r) = self.min_footprint {
            if !(r > 0.0 && r.is_finite()) {
                anyhow::bail!(
                    "--min-footprint must be a positive finite length in metres, got {r}"
                );
            }
            o.footprints.min_semi_axis = Some(r);
        }
        if let Some(k) = self.wavelength_spread {
            if !(k > 0.0 && k.is_finite()) {
                anyhow::bail!("--wavelength-spread must be a positive finite factor, got {k}");
            }
            if self.temporal {
                anyhow::bail!(
                    "--wavelength-spread and --temporal cannot be combined (each photon sweeps \
                     its footprint along one parameter)"
                );
            }
            o.footprints.wavelength_spread = Some(k);
        }
        if let Some(n) = self.volume_photons {
            o.volume.photons = n;
        }
        if let Some(k) = self.volume_k {
            o.volume.k = k;
        }
        o.volume.radius = self.volume_radius;
        o.volume.step = self.march_step;
        if let Some(k) = &self.beam_kernel {
            o.volume.kernel = match k.as_str() {
                "epanechnikov" => BeamKernel::Epanechnikov,
                "uniform" => BeamKernel::Uniform,
                _ => anyhow::bail!(
                    "unknown beam kernel '{k}' (expected 'epanechnikov' or 'uniform')"
                ),
            };
        }
        o.volume.smoothing = self.volume_smoothing;
        if let Some(r) = self.min_semi_axis {
            if !(r > 0.0 && r.is_finite()) {
                anyhow::bail!(
                    "--min-semi-axis must be a positive finite length in metres, got {r}"
                );
            }
            o.volume.min_semi_axis = Some(r);
        }
        if self.paper_axes {
            o.volume.axes = caustica_render::photon::volume_map::AxesRule::PaperLiteral;
        }
        if self.whole_chord {
            o.volume.clip = caustica_density::beam::Clip::WholeChord;
        }
        o.volume.spread_collimated = self.spread_collimated;
        if let Some(b) = &self.volume_boundary {
            use caustica_render::photon::kernel_boundary::KernelBoundary;
            o.volume.boundary = match b.as_str() {
                "open" => KernelBoundary::Open,
                "renormalise" | "renormalize" => KernelBoundary::Renormalised,
                _ => anyhow::bail!(
                    "unknown --volume-boundary '{b}' (expected 'open' or 'renormalise')"
                ),
            };
        }
        o.footprints.temporal = self.temporal;
        o.in_between_frames = self.in_between_frames;
        let pr = &mut o.progressive;
        pr.iterations = self.iterations;
        if let Some(m) = self.photons_per_iteration {
            pr.paths_per_iteration = m;
        }
        if let Some(a) = self.ppm_alpha {
            pr.alpha = a;
        }
        pr.radius = self.radius;
        // pcf's α is --ppm-alpha too, with its own default (and range (0, 1)); checked only
        // when pcf runs (`IntegratorKind::check`).
        self.pcf.apply(&mut o.pcf, self.ppm_alpha)?;
        pr.validate()?;
        let sweep_given =
            self.shutter_align.is_some() || self.time_filter.is_some() || self.paper_area;
        if sweep_given && !self.temporal {
            anyhow::bail!("--shutter-align, --time-filter and --paper-area go with --temporal");
        }
        o.footprints.sweep = caustica_render::SweepRule {
            align: match self.shutter_align.as_deref() {
                Some("centred" | "centered") => caustica_render::ShutterAlign::Centred,
                _ => caustica_render::ShutterAlign::Forward,
            },
            time_filter: self.time_filter,
            paper_area: self.paper_area,
        };
        // What neither the command line nor (see `RenderSettings::resolve`) the scene gives is
        // chosen automatically.
        let auto = !self.no_auto_bandwidth;
        o.auto = AutoBandwidth {
            k: auto && self.k.is_none(),
            bandwidth: auto && self.bandwidth.is_none(),
            q: auto && self.q.is_none(),
            smoothing: auto && self.smoothing.is_none(),
        };
        o.validate()?;
        Ok(o)
    }

    /// True if any photon-mapping option was given (they only affect photon integrators).
    pub fn any_given(&self) -> bool {
        self.photons.is_some()
            || self.light_paths.is_some()
            || self.global_photons.is_some()
            || self.k.is_some()
            || self.global_k.is_some()
            || self.max_radius.is_some()
            || self.kernel.is_some()
            || self.final_gather.is_some()
            || self.tangent_projection
            || self.disc_test
            || self.estimator.is_some()
            || self.bandwidth.is_some()
            || self.q.is_some()
            || self.alpha.is_some()
            || self.noise_scale.is_some()
            || self.isotropic
            || self.smoothing.is_some()
            || self.normal_distance.is_some()
            || self.min_footprint.is_some()
            || self.wavelength_spread.is_some()
            || self.no_auto_bandwidth
            || self.volume_photons.is_some()
            || self.volume_k.is_some()
            || self.volume_radius.is_some()
            || self.march_step.is_some()
            || self.beam_kernel.is_some()
            || self.volume_smoothing.is_some()
            || self.min_semi_axis.is_some()
            || self.paper_axes
            || self.whole_chord
            || self.volume_boundary.is_some()
            || self.spread_collimated.is_some()
            || self.temporal
            || self.in_between_frames.is_some()
            || self.shutter_align.is_some()
            || self.time_filter.is_some()
            || self.paper_area
            || self.progressive_given()
            || self.pcf.any_given()
            || self.light_share.is_some()
    }

    /// True if the only photon options given are the ones `--integrator hybrid` reads
    /// (`--light-paths`, `--light-share`; `--emission` is never reported).
    pub fn only_hybrid_given(&self) -> bool {
        !Self {
            light_paths: None,
            light_share: None,
            ..self.clone()
        }
        .any_given()
    }

    /// True if any option of the progressive methods was given.
    pub fn progressive_given(&self) -> bool {
        self.iterations.is_some()
            || self.photons_per_iteration.is_some()
            || self.ppm_alpha.is_some()
            || self.radius.is_some()
    }
}
