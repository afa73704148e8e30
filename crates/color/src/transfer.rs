//! The sRGB transfer functions of IEC 61966-2-1, exactly as the standard states them
//! (piecewise: a linear segment near black, a 2.4 power above). Values below zero stay on
//! the linear segment, so out-of-gamut negatives survive a round trip (as in colour-science).

/// Encoded sRGB value below which [`srgb_decode`] is linear.
const DECODE_KNEE: f64 = 0.04045;
/// Linear value below which [`srgb_encode`] is linear (`DECODE_KNEE / 12.92`, as published).
const ENCODE_KNEE: f64 = 0.003_130_8;

/// sRGB EOTF: encoded (non-linear) value to linear light.
#[must_use]
pub fn srgb_decode(v: f64) -> f64 {
    if v <= DECODE_KNEE {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// sRGB inverse EOTF: linear light to the encoded (non-linear) value.
#[must_use]
pub fn srgb_encode(v: f64) -> f64 {
    if v <= ENCODE_KNEE {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// [`srgb_decode`] per component.
#[must_use]
pub fn srgb_decode3(rgb: [f64; 3]) -> [f64; 3] {
    rgb.map(srgb_decode)
}

/// [`srgb_encode`] per component.
#[must_use]
pub fn srgb_encode3(rgb: [f64; 3]) -> [f64; 3] {
    rgb.map(srgb_encode)
}

/// Exact sRGB decoding (IEC 61966-2-1).
#[must_use]
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Exact sRGB encoding (IEC 61966-2-1).
#[must_use]
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_and_is_continuous_at_the_knee() {
        for i in -100..=1100 {
            let v = f64::from(i) / 1000.0;
            assert!((srgb_encode(srgb_decode(v)) - v).abs() < 1e-12, "{v}");
        }
        // The two published constants meet within 1e-7 (IEC 61966-2-1 amendment note).
        let below = DECODE_KNEE / 12.92;
        let above = ((DECODE_KNEE + 0.055) / 1.055f64).powf(2.4);
        assert!((below - above).abs() < 1e-7, "{below} {above}");
        assert_eq!(srgb_decode(1.0), 1.0);
        assert_eq!(srgb_encode(0.0), 0.0);
    }
}
