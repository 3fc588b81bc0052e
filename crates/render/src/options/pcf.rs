//! Settings of photon cone focusing (`pcf`, seed 001 ch. 3–4): the parameters of its Table 4.1
//! (M, S, σ₁, θ₁, α, p) and those the seed leaves unstated (spec notes sec. 2.11): the cone
//! techniques and MIS, the camera-NEE exponent, the conical importons, the lookup rule and
//! nested PCF. The light paths per iteration (M, read as light paths: spec notes Q3) and the
//! camera samples per iteration (S) are the progressive settings'
//! ([`super::ProgressiveSettings`]).

use crate::error::OptionError;
use caustica_scene::Scene;
use caustica_scene::material::Material;

/// Which cone-direction samplers make cones at a non-delta light vertex (seed 001 sec. 4.2).
/// Each enabled technique draws one direction per vertex (multi-sample MIS, spec notes Q6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ConeTechniques {
    /// The BSDF's own sampler given the incident direction (sec. 4.2.1; eq. 4.1–4.2 for
    /// Blinn–Phong).
    pub bsdf: bool,
    /// Camera next-event: a Blinn–Phong lobe around the direction to the camera (sec. 4.2.2).
    pub camera: bool,
    /// Conical importons traced from the camera before the loop (sec. 4.2.3).
    pub importons: bool,
    /// Uniform directions over the sphere: "no guiding" of Fig. 4.2 (spec notes Q22), for
    /// ablations.
    pub uniform: bool,
}

impl ConeTechniques {
    /// The triplet, seed 001's "main sampling strategy" (sec. 4.3).
    pub const TRIPLET: ConeTechniques = ConeTechniques {
        bsdf: true,
        camera: true,
        importons: true,
        uniform: false,
    };

    /// The BSDF's own sampler alone.
    pub const BSDF: ConeTechniques = ConeTechniques {
        bsdf: true,
        camera: false,
        importons: false,
        uniform: false,
    };

    /// Parses a comma-separated list of `bsdf`, `camera` (or `nee`), `importons`, `uniform`.
    pub fn parse(text: &str) -> Result<Self, OptionError> {
        let mut t = ConeTechniques {
            bsdf: false,
            camera: false,
            importons: false,
            uniform: false,
        };
        for name in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            match name {
                "bsdf" => t.bsdf = true,
                "camera" | "nee" => t.camera = true,
                "importons" | "importon" => t.importons = true,
                "uniform" => t.uniform = true,
                _ => {
                    return Err(OptionError::Unparsable {
                        what: "--cone-techniques",
                        rule: "a comma-separated list of bsdf, camera, importons, uniform",
                        got: text.into(),
                    });
                }
            }
        }
        Ok(t)
    }

    /// The names of the enabled techniques, comma-separated.
    pub fn names(&self) -> String {
        let mut v = Vec::new();
        for (on, n) in [
            (self.bsdf, "bsdf"),
            (self.camera, "camera"),
            (self.importons, "importons"),
            (self.uniform, "uniform"),
        ] {
            if on {
                v.push(n);
            }
        }
        v.join(",")
    }

    /// Number of enabled techniques.
    pub fn count(&self) -> usize {
        [self.bsdf, self.camera, self.importons, self.uniform]
            .iter()
            .filter(|&&b| b)
            .count()
    }
}

/// At which camera vertex the cone map is looked up (seed 001 Alg. 1 line 13: "a suitable
/// point"). Every rule depends only on the camera-path prefix, which keeps the split of
/// eq. 3.14 exact (spec notes sec. 2.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LookupRule {
    /// The first hit, whatever its surface: "directly visualize the photon cone map".
    First,
    /// The first vertex whose BSDF is not delta: path tracing through mirrors and glass.
    NonDelta,
    /// The first vertex with a diffuse lobe: path tracing through delta and glossy surfaces
    /// (sec. 4.2.3's shiny surfaces).
    Diffuse,
    /// Vertex `n` (1 = the first hit); a path that ends before it is path-traced only.
    Bounce(u32),
}

