//! Device colour models of (encoded) RGB in [0, 1]: HSV (Smith's hexcone), HSL, CMY
//! (subtractive, origin at white), CMYK, YIQ (NTSC), YUV (BT.601 analogue) and YCbCr (BT.601,
//! BT.709 or BT.2020 weights; full or studio range; float or 8-bit code values).
//!
//! Every model converts both ways. Hue is in [0, 1) (multiply by 360 for degrees); an
//! achromatic colour has hue 0 and saturation 0. YIQ and YUV use the matrices of
//! scikit-image (`rgb2yiq`, `rgb2yuv`), whose inverses are computed, not rounded.

use super::matrix::{inverse, mul_vec, Mat3};

/// The hue in [0, 1) of `rgb` with maximum `max` and chroma `delta` (> 0).
fn hue(rgb: [f64; 3], max: f64, delta: f64) -> f64 {
    let [r, g, b] = rgb;
    let h = if max == r {
        (g - b) / delta
    } else if max == g {
        2.0 + (b - r) / delta
    } else {
        4.0 + (r - g) / delta
    };
    (h / 6.0).rem_euclid(1.0)
}

fn max_min(rgb: [f64; 3]) -> (f64, f64) {
    (
        rgb[0].max(rgb[1]).max(rgb[2]),
        rgb[0].min(rgb[1]).min(rgb[2]),
    )
}

/// RGB to HSV (hexcone): V = max, S = (max - min) / max.
#[must_use]
pub fn rgb_to_hsv(rgb: [f64; 3]) -> [f64; 3] {
    let (max, min) = max_min(rgb);
    let delta = max - min;
    if delta <= 0.0 {
        return [0.0, 0.0, max];
    }
    [hue(rgb, max, delta), delta / max, max]
}

/// The RGB of hue `h` (in [0, 1)), chroma `c` and minimum `m`.
fn from_hue(h: f64, c: f64, m: f64) -> [f64; 3] {
    let h6 = h.rem_euclid(1.0) * 6.0;
    let x = c * (1.0 - (h6.rem_euclid(2.0) - 1.0).abs());
    let (r, g, b) = match h6 as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    [r + m, g + m, b + m]
}

/// HSV to RGB.
#[must_use]
pub fn hsv_to_rgb(hsv: [f64; 3]) -> [f64; 3] {
    let [h, s, v] = hsv;
    let c = v * s;
    from_hue(h, c, v - c)
}

/// RGB to HSL: L = (max + min) / 2, S = (max - min) / (1 - |2L - 1|).
#[must_use]
pub fn rgb_to_hsl(rgb: [f64; 3]) -> [f64; 3] {
    let (max, min) = max_min(rgb);
    let delta = max - min;
    let l = (max + min) / 2.0;
    if delta <= 0.0 {
        return [0.0, 0.0, l];
    }
    let s = if l < 0.5 {
        delta / (max + min)
    } else {
        delta / (2.0 - max - min)
    };
    [hue(rgb, max, delta), s, l]
}

/// HSL to RGB.
#[must_use]
pub fn hsl_to_rgb(hsl: [f64; 3]) -> [f64; 3] {
    let [h, s, l] = hsl;
    let c = (1.0 - (2.0 * l - 1.0).abs()) * s;
    from_hue(h, c, l - c / 2.0)
}

/// RGB to CMY: 1 - RGB.
#[must_use]
pub fn rgb_to_cmy(rgb: [f64; 3]) -> [f64; 3] {
    rgb.map(|c| 1.0 - c)
}

/// CMY to RGB: 1 - CMY.
#[must_use]
pub fn cmy_to_rgb(cmy: [f64; 3]) -> [f64; 3] {
    cmy.map(|c| 1.0 - c)
}

/// CMY to CMYK with full grey-component replacement: K = min(C, M, Y), the rest rescaled
/// by 1 / (1 - K); pure black is (0, 0, 0, 1).
#[must_use]
pub fn cmy_to_cmyk(cmy: [f64; 3]) -> [f64; 4] {
    let k = cmy[0].min(cmy[1]).min(cmy[2]);
    if k >= 1.0 {
        return [0.0, 0.0, 0.0, 1.0];
    }
    let [c, m, y] = cmy.map(|v| (v - k) / (1.0 - k));
    [c, m, y, k]
}

/// CMYK to CMY.
#[must_use]
pub fn cmyk_to_cmy(cmyk: [f64; 4]) -> [f64; 3] {
    let k = cmyk[3];
    [0, 1, 2].map(|i| cmyk[i] * (1.0 - k) + k)
}

/// RGB to YIQ (NTSC 1953, scikit-image's matrix).
pub const YIQ_FROM_RGB: Mat3 = [
    [0.299, 0.587, 0.114],
    [0.595_900_59, -0.274_556_67, -0.321_343_92],
    [0.211_536_61, -0.522_736_17, 0.311_199_55],
];

/// RGB to YUV (BT.601 analogue: U = 0.492111 (B' - Y'), V = 0.877283 (R' - Y');
/// scikit-image's matrix).
pub const YUV_FROM_RGB: Mat3 = [
    [0.299, 0.587, 0.114],
    [-0.147_141_19, -0.288_869_16, 0.436_010_35],
    [0.614_975_38, -0.514_965_12, -0.100_010_26],
];

/// RGB to YIQ.
#[must_use]
pub fn rgb_to_yiq(rgb: [f64; 3]) -> [f64; 3] {
    mul_vec(&YIQ_FROM_RGB, rgb)
}

/// YIQ to RGB (exact inverse of [`YIQ_FROM_RGB`]).
#[must_use]
pub fn yiq_to_rgb(yiq: [f64; 3]) -> [f64; 3] {
    mul_vec(&invert(&YIQ_FROM_RGB), yiq)
}

