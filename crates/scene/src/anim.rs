//! Keyframe animation of the node tree (glTF animations): channels that drive a node's
//! translation, rotation, scale or morph weights from a sampler's keyframes, with STEP,
//! LINEAR (rotations by spherical linear interpolation, the shorter way round) and
//! CUBICSPLINE (Hermite with the keyframe interval scaling the tangents, rotations
//! normalised after) interpolation, as the glTF 2.0 specification's Appendix C defines them.
//!
//! Before the first keyframe a sampler holds its first value, after the last its last. An
//! animation lasts until the last keyframe of any of its samplers; looped, time wraps
//! modulo that duration. Sampling allocates nothing, so playback can run every frame.

use glam::{Quat, Vec3};

use super::graph::{Local, Pose};

/// How values between keyframes are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    Step,
    Linear,
    CubicSpline,
}

impl Interpolation {
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Interpolation::Step => "STEP",
            Interpolation::Linear => "LINEAR",
            Interpolation::CubicSpline => "CUBICSPLINE",
        }
    }
}

/// What a channel drives: a node's transform or morph weights, or (through
/// `KHR_animation_pointer`) a material's factor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Property {
    Translation,
    Rotation,
    Scale,
    /// Morph target weights (as many as the node's mesh has targets).
    Weights,
    /// A material's base colour factor (RGBA).
    BaseColor,
    /// A material's emissive factor (RGB).
    Emissive,
    /// A material's metallic factor.
    Metallic,
    /// A material's roughness factor.
    Roughness,
    /// A material's `KHR_materials_emissive_strength`.
    EmissiveStrength,
    /// A light's colour (RGB).
    LightColor,
    /// A light's intensity (in the scene's units: the loader converts).
    LightIntensity,
    /// A spot light's inner cone angle (radians).
    SpotInner,
    /// A spot light's outer cone angle (radians).
    SpotOuter,
    /// A perspective camera's vertical field of view (radians).
    CameraYfov,
    /// A material's `KHR_materials_clearcoat` factor and roughness.
    ClearcoatFactor,
    ClearcoatRoughness,
    /// A material's `KHR_materials_sheen` colour (RGB) and roughness.
    SheenColor,
    SheenRoughness,
    /// A material's `KHR_materials_iridescence` factor, film IOR and thickness range (nm).
    IridescenceFactor,
    IridescenceIor,
    IridescenceThicknessMin,
    IridescenceThicknessMax,
    /// A material's `KHR_materials_anisotropy` strength and rotation (radians).
    AnisotropyStrength,
    AnisotropyRotation,
    /// A material's `KHR_materials_diffuse_transmission` factor and colour (RGB).
    DiffuseTransmission,
    DiffuseTransmissionColor,
    /// A material's `KHR_materials_transmission` factor, `KHR_materials_volume` thickness,
    /// attenuation distance and colour (RGB), and `KHR_materials_dispersion`.
    TransmissionFactor,
    ThicknessFactor,
    AttenuationDistance,
    AttenuationColor,
    Dispersion,
    /// A material slot's `KHR_texture_transform` offset (2 numbers), rotation (radians)
    /// and scale (2 numbers).
    TexOffset(crate::Slot),
    TexRotation(crate::Slot),
    TexScale(crate::Slot),
}

/// What kind of object a channel's target is ([`Property::target`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    Node,
    /// An index into `Scene::materials`.
    Material,
    /// An index into `Scene::lights`.
    Light,
    /// An index into `Scene::cameras`.
    Camera,
}

