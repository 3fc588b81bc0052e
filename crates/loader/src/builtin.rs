//! Built-in scenes, also shipped as TOML files in `scenes/` (a test checks they agree). The
//! case-study scenes (`water-wave`, `metal-ring`, `gold-ring`; `docs/scenes.md`) are also
//! written as Mitsuba 3 XML in `scenes/mitsuba/`, with their meshes in `scenes/meshes/`. The
//! photon cone focusing scenes are in [`pcf_scenes`].

use crate::toml::look_at_transform;
use caustica_core::{Affine3A, Spectrum, Vec3};
use caustica_scene::SceneError;
use caustica_scene::camera::{FovAxis, PerspectiveCamera};
use caustica_scene::intersection::NONE;
use caustica_scene::light::{BeamLight, DirectionalLight, Light, PointLight, SpotLight};
use caustica_scene::material::{Material, conductor_preset};
use caustica_scene::medium::{DensityGrid, Medium, MediumInterface};
use caustica_scene::phase::PhaseFunction;
use caustica_scene::scene::{FilterKind, SceneBuilder};
use caustica_scene::shape::{
    MeshMotion, RingParams, ShapeGeometry, Sphere, TriangleMesh, WaveParams, moving_water_wave,
    ring_mesh, rod_mesh, water_wave_mesh,
};
use caustica_scene::texture::Texture;

pub mod pcf_scenes;
pub mod prism;
pub mod seed002_scenes;

/// The scene `caustica render` uses without an argument: the Cornell box with a glass and a
/// gold ball (`caustic-box`), rendered with `pds` in about 10 s on two cores.
pub const DEFAULT_SCENE: &str = "caustic-box";

const NAMES: &[&str] = &[
    "caustic-box",
    "cornell-box",
    "glass-sphere",
    "water-wave",
    "metal-ring",
    "gold-ring",
    "fog-box",
    "fog-box-hg",
    "smoke-plume",
    "volume-caustic",
    "facet-smoke",
    "laser-smoke",
    "glass-smoke",
    "moving-wave",
    "rotating-rod",
    "painting-glass",
    "painting-sheet",
    "torus-glass",
    "mirror-caustic-box",
    "shiny-pyramids",
    "cognac-glass",
    "swimming-pool",
    "embedded-torus",
    "prism",
];

/// Names accepted by [`builtin_scene`].
pub fn builtin_names() -> &'static [&'static str] {
    NAMES
}

/// The built-in scene called `name`, or `None`.
pub fn builtin_scene(name: &str) -> Option<SceneBuilder> {
    match name {
        "caustic-box" => caustic_box().ok(),
        "cornell-box" => cornell_box().ok(),
        "glass-sphere" => glass_sphere().ok(),
        "water-wave" => water_wave().ok(),
        "metal-ring" => metal_ring().ok(),
        "gold-ring" => gold_ring().ok(),
        "fog-box" => fog_box("fog-box", PhaseFunction::default()).ok(),
        "fog-box-hg" => PhaseFunction::henyey_greenstein(FOG_BOX_HG_G)
            .ok()
            .and_then(|p| fog_box("fog-box-hg", p).ok()),
        "smoke-plume" => smoke_plume().ok(),
        "volume-caustic" => volume_caustic().ok(),
        "facet-smoke" => facet_smoke().ok(),
        "laser-smoke" => laser_smoke().ok(),
        "glass-smoke" => glass_smoke().ok(),
        "moving-wave" => moving_wave().ok(),
        "rotating-rod" => rotating_rod().ok(),
        "painting-glass" => pcf_scenes::painting_glass().ok(),
        "painting-sheet" => pcf_scenes::painting_sheet().ok(),
        "torus-glass" => pcf_scenes::torus_glass().ok(),
        "mirror-caustic-box" => pcf_scenes::mirror_caustic_box().ok(),
        "shiny-pyramids" => pcf_scenes::shiny_pyramids().ok(),
        "cognac-glass" => seed002_scenes::cognac_glass().ok(),
        "swimming-pool" => seed002_scenes::swimming_pool().ok(),
        "embedded-torus" => seed002_scenes::embedded_torus().ok(),
        "prism" => prism::prism().ok(),
        _ => None,
    }
}

fn camera(eye: Vec3, target: Vec3, fov: f32, width: u32, height: u32) -> PerspectiveCamera {
    camera_up(eye, target, Vec3::Y, fov, width, height)
}

/// As [`camera`] with an explicit up vector (for cameras looking straight down).
fn camera_up(
    eye: Vec3,
    target: Vec3,
    up: Vec3,
    fov: f32,
    width: u32,
    height: u32,
) -> PerspectiveCamera {
    PerspectiveCamera {
        width,
        height,
        to_world: look_at_transform(eye, target, up).unwrap_or(Affine3A::IDENTITY),
        fov_deg: fov,
        fov_axis: FovAxis::X,
        lens_radius: 0.0,
        focus_distance: (target - eye).length(),
        near_clip: 1e-4,
    }
}

fn diffuse(r: f32, g: f32, b: f32) -> Material {
    Material::Diffuse {
        reflectance: Texture::Constant(Spectrum::new(r, g, b)),
    }
}

/// A smooth dielectric of index of refraction `ior`, clear.
fn dielectric(ior: f32) -> Material {
    Material::Dielectric {
        ior,
        absorption: Spectrum::ZERO,
        dispersion: None,
    }
}

/// A smooth gold conductor (the `Au` preset's complex IOR).
fn gold() -> Result<Material, SceneError> {
    let (eta, k) = conductor_preset("Au")
        .ok_or_else(|| SceneError::InvalidParameter("the Au conductor preset is missing".into()))?;
    Ok(Material::Conductor {
        eta,
        k,
        specular: Spectrum::ONE,
    })
}

/// `translate · rotate(axis, degrees) · scale`, the order Mitsuba's chained transforms use.
fn trs(t: Vec3, axis: Vec3, deg: f32, s: Vec3) -> Affine3A {
    Affine3A::from_translation(t)
        * Affine3A::from_axis_angle(axis, deg.to_radians())
        * Affine3A::from_scale(s)
}

/// Mitsuba's `mi.cornell_box()`: a 2×2×2 box around the origin, red left wall, green right
/// wall, a small rectangular area light under the ceiling and two boxes.
fn cornell_box() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("cornell-box");
    b.settings.spp = Some(64);
    b.settings.max_depth = Some(8);
    cornell_room_and_boxes(&mut b)?;
    Ok(b)
}

/// The room, light and both boxes of [`cornell_box`].
fn cornell_room_and_boxes(b: &mut SceneBuilder) -> Result<(), SceneError> {
    let white = cornell_room(b)?;
    let cube = |t: Affine3A| ShapeGeometry::Mesh(TriangleMesh::cube(&t));
    // Small box.
    b.add_shape(
        cube(trs(
            Vec3::new(0.335, -0.7, 0.38),
            Vec3::Y,
            -17.0,
            Vec3::splat(0.3),
        )),
        white,
        None,
        false,
    )?;
    // Large box.
    b.add_shape(
        cube(trs(
            Vec3::new(-0.33, -0.4, -0.28),
            Vec3::Y,
            18.25,
            Vec3::new(0.3, 0.61, 0.3),
        )),
        white,
        None,
        false,
    )?;
    Ok(())
}

/// The default scene of `caustica render`: the room of [`cornell_box`] with a glass ball
/// (IOR 1.5, radius 0.4 m) at the front right and a gold ball (radius 0.35 m) at the back
/// left instead of the boxes. The ceiling light focuses through the glass ball into a bright
/// caustic on the floor inside its shadow (L S S D E paths, which the path tracer finds only
/// by chance through an area light of 0.17 m²). Rendered by default with `pds` (s = 8) at 8 spp
/// and 4 final-gather rays per camera sample: about 10 s on two cores.
fn caustic_box() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("caustic-box");
    b.settings.spp = Some(8);
    b.settings.max_depth = Some(16);
    caustic_integrator(&mut b);
    b.settings.smoothing = Some(CAUSTIC_BOX_SMOOTHING);
    b.settings.final_gather = Some(CAUSTIC_BOX_FINAL_GATHER);
    cornell_room(&mut b)?;
    let glass = b.add_material("glass", dielectric(1.5))?;
    let gold = b.add_material("gold", gold()?)?;
    b.add_shape(
        ShapeGeometry::Sphere(Sphere {
            center: CAUSTIC_BOX_GLASS_CENTER,
            radius: CAUSTIC_BOX_GLASS_RADIUS,
        }),
        glass,
        None,
        false,
    )?;
    b.add_shape(
        ShapeGeometry::Sphere(Sphere {
            center: Vec3::new(-0.45, -0.65, -0.35),
            radius: 0.35,
        }),
        gold,
        None,
        false,
    )?;
    Ok(b)
}

/// Centre and radius (m) of the glass ball of `caustic-box`.
pub const CAUSTIC_BOX_GLASS_CENTER: Vec3 = Vec3::new(0.35, -0.6, 0.3);
pub const CAUSTIC_BOX_GLASS_RADIUS: f32 = 0.4;
/// Smoothing s of `caustic-box`, fixed rather than chosen: the SSIM optimum of a sweep of its
/// caustics (docs/results/caustic-box-smoothing). The whole image's RMSE is lowest at s ≈ 20,
/// where the automatic choice lands, because the gold ball's dim, spread-out caustics on the
/// walls dominate it; there the glass ball's sharp floor caustic is smeared and splatting takes
/// twice as long.
const CAUSTIC_BOX_SMOOTHING: f32 = 8.0;
/// Final-gather rays per camera sample of `caustic-box` (`pm`'s default is 16): with 8 spp, 32
/// gather rays per pixel, enough for the smooth indirect light of a diffuse room.
const CAUSTIC_BOX_FINAL_GATHER: u32 = 4;

/// The room of Mitsuba's `mi.cornell_box()` with its camera, filter and ceiling light: a 2×2×2
/// box around the origin, white floor, ceiling and back wall, red left and green right wall.
/// Returns the white material.
fn cornell_room(b: &mut SceneBuilder) -> Result<u32, SceneError> {
    let light = (
        trs(
            Vec3::new(0.0, 0.99, 0.01),
            Vec3::X,
            90.0,
            Vec3::new(0.23, 0.19, 0.19),
        ),
        CORNELL_LIGHT_RADIANCE,
    );
    cornell_room_with_light(b, Some(light), 256)
}

/// Radiance of the ceiling light of `mi.cornell_box()` (W/m²/sr).
const CORNELL_LIGHT_RADIANCE: Spectrum = Spectrum::new(18.387, 13.9873, 6.75357);

