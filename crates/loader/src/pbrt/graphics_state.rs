//! pbrt's graphics state: the current transformation matrix (CTM, kept with its inverse as
//! pbrt does, so `LookAt` and the camera get exact inverses), reverse orientation, the current
//! material and area light, and the attribute stack that saves and restores them.

use caustica_core::{Mat4, Spectrum, Vec3};
use caustica_scene::light::EmissionSpectrum;

/// A transform and its inverse. Composition post-multiplies, as pbrt's directives do:
/// `ctm = ctm · t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Xf {
    pub m: Mat4,
    pub inv: Mat4,
}

impl Xf {
    pub const IDENTITY: Xf = Xf {
        m: Mat4::IDENTITY,
        inv: Mat4::IDENTITY,
    };

    /// `self · t`.
    pub fn then(self, t: Xf) -> Xf {
        Xf {
            m: self.m * t.m,
            inv: t.inv * self.inv,
        }
    }

    pub fn translate(v: Vec3) -> Xf {
        Xf {
            m: Mat4::from_translation(v),
            inv: Mat4::from_translation(-v),
        }
    }

    /// A scale; a zero factor gives a singular transform whose inverse is not finite (shapes
    /// collapse, a camera under it is an error).
    pub fn scale(s: Vec3) -> Xf {
        Xf {
            m: Mat4::from_scale(s),
            inv: Mat4::from_scale(s.recip()),
        }
    }

    /// Rotation by `deg` degrees about `axis` (right-handed, as pbrt's `Rotate`); `None` for a
    /// zero axis.
    pub fn rotate(deg: f32, axis: Vec3) -> Option<Xf> {
        let a = axis.try_normalize()?;
        let m = Mat4::from_axis_angle(a, deg.to_radians());
        Some(Xf {
            m,
            inv: m.transpose(),
        })
    }

    /// A general matrix; its inverse is computed (not finite if singular).
    pub fn matrix(m: Mat4) -> Xf {
        Xf {
            m,
            inv: m.inverse(),
        }
    }

    /// pbrt's `LookAt`: the camera-from-world transform whose inverse is the frame
    /// (x = up × dir, y = dir × x, z = dir, origin = eye). `None` if eye = look or up ∥ dir.
    pub fn look_at(eye: Vec3, look: Vec3, up: Vec3) -> Option<Xf> {
        let world_from_camera = crate::toml::look_at_transform(eye, look, up)?;
        let w = Mat4::from(world_from_camera);
        Some(Xf {
            m: w.inverse(),
            inv: w,
        })
    }

    /// True if the 3×3 part has a negative determinant (pbrt's `SwapsHandedness`).
    pub fn swaps_handedness(&self) -> bool {
        glam::Mat3::from_mat4(self.m).determinant() < 0.0
    }
}

/// Which material the graphics state names.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum MatRef {
    /// pbrt's default: `diffuse` with reflectance 0.5.
    Default,
    /// A `Material` directive's material: index into the loader's material list.
    Anonymous(usize),
    /// `NamedMaterial "name"` at a line and column.
    Named(String, usize, usize),
}

/// An `AreaLightSource "diffuse"` in effect: its radiance (`L` × `scale`, W/m²/sr), emission
/// spectrum, and `power` (W), which rescales the radiance by the area of each shape using it.
#[derive(Clone, Debug)]
pub(crate) struct AreaLightDesc {
    pub radiance: Spectrum,
    pub spectrum: Option<EmissionSpectrum>,
    pub power: Option<f32>,
}

/// The attributes `AttributeBegin`/`AttributeEnd` save and restore.
#[derive(Clone, Debug)]
pub(crate) struct GraphicsState {
    pub ctm: Xf,
    pub reverse_orientation: bool,
    pub material: MatRef,
    pub area_light: Option<AreaLightDesc>,
    /// `ActiveTransform`: which of the start and end transforms directives change (caustica
    /// has no transform motion blur: only changes of the start transform are applied).
    pub active_start: bool,
    pub active_end: bool,
}

impl Default for GraphicsState {
    fn default() -> Self {
        Self {
            ctm: Xf::IDENTITY,
            reverse_orientation: false,
            material: MatRef::Default,
            area_light: None,
            active_start: true,
            active_end: true,
        }
    }
}

/// What pushed an entry of the attribute stack.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Push {
    Attribute,
    /// pbrt-v3's `TransformBegin` (saves the CTM only).
    Transform,
}

/// A saved state, what pushed it and where (for errors about unbalanced blocks).
#[derive(Clone, Debug)]
pub(crate) struct Saved {
    pub state: GraphicsState,
    pub kind: Push,
    pub file: std::path::PathBuf,
    pub line: usize,
    pub col: usize,
}