impl Property {
    /// The glTF name (the channel path, or the last part of the pointer).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Property::Translation => "translation",
            Property::Rotation => "rotation",
            Property::Scale => "scale",
            Property::Weights => "weights",
            Property::BaseColor => "baseColorFactor",
            Property::Emissive => "emissiveFactor",
            Property::Metallic => "metallicFactor",
            Property::Roughness => "roughnessFactor",
            Property::EmissiveStrength => "emissiveStrength",
            Property::LightColor => "color",
            Property::LightIntensity => "intensity",
            Property::SpotInner => "innerConeAngle",
            Property::SpotOuter => "outerConeAngle",
            Property::CameraYfov => "yfov",
            Property::ClearcoatFactor => "clearcoatFactor",
            Property::ClearcoatRoughness => "clearcoatRoughnessFactor",
            Property::SheenColor => "sheenColorFactor",
            Property::SheenRoughness => "sheenRoughnessFactor",
            Property::IridescenceFactor => "iridescenceFactor",
            Property::IridescenceIor => "iridescenceIor",
            Property::IridescenceThicknessMin => "iridescenceThicknessMinimum",
            Property::IridescenceThicknessMax => "iridescenceThicknessMaximum",
            Property::AnisotropyStrength => "anisotropyStrength",
            Property::AnisotropyRotation => "anisotropyRotation",
            Property::DiffuseTransmission => "diffuseTransmissionFactor",
            Property::DiffuseTransmissionColor => "diffuseTransmissionColorFactor",
            Property::TransmissionFactor => "transmissionFactor",
            Property::ThicknessFactor => "thicknessFactor",
            Property::AttenuationDistance => "attenuationDistance",
            Property::AttenuationColor => "attenuationColor",
            Property::Dispersion => "dispersion",
            Property::TexOffset(_) => "offset",
            Property::TexRotation(_) => "rotation",
            Property::TexScale(_) => "scale",
        }
    }

    /// The kind of object the property belongs to.
    #[must_use]
    pub fn target(self) -> Target {
        match self {
            Property::Translation | Property::Rotation | Property::Scale | Property::Weights => {
                Target::Node
            }
            Property::BaseColor
            | Property::Emissive
            | Property::Metallic
            | Property::Roughness
            | Property::EmissiveStrength
            | Property::ClearcoatFactor
            | Property::ClearcoatRoughness
            | Property::SheenColor
            | Property::SheenRoughness
            | Property::IridescenceFactor
            | Property::IridescenceIor
            | Property::IridescenceThicknessMin
            | Property::IridescenceThicknessMax
            | Property::AnisotropyStrength
            | Property::AnisotropyRotation
            | Property::DiffuseTransmission
            | Property::DiffuseTransmissionColor
            | Property::TransmissionFactor
            | Property::ThicknessFactor
            | Property::AttenuationDistance
            | Property::AttenuationColor
            | Property::Dispersion
            | Property::TexOffset(_)
            | Property::TexRotation(_)
            | Property::TexScale(_) => Target::Material,
            Property::LightColor
            | Property::LightIntensity
            | Property::SpotInner
            | Property::SpotOuter => Target::Light,
            Property::CameraYfov => Target::Camera,
        }
    }

    /// Numbers per keyframe (`None` for weights: as many as the node's morph targets).
    #[must_use]
    pub fn width(self) -> Option<usize> {
        match self {
            Property::Translation
            | Property::Scale
            | Property::Emissive
            | Property::LightColor
            | Property::SheenColor
            | Property::DiffuseTransmissionColor
            | Property::AttenuationColor => Some(3),
            Property::TexOffset(_) | Property::TexScale(_) => Some(2),
            Property::Rotation | Property::BaseColor => Some(4),
            Property::Weights => None,
            _ => Some(1),
        }
    }
}

/// Keyframes: times and the values at them.
#[derive(Clone, Debug, PartialEq)]
pub struct Sampler {
    pub interpolation: Interpolation,
    /// Strictly increasing, finite, at least one.
    pub times: Vec<f32>,
    /// `width` values per keyframe; for CUBICSPLINE three groups of `width` per keyframe:
    /// in-tangent, value, out-tangent.
    pub values: Vec<f32>,
    pub width: usize,
}

/// Why a sampler's data cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SamplerError {
    #[error("has no keyframes")]
    Empty,
    #[error("keyframe time {index} is {time}, not a finite number")]
    TimeNotFinite { index: usize, time: f32 },
    #[error("keyframe times are not increasing: time {index} is {time}, after {previous}")]
    NotIncreasing {
        index: usize,
        time: f32,
        previous: f32,
    },
    #[error("has {values} output values for {keys} keyframes; {expected} expected")]
    Count {
        values: usize,
        keys: usize,
        expected: usize,
    },
    #[error("output value {index} is {value}, not a finite number")]
    ValueNotFinite { index: usize, value: f32 },
}