/// [`cornell_room`] with the camera at `size` × `size` pixels and the ceiling light replaced by
/// `light`: the transform of the [−1, 1]² rectangle (facing +z before it) and its radiance
/// (W/m²/sr), white like the walls; no light for `None`. The light, if any, is shape 0, then
/// floor, ceiling, back, right (green) and left (red) wall.
fn cornell_room_with_light(
    b: &mut SceneBuilder,
    light: Option<(Affine3A, Spectrum)>,
    size: u32,
) -> Result<u32, SceneError> {
    b.set_camera(camera(
        Vec3::new(0.0, 0.0, 3.9),
        Vec3::ZERO,
        39.3077,
        size,
        size,
    ));
    b.settings.filter = FilterKind::Gaussian {
        stddev: 0.5,
        radius: 2.0,
    };
    let white = b.add_material("white", diffuse(0.885809, 0.698859, 0.666422))?;
    let green = b.add_material("green", diffuse(0.105421, 0.37798, 0.076425))?;
    let red = b.add_material("red", diffuse(0.570068, 0.0430135, 0.0443706))?;
    let rect = |t: Affine3A| ShapeGeometry::Mesh(TriangleMesh::rectangle(&t));
    let one = Vec3::ONE;
    if let Some((to_world, radiance)) = light {
        b.add_shape(rect(to_world), white, Some(radiance), false)?;
    }
    b.add_shape(
        rect(trs(Vec3::new(0.0, -1.0, 0.0), Vec3::X, -90.0, one)),
        white,
        None,
        false,
    )?;
    b.add_shape(
        rect(trs(Vec3::new(0.0, 1.0, 0.0), Vec3::X, 90.0, one)),
        white,
        None,
        false,
    )?;
    b.add_shape(
        rect(trs(Vec3::new(0.0, 0.0, -1.0), Vec3::X, 0.0, one)),
        white,
        None,
        false,
    )?;
    b.add_shape(
        rect(trs(Vec3::new(1.0, 0.0, 0.0), Vec3::Y, -90.0, one)),
        green,
        None,
        false,
    )?;
    b.add_shape(
        rect(trs(Vec3::new(-1.0, 0.0, 0.0), Vec3::Y, 90.0, one)),
        red,
        None,
        false,
    )?;
    Ok(white)
}

/// A glass ball (IOR 1.5, radius 0.5) resting on a grey diffuse floor, lit by a point light
/// above and to the side so that its caustic falls beside the contact point, seen from above.
fn glass_sphere() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("glass-sphere");
    b.set_camera(camera(
        Vec3::new(1.8, 2.6, 2.4),
        Vec3::new(0.15, 0.25, 0.0),
        40.0,
        256,
        256,
    ));
    b.settings.spp = Some(64);
    b.settings.max_depth = Some(16);
    caustic_integrator(&mut b);
    let floor = b.add_material("floor", diffuse(0.8, 0.8, 0.8))?;
    let glass = b.add_material("glass", dielectric(1.5))?;
    b.add_shape(
        ShapeGeometry::Mesh(TriangleMesh::rectangle(&trs(
            Vec3::ZERO,
            Vec3::X,
            -90.0,
            Vec3::splat(2.0),
        ))),
        floor,
        None,
        false,
    )?;
    b.add_shape(
        ShapeGeometry::Sphere(Sphere {
            center: Vec3::new(0.0, 0.5, 0.0),
            radius: 0.5,
        }),
        glass,
        None,
        false,
    )?;
    b.add_light(Light::Point(PointLight::new(
        Vec3::new(-2.0, 3.5, 0.0),
        Spectrum::splat(40.0),
    )));
    Ok(b)
}

/// The water surface of `water-wave` (seed 000 §6.2, fig. 6.2(a)): one wavelength (2 m) of
/// `y = 3 + 0.25 cos(π x)` over `|x|, |z| ≤ 1`, 128 × 8 grid cells (2048 triangles). The crest
/// is a cylindrical lens of focal length n/((n − 1) κ) ≈ 1.63 m (κ = 0.25 π² the crest's
/// curvature), so the floor 3 m below lies beyond the focus: the refracted rays cross and fold
/// into two bright bands at x ≈ ±0.18 m with a less bright region between them and dark floor
/// outside.
pub const WATER_WAVE: WaveParams = WaveParams {
    half_width: 1.0,
    mean_height: 3.0,
    amplitude: 0.25,
    cells_x: 128,
    cells_z: 8,
};

/// Index of refraction of the water in `water-wave` (one interface: air above, water below).
pub const WATER_IOR: f32 = 1.33;

/// The ring of `metal-ring` and `gold-ring`: inner radius 1 m, wall 0.1 m thick, 0.5 m high
/// (half its inner radius — the "clipped" ring of seed 000 §6.3), 128 segments (1024
/// triangles).
pub const RING: RingParams = RingParams {
    inner_radius: 1.0,
    outer_radius: 1.1,
    height: 0.5,
    segments: 128,
};

/// Elevation of the collimated light of `metal-ring` above the floor (degrees). Light enters
/// the ring over its near wall and reflects off the far inner wall; a ray reflected at
/// azimuth φ touches the nephroid caustic R cos φ / 2 from the wall (horizontally), but
/// reaches the floor between 2R(k − cos φ) and 2Rk from it, with k = H cot(elevation) / 2R
/// ≈ 1.42 here (H the height, R the inner radius). For
/// k > 5/4 the floor stops the two envelopes before they meet in the cusp (seed 000 §6.3);
/// the whole floor inside the ring is in the near wall's shadow (k > 1).
pub const METAL_RING_ELEVATION_DEG: f32 = 10.0;

/// Elevation of the area light of `gold-ring` seen from the ring's centre (degrees): k ≈ 1.08,
/// so the whole cardioid with its cusp reaches the floor, which is otherwise in shadow inside
/// the ring.
pub const GOLD_RING_ELEVATION_DEG: f32 = 13.0;

/// Distance of the `gold-ring` area light's centre from the ring's centre (m).
pub const GOLD_RING_LIGHT_DISTANCE: f32 = 10.0;

/// Unit direction of light travelling toward +x and down at `elevation_deg`.
pub fn slanted_direction(elevation_deg: f32) -> Vec3 {
    let (s, c) = elevation_deg.to_radians().sin_cos();
    Vec3::new(c, -s, 0.0)
}

/// A square diffuse floor `[−half, half]²` in the plane y = 0, facing up.
fn add_floor(b: &mut SceneBuilder, half: f32, material: u32) -> Result<(), SceneError> {
    b.add_shape(
        ShapeGeometry::Mesh(TriangleMesh::rectangle(&trs(
            Vec3::ZERO,
            Vec3::X,
            -90.0,
            Vec3::splat(half),
        ))),
        material,
        None,
        false,
    )
}

/// Settings shared by the case scenes: like their Mitsuba files, but rendered by default with
/// the method that shows their caustic (their Mitsuba files name Mitsuba's `ptracer` or
/// `path`, which see it noisily or not at all).
fn case_settings(b: &mut SceneBuilder) {
    b.settings.spp = Some(64);
    b.settings.max_depth = Some(16);
    caustic_integrator(b);
}

/// `pds`, the built-in caustic scenes' default method, with no smoothing: the renderer chooses
/// s from the traced photons (least-squares cross-validation, docs/automatic-bandwidths.md).
fn caustic_integrator(b: &mut SceneBuilder) {
    b.settings.integrator = Some("pds".to_string());
}

/// Seed 000 §6.2, the refraction case: collimated light straight down through a sinusoidal
/// water surface ([`WATER_WAVE`], IOR 1.33, a single open interface whose normals face the air)
/// onto a diffuse floor 3 m below. The camera is under the surface, 1.2 m above the floor,
/// looking straight down, so it sees only the caustic (x to the image's right); the light
/// tracer can connect floor points to it.
fn water_wave() -> Result<SceneBuilder, SceneError> {
    water_wave_with("water-wave", |b, water| {
        b.add_shape(
            ShapeGeometry::Mesh(water_wave_mesh(&WATER_WAVE)),
            water,
            None,
            false,
        )
    })
}

/// The refraction case with the water surface added by `wave` (given the water material).
fn water_wave_with(
    name: &str,
    wave: impl FnOnce(&mut SceneBuilder, u32) -> Result<(), SceneError>,
) -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new(name);
    b.set_camera(camera_up(
        Vec3::new(0.0, 1.2, 0.0),
        Vec3::ZERO,
        Vec3::NEG_Z,
        45.0,
        256,
        256,
    ));
    case_settings(&mut b);
    let floor = b.add_material("floor", diffuse(0.8, 0.8, 0.8))?;
    let water = b.add_material("water", dielectric(WATER_IOR))?;
    add_floor(&mut b, WATER_WAVE.half_width, floor)?;
    wave(&mut b, water)?;
    b.add_light(Light::Directional(DirectionalLight::new(
        Vec3::NEG_Y,
        Spectrum::splat(0.5),
    )));
    Ok(b)
}

/// Phase speed of `moving-wave` (m per frame): a twentieth of the 2 m wavelength, so one
/// frame of exposure blurs the caustic bands by about a tenth of the camera's 1 m view.
pub const MOVING_WAVE_STEP: f32 = 0.1;

/// Keyframes of `moving-wave` (frames 0 … 24: one second at [`ANIMATION_FPS`]).
pub const MOVING_WAVE_FRAMES: u32 = 25;

/// Frame rate of the built-in animated scenes (frames per second).
pub const ANIMATION_FPS: f32 = 25.0;

/// Seed 003 fig. 7–8 (S-T1): `water-wave` with its wave travelling toward +x by
/// [`MOVING_WAVE_STEP`] per frame, the crests moving perpendicular to themselves; the shutter
/// opens at frame 0 for one frame (seed 003's e = 1). The camera sees only the floor, so only
/// the caustic is blurred by motion.
fn moving_wave() -> Result<SceneBuilder, SceneError> {
    let mut b = water_wave_with("moving-wave", |b, water| {
        let (mesh, motion) = moving_water_wave(&WATER_WAVE, MOVING_WAVE_STEP, MOVING_WAVE_FRAMES);
        b.add_moving_mesh(mesh, motion, water, false)
    })?;
    b.set_shutter(caustica_scene::Shutter::new(0.0, 1.0)?);
    b.settings.fps = Some(ANIMATION_FPS);
    Ok(b)
}

/// The glass rod of `rotating-rod`: radius, length (m), height of its axis above the floor (m),
/// IOR, and its rotation per frame (degrees, counter-clockwise seen from above).
pub const ROD_RADIUS: f32 = 0.08;
pub const ROD_LENGTH: f32 = 1.2;
pub const ROD_HEIGHT: f32 = 0.11;
pub const ROD_IOR: f32 = 1.5;
pub const ROD_DEG_PER_FRAME: f32 = 3.0;
/// Direction the light of `rotating-rod` travels: down and toward +z (the image's bottom), so
/// the rod's focal line falls beside it where the camera above sees it.
pub const ROD_LIGHT_DIRECTION: Vec3 = Vec3::new(0.0, -1.0, 1.0);

/// The rod of `rotating-rod` in its own frame: axis along +x from the origin (the pivot end),
/// 48 segments round, 12 along (shipped as `scenes/meshes/rod.ply`).
pub fn rod() -> TriangleMesh {
    rod_mesh(ROD_RADIUS, ROD_LENGTH, 48, 12)
}

/// Seed 003 fig. 9–10 (S-T2): a horizontal glass rod ([`rod_mesh`], Phong-shaded side) turning
/// counter-clockwise about a vertical axis through the centre of its left end, under
/// collimated light ([`ROD_LIGHT_DIRECTION`]), above a diffuse floor; the far end moves
/// fastest, so its caustic blurs most. The camera looks straight down from 3 m. 25 keyframes
/// (rigid transforms), shutter [0, 1] frame. Pixels that see the rod directly are masked in
/// comparisons (the light tracer leaves them black in caustics-only renders).
fn rotating_rod() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("rotating-rod");
    b.set_camera(camera_up(
        Vec3::new(0.0, 1.6, 0.0),
        Vec3::ZERO,
        Vec3::NEG_Z,
        45.0,
        256,
        256,
    ));
    case_settings(&mut b);
    let floor = b.add_material("floor", diffuse(0.8, 0.8, 0.8))?;
    let glass = b.add_material("glass", dielectric(ROD_IOR))?;
    add_floor(&mut b, 1.5, floor)?;
    let mesh = rod();
    let pivot = Vec3::new(-0.5 * ROD_LENGTH, ROD_HEIGHT, 0.0);
    let transforms: Vec<Affine3A> = (0..MOVING_WAVE_FRAMES)
        .map(|f| {
            Affine3A::from_translation(pivot)
                * Affine3A::from_rotation_y((ROD_DEG_PER_FRAME * f as f32).to_radians())
        })
        .collect();
    let motion = MeshMotion::from_transforms(0.0, &mesh, &transforms)?;
    b.add_moving_mesh(mesh, motion, glass, false)?;
    b.add_light(Light::Directional(DirectionalLight::new(
        ROD_LIGHT_DIRECTION.normalize(),
        Spectrum::splat(0.5),
    )));
    b.set_shutter(caustica_scene::Shutter::new(0.0, 1.0)?);
    b.settings.fps = Some(ANIMATION_FPS);
    Ok(b)
}

