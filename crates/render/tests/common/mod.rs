//! Scenes and statistics shared by the render tests.
#![allow(dead_code)]

use caustica_core::Affine3A;
use caustica_core::image_io::Image;
use caustica_core::{Spectrum, Vec3};
use caustica_render::{IntegratorKind, PathLimits, RenderControl, RenderOptions, render};
use caustica_scene::camera::PerspectiveCamera;
use caustica_scene::light::{Light, PointLight};
use caustica_scene::material::Material;
use caustica_scene::shape::{ShapeGeometry, Sphere, TriangleMesh};
use caustica_scene::texture::Texture;
use caustica_scene::{Scene, SceneBuilder};

pub fn render_image(scene: &Scene, kind: IntegratorKind, spp: u32, seed: u64) -> Image {
    render_image_depth(scene, kind, spp, seed, u32::MAX)
}

/// As [`render_image`] with a maximum path length in edges (Mitsuba's `max_depth`).
pub fn render_image_depth(
    scene: &Scene,
    kind: IntegratorKind,
    spp: u32,
    seed: u64,
    max_depth: u32,
) -> Image {
    let opts = RenderOptions {
        spp,
        seed,
        limits: PathLimits {
            max_depth,
            ..PathLimits::default()
        },
        ..Default::default()
    };
    render(scene, kind, &opts, &RenderControl::silent())
        .expect("valid options")
        .film
        .to_image()
}

pub fn diffuse(b: &mut SceneBuilder, name: &str, albedo: f32) -> u32 {
    b.add_material(
        name,
        Material::Diffuse {
            reflectance: Texture::Constant(Spectrum::splat(albedo)),
        },
    )
    .unwrap()
}

/// A rectangle (Mitsuba convention: [−1,1]² facing +z) transformed.
pub fn quad(t: Affine3A) -> ShapeGeometry {
    ShapeGeometry::Mesh(TriangleMesh::rectangle(&t))
}

/// An open diffuse box (floor, back wall, left and right walls, ceiling) with a square area
/// light under the ceiling, seen from the open front: only diffuse surfaces.
pub fn diffuse_box(width: u32, height: u32) -> Scene {
    let mut b = SceneBuilder::new("diffuse-box");
    let white = diffuse(&mut b, "white", 0.7);
    let grey = diffuse(&mut b, "grey", 0.4);
    let light_mat = diffuse(&mut b, "black", 0.0);
    use std::f32::consts::FRAC_PI_2;
    // floor y = -1 facing up
    b.add_shape(
        quad(
            Affine3A::from_translation(Vec3::new(0.0, -1.0, 0.0))
                * Affine3A::from_rotation_x(-FRAC_PI_2),
        ),
        white,
        None,
        false,
    )
    .unwrap();
    // ceiling y = 1 facing down
    b.add_shape(
        quad(
            Affine3A::from_translation(Vec3::new(0.0, 1.0, 0.0))
                * Affine3A::from_rotation_x(FRAC_PI_2),
        ),
        white,
        None,
        false,
    )
    .unwrap();
    // back wall z = -1 facing +z
    b.add_shape(
        quad(Affine3A::from_translation(Vec3::new(0.0, 0.0, -1.0))),
        grey,
        None,
        false,
    )
    .unwrap();
    // left wall x = -1 facing +x, right wall x = 1 facing -x
    b.add_shape(
        quad(
            Affine3A::from_translation(Vec3::new(-1.0, 0.0, 0.0))
                * Affine3A::from_rotation_y(FRAC_PI_2),
        ),
        white,
        None,
        false,
    )
    .unwrap();
    b.add_shape(
        quad(
            Affine3A::from_translation(Vec3::new(1.0, 0.0, 0.0))
                * Affine3A::from_rotation_y(-FRAC_PI_2),
        ),
        grey,
        None,
        false,
    )
    .unwrap();
    // area light just below the ceiling, facing down
    b.add_shape(
        quad(
            Affine3A::from_translation(Vec3::new(0.0, 0.98, 0.0))
                * Affine3A::from_rotation_x(FRAC_PI_2)
                * Affine3A::from_scale(Vec3::splat(0.3)),
        ),
        light_mat,
        Some(Spectrum::splat(10.0)),
        false,
    )
    .unwrap();
    // a sphere on the floor
    b.add_shape(
        ShapeGeometry::Sphere(Sphere {
            center: Vec3::new(0.3, -0.6, -0.2),
            radius: 0.4,
        }),
        white,
        None,
        false,
    )
    .unwrap();
    b.set_camera(PerspectiveCamera::look_at(
        Vec3::new(0.0, 0.0, 3.5),
        Vec3::ZERO,
        Vec3::Y,
        40.0,
        width,
        height,
    ));
    b.build().unwrap()
}

/// Mean of each channel over a region (x0..x1, y0..y1).
/// Mean of every pixel of `img`, per channel.
pub fn mean_rgb(img: &Image) -> [f64; 3] {
    region_mean(img, 0, 0, img.width, img.height)
}

/// Per channel: the mean of `runs` (one value per independent render) and its standard error
/// from their spread.
pub fn mean_and_standard_error(runs: &[[f64; 3]]) -> [(f64, f64); 3] {
    let n = runs.len() as f64;
    std::array::from_fn(|k| {
        let m = runs.iter().map(|r| r[k]).sum::<f64>() / n;
        let var = runs.iter().map(|r| (r[k] - m).powi(2)).sum::<f64>() / (n - 1.0);
        (m, (var / n).sqrt())
    })
}

