//! Newton's dispersion prism (seed 002 fig. 12, issue 22; `docs/scenes.md`): a narrow
//! collimated beam of daylight through an equilateral flint-glass prism standing on a table.
//! The beam descends gently after the prism, so its spectrum lands on the table as a sharp
//! coloured streak running from the prism toward a white screen, which the table's caustic
//! lights softly. A spectral scene (`--spectral`): in RGB mode the prism refracts every colour
//! with its IOR at the d line and the streak is white.
//!
//! Geometry (m): the prism's triangle lies in the table plane y = 0 (x, z), centroid at the
//! origin, apex toward +z, side [`PRISM_SIDE`], height [`PRISM_HEIGHT`]; the beam travels
//! toward +x, aimed at the middle of the prism's left face at the angle of minimum deviation
//! for 550 nm, tilted down by [`PRISM_BEAM_SLOPE_DEG`].

use super::{camera, diffuse, trs};
use caustica_core::{Spectrum, Vec3};
use caustica_scene::SceneError;
use caustica_scene::dispersion::Dispersion;
use caustica_scene::light::{BeamLight, EmissionSpectrum, Light, NamedSpectrum};
use caustica_scene::material::Material;
use caustica_scene::scene::SceneBuilder;
use caustica_scene::shape::{ShapeGeometry, TriangleMesh};

/// The prism's glass (Schott F2, a flint: V_d ≈ 36, so the colours part widely).
pub const PRISM_GLASS: &str = "F2";
/// Side of the prism's equilateral cross-section and its height (m).
pub const PRISM_SIDE: f32 = 0.1;
pub const PRISM_HEIGHT: f32 = 0.08;
/// The wavelength (nm) whose ray passes the prism at minimum deviation (parallel to the base).
pub const PRISM_DESIGN_NM: f32 = 550.0;
/// Height (m) at which the beam's axis meets the prism's left face.
pub const PRISM_BEAM_HEIGHT: f32 = 0.04;
/// Radius of the beam (m).
pub const PRISM_BEAM_RADIUS: f32 = 0.003;
/// Downward tilt of the beam (degrees): its spectrum reaches the table about 0.45 m after the
/// prism, before the screen.
pub const PRISM_BEAM_SLOPE_DEG: f32 = 4.5;
/// Distance (m) from the beam's axis on the prism's left face back to the beam light.
pub const PRISM_BEAM_DISTANCE: f32 = 0.5;
/// Luminance of the beam's D65 irradiance (W/m² on a plane across the beam).
pub const PRISM_BEAM_IRRADIANCE: f32 = 120.0;
/// Distance (m) from the middle of the prism's right face to the screen, along the design ray.
pub const PRISM_SCREEN_DISTANCE: f32 = 0.6;
/// The screen's half width and height (m).
pub const PRISM_SCREEN_HALF: (f32, f32) = (0.25, 0.15);
/// Albedos: the table and the screen, grey (flat spectra).
pub const PRISM_TABLE_ALBEDO: f32 = 0.7;
pub const PRISM_SCREEN_ALBEDO: f32 = 0.8;

/// The camera: above and in front of the prism, looking down the spectrum toward the screen.
pub const PRISM_EYE: Vec3 = Vec3::new(0.0, 0.3, 0.3);
pub const PRISM_LOOK_AT: Vec3 = Vec3::new(0.4, 0.04, -0.18);
pub const PRISM_FOV_DEG: f32 = 32.0;

/// The prism's glass law.
pub fn prism_dispersion() -> Dispersion {
    Dispersion::named(PRISM_GLASS).unwrap_or(Dispersion::Cauchy {
        a: 1.6,
        b: 0.01,
        c: 0.0,
    })
}

/// The triangle's corners in the table plane as (x, z): left and right ends of the base (at
/// −z) and the apex (+z); the centroid is the origin.
pub fn prism_corners() -> [(f32, f32); 3] {
    let a = PRISM_SIDE;
    let h = a * 3f32.sqrt() / 2.0;
    [
        (-a / 2.0, -h / 3.0),
        (a / 2.0, -h / 3.0),
        (0.0, 2.0 * h / 3.0),
    ]
}

/// Horizontal direction (x, z) of the beam before the prism: the ray of [`PRISM_DESIGN_NM`]
/// that crosses the prism parallel to its base meets the left face at incidence i with
/// sin i = n sin 30° (minimum deviation of a 60° prism).
pub fn prism_incident_azimuth_deg() -> f32 {
    let n = prism_dispersion().ior(PRISM_DESIGN_NM);
    let i = (n * 0.5).asin().to_degrees();
    // The left face's inward normal points at −30° (toward +x, −z); the ray comes in at i from
    // it, on the apex side.
    -30.0 + i
}

