//! `KHR_lights_punctual`: directional, point and spot lights attached to nodes.
//!
//! The extension's data is not part of the `gltf` crate's JSON types as this crate builds
//! them, so it is read by a second, narrow parse of the JSON text ([`parse`]): the root's
//! `extensions.KHR_lights_punctual.lights` and each node's
//! `extensions.KHR_lights_punctual.light`, everything else skipped unread. It runs only when
//! the file lists the extension in `extensionsUsed` (or `extensionsRequired`).
//!
//! Every entry is checked by hand ([`convert`]): a light without a known `type`, a node
//! referring to a light that does not exist, and a light under a degenerate transform are
//! skipped with a warning in the load report; an unusable colour, intensity, range or cone
//! angle is replaced by the spec's default (or clamped) with a warning. Nothing here panics
//! or fails the load.
//!
//! **Units.** glTF gives point and spot intensities in candela (lm/sr) and directional ones
//! in lux (lm/m²). realist has no exposure control, so it maps photometric units to display
//! radiance with one fixed scale, [`LUX_TO_RADIANCE`] = 1: a directional light of 1 lux
//! lights a white surface facing it to white (radiance 1, the strength of the default key
//! light), and a point or spot light of `I` candela gives `I / d²` lux at distance `d`
//! (inverse-square attenuation, or glTF's `range` window when `range` is given), so 1 cd at
//! 1 unit matches the 1 lux sun. The Lambert `1/π` of physically based renderers is left
//! out, as in the textbook's Phong model. Files authored for real-world exposure (a 100 000 lux
//! sun) come out white; scale them in a scene file (`light_scale`).
//!
//! The node's world transform places the light: position = the node's origin, direction =
//! its local -Z (glTF lights shine down -Z), scale ignored.

use glam::{Mat4, Vec3};
use serde::Deserialize;
use serde_json::Value;

use super::Builder;
use crate::scene::{Attenuation, Light, LightKind};

/// The extension's name.
pub const EXTENSION: &str = "KHR_lights_punctual";

/// Display radiance per lux (directional) or per candela at unit distance (point, spot).
pub const LUX_TO_RADIANCE: f32 = 1.0;

/// The largest spot cone half-angle glTF allows (π/2).
const MAX_CONE: f32 = std::f32::consts::FRAC_PI_2;

/// The extension's parts of a document.
#[derive(Debug, Default)]
pub(super) struct PunctualLights {
    /// Lights in their local frame (at the origin, shining down -Z); `None` where an entry
    /// was unusable (already warned about).
    pub lights: Vec<Option<Light>>,
    /// Node index -> light index, as the file says (checked when used).
    pub nodes: Vec<Option<Value>>,
}

#[derive(Deserialize)]
struct LightsPass {
    #[serde(default)]
    extensions: Option<serde_json::Map<String, Value>>,
    #[serde(default)]
    nodes: Vec<NodePass>,
}

#[derive(Deserialize)]
struct NodePass {
    #[serde(default)]
    extensions: Option<serde_json::Map<String, Value>>,
}

/// Whether the file uses the extension.
pub(super) fn used(json: &super::schema::Json) -> bool {
    json.extensions_used
        .iter()
        .chain(&json.extensions_required)
        .any(|e| e == EXTENSION)
}

/// Reads the extension from the JSON text, adding warnings for unusable entries. A text
/// the narrow parse cannot read (it already passed the full parse, so this means a
/// malformed `extensions` object) gives no lights and a warning.
pub(super) fn parse(text: &[u8], warnings: &mut Vec<String>) -> PunctualLights {
    let pass: LightsPass = match serde_json::from_slice(text) {
        Ok(p) => p,
        Err(e) => {
            warnings.push(format!("{EXTENSION}: could not be read ({e}); no lights"));
            return PunctualLights::default();
        }
    };
    let root = pass.extensions.as_ref().and_then(|e| e.get(EXTENSION));
    let entries = match root.map(|r| r.get("lights")) {
        None => Vec::new(),
        Some(Some(Value::Array(items))) => items.clone(),
        Some(_) => {
            warnings.push(format!("{EXTENSION}: `lights` is not an array; no lights"));
            Vec::new()
        }
    };
    let lights = entries
        .iter()
        .enumerate()
        .map(|(i, v)| match convert(v) {
            Ok((light, notes)) => {
                warnings.extend(
                    notes
                        .into_iter()
                        .map(|n| format!("{EXTENSION} light {i}: {n}")),
                );
                Some(light)
            }
            Err(why) => {
                warnings.push(format!("{EXTENSION} light {i}: {why}; skipped"));
                None
            }
        })
        .collect();
    let nodes = pass
        .nodes
        .into_iter()
        .map(|n| n.extensions.and_then(|mut e| e.remove(EXTENSION)))
        .collect();
    PunctualLights { lights, nodes }
}

/// A number from a JSON value, if it is one and finite.
fn number(v: &Value) -> Option<f32> {
    v.as_f64().map(|x| x as f32).filter(|x| x.is_finite())
}