/// Seed 000 §6.3, the reflection case: the clipped mirror ring ([`RING`]) on a diffuse floor
/// under collimated light at [`METAL_RING_ELEVATION_DEG`] travelling toward +x. The camera looks
/// straight down into the ring from 4 m (light from the image's left).
fn metal_ring() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("metal-ring");
    b.set_camera(camera_up(
        Vec3::new(0.0, 4.0, 0.0),
        Vec3::ZERO,
        Vec3::NEG_Z,
        30.0,
        256,
        256,
    ));
    case_settings(&mut b);
    let floor = b.add_material("floor", diffuse(0.8, 0.8, 0.8))?;
    let metal = b.add_material(
        "metal",
        Material::Mirror {
            reflectance: Spectrum::ONE,
        },
    )?;
    add_floor(&mut b, 1.5, floor)?;
    b.add_shape(ShapeGeometry::Mesh(ring_mesh(&RING)), metal, None, false)?;
    b.add_light(Light::Directional(DirectionalLight::new(
        slanted_direction(METAL_RING_ELEVATION_DEG),
        Spectrum::splat(5.0),
    )));
    Ok(b)
}

/// Centre of the `gold-ring` area light.
pub fn gold_ring_light_center() -> Vec3 {
    -slanted_direction(GOLD_RING_ELEVATION_DEG) * GOLD_RING_LIGHT_DISTANCE
}

/// Seed 002 fig. 1: the same ring in gold (complex IOR, the `Au` conductor preset) on a diffuse
/// floor, lit by a 0.6 m square diffuse area light 10 m away at [`GOLD_RING_ELEVATION_DEG`]
/// facing the ring (radiance 1500 W/m²/sr, ≈ 5.4 W/m² across the beam), on a 10 × 10 m floor.
/// The camera looks down at the ring from the front (light from the image's left), so it sees
/// the ring, the cardioid inside it and the ring's long shadow. Seed 002's reference (and the
/// Mitsuba file) use the path tracer; the built-in suggests `pds`, which finds the caustic with
/// far less noise.
fn gold_ring() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("gold-ring");
    b.set_camera(camera(
        Vec3::new(0.2, 4.8, 4.4),
        Vec3::new(0.2, 0.0, 0.0),
        40.0,
        256,
        192,
    ));
    case_settings(&mut b);
    let floor = b.add_material("floor", diffuse(0.8, 0.8, 0.8))?;
    let gold = b.add_material("gold", gold()?)?;
    let black = b.add_material("light-black", diffuse(0.0, 0.0, 0.0))?;
    add_floor(&mut b, 5.0, floor)?;
    b.add_shape(ShapeGeometry::Mesh(ring_mesh(&RING)), gold, None, false)?;
    let to_light = look_at_transform(gold_ring_light_center(), Vec3::ZERO, Vec3::Y)
        .unwrap_or(Affine3A::IDENTITY);
    b.add_shape(
        ShapeGeometry::Mesh(TriangleMesh::rectangle(
            &(to_light * Affine3A::from_scale(Vec3::splat(0.3))),
        )),
        black,
        Some(Spectrum::splat(1500.0)),
        false,
    )?;
    Ok(b)
}

/// Mean cosine of the Henyey–Greenstein phase function of `fog-box-hg`.
pub const FOG_BOX_HG_G: f32 = 0.6;
/// Voxels per axis of the `smoke-plume` grid.
pub const SMOKE_PLUME_RES: u32 = 32;
/// Extinction of the `smoke-plume` medium at density 1 (m⁻¹, Mitsuba's `scale`).
pub const SMOKE_PLUME_SCALE: f32 = 6.0;

/// The dimensionless density of `smoke-plume` (and of TOML's `density = "plume"`) at the
/// grid-space point `u` ∈ [0, 1]³ (y up): a Gaussian column whose axis wanders with height v,
/// cx = 0.5 + 0.08 sin 6v, cz = 0.5 + 0.08 cos 5v, widening as rad = 0.12 + 0.25 v, thinning
/// as 1 − v and modulated by 1 − 0.3 sin 11u sin 13w; never negative.
pub fn plume_density(u: Vec3) -> f32 {
    let (x, v, w) = (u.x, u.y, u.z);
    let cx = 0.5 + 0.08 * (6.0 * v).sin();
    let cz = 0.5 + 0.08 * (5.0 * v).cos();
    let rad = 0.12 + 0.25 * v;
    let r2 = (x - cx).powi(2) + (w - cz).powi(2);
    let d = (-r2 / (2.0 * rad * rad)).exp()
        * (1.0 - v)
        * (1.0 - 0.3 * (11.0 * x).sin() * (13.0 * w).sin());
    d.max(0.0)
}

/// The affine map of the unit cube [0, 1]³ onto the box [`min`, `max`] (a grid's placement).
pub fn unit_cube_to_box(min: Vec3, max: Vec3) -> Affine3A {
    Affine3A::from_translation(min) * Affine3A::from_scale(max - min)
}

/// Mitsuba's `cube` ([−1, 1]³, outward faces) scaled and moved onto the box [`min`, `max`].
fn box_mesh(min: Vec3, max: Vec3) -> ShapeGeometry {
    let t = Affine3A::from_translation((min + max) * 0.5) * Affine3A::from_scale((max - min) * 0.5);
    ShapeGeometry::Mesh(TriangleMesh::cube(&t))
}

/// Adds the index-matched (`null`) box [`min`, `max`] with `medium` inside, and its material
/// `boundary`.
fn add_medium_box(
    b: &mut SceneBuilder,
    min: Vec3,
    max: Vec3,
    medium: u32,
) -> Result<(), SceneError> {
    let boundary = b.add_material("boundary", Material::Null)?;
    b.add_shape_with_media(
        box_mesh(min, max),
        boundary,
        None,
        false,
        MediumInterface {
            inside: medium,
            outside: NONE,
        },
    )
}

/// Settings of the medium scenes rendered with the path tracer.
fn media_path_settings(b: &mut SceneBuilder) {
    b.settings.spp = Some(64);
    b.settings.max_depth = Some(64);
    b.settings.integrator = Some("path".to_string());
}

/// `fog-box` and `fog-box-hg`: [`cornell_box`] filled with homogeneous fog (σ_s = (0.4, 0.5,
/// 0.6), σ_a = 0.05 m⁻¹, i.e. σ_t = (0.45, 0.55, 0.65)) inside a null box just inside the walls
/// (x, y ∈ [−0.998, 0.998], z ∈ [−0.998, 1]: the area light and both boxes are in the fog, the
/// camera is not).
fn fog_box(name: &str, phase: PhaseFunction) -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new(name);
    media_path_settings(&mut b);
    cornell_room_and_boxes(&mut b)?;
    let fog = b.add_medium(
        "fog",
        Medium::homogeneous(Spectrum::splat(0.05), Spectrum::new(0.4, 0.5, 0.6), phase),
    )?;
    add_medium_box(
        &mut b,
        Vec3::new(-0.998, -0.998, -0.998),
        Vec3::new(0.998, 0.998, 1.0),
        fog,
    )?;
    Ok(b)
}

/// Box of the `smoke-plume` grid and of its null boundary: from the floor (1 mm above) to 0.4 m
/// below the ceiling light.
pub const SMOKE_PLUME_BOX: [Vec3; 2] = [Vec3::new(-0.6, -0.999, -0.6), Vec3::new(0.6, 0.6, 0.6)];

/// `smoke-plume`: the Cornell room ([`cornell_room`], no boxes) with a rising plume of smoke:
/// a [`SMOKE_PLUME_RES`]³ grid of [`plume_density`] filling [`SMOKE_PLUME_BOX`], σ_t =
/// [`SMOKE_PLUME_SCALE`] × density, albedo (0.9, 0.8, 0.7), isotropic.
fn smoke_plume() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("smoke-plume");
    media_path_settings(&mut b);
    cornell_room(&mut b)?;
    let [min, max] = SMOKE_PLUME_BOX;
    let r = SMOKE_PLUME_RES;
    let grid = DensityGrid::from_fn([r; 3], unit_cube_to_box(min, max), plume_density)
        .map_err(SceneError::InvalidParameter)?;
    let (sigma_a, sigma_s) = Medium::coefficients_from_albedo(
        Spectrum::ONE * SMOKE_PLUME_SCALE,
        Spectrum::new(0.9, 0.8, 0.7),
    );
    let smoke = b.add_medium(
        "smoke",
        Medium::grid(grid, sigma_a, sigma_s, PhaseFunction::default()),
    )?;
    add_medium_box(&mut b, min, max, smoke)?;
    Ok(b)
}

/// `volume-caustic`: a glass ball (IOR 1.5, radius 0.5 m, centre 1.2 m above the floor) under
/// a hard-edged spot light (20° cone, 60 W/sr, 3 m up, pointing down) in homogeneous fog
/// (σ_s = 0.15, σ_a = 0.01 m⁻¹, isotropic; the ball's outside is the fog, its inside vacuum)
/// filling a null box [−4, 4] × [−0.001, 5] × [−4, 4] around an 8 × 8 m grey floor (the camera,
/// at z = 4.5, looks in from outside). The ball
/// focuses the cone into a bright beam and a caustic on the floor, L S+ M E and L S+ D E paths;
/// the light tracer renders them.
fn volume_caustic() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("volume-caustic");
    b.set_camera(camera(
        Vec3::new(0.0, 1.1, 4.5),
        Vec3::new(0.0, 0.8, 0.0),
        40.0,
        128,
        96,
    ));
    b.settings.filter = FilterKind::Gaussian {
        stddev: 0.5,
        radius: 2.0,
    };
    b.settings.spp = Some(16);
    b.settings.max_depth = Some(64);
    b.settings.integrator = Some("lighttrace".to_string());
    let floor = b.add_material("floor", diffuse(0.5, 0.5, 0.5))?;
    let glass = b.add_material("glass", dielectric(1.5))?;
    let fog = b.add_medium(
        "fog",
        Medium::homogeneous(
            Spectrum::splat(0.01),
            Spectrum::splat(0.15),
            PhaseFunction::default(),
        ),
    )?;
    add_floor(&mut b, 4.0, floor)?;
    b.add_shape_with_media(
        ShapeGeometry::Sphere(Sphere {
            center: Vec3::new(0.0, 1.2, 0.0),
            radius: 0.5,
        }),
        glass,
        None,
        false,
        MediumInterface {
            inside: NONE,
            outside: fog,
        },
    )?;
    add_medium_box(
        &mut b,
        Vec3::new(-4.0, -0.001, -4.0),
        Vec3::new(4.0, 5.0, 4.0),
        fog,
    )?;
    b.add_light(Light::Spot(SpotLight::new(
        Vec3::new(0.0, 3.0, 0.0),
        Vec3::NEG_Y,
        Spectrum::splat(60.0),
        20.0,
        20.0,
    )));
    Ok(b)
}

