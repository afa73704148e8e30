//! `realist color VALUE`: one colour in every model, with the conventions of the
//! colour-science reference (`../shared/color/reference.json`).

use anyhow::{bail, Context, Result};
use clap::Args;

use realist::color::{self, Illuminant, LumaWeights, Observer};

/// Every model `--to` accepts, in output order.
pub(crate) const MODELS: [&str; 16] = [
    "linear", "hsv", "hsl", "cmy", "cmyk", "yiq", "yuv", "ycbcr601", "ycbcr709", "xyz", "xyy",
    "uv", "u'v'", "lab", "lch", "luv",
];

#[derive(Args)]
pub(crate) struct ColorArgs {
    /// The colour: `#rrggbb` (or `#rgb`), or `r,g,b` as encoded sRGB floats in [0, 1].
    value: String,
    /// Comma-separated models (default: all): linear, hsv, hsl, cmy, cmyk, yiq, yuv, ycbcr601,
    /// ycbcr709, xyz, xyy, uv, u'v', lab, lch, luv.
    #[arg(long)]
    to: Option<String>,
    /// Print one JSON object keyed by model name, each an array of floats.
    #[arg(long)]
    json: bool,
}

/// Parses `#rrggbb`, `#rgb` or `r,g,b` into encoded sRGB floats.
pub(crate) fn parse_colour(s: &str) -> Result<[f64; 3]> {
    let s = s.trim();
    if let Some(hex) = s.strip_prefix('#') {
        let digits: Vec<u32> = hex
            .chars()
            .map(|c| c.to_digit(16))
            .collect::<Option<_>>()
            .with_context(|| format!("'{s}' is not a hex colour"))?;
        let channels: Vec<u32> = match digits.len() {
            3 => digits.iter().map(|d| d * 17).collect(),
            6 => digits.chunks(2).map(|p| p[0] * 16 + p[1]).collect(),
            _ => bail!("'{s}': expected #rrggbb or #rgb"),
        };
        return Ok([0, 1, 2].map(|i| f64::from(channels[i]) / 255.0));
    }
    let parts: Vec<f64> = s
        .split(',')
        .map(|p| {
            p.trim()
                .parse::<f64>()
                .with_context(|| format!("bad number '{p}' in '{s}'"))
        })
        .collect::<Result<_>>()?;
    match parts[..] {
        [r, g, b] if [r, g, b].iter().all(|v| (0.0..=1.0).contains(v)) => Ok([r, g, b]),
        [_, _, _] => bail!("'{s}': r,g,b must be encoded sRGB values between 0 and 1"),
        _ => bail!("'{s}': expected #rrggbb or r,g,b"),
    }
}

/// `rgb` (encoded sRGB) in `model`, or `None` for an unknown model name.
#[must_use]
pub(crate) fn convert(rgb: [f64; 3], model: &str) -> Option<Vec<f64>> {
    let d65 = Illuminant::D65.xyz(Observer::Cie1931);
    let xyz = color::srgb_to_xyz(rgb);
    let xyy = color::xyz_to_xyy(xyz);
    let xy = [xyy[0], xyy[1]];
    Some(match model {
        "linear" => color::srgb_decode3(rgb).to_vec(),
        "hsv" => color::rgb_to_hsv(rgb).to_vec(),
        "hsl" => color::rgb_to_hsl(rgb).to_vec(),
        "cmy" => color::rgb_to_cmy(rgb).to_vec(),
        "cmyk" => color::cmy_to_cmyk(color::rgb_to_cmy(rgb)).to_vec(),
        "yiq" => color::rgb_to_yiq(rgb).to_vec(),
        "yuv" => color::rgb_to_yuv(rgb).to_vec(),
        "ycbcr601" => color::rgb_to_ycbcr(rgb, LumaWeights::BT601).to_vec(),
        "ycbcr709" => color::rgb_to_ycbcr(rgb, LumaWeights::BT709).to_vec(),
        "xyz" => xyz.to_vec(),
        "xyy" => xyy.to_vec(),
        "uv" => color::xy_to_uv1960(xy).to_vec(),
        "u'v'" | "uv'" | "u'v" => color::xy_to_uv_prime(xy).to_vec(),
        "lab" => color::xyz_to_lab(xyz, d65).to_vec(),
        "lch" => color::lab_to_lch(color::xyz_to_lab(xyz, d65)).to_vec(),
        "luv" => color::xyz_to_luv(xyz, d65).to_vec(),
        _ => return None,
    })
}

pub(crate) fn color(args: &ColorArgs) -> Result<()> {
    let rgb = parse_colour(&args.value)?;
    let models: Vec<String> = match &args.to {
        None => MODELS.iter().map(|m| (*m).to_owned()).collect(),
        Some(list) => list
            .split(',')
            .map(|m| m.trim().to_ascii_lowercase())
            .collect(),
    };
    let mut out = serde_json::Map::new();
    let mut lines = Vec::new();
    for m in &models {
        let Some(v) = convert(rgb, m) else {
            bail!(
                "unknown model '{m}' in --to (expected {})",
                MODELS.join(", ")
            );
        };
        lines.push(format!(
            "{m:<9} {}",
            v.iter()
                .map(|x| format!("{x:>10.6}"))
                .collect::<Vec<_>>()
                .join(" ")
        ));
        out.insert(m.clone(), serde_json::json!(v));
    }
    if args.json {
        say!("{}", serde_json::Value::Object(out));
    } else {
        let hex: String = rgb
            .iter()
            .map(|c| format!("{:02x}", (c * 255.0).round() as u8))
            .collect();
        say!(
            "sRGB      {:>10.6} {:>10.6} {:>10.6}  (#{hex}; D65, 2 degree observer)",
            rgb[0],
            rgb[1],
            rgb[2]
        );
        for l in lines {
            say!("{l}");
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_hex_and_floats_and_refuses_garbage() {
        assert_eq!(parse_colour("#ff8000").unwrap(), [1.0, 128.0 / 255.0, 0.0]);
        assert_eq!(parse_colour("#f80").unwrap(), [1.0, 136.0 / 255.0, 0.0]);
        assert_eq!(parse_colour(" 0.25, 0.5,0.75 ").unwrap(), [0.25, 0.5, 0.75]);
        for bad in [
            "#ff80",
            "#gg0000",
            "1,2",
            "0.5,0.5,1.5",
            "a,b,c",
            "",
            "nan,0,0",
        ] {
            assert!(parse_colour(bad).is_err(), "{bad}");
        }
        assert!(convert([0.0; 3], "nope").is_none());
        assert!(MODELS.iter().all(|m| convert([0.2, 0.4, 0.6], m).is_some()));
    }
}
