//! `[integrator]`: the method a scene is meant to be rendered with, and its photon options
//! (like Mitsuba's `<integrator>`); the command line overrides each.

use crate::toml::value::Count;
use serde::Deserialize;

/// The integrators caustica has, by their command-line names.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(crate) enum IntegratorType {
    Path,
    Lighttrace,
    Pm,
    Dpm,
    Pdm,
    Pds,
    Vpm,
    Beam,
    Vpd,
}

impl IntegratorType {
    pub(crate) fn name(self) -> &'static str {
        match self {
            IntegratorType::Path => "path",
            IntegratorType::Lighttrace => "lighttrace",
            IntegratorType::Pm => "pm",
            IntegratorType::Dpm => "dpm",
            IntegratorType::Pdm => "pdm",
            IntegratorType::Pds => "pds",
            IntegratorType::Vpm => "vpm",
            IntegratorType::Beam => "beam",
            IntegratorType::Vpd => "vpd",
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct IntegratorDesc {
    #[serde(rename = "type")]
    pub(crate) ty: IntegratorType,
    /// Caustic photons (`--photons`).
    pub(crate) photons: Option<Count>,
    /// Smoothing s of photon differentials (`--smoothing`; pdm, pds).
    pub(crate) smoothing: Option<f32>,
    /// Smoothing s of volume photon differentials (`--volume-smoothing`; vpd).
    pub(crate) volume_smoothing: Option<f32>,
    /// Volume photons (`--volume-photons`).
    pub(crate) volume_photons: Option<Count>,
    /// Final-gather rays per camera sample (`--final-gather`; 0 = the global map seen directly).
    pub(crate) final_gather: Option<u32>,
}
