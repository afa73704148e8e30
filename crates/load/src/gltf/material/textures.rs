//! A material's textures: each slot's textureInfo with its `KHR_texture_transform`, the
//! glTF samplers, and the images decoded once per colour space.

use std::borrow::Cow;
use std::sync::Arc;

use serde::Deserialize;

use glam::Vec2;
use gltf::json::texture::{MagFilter, MinFilter, WrappingMode};
use gltf::json::validation::Checked;
use serde_json::Value;

use super::{SlotInfo, BASISU, TEXTURE_TRANSFORM, WEBP};
use crate::gltf::primitive::MAX_UV_SETS;
use crate::gltf::{uri, Builder};
use crate::progress::Stage;
use crate::scene::{Slot, TextureSlot, UvTransform};
use crate::texture::{Filter, Sampler, Texture, Wrap};
use crate::{images, LoadError};

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

impl Builder<'_> {
    /// The [`TextureSlot`] of `slot` in material `material` from its textureInfo `info`, or
    /// `None` (with a warning) if its texture or image cannot be used. A malformed
    /// `KHR_texture_transform` is a warning and the slot is read untransformed.
    pub(super) fn slot(
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
        if uv_set >= MAX_UV_SETS {
            self.scene.report.warnings.push(format!(
                "{what} reads TEXCOORD_{uv_set}: only TEXCOORD_0 to TEXCOORD_{} are read; \
                 drawn without it",
                MAX_UV_SETS - 1
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
