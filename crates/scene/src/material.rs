//! Materials: BSDF parameters (possibly textured) attached to shapes; [`Material::bsdf`]
//! instantiates the [`Bsdf`] at a hit point.

use crate::bsdf::{
    Bsdf, Conductor, Dielectric, Lambertian, Mirror, Phong, RoughConductor, RoughDielectric,
};
use crate::dispersion::Dispersion;
use crate::intersection::SurfaceInteraction;
use crate::texture::Texture;
use caustica_core::{Channels, Spectrum};

/// A material as described in the scene.
#[derive(Clone, Debug)]
pub enum Material {
    /// Lambertian reflector with albedo `reflectance` ∈ [0, 1].
    Diffuse { reflectance: Texture },
    /// Perfect specular reflector.
    Mirror { reflectance: Spectrum },
    /// Smooth dielectric interface; `ior` = η_inside/η_outside; `absorption` σa (m⁻¹) of the
    /// interior (Beer–Lambert), zero for clear glass. With `dispersion` the IOR varies with
    /// wavelength in spectral mode (`ior` is then its value at the d line, what RGB mode uses).
    Dielectric {
        ior: f32,
        absorption: Spectrum,
        dispersion: Option<Dispersion>,
    },
    /// Smooth conductor with complex IOR η + iκ per channel (relative to the outside medium).
    Conductor {
        eta: Spectrum,
        k: Spectrum,
        specular: Spectrum,
    },
    /// GGX rough conductor, roughness α (= Beckmann-style width; α = r² for perceptual r).
    RoughConductor {
        eta: Spectrum,
        k: Spectrum,
        alpha: f32,
        specular: Spectrum,
    },
    /// GGX rough dielectric (`dispersion` as for [`Material::Dielectric`]).
    RoughDielectric {
        ior: f32,
        alpha: f32,
        absorption: Spectrum,
        dispersion: Option<Dispersion>,
    },
    /// An index-matched boundary (Mitsuba's `null`): rays pass through unchanged, only the
    /// medium changes (a fog volume's box). The walkers skip these surfaces
    /// (`transport::trace_segment`); should one be shaded anyway it acts as a dielectric of
    /// IOR 1, which transmits everything straight on.
    Null,
    /// Normalised Blinn–Phong glossy lobe (seed 001 eq. 4.1) plus a Lambertian term.
    Phong {
        diffuse: Texture,
        specular: Spectrum,
        exponent: f32,
    },
}

/// Below this GGX roughness a rough material is rendered as its smooth counterpart: the lobe is
/// narrower than single-precision sampling resolves (pbrt-v4 `EffectivelySmooth` uses 1e-3).
pub const SMOOTH_ALPHA: f32 = 1e-3;

impl Material {
    /// The BSDF at `si` for a path whose lanes mean `ch` (RGB values are converted to the path's
    /// wavelengths in spectral mode). Textures are evaluated at `si.uv`. Rough materials with
    /// α < [`SMOOTH_ALPHA`] and rough dielectrics with IOR 1 become their smooth counterparts.
    /// A dispersive dielectric in spectral mode refracts with the IOR of the hero wavelength
    /// and ends the path's secondary wavelengths ([`Channels::terminate_secondary`]: they would
    /// refract elsewhere).
    pub fn bsdf(&self, si: &SurfaceInteraction, ch: &mut Channels) -> Bsdf {
        match self {
            Material::Diffuse { reflectance } => {
                Bsdf::Lambertian(Lambertian::new(ch.reflectance(reflectance.eval(si.uv))))
            }
            Material::Mirror { reflectance } => {
                Bsdf::Mirror(Mirror::new(ch.reflectance(*reflectance)))
            }
            Material::Dielectric {
                ior, dispersion, ..
            } => Bsdf::Dielectric(Dielectric::new(ior_for(*ior, dispersion, ch))),
            Material::Null => Bsdf::Dielectric(Dielectric::new(1.0)),
            Material::Conductor { eta, k, specular } => Bsdf::Conductor(Conductor::new(
                ch.unbounded(*eta),
                ch.unbounded(*k),
                ch.reflectance(*specular),
            )),
            Material::RoughConductor {
                eta,
                k,
                alpha,
                specular,
            } => {
                let (eta, k, specular) = (
                    ch.unbounded(*eta),
                    ch.unbounded(*k),
                    ch.reflectance(*specular),
                );
                if *alpha < SMOOTH_ALPHA {
                    Bsdf::Conductor(Conductor::new(eta, k, specular))
                } else {
                    Bsdf::RoughConductor(RoughConductor::new(*alpha, eta, k, specular))
                }
            }
            Material::RoughDielectric {
                ior,
                alpha,
                dispersion,
                ..
            } => {
                let ior = ior_for(*ior, dispersion, ch);
                if *alpha < SMOOTH_ALPHA || ior == 1.0 {
                    Bsdf::Dielectric(Dielectric::new(ior))
                } else {
                    Bsdf::RoughDielectric(RoughDielectric::new(*alpha, ior))
                }
            }
            Material::Phong {
                diffuse,
                specular,
                exponent,
            } => Bsdf::Phong(Phong::new(
                ch.reflectance(diffuse.eval(si.uv)),
                ch.reflectance(*specular),
                *exponent,
            )),
        }
    }