impl Sampler {
    /// Checks and builds a sampler.
    pub fn new(
        interpolation: Interpolation,
        times: Vec<f32>,
        values: Vec<f32>,
        width: usize,
    ) -> Result<Self, SamplerError> {
        if times.is_empty() || width == 0 {
            return Err(SamplerError::Empty);
        }
        for (index, &time) in times.iter().enumerate() {
            if !time.is_finite() {
                return Err(SamplerError::TimeNotFinite { index, time });
            }
            if let Some(&previous) = index.checked_sub(1).and_then(|p| times.get(p)) {
                if time <= previous {
                    return Err(SamplerError::NotIncreasing {
                        index,
                        time,
                        previous,
                    });
                }
            }
        }
        let groups = if interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
        let expected = times.len() * width * groups;
        if values.len() != expected {
            return Err(SamplerError::Count {
                values: values.len(),
                keys: times.len(),
                expected,
            });
        }
        if let Some((index, &value)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(SamplerError::ValueNotFinite { index, value });
        }
        Ok(Self {
            interpolation,
            times,
            values,
            width,
        })
    }

    /// Time of the last keyframe.
    #[must_use]
    pub fn end(&self) -> f32 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// The value of keyframe `k` (for CUBICSPLINE the middle group).
    fn key(&self, k: usize) -> &[f32] {
        let w = self.width;
        let at = match self.interpolation {
            Interpolation::CubicSpline => (3 * k + 1) * w,
            _ => k * w,
        };
        &self.values[at..at + w]
    }

    /// Writes the value at time `t` into `out` (its first `width` values; fewer if `out` is
    /// shorter). `rotation`: the values are quaternions (x, y, z, w), interpolated
    /// spherically and normalised.
    pub fn sample(&self, t: f32, out: &mut [f32], rotation: bool) {
        let n = self.times.len();
        let w = self.width.min(out.len());
        let out = &mut out[..w];
        let last = n - 1;
        // k: the keyframe at or before t.
        let k = self.times.partition_point(|&x| x <= t);
        if k == 0 || k > last || n == 1 {
            let k = if k == 0 { 0 } else { last };
            out.copy_from_slice(&self.key(k)[..w]);
            return;
        }
        let k = k - 1;
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let dt = t1 - t0;
        let s = ((t - t0) / dt).clamp(0.0, 1.0);
        let (a, b) = (&self.key(k)[..w], &self.key(k + 1)[..w]);
        match self.interpolation {
            Interpolation::Step => out.copy_from_slice(a),
            Interpolation::Linear if rotation && w == 4 => {
                let q = quat(a).slerp(quat(b), s);
                out.copy_from_slice(&q.to_array());
            }
            Interpolation::Linear => {
                for ((o, &x), &y) in out.iter_mut().zip(a).zip(b) {
                    *o = x + (y - x) * s;
                }
            }
            Interpolation::CubicSpline => {
                let ww = self.width;
                let out_tangent = &self.values[(3 * k + 2) * ww..][..w];
                let in_tangent = &self.values[3 * (k + 1) * ww..][..w];
                let (s2, s3) = (s * s, s * s * s);
                let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
                let h10 = s3 - 2.0 * s2 + s;
                let h01 = -2.0 * s3 + 3.0 * s2;
                let h11 = s3 - s2;
                for i in 0..w {
                    out[i] = h00 * a[i]
                        + h10 * dt * out_tangent[i]
                        + h01 * b[i]
                        + h11 * dt * in_tangent[i];
                }
                if rotation && w == 4 {
                    let q = quat(out).normalize();
                    out.copy_from_slice(&q.to_array());
                }
            }
        }
    }
}

fn quat(v: &[f32]) -> Quat {
    match v {
        &[x, y, z, w] => Quat::from_xyzw(x, y, z, w),
        _ => Quat::IDENTITY,
    }
}

/// One channel: a node's property driven by a sampler of the same animation.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// The node, or for a property of a material, light or camera ([`Property::target`])
    /// that object (an index into `Scene::materials`, `lights` or `cameras`).
    pub node: usize,
    pub property: Property,
    /// Index into [`Animation::samplers`].
    pub sampler: usize,
}

