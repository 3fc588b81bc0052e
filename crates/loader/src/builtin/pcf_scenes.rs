//! The photon cone focusing scenes (seed 001 ch. 4–5, issue 21; `docs/scenes.md`): the painting
//! behind glass (`painting-glass`, and `painting-sheet` with a closed-form answer), the torus
//! embedded in a glass ball (`torus-glass`), a Cornell box with a glass and a mirror ball lit by
//! a point light (`mirror-caustic-box`) and shiny pyramids lit indirectly (`shiny-pyramids`).
//! All about 2 m across, so that PCF's initial cone radius σ₁ ≈ 0.1 is a twentieth of the scene.

use super::{camera, caustic_integrator, cornell_room_with_light, dielectric, diffuse, trs};
use caustica_core::{Affine3A, Spectrum, Vec3};
use caustica_scene::SceneError;
use caustica_scene::light::{Light, PointLight, SpotLight};
use caustica_scene::material::{Material, conductor_preset};
use caustica_scene::scene::SceneBuilder;
use caustica_scene::shape::{ShapeGeometry, Sphere, TriangleMesh, torus_mesh};
use caustica_scene::texture::Texture;

/// Final-gather rays per camera sample of the two scenes in the Cornell room when rendered with
/// their suggested `pds` (as `caustic-box`: 16, `pm`'s default, makes the camera pass 4 times
/// slower in a closed diffuse room).
const PCF_BOX_FINAL_GATHER: u32 = 4;

// ---------------------------------------------------------------------------------------------
// painting-glass, painting-sheet

/// Centre of the painting (m): on the wall z = −1, 5 mm in front of it.
pub const PAINTING_CENTER: Vec3 = Vec3::new(0.0, 0.1, -0.995);
/// Half width and half height of the painting (m): 0.8 × 0.6 m.
pub const PAINTING_HALF: (f32, f32) = (0.4, 0.3);
/// Checkerboard squares per unit of uv across the painting (10 × 7.5 cm squares).
pub const PAINTING_CHECKS: f32 = 8.0;
/// The painting's two albedos: ochre and blue.
pub const PAINTING_OCHRE: Spectrum = Spectrum::new(0.75, 0.55, 0.15);
pub const PAINTING_BLUE: Spectrum = Spectrum::new(0.1, 0.2, 0.45);
/// Albedo of `painting-sheet`'s uniform sheet, grey.
pub const PAINTING_SHEET_ALBEDO: f32 = 0.5;
/// Albedo of the wall around the painting, grey.
pub const PAINTING_WALL_ALBEDO: f32 = 0.5;
/// The glass plate: IOR 1.5, front face at z = −0.95, 1.5 cm thick, 3 cm in front of the
/// painting, 1.0 × 0.8 m (10 cm wider than the painting on every side).
pub const PAINTING_GLASS_IOR: f32 = 1.5;
pub const PAINTING_GLASS_FRONT_Z: f32 = -0.95;
pub const PAINTING_GLASS_THICKNESS: f32 = 0.015;
pub const PAINTING_GLASS_HALF: (f32, f32) = (0.5, 0.4);
/// The point light: in front of the plate, up and to the right of the camera (W/sr).
pub const PAINTING_LIGHT_POSITION: Vec3 = Vec3::new(0.35, 0.45, 0.2);
pub const PAINTING_LIGHT_INTENSITY: f32 = 10.0;
/// The pinhole camera: 2.15 m in front of the plate, on the painting's axis.
pub const PAINTING_EYE: Vec3 = Vec3::new(0.0, 0.1, 1.2);
pub const PAINTING_FOV_DEG: f32 = 40.0;

/// `painting-glass` (seed 001 sec. 5.1–5.3): a checkerboard painting behind a thin glass plate,
/// lit through the plate by one point light and seen through it by a pinhole camera.
pub(super) fn painting_glass() -> Result<SceneBuilder, SceneError> {
    painting(
        "painting-glass",
        Texture::Checkerboard {
            a: PAINTING_OCHRE,
            b: PAINTING_BLUE,
            scale: PAINTING_CHECKS,
        },
    )
}

/// `painting-sheet`: `painting-glass` with a uniform grey Lambertian sheet instead of the
/// checkerboard, whose radiance through the glass has a closed form (`docs/scenes.md`).
pub(super) fn painting_sheet() -> Result<SceneBuilder, SceneError> {
    painting(
        "painting-sheet",
        Texture::Constant(Spectrum::splat(PAINTING_SHEET_ALBEDO)),
    )
}

