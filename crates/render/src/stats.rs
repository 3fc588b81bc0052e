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
    /// Photon-cone-map lookups (pcf), the cones they scanned (within σ) and the cones inside
    /// the 4-D kernel.
    pub cone_lookups: u64,
    pub cones_scanned: u64,
    pub cones_inside: u64,
    /// Caustic vertices (L S+ D) the light tracer's caustics-only paths reached, connected to
    /// the camera or not: the caustic yield's numerator.
    pub caustic_vertices: u64,
}

impl AddAssign for RenderStats {
    fn add_assign(&mut self, o: Self) {
        self.samples += o.samples;
        self.rays += o.rays;
        self.nonfinite += o.nonfinite;
        self.cone_lookups += o.cone_lookups;
        self.cones_scanned += o.cones_scanned;
        self.cones_inside += o.cones_inside;
        self.caustic_vertices += o.caustic_vertices;
    }
}
