//! Random numbers, samplers and warping functions.

pub mod distribution;
pub mod rng;
pub mod sampler;
pub mod sobol;
pub mod warp;

pub use distribution::Distribution1D;
pub use rng::{Pcg32, hash_u64, mix_seed};
pub use sampler::{Sampler, SamplerKind};
