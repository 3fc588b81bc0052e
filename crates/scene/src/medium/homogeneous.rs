//! Homogeneous media: the same σ_a and σ_s everywhere inside the medium's boundary.
//!
//! Free flights are exponential, t ~ σ_t e^{−σ_t t} per channel (seed 000 eq. 8.20,
//! s = −ln ξ / σ_t), and the transmittance has the closed form T = e^{−σ_t t} (eq. 8.2 with its
//! missing minus sign restored); [`super::tracking`] uses both through a single majorant segment
//! equal to σ_t, so tracking never meets a null collision here.

/// The density field of a homogeneous medium: 1 everywhere.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Homogeneous;
