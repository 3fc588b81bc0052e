//! Three scenes of seed 002's sec. 4.2 (issue 22; `docs/scenes.md`): the cognac glass under a
//! disk light (fig. 10, `cognac-glass`), a swimming pool under the sun (fig. 11,
//! `swimming-pool`) and the embedded torus of progressive photon mapping (fig. 13,
//! `embedded-torus`). The seed gives none of their geometry; every number here is a choice,
//! recorded with its reason in `docs/scenes.md`.

use super::{camera, caustic_integrator, dielectric, diffuse, trs};
use caustica_core::{Affine3A, Spectrum, Vec2, Vec3};
use caustica_scene::SceneError;
use caustica_scene::light::{DirectionalLight, Light, PointLight};
use caustica_scene::material::Material;
use caustica_scene::scene::SceneBuilder;
use caustica_scene::shape::{
    Disk, ShapeGeometry, TriangleMesh, circle_arc, height_field_mesh, lathe_mesh, torus_mesh,
};
use caustica_scene::texture::Texture;
use std::f64::consts::PI;

/// Final-gather rays per camera sample of the three scenes' suggested `pds` (as `caustic-box`:
/// enough for their weak indirect light, a quarter of the camera pass of pm's default 16).
const SEED002_FINAL_GATHER: u32 = 4;

// ---------------------------------------------------------------------------------------------
// cognac-glass

/// Index of refraction of the glass (η_glass/η_air).
pub const COGNAC_GLASS_IOR: f32 = 1.5;
/// Index of refraction of the cognac (40 % ethanol in water: 1.356).
pub const COGNAC_IOR: f32 = 1.356;
/// Beer–Lambert absorption σa of the cognac (m⁻¹, RGB): a warm amber; through the 4 cm of the
/// filled bowl it keeps 73 % of red, 30 % of green and 3 % of blue.
pub const COGNAC_ABSORPTION: Spectrum = Spectrum::new(8.0, 30.0, 90.0);
/// Steps of the glass and the liquid around their axis.
pub const COGNAC_SEGMENTS: u32 = 96;
/// The snifter (m), standing on the table y = 0 with its axis the y axis. The foot: a disc of
/// radius 4 cm, 3 mm thick at the rim, rising to the stem (radius 7 mm at y = 9 mm).
pub const SNIFTER_FOOT: [[f64; 2]; 4] = [[0.0, 0.0], [0.04, 0.0], [0.04, 0.003], [0.007, 0.009]];
/// The stem's radius where it meets the bowl.
pub const SNIFTER_STEM_TOP_RADIUS: f64 = 0.005;
/// The bowl: the outside a sphere of radius 5.5 cm about (0, 11.5 cm, 0), the inside a
/// concentric sphere 2 mm smaller, both cut at 4.5 cm above the centre (the rim: outer radius
/// 3.16 cm, inner 2.80 cm, a flat lip).
pub const SNIFTER_BOWL_CENTER_Y: f64 = 0.115;
pub const SNIFTER_BOWL_OUTER: f64 = 0.055;
pub const SNIFTER_WALL: f64 = 0.002;
pub const SNIFTER_RIM_ABOVE_CENTER: f64 = 0.045;
/// The cognac's level: 1.5 cm below the bowl's widest point (y = 10 cm; 3.8 cm deep, a
/// surface of radius 5.08 cm, about 183 ml).
pub const COGNAC_LEVEL_BELOW_CENTER: f64 = 0.015;
/// Profile steps per radian of the bowl's arcs (about 2.3° a step).
pub const SNIFTER_STEPS_PER_RADIAN: f64 = 25.0;
/// The table: a 1 × 1 m diffuse square at y = 0, albedo 0.75.
pub const COGNAC_TABLE_HALF: f32 = 0.5;
pub const COGNAC_TABLE_ALBEDO: f32 = 0.75;
/// The disk light (seed 002: "a diffuse disk source"): radius 2.5 cm, 0.38 m from the centre
/// of the cognac's surface (0, 0.1, 0), behind the glass to the left at 43° elevation, facing
/// that centre (3.8° across seen from the glass).
pub const COGNAC_LIGHT_CENTER: Vec3 = Vec3::new(-0.22, 0.36, -0.17);
pub const COGNAC_LIGHT_NORMAL: Vec3 = Vec3::new(0.22, -0.26, 0.17);
pub const COGNAC_LIGHT_RADIUS: f32 = 0.025;
pub const COGNAC_LIGHT_RADIANCE: f32 = 200.0;

