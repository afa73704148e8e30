//! The `KHR_materials_*` extensions of a material: their factors ([`PbrMaterial`]) and
//! their texture slots.

use glam::Vec3;
use serde_json::{Map, Value};

use super::{
    SlotInfo, ANISOTROPY, CLEARCOAT, DIFFUSE_TRANSMISSION, DISPERSION, EMISSIVE_STRENGTH, IOR,
    IRIDESCENCE, SHEEN, SPECULAR, TRANSMISSION, UNLIT, VOLUME,
};
use crate::scene::{PbrMaterial, Slot};

/// A colour field (three non-negative finite numbers) of an extension object: `default`
/// when absent or unusable (with the problem in `notes`).
fn ext_color(obj: &Value, key: &str, default: Vec3, notes: &mut Vec<String>) -> Vec3 {
    let Some(v) = obj.get(key) else {
        return default;
    };
    serde_json::from_value::<[f32; 3]>(v.clone())
        .ok()
        .map(Vec3::from_array)
        .filter(|c| c.is_finite() && c.min_element() >= 0.0)
        .unwrap_or_else(|| {
            notes.push(format!(
                "{key} {v} is not three non-negative numbers; {:?} used",
                default.to_array()
            ));
            default
        })
}

/// A number field of an extension object: `default` when absent; `None` (with the problem
/// in `notes`) when present but not a finite number in `lo..=hi`.
fn ext_number(
    obj: &Value,
    key: &str,
    default: f32,
    lo: f32,
    hi: f32,
    notes: &mut Vec<String>,
) -> f32 {
    match obj.get(key) {
        None => default,
        Some(v) => match v.as_f64() {
            Some(x) if x.is_finite() && (f64::from(lo)..=f64::from(hi)).contains(&x) => x as f32,
            _ => {
                notes.push(format!(
                    "{key} {v} is not a number in {lo}..={hi}; {default} used"
                ));
                default
            }
        },
    }
}

/// The [`PbrMaterial`] of a material with base colour `base` and extension objects `ext`
/// (by name): the `KHR_materials_*` extensions realist reads; each other one is named
/// in `notes` as ignored, and so is a bad field (replaced by its default).
pub(super) fn pbr_material(
    ext: Option<&Map<String, Value>>,
    notes: &mut Vec<String>,
) -> PbrMaterial {
    let mut p = PbrMaterial::default();
    let Some(ext) = ext else {
        return p;
    };
    for (name, obj) in ext {
        match name.as_str() {
            EMISSIVE_STRENGTH => {
                p.emissive_strength =
                    ext_number(obj, "emissiveStrength", 1.0, 0.0, f32::MAX, notes);
            }
            UNLIT => p.unlit = true,
            IOR => {
                let ior = ext_number(obj, "ior", 1.5, 0.0, f32::MAX, notes);
                // The schema allows 0 (Fresnel 1) or at least 1.
                p.ior = if ior == 0.0 || ior >= 1.0 {
                    ior
                } else {
                    notes.push(format!("ior {ior} is neither 0 nor at least 1; 1.5 used"));
                    1.5
                };
            }
            SPECULAR => {
                p.specular = ext_number(obj, "specularFactor", 1.0, 0.0, 1.0, notes);
                let c = match obj.get("specularColorFactor") {
                    None => Some(Vec3::ONE),
                    Some(v) => serde_json::from_value::<[f32; 3]>(v.clone())
                        .ok()
                        .map(Vec3::from_array)
                        .filter(|c| c.is_finite() && c.min_element() >= 0.0),
                };
                p.specular_color = c.unwrap_or_else(|| {
                    notes.push(
                        "specularColorFactor is not three non-negative numbers; [1, 1, 1] used"
                            .into(),
                    );
                    Vec3::ONE
                });
            }
            CLEARCOAT => {
                p.clearcoat = ext_number(obj, "clearcoatFactor", 0.0, 0.0, 1.0, notes);
                p.clearcoat_roughness =
                    ext_number(obj, "clearcoatRoughnessFactor", 0.0, 0.0, 1.0, notes);
            }
            SHEEN => {
                p.sheen_color = ext_color(obj, "sheenColorFactor", Vec3::ZERO, notes);
                p.sheen_roughness = ext_number(obj, "sheenRoughnessFactor", 0.0, 0.0, 1.0, notes);
            }
            IRIDESCENCE => {
                p.iridescence = ext_number(obj, "iridescenceFactor", 0.0, 0.0, 1.0, notes);
                p.iridescence_ior = ext_number(obj, "iridescenceIor", 1.3, 1.0, f32::MAX, notes);
                let lo = ext_number(
                    obj,
                    "iridescenceThicknessMinimum",
                    100.0,
                    0.0,
                    f32::MAX,
                    notes,
                );
                let hi = ext_number(
                    obj,
                    "iridescenceThicknessMaximum",
                    400.0,
                    0.0,
                    f32::MAX,
                    notes,
                );
                p.iridescence_thickness = [lo, hi];
            }
            ANISOTROPY => {
                p.anisotropy = ext_number(obj, "anisotropyStrength", 0.0, 0.0, 1.0, notes);
                p.anisotropy_rotation =
                    ext_number(obj, "anisotropyRotation", 0.0, f32::MIN, f32::MAX, notes);
            }
            DIFFUSE_TRANSMISSION => {
                p.diffuse_transmission =
                    ext_number(obj, "diffuseTransmissionFactor", 0.0, 0.0, 1.0, notes);
                p.diffuse_transmission_color =
                    ext_color(obj, "diffuseTransmissionColorFactor", Vec3::ONE, notes);
            }
            TRANSMISSION => {
                p.transmission = ext_number(obj, "transmissionFactor", 0.0, 0.0, 1.0, notes);
            }
            VOLUME => {
                p.thickness = ext_number(obj, "thicknessFactor", 0.0, 0.0, f32::MAX, notes);
                p.attenuation_distance = match obj.get("attenuationDistance") {
                    None => f32::INFINITY,
                    Some(_) => ext_number(
                        obj,
                        "attenuationDistance",
                        f32::INFINITY,
                        f32::MIN_POSITIVE,
                        f32::MAX,
                        notes,
                    ),
                };
                p.attenuation_color = ext_color(obj, "attenuationColor", Vec3::ONE, notes);
            }
            DISPERSION => {
                p.dispersion = ext_number(obj, "dispersion", 0.0, 0.0, f32::MAX, notes);
            }
            other => notes.push(format!("material extension {other} ignored")),
        }
    }
    p
}