/// Unit direction of the beam: azimuth [`prism_incident_azimuth_deg`] toward +x/+z, tilted
/// down by `slope_deg`.
pub fn prism_beam_direction(slope_deg: f32) -> Vec3 {
    let (sa, ca) = prism_incident_azimuth_deg().to_radians().sin_cos();
    let (ss, cs) = slope_deg.to_radians().sin_cos();
    Vec3::new(ca * cs, -ss, sa * cs)
}

/// Where the beam's axis meets the prism's left face (the middle of the face at
/// [`PRISM_BEAM_HEIGHT`]).
pub fn prism_beam_target() -> Vec3 {
    let [l, _, t] = prism_corners();
    Vec3::new(0.5 * (l.0 + t.0), PRISM_BEAM_HEIGHT, 0.5 * (l.1 + t.1))
}

/// The prism as a closed mesh with outward faces (flat: no vertex normals).
pub fn prism_mesh() -> TriangleMesh {
    let c = prism_corners();
    let mut positions = Vec::new();
    for y in [0.0, PRISM_HEIGHT] {
        for (x, z) in c {
            positions.push(Vec3::new(x, y, z));
        }
    }
    // Bottom 0,1,2 (facing −y), top 3,4,5 (facing +y); sides counter-clockwise seen from
    // outside.
    let indices = vec![
        [0, 1, 2],
        [3, 5, 4],
        [0, 4, 1],
        [0, 3, 4],
        [1, 5, 2],
        [1, 4, 5],
        [2, 3, 0],
        [2, 5, 3],
    ];
    TriangleMesh {
        positions,
        normals: None,
        uvs: None,
        indices,
    }
}

/// `prism`: the scene of seed 002 fig. 12 (parameters above and in `docs/scenes.md`).
pub(super) fn prism() -> Result<SceneBuilder, SceneError> {
    prism_with_slope(PRISM_BEAM_SLOPE_DEG)
}

/// The prism scene with the beam tilted down by `slope_deg` (0: the spectrum reaches the
/// screen, for the deviation test).
pub fn prism_with_slope(slope_deg: f32) -> Result<SceneBuilder, SceneError> {
    let mut b = SceneBuilder::new("prism");
    b.set_camera(camera(PRISM_EYE, PRISM_LOOK_AT, PRISM_FOV_DEG, 400, 300));
    b.settings.spp = Some(16);
    b.settings.max_depth = Some(16);
    b.settings.integrator = Some("pds".into());
    let table = b.add_material(
        "table",
        diffuse(PRISM_TABLE_ALBEDO, PRISM_TABLE_ALBEDO, PRISM_TABLE_ALBEDO),
    )?;
    let screen = b.add_material(
        "screen",
        diffuse(
            PRISM_SCREEN_ALBEDO,
            PRISM_SCREEN_ALBEDO,
            PRISM_SCREEN_ALBEDO,
        ),
    )?;
    let law = prism_dispersion();
    let glass = b.add_material(
        "glass",
        Material::Dielectric {
            ior: law.ior_d(),
            absorption: Spectrum::ZERO,
            dispersion: Some(law),
        },
    )?;
    // The table: 1.6 × 1.6 m around the prism and the screen, facing up.
    b.add_shape(
        ShapeGeometry::Mesh(TriangleMesh::rectangle(&trs(
            Vec3::new(0.3, 0.0, -0.2),
            Vec3::X,
            -90.0,
            Vec3::new(0.8, 0.8, 1.0),
        ))),
        table,
        None,
        false,
    )?;
    b.add_shape(ShapeGeometry::Mesh(prism_mesh()), glass, None, false)?;
    // The screen stands on the table across the design ray, facing back toward the prism.
    let [_, r, t] = prism_corners();
    let exit = Vec3::new(0.5 * (r.0 + t.0), 0.0, 0.5 * (r.1 + t.1));
    let az = prism_incident_azimuth_deg().to_radians();
    let out = Vec3::new(az.cos(), 0.0, -az.sin());
    let centre = exit + out * PRISM_SCREEN_DISTANCE + Vec3::Y * PRISM_SCREEN_HALF.1;
    // The rectangle faces +z before rotation; turn it about y so that it faces −out.
    let facing = -out;
    let yaw = facing.x.atan2(facing.z).to_degrees();
    b.add_shape(
        ShapeGeometry::Mesh(TriangleMesh::rectangle(&trs(
            centre,
            Vec3::Y,
            yaw,
            Vec3::new(PRISM_SCREEN_HALF.0, PRISM_SCREEN_HALF.1, 1.0),
        ))),
        screen,
        None,
        false,
    )?;
    let d = prism_beam_direction(slope_deg);
    let centre = prism_beam_target() - d * PRISM_BEAM_DISTANCE;
    let d65 = NamedSpectrum::D65;
    b.add_light(Light::Beam(BeamLight::new(
        centre,
        d,
        PRISM_BEAM_RADIUS,
        d65.rgb() * PRISM_BEAM_IRRADIANCE,
    )));
    b.set_light_spectrum(0, EmissionSpectrum::named(d65));
    Ok(b)
}