// ---------------------------------------------------------------------------------------------
// The participating-media scenes of seed 000 sec. 8.5 (Schjøth 2009 ch. 8, figs. 8.5–8.7):
// `facet-smoke` (S-M1), `laser-smoke` (S-M2) and `glass-smoke` (S-M3). What the thesis leaves
// open and why these values: docs/scenes.md.

/// A hash of the integer lattice point (i, j, k) to [0, 1) (a 32-bit integer mix; the same on
/// every platform).
fn lattice_hash(i: i32, j: i32, k: i32) -> f32 {
    let mut h = (i as u32).wrapping_mul(0x8da6_b343)
        ^ (j as u32).wrapping_mul(0xd816_3841)
        ^ (k as u32).wrapping_mul(0xcb1a_b31f);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^= h >> 16;
    (h >> 8) as f32 / (1u32 << 24) as f32
}

/// Value noise at `p`: the lattice values of [`lattice_hash`] at the unit cube's corners around
/// `p`, interpolated with smoothstep weights; in [0, 1), continuous, with unit feature size.
pub fn value_noise(p: Vec3) -> f32 {
    let f = p.floor();
    let (i, j, k) = (f.x as i32, f.y as i32, f.z as i32);
    let t = p - f;
    let w = t * t * (Vec3::splat(3.0) - 2.0 * t);
    let lerp = |a: f32, b: f32, s: f32| a + (b - a) * s;
    let v = |di: i32, dj: i32, dk: i32| {
        lattice_hash(i.wrapping_add(di), j.wrapping_add(dj), k.wrapping_add(dk))
    };
    let x00 = lerp(v(0, 0, 0), v(1, 0, 0), w.x);
    let x10 = lerp(v(0, 1, 0), v(1, 1, 0), w.x);
    let x01 = lerp(v(0, 0, 1), v(1, 0, 1), w.x);
    let x11 = lerp(v(0, 1, 1), v(1, 1, 1), w.x);
    lerp(lerp(x00, x10, w.y), lerp(x01, x11, w.y), w.z)
}

/// Fractal value noise: four octaves of [`value_noise`] (frequencies 1, 2, 4, 8, amplitudes
/// halving, each octave shifted), normalised to [0, 1) with mean about ½.
pub fn smoke_noise(p: Vec3) -> f32 {
    let (mut sum, mut amp, mut norm, mut q) = (0.0, 1.0, 0.0, p);
    for o in 0..4 {
        sum += amp * value_noise(q + Vec3::new(17.3, 5.1, 11.7) * o as f32);
        norm += amp;
        amp *= 0.5;
        q *= 2.0;
    }
    sum / norm
}

/// The dimensionless density of `facet-smoke` (and of TOML's `density = "rising-smoke"`) at
/// the grid-space point `u` ∈ [0, 1]³ (y up): warm smoke rising from the floor. Fractal noise
/// ([`smoke_noise`]) stretched twofold along y, its horizontal coordinates swaying with height,
/// mapped to wisps with clear air between them by (noise − 0.45) / 0.15 clamped to [0, 1];
/// times a broad column around the room's axis (0.4 at the walls, 1 on the axis, Gaussian of
/// width 0.3) and a fade 1 − v² to nothing at the top of the grid. In [0, 1].
pub fn rising_smoke_density(u: Vec3) -> f32 {
    let (x, v, z) = (u.x, u.y, u.z);
    let q = Vec3::new(
        5.0 * (x + 0.06 * (7.0 * v).sin()),
        2.5 * v,
        5.0 * (z + 0.06 * (6.0 * v).cos()),
    );
    let wisps = ((smoke_noise(q) - 0.45) / 0.15).clamp(0.0, 1.0);
    let r2 = (x - 0.5).powi(2) + (z - 0.5).powi(2);
    let column = 0.4 + 0.6 * (-r2 / (2.0 * 0.3 * 0.3)).exp();
    (column * wisps * (1.0 - v * v)).clamp(0.0, 1.0)
}

/// The dimensionless density of `laser-smoke` (and of TOML's `density = "room-smoke"`) at the
/// grid-space point `u` ∈ [0, 1]³ (y up): smoke filling the room, fractal noise at a feature
/// size of a quarter of the grid, 0.6 + 1.6 (noise − ½) clamped to [0.05, 1.2], denser near the
/// floor (× (1 − 0.4 v)).
pub fn room_smoke_density(u: Vec3) -> f32 {
    let q = Vec3::new(4.0 * u.x, 3.0 * u.y, 4.0 * u.z) + Vec3::new(3.7, 1.3, 8.9);
    let n = (0.6 + 1.6 * (smoke_noise(q) - 0.5)).clamp(0.05, 1.2);
    n * (1.0 - 0.4 * u.y)
}

/// Volume smoothing of `facet-smoke`, `laser-smoke` and `glass-smoke` (vpd's `s`): the
/// collimated laser's kernels never widen (its directional differentials are zero), so it needs
/// a far larger `s` than the area-lit scenes.
pub const FACET_SMOKE_S: f32 = 8.0;
pub const LASER_SMOKE_S: f32 = 128.0;
pub const GLASS_SMOKE_S: f32 = 8.0;

/// Settings of the sec. 8.5 scenes: 16 spp, max depth 64, photon differentials in media (vpd)
/// with the volume smoothing `s` of `docs/results/volume-differentials` (the RMSE optimum of
/// the scene's sweep, rounded to a power of two).
///
/// The volume photons are the thesis's counts (80 000, 80 000, 10 000), for which `s` was chosen.
/// Final gathering runs the volume estimate along every gather ray, which costs most of a render
/// in these scenes (glass-smoke: 110 s per sample with 16 gather rays, 4 s with none), so the
/// area-lit scenes show the global map directly (`final_gather = 0`) and the laser, whose
/// kernels are small, gathers with 2 rays; `glass-smoke` takes 8 spp (about 30 s on two cores).
fn media_photon_settings(
    b: &mut SceneBuilder,
    volume_smoothing: f32,
    volume_photons: u32,
    final_gather: u32,
) {
    b.settings.spp = Some(16);
    b.settings.max_depth = Some(64);
    b.settings.integrator = Some("vpd".to_string());
    b.settings.volume_smoothing = Some(volume_smoothing);
    b.settings.volume_photons = Some(volume_photons);
    b.settings.final_gather = Some(final_gather);
}

/// Adds a grid medium `name` of `res` voxels of `density` filling `[min, max]`, extinction
/// `sigma_t` (m⁻¹) at density 1, single-scattering `albedo`, isotropic, inside a null box of
/// the same size.
fn add_smoke(
    b: &mut SceneBuilder,
    name: &str,
    [min, max]: [Vec3; 2],
    res: [u32; 3],
    density: fn(Vec3) -> f32,
    sigma_t: f32,
    albedo: Spectrum,
) -> Result<(), SceneError> {
    let grid = DensityGrid::from_fn(res, unit_cube_to_box(min, max), density)
        .map_err(SceneError::InvalidParameter)?;
    let (sigma_a, sigma_s) = Medium::coefficients_from_albedo(Spectrum::splat(sigma_t), albedo);
    let smoke = b.add_medium(
        name,
        Medium::grid(grid, sigma_a, sigma_s, PhaseFunction::default()),
    )?;
    add_medium_box(b, min, max, smoke)
}

/// Box of the `facet-smoke` grid and its null boundary (m): the room's width and depth, 1–2 mm
/// inside the walls, from 1 mm above the floor to 0.4 m above the room's centre.
pub const FACET_SMOKE_BOX: [Vec3; 2] = [
    Vec3::new(-0.998, -0.999, -0.998),
    Vec3::new(0.998, 0.4, 0.998),
];
/// Voxels of the `facet-smoke` grid (x, y, z).
pub const FACET_SMOKE_RES: [u32; 3] = [32, 24, 32];
/// Extinction of the `facet-smoke` smoke at density 1 (m⁻¹).
pub const FACET_SMOKE_SIGMA_T: f32 = 2.2;
/// Single-scattering albedo of the `facet-smoke` smoke (warm: mean 0.9).
pub const FACET_SMOKE_ALBEDO: Spectrum = Spectrum::new(0.96, 0.9, 0.84);
/// Centre and radius (m) of the faceted sphere of `facet-smoke`, levitating with its bottom
/// 0.5 m above the floor.
pub const FACET_SMOKE_SPHERE_CENTER: Vec3 = Vec3::new(0.0, -0.2, 0.0);
pub const FACET_SMOKE_SPHERE_RADIUS: f32 = 0.3;
/// Subdivisions of the icosahedron of the `facet-smoke` sphere (1: 80 facets).
pub const FACET_SMOKE_SPHERE_SUBDIVISIONS: u32 = 1;
/// Half the side (m) of the square ceiling light of `facet-smoke` (1 × 1 m) and its radiance
/// (W/m²/sr): the colour of `mi.cornell_box()`'s light at 0.4 of its radiance, so 2.3 times
/// its power (the light is 5.7 times larger).
pub const FACET_SMOKE_LIGHT_HALF: f32 = 0.5;
pub const FACET_SMOKE_LIGHT_RADIANCE: Spectrum = Spectrum::new(7.3548, 5.59492, 2.701428);

/// The faceted sphere of `facet-smoke` (`scenes/meshes/facet-sphere.ply`).
pub fn facet_smoke_sphere() -> TriangleMesh {
    caustica_scene::shape::geodesic_sphere_mesh(
        FACET_SMOKE_SPHERE_CENTER,
        FACET_SMOKE_SPHERE_RADIUS,
        FACET_SMOKE_SPHERE_SUBDIVISIONS,
    )
}

/// `facet-smoke` (S-M1, seed 000 fig. 8.5): the Cornell room ([`cornell_room`], no boxes) with
/// a 1 × 1 m ceiling light, warm smoke rising from the floor ([`rising_smoke_density`] on a
/// [`FACET_SMOKE_RES`] grid filling [`FACET_SMOKE_BOX`], σ_t = [`FACET_SMOKE_SIGMA_T`] ×
/// density, albedo [`FACET_SMOKE_ALBEDO`], isotropic) around a diffuse white faceted sphere (80
/// flat facets, radius 0.3 m) levitating in it. Heterogeneous media in a diffuse environment;
/// no prominent volume caustics.
fn facet_smoke() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("facet-smoke");
    media_photon_settings(&mut b, FACET_SMOKE_S, 80_000, 0);
    let light = trs(
        Vec3::new(0.0, 0.99, 0.0),
        Vec3::X,
        90.0,
        Vec3::splat(FACET_SMOKE_LIGHT_HALF),
    );
    cornell_room_with_light(&mut b, Some((light, FACET_SMOKE_LIGHT_RADIANCE)), 128)?;
    let sphere = b.add_material("sphere", diffuse(0.8, 0.8, 0.8))?;
    b.add_shape(
        ShapeGeometry::Mesh(facet_smoke_sphere()),
        sphere,
        None,
        false,
    )?;
    add_smoke(
        &mut b,
        "smoke",
        FACET_SMOKE_BOX,
        FACET_SMOKE_RES,
        rising_smoke_density,
        FACET_SMOKE_SIGMA_T,
        FACET_SMOKE_ALBEDO,
    )?;
    Ok(b)
}