    /// The dispersion law of a dispersive dielectric (smooth or rough), `None` otherwise.
    pub fn dispersion(&self) -> Option<&Dispersion> {
        match self {
            Material::Dielectric { dispersion, .. }
            | Material::RoughDielectric { dispersion, .. } => dispersion.as_ref(),
            _ => None,
        }
    }

    /// How many texels of the material's reflectance textures (diffuse albedos) have a
    /// component outside [0, 1]: spectral mode clamps them.
    pub fn reflectance_values_outside_unit_range(&self) -> usize {
        let count = |t: &Texture| match t {
            Texture::Image(img) => img
                .image
                .data
                .iter()
                .filter(|p| p.iter().any(|v| !(0.0..=1.0).contains(v)))
                .count(),
            _ => 0,
        };
        match self {
            Material::Diffuse { reflectance } => count(reflectance),
            Material::Phong { diffuse, .. } => count(diffuse),
            _ => 0,
        }
    }

    /// True for the index-matched [`Material::Null`].
    #[inline]
    pub fn is_null(&self) -> bool {
        matches!(self, Material::Null)
    }

    /// True if the material's BSDF has a delta lobe (mirror, smooth glass and metal, rough ones
    /// below [`SMOOTH_ALPHA`]): the surfaces a caustic light path L S+ D scatters at first.
    /// Projection maps mark the emission cells that reach such surfaces.
    pub fn can_be_delta(&self) -> bool {
        match self {
            Material::Mirror { .. } | Material::Dielectric { .. } | Material::Conductor { .. } => {
                true
            }
            Material::RoughConductor { alpha, .. } => *alpha < SMOOTH_ALPHA,
            Material::RoughDielectric { alpha, ior, .. } => *alpha < SMOOTH_ALPHA || *ior == 1.0,
            Material::Diffuse { .. } | Material::Phong { .. } | Material::Null => false,
        }
    }

    /// Interior absorption coefficient σa (m⁻¹) for dielectrics with Beer–Lambert absorption,
    /// in RGB (convert with [`Channels::unbounded`]).
    pub fn interior_absorption(&self) -> Option<Spectrum> {
        match self {
            Material::Dielectric { absorption, .. }
            | Material::RoughDielectric { absorption, .. }
                if !absorption.is_black() =>
            {
                Some(*absorption)
            }
            _ => None,
        }
    }
    /// Checks parameter ranges (IOR > 0, α > 0, exponent ≥ 0, finite values, non-negative
    /// colours, albedos and tints ≤ 1, Phong kd + ks ≤ 1 per channel). The message names the
    /// offending parameter and its value.
    pub fn validate(&self) -> Result<(), String> {
        match self {
            Material::Diffuse { reflectance } => check_texture("diffuse reflectance", reflectance),
            Material::Mirror { reflectance } => check_albedo("mirror reflectance", *reflectance),
            Material::Null => Ok(()),
            Material::Dielectric {
                ior,
                absorption,
                dispersion,
            } => {
                check_ior("dielectric ior", *ior)?;
                check_dispersion("dielectric", dispersion)?;
                check_colour("dielectric absorption", *absorption)
            }
            Material::Conductor { eta, k, specular } => {
                check_complex_ior("conductor", *eta, *k)?;
                check_albedo("conductor specular", *specular)
            }
            Material::RoughConductor {
                eta,
                k,
                alpha,
                specular,
            } => {
                check_complex_ior("rough conductor", *eta, *k)?;
                check_alpha("rough conductor alpha", *alpha)?;
                check_albedo("rough conductor specular", *specular)
            }
            Material::RoughDielectric {
                ior,
                alpha,
                absorption,
                dispersion,
            } => {
                check_ior("rough dielectric ior", *ior)?;
                check_dispersion("rough dielectric", dispersion)?;
                check_alpha("rough dielectric alpha", *alpha)?;
                check_colour("rough dielectric absorption", *absorption)
            }
            Material::Phong {
                diffuse,
                specular,
                exponent,
            } => {
                if !(exponent.is_finite() && *exponent >= 0.0) {
                    return Err(format!(
                        "phong exponent must be finite and >= 0, got {exponent}"
                    ));
                }
                check_albedo("phong specular", *specular)?;
                check_texture("phong diffuse", diffuse)?;
                for_each_texel(diffuse, |kd| {
                    let sum = kd + *specular;
                    if sum.max_component() > 1.0 + 1e-6 {
                        Err(format!(
                            "phong diffuse + specular must be <= 1 per channel (energy \
                             conservation), got diffuse {:?} + specular {:?} = {:?}",
                            kd.to_rgb(),
                            specular.to_rgb(),
                            sum.to_rgb()
                        ))
                    } else {
                        Ok(())
                    }
                })
            }
        }
    }
}

