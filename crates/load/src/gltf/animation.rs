//! glTF animations into [`crate::scene::Animation`]s: every channel whose target is a node's
//! translation, rotation, scale or morph weights, its sampler's keyframe times (`input`)
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
use crate::scene::{Animation, Local};
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
        let graph = &self.scene.graph;
        let Some(target) = graph.nodes.get(node) else {
            let count = graph.nodes.len();
            return Err(Skip::Why(format!(
                "target node {node}, but there are only {count} nodes"
            )));
        };
        let property = match ch.target.path.as_str() {
            "translation" => Property::Translation,
            "rotation" => Property::Rotation,
            "scale" => Property::Scale,
            "weights" => Property::Weights,
            other => return Err(Skip::Why(format!("path '{other}' is not supported"))),
        };
        let width = match property {
            Property::Translation | Property::Scale => 3,
            Property::Rotation => 4,
            Property::Weights if target.weights.is_empty() => {
                return Err(Skip::Why(format!(
                    "node {node} has no morph targets to weight"
                )))
            }
            Property::Weights => target.weights.len(),
        };
        if property != Property::Weights && matches!(target.local, Local::Matrix(_)) {
            return Err(Skip::Why(format!(
                "node {node} has a matrix, which cannot be animated"
            )));
        }
        let sampler =
            if let Some(&(_, k)) = read.iter().find(|(key, _)| *key == (ch.sampler, width)) {
                k
            } else {
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
                out.samplers.len() - 1
            };
        out.channels.push(Channel {
            node,
            property,
            sampler,
        });
        Ok(())
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
            Property::Translation | Property::Scale => Format::Float,
            _ => Format::Quantized,
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