/// The wall z = −1 (2 × 2 m, facing +z), the painting with albedo `painting`, the glass plate
/// (a closed box, two large interfaces), the point light and the camera. Nothing else: no floor
/// or room, so that the painting gets light only through the plate.
fn painting(name: &str, painting: Texture) -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new(name);
    b.set_camera(camera(
        PAINTING_EYE,
        Vec3::new(PAINTING_EYE.x, PAINTING_EYE.y, -1.0),
        PAINTING_FOV_DEG,
        256,
        256,
    ));
    b.settings.spp = Some(8);
    b.settings.max_depth = Some(16);
    caustic_integrator(&mut b);
    let wall = b.add_material(
        "wall",
        diffuse(
            PAINTING_WALL_ALBEDO,
            PAINTING_WALL_ALBEDO,
            PAINTING_WALL_ALBEDO,
        ),
    )?;
    let paint = b.add_material(
        "painting",
        Material::Diffuse {
            reflectance: painting,
        },
    )?;
    let glass = b.add_material("glass", dielectric(PAINTING_GLASS_IOR))?;
    let rect = |t: Affine3A| ShapeGeometry::Mesh(TriangleMesh::rectangle(&t));
    b.add_shape(
        rect(trs(Vec3::new(0.0, 0.0, -1.0), Vec3::X, 0.0, Vec3::ONE)),
        wall,
        None,
        false,
    )?;
    b.add_shape(
        rect(trs(
            PAINTING_CENTER,
            Vec3::X,
            0.0,
            Vec3::new(PAINTING_HALF.0, PAINTING_HALF.1, 1.0),
        )),
        paint,
        None,
        false,
    )?;
    let half_t = 0.5 * PAINTING_GLASS_THICKNESS;
    b.add_shape(
        ShapeGeometry::Mesh(TriangleMesh::cube(&trs(
            Vec3::new(
                PAINTING_CENTER.x,
                PAINTING_CENTER.y,
                PAINTING_GLASS_FRONT_Z - half_t,
            ),
            Vec3::X,
            0.0,
            Vec3::new(PAINTING_GLASS_HALF.0, PAINTING_GLASS_HALF.1, half_t),
        ))),
        glass,
        None,
        false,
    )?;
    b.add_light(Light::Point(PointLight::new(
        PAINTING_LIGHT_POSITION,
        Spectrum::splat(PAINTING_LIGHT_INTENSITY),
    )));
    Ok(b)
}

// ---------------------------------------------------------------------------------------------
// torus-glass

/// The glass ball of `torus-glass` (IOR 1.5): radius 0.5 m, resting on the floor of the
/// Cornell room at its centre.
pub const TORUS_BALL_CENTER: Vec3 = Vec3::new(0.0, -0.5, 0.0);
pub const TORUS_BALL_RADIUS: f32 = 0.5;
/// The torus inside it: major radius 0.25 m, tube radius 0.08 m, centred in the ball, its axis
/// tilted 60° about x toward the camera and 20° about z; 64 × 24 steps (3072 triangles).
pub const TORUS_MAJOR: f32 = 0.25;
pub const TORUS_MINOR: f32 = 0.08;
pub const TORUS_SEGMENTS: u32 = 64;
pub const TORUS_RINGS: u32 = 24;
/// The point light of `torus-glass`: behind the ball, to the left, halfway up (W/sr).
pub const TORUS_LIGHT_POSITION: Vec3 = Vec3::new(-0.55, 0.5, -0.45);
pub const TORUS_LIGHT_INTENSITY: f32 = 4.0;

/// Where the torus is: `torus_mesh`'s torus around the y axis, turned 60° about x (its axis
/// toward the camera) then 20° about z, centred in the ball.
pub fn torus_glass_torus() -> TriangleMesh {
    let t = Affine3A::from_translation(TORUS_BALL_CENTER)
        * Affine3A::from_axis_angle(Vec3::Z, 20f32.to_radians())
        * Affine3A::from_axis_angle(Vec3::X, 60f32.to_radians());
    torus_mesh(TORUS_MAJOR, TORUS_MINOR, TORUS_SEGMENTS, TORUS_RINGS, &t)
}

