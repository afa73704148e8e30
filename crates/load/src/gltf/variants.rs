//! `KHR_materials_variants`: the file names its variants (`extensions.KHR_materials_variants
//! .variants`, each with a `name`), and each primitive maps some of them to a material
//! (`primitive.extensions.KHR_materials_variants.mappings`: `{material, variants: [..]}`).
//! The scene keeps the names ([`crate::scene::Scene::variants`]) and each mesh its pairs
//! (variant, material) ([`crate::mesh::Mesh::variants`]); which one is drawn is a setting.
//! A mapping that names a variant or a material the file does not have is left out with a
//! warning; a variant mapped twice for one primitive keeps its first mapping (the
//! specification forbids it).

use serde_json::{Map, Value};

/// The extension's name.
pub(super) const EXTENSION: &str = "KHR_materials_variants";

/// The variant names of the file's root `extensions` (a variant without a name is called
/// "variant N"), with warnings for entries that cannot be read.
pub(super) fn names(root: Option<&Map<String, Value>>, warnings: &mut Vec<String>) -> Vec<String> {
    let Some(ext) = root.and_then(|r| r.get(EXTENSION)) else {
        return Vec::new();
    };
    let Some(list) = ext.get("variants").and_then(Value::as_array) else {
        warnings.push(format!(
            "{EXTENSION}: `variants` is not an array; no variants"
        ));
        return Vec::new();
    };
    list.iter()
        .enumerate()
        .map(|(i, v)| match v.get("name").and_then(Value::as_str) {
            Some(name) if !name.is_empty() => name.to_owned(),
            _ => format!("variant {i}"),
        })
        .collect()
}

/// The (variant, glTF material index) pairs of a primitive's `extensions` (`label` names
/// it in warnings), checked against `variants` and `materials` (the file's counts).
pub(super) fn mappings(
    extensions: Option<&Map<String, Value>>,
    variants: usize,
    materials: usize,
    label: &str,
    warnings: &mut Vec<String>,
) -> Vec<(u32, usize)> {
    let Some(ext) = extensions.and_then(|e| e.get(EXTENSION)) else {
        return Vec::new();
    };
    let Some(list) = ext.get("mappings").and_then(Value::as_array) else {
        warnings.push(format!(
            "{label}: {EXTENSION}: `mappings` is not an array; ignored"
        ));
        return Vec::new();
    };
    let index = |v: &Value| v.as_u64().and_then(|n| usize::try_from(n).ok());
    let mut out: Vec<(u32, usize)> = Vec::new();
    for (i, m) in list.iter().enumerate() {
        let Some(material) = m.get("material").and_then(index).filter(|&k| k < materials) else {
            warnings.push(format!(
                "{label}: {EXTENSION} mapping {i}: `material` is not one of the file's {materials} materials; ignored"
            ));
            continue;
        };
        let Some(vs) = m.get("variants").and_then(Value::as_array) else {
            warnings.push(format!(
                "{label}: {EXTENSION} mapping {i}: `variants` is not an array; ignored"
            ));
            continue;
        };
        for v in vs {
            match index(v).filter(|&k| k < variants) {
                Some(k) if out.iter().any(|&(w, _)| w as usize == k) => warnings.push(format!(
                    "{label}: {EXTENSION} mapping {i}: variant {k} is mapped twice; the first mapping kept"
                )),
                Some(k) => out.push((k as u32, material)),
                None => warnings.push(format!(
                    "{label}: {EXTENSION} mapping {i}: {v} is not one of the file's {variants} variants; ignored"
                )),
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(v: Value) -> Map<String, Value> {
        v.as_object().cloned().expect("an object")
    }

    #[test]
    fn names_and_mappings_are_read_and_bad_entries_named() {
        let mut w = Vec::new();
        let root = map(serde_json::json!({EXTENSION: {"variants": [{"name": "red"}, {}]}}));
        assert_eq!(names(Some(&root), &mut w), ["red", "variant 1"]);
        assert!(w.is_empty());
        let prim = map(serde_json::json!({EXTENSION: {"mappings": [
            {"material": 2, "variants": [0]},
            {"material": 1, "variants": [1, 0, 7]},
            {"material": 9, "variants": [1]},
            {"variants": [1]},
        ]}}));
        let got = mappings(Some(&prim), 2, 3, "mesh 0 primitive 0", &mut w);
        assert_eq!(got, [(0, 2), (1, 1)]);
        assert_eq!(w.len(), 4, "{w:?}");
        assert!(w[0].contains("variant 0 is mapped twice"), "{w:?}");
        assert!(
            w[1].contains("7 is not one of the file's 2 variants"),
            "{w:?}"
        );
        assert!(
            w[2].contains("mapping 2: `material` is not one of the file's 3"),
            "{w:?}"
        );
        assert!(w[3].starts_with("mesh 0 primitive 0: "), "{w:?}");
        let bad = map(serde_json::json!({EXTENSION: {"variants": 3}}));
        assert!(names(Some(&bad), &mut w).is_empty());
        assert!(names(None, &mut w).is_empty());
    }
}
