//! `[render]`: samples per pixel and path depth.

use crate::toml::value::Count;
use serde::Deserialize;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RenderDesc {
    pub(crate) spp: Option<Count>,
    pub(crate) max_depth: Option<Count>,
}