impl LookupRule {
    pub fn parse(text: &str) -> Result<Self, OptionError> {
        let bad = || OptionError::Unparsable {
            what: "--cone-lookup",
            rule: "first, non-delta, diffuse or bounce:N (N >= 1)",
            got: text.into(),
        };
        Ok(match text {
            "first" => LookupRule::First,
            "non-delta" | "nondelta" => LookupRule::NonDelta,
            "diffuse" => LookupRule::Diffuse,
            _ => match text.strip_prefix("bounce:") {
                Some(n) => match n.parse::<u32>() {
                    Ok(n) if n >= 1 => LookupRule::Bounce(n),
                    _ => return Err(bad()),
                },
                None => return Err(bad()),
            },
        })
    }

    pub fn name(&self) -> String {
        match self {
            LookupRule::First => "first".into(),
            LookupRule::NonDelta => "non-delta".into(),
            LookupRule::Diffuse => "diffuse".into(),
            LookupRule::Bounce(n) => format!("bounce:{n}"),
        }
    }
}

/// Nested PCF (seed 001 sec. 3.6): cone estimates in place of next-event estimation at the
/// camera vertices before the lookup.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Nesting {
    /// Next-event estimation and emission hits everywhere before the lookup: point lights seen
    /// through glass or in mirrors are missed (L S+ E with a delta light).
    Off,
    /// Only where path tracing cannot reach: at delta camera vertices, the direct light of
    /// delta lights (point, spot, directional, beam) from their length-1 cones, added to the
    /// emission hits of the other lights, which path tracing finds exactly. Elsewhere NEE.
    DeltaLights,
    /// The spec notes' design (sec. 2.10): at every camera vertex before the lookup, all
    /// direct light from length-1 cones instead of NEE, and emission found by the next bounce
    /// not counted. Blurs highlights and directly lit glossy surfaces by the kernel.
    All,
}

impl Nesting {
    pub fn parse(text: &str) -> Result<Self, OptionError> {
        match text {
            "off" | "none" => Ok(Nesting::Off),
            "delta-lights" | "delta" => Ok(Nesting::DeltaLights),
            "all" => Ok(Nesting::All),
            _ => Err(OptionError::Unparsable {
                what: "--nested",
                rule: "off, delta-lights or all",
                got: text.into(),
            }),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Nesting::Off => "off",
            Nesting::DeltaLights => "delta-lights",
            Nesting::All => "all",
        }
    }
}

/// Which cones within σ of a lookup count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConeSurfaces {
    /// Every cone in the ball of radius σ: seed 001's estimator (eq. 3.3 with a 3-D
    /// distance). Surfaces closer than σ leak into each other (its sec. 5.3.3, Fig. 5.14): a
    /// painting 3 cm behind a glass plate gathers the plate's cones too.
    Any,
    /// Only cones on the query's shape whose geometric normal agrees with the query's
    /// (n_j·n_x > 0; spec notes Q10's normal test, with the shape identity): no leaking between
    /// nearby surfaces or the two sides of a thin plate, at the price of the classic boundary
    /// bias where a shape ends within σ (its cut disc is still normalised by πσ²).
    Same,
}

impl ConeSurfaces {
    pub fn parse(text: &str) -> Result<Self, OptionError> {
        match text {
            "any" => Ok(ConeSurfaces::Any),
            "same" => Ok(ConeSurfaces::Same),
            _ => Err(OptionError::Unparsable {
                what: "--cone-surfaces",
                rule: "any or same",
                got: text.into(),
            }),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            ConeSurfaces::Any => "any",
            ConeSurfaces::Same => "same",
        }
    }
}

/// The direction part of the kernel at a lookup on a Lambertian surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiffuseAperture {
    /// The cap of half-angle t(σ) around the query direction, as on every other surface
    /// (seed 001's kernel).
    Cap,
    /// The whole hemisphere weighted by cos θ/π (`pcf::Aperture::Cosine`): a Lambertian
    /// surface's radiance is the same in every direction, so the cap only discards cones
    /// (seed 001 sec. 4.4's material-dependent θ₁ taken to its end; docs/pcf.md).
    Cosine,
}

