//! Errors of the renderer: options that cannot be rendered, and scenes a method cannot render.

use thiserror::Error;

/// An option value or combination the renderer refuses; the message names the option, the rule
/// and the value given.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum OptionError {
    /// A value outside its range: "`what` must be `rule`, got `got`".
    #[error("{what} must be {rule}, got {got}")]
    Invalid {
        what: &'static str,
        rule: &'static str,
        got: String,
    },
    /// A value that does not parse.
    #[error("{what}: '{got}' is not {rule}")]
    Unparsable {
        what: &'static str,
        rule: &'static str,
        got: String,
    },
    /// Options that cannot be combined, or an option the chosen integrator cannot honour.
    #[error("{0}")]
    Conflict(String),
}

/// Why a render cannot start.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum RenderError {
    #[error(transparent)]
    Option(#[from] OptionError),
    /// The render would allocate more than [`crate::RenderOptions::memory_limit`].
    #[error(
        "the render would need {estimate}, more than the memory budget of {limit} (--memory); {hint}"
    )]
    Memory {
        estimate: String,
        limit: String,
        hint: &'static str,
    },
    /// A photon method on a scene without lights.
    #[error("scene '{scene}' has no lights: photon mapping needs at least one to emit photons")]
    NoLights { scene: String },
}
