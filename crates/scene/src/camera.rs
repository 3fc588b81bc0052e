//! Perspective cameras (pinhole and thin lens) with per-pixel ray differentials.

use caustica_core::{Affine3A, RayDifferential, Spectrum, Vec2, Vec3};

/// Which image axis the field of view spans.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FovAxis {
    #[default]
    X,
    Y,
    /// The shorter of the two.
    Smaller,
    /// The longer of the two.
    Larger,
}

/// A perspective camera. Raster coordinates are in pixels, (0, 0) at the top-left corner of the
/// image, x to the right, y down. Camera space looks down +z with +y up (the loaders convert
/// look-at and Mitsuba `to_world`, which looks down +z too).
#[derive(Clone, Debug)]
pub struct PerspectiveCamera {
    pub width: u32,
    pub height: u32,
    /// Camera-to-world transform (rigid; no scale).
    pub to_world: Affine3A,
    /// Full field of view (degrees) along `fov_axis`.
    pub fov_deg: f32,
    pub fov_axis: FovAxis,
    /// Lens radius (m); 0 for a pinhole.
    pub lens_radius: f32,
    /// Distance of the plane in focus (m).
    pub focus_distance: f32,
    /// Rays start this far along the view axis (m).
    pub near_clip: f32,
}

/// A direction from a scene point to the camera, for light tracing.
#[derive(Clone, Copy, Debug)]
pub struct CameraSample {
    /// Raster position (pixels) the point projects to.
    pub raster: Vec2,
    /// Unit direction from the scene point toward the sampled lens point.
    pub wi: Vec3,
    pub dist: f32,
    /// Importance We·|cos θ_camera| / (dist²·pdf_lens) — the light tracer adds
    /// β·f·|cos θ_surface|·weight / N to the pixel at `raster`, with N the number of light paths.
    pub weight: Spectrum,
    /// Sampled point on the lens (world space).
    pub lens_p: Vec3,
}

impl PerspectiveCamera {
    /// Camera at `eye` looking at `target` with `up` roughly up.
    pub fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_deg: f32,
        width: u32,
        height: u32,
    ) -> Self {
        let _ = (eye, target, up, fov_deg, width, height);
        todo!("PerspectiveCamera::look_at")
    }
    /// Primary ray through raster point `raster` with lens sample `u_lens`, with its
    /// differentials for a one-pixel step in x and y.
    pub fn generate_ray(&self, raster: Vec2, u_lens: Vec2) -> RayDifferential {
        let _ = (raster, u_lens);
        todo!("PerspectiveCamera::generate_ray")
    }
    /// Samples a point on the lens that sees `p`; `None` if `p` is behind the camera or outside
    /// the image.
    pub fn sample_wi(&self, p: Vec3, u_lens: Vec2) -> Option<CameraSample> {
        let _ = (p, u_lens);
        todo!("PerspectiveCamera::sample_wi")
    }
    /// Camera position (centre of the lens).
    pub fn position(&self) -> Vec3 {
        self.to_world.translation.into()
    }
}
