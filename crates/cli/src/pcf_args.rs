//! Options of photon cone focusing (`--integrator pcf`), flattened into the photon options.

use anyhow::Result;
use caustica_render::options::{
    ConeSurfaces, ConeTechniques, DiffuseAperture, LookupRule, Nesting, PcfSettings,
};
use clap::Args;

const HEADING: &str = "Photon cone focusing (pcf)";

#[derive(Args, Debug, Clone, Default)]
pub struct PcfArgs {
    /// sigma_1, the first iteration's spatial bandwidth in metres (default 1.5 % of the scene's
    /// bounding-box diagonal, about 0.05 m in the Cornell box).
    #[arg(long, value_name = "M", allow_negative_numbers = true, help_heading = HEADING)]
    pub cone_radius: Option<f32>,
    /// theta_1, the first iteration's angular bandwidth (cap half-angle, degrees; default 18,
    /// above 60 not recommended).
    #[arg(long, value_name = "DEG", allow_negative_numbers = true, help_heading = HEADING)]
    pub cone_angle: Option<f32>,
    /// p >= 1, the order of t(sigma) = theta_1 (sigma/sigma_1)^p (default 1).
    #[arg(long, value_name = "P", allow_negative_numbers = true, help_heading = HEADING)]
    pub cone_order: Option<f64>,
    /// Cone-direction techniques, comma-separated: bsdf, camera, importons, uniform (default:
    /// bsdf alone in scenes without glossy materials when Lambertian lookups are cosine,
    /// bsdf,camera,importons otherwise).
    #[arg(long, value_name = "LIST", help_heading = HEADING)]
    pub cone_techniques: Option<String>,
    /// Store every technique's cone at full weight instead of the power heuristic (an
    /// ablation: biased by the number of techniques).
    #[arg(long, help_heading = HEADING)]
    pub no_mis: bool,
    /// Camera-NEE Blinn-Phong exponent (default: half the lobe inside the current cap).
    #[arg(long, value_name = "N", allow_negative_numbers = true, help_heading = HEADING)]
    pub camera_exponent: Option<f32>,
    /// Do not fold camera-NEE directions below an opaque surface into its upper side.
    #[arg(long, help_heading = HEADING)]
    pub no_camera_mirror: bool,
    /// Camera paths traced for the importon map (default: the light paths of one iteration).
    #[arg(long, value_name = "N", allow_negative_numbers = true, help_heading = HEADING)]
    pub importons: Option<u64>,
    /// Nearest importons a light vertex draws from (default 8).
    #[arg(long, value_name = "K", allow_negative_numbers = true, help_heading = HEADING)]
    pub importon_k: Option<usize>,
    /// The importons' search radius in metres (default sigma_1).
    #[arg(long, value_name = "M", allow_negative_numbers = true, help_heading = HEADING)]
    pub importon_radius: Option<f32>,
    /// The importons' cap half-angle in degrees (default theta_1).
    #[arg(long, value_name = "DEG", allow_negative_numbers = true, help_heading = HEADING)]
    pub importon_angle: Option<f32>,
    /// Where camera paths look up the cone map: first (the first hit), non-delta (through
    /// mirrors and glass; default), diffuse (through glossy surfaces too), bounce:N.
    #[arg(long, value_name = "RULE", help_heading = HEADING)]
    pub cone_lookup: Option<String>,
    /// Which cones within sigma count: same (the lookup's shape, normals agreeing; default)
    /// or any (every cone in the ball: seed 001's estimator, which leaks between surfaces
    /// closer than sigma).
    #[arg(long, value_name = "any|same", help_heading = HEADING)]
    pub cone_surfaces: Option<String>,
    /// The direction kernel at lookups on Lambertian surfaces: cosine (default: the whole
    /// hemisphere weighted by cos/pi, exact there since their radiance is the same in every
    /// direction) or cap (seed 001's cap around the viewing direction, as elsewhere).
    #[arg(long, value_name = "cosine|cap", help_heading = HEADING)]
    pub cone_diffuse: Option<String>,
    /// Direct light at a non-delta lookup vertex: nee (default: next-event estimation, the
    /// cones of longer light paths for the rest, as photon mapping does) or cones (all light
    /// from the cone map, seed 001's Alg. 1 read literally).
    #[arg(long, value_name = "nee|cones", help_heading = HEADING)]
    pub lookup_direct: Option<String>,
    /// Nested PCF at the camera vertices before the lookup: delta-lights (default: at glass
    /// and mirrors, the direct light of point, spot and directional lights from their
    /// length-1 cones, which path tracing cannot find), all (all direct light from length-1
    /// cones instead of NEE, the spec notes' design) or off.
    #[arg(long, value_name = "off|delta-lights|all", help_heading = HEADING)]
    pub nested: Option<String>,
}

impl PcfArgs {
    /// Writes the given values into `s` (`alpha`: `--ppm-alpha`, shared with the progressive
    /// methods); `IntegratorKind::check` validates them when pcf runs.
    pub fn apply(&self, s: &mut PcfSettings, alpha: Option<f64>) -> Result<()> {
        if let Some(r) = self.cone_radius {
            s.sigma1 = Some(r);
        }
        if let Some(a) = self.cone_angle {
            s.theta1_deg = a;
        }
        if let Some(p) = self.cone_order {
            s.order = p;
        }
        if let Some(t) = &self.cone_techniques {
            s.techniques = Some(ConeTechniques::parse(t)?);
        }
        s.mis = !self.no_mis;
        s.camera_exponent = self.camera_exponent;
        s.camera_mirror = !self.no_camera_mirror;
        s.importon_paths = self.importons;
        if let Some(k) = self.importon_k {
            s.importon_k = k;
        }
        s.importon_radius = self.importon_radius;
        s.importon_angle_deg = self.importon_angle;
        if let Some(r) = &self.cone_lookup {
            s.lookup = LookupRule::parse(r)?;
        }
        if let Some(d) = &self.lookup_direct {
            s.lookup_nee = match d.as_str() {
                "nee" => true,
                "cones" => false,
                _ => anyhow::bail!("unknown --lookup-direct '{d}' (expected 'nee' or 'cones')"),
            };
        }
        if let Some(c) = &self.cone_surfaces {
            s.surfaces = ConeSurfaces::parse(c)?;
        }
        if let Some(a) = &self.cone_diffuse {
            s.diffuse_aperture = DiffuseAperture::parse(a)?;
        }
        if let Some(n) = &self.nested {
            s.nested = Nesting::parse(n)?;
        }
        s.alpha = alpha;
        Ok(())
    }

    /// True if any pcf option was given.
    pub fn any_given(&self) -> bool {
        self.cone_radius.is_some()
            || self.cone_angle.is_some()
            || self.cone_order.is_some()
            || self.cone_techniques.is_some()
            || self.no_mis
            || self.camera_exponent.is_some()
            || self.no_camera_mirror
            || self.importons.is_some()
            || self.importon_k.is_some()
            || self.importon_radius.is_some()
            || self.importon_angle.is_some()
            || self.cone_lookup.is_some()
            || self.cone_surfaces.is_some()
            || self.cone_diffuse.is_some()
            || self.lookup_direct.is_some()
            || self.nested.is_some()
    }
}