/// One light entry in its local frame, with notes about replaced values; `Err` if it
/// cannot be used at all.
pub(super) fn convert(v: &Value) -> Result<(Light, Vec<String>), String> {
    let obj = v.as_object().ok_or("is not an object")?;
    let mut notes = Vec::new();
    let kind = match obj.get("type").and_then(Value::as_str) {
        Some("directional") => LightKind::Directional,
        Some("point") => LightKind::Point,
        Some("spot") => LightKind::Spot,
        Some(other) => return Err(format!("unknown type '{other}'")),
        None => return Err("has no `type`".into()),
    };
    let name = obj
        .get("name")
        .and_then(Value::as_str)
        .map_or_else(String::new, str::to_owned);
    let color = match obj.get("color") {
        None => Vec3::ONE,
        Some(c) => {
            let rgb: Option<Vec<f32>> = c
                .as_array()
                .and_then(|a| a.iter().map(number).collect::<Option<Vec<f32>>>());
            match rgb.as_deref() {
                Some(&[r, g, b]) if r >= 0.0 && g >= 0.0 && b >= 0.0 => Vec3::new(r, g, b),
                _ => {
                    notes.push(format!(
                        "color {c} is not 3 non-negative numbers; white used"
                    ));
                    Vec3::ONE
                }
            }
        }
    };
    let intensity = match obj.get("intensity") {
        None => 1.0,
        Some(i) => match number(i) {
            Some(x) if x >= 0.0 => x,
            _ => {
                notes.push(format!(
                    "intensity {i} is not a non-negative number; 1 used"
                ));
                1.0
            }
        },
    };
    let attenuation = if kind == LightKind::Directional {
        Attenuation::None
    } else {
        match obj.get("range") {
            None => Attenuation::InverseSquare,
            Some(r) => match number(r) {
                Some(x) if x > 0.0 => Attenuation::Range(x),
                _ => {
                    notes.push(format!(
                        "range {r} is not a positive number; inverse-square used"
                    ));
                    Attenuation::InverseSquare
                }
            },
        }
    };
    let mut light = Light {
        name: name.into(),
        kind,
        color,
        intensity: intensity * LUX_TO_RADIANCE,
        position: Vec3::ZERO,
        direction: Vec3::NEG_Z,
        attenuation,
        ..Light::default()
    };
    if kind == LightKind::Spot {
        let spot = obj.get("spot").and_then(Value::as_object);
        if spot.is_none() {
            notes.push("spot light without a `spot` object; default cone used".into());
        }
        let angle = |key: &str, default: f32, notes: &mut Vec<String>| match spot
            .and_then(|s| s.get(key))
        {
            None => default,
            Some(a) => match number(a) {
                Some(x) if (0.0..=MAX_CONE).contains(&x) => x,
                Some(x) if x > MAX_CONE => {
                    notes.push(format!("{key} {a} is beyond π/2; clamped"));
                    MAX_CONE
                }
                _ => {
                    notes.push(format!(
                        "{key} {a} is not an angle in 0..π/2; {default} used"
                    ));
                    default
                }
            },
        };
        let mut outer = angle("outerConeAngle", std::f32::consts::FRAC_PI_4, &mut notes);
        if outer <= 0.0 {
            notes.push("outerConeAngle 0: the cone is empty; π/4 used".into());
            outer = std::f32::consts::FRAC_PI_4;
        }
        let mut inner = angle("innerConeAngle", 0.0, &mut notes);
        if inner >= outer {
            notes.push(format!(
                "innerConeAngle {inner} is not below outerConeAngle {outer}; clamped"
            ));
            inner = outer;
        }
        light.inner = inner;
        light.outer = outer;
    }
    Ok((light, notes))
}

impl Builder<'_> {
    /// Adds the light node `n` carries (if any), placed by `world`.
    pub(super) fn node_light(&mut self, n: usize, world: Mat4, node: &str) {
        let Some(ext) = self.lights.nodes.get(n).and_then(Option::as_ref) else {
            return;
        };
        let warn = |this: &mut Self, why: String| {
            this.scene
                .report
                .warnings
                .push(format!("node '{node}': {EXTENSION} {why}; no light"));
        };
        // An index written as an integral float (`0.0`) is accepted, as for the rest of
        // the document (see `schema`).
        let index = ext.get("light").and_then(|v| {
            v.as_u64().or_else(|| {
                v.as_f64()
                    .filter(|f| f.fract() == 0.0 && *f >= 0.0)
                    .map(|f| f as u64)
            })
        });
        let Some(index) = index else {
            return warn(self, format!("{ext} has no light index"));
        };
        let count = self.lights.lights.len();
        let Some(slot) = usize::try_from(index)
            .ok()
            .and_then(|i| self.lights.lights.get(i))
        else {
            return warn(
                self,
                format!("refers to light {index}, but there are only {count}"),
            );
        };
        let Some(local) = slot.clone() else {
            // The entry was unusable; already reported.
            return;
        };
        let position = world.transform_point3(Vec3::ZERO);
        let direction = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
        let up = world.transform_vector3(Vec3::Y).normalize_or_zero();
        if !position.is_finite() || direction == Vec3::ZERO || !direction.is_finite() {
            return warn(self, "is under a degenerate transform".into());
        }
        let mut light = local;
        if light.name.is_empty() {
            light.name = node.to_owned().into();
        }
        light.position = position;
        light.direction = direction;
        light.up = if up == Vec3::ZERO { Vec3::Y } else { up };
        self.scene.lights.push(light);
        if let Ok(i) = usize::try_from(index) {
            self.placed_lights.push((i, self.scene.lights.len() - 1));
        }
    }
}
