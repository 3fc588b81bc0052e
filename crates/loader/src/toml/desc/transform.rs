//! A shape's `scale` and `rotate` fields.

use crate::toml::value::{Finite, Nums, V3, three};
use caustica_core::Vec3;
use serde::Deserialize;
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};

/// `scale = s` or `scale = [sx, sy, sz]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ScaleDesc(pub(crate) Vec3);
impl<'de> Deserialize<'de> for ScaleDesc {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = three(Nums::deserialize(d)?, true, "a scale")?;
        if v.contains(&0.0) {
            return Err(de::Error::custom(format!(
                "scale must be non-zero, got {v:?}"
            )));
        }
        Ok(ScaleDesc(Vec3::from(v)))
    }
}

#[derive(Deserialize, Clone, Copy, Debug)]
#[serde(deny_unknown_fields)]
pub(crate) struct RotateDesc {
    pub(crate) axis: V3,
    /// Degrees, counter-clockwise about `axis` (right-handed).
    pub(crate) angle: Finite,
}

/// `rotate = { axis, angle }` or an array of such tables (applied in order).
#[derive(Clone, Debug)]
pub(crate) struct RotateList(pub(crate) Vec<RotateDesc>);

impl<'de> Deserialize<'de> for RotateList {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = RotateList;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("{ axis = [x, y, z], angle = degrees } or an array of them")
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<RotateList, A::Error> {
                let r = RotateDesc::deserialize(de::value::MapAccessDeserializer::new(map))?;
                Ok(RotateList(vec![r]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<RotateList, A::Error> {
                Vec::<RotateDesc>::deserialize(de::value::SeqAccessDeserializer::new(seq))
                    .map(RotateList)
            }
        }
        d.deserialize_any(V)
    }
}