fn check_ior(name: &str, ior: f32) -> Result<(), String> {
    if ior.is_finite() && ior > 0.0 {
        Ok(())
    } else {
        Err(format!("{name} must be finite and > 0, got {ior}"))
    }
}

fn check_dispersion(name: &str, d: &Option<Dispersion>) -> Result<(), String> {
    match d {
        Some(d) => d.validate().map_err(|e| format!("{name}: {e}")),
        None => Ok(()),
    }
}

/// The relative IOR a dielectric refracts with on a path with lanes `ch`: the dispersion law at
/// the hero wavelength in spectral mode (ending the secondary wavelengths), else `ior`.
#[inline]
fn ior_for(ior: f32, dispersion: &Option<Dispersion>, ch: &mut Channels) -> f32 {
    match (dispersion, ch.hero()) {
        (Some(d), Some(hero)) => {
            ch.terminate_secondary();
            d.ior(hero)
        }
        _ => ior,
    }
}

fn check_alpha(name: &str, alpha: f32) -> Result<(), String> {
    if alpha.is_finite() && alpha > 0.0 {
        Ok(())
    } else {
        Err(format!("{name} must be finite and > 0, got {alpha}"))
    }
}

fn check_colour(name: &str, c: Spectrum) -> Result<(), String> {
    if c.is_finite() && c.min_component() >= 0.0 {
        Ok(())
    } else {
        Err(format!(
            "{name} must be finite and >= 0, got {:?}",
            c.to_rgb()
        ))
    }
}

fn check_albedo(name: &str, c: Spectrum) -> Result<(), String> {
    check_colour(name, c)?;
    if c.max_component() > 1.0 {
        return Err(format!(
            "{name} must be <= 1 (energy conservation), got {:?}",
            c.to_rgb()
        ));
    }
    Ok(())
}

fn check_complex_ior(name: &str, eta: Spectrum, k: Spectrum) -> Result<(), String> {
    if !(eta.is_finite() && eta.min_component() > 0.0) {
        return Err(format!(
            "{name} eta must be finite and > 0, got {:?}",
            eta.to_rgb()
        ));
    }
    check_colour(&format!("{name} k"), k)
}

/// Calls `f` on every value a texture can take (constant, both checker colours, every texel).
fn for_each_texel(
    t: &Texture,
    mut f: impl FnMut(Spectrum) -> Result<(), String>,
) -> Result<(), String> {
    match t {
        Texture::Constant(c) => f(*c),
        Texture::Checkerboard { a, b, .. } => {
            f(*a)?;
            f(*b)
        }
        Texture::Image(img) => img
            .image
            .data
            .iter()
            .try_for_each(|p| f(Spectrum::from_rgb(*p))),
    }
}

fn check_texture(name: &str, t: &Texture) -> Result<(), String> {
    for_each_texel(t, |c| check_albedo(name, c))
}

