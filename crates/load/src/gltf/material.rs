//! glTF materials (pbrMetallicRoughness core, emissive, alpha mode, double-sidedness) and
//! their base colour textures: images from a URI or a bufferView, decoded once per image;
//! every (image, sampler) pair becomes one scene texture.
//!
//! The Phong parameters are derived so that Phong shading and PBR shading of the same
//! material agree roughly ([`phong_from_pbr`]); the PBR factors are kept in the material
//! too. Broken factors (NaN, out of range) are clamped or defaulted with a warning; a
//! texture or image that cannot be used is a warning and the material is drawn without it.

use std::borrow::Cow;
use std::sync::Arc;

use serde::Deserialize;

use glam::{Vec2, Vec3, Vec4};
use gltf::json;
use gltf::json::material::AlphaMode as JsonAlpha;
use gltf::json::texture::{MagFilter, MinFilter, WrappingMode};
use gltf::json::validation::Checked;
use serde_json::{Map, Value};

use super::{uri, Builder};
use crate::progress::Stage;
use crate::scene::{AlphaMode, Material, PbrMaterial, Slot, TextureSlot, UvTransform};
use crate::texture::{Filter, Sampler, Texture, Wrap};
use crate::{images, LoadError};

/// A texture whose image is KTX2 with Basis Universal data (decoded by `load::ktx2`).
pub const BASISU: &str = "KHR_texture_basisu";
/// A texture whose image is WebP (decoded by `image`).
pub const WEBP: &str = "EXT_texture_webp";
/// The texture transform extension's name.
pub const TEXTURE_TRANSFORM: &str = "KHR_texture_transform";
/// The material extensions read ([`PbrMaterial`]).
pub const EMISSIVE_STRENGTH: &str = "KHR_materials_emissive_strength";
pub const UNLIT: &str = "KHR_materials_unlit";
pub const IOR: &str = "KHR_materials_ior";
pub const SPECULAR: &str = "KHR_materials_specular";
pub const CLEARCOAT: &str = "KHR_materials_clearcoat";
pub const SHEEN: &str = "KHR_materials_sheen";
pub const IRIDESCENCE: &str = "KHR_materials_iridescence";
pub const ANISOTROPY: &str = "KHR_materials_anisotropy";
pub const DIFFUSE_TRANSMISSION: &str = "KHR_materials_diffuse_transmission";
pub const TRANSMISSION: &str = "KHR_materials_transmission";
pub const VOLUME: &str = "KHR_materials_volume";
pub const DISPERSION: &str = "KHR_materials_dispersion";

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
fn pbr_material(ext: Option<&Map<String, Value>>, notes: &mut Vec<String>) -> PbrMaterial {
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
pub(super) fn layer_slot(ext: &str, key: &str) -> Option<Slot> {
    LAYER_TEXTURES
        .iter()
        .find(|(e, k, _)| *e == ext && *k == key)
        .map(|&(_, _, slot)| slot)
}

/// The textureInfos of the material extensions `ext` (a `scale` read for the normal
/// texture's); one that is not a textureInfo is named in `notes` and left out.
fn layer_infos<'a>(
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

/// A textureInfo of any slot, as the file gives it.
struct SlotInfo<'a> {
    texture: usize,
    tex_coord: u32,
    /// `normalTexture.scale` or `occlusionTexture.strength`; 1 for the others.
    scale: f32,
    /// The textureInfo's extensions.
    extensions: Option<&'a Map<String, Value>>,
}

/// `KHR_texture_transform` as the file writes it (every field optional).
#[derive(serde::Deserialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
struct TransformJson {
    #[serde(default)]
    offset: Option<[f32; 2]>,
    #[serde(default)]
    rotation: Option<f32>,
    #[serde(default)]
    scale: Option<[f32; 2]>,
    #[serde(default)]
    tex_coord: Option<u32>,
    #[serde(default)]
    extensions: Option<Value>,
    #[serde(default)]
    extras: Option<Value>,
}

/// The transform and the `texCoord` override of a `KHR_texture_transform` object.
fn parse_transform(v: &Value) -> Result<(UvTransform, Option<u32>), String> {
    let t = TransformJson::deserialize(v).map_err(|e| e.to_string())?;
    let _ = (&t.extensions, &t.extras);
    let raw = UvTransform {
        offset: Vec2::from(t.offset.unwrap_or([0.0, 0.0])),
        rotation: t.rotation.unwrap_or(0.0),
        scale: Vec2::from(t.scale.unwrap_or([1.0, 1.0])),
    };
    match raw.sanitized() {
        (t, false) => Ok(t),
        (_, true) => Err(format!("non-finite numbers in {raw:?}")),
    }
    .map(|transform| (transform, t.tex_coord))
}