/// The faceted silver hemisphere of `laser-smoke` on the floor: radius 0.35 m, a pentagonal
/// cap reaching 52° from the apex (its facets lean 31.1° from the horizontal, so they reflect
/// the vertical laser into five beams 62.2° from the vertical), two bands below it (40
/// facets). The cap is turned so that the five beams leave at azimuths 11.5° + 72° k (from +x
/// toward +z): none runs straight away from the camera (it would hide behind the incoming
/// beam) and no two mirror each other across the image's vertical, so seen from the front the
/// five beams and the laser lean at least 17° apart (the beam at 83.5° comes toward the
/// camera).
pub const LASER_SMOKE_DOME: caustica_scene::shape::DomeParams = caustica_scene::shape::DomeParams {
    base: Vec3::new(0.0, -1.0, 0.0),
    radius: 0.35,
    cap_facets: 5,
    cap_polar_deg: 52.0,
    bands: 2,
    azimuth_deg: 47.5,
};
/// Aperture centre of the `laser-smoke` beam (m), 1 cm under the ceiling above the apex.
pub const LASER_SMOKE_BEAM_CENTER: Vec3 = Vec3::new(0.0, 0.99, 0.0);
/// Radius of the `laser-smoke` beam (m): 1 % of the room's width.
pub const LASER_SMOKE_BEAM_RADIUS: f32 = 0.02;
/// Irradiance across the `laser-smoke` beam (W/m²): 1.26 W in all.
pub const LASER_SMOKE_IRRADIANCE: f32 = 1000.0;
/// Box of the `laser-smoke` grid and its null boundary (m): the whole room, 1–2 mm inside its
/// walls, floor and ceiling.
pub const LASER_SMOKE_BOX: [Vec3; 2] = [Vec3::splat(-0.998), Vec3::splat(0.998)];
/// Voxels of the `laser-smoke` grid per axis.
pub const LASER_SMOKE_RES: [u32; 3] = [32, 32, 32];
/// Extinction of the `laser-smoke` smoke at density 1 (m⁻¹).
pub const LASER_SMOKE_SIGMA_T: f32 = 0.6;
/// Single-scattering albedo of the `laser-smoke` smoke (grey).
pub const LASER_SMOKE_ALBEDO: f32 = 0.9;

/// `laser-smoke` (S-M2, seed 000 fig. 8.6): the Cornell room without its ceiling light, filled
/// with thin smoke ([`room_smoke_density`] on a 32³ grid filling [`LASER_SMOKE_BOX`], σ_t =
/// [`LASER_SMOKE_SIGMA_T`] × density, albedo 0.9, isotropic); a narrow collimated beam
/// (radius 2 cm, 1000 W/m², white) straight down from under the ceiling onto the apex of a
/// faceted silver hemisphere ([`LASER_SMOKE_DOME`], smooth `Ag` conductor) on the floor, whose
/// five cap facets reflect it into five beams through the smoke.
fn laser_smoke() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("laser-smoke");
    media_photon_settings(&mut b, LASER_SMOKE_S, 80_000, 2);
    cornell_room_with_light(&mut b, None, 128)?;
    let (eta, k) = conductor_preset("Ag")
        .ok_or_else(|| SceneError::InvalidParameter("the Ag conductor preset is missing".into()))?;
    let silver = b.add_material(
        "silver",
        Material::Conductor {
            eta,
            k,
            specular: Spectrum::ONE,
        },
    )?;
    b.add_shape(
        ShapeGeometry::Mesh(caustica_scene::shape::faceted_dome_mesh(&LASER_SMOKE_DOME)),
        silver,
        None,
        false,
    )?;
    add_smoke(
        &mut b,
        "smoke",
        LASER_SMOKE_BOX,
        LASER_SMOKE_RES,
        room_smoke_density,
        LASER_SMOKE_SIGMA_T,
        Spectrum::splat(LASER_SMOKE_ALBEDO),
    )?;
    b.add_light(Light::Beam(BeamLight::new(
        LASER_SMOKE_BEAM_CENTER,
        Vec3::NEG_Y,
        LASER_SMOKE_BEAM_RADIUS,
        Spectrum::splat(LASER_SMOKE_IRRADIANCE),
    )));
    Ok(b)
}

/// Centre and radius (m) and index of refraction of the glass ball of `glass-smoke`.
pub const GLASS_SMOKE_SPHERE_CENTER: Vec3 = Vec3::new(0.0, 1.2, 0.0);
pub const GLASS_SMOKE_SPHERE_RADIUS: f32 = 0.5;
pub const GLASS_SMOKE_IOR: f32 = 1.5;
/// Height of the `glass-smoke` light above the floor (m), half its side (m) and its radiance
/// (W/m²/sr): a 0.2 m square facing down, 40 W/sr along the axis (126 W in all).
pub const GLASS_SMOKE_LIGHT_HEIGHT: f32 = 2.8;
pub const GLASS_SMOKE_LIGHT_HALF: f32 = 0.1;
pub const GLASS_SMOKE_LIGHT_RADIANCE: f32 = 1000.0;
/// Extinction (m⁻¹) and single-scattering albedo of the `glass-smoke` smoke.
pub const GLASS_SMOKE_SIGMA_T: f32 = 0.2;
pub const GLASS_SMOKE_ALBEDO: f32 = 0.9;

/// `glass-smoke` (S-M3, seed 000 fig. 8.7): a glass ball (IOR 1.5, radius 0.5 m, centre 1.2 m
/// above the floor) under a small one-sided area light (0.2 m square, 1000 W/m²/sr, 1.6 m above
/// the ball's centre, facing down), both in homogeneous smoke (σ_t = 0.2 m⁻¹, albedo 0.9,
/// isotropic; the ball's outside is the smoke, its inside vacuum) filling a null box [−4, 4] ×
/// [−0.001, 5] × [−4, 4] around an 8 × 8 m grey floor; the layout and camera of
/// [`volume_caustic`]. The ball focuses the light into a bright cone under it (a volume
/// caustic, L S+ M E) and a caustic on the floor (L S+ D E).
fn glass_smoke() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("glass-smoke");
    b.set_camera(camera(
        Vec3::new(0.0, 1.1, 4.5),
        Vec3::new(0.0, 0.8, 0.0),
        40.0,
        160,
        120,
    ));
    b.settings.filter = FilterKind::Gaussian {
        stddev: 0.5,
        radius: 2.0,
    };
    media_photon_settings(&mut b, GLASS_SMOKE_S, 10_000, 0);
    b.settings.spp = Some(8);
    // The floor caustic is focused to a few centimetres: the automatic choice (s = 2) leaves
    // its tiny footprints to chance at 16 spp (−17 % against the light tracer), s = 8 agrees.
    b.settings.smoothing = Some(8.0);
    let floor = b.add_material("floor", diffuse(0.5, 0.5, 0.5))?;
    let glass = b.add_material("glass", dielectric(GLASS_SMOKE_IOR))?;
    let black = b.add_material("light-black", diffuse(0.0, 0.0, 0.0))?;
    let (sigma_a, sigma_s) = Medium::coefficients_from_albedo(
        Spectrum::splat(GLASS_SMOKE_SIGMA_T),
        Spectrum::splat(GLASS_SMOKE_ALBEDO),
    );
    let smoke = b.add_medium(
        "smoke",
        Medium::homogeneous(sigma_a, sigma_s, PhaseFunction::default()),
    )?;
    add_floor(&mut b, 4.0, floor)?;
    b.add_shape_with_media(
        ShapeGeometry::Sphere(Sphere {
            center: GLASS_SMOKE_SPHERE_CENTER,
            radius: GLASS_SMOKE_SPHERE_RADIUS,
        }),
        glass,
        None,
        false,
        MediumInterface {
            inside: NONE,
            outside: smoke,
        },
    )?;
    b.add_shape(
        ShapeGeometry::Mesh(TriangleMesh::rectangle(&trs(
            Vec3::new(0.0, GLASS_SMOKE_LIGHT_HEIGHT, 0.0),
            Vec3::X,
            90.0,
            Vec3::splat(GLASS_SMOKE_LIGHT_HALF),
        ))),
        black,
        Some(Spectrum::splat(GLASS_SMOKE_LIGHT_RADIANCE)),
        false,
    )?;
    add_medium_box(
        &mut b,
        Vec3::new(-4.0, -0.001, -4.0),
        Vec3::new(4.0, 5.0, 4.0),
        smoke,
    )?;
    Ok(b)
}

#[cfg(test)]
mod tests {
    mod media_scenes;

    use super::*;
    use crate::parse_scene_file;
    use caustica_core::Ray;
    use caustica_scene::light::AreaShape;
    use caustica_scene::medium::MediumKind;
    use std::path::Path;

    #[test]
    fn names_include_the_default() {
        assert!(builtin_names().contains(&DEFAULT_SCENE));
        assert!(builtin_names().contains(&"cornell-box"));
        assert!(builtin_scene("no-such-scene").is_none());
    }

    fn mesh_positions(b: &SceneBuilder) -> Vec<Vec<Vec3>> {
        b.shapes()
            .iter()
            .map(|s| match &s.geometry {
                ShapeGeometry::Mesh(m) => m.positions.clone(),
                ShapeGeometry::Sphere(s) => vec![s.center, Vec3::splat(s.radius)],
                ShapeGeometry::Disk(d) => vec![d.center, d.normal, Vec3::splat(d.radius)],
            })
            .collect()
    }

    #[test]
    fn builtin_scenes_match_their_toml_files() {
        for name in builtin_names() {
            let a = builtin_scene(name).unwrap();
            let path = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../scenes")
                .join(format!("{name}.toml"));
            let b = parse_scene_file(&path).unwrap();
            assert_eq!(a.name, b.name);
            assert_eq!(a.shape_count(), b.shape_count(), "{name}");
            assert_eq!(a.material_names(), b.material_names(), "{name}");
            assert_eq!(a.lights().len(), b.lights().len(), "{name}");
            for (la, lb) in a.lights().iter().zip(b.lights()) {
                let (pa, pb) = (la.power(), lb.power());
                for i in 0..3 {
                    assert!(
                        (pa.c[i] - pb.c[i]).abs() <= 1e-5 * pa.c[i].abs().max(1e-3),
                        "{name}: {pa:?} vs {pb:?}"
                    );
                }
                assert_eq!(std::mem::discriminant(la), std::mem::discriminant(lb));
            }
            let (ca, cb) = (a.camera().unwrap(), b.camera().unwrap());
            assert_eq!(
                (ca.width, ca.height, ca.fov_axis),
                (cb.width, cb.height, cb.fov_axis)
            );
            assert!((ca.fov_deg - cb.fov_deg).abs() < 1e-6);
            assert!(Mat4Cmp(ca.to_world).close(cb.to_world));
            assert!((ca.focus_distance - cb.focus_distance).abs() < 1e-5);
            assert_eq!(a.settings.spp, b.settings.spp);
            assert_eq!(a.settings.max_depth, b.settings.max_depth);
            assert_eq!(a.settings.filter, b.settings.filter);
            assert_eq!(a.settings.integrator, b.settings.integrator, "{name}");
            assert_eq!(a.settings.smoothing, b.settings.smoothing, "{name}");
            assert_eq!(
                (a.settings.volume_smoothing, a.settings.volume_photons),
                (b.settings.volume_smoothing, b.settings.volume_photons),
                "{name}"
            );
            assert_eq!(a.settings.photons, b.settings.photons, "{name}");
            assert_same_media(name, &a, &b);
            for (sa, sb) in a.shapes().iter().zip(b.shapes()) {
                assert_eq!(sa.material, sb.material, "{name}");
                assert_eq!(
                    (sa.medium_inside, sa.medium_outside),
                    (sb.medium_inside, sb.medium_outside),
                    "{name}: shape media"
                );
                assert_eq!(
                    sa.light == caustica_scene::intersection::NONE,
                    sb.light == caustica_scene::intersection::NONE
                );
            }
            for (pa, pb) in mesh_positions(&a).iter().zip(mesh_positions(&b).iter()) {
                assert_eq!(pa.len(), pb.len());
                for (x, y) in pa.iter().zip(pb) {
                    assert!(x.abs_diff_eq(*y, 1e-5), "{name}: {x} vs {y}");
                }
            }
            assert_same_motion(name, &a, &b);
        }
    }