/// The smooth dielectric of [`dielectric`] with Beer–Lambert absorption `sigma` (m⁻¹) inside.
fn absorbing_dielectric(ior: f32, sigma: Spectrum) -> Material {
    let mut m = dielectric(ior);
    if let Material::Dielectric { absorption, .. } = &mut m {
        *absorption = sigma;
    }
    m
}

fn bowl_angle(radius: f64, height_above_center: f64) -> f64 {
    (-height_above_center / radius).acos()
}

/// The point of the inner bowl at the cognac's level: where the glass's inner wall, the
/// liquid–glass interface and the liquid's surface meet (one value, so their rings coincide).
pub fn cognac_level_angle() -> f64 {
    bowl_angle(
        SNIFTER_BOWL_OUTER - SNIFTER_WALL,
        -COGNAC_LEVEL_BELOW_CENTER,
    )
}

fn arc_steps(from: f64, to: f64) -> u32 {
    ((to - from).abs() * SNIFTER_STEPS_PER_RADIAN).ceil() as u32
}

/// The profiles (r, y) of the glass, the liquid–glass interface and the liquid's surface, for
/// [`lathe_mesh`] (front = right of travel). The glass: foot, stem and outer bowl upward, the
/// lip inward, the inner bowl down to the cognac's level (fronts facing out of the glass). The
/// interface: the inner bowl below the level, from the bottom up (fronts facing into the glass,
/// out of the cognac). The surface: the level disc from the wall to the axis (front up).
pub fn snifter_profiles() -> [Vec<Vec<[f64; 2]>>; 3] {
    let (yc, ro, ri) = (
        SNIFTER_BOWL_CENTER_Y,
        SNIFTER_BOWL_OUTER,
        SNIFTER_BOWL_OUTER - SNIFTER_WALL,
    );
    let join = (SNIFTER_STEM_TOP_RADIUS / ro).asin();
    let (rim_o, rim_i) = (
        bowl_angle(ro, SNIFTER_RIM_ABOVE_CENTER),
        bowl_angle(ri, SNIFTER_RIM_ABOVE_CENTER),
    );
    let level = cognac_level_angle();
    let outer = circle_arc(yc, ro, join, rim_o, arc_steps(join, rim_o));
    let inner_above = circle_arc(yc, ri, rim_i, level, arc_steps(rim_i, level));
    let interface = circle_arc(yc, ri, 0.0, level, arc_steps(0.0, level));
    let f = SNIFTER_FOOT;
    let glass = vec![
        vec![f[0], f[1]],
        vec![f[1], f[2]],
        vec![f[2], f[3]],
        vec![f[3], outer[0]],
        outer.clone(),
        vec![outer[outer.len() - 1], inner_above[0]],
        inner_above,
    ];
    let top = interface[interface.len() - 1];
    [glass, vec![interface], vec![vec![top, [0.0, top[1]]]]]
}

/// The glass, the cognac's interface with it and the cognac's surface as meshes.
pub fn snifter_meshes() -> [TriangleMesh; 3] {
    snifter_profiles().map(|p| lathe_mesh(&p, COGNAC_SEGMENTS, &Affine3A::IDENTITY))
}

