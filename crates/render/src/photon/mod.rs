//! The photon family: everything the photon methods (`pm`, `dpm`, `pdm`, `pds`, and later the
//! progressive methods and photon cone focusing) share on the light side and at the eye.
//!
//! * [`bandwidth_choice`] — automatic bandwidths (k, h, q, s) by least-squares
//!   cross-validation of the image against a hold-out light-tracer image.
//! * [`plan`] — numbered light paths cut into chunks, waves and ranges ([`plan::trace_paths`]
//!   with a `first_path`, [`plan::trace_path_range`] for a fixed budget N_e): the seam
//!   iterations and shards use.
//! * [`tracer`] — photons from light paths: caustic and global maps ([`tracer::trace_photons`]).
//! * [`adaptive`] — visibility-driven adaptive photon tracing (Hachisuka and Jensen 2011):
//!   Markov chains in primary sample space toward light paths that reach [`visible_points`],
//!   the camera's view (`--emission adaptive`).
//! * [`map`] — a photon map with its k-d tree and the radiance estimate of seed 000 eq. 3.2.
//! * [`caustic`] — the caustic estimate of a photon method, one enum over the density
//!   estimators of `pm`/`dpm`, the footprints of `pdm` and the splatting of `pds`.
//! * [`volume_map`] — volume photons and their two estimates along camera rays: ray marching
//!   (seed 000 eq. 8.3) and the beam radiance estimate (eq. 8.4).
//! * [`eye_map`] — the eye-path vertices of a camera pass, in spatial tiles.
//! * [`differential`] — photon differentials: tracing, footprints, the `pdm` map, counting.

pub mod adaptive;
pub mod bandwidth_choice;
pub mod caustic;
pub mod differential;
pub mod eye_map;
pub mod kernel_boundary;
pub mod map;
pub mod plan;
pub mod tracer;
pub mod visible_points;
pub mod volume_map;
