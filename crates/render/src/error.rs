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
    /// A crop window (`--crop`) that does not parse or does not fit the film.
    #[error(
        "--crop {got}: {why}; expected X,Y,W,H (pixels of the {film_width}x{film_height} film): four non-negative integers, W and H at least 1, X+W <= {film_width} and Y+H <= {film_height}"
    )]
    Crop {
        got: String,
        film_width: u32,
        film_height: u32,
        why: String,
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