/// `cognac-glass` (seed 002 fig. 10, after Jensen 2001): a snifter of clear glass (IOR 1.5) a
/// third filled with amber cognac (IOR 1.356, Beer–Lambert absorption) on a diffuse table, lit
/// by a small disk light behind it to the left, so that the bowl and the liquid focus the light
/// into a caustic on the table in the glass's shadow, in front of it to the right. The liquid is
/// bounded by two dielectric interfaces whose inside (−normal side) is the cognac: its surface
/// (ior η_cognac/η_air) and its interface with the glass (ior η_cognac/η_glass = 0.904, the
/// normal pointing into the glass), both carrying its absorption, which caustica applies to a
/// segment that ends on a surface's inside; the glass bounding the cognac is that interface,
/// seen from the glass's side.
pub(super) fn cognac_glass() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("cognac-glass");
    b.set_camera(camera(
        Vec3::new(0.32, 0.26, 0.42),
        Vec3::new(0.06, 0.06, 0.06),
        40.0,
        320,
        240,
    ));
    b.settings.spp = Some(8);
    b.settings.max_depth = Some(16);
    caustic_integrator(&mut b);
    b.settings.final_gather = Some(SEED002_FINAL_GATHER);
    let table = b.add_material(
        "table",
        diffuse(
            COGNAC_TABLE_ALBEDO,
            COGNAC_TABLE_ALBEDO,
            COGNAC_TABLE_ALBEDO,
        ),
    )?;
    let glass = b.add_material("glass", dielectric(COGNAC_GLASS_IOR))?;
    let in_glass = b.add_material(
        "cognac-in-glass",
        absorbing_dielectric(COGNAC_IOR / COGNAC_GLASS_IOR, COGNAC_ABSORPTION),
    )?;
    let cognac = b.add_material(
        "cognac",
        absorbing_dielectric(COGNAC_IOR, COGNAC_ABSORPTION),
    )?;
    let black = b.add_material("light-black", diffuse(0.0, 0.0, 0.0))?;
    b.add_shape(
        ShapeGeometry::Mesh(TriangleMesh::rectangle(&trs(
            Vec3::ZERO,
            Vec3::X,
            -90.0,
            Vec3::splat(COGNAC_TABLE_HALF),
        ))),
        table,
        None,
        false,
    )?;
    let [g, i, s] = snifter_meshes();
    for (mesh, m) in [(g, glass), (i, in_glass), (s, cognac)] {
        b.add_shape(ShapeGeometry::Mesh(mesh), m, None, false)?;
    }
    b.add_shape(
        ShapeGeometry::Disk(Disk {
            center: COGNAC_LIGHT_CENTER,
            normal: COGNAC_LIGHT_NORMAL.normalize(),
            radius: COGNAC_LIGHT_RADIUS,
        }),
        black,
        Some(Spectrum::splat(COGNAC_LIGHT_RADIANCE)),
        false,
    )?;
    Ok(b)
}

// ---------------------------------------------------------------------------------------------
// swimming-pool

/// The pool's inside (m): x ∈ [−2, 2], z ∈ [−1.25, 1.25], floor at y = −1.2, its walls up to
/// the deck at y = 0, which reaches 0.5 m beyond them.
pub const POOL_HALF: (f32, f32) = (2.0, 1.25);
pub const POOL_DEPTH: f32 = 1.2;
pub const POOL_DECK: f32 = 0.5;
/// Tiles: a checkerboard of 25 cm squares in two blues over floor, walls and deck (uv in metres).
pub const POOL_TILES_PER_METRE: f32 = 4.0;
pub const POOL_TILE_LIGHT: Spectrum = Spectrum::new(0.55, 0.75, 0.8);
pub const POOL_TILE_DARK: Spectrum = Spectrum::new(0.3, 0.5, 0.65);
/// Mean height of the water surface: 12 cm below the deck (1.08 m deep).
pub const POOL_WATER_LEVEL: f64 = -0.12;
/// Index of refraction of the water (one interface: air above, water below).
pub const POOL_WATER_IOR: f32 = 1.33;
/// Grid cells of the water surface (4 cm squares).
pub const POOL_WATER_CELLS: (u32, u32) = (100, 62);

/// One travelling sine of the water surface: amplitude (m), wavelength (m), direction of travel
/// in the (x, z) plane (unit) and phase (radians).
#[derive(Clone, Copy, Debug)]
pub struct SineWave {
    pub amplitude: f64,
    pub wavelength: f64,
    pub direction: [f64; 2],
    pub phase: f64,
}

/// The water surface of `swimming-pool`: four sines from 1.1 m to 33 cm long, 2 cm to 5 mm
/// high, in four directions; each alone has a peak curvature a (2π/λ)² of 0.65–1.8 m⁻¹, and
/// where they add up the crests focus the sun at about the floor's depth (a water lens of
/// curvature κ focuses at n/((n − 1) κ) ≈ 4/κ).
pub const POOL_WAVES: [SineWave; 4] = [
    SineWave {
        amplitude: 0.02,
        wavelength: 1.1,
        direction: [0.94, 0.341],
        phase: 0.0,
    },
    SineWave {
        amplitude: 0.012,
        wavelength: 0.7,
        direction: [-0.5, 0.866],
        phase: 1.3,
    },
    SineWave {
        amplitude: 0.008,
        wavelength: 0.45,
        direction: [0.2, -0.98],
        phase: 2.1,
    },
    SineWave {
        amplitude: 0.005,
        wavelength: 0.33,
        direction: [-0.8, -0.6],
        phase: 4.0,
    },
];

