//! glTF animations into [`crate::scene::Animation`]s: every channel whose target is a node's
//! translation, rotation, scale or morph weights, or (`KHR_animation_pointer`) one of these,
//! a material's base colour, emissive, metallic, roughness or emissive strength, a light's
//! colour, intensity or cone angles, or a camera's yfov ([`pointed`]; a light or camera is
//! animated wherever a node placed it), its
//! sampler's keyframe times (`input`)
//! and values (`output`, FLOAT or normalized integers) checked by
//! [`Sampler::new`](crate::scene::anim::Sampler::new).
//!
//! A channel that cannot be used is reported (naming the animation, the channel and why)
//! and left out; the rest of the animation still plays: an unknown path, a node that does
//! not exist or is a `matrix` node, weights for a node without morph targets, times that do
//! not increase, the wrong number of values, non-finite numbers. An animation is read
//! leniently, one at a time, so a malformed one never rejects the file. Keyframe data is
//! charged to the load budget as it is read.

use super::accessor::Format;
use super::Builder;
use crate::scene::anim::{Channel, Interpolation, Property, Sampler};
use crate::scene::{Animation, Local, Slot};
use crate::LoadError;

#[derive(serde::Deserialize)]
struct AnimationJson {
    #[serde(default)]
    channels: Vec<ChannelJson>,
    #[serde(default)]
    samplers: Vec<SamplerJson>,
    name: Option<String>,
}

#[derive(serde::Deserialize)]
struct ChannelJson {
    sampler: usize,
    target: TargetJson,
}

#[derive(serde::Deserialize)]
struct TargetJson {
    node: Option<usize>,
    /// glTF 1.0 named the target `id`; some files still do (read as `node`, noted).
    id: Option<serde_json::Value>,
    path: String,
    /// `KHR_animation_pointer` (with `path: "pointer"`).
    #[serde(default)]
    extensions: Option<serde_json::Map<String, serde_json::Value>>,
}

/// `KHR_animation_pointer`: a channel whose `path` is `"pointer"` names what it animates by
/// a JSON pointer into the file.
pub(super) const POINTER: &str = "KHR_animation_pointer";

/// What a pointer names that realist animates.
#[derive(Debug, PartialEq)]
enum Pointed {
    /// A node's transform or weights (the same as the plain paths).
    Node(usize, Property),
    /// A material's factor (the file's material index).
    Material(usize, Property),
    /// A `KHR_lights_punctual` light's property (the file's light index).
    Light(usize, Property),
    /// A camera's property (the file's camera index).
    Camera(usize, Property),
}