/// `torus-glass` (seed 001 figs. 4.2 and 5.4, seed 002 fig. 13): a diffuse white torus inside
/// a solid glass ball on the floor of the Cornell room (no ceiling light), lit by a point light.
/// The torus is seen only through the glass and lit only through it (L S D S E); the ball
/// focuses the light into a caustic on the floor in front of it, with the torus's shadow in it.
pub(super) fn torus_glass() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("torus-glass");
    b.settings.spp = Some(8);
    b.settings.max_depth = Some(16);
    caustic_integrator(&mut b);
    b.settings.final_gather = Some(PCF_BOX_FINAL_GATHER);
    cornell_room_with_light(&mut b, None, 256)?;
    b.set_camera(camera(
        Vec3::new(0.0, 0.3, 2.8),
        Vec3::new(0.0, -0.5, 0.0),
        39.3077,
        256,
        256,
    ));
    let glass = b.add_material("glass", dielectric(1.5))?;
    let torus = b.add_material("torus", diffuse(0.8, 0.8, 0.8))?;
    b.add_shape(
        ShapeGeometry::Sphere(Sphere {
            center: TORUS_BALL_CENTER,
            radius: TORUS_BALL_RADIUS,
        }),
        glass,
        None,
        false,
    )?;
    b.add_shape(ShapeGeometry::Mesh(torus_glass_torus()), torus, None, false)?;
    b.add_light(Light::Point(PointLight::new(
        TORUS_LIGHT_POSITION,
        Spectrum::splat(TORUS_LIGHT_INTENSITY),
    )));
    Ok(b)
}

// ---------------------------------------------------------------------------------------------
// mirror-caustic-box

/// The glass ball (IOR 1.5) left of centre and the mirror ball to its right of
/// `mirror-caustic-box`, both resting on the floor, 6 cm apart.
pub const MIRROR_BOX_GLASS_CENTER: Vec3 = Vec3::new(-0.3, -0.65, 0.1);
pub const MIRROR_BOX_GLASS_RADIUS: f32 = 0.35;
pub const MIRROR_BOX_MIRROR_CENTER: Vec3 = Vec3::new(0.5, -0.6, 0.2);
pub const MIRROR_BOX_MIRROR_RADIUS: f32 = 0.4;
/// The point light 15 cm under the ceiling, in the back left corner: behind the glass ball on
/// the line that puts its caustic on the floor in front of the ball (W/sr).
pub const MIRROR_BOX_LIGHT_POSITION: Vec3 = Vec3::new(-0.55, 0.85, -0.75);
pub const MIRROR_BOX_LIGHT_INTENSITY: f32 = 3.0;

/// `mirror-caustic-box` (seed 001 figs. 5.6–5.7, 5.14: "a caustic and its reflected caustic"):
/// the Cornell room of `mi.cornell_box()` without its ceiling light, a glass ball and a perfect
/// mirror ball, lit by a point light under the ceiling. The glass ball's caustic on the floor is
/// seen directly and in the mirror ball.
pub(super) fn mirror_caustic_box() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("mirror-caustic-box");
    b.settings.spp = Some(8);
    b.settings.max_depth = Some(16);
    caustic_integrator(&mut b);
    b.settings.final_gather = Some(PCF_BOX_FINAL_GATHER);
    cornell_room_with_light(&mut b, None, 256)?;
    let glass = b.add_material("glass", dielectric(1.5))?;
    let mirror = b.add_material(
        "mirror",
        Material::Mirror {
            reflectance: Spectrum::ONE,
        },
    )?;
    b.add_shape(
        ShapeGeometry::Sphere(Sphere {
            center: MIRROR_BOX_GLASS_CENTER,
            radius: MIRROR_BOX_GLASS_RADIUS,
        }),
        glass,
        None,
        false,
    )?;
    b.add_shape(
        ShapeGeometry::Sphere(Sphere {
            center: MIRROR_BOX_MIRROR_CENTER,
            radius: MIRROR_BOX_MIRROR_RADIUS,
        }),
        mirror,
        None,
        false,
    )?;
    b.add_light(Light::Point(PointLight::new(
        MIRROR_BOX_LIGHT_POSITION,
        Spectrum::splat(MIRROR_BOX_LIGHT_INTENSITY),
    )));
    Ok(b)
}

// ---------------------------------------------------------------------------------------------
// shiny-pyramids

/// GGX roughness α of the pyramids of `shiny-pyramids`: near-specular (seed 001 sec. 5.3.2,
/// "a GGX roughness close to 0").
pub const PYRAMID_ALPHA: f32 = 0.03;

/// One pyramid: the conductor preset, the centre of its base on the floor (y = −1), its turn
/// about the vertical (degrees), the half side of its square base and its height (m).
pub struct PyramidPlacement {
    pub preset: &'static str,
    pub base_center: Vec3,
    pub turn_deg: f32,
    pub half_side: f32,
    pub height: f32,
}