/// Height of the water surface at (x, z) and its gradient (∂h/∂x, ∂h/∂z).
pub fn pool_water_height(x: f64, z: f64) -> (f64, [f64; 2]) {
    let mut h = POOL_WATER_LEVEL;
    let mut g = [0.0, 0.0];
    for w in &POOL_WAVES {
        let k = 2.0 * PI / w.wavelength;
        let [dx, dz] = w.direction;
        let arg = k * (dx * x + dz * z) + w.phase;
        h += w.amplitude * arg.sin();
        let c = w.amplitude * k * arg.cos();
        g[0] += c * dx;
        g[1] += c * dz;
    }
    (h, g)
}

/// The water surface: the height field over the pool's inside, its edges on the walls.
pub fn pool_water_mesh() -> TriangleMesh {
    let (hx, hz) = (POOL_HALF.0 as f64, POOL_HALF.1 as f64);
    height_field_mesh((-hx, hx), (-hz, hz), POOL_WATER_CELLS, pool_water_height)
}

/// The basin: floor, the four walls facing in and the deck around them, as quads with uv in
/// metres along each face (so the checkerboard's squares are square everywhere).
pub fn pool_basin_mesh() -> TriangleMesh {
    let (x, z, d, e) = (POOL_HALF.0, POOL_HALF.1, -POOL_DEPTH, POOL_DECK);
    let v = Vec3::new;
    // Each quad: corners counter-clockwise seen from its front, with their uv.
    let quads: [[(Vec3, Vec2); 4]; 9] = [
        // Floor, facing up.
        quad_uv([v(-x, d, z), v(x, d, z), v(x, d, -z), v(-x, d, -z)], |p| {
            Vec2::new(p.x, -p.z)
        }),
        // Walls: back (z = −z, facing +z), front, left (x = −x, facing +x), right.
        quad_uv(
            [v(-x, d, -z), v(x, d, -z), v(x, 0.0, -z), v(-x, 0.0, -z)],
            |p| Vec2::new(p.x, p.y),
        ),
        quad_uv(
            [v(x, d, z), v(-x, d, z), v(-x, 0.0, z), v(x, 0.0, z)],
            |p| Vec2::new(-p.x, p.y),
        ),
        quad_uv(
            [v(-x, d, z), v(-x, d, -z), v(-x, 0.0, -z), v(-x, 0.0, z)],
            |p| Vec2::new(-p.z, p.y),
        ),
        quad_uv(
            [v(x, d, -z), v(x, d, z), v(x, 0.0, z), v(x, 0.0, -z)],
            |p| Vec2::new(p.z, p.y),
        ),
        // Deck, facing up: the strips behind and in front (full width), left and right.
        quad_uv(
            [
                v(-x - e, 0.0, -z),
                v(x + e, 0.0, -z),
                v(x + e, 0.0, -z - e),
                v(-x - e, 0.0, -z - e),
            ],
            |p| Vec2::new(p.x, -p.z),
        ),
        quad_uv(
            [
                v(-x - e, 0.0, z + e),
                v(x + e, 0.0, z + e),
                v(x + e, 0.0, z),
                v(-x - e, 0.0, z),
            ],
            |p| Vec2::new(p.x, -p.z),
        ),
        quad_uv(
            [
                v(-x - e, 0.0, z),
                v(-x, 0.0, z),
                v(-x, 0.0, -z),
                v(-x - e, 0.0, -z),
            ],
            |p| Vec2::new(p.x, -p.z),
        ),
        quad_uv(
            [
                v(x, 0.0, z),
                v(x + e, 0.0, z),
                v(x + e, 0.0, -z),
                v(x, 0.0, -z),
            ],
            |p| Vec2::new(p.x, -p.z),
        ),
    ];
    let mut m = TriangleMesh::default();
    let mut uvs = Vec::new();
    for q in quads {
        let base = m.positions.len() as u32;
        for (p, uv) in q {
            m.positions.push(p);
            uvs.push(uv);
        }
        m.indices.push([base, base + 1, base + 2]);
        m.indices.push([base, base + 2, base + 3]);
    }
    m.uvs = Some(uvs);
    m
}