/// The extensions' texture slots: (extension, textureInfo key, slot).
const LAYER_TEXTURES: [(&str, &str, Slot); 14] = [
    (SPECULAR, "specularTexture", Slot::SpecularStrength),
    (SPECULAR, "specularColorTexture", Slot::SpecularColor),
    (CLEARCOAT, "clearcoatTexture", Slot::Clearcoat),
    (
        CLEARCOAT,
        "clearcoatRoughnessTexture",
        Slot::ClearcoatRoughness,
    ),
    (CLEARCOAT, "clearcoatNormalTexture", Slot::ClearcoatNormal),
    (SHEEN, "sheenColorTexture", Slot::SheenColor),
    (SHEEN, "sheenRoughnessTexture", Slot::SheenRoughness),
    (IRIDESCENCE, "iridescenceTexture", Slot::Iridescence),
    (
        IRIDESCENCE,
        "iridescenceThicknessTexture",
        Slot::IridescenceThickness,
    ),
    (ANISOTROPY, "anisotropyTexture", Slot::Anisotropy),
    (
        DIFFUSE_TRANSMISSION,
        "diffuseTransmissionTexture",
        Slot::DiffuseTransmission,
    ),
    (
        DIFFUSE_TRANSMISSION,
        "diffuseTransmissionColorTexture",
        Slot::DiffuseTransmissionColor,
    ),
    (TRANSMISSION, "transmissionTexture", Slot::Transmission),
    (VOLUME, "thicknessTexture", Slot::Thickness),
];

/// The slot of textureInfo `key` of material extension `ext`, if realist reads it.
pub(in crate::gltf) fn layer_slot(ext: &str, key: &str) -> Option<Slot> {
    LAYER_TEXTURES
        .iter()
        .find(|(e, k, _)| *e == ext && *k == key)
        .map(|&(_, _, slot)| slot)
}

/// The textureInfos of the material extensions `ext` (a `scale` read for the normal
/// texture's); one that is not a textureInfo is named in `notes` and left out.
pub(super) fn layer_infos<'a>(
    ext: Option<&'a Map<String, Value>>,
    notes: &mut Vec<String>,
) -> Vec<(Slot, SlotInfo<'a>)> {
    let mut out = Vec::new();
    let Some(ext) = ext else {
        return out;
    };
    for (name, key, slot) in LAYER_TEXTURES {
        let Some(v) = ext.get(name).and_then(|e| e.get(key)) else {
            continue;
        };
        let index = v.get("index").and_then(Value::as_u64);
        let tex_coord = v.get("texCoord").map_or(Some(0), Value::as_u64);
        let scale = v.get("scale").map_or(Some(1.0), Value::as_f64);
        match (index, tex_coord, scale) {
            (Some(index), Some(tex_coord), Some(scale)) => out.push((
                slot,
                SlotInfo {
                    texture: usize::try_from(index).unwrap_or(usize::MAX),
                    tex_coord: u32::try_from(tex_coord).unwrap_or(u32::MAX),
                    scale: scale as f32,
                    extensions: v.get("extensions").and_then(Value::as_object),
                },
            )),
            _ => notes.push(format!(
                "{name}.{key} {v} is not a textureInfo (a texture index, texCoord and scale \
                 as numbers); drawn without it"
            )),
        }
    }
    out
}
