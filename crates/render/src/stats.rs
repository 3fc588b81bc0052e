//! Counters reported in the closing summary line.

use std::ops::AddAssign;

/// Work counters; summed over threads in a fixed order.
#[derive(Clone, Copy, Debug, Default)]
pub struct RenderStats {
    /// Camera samples (path tracer) or light paths (light tracer).
    pub samples: u64,
    /// Closest-hit and shadow rays traced.
    pub rays: u64,
    /// Sample contributions discarded because they were NaN or infinite.
    pub nonfinite: u64,
}

impl AddAssign for RenderStats {
    fn add_assign(&mut self, o: Self) {
        self.samples += o.samples;
        self.rays += o.rays;
        self.nonfinite += o.nonfinite;
    }
}