fn quad_uv(p: [Vec3; 4], uv: impl Fn(Vec3) -> Vec2) -> [(Vec3, Vec2); 4] {
    p.map(|p| (p, uv(p)))
}

/// The sun: irradiance 2 W/m² (on a plane facing it), 55° above the horizon, shining toward
/// +x and −z (from the camera's front left), so that the wall on the left and the one in front
/// shade strips of the floor.
pub const POOL_SUN_DIRECTION: Vec3 = Vec3::new(0.5, -0.819152, -0.28);
pub const POOL_SUN_IRRADIANCE: f32 = 2.0;

/// `swimming-pool` (seed 002 fig. 11): a tiled pool filled with water whose surface is a sum of
/// four sines (one open dielectric interface, normals toward the air), under a directional sun,
/// seen from above the water: the floor and walls are lit and seen only through the surface
/// (L S D S E), so the caustic net on the floor is beyond the path tracer (a delta light behind
/// glass) and the light tracer (a camera behind glass).
pub(super) fn swimming_pool() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("swimming-pool");
    b.set_camera(camera(
        Vec3::new(0.0, 3.6, 2.5),
        Vec3::new(0.0, -1.2, -0.25),
        52.0,
        320,
        240,
    ));
    b.settings.spp = Some(8);
    b.settings.max_depth = Some(16);
    caustic_integrator(&mut b);
    b.settings.final_gather = Some(SEED002_FINAL_GATHER);
    let tiles = b.add_material(
        "tiles",
        Material::Diffuse {
            reflectance: Texture::Checkerboard {
                a: POOL_TILE_LIGHT,
                b: POOL_TILE_DARK,
                scale: POOL_TILES_PER_METRE,
            },
        },
    )?;
    let water = b.add_material("water", dielectric(POOL_WATER_IOR))?;
    b.add_shape(ShapeGeometry::Mesh(pool_basin_mesh()), tiles, None, false)?;
    b.add_shape(ShapeGeometry::Mesh(pool_water_mesh()), water, None, false)?;
    b.add_light(Light::Directional(DirectionalLight::new(
        POOL_SUN_DIRECTION,
        Spectrum::splat(POOL_SUN_IRRADIANCE),
    )));
    Ok(b)
}

// ---------------------------------------------------------------------------------------------
// embedded-torus

/// The glass block (IOR 1.5): a 0.6 m cube standing on the floor, turned 25° about y.
pub const EMBEDDED_CUBE_HALF: f32 = 0.3;
pub const EMBEDDED_CUBE_TURN_DEG: f32 = 25.0;
pub const EMBEDDED_GLASS_IOR: f32 = 1.5;
/// The torus inside it, at the cube's centre: radii 0.17 and 0.06 m, its axis turned 50° about
/// x then 30° about y; 64 × 24 steps (3072 triangles), diffuse white (0.8). Its outermost points
/// are 0.23 m from the centre, at least 7 cm inside every face.
pub const EMBEDDED_TORUS_MAJOR: f32 = 0.17;
pub const EMBEDDED_TORUS_MINOR: f32 = 0.06;
/// The point light: above the block, behind it to the left (W/sr).
pub const EMBEDDED_LIGHT_POSITION: Vec3 = Vec3::new(-0.7, 1.6, -0.5);
pub const EMBEDDED_LIGHT_INTENSITY: f32 = 10.0;
/// Seed 002 fig. 13's smoothing and caustic photons: s = 40, n = 5.55 · 10⁵.
pub const EMBEDDED_SMOOTHING: f32 = 40.0;
pub const EMBEDDED_PHOTONS: u32 = 555_000;

/// The torus of `embedded-torus` in place.
pub fn embedded_torus_mesh() -> TriangleMesh {
    let t = Affine3A::from_translation(Vec3::new(0.0, EMBEDDED_CUBE_HALF, 0.0))
        * Affine3A::from_axis_angle(Vec3::Y, 30f32.to_radians())
        * Affine3A::from_axis_angle(Vec3::X, 50f32.to_radians());
    torus_mesh(EMBEDDED_TORUS_MAJOR, EMBEDDED_TORUS_MINOR, 64, 24, &t)
}

