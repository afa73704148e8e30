//! glTF materials (pbrMetallicRoughness core, emissive, alpha mode, double-sidedness) and
//! their base colour textures: images from a URI or a bufferView, decoded once per image;
//! every (image, sampler) pair becomes one scene texture.
//!
//! The Phong parameters are derived so that Phong shading and PBR shading of the same
//! material agree roughly ([`phong_from_pbr`]); the PBR factors are kept in the material
//! too. Broken factors (NaN, out of range) are clamped or defaulted with a warning; a
//! texture or image that cannot be used is a warning and the material is drawn without it.

use glam::{Vec3, Vec4};
use gltf::json;
use gltf::json::material::AlphaMode as JsonAlpha;
use gltf::json::validation::Checked;
use serde_json::{Map, Value};

use super::Builder;
use crate::scene::{AlphaMode, Material, PbrMaterial, Slot};
use crate::LoadError;

mod extensions;
mod textures;

pub(super) use extensions::layer_slot;
use extensions::{layer_infos, pbr_material};

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

/// A textureInfo of any slot, as the file gives it.
struct SlotInfo<'a> {
    texture: usize,
    tex_coord: u32,
    /// `normalTexture.scale` or `occlusionTexture.strength`; 1 for the others.
    scale: f32,
    /// The textureInfo's extensions.
    extensions: Option<&'a Map<String, Value>>,
}

/// `v` if finite, else `default`; then clamped to `lo..=hi`.
fn factor(v: f32, default: f32, lo: f32, hi: f32) -> f32 {
    if v.is_finite() { v } else { default }.clamp(lo, hi)
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

    /// The scene material for glTF material `i` (used by `from`), converted on first use;
    /// `None` (default material, with a warning) if it does not exist.
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