impl DiffuseAperture {
    pub fn parse(text: &str) -> Result<Self, OptionError> {
        match text {
            "cap" => Ok(DiffuseAperture::Cap),
            "cosine" => Ok(DiffuseAperture::Cosine),
            _ => Err(OptionError::Unparsable {
                what: "--cone-diffuse",
                rule: "cap or cosine",
                got: text.into(),
            }),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            DiffuseAperture::Cap => "cap",
            DiffuseAperture::Cosine => "cosine",
        }
    }
}

/// Settings of `pcf`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PcfSettings {
    /// σ₁, the first iteration's spatial bandwidth in metres (`--cone-radius`); `None`: 1.5 % of
    /// the scene's bounding-box diagonal (0.05 m in a 2 m box; seed 001 sec. 4.1.2 says ≈ 0.1 in
    /// units it does not give; measured in docs/pcf.md).
    pub sigma1: Option<f32>,
    /// θ₁, the first iteration's angular bandwidth in degrees, a cap half-angle in (0, 180]
    /// (`--cone-angle`, default 18°, seed 001 sec. 4.1.2; above 60° "not recommended").
    pub theta1_deg: f32,
    /// p ≥ 1, the order of t(σ) = θ₁ (σ/σ₁)^p (`--cone-order`, default 1; spec notes Q1).
    pub order: f64,
    /// α of eq. 3.27 in (0, 1) (`--ppm-alpha`); `None`: 0.5, the α = 2/(p + 3) that balances
    /// variance N^−α against squared bias N^{2(α−1)/(p+1)} at p = 1 (spec notes sec. 2.5).
    pub alpha: Option<f64>,
    /// The cone techniques (`--cone-techniques`); `None`: [`PcfSettings::techniques_for`]
    /// chooses from the scene.
    pub techniques: Option<ConeTechniques>,
    /// Power-heuristic MIS (β = 2, eq. 4.4) between the techniques; off: every technique's
    /// cone at full weight (biased ×(number of techniques); an ablation, T-15).
    pub mis: bool,
    /// Camera-NEE Blinn–Phong exponent; `None`: per iteration, the n that puts half the lobe's
    /// mass inside the current cap, cos^{n+1} t = 1/2 (spec notes Q8).
    pub camera_exponent: Option<f32>,
    /// Fold camera-NEE directions that fall below the surface of a reflection-only BSDF into
    /// the upper side (sec. 4.2.2's mirroring, read as a reflection in the tangent plane with
    /// the folded density, spec notes Q8).
    pub camera_mirror: bool,
    /// Camera paths traced for the importon map (`--importons`); `None`: the light paths of
    /// one iteration.
    pub importon_paths: Option<u64>,
    /// Importons the mixture of a light vertex draws from (its nearest neighbours).
    pub importon_k: usize,
    /// The importons' spatial search radius (m); `None`: σ₁.
    pub importon_radius: Option<f32>,
    /// The importons' cap half-angle (degrees); `None`: θ₁ (fixed: seed 001 does not adapt it).
    pub importon_angle_deg: Option<f32>,
    /// Where the cone map is looked up (`--cone-lookup`).
    pub lookup: LookupRule,
    /// Nested PCF (sec. 3.6; `--nested`, default `delta-lights`).
    pub nested: Nesting,
    /// Which cones within σ count (`--cone-surfaces`, default `same`).
    pub surfaces: ConeSurfaces,
    /// Direct light at a non-delta lookup vertex from next-event estimation and the rest from
    /// cones of light-path length ≥ 2 (`--lookup-direct nee`, default, as photon mapping and
    /// SPPM do: sharp shadows and no kernel blur of direct light), or all from cones
    /// (`cones`: seed 001's Alg. 1 read literally).
    pub lookup_nee: bool,
    /// The direction kernel at lookups on Lambertian surfaces (`--cone-diffuse`, default
    /// `cosine`).
    pub diffuse_aperture: DiffuseAperture,
}