/// `v` if finite, else `default`; then clamped to `lo..=hi`.
fn factor(v: f32, default: f32, lo: f32, hi: f32) -> f32 {
    if v.is_finite() { v } else { default }.clamp(lo, hi)
}

/// The [`Filter`] for a glTF sampler's `minFilter` and `magFilter` (see `Builder::sampler`).
fn sampler_filter(min: Option<Checked<MinFilter>>, mag: Option<Checked<MagFilter>>) -> Filter {
    match min {
        Some(Checked::Valid(MinFilter::Nearest | MinFilter::Linear)) => match mag {
            Some(Checked::Valid(MagFilter::Nearest)) => Filter::Nearest,
            _ => Filter::Bilinear,
        },
        // The four *_MIPMAP_* filters, no minFilter, or an invalid one.
        _ => Filter::Trilinear,
    }
}

/// Reflectance at normal incidence of a dielectric (glTF's fixed F0 = 0.04, an index of
/// refraction of 1.5).
pub const DIELECTRIC_F0: f32 = 0.04;

/// The Phong diffuse colour `K_d`, specular colour `K_s` and exponent `n` that approximate
/// glTF's metallic-roughness material of base colour `base`:
///
/// - `n = 2 / α² - 2` with `α = roughness²` (the Blinn-Phong exponent whose lobe matches a
///   GGX lobe of width α, Walter et al. 2007), clamped to 1..=2000;
/// - `F0 = mix(0.04, base, metallic)`: dielectrics reflect 4% at normal incidence, metals
///   reflect their base colour;
/// - `K_s = F0 (n + 8) / 8`, each channel at most 1: the normalised Blinn-Phong lobe
///   `(n + 8) / 8π` times π, the same factor by which this renderer's Lambert term
///   `K_d (N·L)` omits the BRDF's `1/π` — so a smooth surface gets a small bright highlight
///   and a rough one a faint broad sheen of the same energy, where a constant `K_s` would
///   wash rough plastics with a flat 20% highlight;
/// - `K_d = base (1 - metallic)`: metals have no diffuse reflection, their colour is in the
///   highlight.
///
/// The exponent is Blinn's (N·H); the Phong (R·V) mode draws a highlight about half as
/// wide for the same `n`. No Fresnel rise at grazing angles, no geometry term.
#[must_use]
pub fn phong_from_pbr(base: Vec3, metallic: f32, roughness: f32) -> (Vec3, Vec3, f32) {
    let alpha = roughness * roughness;
    let n = (2.0 / (alpha * alpha).max(1e-7) - 2.0).clamp(1.0, 2000.0);
    let f0 = Vec3::splat(DIELECTRIC_F0).lerp(base, metallic);
    let specular = (f0 * (n + 8.0) / 8.0).min(Vec3::ONE);
    (base * (1.0 - metallic), specular, n)
}

