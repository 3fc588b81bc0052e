//! The caustic estimate of a photon method: how light of paths L S+ D is estimated at the first
//! non-delta vertex a camera path reaches. One enum for the four methods: a density estimate in
//! a photon map (`pm` with k-NN, fixed or variable bandwidth; `dpm` with the diffusion
//! estimate), photon-differential footprints gathered at the vertex (`pdm`), or none stored and
//! the footprints splatted onto the vertex later (`pds`).

use crate::options::{CausticEstimator, PhotonOptions, RenderOptions};
use crate::photon::differential::{FootprintFilter, PdmMap, trace_photon_differentials};
use crate::photon::map::PhotonMap;
use crate::photon::tracer::{MapKind, Photon, TracedPhotons, trace_photons};
use crate::transport::vertex::Vertex;
use caustica_core::Spectrum;
use caustica_density::diffusion::DiffusionParams;
use caustica_density::estimator::{Estimator, EstimatorSpec, Scratch, median_knn_radius};
use caustica_scene::Scene;
use std::cell::RefCell;

/// Random-number stream of the caustic light paths (every caustic method uses the same paths).
pub const CAUSTIC_STREAM: u64 = 0xCA05;

/// How a photon method estimates caustics.
pub enum CausticEstimate {
    /// A photon map with a density estimator prepared for it (`pm`, `dpm`).
    Density {
        map: PhotonMap,
        estimator: Estimator,
        /// Seconds spent preparing the estimator (the diffusion pre-passes).
        prepare_secs: f64,
    },
    /// Photon-differential footprints gathered at the vertex (`pdm`, seed 002 eq. 10).
    Footprints(PdmMap),
    /// Nothing stored: the vertex is recorded and the footprints are splatted onto it later
    /// (`pds`, seed 002 sec. 3.3).
    Splatted,
    /// No caustic light is wanted: `--volume-only` renders shade no surface.
    None,
}

impl CausticEstimate {
    /// The caustic map of `pm` (or `dpm` with `CausticEstimator::Diffusion`) under the caustic
    /// budget of `opts`, with `estimator` prepared for it.
    pub fn density(
        scene: &Scene,
        estimator: CausticEstimator,
        opts: &RenderOptions,
        progress: &mut dyn FnMut(f64) -> bool,
    ) -> (Self, TracedPhotons) {
        let p = &opts.photons;
        let mut traced = trace_photons(
            scene,
            p.caustic_budget(),
            MapKind::Caustic,
            CAUSTIC_STREAM,
            opts,
            progress,
        );
        let map = PhotonMap::new(std::mem::take(&mut traced.photons), traced.paths);
        let mut caustic = CausticEstimate::Density {
            estimator: PhotonMap::knn_estimator(&p.estimate),
            map,
            prepare_secs: 0.0,
        };
        caustic.set_estimator(estimator, p);
        (caustic, traced)
    }

    /// The footprints of `pdm`: the caustic light paths of [`CausticEstimate::density`] (same
    /// stream) traced as photon differentials with the footprint settings of `opts`.
    pub fn footprints(
        scene: &Scene,
        opts: &RenderOptions,
        progress: &mut dyn FnMut(f64) -> bool,
    ) -> (
        Self,
        Option<String>,
        Option<String>,
        crate::stats::RenderStats,
    ) {
        let p = &opts.photons;
        let mut d = trace_photon_differentials(
            scene,
            p.caustic_budget(),
            p.footprints.smoothing,
            CAUSTIC_STREAM,
            opts,
            progress,
        );
        let warning = d.warning.take();
        let note = d.note.take();
        let stats = d.stats;
        let map = PdmMap::with_filter(d, FootprintFilter::new(&p.footprints));
        (CausticEstimate::Footprints(map), warning, note, stats)
    }

    /// Prepares density estimator `estimator` (with the parameters of `opts`) for a photon map
    /// and returns what it is; `None` (and nothing changes) for footprints and splatting.
    pub fn set_estimator(
        &mut self,
        estimator: CausticEstimator,
        opts: &PhotonOptions,
    ) -> Option<EstimatorSpec> {
        let CausticEstimate::Density {
            map,
            estimator: prepared,
            prepare_secs,
        } = self
        else {
            return None;
        };
        let spec = caustic_spec(map, estimator, opts);
        let t = std::time::Instant::now();
        *prepared = Estimator::prepare(&spec, &map.points(&opts.estimate));
        *prepare_secs = t.elapsed().as_secs_f64();
        Some(spec)
    }