impl Default for PcfSettings {
    fn default() -> Self {
        Self {
            sigma1: None,
            theta1_deg: 18.0,
            order: 1.0,
            alpha: None,
            techniques: None,
            mis: true,
            camera_exponent: None,
            camera_mirror: true,
            importon_paths: None,
            importon_k: 8,
            importon_radius: None,
            importon_angle_deg: None,
            lookup: LookupRule::NonDelta,
            nested: Nesting::DeltaLights,
            surfaces: ConeSurfaces::Same,
            lookup_nee: true,
            diffuse_aperture: DiffuseAperture::Cosine,
        }
    }
}

/// The default α of `pcf`.
pub const DEFAULT_PCF_ALPHA: f64 = 0.5;

impl PcfSettings {
    /// α of the schedule.
    pub fn alpha(&self) -> f64 {
        self.alpha.unwrap_or(DEFAULT_PCF_ALPHA)
    }

    /// The cone techniques of a render of `scene`: the ones given, else the BSDF's sampler
    /// alone where every lookup is on a Lambertian surface with the cosine aperture or on a
    /// delta surface, else seed 001's triplet (sec. 4.3).
    ///
    /// Camera NEE and importons aim cones at the directions a lookup's cap will ask for; a
    /// cosine aperture asks for every direction and weights them by cos θ/π, which the BSDF's
    /// cosine-weighted sampler matches exactly (each cone then adds β ρ/π, photon mapping's
    /// value), and delta surfaces have their cone in the delta direction whatever the
    /// techniques. So in a scene without glossy materials the other two only add cones of
    /// small MIS weight: on `mirror-caustic-box`, both with the cosine aperture, the BSDF alone
    /// runs 2.9× the triplet's iterations in the same time at a lower error (docs/pcf.md,
    /// "Lambertian lookups").
    pub fn techniques_for(&self, scene: &Scene) -> ConeTechniques {
        if let Some(t) = self.techniques {
            return t;
        }
        let glossy = |m: &Material| {
            !matches!(m, Material::Diffuse { .. } | Material::Null) && !m.can_be_delta()
        };
        if self.diffuse_aperture == DiffuseAperture::Cosine && !scene.materials.iter().any(glossy) {
            ConeTechniques::BSDF
        } else {
            ConeTechniques::TRIPLET
        }
    }

    /// Checks the values (the "bad input"); the message names the option.
    pub fn validate(&self) -> Result<(), OptionError> {
        let a = self.alpha();
        if !(a > 0.0 && a < 1.0) {
            return Err(OptionError::Invalid {
                what: "--ppm-alpha of pcf",
                rule: "a number in (0, 1) (seed 001 sec. 3.5.3: at 0 the variance never vanishes, at 1 the bias never does)",
                got: a.to_string(),
            });
        }
        if !(self.order.is_finite() && self.order >= 1.0) {
            return Err(OptionError::Invalid {
                what: "--cone-order (p)",
                rule: "a number >= 1 (seed 001 Lemma 3.3: t(sigma) a polynomial of order p >= 1)",
                got: self.order.to_string(),
            });
        }
        if !(self.theta1_deg > 0.0 && self.theta1_deg <= 180.0) {
            return Err(OptionError::Invalid {
                what: "--cone-angle (theta_1)",
                rule: "a cap half-angle in degrees in (0, 180]",
                got: self.theta1_deg.to_string(),
            });
        }
        if let Some(s) = self.sigma1
            && !(s.is_finite() && s > 0.0)
        {
            return Err(OptionError::Invalid {
                what: "--cone-radius (sigma_1)",
                rule: "a finite length > 0 in metres",
                got: s.to_string(),
            });
        }
        if let Some(s) = self.importon_radius
            && !(s.is_finite() && s > 0.0)
        {
            return Err(OptionError::Invalid {
                what: "--importon-radius",
                rule: "a finite length > 0 in metres",
                got: s.to_string(),
            });
        }
        if let Some(t) = self.importon_angle_deg
            && !(t > 0.0 && t <= 180.0)
        {
            return Err(OptionError::Invalid {
                what: "--importon-angle",
                rule: "a cap half-angle in degrees in (0, 180]",
                got: t.to_string(),
            });
        }
        if let Some(n) = self.camera_exponent
            && !(n.is_finite() && n >= 0.0)
        {
            return Err(OptionError::Invalid {
                what: "--camera-exponent",
                rule: "a finite number >= 0",
                got: n.to_string(),
            });
        }
        if self.importon_k == 0 {
            return Err(OptionError::Invalid {
                what: "--importon-k",
                rule: "at least 1",
                got: "0".into(),
            });
        }
        if self.importon_paths == Some(0) {
            return Err(OptionError::Invalid {
                what: "--importons",
                rule: "at least 1 camera path",
                got: "0".into(),
            });
        }
        if let Some(t) = self.techniques
            && !t.bsdf
            && !t.uniform
        {
            return Err(OptionError::Conflict(format!(
                "--cone-techniques {} leaves directions where the BSDF is non-zero unsampled (camera NEE and importons cover only lobes around the camera and the importons): include bsdf or uniform",
                if t.count() == 0 {
                    "(none)".to_string()
                } else {
                    t.names()
                }
            )));
        }
        Ok(())
    }

