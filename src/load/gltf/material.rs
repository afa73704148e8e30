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

use glam::{Vec3, Vec4};
use gltf::json::material::AlphaMode as JsonAlpha;
use gltf::json::texture::{MagFilter, MinFilter, WrappingMode};
use gltf::json::validation::Checked;

use super::{uri, Builder};
use crate::load::progress::Stage;
use crate::load::{images, LoadError};
use crate::scene::{AlphaMode, Material, TextureRef};
use crate::texture::{Filter, Sampler, Texture, Wrap};

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
    pub fn material(&mut self, i: usize, from: &str) -> Result<Option<usize>, LoadError> {
        if let Some(&cached) = self.materials.get(&i) {
            return Ok(cached);
        }
        let Some(m) = self.doc.json.materials.get(i) else {
            let count = self.doc.json.materials.len();
            self.scene.report.warnings.push(format!(
                "{from}: material {i} does not exist (there are {count}); default used"
            ));
            self.materials.insert(i, None);
            return Ok(None);
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
        let unused = [
            (m.normal_texture.is_some(), "normal"),
            (m.occlusion_texture.is_some(), "occlusion"),
            (m.emissive_texture.is_some(), "emissive"),
            (
                pbr.metallic_roughness_texture.is_some(),
                "metallic-roughness",
            ),
        ];
        let unused: Vec<&str> = unused
            .iter()
            .filter(|(present, _)| *present)
            .map(|(_, what)| *what)
            .collect();
        if !unused.is_empty() {
            self.scene.report.skipped.push(format!(
                "material '{name}': {} texture(s) not used",
                unused.join(", ")
            ));
        }
        let texture_info = pbr
            .base_color_texture
            .as_ref()
            .map(|t| (t.index.value(), t.tex_coord));
        let double_sided = m.double_sided;
        let textured = pbr.metallic_roughness_texture.is_some();
        let base_color_texture = match texture_info {
            Some((t, tex_coord)) => {
                if tex_coord != 0 {
                    self.scene.report.warnings.push(format!(
                        "material '{name}': base colour texture uses TEXCOORD_{tex_coord}; meshes carry only TEXCOORD_0"
                    ));
                }
                self.texture(t, &name)?
                    .map(|texture| TextureRef { texture, tex_coord })
            }
            None => None,
        };
        let d = Material::default();
        // The metallic-roughness texture is not read, so with one the factors are only an
        // upper bound: the material is then taken as a dielectric (diffuse kept), rather
        // than blackening e.g. a helmet whose texture marks a few parts as metal.
        let (diffuse, specular, shininess) = phong_from_pbr(
            base.truncate(),
            if textured { 0.0 } else { metallic },
            roughness,
        );
        self.scene.materials.push(Material {
            name,
            base_color: diffuse.extend(base.w),
            base_color_texture,
            ambient: d.ambient,
            specular,
            specular_texture: None,
            shininess,
            emissive,
            metallic,
            roughness,
            alpha_mode,
            double_sided,
        });
        let index = Some(self.scene.materials.len() - 1);
        self.materials.insert(i, index);
        Ok(index)
    }

    /// The scene texture for glTF texture `t` (of material `material`), or `None` with a
    /// warning.
    fn texture(&mut self, t: usize, material: &str) -> Result<Option<usize>, LoadError> {
        let Some(tex) = self.doc.json.textures.get(t) else {
            self.scene
                .report
                .warnings
                .push(format!("material '{material}': texture {t} does not exist"));
            return Ok(None);
        };
        let key = (tex.source.value(), tex.sampler.map(|s| s.value()));
        if let Some(&cached) = self.textures.get(&key) {
            return Ok(cached);
        }
        let sampler = self.sampler(key.1);
        let index = match self.image(key.0, material)? {
            None => None,
            Some(decoded) => {
                let texture = if decoded.sampler == sampler {
                    decoded
                } else {
                    let bytes = decoded.texels.len() as u64 * 4;
                    self.doc.budget.charge(bytes, || {
                        format!("texture {t} (a copy of image {} for its sampler)", key.0)
                    })?;
                    let mut copy = (*decoded).clone();
                    copy.sampler = sampler;
                    Arc::new(copy)
                };
                self.scene.textures.push(texture);
                Some(self.scene.textures.len() - 1)
            }
        };
        self.textures.insert(key, index);
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

    /// glTF image `i`, decoded on first use (`None`: unusable, warned about once).
    fn image(&mut self, i: usize, material: &str) -> Result<Option<Arc<Texture>>, LoadError> {
        if let Some(cached) = self.images.get(&i) {
            return Ok(cached.clone());
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
                let decoded = bytes.map(|b| images::decode(&b, &name, doc.budget));
                doc.tracker.label(Stage::Geometry)?;
                match decoded {
                    Ok(Ok(t)) => Ok(Arc::new(t)),
                    Ok(Err(images::DecodeError::Budget(e))) => return Err(e),
                    Ok(Err(images::DecodeError::Invalid(reason))) | Err(reason) => Err(reason),
                }
            }
        };
        let decoded = match result {
            Ok(t) => Some(t),
            Err(reason) => {
                self.scene.report.warnings.push(format!(
                    "image {i}: {reason}; material '{material}' drawn without it"
                ));
                None
            }
        };
        self.images.insert(i, decoded.clone());
        Ok(decoded)
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