/// The three pyramids: gold at the back left, silver at the back right, copper in front.
pub const PYRAMIDS: [PyramidPlacement; 3] = [
    PyramidPlacement {
        preset: "Au",
        base_center: Vec3::new(-0.5, -1.0, -0.4),
        turn_deg: 45.0,
        half_side: 0.3,
        height: 0.55,
    },
    PyramidPlacement {
        preset: "Ag",
        base_center: Vec3::new(0.5, -1.0, -0.45),
        turn_deg: 40.0,
        half_side: 0.25,
        height: 0.7,
    },
    PyramidPlacement {
        preset: "Cu",
        base_center: Vec3::new(0.05, -1.0, 0.35),
        turn_deg: 50.0,
        half_side: 0.2,
        height: 0.35,
    },
];

/// The spot light of `shiny-pyramids`: in the front half of the room, aimed up at the ceiling
/// so that the pyramids get (almost) only light the ceiling and walls have scattered (W/sr).
pub const PYRAMIDS_SPOT_POSITION: Vec3 = Vec3::new(0.0, -0.1, 0.4);
pub const PYRAMIDS_SPOT_TARGET: Vec3 = Vec3::new(0.0, 1.0, 0.0);
pub const PYRAMIDS_SPOT_INTENSITY: f32 = 10.0;
pub const PYRAMIDS_SPOT_CUTOFF_DEG: f32 = 50.0;
pub const PYRAMIDS_SPOT_BEAM_DEG: f32 = 35.0;

/// The vertices of the canonical square pyramid: base [−1, 1]² at y = 0, apex (0, 1, 0).
pub const PYRAMID_POSITIONS: [Vec3; 5] = [
    Vec3::new(-1.0, 0.0, -1.0),
    Vec3::new(1.0, 0.0, -1.0),
    Vec3::new(1.0, 0.0, 1.0),
    Vec3::new(-1.0, 0.0, 1.0),
    Vec3::new(0.0, 1.0, 0.0),
];
/// Its six triangles, wound outward: the base (−y) then the four sides.
pub const PYRAMID_INDICES: [[u32; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 3],
    [1, 0, 4],
    [2, 1, 4],
    [3, 2, 4],
    [0, 3, 4],
];

/// The flat-shaded square pyramid of `p` (closed, outward winding).
pub fn pyramid_mesh(p: &PyramidPlacement) -> TriangleMesh {
    let mut m = TriangleMesh {
        positions: PYRAMID_POSITIONS.to_vec(),
        normals: None,
        uvs: None,
        indices: PYRAMID_INDICES.to_vec(),
    };
    m.transform(&trs(
        p.base_center,
        Vec3::Y,
        p.turn_deg,
        Vec3::new(p.half_side, p.height, p.half_side),
    ));
    m
}

/// `shiny-pyramids` (seed 001 figs. 5.8–5.13): three near-specular GGX metal pyramids (gold,
/// silver, copper; α = 0.03) on the floor of the Cornell room, lit by a spot light aimed at the
/// ceiling, so that they reflect the lit ceiling and walls (L D S E, L D S D E …) rather than the
/// light. The seed's bunny is left out.
pub(super) fn shiny_pyramids() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("shiny-pyramids");
    b.settings.spp = Some(64);
    b.settings.max_depth = Some(16);
    b.settings.integrator = Some("path".to_string());
    cornell_room_with_light(&mut b, None, 256)?;
    for p in &PYRAMIDS {
        let (eta, k) = conductor_preset(p.preset).ok_or_else(|| {
            SceneError::InvalidParameter(format!("the {} conductor preset is missing", p.preset))
        })?;
        let name = match p.preset {
            "Au" => "gold",
            "Ag" => "silver",
            _ => "copper",
        };
        let m = b.add_material(
            name,
            Material::RoughConductor {
                eta,
                k,
                alpha: PYRAMID_ALPHA,
                specular: Spectrum::ONE,
            },
        )?;
        b.add_shape(ShapeGeometry::Mesh(pyramid_mesh(p)), m, None, false)?;
    }
    b.add_light(Light::Spot(SpotLight::new(
        PYRAMIDS_SPOT_POSITION,
        PYRAMIDS_SPOT_TARGET - PYRAMIDS_SPOT_POSITION,
        Spectrum::splat(PYRAMIDS_SPOT_INTENSITY),
        PYRAMIDS_SPOT_CUTOFF_DEG,
        PYRAMIDS_SPOT_BEAM_DEG,
    )));
    Ok(b)
}