    /// Warnings about values that are valid but unwise.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        if self.theta1_deg > 60.0 {
            w.push(format!(
                "--cone-angle {}° is above 60°, which seed 001 (sec. 4.1.2) does not recommend: highlights blur and convergence needs many iterations",
                self.theta1_deg
            ));
        }
        w
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_values_are_refused_with_the_option_named() {
        let ok = PcfSettings::default();
        assert!(ok.validate().is_ok());
        let cases: Vec<(PcfSettings, &str)> = vec![
            (
                PcfSettings {
                    alpha: Some(1.0),
                    ..ok
                },
                "alpha",
            ),
            (
                PcfSettings {
                    alpha: Some(0.0),
                    ..ok
                },
                "alpha",
            ),
            (PcfSettings { order: 0.5, ..ok }, "cone-order"),
            (
                PcfSettings {
                    theta1_deg: 0.0,
                    ..ok
                },
                "cone-angle",
            ),
            (
                PcfSettings {
                    theta1_deg: 181.0,
                    ..ok
                },
                "cone-angle",
            ),
            (
                PcfSettings {
                    sigma1: Some(0.0),
                    ..ok
                },
                "cone-radius",
            ),
            (
                PcfSettings {
                    techniques: Some(ConeTechniques::parse("camera,importons").unwrap()),
                    ..ok
                },
                "unsampled",
            ),
        ];
        for (s, name) in cases {
            let e = s.validate().unwrap_err().to_string();
            assert!(e.contains(name), "{e}");
        }
        assert!(
            PcfSettings {
                theta1_deg: 90.0,
                ..ok
            }
            .warnings()[0]
                .contains("60")
        );
    }

    #[test]
    fn parsing() {
        assert_eq!(
            ConeTechniques::parse("bsdf,nee").unwrap(),
            ConeTechniques {
                bsdf: true,
                camera: true,
                importons: false,
                uniform: false
            }
        );
        assert!(ConeTechniques::parse("bsdf,foo").is_err());
        assert_eq!(
            LookupRule::parse("bounce:3").unwrap(),
            LookupRule::Bounce(3)
        );
        assert!(LookupRule::parse("bounce:0").is_err());
        assert!(LookupRule::parse("x").is_err());
        for a in [DiffuseAperture::Cap, DiffuseAperture::Cosine] {
            assert_eq!(DiffuseAperture::parse(a.name()).unwrap(), a);
        }
        assert!(DiffuseAperture::parse("hemisphere").is_err());
        for r in [
            LookupRule::First,
            LookupRule::NonDelta,
            LookupRule::Diffuse,
            LookupRule::Bounce(2),
        ] {
            assert_eq!(LookupRule::parse(&r.name()).unwrap(), r);
        }
    }
}
