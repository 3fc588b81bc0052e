//! Volume kernels cut by surfaces: the part of a photon's kernel that lies in the region its
//! photon can reach, and the renormalisation that gives that part the photon's whole flux.
//!
//! A volume photon's kernel (a ball of the beam estimate, an ellipsoid of `vpd`) spreads its
//! flux `ΔΦ` over the kernel's volume. Where the kernel reaches through a wall, a floor, a glass
//! surface or the medium's null boundary, the part beyond is seen by no camera ray in this
//! medium: the flux there is lost and the medium looks darker within a kernel radius of every
//! surface. This is the *boundary bias* Schjøth 2009 sec. 8.5 finds darkening S-M1 (seed notes
//! §2.6); it grows with the kernels (the smoothing `s`), and in media-filled rooms most of the
//! lit medium is near some surface.
//!
//! The correction is the renormalisation of boundary kernels in density estimation (the
//! "cut-and-normalise" estimator; e.g. Jones 1993, *Simple boundary correction for kernel density
//! estimation*): each kernel is divided by the fraction `F` of its mass inside the region, so
//! that the mass the estimate can see is `ΔΦ` again. Here the region is what the photon's
//! position sees: a kernel point counts if the segment from the photon to it crosses no surface.
//! This is not in the thesis; it is an extension (`--volume-boundary renormalise`), measured in
//! `docs/results/volume-differentials`.
//!
//! # The fraction `F`
//!
//! A kernel is `K(|y|)` over the unit ball of filter space, `x = c + A y` (`A = M⁻¹`: the columns
//! are the semi-axes). Rays from the centre map to rays from the centre, so along a filter-space
//! direction `u` the physical direction is `d = A u / |A u|` and the kernel's boundary is
//! `ρ(u) = |A u|` metres away. The mass within filter radius `a` along any `u` is the same
//! fraction `C(a)` of the kernel's (`C(1) = 1`), so with `t(u)` the distance to the first surface
//! along `d`
//!
//! ```text
//! F = E_u[ C(min(1, t(u)/ρ(u))) ],   u uniform on the unit sphere
//! C(a) = a³                    (uniform kernel, eq. 8.10)
//! C(a) = (5a³ − 3a⁵)/2         (Epanechnikov, eq. 8.12: ∫₀^a (1 − u²)u² du / (2/15))
//!                              (`BeamKernel::radial_mass`)
//! ```
//!
//! estimated with [`DIRECTIONS`] spherical-Fibonacci directions under a random rotation of its
//! own per photon (deterministic from the photon's index and the render's seed), so that each
//! photon's `F` is unbiased and neighbouring photons' errors are independent. A kernel that no
//! surface cuts has `F = 1` exactly (every `t(u) ≥ ρ(u)`).

use caustica_core::sampling::Pcg32;
use caustica_core::{Mat3, Ray, Vec3};
use caustica_density::beam::BeamKernel;
use caustica_scene::Scene;
use glam::Quat;

/// Directions per kernel (spherical Fibonacci, randomly rotated per photon). For a kernel cut
/// by a plane one photon's `F` is within 0.05 of the exact fraction (RMS error below 0.02), and
/// unbiased (test `a_plane_cuts_the_kernel_as_its_marginal_says`).
pub const DIRECTIONS: usize = 64;

/// What a volume kernel that reaches through a surface keeps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum KernelBoundary {
    /// The kernel as it is: the part beyond the surface is lost (the thesis).
    #[default]
    Open,
    /// The kernel divided by the fraction of its mass its photon can see (cut and normalised).
    Renormalised,
}

/// The `i`-th of `n` spherical-Fibonacci directions (unit).
fn fibonacci(i: usize, n: usize) -> Vec3 {
    // Golden angle π(3 − √5).
    const GOLDEN: f32 = 2.399_963_2;
    let z = 1.0 - (2 * i + 1) as f32 / n as f32;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = (i as f32 * GOLDEN).sin_cos();
    Vec3::new(r * c, r * s, z)
}

/// A rotation uniform over SO(3) (Shoemake 1992) from the photon's own random stream.
fn random_rotation(seed: u64, index: u64) -> Quat {
    let mut rng = Pcg32::new(seed ^ 0x6b65_726e_656c, index);
    let (u1, u2, u3) = (rng.next_f32(), rng.next_f32(), rng.next_f32());
    let tau = std::f32::consts::TAU;
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    Quat::from_xyzw(
        a * (tau * u2).sin(),
        a * (tau * u2).cos(),
        b * (tau * u3).sin(),
        b * (tau * u3).cos(),
    )
    .normalize()
}

