//! Tone mapping: what happens to colours outside [0, 1] before they are encoded (clamp,
//! Reinhard, Khronos PBR Neutral, the ACES fits).

use glam::Vec4;

/// What happens to colours outside [0, 1] (the textbook's pipeline chapter, §4.2) before they are
/// encoded. The background colour is never tone mapped (nor exposed); an environment shown
/// as the background is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ToneMap {
    /// [`ToneMap::PbrNeutral`] for a scene drawn entirely in the `pbr` mode (a glTF file's
    /// own look, as the Khronos glTF Sample Viewer shows it), else [`ToneMap::Clamp`] (the
    /// textbook's modes, whose colours are meant to be shown as they are):
    /// [`Settings::tone_for`](super::Settings::tone_for).
    #[default]
    Auto,
    /// Each channel clamped to [0, 1]: (1, 2, 1) becomes white.
    Clamp,
    /// A colour whose largest channel exceeds 1 is divided by it, keeping its hue:
    /// (1, 2, 1) becomes (0.5, 1, 0.5), light green.
    ScaleMax,
    /// Reinhard's operator on luminance, `L / (1 + L)`, applied as a scale to the colour
    /// (then scaled by the largest channel if one still exceeds 1): every colour stays in
    /// range and keeps its hue; darkens everything a little.
    Reinhard,
    /// Khronos PBR Neutral (KhronosGroup/ToneMapping): colours in [0.08, 0.8] lose 0.04
    /// and keep their hue, brighter ones roll off towards white and desaturate.
    PbrNeutral,
    /// ACES filmic, Narkowicz's per-channel fit (2016): 1 becomes about 0.80.
    AcesNarkowicz,
    /// ACES filmic, Hill's fit of the RRT and ODT (BakingLab `ACES.hlsl`), in its own
    /// colour space: 1 becomes about 0.62 (three.js's `ACESFilmicToneMapping` is this on
    /// x / 0.6).
    AcesHill,
}

impl ToneMap {
    pub const ALL: [ToneMap; 7] = [
        ToneMap::Auto,
        ToneMap::Clamp,
        ToneMap::ScaleMax,
        ToneMap::Reinhard,
        ToneMap::PbrNeutral,
        ToneMap::AcesNarkowicz,
        ToneMap::AcesHill,
    ];

    /// The name on the command line and in scene files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ToneMap::Auto => "auto",
            ToneMap::Clamp => "clamp",
            ToneMap::ScaleMax => "scale-max",
            ToneMap::Reinhard => "reinhard",
            ToneMap::PbrNeutral => "pbr-neutral",
            ToneMap::AcesNarkowicz => "aces-narkowicz",
            ToneMap::AcesHill => "aces-hill",
        }
    }

    /// Maps one linear colour (alpha kept); [`ToneMap::Auto`], not resolved, clamps.
    #[must_use]
    #[inline]
    pub fn apply(self, c: Vec4) -> Vec4 {
        let rgb = c.truncate();
        let scale_max = |rgb: glam::Vec3| {
            let m = rgb.max_element();
            if m > 1.0 && m.is_finite() {
                rgb / m
            } else {
                rgb
            }
        };
        let out = match self {
            ToneMap::Auto | ToneMap::Clamp => return c,
            ToneMap::ScaleMax => scale_max(rgb),
            ToneMap::Reinhard => {
                let l = rgb.dot(glam::Vec3::new(0.2126, 0.7152, 0.0722));
                if l > 0.0 && l.is_finite() {
                    scale_max(rgb / (1.0 + l))
                } else {
                    rgb
                }
            }
            ToneMap::PbrNeutral => pbr_neutral(rgb),
            ToneMap::AcesNarkowicz => rgb.map(aces_narkowicz),
            ToneMap::AcesHill => aces_hill(rgb),
        };
        // Non-finite input stays what it was (the operators would turn NaN into NaN and
        // infinity into NaN or 1 depending on the formula).
        if rgb.is_finite() {
            out.extend(c.w)
        } else {
            c
        }
    }
}

/// Khronos PBR Neutral on one linear colour (the reference GLSL, operation for operation).
fn pbr_neutral(c: glam::Vec3) -> glam::Vec3 {
    const START: f32 = 0.8 - 0.04;
    const DESATURATION: f32 = 0.15;
    let x = c.min_element();
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    let c = c - offset;
    let peak = c.max_element();
    if peak < START {
        return c;
    }
    let d = 1.0 - START;
    let new_peak = 1.0 - d * d / (peak + d - START);
    let c = c * (new_peak / peak);
    let g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    c.lerp(glam::Vec3::splat(new_peak), g)
}

/// Narkowicz's ACES fit on one channel, clamped to [0, 1].
fn aces_narkowicz(x: f32) -> f32 {
    let x = x.max(0.0);
    (x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// Hill's ACES fit: into the fit's colour space, the RRT + ODT rational curve, back out,
/// clamped to [0, 1].
fn aces_hill(c: glam::Vec3) -> glam::Vec3 {
    // Rows of the input and output matrices (glam's from_cols takes columns: transposed).
    let input = glam::Mat3::from_cols_array(&[
        0.59719, 0.07600, 0.02840, 0.35458, 0.90834, 0.13383, 0.04823, 0.01566, 0.83777,
    ]);
    let output = glam::Mat3::from_cols_array(&[
        1.60475, -0.10208, -0.00327, -0.53108, 1.10813, -0.07276, -0.07367, -0.00605, 1.07602,
    ]);
    let v = input * c.max(glam::Vec3::ZERO);
    let v = (v * (v + 0.024_578_6) - 0.000_090_537) / (v * (0.983_729 * v + 0.432_951) + 0.238_081);
    (output * v).clamp(glam::Vec3::ZERO, glam::Vec3::ONE)
}

impl std::str::FromStr for ToneMap {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        ToneMap::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| {
                format!(
                    "unknown tone map '{s}' (expected auto, clamp, scale-max, reinhard, \
                     pbr-neutral, aces-narkowicz or aces-hill)"
                )
            })
    }
}
