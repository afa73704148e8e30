//! One colour by name in every model: what `realist color` prints and the Python bindings'
//! `color.convert` return, said once here. A colour is read from `#rrggbb`, `#rgb` or
//! `r,g,b` (encoded sRGB floats in [0, 1]); the models are named as `--to` names them.

use crate::{Illuminant, LumaWeights, Observer};

/// Every model [`convert`] knows, in output order.
pub const MODELS: [&str; 16] = [
    "linear", "hsv", "hsl", "cmy", "cmyk", "yiq", "yuv", "ycbcr601", "ycbcr709", "xyz", "xyy",
    "uv", "u'v'", "lab", "lch", "luv",
];

/// Parses `#rrggbb`, `#rgb` or `r,g,b` into encoded sRGB floats; the error names the text
/// and what is wrong with it.
pub fn parse_colour(s: &str) -> Result<[f64; 3], String> {
    let s = s.trim();
    if let Some(hex) = s.strip_prefix('#') {
        let digits: Vec<u32> = hex
            .chars()
            .map(|c| c.to_digit(16))
            .collect::<Option<_>>()
            .ok_or_else(|| format!("'{s}' is not a hex colour"))?;
        let channels: Vec<u32> = match digits.len() {
            3 => digits.iter().map(|d| d * 17).collect(),
            6 => digits.chunks(2).map(|p| p[0] * 16 + p[1]).collect(),
            _ => return Err(format!("'{s}': expected #rrggbb or #rgb")),
        };
        return Ok([0, 1, 2].map(|i| f64::from(channels[i]) / 255.0));
    }
    let parts: Vec<f64> = s
        .split(',')
        .map(|p| {
            p.trim()
                .parse::<f64>()
                .map_err(|_| format!("bad number '{p}' in '{s}'"))
        })
        .collect::<Result<_, _>>()?;
    match parts[..] {
        [r, g, b] if [r, g, b].iter().all(|v| (0.0..=1.0).contains(v)) => Ok([r, g, b]),
        [_, _, _] => Err(format!(
            "'{s}': r,g,b must be encoded sRGB values between 0 and 1"
        )),
        _ => Err(format!("'{s}': expected #rrggbb or r,g,b")),
    }
}

/// Encoded sRGB `rgb` in `model` (one of [`MODELS`]; D65 and the 2 degree observer where a
/// white is needed), or `None` for an unknown model name.
#[must_use]
pub fn convert(rgb: [f64; 3], model: &str) -> Option<Vec<f64>> {
    let d65 = Illuminant::D65.xyz(Observer::Cie1931);
    let xyz = crate::srgb_to_xyz(rgb);
    let xyy = crate::xyz_to_xyy(xyz);
    let xy = [xyy[0], xyy[1]];
    Some(match model {
        "linear" => crate::srgb_decode3(rgb).to_vec(),
        "hsv" => crate::rgb_to_hsv(rgb).to_vec(),
        "hsl" => crate::rgb_to_hsl(rgb).to_vec(),
        "cmy" => crate::rgb_to_cmy(rgb).to_vec(),
        "cmyk" => crate::cmy_to_cmyk(crate::rgb_to_cmy(rgb)).to_vec(),
        "yiq" => crate::rgb_to_yiq(rgb).to_vec(),
        "yuv" => crate::rgb_to_yuv(rgb).to_vec(),
        "ycbcr601" => crate::rgb_to_ycbcr(rgb, LumaWeights::BT601).to_vec(),
        "ycbcr709" => crate::rgb_to_ycbcr(rgb, LumaWeights::BT709).to_vec(),
        "xyz" => xyz.to_vec(),
        "xyy" => xyy.to_vec(),
        "uv" => crate::xy_to_uv1960(xy).to_vec(),
        "u'v'" | "uv'" | "u'v" => crate::xy_to_uv_prime(xy).to_vec(),
        "lab" => crate::xyz_to_lab(xyz, d65).to_vec(),
        "lch" => crate::lab_to_lch(crate::xyz_to_lab(xyz, d65)).to_vec(),
        "luv" => crate::xyz_to_luv(xyz, d65).to_vec(),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_are_read_in_every_form() {
        assert_eq!(parse_colour("#fff"), Ok([1.0; 3]));
        assert_eq!(parse_colour(" #ff0000 "), Ok([1.0, 0.0, 0.0]));
        assert_eq!(parse_colour("0.5, 0, 1"), Ok([0.5, 0.0, 1.0]));
        for bad in ["#ff00", "#zzzzzz", "1,2,3", "0.5,0.5", "a,b,c"] {
            assert!(parse_colour(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn every_model_is_known() {
        for m in MODELS {
            assert!(convert([0.2, 0.4, 0.6], m).is_some(), "{m}");
        }
        assert_eq!(convert([1.0; 3], "nope"), None);
        assert_eq!(convert([1.0, 0.0, 0.0], "hsv"), Some(vec![0.0, 1.0, 1.0]));
    }
}