/// `F` for the kernel `x = centre + axes · y`, `|y| ≤ 1` (`axes = M⁻¹`, m), of photon `index`:
/// the fraction of its mass that `centre` sees without crossing a surface of `scene`, in
/// `(0, 1]` (see the module docs). `seed` and `index` choose the photon's rotation of the
/// directions.
pub fn kept_fraction(
    scene: &Scene,
    centre: Vec3,
    axes: Mat3,
    kernel: BeamKernel,
    seed: u64,
    index: u64,
) -> f32 {
    let q = random_rotation(seed, index);
    let mut sum = 0.0f32;
    for i in 0..DIRECTIONS {
        let u = q * fibonacci(i, DIRECTIONS);
        let w = axes * u;
        let rho = w.length();
        if !(rho > 0.0 && rho.is_finite()) {
            sum += 1.0;
            continue;
        }
        let ray = Ray {
            t_max: rho,
            ..Ray::new(centre, w / rho)
        };
        sum += match scene.intersect(&ray) {
            Some(hit) => kernel.radial_mass(hit.t / rho),
            None => 1.0,
        };
    }
    // A centre on a surface could see nothing; keep F away from 0 (at most a 64× boost, the
    // resolution of the direction set).
    (sum / DIRECTIONS as f32).max(1.0 / DIRECTIONS as f32)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use caustica_core::{Affine3A, Spectrum};
    use caustica_scene::SceneBuilder;
    use caustica_scene::camera::PerspectiveCamera;
    use caustica_scene::material::Material;
    use caustica_scene::medium::Medium;
    use caustica_scene::shape::{ShapeGeometry, TriangleMesh};
    use caustica_scene::texture::Texture;

    /// A scene with one 100 × 100 m diffuse quad in the plane y = 0 and, if given, a medium
    /// (index 0; the quad does not bound it, spans are made by hand).
    pub(crate) fn floor(medium: Option<Medium>) -> Scene {
        let mut b = SceneBuilder::new("floor");
        if let Some(m) = medium {
            b.add_medium("m", m).unwrap();
        }
        let m = b
            .add_material(
                "grey",
                Material::Diffuse {
                    reflectance: Texture::Constant(Spectrum::splat(0.5)),
                },
            )
            .unwrap();
        let to_world = Affine3A::from_rotation_x(-std::f32::consts::FRAC_PI_2)
            * Affine3A::from_scale(Vec3::splat(50.0));
        b.add_shape(
            ShapeGeometry::Mesh(TriangleMesh::rectangle(&to_world)),
            m,
            None,
            false,
        )
        .unwrap();
        b.set_camera(PerspectiveCamera::look_at(
            Vec3::new(0.0, 1.0, 5.0),
            Vec3::ZERO,
            Vec3::Y,
            30.0,
            4,
            4,
        ));
        b.build().unwrap()
    }

    /// The exact fraction of a kernel whose centre is `h` filter radii above a plane (the
    /// kernel's marginal along the normal: `(1 − z²)²` for Epanechnikov, `1 − z²` uniform).
    fn marginal_above(kernel: BeamKernel, h: f64) -> f64 {
        let h = h.clamp(-1.0, 1.0);
        match kernel {
            // ∫_{-h}^{1} (1 − z²)² dz / (16/15)
            BeamKernel::Epanechnikov => {
                let f = |z: f64| z - 2.0 * z.powi(3) / 3.0 + z.powi(5) / 5.0;
                (f(1.0) - f(-h)) / (16.0 / 15.0)
            }
            BeamKernel::Uniform => {
                let f = |z: f64| z - z.powi(3) / 3.0;
                (f(1.0) - f(-h)) / (4.0 / 3.0)
            }
        }
    }

    #[test]
    fn a_plane_cuts_the_kernel_as_its_marginal_says() {
        // Balls and random ellipsoids over the plane y = 0 at filter-space heights h (the
        // plane's distance over the kernel's extent |Aᵀn| along its normal): one photon's F
        // within 0.05 of the exact fraction (RMS 0.02), the mean over photons within 0.5 %
        // (unbiased).
        let scene = floor(None);
        let mut rng = Pcg32::new(3, 9);
        let mut u = || 2.0 * rng.next_f32() - 1.0;
        let mut worst = 0.0f64;
        for kernel in [BeamKernel::Epanechnikov, BeamKernel::Uniform] {
            for (case, h) in [0.0f32, 0.3, 0.6, 0.9, 1.5].into_iter().enumerate() {
                let (mut mean, mut sq) = (0.0f64, 0.0f64);
                let photons = 200;
                let mut want = 0.0;
                for i in 0..photons {
                    let axes = if i % 2 == 0 {
                        Mat3::from_diagonal(Vec3::splat(0.2))
                    } else {
                        // A random, possibly flat, ellipsoid.
                        Mat3::from_cols(
                            Vec3::new(u(), u(), u()) * 0.3,
                            Vec3::new(u(), u(), u()) * 0.2,
                            Vec3::new(u(), u(), u()) * 0.05,
                        )
                    };
                    let extent = (axes.transpose() * Vec3::Y).length();
                    let centre = Vec3::new(u(), h * extent + 1e-5, u());
                    let f =
                        kept_fraction(&scene, centre, axes, kernel, 11, (case * 1000 + i) as u64);
                    want = marginal_above(kernel, h as f64);
                    assert!(
                        (f as f64 - want).abs() < 0.05,
                        "{kernel:?} h = {h}: F = {f} vs {want}"
                    );
                    mean += f as f64 / photons as f64;
                    sq += (f as f64 - want).powi(2) / photons as f64;
                }
                assert!(
                    (mean - want).abs() < 0.005 * want.max(0.5),
                    "{kernel:?} h = {h}: mean F = {mean} vs {want}"
                );
                assert!(
                    sq.sqrt() < 0.02,
                    "{kernel:?} h = {h}: RMS error {}",
                    sq.sqrt()
                );
                worst = worst.max(sq.sqrt());
            }
        }
        eprintln!("worst RMS error of one photon's F: {worst:.4}");
    }

    #[test]
    fn an_uncut_kernel_keeps_everything() {
        let scene = floor(None);
        let axes = Mat3::from_diagonal(Vec3::new(0.3, 0.1, 0.2));
        for i in 0..50 {
            let f = kept_fraction(
                &scene,
                Vec3::new(0.0, 0.31, 0.0),
                axes,
                BeamKernel::Epanechnikov,
                1,
                i,
            );
            assert_eq!(f, 1.0);
        }
    }
}