    /// Same shutter, frame rate and keyframes (positions and normals) of every moving mesh.
    fn assert_same_motion(name: &str, a: &SceneBuilder, b: &SceneBuilder) {
        assert_eq!(a.shutter(), b.shutter(), "{name}: shutter");
        assert_eq!(a.settings.fps, b.settings.fps, "{name}: fps");
        for (sa, sb) in a.shapes().iter().zip(b.shapes()) {
            let (ma, mb) = match (&sa.motion, &sb.motion) {
                (None, None) => continue,
                (Some(x), Some(y)) => (x, y),
                _ => panic!("{name}: a shape moves in one and not in the other"),
            };
            assert_eq!(ma.first_frame, mb.first_frame, "{name}");
            assert_eq!(ma.frame_count(), mb.frame_count(), "{name}");
            let close = |x: &[Vec<Vec3>], y: &[Vec<Vec3>], tol: f32| {
                x.iter()
                    .flatten()
                    .zip(y.iter().flatten())
                    .all(|(p, q)| p.abs_diff_eq(*q, tol))
            };
            assert!(
                close(&ma.positions, &mb.positions, 1e-5),
                "{name}: keyframes"
            );
            match (&ma.normals, &mb.normals) {
                (Some(x), Some(y)) => {
                    let unit = |v: &[Vec<Vec3>]| -> Vec<Vec<Vec3>> {
                        v.iter()
                            .map(|f| f.iter().map(|n| n.normalize()).collect())
                            .collect()
                    };
                    assert!(close(&unit(x), &unit(y), 1e-5), "{name}: keyframe normals");
                }
                (None, None) => {}
                _ => panic!("{name}: keyframe normals in one and not in the other"),
            }
        }
    }

