//! Photon cone focusing (seed 001 ch. 3–4): photon cones, their 4-D kernel and schedule, the
//! cone-direction techniques and their MIS, conical importons, the cone map, and the split of a
//! camera path between path tracing and the map. The integrator is `integrator/pcf.rs`.

pub mod cone;
pub mod cone_map;
pub mod importon;
pub mod kernel;
pub mod split;
pub mod techniques;
pub mod tracer;

pub use cone::PhotonCone;
pub use cone_map::{ConeSet, LookupStats, PhotonConeMap};
pub use importon::{ConicalImporton, ImportonMap};
pub use kernel::{AngularMap, Aperture, ConeSchedule, DiskCapKernel};
pub use split::PathSplit;
pub use tracer::{ConeRule, trace_cones};
