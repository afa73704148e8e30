//! The part of a glTF document that is loaded, deserialised into the `gltf` crate's JSON
//! types, and a lenient second attempt for valid files those types reject.
//!
//! `gltf-json` 1.4 refuses some files the spec allows: integers written as `1.0`, a scene
//! without `nodes`, `extras` that are not objects. When the strict parse fails, the text is
//! parsed once more into a `serde_json::Value`, those cases are normalised (walking the
//! tree with an explicit stack), and the value is deserialised again; if that fails too,
//! the first error is reported.

use gltf::json;
use serde_json::Value;

use crate::{Budget, LoadError};

/// The part of a glTF document that is loaded (the fields of `gltf::json::Root` that are
/// used; animations and skins as plain JSON values, read leniently later).
#[derive(serde::Deserialize)]
#[serde(rename_all = "camelCase")]
pub(crate) struct Json {
    pub asset: json::Asset,
    #[serde(default)]
    pub accessors: Vec<json::Accessor>,
    #[serde(default)]
    pub buffers: Vec<json::Buffer>,
    #[serde(default)]
    pub buffer_views: Vec<json::buffer::View>,
    #[serde(default)]
    pub cameras: Vec<json::Camera>,
    #[serde(default)]
    pub images: Vec<json::Image>,
    #[serde(default)]
    pub materials: Vec<json::Material>,
    #[serde(default)]
    pub meshes: Vec<json::Mesh>,
    #[serde(default)]
    pub nodes: Vec<json::Node>,
    #[serde(default)]
    pub samplers: Vec<json::texture::Sampler>,
    pub scene: Option<json::Index<json::Scene>>,
    #[serde(default)]
    pub scenes: Vec<json::Scene>,
    #[serde(default)]
    pub textures: Vec<json::Texture>,
    #[serde(default)]
    pub extensions_used: Vec<String>,
    #[serde(default)]
    pub extensions_required: Vec<String>,
    /// The root's extensions (`KHR_materials_variants` reads its variant names here).
    #[serde(default)]
    pub extensions: Option<serde_json::Map<String, Value>>,
    /// Read one at a time by `animation`, so a malformed one is skipped, not fatal.
    #[serde(default)]
    pub animations: Vec<Value>,
    /// Read one at a time by `skin`.
    #[serde(default)]
    pub skins: Vec<Value>,
}

/// Parses the JSON chunk. The outer `Result` is a budget overrun, the inner one the parse
/// error of the strict attempt.
pub(super) fn parse(
    bytes: &[u8],
    budget: &Budget,
) -> Result<Result<Json, serde_json::Error>, LoadError> {
    // serde structures take a few times the text's size.
    budget.charge((bytes.len() as u64).saturating_mul(4), || {
        "glTF JSON".into()
    })?;
    let strict = match serde_json::from_slice::<Json>(bytes) {
        Ok(json) => return Ok(Ok(json)),
        Err(e) => e,
    };
    let Ok(mut value) = serde_json::from_slice::<Value>(bytes) else {
        return Ok(Err(strict));
    };
    budget.charge((bytes.len() as u64).saturating_mul(8), || {
        "glTF JSON (lenient second parse)".into()
    })?;
    normalise(&mut value);
    Ok(serde_json::from_value(value).map_err(|_| strict))
}

/// Integral floats become integers, `extras` are dropped, scenes get their `nodes`.
pub(super) fn normalise(root: &mut Value) {
    if let Some(scenes) = root.get_mut("scenes").and_then(Value::as_array_mut) {
        for scene in scenes.iter_mut().filter_map(Value::as_object_mut) {
            scene
                .entry("nodes")
                .or_insert_with(|| Value::Array(Vec::new()));
        }
    }
    let mut stack = vec![root];
    while let Some(v) = stack.pop() {
        match v {
            Value::Object(map) => {
                map.remove("extras");
                stack.extend(map.values_mut());
            }
            Value::Array(items) => stack.extend(items.iter_mut()),
            Value::Number(n) => {
                let f = n.as_f64().filter(|f| f.fract() == 0.0 && n.is_f64());
                if let Some(i) = f.filter(|f| f.abs() < 9.0e15).map(|f| f as i64) {
                    *n = i.into();
                }
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn lenient_parse_accepts_what_the_spec_allows() {
        let budget = Budget::new(Path::new("t"), 1 << 20);
        let text = br#"{"asset": {"version": "2.0", "extras": 42}, "scenes": [{"name": "s"}],
            "accessors": [{"componentType": 5126, "count": 3.0, "type": "VEC3"}]}"#;
        let json = parse(text, &budget).unwrap().unwrap();
        assert_eq!((json.scenes.len(), json.accessors[0].count.0), (1, 3));
        let err = parse(
            br#"{"asset": {"version": "2.0"}, "accessors": [{"count": 1.5}]}"#,
            &budget,
        )
        .unwrap();
        assert!(err.is_err());
    }
}