    /// Same media (names, kinds, coefficients, phase functions, densities on a lattice of
    /// points spanning the scene) and materials.
    fn assert_same_media(name: &str, a: &SceneBuilder, b: &SceneBuilder) {
        for (ma, mb) in a.materials().iter().zip(b.materials()) {
            assert_eq!(format!("{ma:?}"), format!("{mb:?}"), "{name}: materials");
        }
        assert_eq!(a.media().len(), b.media().len(), "{name}: media");
        for (x, y) in a.media().iter().zip(b.media()) {
            assert_eq!(x.phase, y.phase, "{name}");
            assert_eq!(
                std::mem::discriminant(&x.kind),
                std::mem::discriminant(&y.kind),
                "{name}"
            );
            for (p, q) in [(x.sigma_a, y.sigma_a), (x.sigma_s, y.sigma_s)] {
                for i in 0..3 {
                    assert!(
                        (p.c[i] - q.c[i]).abs() <= 1e-6 * p.c[i].abs().max(1.0),
                        "{name}: {p:?} vs {q:?}"
                    );
                }
            }
            if let (MediumKind::Grid(g), MediumKind::Grid(h)) = (&x.kind, &y.kind) {
                assert_eq!(g.resolution(), h.resolution(), "{name}");
                for i in 0..=20 {
                    for j in 0..=20 {
                        for k in 0..=20 {
                            let p = Vec3::new(i as f32, j as f32, k as f32) / 10.0 - 1.0;
                            let (dg, dh) = (g.density(p), h.density(p));
                            assert!(
                                (dg - dh).abs() < 1e-5,
                                "{name}: density at {p}: {dg} vs {dh}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn media_scenes_put_camera_lights_and_shapes_in_the_right_media() {
        for name in ["fog-box", "fog-box-hg"] {
            let b = builtin_scene(name).unwrap();
            let boxes = builtin_scene("cornell-box").unwrap();
            // Exactly cornell-box plus the fog's box.
            assert_eq!(b.shape_count(), boxes.shape_count() + 1);
            for (s, r) in b.shapes().iter().zip(boxes.shapes()) {
                assert_eq!(format!("{:?}", s.geometry), format!("{:?}", r.geometry));
                assert_eq!(s.material, r.material);
                assert_eq!((s.medium_inside, s.medium_outside), (NONE, NONE));
            }
            let [fog] = b.media() else {
                panic!("{name}: one medium")
            };
            assert!(matches!(fog.kind, MediumKind::Homogeneous(_)));
            let st = fog.sigma_t();
            for (c, want) in [0.45f32, 0.55, 0.65].into_iter().enumerate() {
                assert!((st.c[c] - want).abs() < 1e-6);
                assert!((fog.sigma_a.c[c] - 0.05).abs() < 1e-6);
            }
            assert_eq!(fog.sigma_s, Spectrum::new(0.4, 0.5, 0.6));
            if name == "fog-box" {
                assert_eq!(fog.phase, PhaseFunction::default());
            } else {
                assert_eq!(fog.phase, PhaseFunction::henyey_greenstein(0.6).unwrap());
            }
            let cube = b.shapes().last().unwrap();
            assert_eq!((cube.medium_inside, cube.medium_outside), (0, NONE));
            assert!(b.materials()[cube.material as usize].is_null());
            let ShapeGeometry::Mesh(m) = &cube.geometry else {
                panic!()
            };
            let (lo, hi) = m
                .positions
                .iter()
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(a, b), p| {
                    (a.min(*p), b.max(*p))
                });
            assert!(lo.abs_diff_eq(Vec3::splat(-0.998), 1e-6), "{lo}");
            assert!(hi.abs_diff_eq(Vec3::new(0.998, 0.998, 1.0), 1e-6), "{hi}");
            assert_eq!(
                (
                    b.settings.integrator.as_deref(),
                    b.settings.spp,
                    b.settings.max_depth
                ),
                (Some("path"), Some(64), Some(64))
            );
            let scene = b.build().unwrap();
            assert!(
                scene.has_media && scene.warnings.is_empty(),
                "{:?}",
                scene.warnings
            );
            assert_eq!(
                scene.camera_medium, NONE,
                "{name}: the camera is outside the fog"
            );
            assert_eq!(
                scene.light_media,
                vec![0],
                "{name}: the area light is in the fog"
            );
            assert_eq!(scene.medium_at(Vec3::ZERO), 0);
            assert_eq!(scene.medium_at(Vec3::new(0.0, 0.0, 2.0)), NONE);
        }

        let b = builtin_scene("smoke-plume").unwrap();
        assert_eq!(b.shape_count(), 7);
        let [smoke] = b.media() else { panic!() };
        let MediumKind::Grid(g) = &smoke.kind else {
            panic!("smoke-plume: a grid")
        };
        assert_eq!(g.resolution(), [32, 32, 32]);
        assert_eq!(smoke.phase, PhaseFunction::default());
        for (c, a) in [0.9f32, 0.8, 0.7].into_iter().enumerate() {
            assert!((smoke.sigma_t().c[c] - 6.0).abs() < 1e-5);
            assert!((smoke.sigma_s.c[c] - 6.0 * a).abs() < 1e-5);
        }
        // The grid fills the box: density at a voxel centre is plume_density there.
        let [lo, hi] = SMOKE_PLUME_BOX;
        for (i, j, k) in [(16u32, 3u32, 15u32), (0, 0, 0), (20, 31, 9)] {
            let u = (Vec3::new(i as f32, j as f32, k as f32) + 0.5) / 32.0;
            let p = lo + (hi - lo) * u;
            assert!((g.density(p) - plume_density(u)).abs() < 1e-5, "{u}");
        }
        assert!(g.density(hi + 0.01) == 0.0 && g.max_density() > 0.5);
        let scene = b.build().unwrap();
        assert_eq!(
            (scene.camera_medium, scene.light_media.clone()),
            (NONE, vec![NONE])
        );
        assert_eq!(scene.medium_at(Vec3::new(0.0, -0.5, 0.0)), 0);
        assert_eq!(scene.medium_at(Vec3::new(0.0, 0.8, 0.0)), NONE);

        let b = builtin_scene("volume-caustic").unwrap();
        let [fog] = b.media() else { panic!() };
        assert_eq!(
            (fog.sigma_a, fog.sigma_s),
            (Spectrum::splat(0.01), Spectrum::splat(0.15))
        );
        let sphere = &b.shapes()[1];
        assert!(
            matches!(sphere.geometry, ShapeGeometry::Sphere(s) if s.radius == 0.5 && s.center == Vec3::new(0.0, 1.2, 0.0))
        );
        assert_eq!((sphere.medium_inside, sphere.medium_outside), (NONE, 0));
        let [Light::Spot(spot)] = b.lights() else {
            panic!("one spot light")
        };
        assert_eq!(spot.position, Vec3::new(0.0, 3.0, 0.0));
        assert!((spot.cutoff_angle.to_degrees() - 20.0).abs() < 1e-4);
        assert_eq!(spot.cutoff_angle, spot.beam_width);
        assert_eq!(b.settings.integrator.as_deref(), Some("lighttrace"));
        let scene = b.build().unwrap();
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        assert_eq!(scene.camera_medium, NONE, "the camera is outside the fog");
        assert_eq!(scene.light_media, vec![0], "the spot light is in the fog");
        assert_eq!(
            scene.medium_at(Vec3::new(0.0, 1.2, 0.0)),
            NONE,
            "vacuum in the ball"
        );
        assert_eq!(scene.medium_at(Vec3::new(0.0, 0.5, 0.0)), 0);
    }

    #[test]
    fn plume_density_follows_its_formula() {
        // On the axis at the bottom the Gaussian is 1: density = 1 − 0.3 sin(11u) sin(13w).
        let u = Vec3::new(0.5, 0.0, 0.5 + 0.08);
        let want = 1.0 - 0.3 * (11.0f32 * 0.5).sin() * (13.0f32 * 0.58).sin();
        assert!((plume_density(u) - want).abs() < 1e-6);
        // At the top it vanishes; off axis it falls off as a Gaussian of width rad.
        assert_eq!(plume_density(Vec3::new(0.5, 1.0, 0.5)), 0.0);
        let v = 0.5f32;
        let (cx, cz, rad) = (
            0.5 + 0.08 * (3.0f32).sin(),
            0.5 + 0.08 * 2.5f32.cos(),
            0.245,
        );
        let p = Vec3::new(cx + rad, v, cz);
        let want = (-0.5f32).exp() * 0.5 * (1.0 - 0.3 * (11.0 * p.x).sin() * (13.0 * p.z).sin());
        assert!((plume_density(p) - want).abs() < 1e-6);
        assert!(plume_density(Vec3::new(0.0, 0.0, 0.0)) >= 0.0);
    }

    /// The meshes of the case scenes as shipped in `scenes/meshes/`: file name, mesh, header
    /// comments.
    fn case_meshes() -> Vec<(String, TriangleMesh, [&'static str; 2])> {
        let (wave, motion) = moving_water_wave(&WATER_WAVE, MOVING_WAVE_STEP, MOVING_WAVE_FRAMES);
        let frames = (0..motion.frame_count()).map(move |k| {
            let mut m = wave.clone();
            m.positions.clone_from(&motion.positions[k]);
            m.normals = motion.normals.as_ref().map(|n| n[k].clone());
            (
                format!("moving-wave/frame-{k:04}.ply"),
                m,
                [
                    "caustica moving-wave: the water-wave surface with its phase moved 0.1 m per frame toward +x",
                    "generated by crates/loader/src/builtin.rs (moving_water_wave)",
                ],
            )
        });
        let mut v = vec![
            (
                "water-wave.ply".to_string(),
                water_wave_mesh(&WATER_WAVE),
                [
                    "caustica water-wave surface: y = 3 + 0.25 cos(pi x), |x|, |z| <= 1, 128 x 8 cells",
                    "vertex normals are the analytic (-dy/dx, 1, 0) normalised; generated by crates/loader/src/builtin.rs",
                ],
            ),
            (
                "ring.ply".to_string(),
                ring_mesh(&RING),
                [
                    "caustica ring: radii 1 and 1.1, height 0.5, 128 segments, closed, outward normals",
                    "generated by crates/loader/src/builtin.rs",
                ],
            ),
            (
                "prism.ply".to_string(),
                prism::prism_mesh(),
                [
                    "caustica prism: equilateral prism of side 0.1 m and height 0.08 m standing on y = 0, centroid at the origin, apex toward +z; flat faces, outward",
                    "generated by crates/loader/src/builtin/prism.rs",
                ],
            ),
            (
                "torus.ply".to_string(),
                pcf_scenes::torus_glass_torus(),
                [
                    "caustica torus-glass: torus of radii 0.25 and 0.08 m, 64 x 24 steps, turned 60 deg about x then 20 deg about z, centred at (0, -0.5, 0)",
                    "smooth vertex normals; generated by crates/scene/src/shape/torus.rs via crates/loader/src/builtin/pcf_scenes.rs",
                ],
            ),
            (
                "rod.ply".to_string(),
                rod(),
                [
                    "caustica rotating-rod: glass rod of radius 0.08 m and length 1.2 m along +x from the origin",
                    "Phong side normals, flat caps; generated by crates/loader/src/builtin.rs",
                ],
            ),
        ];
        v.extend(frames);
        v
    }

    fn meshes_dir() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/meshes")
    }

    /// Regenerates `scenes/meshes/{water-wave,ring,torus,rod}.ply` and `moving-wave/` after a change
    /// to [`WATER_WAVE`], [`RING`], the rod or the wave's motion:
    /// `cargo test -p caustica-loader write_case_meshes -- --ignored`.
    #[test]
    #[ignore]
    fn write_case_meshes() {
        for (file, mesh, comments) in case_meshes() {
            let text = crate::ply::to_ascii_ply(&mesh, &comments);
            let path = meshes_dir().join(file);
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(path, text).unwrap();
        }
    }

    #[test]
    fn case_mesh_files_are_up_to_date() {
        for (file, mesh, comments) in case_meshes() {
            let expected = crate::ply::to_ascii_ply(&mesh, &comments);
            let found = std::fs::read_to_string(meshes_dir().join(&file)).unwrap();
            assert!(
                found == expected,
                "scenes/meshes/{file} differs from the procedural mesh; regenerate it with \
                 `cargo test -p caustica-loader write_case_meshes -- --ignored`"
            );
            assert!(mesh.indices.len() <= 20_000);
        }
    }

    const CASE_SCENES: [&str; 3] = ["water-wave", "metal-ring", "gold-ring"];

    fn mitsuba_file(name: &str) -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenes/mitsuba")
            .join(format!("{name}.xml"))
    }

    fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
        a.abs_diff_eq(b, tol)
    }

    /// Everything a render depends on, shape by shape (meshes and spheres, and the media on
    /// their sides) and light by light (directional, area and beam lights), within `tol` (m).
    fn assert_same_scene(name: &str, a: &SceneBuilder, b: &SceneBuilder, tol: f32) {
        assert_eq!(a.name, b.name);
        assert_eq!(a.material_names(), b.material_names(), "{name}");
        for (ma, mb) in a.materials().iter().zip(b.materials()) {
            assert_eq!(
                format!("{ma:?}"),
                format!("{mb:?}"),
                "{name}: materials differ"
            );
        }
        assert_eq!(a.shape_count(), b.shape_count(), "{name}");
        for (i, (sa, sb)) in a.shapes().iter().zip(b.shapes()).enumerate() {
            assert_eq!(sa.material, sb.material, "{name}: shape {i}");
            assert_eq!(sa.light, sb.light, "{name}: shape {i}");
            assert_eq!(sa.flip_normals, sb.flip_normals, "{name}: shape {i}");
            assert_eq!(
                (sa.medium_inside, sa.medium_outside),
                (sb.medium_inside, sb.medium_outside),
                "{name}: shape {i}: media"
            );
            let (ma, mb) = match (&sa.geometry, &sb.geometry) {
                (ShapeGeometry::Mesh(ma), ShapeGeometry::Mesh(mb)) => (ma, mb),
                (ShapeGeometry::Sphere(x), ShapeGeometry::Sphere(y)) => {
                    assert!(close(x.center, y.center, tol), "{name}: shape {i}: centre");
                    assert!(
                        (x.radius - y.radius).abs() <= tol,
                        "{name}: shape {i}: radius"
                    );
                    continue;
                }
                _ => panic!("{name}: shape {i}: geometries differ in kind"),
            };
            assert_eq!(ma.indices, mb.indices, "{name}: shape {i}");
            assert_eq!(ma.positions.len(), mb.positions.len(), "{name}: shape {i}");
            for (p, q) in ma.positions.iter().zip(&mb.positions) {
                assert!(close(*p, *q, tol), "{name}: shape {i}: vertex {p} vs {q}");
            }
            assert_eq!(
                ma.normals.is_some(),
                mb.normals.is_some(),
                "{name}: shape {i}"
            );
            for (p, q) in ma.normals.iter().flatten().zip(mb.normals.iter().flatten()) {
                assert!(close(*p, *q, 1e-6), "{name}: shape {i}: normal {p} vs {q}");
            }
        }
        assert_eq!(a.lights().len(), b.lights().len(), "{name}");
        for (la, lb) in a.lights().iter().zip(b.lights()) {
            match (la, lb) {
                (Light::Directional(x), Light::Directional(y)) => {
                    assert!(
                        close(x.direction, y.direction, 1e-6),
                        "{name}: light direction"
                    );
                    assert_eq!(x.irradiance, y.irradiance, "{name}");
                }
                (Light::Beam(x), Light::Beam(y)) => {
                    assert!(close(x.center, y.center, tol), "{name}: beam centre");
                    assert!(close(x.direction(), y.direction(), 1e-6), "{name}: beam");
                    assert!((x.radius - y.radius).abs() <= 1e-7, "{name}: beam radius");
                    assert_eq!(x.irradiance, y.irradiance, "{name}");
                }
                (Light::Area(x), Light::Area(y)) => {
                    for c in 0..3 {
                        let (p, q) = (x.radiance.c[c], y.radiance.c[c]);
                        assert!((p - q).abs() <= 1e-6 * p.abs(), "{name}: radiance");
                    }
                    assert_eq!(x.two_sided, y.two_sided, "{name}");
                    let (AreaShape::Triangles(ta), AreaShape::Triangles(tb)) = (&x.shape, &y.shape)
                    else {
                        panic!("{name}: area lights are rectangles")
                    };
                    assert_eq!(ta.len(), tb.len());
                    for (p, q) in ta.iter().flatten().zip(tb.iter().flatten()) {
                        assert!(close(*p, *q, tol), "{name}: light vertex {p} vs {q}");
                    }
                }
                _ => panic!("{name}: lights differ: {la:?} vs {lb:?}"),
            }
        }
        let (ca, cb) = (a.camera().unwrap(), b.camera().unwrap());
        assert_eq!(
            (ca.width, ca.height, ca.fov_axis, ca.lens_radius),
            (cb.width, cb.height, cb.fov_axis, cb.lens_radius),
            "{name}"
        );
        assert!((ca.fov_deg - cb.fov_deg).abs() < 1e-6, "{name}");
        assert!(ca.to_world.abs_diff_eq(cb.to_world, 1e-6), "{name}: camera");
        assert_eq!(a.settings.spp, b.settings.spp, "{name}");
        assert_eq!(a.settings.max_depth, b.settings.max_depth, "{name}");
        assert_eq!(a.settings.filter, b.settings.filter, "{name}");
    }

    #[test]
    fn case_scenes_match_their_mitsuba_files() {
        for name in CASE_SCENES {
            let builtin = builtin_scene(name).unwrap();
            let xml = crate::load_mitsuba(&mitsuba_file(name), &[]).unwrap();
            assert!(
                xml.pending_warnings().is_empty(),
                "{name}.xml needs no approximation: {:?}",
                xml.pending_warnings()
            );
            assert_same_scene(name, &builtin, &xml, 1e-6);
            // The Mitsuba file names a Mitsuba integrator; the built-in the one that shows the
            // caustic.
            assert!(matches!(
                xml.settings.integrator.as_deref(),
                Some("ptracer" | "path")
            ));
            assert_eq!(
                builtin.settings.integrator.as_deref(),
                Some("pds"),
                "{name}"
            );
            // The TOML version too (its rotations give the light's corners to rounding).
            let toml = parse_scene_file(
                &Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("../../scenes")
                    .join(format!("{name}.toml")),
            )
            .unwrap();
            assert_same_scene(name, &builtin, &toml, 1e-5);
        }
    }

    fn mesh_of(b: &SceneBuilder, i: usize) -> &TriangleMesh {
        match &b.shapes()[i].geometry {
            ShapeGeometry::Mesh(m) => m,
            _ => panic!("shape {i} is not a mesh"),
        }
    }

    fn winding_normal(m: &TriangleMesh, t: usize) -> Vec3 {
        let [a, b, c] = m.triangle(t).unwrap();
        (b - a).cross(c - a).normalize()
    }

    #[test]
    fn case_scenes_build_with_the_documented_lights_and_materials() {
        for name in CASE_SCENES {
            let b = builtin_scene(name).unwrap();
            // Shape 0 is the floor: diffuse, at y = 0, facing up.
            let floor = mesh_of(&b, 0);
            assert!(floor.positions.iter().all(|p| p.y.abs() < 1e-6), "{name}");
            assert!(close(winding_normal(floor, 0), Vec3::Y, 1e-6), "{name}");
            assert!(matches!(
                b.materials()[b.shapes()[0].material as usize],
                Material::Diffuse { .. }
            ));
            let specular = &b.materials()[b.shapes()[1].material as usize];
            match name {
                "water-wave" => {
                    assert!(matches!(specular, Material::Dielectric { ior, .. } if *ior == 1.33));
                    let [Light::Directional(l)] = b.lights() else {
                        panic!("{name}: one directional light")
                    };
                    assert_eq!(l.direction, Vec3::NEG_Y);
                }
                "metal-ring" => {
                    assert!(
                        matches!(specular, Material::Mirror { reflectance } if *reflectance == Spectrum::ONE)
                    );
                    let [Light::Directional(l)] = b.lights() else {
                        panic!("{name}: one directional light")
                    };
                    let elevation = (-l.direction.y).asin().to_degrees();
                    assert!((elevation - 10.0).abs() < 1e-4 && l.direction.x > 0.0);
                }
                "gold-ring" => {
                    let (eta, k) = conductor_preset("Au").unwrap();
                    assert!(
                        matches!(specular, Material::Conductor { eta: e, k: kk, .. } if *e == eta && *kk == k)
                    );
                    let [Light::Area(l)] = b.lights() else {
                        panic!("{name}: one area light")
                    };
                    // The light faces the ring's centre from 13° above the horizon.
                    let m = mesh_of(&b, 2);
                    let c = m.positions.iter().sum::<Vec3>() / 4.0;
                    assert!((c.length() - 10.0).abs() < 1e-4);
                    assert!(((c.y / c.length()).asin().to_degrees() - 13.0).abs() < 1e-3);
                    for t in 0..2 {
                        assert!(winding_normal(m, t).dot(-c.normalize()) > 1.0 - 1e-6);
                    }
                    assert!((m.triangle_area(0) + m.triangle_area(1) - 0.36).abs() < 1e-5);
                    assert!(!l.two_sided);
                }
                _ => unreachable!(),
            }
            let scene = b.build().unwrap();
            assert!(scene.warnings.is_empty(), "{name}: {:?}", scene.warnings);
            assert!(scene.total_power().average() > 0.0);
            // The camera sees the floor through the centre of the image.
            let c = &scene.camera;
            let ray = Ray::new(
                c.to_world.transform_point3(Vec3::ZERO),
                c.to_world.transform_vector3(Vec3::Z).normalize(),
            );
            let hit = scene.intersect(&ray).unwrap();
            assert_eq!(
                hit.shape, 0,
                "{name}: the image centre does not show the floor"
            );
        }
    }

    /// Follows a ray through specular surfaces (reflection about the shading normal at opaque
    /// ones, refraction without Fresnel reflection at dielectrics) to its first floor hit.
    fn trace_to_floor(scene: &caustica_scene::Scene, mut ray: Ray) -> Option<(Vec3, u32)> {
        for bounces in 0..8 {
            let si = scene.intersect(&ray)?;
            if si.shape == 0 {
                return Some((si.p, bounces));
            }
            let d = ray.d.normalize();
            let n = si.ns;
            let out = match scene.materials[si.material as usize] {
                Material::Dielectric { ior, .. } => {
                    // Entering when the ray comes from the side ng faces.
                    let (eta, n) = if d.dot(si.ng) < 0.0 {
                        (1.0 / ior, n)
                    } else {
                        (ior, -n)
                    };
                    let cos_i = -d.dot(n);
                    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
                    if k < 0.0 {
                        return None;
                    }
                    d * eta + n * (eta * cos_i - k.sqrt())
                }
                _ => d - n * (2.0 * d.dot(n)),
            };
            ray = si.spawn_ray(out);
        }
        None
    }

    /// Landing point on y = 0 of a vertical ray refracted once at x by the analytic surface.
    fn analytic_landing(x: f64) -> f64 {
        let w = &WATER_WAVE;
        let [nx, ny, _] = w.normal(x);
        let eta = 1.0 / WATER_IOR as f64;
        let cos_i = ny; // d = (0, −1, 0)
        let k = (1.0 - eta * eta * (1.0 - cos_i * cos_i)).sqrt();
        let (tx, ty) = (nx * (eta * cos_i - k), -eta + ny * (eta * cos_i - k));
        x + w.height(x) * tx / -ty
    }

    #[test]
    fn water_wave_caustic_bands_are_where_geometric_optics_puts_them() {
        // The fold caustics are the extrema of the landing point X(x) (dX/dx = 0).
        let n = 200_000;
        let xs: Vec<f64> = (0..=n).map(|i| -1.0 + 2.0 * i as f64 / n as f64).collect();
        let landing: Vec<f64> = xs.iter().map(|&x| analytic_landing(x)).collect();
        let folds: Vec<f64> = (1..n)
            .filter(|&i| (landing[i] - landing[i - 1]) * (landing[i + 1] - landing[i]) <= 0.0)
            .map(|i| landing[i])
            .collect();
        assert_eq!(folds.len(), 2, "{folds:?}");
        let fold = folds[0].abs();
        assert!(
            (folds[0] + folds[1]).abs() < 1e-6 && (0.15..0.22).contains(&fold),
            "{folds:?}"
        );

        // Trace vertical rays through the built scene: the Phong-interpolated mesh normals refract
        // like the analytic surface, and the histogram of landing points peaks at the folds.
        let scene = builtin_scene("water-wave").unwrap().build().unwrap();
        let bins = 200; // 1 cm over [−1, 1]
        let mut hist = vec![0u32; bins];
        let rays = 40_000;
        for i in 0..rays {
            let x = -1.0 + 2.0 * (i as f64 + 0.5) / rays as f64;
            let ray = Ray::new(Vec3::new(x as f32, 10.0, 0.3), Vec3::NEG_Y);
            let (p, bounces) = trace_to_floor(&scene, ray).expect("every ray reaches the floor");
            assert_eq!(bounces, 1);
            let expected = analytic_landing(x);
            assert!(
                (p.x as f64 - expected).abs() < 2e-3,
                "ray at x = {x}: lands at {} instead of {expected}",
                p.x
            );
            if (-1.0..1.0).contains(&p.x) {
                hist[((p.x + 1.0) * 100.0) as usize] += 1;
            }
        }
        let peak = |range: std::ops::Range<usize>| {
            let i = range.clone().max_by_key(|&i| hist[i]).unwrap();
            -1.0 + (i as f64 + 0.5) / 100.0
        };
        let (left, right) = (peak(0..100), peak(100..200));
        assert!(
            (left + fold).abs() <= 0.01,
            "left band at {left}, fold at {}",
            -fold
        );
        assert!(
            (right - fold).abs() <= 0.01,
            "right band at {right}, fold at {fold}"
        );
        // Between the bands brighter than outside them, dimmer than the bands.
        let mean = |r: std::ops::Range<usize>| {
            r.clone().map(|i| hist[i] as f64).sum::<f64>() / r.len() as f64
        };
        let (inside, outside) = (mean(90..110), mean(20..60));
        assert!(inside > 2.0 * outside, "inside {inside}, outside {outside}");
        assert!((hist[((left + 1.0) * 100.0) as usize] as f64) > 1.5 * inside);
    }

    /// Floor hits of parallel rays along `dir` entering the ring's opening (uniform over the
    /// disk of radius 0.999 at the ring's top), and how many rays were shot.
    fn ring_floor_hits(scene: &caustica_scene::Scene, dir: Vec3) -> (Vec<Vec3>, usize) {
        let n = 300;
        let mut hits = Vec::new();
        let mut shot = 0;
        for i in 0..n {
            for j in 0..n {
                let p = Vec3::new(
                    -1.0 + 2.0 * (i as f32 + 0.5) / n as f32,
                    RING.height + 1e-3,
                    -1.0 + 2.0 * (j as f32 + 0.5) / n as f32,
                );
                if p.x * p.x + p.z * p.z > 0.999 * 0.999 {
                    continue;
                }
                shot += 1;
                // Start upstream so the ray also meets whatever lies before the opening.
                let ray = Ray::new(p - dir * 5.0, dir);
                if let Some((q, bounces)) = trace_to_floor(scene, ray)
                    && bounces > 0
                    && q.x * q.x + q.z * q.z < 1.0
                {
                    hits.push(q);
                }
            }
        }
        (hits, shot)
    }

    #[test]
    fn ring_floors_are_shadowed_and_the_cusp_is_cut_only_in_metal_ring() {
        for (name, elevation) in [
            ("metal-ring", METAL_RING_ELEVATION_DEG),
            ("gold-ring", GOLD_RING_ELEVATION_DEG),
        ] {
            let scene = builtin_scene(name).unwrap().build().unwrap();
            let dir = slanted_direction(elevation);
            // k = H cot(e) / 2R > 1: no floor point inside the ring sees the light directly.
            let k = RING.height / elevation.to_radians().tan() / (2.0 * RING.inner_radius);
            assert!(k > 1.0, "{name}: k = {k}");
            for i in 0..=20 {
                for j in 0..=20 {
                    let p = Vec3::new(-0.95 + 0.095 * i as f32, 0.0, -0.95 + 0.095 * j as f32);
                    if p.length() > 0.95 {
                        continue;
                    }
                    let ray = Ray::new(p + Vec3::Y * 1e-4, -dir);
                    assert!(scene.occluded(&ray), "{name}: floor at {p} is lit directly");
                }
            }
            // The nephroid's cusp lies R/2 in front of the far wall, at (0.5, 0, 0).
            let (hits, shot) = ring_floor_hits(&scene, dir);
            assert!(hits.len() > shot / 2, "{name}: {} of {shot}", hits.len());
            let near_cusp = hits
                .iter()
                .filter(|q| (**q - Vec3::new(0.5, 0.0, 0.0)).length() < 0.05)
                .count();
            // Density near the cusp relative to the mean density over the inner floor.
            let ratio = near_cusp as f32 / (0.05f32 * 0.05) / (hits.len() as f32 / 1.0);
            if name == "metal-ring" {
                // k > 5/4: the floor stops the envelopes before the cusp (seed 000 §6.3).
                assert!(
                    k > 1.25 && near_cusp == 0,
                    "{name}: {near_cusp} hits near the cusp"
                );
            } else {
                // k < 5/4: the whole cardioid with its cusp, the brightest spot.
                assert!(
                    k < 1.25 && ratio > 3.0,
                    "{name}: cusp density ratio {ratio}"
                );
            }
        }
    }

    struct Mat4Cmp(Affine3A);
    impl Mat4Cmp {
        fn close(&self, o: Affine3A) -> bool {
            self.0.abs_diff_eq(o, 1e-5)
        }
    }

    #[test]
    fn cornell_box_geometry() {
        let b = builtin_scene("cornell-box").unwrap();
        assert_eq!(b.shape_count(), 8);
        assert_eq!(b.lights().len(), 1);
        // Light: 0.46 × 0.38 rectangle at y = 0.99 facing down.
        let ShapeGeometry::Mesh(l) = &b.shapes()[0].geometry else {
            panic!()
        };
        let area = l.triangle_area(0) + l.triangle_area(1);
        assert!((area - 0.46 * 0.38).abs() < 1e-5);
        let [p0, p1, p2] = l.indices[0].map(|i| l.positions[i as usize]);
        assert!(
            (p1 - p0)
                .cross(p2 - p0)
                .normalize()
                .abs_diff_eq(-Vec3::Y, 1e-6)
        );
        assert!(l.positions.iter().all(|p| (p.y - 0.99).abs() < 1e-6));
        // Every wall faces the inside of the box and the red wall is on the left (x = −1).
        for s in &b.shapes()[1..6] {
            let ShapeGeometry::Mesh(m) = &s.geometry else {
                panic!()
            };
            let [p0, p1, p2] = m.indices[0].map(|i| m.positions[i as usize]);
            let n = (p1 - p0).cross(p2 - p0).normalize();
            assert!(n.dot(-p0) > 0.9, "wall at {p0} faces {n}");
        }
        let red = b.material_index("red").unwrap();
        let ShapeGeometry::Mesh(m) = &b.shapes()[5].geometry else {
            panic!()
        };
        assert_eq!(b.shapes()[5].material, red);
        assert!(m.positions.iter().all(|p| (p.x + 1.0).abs() < 1e-6));
        // Boxes stand on the floor (Mitsuba's large box is 1.22 high and sinks 1 cm into it).
        for (s, floor) in b.shapes()[6..].iter().zip([-1.0f32, -1.01]) {
            let ShapeGeometry::Mesh(m) = &s.geometry else {
                panic!()
            };
            let min_y = m
                .positions
                .iter()
                .map(|p| p.y)
                .fold(f32::INFINITY, f32::min);
            assert!(
                (min_y - floor).abs() < 1e-5,
                "box bottom at {min_y}, expected {floor}"
            );
        }
    }
}