/// Reads a `KHR_animation_pointer` pointer: `/nodes/N/translation|rotation|scale|weights`,
/// `/materials/N/pbrMetallicRoughness/baseColorFactor|metallicFactor|roughnessFactor` and
/// `/materials/N/emissiveFactor`; anything else is `Err` with the reason.
fn pointed(pointer: &str) -> Result<Pointed, String> {
    let parts: Vec<&str> = pointer.split('/').collect();
    let index = |s: &str| {
        s.parse::<usize>()
            .map_err(|_| format!("pointer '{pointer}': '{s}' is not an index"))
    };
    match parts.as_slice() {
        ["", "nodes", n, path] => {
            let property = match *path {
                "translation" => Property::Translation,
                "rotation" => Property::Rotation,
                "scale" => Property::Scale,
                "weights" => Property::Weights,
                _ => return Err(format!("pointer '{pointer}' is not supported")),
            };
            Ok(Pointed::Node(index(n)?, property))
        }
        ["", "materials", m, "pbrMetallicRoughness", field] => {
            let property = match *field {
                "baseColorFactor" => Property::BaseColor,
                "metallicFactor" => Property::Metallic,
                "roughnessFactor" => Property::Roughness,
                _ => return Err(format!("pointer '{pointer}' is not supported")),
            };
            Ok(Pointed::Material(index(m)?, property))
        }
        ["", "materials", m, "emissiveFactor"] => Ok(Pointed::Material(index(m)?, Property::Emissive)),
        ["", "materials", m, "extensions", "KHR_materials_clearcoat", field] => {
            let property = match *field {
                "clearcoatFactor" => Property::ClearcoatFactor,
                "clearcoatRoughnessFactor" => Property::ClearcoatRoughness,
                _ => return Err(format!("pointer '{pointer}' is not supported")),
            };
            Ok(Pointed::Material(index(m)?, property))
        }
        ["", "materials", m, "extensions", "KHR_materials_iridescence", field] => {
            let property = match *field {
                "iridescenceFactor" => Property::IridescenceFactor,
                "iridescenceIor" => Property::IridescenceIor,
                "iridescenceThicknessMinimum" => Property::IridescenceThicknessMin,
                "iridescenceThicknessMaximum" => Property::IridescenceThicknessMax,
                _ => return Err(format!("pointer '{pointer}' is not supported")),
            };
            Ok(Pointed::Material(index(m)?, property))
        }
        ["", "materials", m, "extensions", "KHR_materials_anisotropy", field] => {
            let property = match *field {
                "anisotropyStrength" => Property::AnisotropyStrength,
                "anisotropyRotation" => Property::AnisotropyRotation,
                _ => return Err(format!("pointer '{pointer}' is not supported")),
            };
            Ok(Pointed::Material(index(m)?, property))
        }
        ["", "materials", m, "extensions", "KHR_materials_diffuse_transmission", field] => {
            let property = match *field {
                "diffuseTransmissionFactor" => Property::DiffuseTransmission,
                "diffuseTransmissionColorFactor" => Property::DiffuseTransmissionColor,
                _ => return Err(format!("pointer '{pointer}' is not supported")),
            };
            Ok(Pointed::Material(index(m)?, property))
        }
        ["", "materials", m, "extensions", ext @ ("KHR_materials_transmission" | "KHR_materials_volume" | "KHR_materials_dispersion"), field] => {
            let property = match (*ext, *field) {
                ("KHR_materials_transmission", "transmissionFactor") => Property::TransmissionFactor,
                ("KHR_materials_volume", "thicknessFactor") => Property::ThicknessFactor,
                ("KHR_materials_volume", "attenuationDistance") => Property::AttenuationDistance,
                ("KHR_materials_volume", "attenuationColor") => Property::AttenuationColor,
                ("KHR_materials_dispersion", "dispersion") => Property::Dispersion,
                _ => return Err(format!("pointer '{pointer}' is not supported")),
            };
            Ok(Pointed::Material(index(m)?, property))
        }
        ["", "materials", m, "extensions", "KHR_materials_sheen", field] => {
            let property = match *field {
                "sheenColorFactor" => Property::SheenColor,
                "sheenRoughnessFactor" => Property::SheenRoughness,
                _ => return Err(format!("pointer '{pointer}' is not supported")),
            };
            Ok(Pointed::Material(index(m)?, property))
        }
        ["", "materials", m, path @ .., "extensions", "KHR_texture_transform", field] => {
            let slot = match path {
                ["pbrMetallicRoughness", "baseColorTexture"] => Slot::BaseColor,
                ["pbrMetallicRoughness", "metallicRoughnessTexture"] => Slot::MetallicRoughness,
                ["normalTexture"] => Slot::Normal,
                ["occlusionTexture"] => Slot::Occlusion,
                ["emissiveTexture"] => Slot::Emissive,
                ["extensions", ext, key] => super::material::layer_slot(ext, key)
                    .ok_or_else(|| format!("pointer '{pointer}' is not supported"))?,
                _ => return Err(format!("pointer '{pointer}' is not supported")),
            };
            let property = match *field {
                "offset" => Property::TexOffset(slot),
                "rotation" => Property::TexRotation(slot),
                "scale" => Property::TexScale(slot),
                _ => return Err(format!("pointer '{pointer}' is not supported")),
            };
            Ok(Pointed::Material(index(m)?, property))
        }
        ["", "materials", m, "extensions", "KHR_materials_emissive_strength", "emissiveStrength"] => {
            Ok(Pointed::Material(index(m)?, Property::EmissiveStrength))
        }
        ["", "extensions", "KHR_lights_punctual", "lights", l, rest @ ..] => {
            let property = match rest {
                ["color"] => Property::LightColor,
                ["intensity"] => Property::LightIntensity,
                ["spot", "innerConeAngle"] => Property::SpotInner,
                ["spot", "outerConeAngle"] => Property::SpotOuter,
                _ => return Err(format!("pointer '{pointer}' is not supported")),
            };
            Ok(Pointed::Light(index(l)?, property))
        }
        ["", "cameras", c, "perspective", "yfov"] => Ok(Pointed::Camera(index(c)?, Property::CameraYfov)),
        _ => Err(format!("pointer '{pointer}' is not supported (realist animates node transforms and weights, the materials' base colour, emissive, metallic, roughness, emissive strength, clear coat, sheen, iridescence, anisotropy, diffuse transmission, transmission, volume and dispersion factors and texture transforms, the lights' colour, intensity and cone angles and the cameras' yfov)")),
    }
}