/// A named set of channels played together.
#[derive(Clone, Debug, PartialEq)]
pub struct Animation {
    pub name: String,
    pub samplers: Vec<Sampler>,
    pub channels: Vec<Channel>,
}

impl Animation {
    /// Time of the last keyframe of any sampler (0 for an animation without channels).
    #[must_use]
    pub fn duration(&self) -> f32 {
        self.channels
            .iter()
            .filter_map(|c| self.samplers.get(c.sampler))
            .map(Sampler::end)
            .fold(0.0, f32::max)
    }

    /// The time sampled at playback time `t` (seconds): wrapped into `[0, duration)` when
    /// looping, else as it is (samplers hold their ends). A non-finite `t` reads as 0.
    #[must_use]
    pub fn local_time(&self, t: f32, looping: bool) -> f32 {
        let t = if t.is_finite() { t } else { 0.0 };
        let d = self.duration();
        // The end itself stays the end: a looping animation scrubbed to its last instant
        // shows its last pose, not its first.
        if looping && d > 0.0 && !(0.0..=d).contains(&t) {
            t.rem_euclid(d)
        } else {
            t
        }
    }

    /// Sets the animated properties of `pose` to their values at time `t` (no wrapping;
    /// see [`Self::local_time`]). Other properties keep what `pose` has. Channels on
    /// nodes `pose` does not have, or on matrix nodes, are ignored (the loader drops them
    /// with a warning).
    pub fn apply(&self, t: f32, pose: &mut Pose) {
        for c in &self.channels {
            let Some(sampler) = self.samplers.get(c.sampler) else {
                continue;
            };
            if c.property.target() != Target::Node {
                let mut v = [0.0f32; 4];
                let width = c.property.width().unwrap_or(1);
                sampler.sample(t, &mut v[..width], false);
                let key = |e: &&mut (usize, Property, [f32; 4])| e.0 == c.node && e.1 == c.property;
                match pose.values.iter_mut().find(key) {
                    Some(e) => e.2 = v,
                    None => pose.values.push((c.node, c.property, v)),
                }
                continue;
            }
            if c.property == Property::Weights {
                if let Some(w) = pose.weights.get_mut(c.node) {
                    sampler.sample(t, w, false);
                }
                continue;
            }
            let Some(Local::Trs(trs)) = pose.locals.get_mut(c.node) else {
                continue;
            };
            let mut v = [0.0f32; 4];
            match c.property {
                Property::Translation => {
                    v[..3].copy_from_slice(&trs.translation.to_array());
                    sampler.sample(t, &mut v[..3], false);
                    trs.translation = Vec3::from_slice(&v[..3]);
                }
                Property::Scale => {
                    v[..3].copy_from_slice(&trs.scale.to_array());
                    sampler.sample(t, &mut v[..3], false);
                    trs.scale = Vec3::from_slice(&v[..3]);
                }
                Property::Rotation => {
                    v = trs.rotation.to_array();
                    sampler.sample(t, &mut v, true);
                    let q = quat(&v);
                    // A zero quaternion (all-zero keys) keeps the rest rotation.
                    if q.length_squared() > 1e-12 {
                        trs.rotation = q.normalize();
                    }
                }
                _ => {}
            }
        }
    }
}

/// Which animations play.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Play {
    /// None: the rest pose.
    #[default]
    Rest,
    /// One animation (an index into the scene's animations).
    One(usize),
    /// All of them together, each looping over its own duration (files often split one
    /// motion into an animation per node).
    All,
}