/// Complex refractive index (η, κ) in RGB of a named conductor, relative to air:
/// "Au" (gold), "Ag" (silver), "Al" (aluminium), "Cu" (copper).
///
/// Values: spectral optical constants integrated to linear sRGB, as tabulated in Tungsten's
/// `ComplexIorData.hpp` (Benedikt Bitterli, derived from the measured data shipped with Mitsuba
/// 0.5/PBRT) and used unchanged by pbrt-v4 and Nori scene converters.
pub fn conductor_preset(name: &str) -> Option<(Spectrum, Spectrum)> {
    let (eta, k) = match name {
        "Au" => (
            [0.143_118_96, 0.374_957_04, 1.442_478_6],
            [3.983_160_4, 2.385_720_7, 1.603_215_3],
        ),
        "Ag" => (
            [0.155_264_65, 0.116_723_3, 0.138_380_7],
            [4.828_343_3, 3.122_246, 2.146_950_4],
        ),
        "Al" => (
            [1.657_459_9, 0.880_369, 0.521_228_7],
            [9.223_869, 6.269_523, 4.837_001],
        ),
        "Cu" => (
            [0.200_437_7, 0.924_033_4, 1.102_212],
            [3.912_948_6, 2.452_847_7, 2.142_188],
        ),
        _ => return None,
    };
    Some((Spectrum::from_rgb(eta), Spectrum::from_rgb(k)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::BsdfFlags;
    use caustica_core::Vec2;

    fn white() -> Texture {
        Texture::Constant(Spectrum::ONE)
    }

    /// Spectral mode counts the reflectance texels it must clamp (values outside [0, 1]).
    #[test]
    fn reflectance_texels_outside_the_unit_range_are_counted() {
        let image = caustica_core::image_io::Image {
            width: 3,
            height: 1,
            data: vec![[0.5, 0.5, 0.5], [1.5, 0.2, 0.1], [0.1, -0.01, 0.3]],
        };
        let tex = Texture::Image(std::sync::Arc::new(crate::texture::ImageTexture::new(
            image,
        )));
        let m = Material::Diffuse { reflectance: tex };
        assert_eq!(m.reflectance_values_outside_unit_range(), 2);
        let c = Material::Diffuse {
            reflectance: Texture::Constant(Spectrum::splat(0.5)),
        };
        assert_eq!(c.reflectance_values_outside_unit_range(), 0);
    }

    #[test]
    fn validate_rejects_bad_parameters_with_named_messages() {
        let s = Spectrum::splat(0.5);
        let cases: Vec<(Material, &str)> = vec![
            (
                Material::Dielectric {
                    ior: 0.0,
                    absorption: Spectrum::ZERO,
                    dispersion: None,
                },
                "ior",
            ),
            (
                Material::Dielectric {
                    ior: f32::NAN,
                    absorption: Spectrum::ZERO,
                    dispersion: None,
                },
                "ior",
            ),
            (
                Material::Dielectric {
                    ior: 1.5,
                    absorption: Spectrum::splat(-1.0),
                    dispersion: None,
                },
                "absorption",
            ),
            (
                Material::Dielectric {
                    ior: 1.5,
                    absorption: Spectrum::ZERO,
                    dispersion: Some(Dispersion::Cauchy {
                        a: 0.8,
                        b: 0.0,
                        c: 0.0,
                    }),
                },
                "dispersion gives IOR",
            ),
            (
                Material::RoughDielectric {
                    ior: -1.5,
                    alpha: 0.1,
                    absorption: Spectrum::ZERO,
                    dispersion: None,
                },
                "ior",
            ),
            (
                Material::RoughDielectric {
                    ior: 1.5,
                    alpha: 0.0,
                    absorption: Spectrum::ZERO,
                    dispersion: None,
                },
                "alpha",
            ),
            (
                Material::RoughConductor {
                    eta: s,
                    k: s,
                    alpha: -0.1,
                    specular: Spectrum::ONE,
                },
                "alpha",
            ),
            (
                Material::RoughConductor {
                    eta: s,
                    k: s,
                    alpha: f32::INFINITY,
                    specular: Spectrum::ONE,
                },
                "alpha",
            ),
            (
                Material::Conductor {
                    eta: Spectrum::ZERO,
                    k: s,
                    specular: Spectrum::ONE,
                },
                "eta",
            ),
            (
                Material::Conductor {
                    eta: s,
                    k: Spectrum::splat(-1.0),
                    specular: Spectrum::ONE,
                },
                "k",
            ),
            (
                Material::Diffuse {
                    reflectance: Texture::Constant(Spectrum::new(0.5, 1.2, 0.5)),
                },
                "reflectance",
            ),
            (
                Material::Diffuse {
                    reflectance: Texture::Checkerboard {
                        a: s,
                        b: Spectrum::new(-0.1, 0.0, 0.0),
                        scale: 4.0,
                    },
                },
                "reflectance",
            ),
            (
                Material::Diffuse {
                    reflectance: Texture::Constant(Spectrum::new(f32::NAN, 0.0, 0.0)),
                },
                "reflectance",
            ),
            (
                Material::Mirror {
                    reflectance: Spectrum::splat(-0.5),
                },
                "reflectance",
            ),
            (
                Material::Phong {
                    diffuse: Texture::Constant(s),
                    specular: s,
                    exponent: -1.0,
                },
                "exponent",
            ),
            (
                Material::Phong {
                    diffuse: Texture::Constant(Spectrum::splat(0.6)),
                    specular: s,
                    exponent: 10.0,
                },
                "diffuse + specular",
            ),
        ];
        for (m, needle) in cases {
            let e = m.validate().expect_err(&format!("{m:?} accepted"));
            assert!(e.contains(needle), "{e:?} should mention {needle}");
        }
        let ok = [
            Material::Diffuse {
                reflectance: white(),
            },
            Material::Dielectric {
                ior: 1.5,
                absorption: Spectrum::new(0.1, 0.0, 2.0),
                dispersion: None,
            },
            Material::RoughDielectric {
                ior: 1.0 / 1.5,
                alpha: 0.2,
                absorption: Spectrum::ZERO,
                dispersion: None,
            },
            Material::Phong {
                diffuse: Texture::Constant(s),
                specular: s,
                exponent: 0.0,
            },
        ];
        for m in ok {
            assert!(m.validate().is_ok(), "{m:?}");
        }
        let (eta, k) = conductor_preset("Cu").unwrap();
        assert!(
            Material::RoughConductor {
                eta,
                k,
                alpha: 0.3,
                specular: Spectrum::ONE
            }
            .validate()
            .is_ok()
        );
    }

    #[test]
    fn presets_are_known_metals_only() {
        for n in ["Au", "Ag", "Al", "Cu"] {
            let (eta, k) = conductor_preset(n).unwrap();
            assert!(eta.min_component() > 0.0 && k.min_component() > 1.0, "{n}");
        }
        assert!(conductor_preset("Unobtainium").is_none());
        assert!(conductor_preset("au").is_none());
        // Gold is yellow: reflects red more than blue at normal incidence.
        let (eta, k) = conductor_preset("Au").unwrap();
        let f = crate::bsdf::fresnel::fresnel_conductor(1.0, eta, k);
        assert!(f[0] > 0.9 && f[2] < 0.5, "{f:?}");
    }

    #[test]
    fn bsdf_evaluates_textures_and_picks_models() {
        let mut si = crate::intersection::SurfaceInteraction {
            p: caustica_core::Vec3::ZERO,
            t: 1.0,
            ng: caustica_core::Vec3::Z,
            ns: caustica_core::Vec3::Z,
            uv: Vec2::new(0.1, 0.1),
            bary: Vec2::ZERO,
            dpdu: caustica_core::Vec3::X,
            dpdv: caustica_core::Vec3::Y,
            shape: 0,
            prim: 0,
            material: 0,
            light: crate::intersection::NONE,
            medium_inside: crate::intersection::NONE,
            medium_outside: crate::intersection::NONE,
            time: 0.0,
        };
        let a = Spectrum::new(0.2, 0.3, 0.4);
        let b = Spectrum::new(0.9, 0.8, 0.7);
        let m = Material::Diffuse {
            reflectance: Texture::Checkerboard { a, b, scale: 2.0 },
        };
        match m.bsdf(&si, &mut Channels::Rgb) {
            Bsdf::Lambertian(l) => assert_eq!(l.albedo, a),
            other => panic!("{other:?}"),
        }
        si.uv = Vec2::new(0.6, 0.1);
        match m.bsdf(&si, &mut Channels::Rgb) {
            Bsdf::Lambertian(l) => assert_eq!(l.albedo, b),
            other => panic!("{other:?}"),
        }
        let rd = Material::RoughDielectric {
            ior: 1.5,
            alpha: 0.3,
            absorption: Spectrum::ZERO,
            dispersion: None,
        };
        assert!(matches!(
            rd.bsdf(&si, &mut Channels::Rgb),
            Bsdf::RoughDielectric(_)
        ));
        let rd0 = Material::RoughDielectric {
            ior: 1.5,
            alpha: 1e-5,
            absorption: Spectrum::ZERO,
            dispersion: None,
        };
        assert!(rd0.bsdf(&si, &mut Channels::Rgb).flags().is_delta());
        let (eta, k) = conductor_preset("Ag").unwrap();
        let rc = Material::RoughConductor {
            eta,
            k,
            alpha: 0.2,
            specular: Spectrum::ONE,
        };
        assert!(
            rc.bsdf(&si, &mut Channels::Rgb)
                .flags()
                .contains(BsdfFlags::GLOSSY)
        );
    }
}