#[derive(serde::Deserialize)]
struct SamplerJson {
    input: usize,
    output: usize,
    interpolation: Option<String>,
}

impl Builder<'_> {
    /// Reads the file's animations into [`crate::scene::Scene::animations`] (those with at
    /// least one usable channel).
    pub(super) fn animations(&mut self, values: &[serde_json::Value]) -> Result<(), LoadError> {
        for (i, value) in values.iter().enumerate() {
            let mut value = value.clone();
            super::schema::normalise(&mut value);
            match serde_json::from_value::<AnimationJson>(value) {
                Ok(a) => self.animation(i, a)?,
                Err(e) => self
                    .scene
                    .report
                    .warnings
                    .push(format!("animation {i} is malformed ({e}); skipped")),
            }
        }
        Ok(())
    }

    fn animation(&mut self, i: usize, a: AnimationJson) -> Result<(), LoadError> {
        let name = a.name.clone().unwrap_or_else(|| format!("animation {i}"));
        let label = format!("animation {i} ('{name}')");
        let mut out = Animation {
            name,
            samplers: Vec::new(),
            channels: Vec::new(),
        };
        // (file sampler, width) -> index in `out.samplers`.
        let mut read: Vec<((usize, usize), usize)> = Vec::new();
        for (c, ch) in a.channels.iter().enumerate() {
            let why = match self.channel(&label, c, ch, &a, &mut out, &mut read) {
                Ok(()) => continue,
                Err(Skip::Load(e)) => return Err(e),
                Err(Skip::Why(why)) => why,
            };
            self.scene
                .report
                .warnings
                .push(format!("{label} channel {c}: {why}; ignored"));
        }
        if out.channels.is_empty() {
            self.scene
                .report
                .skipped
                .push(format!("{label}: no usable channel"));
        } else {
            self.scene.animations.push(out);
        }
        Ok(())
    }

    fn channel(
        &mut self,
        label: &str,
        c: usize,
        ch: &ChannelJson,
        a: &AnimationJson,
        out: &mut Animation,
        read: &mut Vec<((usize, usize), usize)>,
    ) -> Result<(), Skip> {
        if ch.target.path == "pointer" {
            let pointer = ch
                .target
                .extensions
                .as_ref()
                .and_then(|e| e.get(POINTER))
                .and_then(|p| p.get("pointer"))
                .and_then(serde_json::Value::as_str)
                .ok_or_else(|| Skip::Why(format!("path 'pointer' without a {POINTER} pointer")))?;
            return match pointed(pointer).map_err(Skip::Why)? {
                Pointed::Node(node, property) => {
                    self.node_channel(label, node, property, ch, a, out, read)
                }
                Pointed::Light(i, property) | Pointed::Camera(i, property) => {
                    let (placed, what) = if property.target() == crate::scene::anim::Target::Light {
                        (&self.placed_lights, "light")
                    } else {
                        (&self.placed_cameras, "camera")
                    };
                    let targets: Vec<usize> = placed
                        .iter()
                        .filter(|(g, _)| *g == i)
                        .map(|&(_, k)| k)
                        .collect();
                    if targets.is_empty() {
                        return Err(Skip::Why(format!(
                            "pointer '{pointer}': {what} {i} is placed by no drawn node"
                        )));
                    }
                    let width = property.width().unwrap_or(1);
                    let sampler = self.sampler_of(label, ch, a, out, read, width, property)?;
                    // Animated intensities are used as the file gives them, which is right
                    // while the scene's unit is the file's (a sampler may be shared, so it
                    // is not rescaled here).
                    const _: () = assert!(super::lights::LUX_TO_RADIANCE == 1.0);
                    for k in targets {
                        out.channels.push(Channel {
                            node: k,
                            property,
                            sampler,
                        });
                    }
                    Ok(())
                }
                Pointed::Material(m, property) => {
                    let count = self.doc.json.materials.len();
                    if m >= count {
                        return Err(Skip::Why(format!(
                            "pointer '{pointer}': material {m}, but there are only {count}"
                        )));
                    }
                    let k = self
                        .material(m, label)
                        .map_err(Skip::Load)?
                        .ok_or_else(|| {
                            Skip::Why(format!(
                                "pointer '{pointer}': material {m} could not be read"
                            ))
                        })?;
                    let width = property.width().unwrap_or(1);
                    let sampler = self.sampler_of(label, ch, a, out, read, width, property)?;
                    out.channels.push(Channel {
                        node: k,
                        property,
                        sampler,
                    });
                    Ok(())
                }
            };
        }
        let legacy = ch.target.id.as_ref().and_then(serde_json::Value::as_u64);
        let node = match (ch.target.node, legacy) {
            (Some(n), _) => n,
            (None, Some(id)) => {
                self.scene.report.warnings.push(format!(
                    "{label} channel {c}: target written as 'id' (glTF 1.0); read as node {id}"
                ));
                usize::try_from(id).unwrap_or(usize::MAX)
            }
            (None, None) => return Err(Skip::Why("no target node".into())),
        };
        let property = match ch.target.path.as_str() {
            "translation" => Property::Translation,
            "rotation" => Property::Rotation,
            "scale" => Property::Scale,
            "weights" => Property::Weights,
            other => return Err(Skip::Why(format!("path '{other}' is not supported"))),
        };
        self.node_channel(label, node, property, ch, a, out, read)
    }

    /// A channel on `node`'s `property` (a plain path, or a pointer to a node).
    #[allow(clippy::too_many_arguments)]
    fn node_channel(
        &mut self,
        label: &str,
        node: usize,
        property: Property,
        ch: &ChannelJson,
        a: &AnimationJson,
        out: &mut Animation,
        read: &mut Vec<((usize, usize), usize)>,
    ) -> Result<(), Skip> {
        let graph = &self.scene.graph;
        let Some(target) = graph.nodes.get(node) else {
            let count = graph.nodes.len();
            return Err(Skip::Why(format!(
                "target node {node}, but there are only {count} nodes"
            )));
        };
        let width = match property.width() {
            Some(w) => w,
            None if target.weights.is_empty() => {
                return Err(Skip::Why(format!(
                    "node {node} has no morph targets to weight"
                )))
            }
            None => target.weights.len(),
        };
        if property != Property::Weights && matches!(target.local, Local::Matrix(_)) {
            return Err(Skip::Why(format!(
                "node {node} has a matrix, which cannot be animated"
            )));
        }
        let sampler = self.sampler_of(label, ch, a, out, read, width, property)?;
        out.channels.push(Channel {
            node,
            property,
            sampler,
        });
        Ok(())
    }

    /// The index in `out.samplers` of the channel's sampler read with `width` numbers a
    /// keyframe (read once per sampler and width).
    #[allow(clippy::too_many_arguments)]
    fn sampler_of(
        &self,
        label: &str,
        ch: &ChannelJson,
        a: &AnimationJson,
        out: &mut Animation,
        read: &mut Vec<((usize, usize), usize)>,
        width: usize,
        property: Property,
    ) -> Result<usize, Skip> {
        if let Some(&(_, k)) = read.iter().find(|(key, _)| *key == (ch.sampler, width)) {
            return Ok(k);
        }
        let s = a.samplers.get(ch.sampler).ok_or_else(|| {
            Skip::Why(format!(
                "sampler {}, but there are only {}",
                ch.sampler,
                a.samplers.len()
            ))
        })?;
        let sampler = self.keyframes(label, ch.sampler, s, width, property)?;
        out.samplers.push(sampler);
        read.push(((ch.sampler, width), out.samplers.len() - 1));
        Ok(out.samplers.len() - 1)
    }

    fn keyframes(
        &self,
        label: &str,
        index: usize,
        s: &SamplerJson,
        width: usize,
        property: Property,
    ) -> Result<Sampler, Skip> {
        let interpolation = match s.interpolation.as_deref() {
            None | Some("LINEAR") => Interpolation::Linear,
            Some("STEP") => Interpolation::Step,
            Some("CUBICSPLINE") => Interpolation::CubicSpline,
            Some(other) => {
                return Err(Skip::Why(format!(
                    "sampler {index} has unknown interpolation '{other}'"
                )))
            }
        };
        let doc = &self.doc;
        let keep = |e: LoadError| match e {
            e @ (LoadError::TooLarge { .. } | LoadError::Cancelled { .. }) => Skip::Load(e),
            e => Skip::Why(e.to_string()),
        };
        let (_, times) = doc
            .read_floats(
                s.input,
                &format!("{label} sampler {index} input"),
                &[1],
                Format::Float,
            )
            .map_err(keep)?;
        let sizes: &[usize] = match property {
            Property::Weights => &[1],
            _ => &[width],
        };
        let format = match property {
            Property::Rotation | Property::Weights => Format::Quantized,
            _ => Format::Float,
        };
        let (_, values) = doc
            .read_floats(
                s.output,
                &format!("{label} sampler {index} output"),
                sizes,
                format,
            )
            .map_err(keep)?;
        Sampler::new(interpolation, times, values, width)
            .map_err(|e| Skip::Why(format!("sampler {index} ({}) {e}", property.name())))
    }
}

