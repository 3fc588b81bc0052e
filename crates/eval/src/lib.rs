//! Image comparison for caustica: the numbers rendering methods are judged by.
//!
//! Every metric compares an `image` against a `reference` over a [`Region`] (an optional crop
//! rectangle and an optional mask). Metrics on linear radiance (relative mean difference, RMSE,
//! relative MSE) measure physical agreement; metrics on the display range (MISE, SSIM) follow the
//! evaluation of seed 000 ch. 6 and seed 002 sec. 4, which judge images as they are seen. The
//! display transform is documented in [`display`]. The z-score tests in [`zscore`] tell noise from
//! systematic, per-region bias when two independent Monte Carlo renderers are compared. [`plot`]
//! draws a parameter sweep (RMSE and SSIM against the parameter) as SVG and PNG.
//! [`testbed`] is a 2-D density-estimation testbed with exact ground truth (seed 000 fig. 4.4).

#![forbid(unsafe_code)]

pub mod colormap;
pub mod density_study;
pub mod display;
pub mod metrics;
pub mod normal;
pub mod plot;
pub mod region;
pub mod ssim;
pub mod testbed;
pub mod zscore;

pub use metrics::{Comparison, compare};
pub use region::Region;

/// Errors of the comparison tools.
#[derive(Debug, thiserror::Error)]
pub enum EvalError {
    #[error("image sizes differ: the image is {iw}x{ih}, the reference {rw}x{rh}")]
    SizeMismatch {
        iw: usize,
        ih: usize,
        rw: usize,
        rh: usize,
    },
    #[error("crop {x},{y},{w},{h} does not fit inside the {width}x{height} image")]
    BadCrop {
        x: usize,
        y: usize,
        w: usize,
        h: usize,
        width: usize,
        height: usize,
    },
    #[error("mask is {mw}x{mh} but the images are {width}x{height}")]
    MaskSize {
        mw: usize,
        mh: usize,
        width: usize,
        height: usize,
    },
    #[error("no pixel left to compare after crop and mask")]
    EmptyRegion,
}