pub fn region_mean(img: &Image, x0: usize, y0: usize, x1: usize, y1: usize) -> [f64; 3] {
    let mut s = [0.0f64; 3];
    for y in y0..y1 {
        for x in x0..x1 {
            let p = img.get(x, y);
            for k in 0..3 {
                s[k] += p[k] as f64;
            }
        }
    }
    let n = ((x1 - x0) * (y1 - y0)) as f64;
    s.map(|v| v / n)
}

/// Luminance-like scalar of a pixel (channel mean).
pub fn lum(p: [f32; 3]) -> f64 {
    (p[0] as f64 + p[1] as f64 + p[2] as f64) / 3.0
}

/// Mean of [`lum`] over an image.
pub fn mean_lum(img: &caustica_core::image_io::Image) -> f64 {
    img.data.iter().map(|&p| lum(p)).sum::<f64>() / img.data.len() as f64
}

/// Averages `block × block` pixel blocks (channel mean), returning the block image.
pub fn blocks(img: &Image, block: usize) -> Vec<f64> {
    let (bw, bh) = (img.width / block, img.height / block);
    let mut out = vec![0.0; bw * bh];
    for by in 0..bh {
        for bx in 0..bw {
            let mut s = 0.0;
            for y in 0..block {
                for x in 0..block {
                    s += lum(img.get(bx * block + x, by * block + y));
                }
            }
            out[by * bw + bx] = s / (block * block) as f64;
        }
    }
    out
}

/// Channel mean of an RGB triple.
pub fn lum_arr(p: [f64; 3]) -> f64 {
    (p[0] + p[1] + p[2]) / 3.0
}

/// Adds a diffuse material "floor" (albedo `albedo`) and a 4 m × 4 m quad of it at y = 0 facing
/// up; returns the material.
pub fn add_floor(b: &mut SceneBuilder, albedo: f32) -> u32 {
    let floor = diffuse(b, "floor", albedo);
    b.add_shape(
        quad(
            Affine3A::from_rotation_x(-std::f32::consts::FRAC_PI_2)
                * Affine3A::from_scale(Vec3::splat(2.0)),
        ),
        floor,
        None,
        false,
    )
    .unwrap();
    floor
}

/// Adds a dielectric material "glass" (IOR 1.5) and a ball of it, radius 0.5, centred at
/// (0, 1, 0).
pub fn add_glass_ball(b: &mut SceneBuilder) {
    let glass = b
        .add_material(
            "glass",
            Material::Dielectric {
                ior: 1.5,
                absorption: Spectrum::ZERO,
                dispersion: None,
            },
        )
        .unwrap();
    b.add_shape(
        ShapeGeometry::Sphere(Sphere {
            center: Vec3::new(0.0, 1.0, 0.0),
            radius: 0.5,
        }),
        glass,
        None,
        false,
    )
    .unwrap();
}

/// A 4 m × 4 m diffuse floor (albedo `albedo`) at y = 0 facing up, under a point light of
/// intensity `intensity` (W/sr) at (0, `light_y`, 0), optionally with a glass ball (IOR 1.5,
/// radius 0.5) centred 1 m above the floor, seen from (0, 3, 3.5) at `size`×`size` pixels.
/// With the light at y = 4 the ball images it (paraxially: 1/v = 2(n−1)/(nR) − 1/u) onto the
/// floor, a sharply focused caustic.
pub fn ball_on_floor(albedo: f32, intensity: f32, light_y: f32, glass: bool, size: u32) -> Scene {
    let mut b = SceneBuilder::new("ball-on-floor");
    add_floor(&mut b, albedo);
    if glass {
        add_glass_ball(&mut b);
    }
    b.add_light(Light::Point(PointLight::new(
        Vec3::new(0.0, light_y, 0.0),
        Spectrum::splat(intensity),
    )));
    b.set_camera(PerspectiveCamera::look_at(
        Vec3::new(0.0, 3.0, 3.5),
        Vec3::ZERO,
        Vec3::Y,
        50.0,
        size,
        size,
    ));
    b.build().unwrap()
}

/// `f` run on a rayon pool of `threads` threads (determinism tests: same bytes for any count).
pub fn with_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(f)
}

/// The white furnace: a unit sphere of `material` at the origin inside a constant environment of
/// radiance 1 (RGB (1, 1, 1); D65_n in spectral mode), seen from 4 m at `size`×`size` pixels.
pub fn furnace(material: Material, size: u32) -> Scene {
    let mut b = SceneBuilder::new("furnace");
    let m = b.add_material("ball", material).unwrap();
    b.add_shape(
        ShapeGeometry::Sphere(Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        }),
        m,
        None,
        false,
    )
    .unwrap();
    b.add_light(Light::Environment(
        caustica_scene::light::EnvironmentLight::constant(Spectrum::ONE),
    ));
    b.set_camera(PerspectiveCamera::look_at(
        Vec3::new(0.0, 0.0, 4.0),
        Vec3::ZERO,
        Vec3::Y,
        35.0,
        size,
        size,
    ));
    b.build().unwrap()
}

/// The built-in scene `name` at `w` × `h` pixels.
pub fn small_builtin(name: &str, w: u32, h: u32) -> Scene {
    let mut b = caustica_loader::builtin_scene(name).unwrap();
    let mut camera = b.camera().unwrap().clone();
    (camera.width, camera.height) = (w, h);
    b.set_camera(camera);
    b.build().unwrap()
}
