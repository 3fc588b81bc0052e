//! `[[medium]]`: participating media and their phase functions.

use crate::toml::value::{Count, NonNeg, Rgb, V3};
use caustica_scene::phase::PhaseFunction;
use serde::Deserialize;
use serde::de::{self, Deserializer, MapAccess, Visitor};

#[derive(Deserialize, Clone, Copy, PartialEq, Debug)]
#[serde(rename_all = "lowercase")]
pub(crate) enum MediumType {
    Homogeneous,
    Grid,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MediumDesc {
    pub(crate) name: String,
    #[serde(rename = "type")]
    pub(crate) ty: MediumType,
    pub(crate) sigma_a: Option<Rgb>,
    pub(crate) sigma_s: Option<Rgb>,
    pub(crate) sigma_t: Option<Rgb>,
    pub(crate) albedo: Option<Rgb>,
    pub(crate) scale: Option<NonNeg>,
    pub(crate) phase: Option<PhaseDesc>,
    pub(crate) file: Option<String>,
    pub(crate) density: Option<String>,
    pub(crate) res: Option<[Count; 3]>,
    pub(crate) min: Option<V3>,
    pub(crate) max: Option<V3>,
}

/// `phase = "isotropic"`, `phase = { type = "isotropic" }` or `phase = { type = "hg", g = … }`
/// with g in (−1, 1), checked while deserialising.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PhaseDesc(pub(crate) PhaseFunction);

#[derive(Deserialize, Clone, Copy, PartialEq, Debug)]
#[serde(rename_all = "lowercase")]
enum PhaseType {
    Isotropic,
    Hg,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PhaseTable {
    #[serde(rename = "type")]
    ty: PhaseType,
    g: Option<f64>,
}

impl<'de> Deserialize<'de> for PhaseDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = PhaseDesc;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("\"isotropic\" or { type = \"hg\", g = mean cosine in (-1, 1) }")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<PhaseDesc, E> {
                match v {
                    "isotropic" => Ok(PhaseDesc(PhaseFunction::default())),
                    "hg" => Err(E::custom(
                        "an hg phase function needs its g: phase = { type = \"hg\", g = 0.6 }",
                    )),
                    other => Err(E::custom(format!(
                        "unknown phase function '{other}' (expected \"isotropic\" or {{ type = \"hg\", g = … }})"
                    ))),
                }
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<PhaseDesc, A::Error> {
                let t = PhaseTable::deserialize(de::value::MapAccessDeserializer::new(map))?;
                match (t.ty, t.g) {
                    (PhaseType::Isotropic, None) => Ok(PhaseDesc(PhaseFunction::default())),
                    (PhaseType::Isotropic, Some(_)) => Err(de::Error::custom(
                        "an isotropic phase function takes no 'g'",
                    )),
                    (PhaseType::Hg, None) => Err(de::Error::custom(
                        "an hg phase function needs 'g' (its mean cosine, in (-1, 1))",
                    )),
                    (PhaseType::Hg, Some(g)) => PhaseFunction::henyey_greenstein(g as f32)
                        .map(PhaseDesc)
                        .map_err(|e| de::Error::custom(format!("phase 'g': {e}"))),
                }
            }
        }
        d.deserialize_any(V)
    }
}
