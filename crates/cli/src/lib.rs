//! The caustica command line as a library: the `caustica` binary's subcommands, and the render
//! settings (scene loading, option resolution) that the Python package shares with it, so a
//! render from Python computes what the same command line computes.

#![forbid(unsafe_code)]

pub mod compare_cmd;
pub mod convert_cmd;
pub mod eta;
pub mod merge_cmd;
pub mod pcf_args;
pub mod photon_args;
pub mod photons_cmd;
pub mod preview;
pub mod render_cmd;
pub mod shard_args;
pub mod sweep_cmd;
pub mod testbed_cmd;
pub mod values;
