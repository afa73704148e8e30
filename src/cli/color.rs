//! `realist color VALUE`: one colour in every model, with the conventions of the
//! colour-science reference (`../shared/color/reference.json`).

use anyhow::{bail, Result};
use clap::Args;

use realist::color::named::convert;

/// Every model `--to` accepts, in output order.
pub(crate) use realist::color::named::MODELS;

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
    realist::color::named::parse_colour(s).map_err(anyhow::Error::msg)
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