/// `embedded-torus` (seed 002 fig. 13; Hachisuka et al. 2008's test scene, seed 001's "torus
/// scene" with its "glass enclosure"): a diffuse torus embedded in a solid glass cube on a
/// diffuse floor, lit by a point light above and behind. The torus is lit and seen only through
/// the glass (L S D S E); the block throws its refracted light and the torus's shadow onto the
/// floor beside it, with bright bands where light entering the top leaves by the sides. Suggests
/// `pds` with the seed's s = 40 and n = 5.55 · 10⁵.
pub(super) fn embedded_torus() -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("embedded-torus");
    b.set_camera(camera(
        Vec3::new(0.9, 1.2, 1.9),
        Vec3::new(0.15, 0.2, 0.1),
        45.0,
        320,
        240,
    ));
    b.settings.spp = Some(8);
    b.settings.max_depth = Some(16);
    caustic_integrator(&mut b);
    b.settings.smoothing = Some(EMBEDDED_SMOOTHING);
    b.settings.photons = Some(EMBEDDED_PHOTONS);
    b.settings.final_gather = Some(SEED002_FINAL_GATHER);
    let floor = b.add_material("floor", diffuse(0.7, 0.7, 0.7))?;
    let glass = b.add_material("glass", dielectric(EMBEDDED_GLASS_IOR))?;
    let torus = b.add_material("torus", diffuse(0.8, 0.8, 0.8))?;
    b.add_shape(
        ShapeGeometry::Mesh(TriangleMesh::rectangle(&trs(
            Vec3::ZERO,
            Vec3::X,
            -90.0,
            Vec3::splat(1.5),
        ))),
        floor,
        None,
        false,
    )?;
    b.add_shape(
        ShapeGeometry::Mesh(TriangleMesh::cube(&trs(
            Vec3::new(0.0, EMBEDDED_CUBE_HALF, 0.0),
            Vec3::Y,
            EMBEDDED_CUBE_TURN_DEG,
            Vec3::splat(EMBEDDED_CUBE_HALF),
        ))),
        glass,
        None,
        false,
    )?;
    b.add_shape(
        ShapeGeometry::Mesh(embedded_torus_mesh()),
        torus,
        None,
        false,
    )?;
    b.add_light(Light::Point(PointLight::new(
        EMBEDDED_LIGHT_POSITION,
        Spectrum::splat(EMBEDDED_LIGHT_INTENSITY),
    )));
    Ok(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::builtin_scene;
    use std::collections::HashMap;
    use std::path::{Path, PathBuf};

    /// The meshes of the three scenes as shipped in `scenes/meshes/`: file name, mesh, header
    /// comments.
    fn seed002_meshes() -> Vec<(&'static str, TriangleMesh, [&'static str; 2])> {
        let [glass, interface, surface] = snifter_meshes();
        let src = "generated by crates/loader/src/builtin/seed002_scenes.rs";
        vec![
            (
                "cognac-glass.ply",
                glass,
                [
                    "caustica cognac-glass: the snifter (foot, stem, bowl of radii 0.055/0.053 about y = 0.115, lip, inner wall down to the cognac at y = 0.1), 96 steps; normals out of the glass",
                    src,
                ],
            ),
            (
                "cognac-interface.ply",
                interface,
                [
                    "caustica cognac-glass: the cognac-glass interface (inner bowl below y = 0.1); normals into the glass, out of the cognac",
                    src,
                ],
            ),
            (
                "cognac-surface.ply",
                surface,
                [
                    "caustica cognac-glass: the cognac's surface, a disc at y = 0.1 of the inner bowl's radius there; normal up",
                    src,
                ],
            ),
            (
                "pool-water.ply",
                pool_water_mesh(),
                [
                    "caustica swimming-pool: water surface y = -0.12 + four sines over |x| <= 2, |z| <= 1.25, 100 x 62 cells, analytic normals (up)",
                    src,
                ],
            ),
            (
                "embedded-torus.ply",
                embedded_torus_mesh(),
                [
                    "caustica embedded-torus: torus of radii 0.17 and 0.06 m, 64 x 24 steps, turned 50 deg about x then 30 deg about y, centred at (0, 0.3, 0)",
                    "smooth vertex normals; generated by crates/scene/src/shape/torus.rs via crates/loader/src/builtin/seed002_scenes.rs",
                ],
            ),
        ]
    }

    fn meshes_dir() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/meshes")
    }

    /// Regenerates `scenes/meshes/{cognac-*,pool-water,embedded-torus}.ply` after a change to
    /// the scenes' constants: `cargo test -p caustica-loader write_seed002_meshes -- --ignored`.
    #[test]
    #[ignore]
    fn write_seed002_meshes() {
        for (file, mesh, comments) in seed002_meshes() {
            let text = crate::ply::to_ascii_ply(&mesh, &comments);
            std::fs::write(meshes_dir().join(file), text).unwrap();
        }
    }

    #[test]
    fn seed002_mesh_files_are_up_to_date() {
        for (file, mesh, comments) in seed002_meshes() {
            let expected = crate::ply::to_ascii_ply(&mesh, &comments);
            let found = std::fs::read_to_string(meshes_dir().join(file)).unwrap();
            assert!(
                found == expected,
                "scenes/meshes/{file} differs from the procedural mesh; regenerate it with \
                 `cargo test -p caustica-loader write_seed002_meshes -- --ignored`"
            );
            assert!(mesh.indices.len() <= 20_000, "{file}");
        }
    }

    /// Directed edges (by vertex position, bit for bit) of `meshes`, each reversed if its flag
    /// says so, with how often each occurs.
    fn edges(meshes: &[(&TriangleMesh, bool)]) -> HashMap<([u32; 3], [u32; 3]), u32> {
        let key = |v: Vec3| v.to_array().map(f32::to_bits);
        let mut e = HashMap::new();
        for (m, flip) in meshes {
            for t in &m.indices {
                for k in 0..3 {
                    let (a, b) = (
                        m.positions[t[k] as usize],
                        m.positions[t[(k + 1) % 3] as usize],
                    );
                    let (a, b) = if *flip { (b, a) } else { (a, b) };
                    *e.entry((key(a), key(b))).or_insert(0) += 1;
                }
            }
        }
        e
    }

    /// Every directed edge once and its reverse once: a closed, consistently wound surface.
    fn assert_closed(what: &str, meshes: &[(&TriangleMesh, bool)]) {
        let e = edges(meshes);
        for (&(a, b), &n) in &e {
            assert_eq!(n, 1, "{what}: edge repeated");
            assert_eq!(e.get(&(b, a)), Some(&1), "{what}: open edge");
        }
    }

    /// Signed volume enclosed by `meshes` (positive for outward winding).
    fn volume(meshes: &[(&TriangleMesh, bool)]) -> f64 {
        let mut v = 0.0;
        for (m, flip) in meshes {
            let s = if *flip { -1.0 } else { 1.0 };
            for t in &m.indices {
                let [a, b, c] = t.map(|k| m.positions[k as usize].as_dvec3());
                v += s * a.dot(b.cross(c)) / 6.0;
            }
        }
        v
    }

    #[test]
    fn the_glass_and_the_cognac_are_closed_solids_sharing_the_interface() {
        let [glass, interface, surface] = snifter_meshes();
        // The glass: its mesh plus the interface seen from the glass (reversed); the cognac:
        // the interface and its surface, both facing out of it.
        assert_closed("glass", &[(&glass, false), (&interface, true)]);
        assert_closed("cognac", &[(&interface, false), (&surface, false)]);
        // The cognac fills the spherical cap of the inner bowl below its level:
        // π h² (3 r − h) / 3 with h = r − 0.015.
        let r = SNIFTER_BOWL_OUTER - SNIFTER_WALL;
        let h = r - COGNAC_LEVEL_BELOW_CENTER;
        let cap = PI * h * h * (3.0 * r - h) / 3.0;
        let v = volume(&[(&interface, false), (&surface, false)]);
        assert!((v - cap).abs() < 5e-3 * cap, "{v} vs {cap} m³");
        assert!((1.8e-4..1.85e-4).contains(&v), "about 183 ml: {v}");
        let vg = volume(&[(&glass, false), (&interface, true)]);
        assert!(vg > 0.0 && vg < v, "glass {vg} m³");
        // The surface is at y = 0.1 and the whole glass stands on the table.
        assert!(surface.positions.iter().all(|p| (p.y - 0.1).abs() < 1e-6));
        let low = glass
            .positions
            .iter()
            .map(|p| p.y)
            .fold(f32::INFINITY, f32::min);
        assert_eq!(low, 0.0);
    }

    #[test]
    fn the_cognac_boundaries_carry_its_absorption_on_their_inside() {
        let b = builtin_scene("cognac-glass").unwrap();
        let scene = b.build().unwrap();
        let m = |name: &str| {
            let i = scene.material_names.iter().position(|n| n == name).unwrap();
            &scene.materials[i]
        };
        let ior = |m: &Material| match m {
            Material::Dielectric { ior, .. } => *ior,
            _ => panic!("not a dielectric"),
        };
        assert_eq!(ior(m("glass")), 1.5);
        assert_eq!(ior(m("cognac")), 1.356);
        assert!((ior(m("cognac-in-glass")) - 1.356 / 1.5).abs() < 1e-7);
        assert_eq!(m("glass").interior_absorption(), None);
        for n in ["cognac", "cognac-in-glass"] {
            assert_eq!(m(n).interior_absorption(), Some(COGNAC_ABSORPTION), "{n}");
        }
    }

    #[test]
    fn the_pool_water_spans_the_basin_between_floor_and_deck() {
        let w = pool_water_mesh();
        let (hx, hz) = POOL_HALF;
        let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
        for p in &w.positions {
            assert!(p.x.abs() <= hx && p.z.abs() <= hz);
            (lo, hi) = (lo.min(p.y), hi.max(p.y));
        }
        let amp: f64 = POOL_WAVES.iter().map(|w| w.amplitude).sum();
        assert!(hi < 0.0 && lo > -POOL_DEPTH, "{lo} {hi}");
        assert!((hi as f64 - POOL_WATER_LEVEL) <= amp + 1e-6);
        // Its edges lie on the walls: the corners exactly.
        for c in [(-hx, -hz), (hx, -hz), (-hx, hz), (hx, hz)] {
            assert!(w.positions.iter().any(|p| p.x == c.0 && p.z == c.1));
        }
        // The gradient is the derivative of the height.
        let (x, z, e) = (0.3, -0.7, 1e-6);
        let (_, [gx, gz]) = pool_water_height(x, z);
        let dx = (pool_water_height(x + e, z).0 - pool_water_height(x - e, z).0) / (2.0 * e);
        let dz = (pool_water_height(x, z + e).0 - pool_water_height(x, z - e).0) / (2.0 * e);
        assert!((gx - dx).abs() < 1e-6 && (gz - dz).abs() < 1e-6);
        // The basin faces into the pool or up: floor and walls toward the pool's centre, the
        // deck up; uv in metres (25 cm tiles).
        let basin = pool_basin_mesh();
        let centre = Vec3::new(0.0, -0.5 * POOL_DEPTH, 0.0);
        for t in &basin.indices {
            let [a, b, c] = t.map(|k| basin.positions[k as usize]);
            let n = (b - a).cross(c - a);
            if a.y == 0.0 && b.y == 0.0 && c.y == 0.0 {
                assert!(n.y > 0.0, "deck faces up");
            } else {
                assert!(n.dot(centre - a) > 0.0, "faces into the pool");
            }
            let uv = basin.uvs.as_ref().unwrap();
            let (ua, ub) = (uv[t[0] as usize], uv[t[1] as usize]);
            assert!(((ub - ua).length() - (b - a).length()).abs() < 1e-5);
        }
    }

    #[test]
    fn the_torus_is_inside_the_glass_cube() {
        let inv = trs(
            Vec3::new(0.0, EMBEDDED_CUBE_HALF, 0.0),
            Vec3::Y,
            EMBEDDED_CUBE_TURN_DEG,
            Vec3::splat(EMBEDDED_CUBE_HALF),
        )
        .inverse();
        let t = embedded_torus_mesh();
        let worst = t
            .positions
            .iter()
            .map(|p| inv.transform_point3(*p).abs().max_element())
            .fold(0.0f32, f32::max);
        // In the cube's [−1, 1]³: at least 5 cm (a sixth of the half side) inside every face.
        assert!(worst < 1.0 - 0.05 / EMBEDDED_CUBE_HALF, "{worst}");
        let b = builtin_scene("embedded-torus").unwrap();
        assert_eq!(b.settings.smoothing, Some(40.0));
        assert_eq!(b.settings.photons, Some(555_000));
        assert_eq!(b.settings.integrator.as_deref(), Some("pds"));
    }
}
