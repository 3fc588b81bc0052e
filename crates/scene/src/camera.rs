//! Perspective cameras (pinhole and thin lens) with per-pixel ray differentials.

use caustica_core::sampling::warp;
use caustica_core::{Affine3A, PI, Ray, RayDifferential, Spectrum, Vec2, Vec3};

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

/// A primary ray in camera space: origin, unit direction, the length of the unnormalised
/// direction `w` and the focus scale (see [`PerspectiveCamera::generate_ray`]).
struct CameraSpaceRay {
    o: Vec3,
    d: Vec3,
    len: f32,
    scale: f32,
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
    ///
    /// Mitsuba's `lookat`: camera-space +z = `dir`, +x = `left` = normalize(up × dir),
    /// +y = dir × left; so raster x increasing goes toward the camera's right (−x). Degenerate
    /// input (eye = target, up ∥ dir) falls back to a valid frame.
    pub fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_deg: f32,
        width: u32,
        height: u32,
    ) -> Self {
        let dir = (target - eye).try_normalize().unwrap_or(Vec3::Z);
        let left = up
            .cross(dir)
            .try_normalize()
            .unwrap_or_else(|| caustica_core::Frame::from_normal(dir).s);
        let new_up = dir.cross(left);
        let to_world = Affine3A::from_cols(left.into(), new_up.into(), dir.into(), eye.into());
        let fd = (target - eye).length();
        Self {
            width,
            height,
            to_world,
            fov_deg,
            fov_axis: FovAxis::X,
            lens_radius: 0.0,
            focus_distance: if fd.is_finite() && fd > 0.0 { fd } else { 1.0 },
            near_clip: 1e-4,
        }
    }

    /// Half-extents `(tan_x, tan_y)` of the image on the camera-space plane z = 1.
    pub fn screen_half_extent(&self) -> Vec2 {
        let w = self.width.max(1) as f32;
        let h = self.height.max(1) as f32;
        let aspect = w / h;
        let t = (0.5 * self.fov_deg.clamp(1e-3, 179.9).to_radians()).tan();
        let along_x = match self.fov_axis {
            FovAxis::X => true,
            FovAxis::Y => false,
            FovAxis::Smaller => w <= h,
            FovAxis::Larger => w >= h,
        };
        if along_x {
            Vec2::new(t, t / aspect)
        } else {
            Vec2::new(t * aspect, t)
        }
    }

    /// Camera-space point on the plane z = 1 seen at raster position `raster`.
    #[inline]
    pub fn raster_to_plane(&self, raster: Vec2, ext: Vec2) -> Vec3 {
        let w = self.width.max(1) as f32;
        let h = self.height.max(1) as f32;
        Vec3::new(
            ext.x * (1.0 - 2.0 * raster.x / w),
            ext.y * (1.0 - 2.0 * raster.y / h),
            1.0,
        )
    }

    /// Change of the z = 1 plane point per pixel step in x and y (camera space).
    #[inline]
    pub fn plane_steps(&self, ext: Vec2) -> (Vec3, Vec3) {
        let w = self.width.max(1) as f32;
        let h = self.height.max(1) as f32;
        (
            Vec3::new(-2.0 * ext.x / w, 0.0, 0.0),
            Vec3::new(0.0, -2.0 * ext.y / h, 0.0),
        )
    }

    /// Focus distance used by the thin lens (positive, finite).
    #[inline]
    pub fn focus(&self) -> f32 {
        if self.focus_distance.is_finite() && self.focus_distance > 0.0 {
            self.focus_distance
        } else {
            1.0
        }
    }

    /// Lens point (camera space, z = 0) for lens sample `u`, and the lens pdf (m⁻², 1 for a
    /// pinhole).
    #[inline]
    pub fn lens_point(&self, u: Vec2) -> (Vec3, f32) {
        if self.lens_radius > 0.0 {
            let d = warp::square_to_disk_concentric(u) * self.lens_radius;
            (
                Vec3::new(d.x, d.y, 0.0),
                1.0 / (PI * self.lens_radius * self.lens_radius),
            )
        } else {
            (Vec3::ZERO, 1.0)
        }
    }

    /// Primary ray through raster point `raster` with lens sample `u_lens`, with its
    /// differentials for a one-pixel step in x and y.
    ///
    /// The ray starts where it crosses the camera-space plane z = `near_clip`; its direction is
    /// normalised. For a thin lens the ray goes from the lens point through the point of the
    /// focus plane (z = `focus_distance`) seen by the pinhole ray; the differentials are those of
    /// that ray when the raster point moves while the lens point stays fixed (pbrt), so
    /// ∂d/∂x = (I − d dᵀ) f ∂v/∂x / |w| with w = f v − lens, and ∂o/∂x = near_clip ∂v/∂x for both
    /// models (v = point on the plane z = 1).
    pub fn generate_ray(&self, raster: Vec2, u_lens: Vec2) -> RayDifferential {
        let ext = self.screen_half_extent();
        let c = self.camera_space_ray(raster, u_lens, ext);
        let (dvx, dvy) = self.plane_steps(ext);
        let (d, len, scale) = (c.d, c.len, c.scale);
        let dd = |dv: Vec3| {
            let dw = dv * scale;
            (dw - d * d.dot(dw)) / len
        };
        let m = &self.to_world;
        RayDifferential {
            ray: self.world_ray(&c),
            dodx: m.transform_vector3(dvx * self.near_clip),
            dody: m.transform_vector3(dvy * self.near_clip),
            dddx: m.transform_vector3(dd(dvx)),
            dddy: m.transform_vector3(dd(dvy)),
        }
    }

    /// [`Self::generate_ray`]'s ray without its differentials, the same bits, for a camera whose
    /// [`Self::screen_half_extent`] is `ext` (computed once by callers that make many rays).
    #[inline]
    pub fn ray(&self, raster: Vec2, u_lens: Vec2, ext: Vec2) -> Ray {
        self.world_ray(&self.camera_space_ray(raster, u_lens, ext))
    }

    /// The ray through `raster` in camera space (see [`Self::generate_ray`]).
    #[inline(always)]
    fn camera_space_ray(&self, raster: Vec2, u_lens: Vec2, ext: Vec2) -> CameraSpaceRay {
        let v = self.raster_to_plane(raster, ext);
        let (pl, scale) = if self.lens_radius > 0.0 {
            (self.lens_point(u_lens).0, self.focus())
        } else {
            (Vec3::ZERO, 1.0)
        };
        // Unnormalised direction w = scale·v − pl, with w.z = scale.
        let w = v * scale - pl;
        let len = w.length();
        CameraSpaceRay {
            o: pl + w * (self.near_clip / scale),
            d: w / len,
            len,
            scale,
        }
    }

    /// A camera-space ray in world space.
    #[inline(always)]
    fn world_ray(&self, c: &CameraSpaceRay) -> Ray {
        let m = &self.to_world;
        Ray::new(
            m.transform_point3(c.o),
            m.transform_vector3(c.d).normalize(),
        )
    }

    /// Raster position (pixels) at which the camera-space point `pc` is seen through the
    /// camera-space lens point `pl` (the pinhole position for a pinhole), if in front.
    fn raster_of(&self, pc: Vec3, pl: Vec3, ext: Vec2) -> Option<Vec2> {
        let w = pc - pl;
        if w.z <= 0.0 || w.z.is_nan() {
            return None;
        }
        let scale = if self.lens_radius > 0.0 {
            self.focus()
        } else {
            1.0
        };
        // Point on the focus plane, then back to the plane z = 1 of the pinhole model.
        let v = (pl + w * (scale / w.z)) / scale;
        let rx = 0.5 * self.width as f32 * (1.0 - v.x / ext.x);
        let ry = 0.5 * self.height as f32 * (1.0 - v.y / ext.y);
        Some(Vec2::new(rx, ry))
    }

    /// Raster position of the world point `p` as seen by the pinhole at the lens centre (or
    /// through the lens centre for a thin lens); `None` if behind the camera or outside the image.
    pub fn world_to_raster(&self, p: Vec3) -> Option<Vec2> {
        let pc = self.to_world.inverse().transform_point3(p);
        let r = self.raster_of(pc, Vec3::ZERO, self.screen_half_extent())?;
        self.inside(r).then_some(r)
    }

    #[inline]
    fn inside(&self, r: Vec2) -> bool {
        r.x >= 0.0 && r.y >= 0.0 && r.x < self.width as f32 && r.y < self.height as f32
    }

    /// Importance `We` (m⁻² sr⁻¹) of a ray leaving the lens with angle θ to the view axis, for
    /// directions inside the image:
    ///
    /// `We = 1 / (A_lens · a_pix · cos⁴θ)`, with `a_pix = (2 tan_x / W)(2 tan_y / H)` the area of
    /// one pixel on the plane z = 1 and `A_lens = π r²` (1 for a pinhole, whose lens pdf is a
    /// delta). Derivation: a pixel's value is the average of the radiance over its raster square
    /// (area 1) and over the lens; a raster step maps to solid angle as
    /// dω = a_pix cos³θ d(raster) (also through a thin lens, via the focus plane), so
    /// I_pix = ∫∫ L (1/A_lens) d(raster) dA = ∫∫ We L cos θ dω dA with We as above. Hence
    /// ∫_lens ∫_pixel We cos θ dω dA = 1 for every pixel (the identity the tests check), and
    /// a path tracer averaging radiance per pixel agrees with a light tracer that adds
    /// β·f·|cos θ_surface|·[`CameraSample::weight`]/N.
    pub fn we(&self, cos_theta: f32) -> f32 {
        let ext = self.screen_half_extent();
        let a_pix = 4.0 * ext.x * ext.y / (self.width.max(1) as f32 * self.height.max(1) as f32);
        let a_lens = if self.lens_radius > 0.0 {
            PI * self.lens_radius * self.lens_radius
        } else {
            1.0
        };
        let c2 = cos_theta * cos_theta;
        1.0 / (a_lens * a_pix * c2 * c2)
    }

    /// Samples a point on the lens that sees `p`; `None` if `p` is behind the camera or outside
    /// the image.
    ///
    /// `weight` = We·cos θ / (dist²·pdf_lens) = 1 / (a_pix cos³θ dist²) (m⁻², per pixel), see
    /// [`PerspectiveCamera::we`].
    pub fn sample_wi(&self, p: Vec3, u_lens: Vec2) -> Option<CameraSample> {
        let pc = self.to_world.inverse().transform_point3(p);
        if pc.z <= self.near_clip || pc.z.is_nan() {
            return None;
        }
        let ext = self.screen_half_extent();
        let (pl, pdf_lens) = self.lens_point(u_lens);
        let raster = self.raster_of(pc, pl, ext)?;
        if !self.inside(raster) {
            return None;
        }
        let w = pc - pl;
        let dist2 = w.length_squared();
        let dist = dist2.sqrt();
        let cos = w.z / dist;
        let weight = self.we(cos) * cos / (dist2 * pdf_lens);
        if !weight.is_finite() {
            return None;
        }
        let lens_p = self.to_world.transform_point3(pl);
        Some(CameraSample {
            raster,
            wi: self.to_world.transform_vector3(-w / dist).normalize(),
            dist,
            weight: Spectrum::splat(weight),
            lens_p,
        })
    }
    /// Camera position (centre of the lens).
    pub fn position(&self) -> Vec3 {
        self.to_world.translation.into()
    }
}
