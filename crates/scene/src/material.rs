//! Materials: BSDF parameters (possibly textured) attached to shapes; [`Material::bsdf`]
//! instantiates the [`Bsdf`] at a hit point.

use crate::bsdf::Bsdf;
use crate::intersection::SurfaceInteraction;
use crate::texture::Texture;
use caustica_core::Spectrum;

/// A material as described in the scene.
#[derive(Clone, Debug)]
pub enum Material {
    /// Lambertian reflector with albedo `reflectance` ∈ [0, 1].
    Diffuse { reflectance: Texture },
    /// Perfect specular reflector.
    Mirror { reflectance: Spectrum },
    /// Smooth dielectric interface; `ior` = η_inside/η_outside; `absorption` σa (m⁻¹) of the
    /// interior (Beer–Lambert), zero for clear glass.
    Dielectric { ior: f32, absorption: Spectrum },
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
    /// GGX rough dielectric.
    RoughDielectric {
        ior: f32,
        alpha: f32,
        absorption: Spectrum,
    },
    /// Normalised Blinn–Phong glossy lobe (seed 001 eq. 4.1) plus a Lambertian term.
    Phong {
        diffuse: Texture,
        specular: Spectrum,
        exponent: f32,
    },
}

impl Material {
    /// The BSDF at `si`.
    pub fn bsdf(&self, si: &SurfaceInteraction) -> Bsdf {
        let _ = si;
        todo!("Material::bsdf")
    }
    /// Interior absorption coefficient σa (m⁻¹) for dielectrics with Beer–Lambert absorption.
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
    /// Checks parameter ranges (IOR > 0, α > 0, exponent ≥ 0, finite values).
    pub fn validate(&self) -> Result<(), String> {
        todo!("Material::validate")
    }
}

/// Complex refractive index (η, κ) in RGB of a named conductor, relative to air:
/// "Au" (gold), "Ag" (silver), "Al" (aluminium), "Cu" (copper).
pub fn conductor_preset(name: &str) -> Option<(Spectrum, Spectrum)> {
    let _ = name;
    todo!("conductor_preset")
}