    /// Reflected caustic radiance (W/m²/sr) at vertex `v` toward its `wo`; zero for
    /// [`CausticEstimate::Splatted`], whose vertices receive it by splatting.
    pub fn radiance(&self, v: &Vertex, opts: &PhotonOptions) -> Spectrum {
        match self {
            CausticEstimate::Density { map, estimator, .. } => SCRATCH
                .with(|b| map.estimate_with(v, &opts.estimate, estimator, &mut b.borrow_mut())),
            CausticEstimate::Footprints(map) => map.radiance(v),
            CausticEstimate::Splatted | CausticEstimate::None => Spectrum::ZERO,
        }
    }

    /// Light paths emitted for the estimate (0 when splatted: they are traced later).
    pub fn paths(&self) -> u64 {
        match self {
            CausticEstimate::Density { map, .. } => map.paths,
            CausticEstimate::Footprints(map) => map.paths,
            CausticEstimate::Splatted | CausticEstimate::None => 0,
        }
    }

    /// The point photons of a photon map (none for footprints or splatting).
    pub fn point_photons(&self) -> &[Photon] {
        match self {
            CausticEstimate::Density { map, .. } => &map.photons,
            _ => &[],
        }
    }

    /// Caustic photons stored.
    pub fn len(&self) -> usize {
        match self {
            CausticEstimate::Density { map, .. } => map.len(),
            CausticEstimate::Footprints(map) => map.len(),
            CausticEstimate::Splatted | CausticEstimate::None => 0,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Bytes held by the stored photons and their search structures.
    pub fn memory_bytes(&self) -> usize {
        match self {
            CausticEstimate::Density { map, .. } => map.memory_bytes(),
            CausticEstimate::Footprints(map) => map.memory_bytes(),
            CausticEstimate::Splatted | CausticEstimate::None => 0,
        }
    }
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// The global map's radiance estimate (W/m²/sr) at `v` (its own k when `global_k` is set).
pub fn global_radiance(map: &PhotonMap, v: &Vertex, opts: &PhotonOptions) -> Spectrum {
    let est = opts.global_estimate();
    SCRATCH.with(|b| match opts.global_bandwidth {
        Some(h) => map.estimate_with(
            v,
            &est,
            &Estimator::Fixed {
                h: h.get(),
                kernel: est.kernel,
            },
            &mut b.borrow_mut(),
        ),
        None => map.estimate(v, &est, &mut b.borrow_mut()),
    })
}

/// The caustic map's estimator `estimator` with the parameters of `opts`, with the data-driven
/// default bandwidth (median k-NN radius, k = `estimate.k`) where none is given.
pub fn caustic_spec(
    map: &PhotonMap,
    estimator: CausticEstimator,
    opts: &PhotonOptions,
) -> EstimatorSpec {
    let e = &opts.estimate;
    let bandwidth = || {
        opts.bandwidth
            .map(|h| h.get())
            .or_else(|| median_knn_radius(&map.points(e), e.k))
            .unwrap_or(1.0)
    };
    match estimator {
        CausticEstimator::Knn => EstimatorSpec::Knn {
            k: e.k,
            max_radius: e.max_radius,
            kernel: e.kernel,
        },
        CausticEstimator::Fixed => EstimatorSpec::Fixed {
            h: bandwidth(),
            kernel: e.kernel,
        },
        CausticEstimator::Variable => EstimatorSpec::Variable {
            k: e.k,
            max_radius: e.max_radius,
            kernel: e.kernel,
        },
        CausticEstimator::Diffusion => {
            let h = bandwidth();
            let d = &opts.diffusion;
            EstimatorSpec::Diffusion(DiffusionParams {
                bandwidth: h,
                noise_scale: d.noise_scale.map_or(0.5 * h, |s| s.get()),
                q: d.q.get(),
                alpha: d.alpha.get(),
                isotropic: d.isotropic,
                kernel: e.kernel,
            })
        }
    }
}