/// Why a channel is left out: a reason for the report, or an error that stops the load
/// (the budget, a cancel).
enum Skip {
    Why(String),
    Load(LoadError),
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pointers_name_what_they_animate_or_why_not() {
        assert_eq!(
            pointed("/materials/3/pbrMetallicRoughness/baseColorFactor"),
            Ok(Pointed::Material(3, Property::BaseColor))
        );
        assert_eq!(
            pointed("/materials/0/emissiveFactor"),
            Ok(Pointed::Material(0, Property::Emissive))
        );
        assert_eq!(
            pointed("/nodes/7/rotation"),
            Ok(Pointed::Node(7, Property::Rotation))
        );
        assert_eq!(
            pointed("/extensions/KHR_lights_punctual/lights/2/spot/outerConeAngle"),
            Ok(Pointed::Light(2, Property::SpotOuter))
        );
        assert_eq!(
            pointed("/cameras/1/perspective/yfov"),
            Ok(Pointed::Camera(1, Property::CameraYfov))
        );
        assert_eq!(
            pointed("/materials/0/extensions/KHR_materials_emissive_strength/emissiveStrength"),
            Ok(Pointed::Material(0, Property::EmissiveStrength))
        );
        let e = pointed("/extensions/KHR_lights_punctual/lights/0/range").unwrap_err();
        assert!(e.contains("is not supported"), "{e}");
        let e = pointed("/materials/x/emissiveFactor").unwrap_err();
        assert!(e.contains("'x' is not an index"), "{e}");
        let e = pointed("/cameras/0/perspective/znear").unwrap_err();
        assert!(
            e.contains("is not supported") && e.contains("base colour"),
            "{e}"
        );
        let e = pointed("/materials/0/pbrMetallicRoughness/baseColorTexture").unwrap_err();
        assert!(e.contains("is not supported"), "{e}");
        assert_eq!(
            pointed("/materials/2/extensions/KHR_materials_sheen/sheenColorFactor"),
            Ok(Pointed::Material(2, Property::SheenColor))
        );
        assert_eq!(
            pointed("/materials/0/extensions/KHR_materials_clearcoat/clearcoatRoughnessFactor"),
            Ok(Pointed::Material(0, Property::ClearcoatRoughness))
        );
        assert_eq!(
            pointed("/materials/1/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/offset"),
            Ok(Pointed::Material(1, Property::TexOffset(Slot::BaseColor)))
        );
        assert_eq!(
            pointed("/materials/1/normalTexture/extensions/KHR_texture_transform/rotation"),
            Ok(Pointed::Material(1, Property::TexRotation(Slot::Normal)))
        );
        assert_eq!(
            pointed("/materials/4/extensions/KHR_materials_clearcoat/clearcoatNormalTexture/extensions/KHR_texture_transform/scale"),
            Ok(Pointed::Material(4, Property::TexScale(Slot::ClearcoatNormal)))
        );
        assert_eq!(
            pointed("/materials/0/extensions/KHR_materials_sheen/sheenRoughnessTexture/extensions/KHR_texture_transform/offset"),
            Ok(Pointed::Material(0, Property::TexOffset(Slot::SheenRoughness)))
        );
        let e = pointed("/materials/0/extensions/KHR_materials_sheen/fooTexture/extensions/KHR_texture_transform/offset")
            .unwrap_err();
        assert!(e.contains("is not supported"), "{e}");
        let e = pointed("/materials/1/normalTexture/extensions/KHR_texture_transform/texCoord")
            .unwrap_err();
        assert!(e.contains("is not supported"), "{e}");
        let e =
            pointed("/materials/1/fooTexture/extensions/KHR_texture_transform/offset").unwrap_err();
        assert!(e.contains("is not supported"), "{e}");
    }
}