/// A rest pose changed by the animations of `play` at playback time `t`: the rest of
/// `graph`, the animations applied in file order, world matrices updated (into `pose`,
/// reusing its buffers). An index that does not exist plays nothing.
pub fn pose_at(
    graph: &super::graph::Graph,
    animations: &[Animation],
    play: Play,
    t: f32,
    looping: bool,
    pose: &mut Pose,
) {
    graph.reset(pose);
    let chosen = match play {
        Play::Rest => &[][..],
        Play::One(i) => animations.get(i..=i).unwrap_or(&[]),
        Play::All => animations,
    };
    for a in chosen {
        a.apply(a.local_time(t, looping), pose);
    }
    graph.update_worlds(pose);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sampler(i: Interpolation, times: &[f32], values: &[f32], width: usize) -> Sampler {
        Sampler::new(i, times.to_vec(), values.to_vec(), width).unwrap()
    }

    #[test]
    fn step_linear_and_cubic_follow_the_specification() {
        let times = [0.0, 1.0, 3.0];
        let mut out = [0.0f32];
        let step = sampler(Interpolation::Step, &times, &[1.0, 2.0, 4.0], 1);
        for (t, want) in [(-1.0, 1.0), (0.5, 1.0), (1.0, 2.0), (2.9, 2.0), (9.0, 4.0)] {
            step.sample(t, &mut out, false);
            assert_eq!(out[0], want, "STEP at {t}");
        }
        let linear = sampler(Interpolation::Linear, &times, &[1.0, 2.0, 4.0], 1);
        linear.sample(2.0, &mut out, false);
        assert_eq!(out[0], 3.0);
        // Hermite: a cubic with known tangents is reproduced exactly. f(t) = t^3 on
        // [0, 1, 3]: values 0, 1, 27; derivatives 0, 3, 27.
        let cubic = sampler(
            Interpolation::CubicSpline,
            &times,
            &[0.0, 0.0, 0.0, 3.0, 1.0, 3.0, 27.0, 27.0, 27.0],
            1,
        );
        for t in [0.25f32, 0.5, 1.5, 2.0, 2.75] {
            cubic.sample(t, &mut out, false);
            assert!((out[0] - t.powi(3)).abs() < 1e-4, "t^3 at {t}: {}", out[0]);
        }
    }

    #[test]
    fn rotations_slerp_the_short_way() {
        let a = Quat::from_rotation_y(0.0);
        // The same rotation as 170 degrees, written with the opposite sign.
        let b = -Quat::from_rotation_y(170f32.to_radians());
        let mut v = [0.0; 8];
        v[..4].copy_from_slice(&a.to_array());
        v[4..].copy_from_slice(&b.to_array());
        let s = sampler(Interpolation::Linear, &[0.0, 1.0], &v, 4);
        let mut out = [0.0; 4];
        s.sample(0.5, &mut out, true);
        let got = quat(&out);
        let want = Quat::from_rotation_y(85f32.to_radians());
        assert!(got.dot(want).abs() > 0.9999, "{got:?}");
    }

    #[test]
    fn bad_samplers_are_refused() {
        let e = Sampler::new(Interpolation::Linear, vec![0.0, 0.0], vec![1.0, 2.0], 1);
        assert!(matches!(
            e,
            Err(SamplerError::NotIncreasing { index: 1, .. })
        ));
        let e = Sampler::new(Interpolation::CubicSpline, vec![0.0], vec![1.0], 1);
        assert!(matches!(e, Err(SamplerError::Count { expected: 3, .. })));
        let e = Sampler::new(Interpolation::Step, vec![f32::NAN], vec![1.0], 1);
        assert!(matches!(e, Err(SamplerError::TimeNotFinite { .. })));
        let e = Sampler::new(Interpolation::Step, vec![0.0], vec![f32::NAN], 1);
        assert!(matches!(e, Err(SamplerError::ValueNotFinite { .. })));
        assert!(matches!(
            Sampler::new(Interpolation::Step, vec![], vec![], 1),
            Err(SamplerError::Empty)
        ));
    }

    #[test]
    fn looping_wraps_and_holds() {
        let s = sampler(Interpolation::Linear, &[0.0, 2.0], &[0.0, 2.0], 1);
        let a = Animation {
            name: "a".into(),
            samplers: vec![s],
            channels: vec![Channel {
                node: 0,
                property: Property::Translation,
                sampler: 0,
            }],
        };
        assert_eq!(a.duration(), 2.0);
        assert_eq!(a.local_time(5.0, true), 1.0);
        assert_eq!(a.local_time(-0.5, true), 1.5);
        assert_eq!(a.local_time(5.0, false), 5.0);
        assert_eq!(a.local_time(f32::NAN, true), 0.0);
        // Scrubbed to the end of a looping animation: the end, not the start.
        assert_eq!(a.local_time(2.0, true), 2.0);
        assert_eq!(a.local_time(4.0, true), 0.0);
    }
}