impl Builder<'_> {
    /// The scene material for glTF material `i` (used by `from`), converted on first use;
    /// `None` (default material, with a warning) if it does not exist.
    /// The specification's default material for a primitive without one (Materials: "the
    /// default material ... is white, fully metallic and fully rough" in the metallic-roughness
    /// model): added to the scene once.
    pub fn default_material(&mut self) -> usize {
        if let Some(k) = self.default_material {
            return k;
        }
        let base = Vec4::ONE;
        let (_, specular, shininess) = phong_from_pbr(base.truncate(), 1.0, 1.0);
        self.scene.materials.push(Material {
            name: "default (glTF)".into(),
            base_color: base,
            specular,
            shininess,
            metallic: 1.0,
            roughness: 1.0,
            pbr: Some(PbrMaterial::default()),
            ..Material::default()
        });
        let k = self.scene.materials.len() - 1;
        self.default_material = Some(k);
        k
    }

    pub fn material(&mut self, i: usize, from: &str) -> Result<Option<usize>, LoadError> {
        if let Some(&cached) = self.materials.get(&i) {
            return Ok(cached);
        }
        // A copy: the slots below need the builder mutably.
        let Some(m) = self.doc.json.materials.get(i).cloned() else {
            let count = self.doc.json.materials.len();
            self.scene.report.warnings.push(format!(
                "{from}: material {i} does not exist (there are {count}); default used"
            ));
            let k = self.default_material();
            self.materials.insert(i, Some(k));
            return Ok(Some(k));
        };
        let name = m.name.clone().unwrap_or_else(|| format!("material {i}"));
        let pbr = &m.pbr_metallic_roughness;
        let f = pbr.base_color_factor.0;
        let base = Vec4::from_array(f.map(|c| factor(c, 1.0, 0.0, 1.0)));
        let metallic = factor(pbr.metallic_factor.0, 1.0, 0.0, 1.0);
        let roughness = factor(pbr.roughness_factor.0, 1.0, 0.0, 1.0);
        let emissive = Vec3::from_array(m.emissive_factor.0.map(|c| factor(c, 0.0, 0.0, f32::MAX)));
        let alpha_mode = match m.alpha_mode {
            Checked::Valid(JsonAlpha::Opaque) => AlphaMode::Opaque,
            Checked::Valid(JsonAlpha::Mask) => AlphaMode::Mask(factor(
                m.alpha_cutoff.map_or(0.5, |c| c.0),
                0.5,
                0.0,
                f32::MAX,
            )),
            Checked::Valid(JsonAlpha::Blend) => AlphaMode::Blend,
            Checked::Invalid => {
                self.scene
                    .report
                    .warnings
                    .push(format!("material '{name}': unknown alphaMode, OPAQUE used"));
                AlphaMode::Opaque
            }
        };
        if f.iter().any(|c| !c.is_finite() || !(0.0..=1.0).contains(c)) {
            self.scene.report.warnings.push(format!(
                "material '{name}': baseColorFactor {f:?} clamped to 0..=1"
            ));
        }
        // Every slot is read, each with its sampler, texture coordinate set and
        // KHR_texture_transform; images are decoded once per colour space their slots need.
        fn info(t: &Option<json::texture::Info>) -> Option<SlotInfo<'_>> {
            t.as_ref().map(|t| SlotInfo {
                texture: t.index.value(),
                tex_coord: t.tex_coord,
                scale: 1.0,
                extensions: t.extensions.as_ref().map(|e| &e.others),
            })
        }
        let normal = m.normal_texture.as_ref().map(|t| SlotInfo {
            texture: t.index.value(),
            tex_coord: t.tex_coord,
            scale: t.scale,
            extensions: t.extensions.as_ref().map(|e| &e.others),
        });
        let occlusion = m.occlusion_texture.as_ref().map(|t| SlotInfo {
            texture: t.index.value(),
            tex_coord: t.tex_coord,
            scale: t.strength.0,
            extensions: t.extensions.as_ref().map(|e| &e.others),
        });
        let infos = [
            (Slot::BaseColor, info(&pbr.base_color_texture)),
            (
                Slot::MetallicRoughness,
                info(&pbr.metallic_roughness_texture),
            ),
            (Slot::Normal, normal),
            (Slot::Occlusion, occlusion),
            (Slot::Emissive, info(&m.emissive_texture)),
        ];
        let ext = m.extensions.as_ref().map(|e| &e.others);
        let mut notes = Vec::new();
        let layers = layer_infos(ext, &mut notes);
        let mut slots = Vec::with_capacity(infos.len() + layers.len());
        let infos = infos
            .into_iter()
            .filter_map(|(slot, found)| Some((slot, found?)));
        for (slot, found) in infos.chain(layers) {
            slots.push((slot, self.slot(slot, &found, &name)?));
        }
        let double_sided = m.double_sided;
        let textured = pbr.metallic_roughness_texture.is_some();
        let d = Material::default();
        // The metallic-roughness texture is not read by the Phong modes, so with one the
        // factors are only an upper bound: the material is then taken as a dielectric
        // (diffuse kept), rather than blackening e.g. a helmet whose texture marks a few
        // parts as metal.
        let (_, specular, shininess) = phong_from_pbr(
            base.truncate(),
            if textured { 0.0 } else { metallic },
            roughness,
        );
        let pbr_material = pbr_material(ext, &mut notes);
        for n in notes {
            self.scene
                .report
                .warnings
                .push(format!("material '{name}': {n}"));
        }
        let mut material = Material {
            name,
            base_color: base,
            ambient: d.ambient,
            specular,
            shininess,
            emissive,
            metallic,
            roughness,
            alpha_mode,
            double_sided,
            pbr: Some(pbr_material),
            ..Material::default()
        };
        for (slot, texture) in slots {
            *material.slot_mut(slot) = texture;
        }
        self.scene.materials.push(material);
        let index = Some(self.scene.materials.len() - 1);
        self.materials.insert(i, index);
        Ok(index)
    }

    /// The [`TextureSlot`] of `slot` in material `material` from its textureInfo `info`, or
    /// `None` (with a warning) if its texture or image cannot be used. A malformed
    /// `KHR_texture_transform` is a warning and the slot is read untransformed.
    fn slot(
        &mut self,
        slot: Slot,
        info: &SlotInfo,
        material: &str,
    ) -> Result<Option<TextureSlot>, LoadError> {
        let what = format!("material '{material}': {} texture", slot.name());
        let transform = info.extensions.and_then(|e| e.get(TEXTURE_TRANSFORM));
        let (transform, tex_coord) = match transform.map(parse_transform) {
            None => (UvTransform::IDENTITY, None),
            Some(Ok(t)) => t,
            Some(Err(e)) => {
                self.scene
                    .report
                    .warnings
                    .push(format!("{what}: {TEXTURE_TRANSFORM} ignored: {e}"));
                (UvTransform::IDENTITY, None)
            }
        };
        let uv_set = tex_coord.unwrap_or(info.tex_coord);
        if uv_set >= super::primitive::MAX_UV_SETS {
            self.scene.report.warnings.push(format!(
                "{what} reads TEXCOORD_{uv_set}: only TEXCOORD_0 to TEXCOORD_{} are read; \
                 drawn without it",
                super::primitive::MAX_UV_SETS - 1
            ));
            return Ok(None);
        }
        let scale = if info.scale.is_finite() {
            info.scale
        } else {
            self.scene
                .report
                .warnings
                .push(format!("{what}: scale {} replaced by 1", info.scale));
            1.0
        };
        let Some(tex) = self.doc.json.textures.get(info.texture) else {
            self.scene
                .report
                .warnings
                .push(format!("{what}: texture {} does not exist", info.texture));
            return Ok(None);
        };
        let sampler = tex.sampler.map(|s| s.value());
        // KHR_texture_basisu and EXT_texture_webp name their image in the texture's
        // extension; `source`, if present, is then a fallback for viewers without them.
        let others = tex.extensions.as_ref().map(|e| &e.others);
        let compressed = [BASISU, WEBP]
            .into_iter()
            .find_map(|name| others.and_then(|o| o.get(name)).map(|v| (name, v)));
        let source = match compressed {
            None => tex.source.value(),
            Some((name, v)) => match v.get("source").and_then(Value::as_u64) {
                Some(i) => usize::try_from(i).unwrap_or(usize::MAX),
                None => {
                    self.scene.report.warnings.push(format!(
                        "{what}: texture {}: {name} has no valid source",
                        info.texture
                    ));
                    return Ok(None);
                }
            },
        };
        let sampler = self.sampler(sampler);
        let Some(texture) = self.texture(source, slot.srgb(), material)? else {
            return Ok(None);
        };
        Ok(Some(TextureSlot {
            texture,
            sampler,
            uv_set,
            transform,
            scale,
        }))
    }

    /// The scene texture for glTF image `image` decoded for a slot of colour space `srgb`,
    /// or `None` (warned about once) if it cannot be used.
    fn texture(
        &mut self,
        image: usize,
        srgb: bool,
        material: &str,
    ) -> Result<Option<usize>, LoadError> {
        if let Some(&cached) = self.textures.get(&(image, srgb)) {
            return Ok(cached);
        }
        let index = self.image(image, srgb, material)?.map(|t| {
            self.scene.textures.push(t);
            self.scene.textures.len() - 1
        });
        self.textures.insert((image, srgb), index);
        Ok(index)
    }

    /// glTF sampler `s` (`None`: the default, repeat with trilinear filtering).
    ///
    /// Filters: one [`Filter`] serves both minification and magnification, so the glTF
    /// pair is mapped by what matters most. A mipmapped `minFilter` (any `*_MIPMAP_*`) or
    /// none at all (glTF leaves that to the implementation; viewers mipmap) gives
    /// [`Filter::Trilinear`]; a non-mipmapped `minFilter` (NEAREST or LINEAR) keeps the
    /// base level only, nearest if `magFilter` is NEAREST, else bilinear.
    fn sampler(&mut self, s: Option<usize>) -> Sampler {
        let Some(s) = s else {
            return Sampler::default();
        };
        let Some(js) = self.doc.json.samplers.get(s) else {
            self.scene
                .report
                .warnings
                .push(format!("sampler {s} does not exist; default used"));
            return Sampler::default();
        };
        let wrap = |w: Checked<WrappingMode>| match w {
            Checked::Valid(WrappingMode::ClampToEdge) => Wrap::ClampToEdge,
            Checked::Valid(WrappingMode::MirroredRepeat) => Wrap::MirroredRepeat,
            _ => Wrap::Repeat,
        };
        let filter = sampler_filter(js.min_filter, js.mag_filter);
        Sampler {
            wrap_u: wrap(js.wrap_s),
            wrap_v: wrap(js.wrap_t),
            filter,
        }
    }

    /// glTF image `i` decoded for a slot of colour space `srgb` (`None`: unusable, warned
    /// about once). Called once per (image, colour space) through [`Builder::texture`].
    fn image(
        &mut self,
        i: usize,
        srgb: bool,
        material: &str,
    ) -> Result<Option<Arc<Texture>>, LoadError> {
        if self.failed_images.contains(&i) {
            return Ok(None);
        }
        let doc = &self.doc;
        let result = match doc.json.images.get(i) {
            None => Err(format!(
                "does not exist (there are {})",
                doc.json.images.len()
            )),
            Some(img) => {
                let name = img.name.clone().unwrap_or_else(|| match &img.uri {
                    Some(u) if !u.starts_with("data:") => u.clone(),
                    _ => format!("image {i}"),
                });
                doc.tracker.label(Stage::Textures)?;
                let bytes: Result<Cow<[u8]>, String> = match (&img.uri, img.buffer_view) {
                    (Some(u), _) => {
                        uri::load(u, &doc.root, doc.budget, &format!("image {i}"))?.map(Cow::Owned)
                    }
                    (None, Some(v)) => match doc.view(v.value(), &format!("image {i}")) {
                        Ok((b, _)) => Ok(Cow::Borrowed(b)),
                        Err(e @ (LoadError::TooLarge { .. } | LoadError::Cancelled { .. })) => {
                            return Err(e)
                        }
                        Err(e) => Err(e.to_string()),
                    },
                    (None, None) => Err("has neither a uri nor a bufferView".into()),
                };
                let decoded = bytes.map(|b| images::decode(&b, &name, doc.budget, srgb));
                doc.tracker.label(Stage::Geometry)?;
                match decoded {
                    Ok(Ok(t)) => Ok(Arc::new(t)),
                    Ok(Err(images::DecodeError::Budget(e))) => return Err(e),
                    Ok(Err(images::DecodeError::Invalid(reason))) | Err(reason) => Err(reason),
                }
            }
        };
        match result {
            Ok(t) => Ok(Some(t)),
            Err(reason) => {
                self.scene.report.warnings.push(format!(
                    "image {i}: {reason}; material '{material}' drawn without it"
                ));
                self.failed_images.insert(i);
                Ok(None)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pbr_to_phong_keeps_energy_where_it_belongs() {
        let red = Vec3::new(0.8, 0.1, 0.1);
        // Rough plastic: all diffuse, a faint sheen, the broadest lobe.
        let (kd, ks, n) = phong_from_pbr(red, 0.0, 1.0);
        assert_eq!((kd, n), (red, 1.0));
        assert!((ks - Vec3::splat(0.04 * 9.0 / 8.0)).length() < 1e-6, "{ks}");
        // Smooth plastic: same diffuse, a tight white highlight.
        let (kd, ks, n) = phong_from_pbr(red, 0.0, 0.3);
        assert_eq!(kd, red);
        assert!(
            (n - (2.0 / 0.3f32.powi(4) - 2.0)).abs() < 1e-2 && n > 200.0,
            "{n}"
        );
        assert!(ks.x == ks.y && ks.x > 0.9, "{ks}");
        // Metal: no diffuse; the highlight has the base colour (each channel at most 1).
        let gold = Vec3::new(1.0, 0.78, 0.34);
        let (kd, ks, _) = phong_from_pbr(gold, 1.0, 0.7);
        assert_eq!(kd, Vec3::ZERO);
        assert!(
            ks.x >= ks.y && ks.y > ks.z && ks.max_element() <= 1.0,
            "{ks}"
        );
        // Half metal: half the diffuse.
        let (kd, _, _) = phong_from_pbr(gold, 0.5, 0.5);
        assert_eq!(kd, gold * 0.5);
        // Roughness 0 stays finite.
        assert_eq!(phong_from_pbr(red, 0.0, 0.0).2, 2000.0);
    }
}