/// RGB to YUV.
#[must_use]
pub fn rgb_to_yuv(rgb: [f64; 3]) -> [f64; 3] {
    mul_vec(&YUV_FROM_RGB, rgb)
}

/// YUV to RGB (exact inverse of [`YUV_FROM_RGB`]).
#[must_use]
pub fn yuv_to_rgb(yuv: [f64; 3]) -> [f64; 3] {
    mul_vec(&invert(&YUV_FROM_RGB), yuv)
}

fn invert(m: &Mat3) -> Mat3 {
    // Both constant matrices are well conditioned; the fallback is unreachable.
    inverse(m).unwrap_or([[0.0; 3]; 3])
}

/// Luma weights of a YCbCr system: Y' = kr R' + (1 - kr - kb) G' + kb B'.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LumaWeights {
    pub kr: f64,
    pub kb: f64,
}

impl LumaWeights {
    /// ITU-R BT.601 (SD video, JPEG/JFIF).
    pub const BT601: Self = Self {
        kr: 0.299,
        kb: 0.114,
    };
    /// ITU-R BT.709 (HD video).
    pub const BT709: Self = Self {
        kr: 0.2126,
        kb: 0.0722,
    };
    /// ITU-R BT.2020 (UHD video).
    pub const BT2020: Self = Self {
        kr: 0.2627,
        kb: 0.0593,
    };
}

/// Code-value range of YCbCr.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum YCbCrRange {
    /// Y in [0, 1], Cb and Cr in [-0.5, 0.5]; 8-bit: Y 0..=255, C 128 + 255 C clamped (JFIF).
    Full,
    /// 8-bit studio swing: Y 16..235, C 16..240 (as code value / 255 in float).
    Studio,
}

/// RGB to full-range float YCbCr: Y in [0, 1], Cb and Cr in [-0.5, 0.5].
#[must_use]
pub fn rgb_to_ycbcr(rgb: [f64; 3], k: LumaWeights) -> [f64; 3] {
    let [r, g, b] = rgb;
    let y = k.kr * r + (1.0 - k.kr - k.kb) * g + k.kb * b;
    // 0.5 * (B - Y) / (1 - kb), in colour-science's order of operations, so that 8-bit
    // rounding of exact halves (e.g. cyan's Cr) agrees with it.
    [
        y,
        0.5 * (b - y) / (1.0 - k.kb),
        0.5 * (r - y) / (1.0 - k.kr),
    ]
}

/// Full-range float YCbCr to RGB.
#[must_use]
pub fn ycbcr_to_rgb(ycbcr: [f64; 3], k: LumaWeights) -> [f64; 3] {
    let [y, cb, cr] = ycbcr;
    let r = y + 2.0 * (1.0 - k.kr) * cr;
    let b = y + 2.0 * (1.0 - k.kb) * cb;
    let g = (y - k.kr * r - k.kb * b) / (1.0 - k.kr - k.kb);
    [r, g, b]
}

/// Full-range float YCbCr to 8-bit code values in `range`, unrounded (studio: Y 16 + 219 Y,
/// C 128 + 224 C; full: Y 255 Y, C 128 + 255 C).
#[must_use]
pub fn ycbcr_codes(ycbcr: [f64; 3], range: YCbCrRange) -> [f64; 3] {
    let [y, cb, cr] = ycbcr;
    match range {
        YCbCrRange::Full => [255.0 * y, 128.0 + 255.0 * cb, 128.0 + 255.0 * cr],
        YCbCrRange::Studio => [16.0 + 219.0 * y, 128.0 + 224.0 * cb, 128.0 + 224.0 * cr],
    }
}

/// Full-range float YCbCr as floats in `range`: code value / 255 (identity for `Full`).
#[must_use]
pub fn ycbcr_in_range(ycbcr: [f64; 3], range: YCbCrRange) -> [f64; 3] {
    match range {
        YCbCrRange::Full => ycbcr,
        YCbCrRange::Studio => ycbcr_codes(ycbcr, range).map(|c| c / 255.0),
    }
}

/// Full-range float YCbCr to 8-bit code values in `range`, rounded half away from zero
/// (as ITU-R BT.2100 specifies; colour-science does the same) and
/// clamped to 0..=255.
#[must_use]
pub fn ycbcr_to_8bit(ycbcr: [f64; 3], range: YCbCrRange) -> [u8; 3] {
    ycbcr_codes(ycbcr, range).map(|c| c.clamp(0.0, 255.0).round() as u8)
}

/// 8-bit code values in `range` to full-range float YCbCr.
#[must_use]
pub fn ycbcr_from_8bit(codes: [u8; 3], range: YCbCrRange) -> [f64; 3] {
    let [y, cb, cr] = codes.map(f64::from);
    match range {
        YCbCrRange::Full => [y / 255.0, (cb - 128.0) / 255.0, (cr - 128.0) / 255.0],
        YCbCrRange::Studio => [
            (y - 16.0) / 219.0,
            (cb - 128.0) / 224.0,
            (cr - 128.0) / 224.0,
        ],
    }
}

/// RGB to YIQ with the rounded FCC coefficients of Python's `colorsys.rgb_to_yiq`
/// (Y = 0.30 R + 0.59 G + 0.11 B, I = 0.74 (R - Y) - 0.27 (B - Y),
/// Q = 0.48 (R - Y) + 0.41 (B - Y)).
#[must_use]
pub fn rgb_to_yiq_fcc(rgb: [f64; 3]) -> [f64; 3] {
    let [r, g, b] = rgb;
    let y = 0.30 * r + 0.59 * g + 0.11 * b;
    [
        y,
        0.74 * (r - y) - 0.27 * (b - y),
        0.48 * (r - y) + 0.41 * (b - y),
    ]
}
