//! `[film]`: the reconstruction filter.

use crate::toml::value::Positive;
use serde::Deserialize;

#[derive(Deserialize, Clone, Copy, PartialEq)]
#[serde(rename_all = "lowercase")]
pub(crate) enum FilterType {
    Box,
    Gaussian,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct FilmDesc {
    pub(crate) filter: FilterType,
    pub(crate) stddev: Option<Positive>,
    pub(crate) radius: Option<Positive>,
}
