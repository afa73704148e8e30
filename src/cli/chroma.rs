//! `realist chroma`: the CIE chromaticity diagram to PNG or SVG, with gamut coverage and an
//! image's out-of-gamut fractions printed.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use clap::Args;

use realist::color::{self, Illuminant, Observer, RgbSpace, Transfer};
use realist::overlay::chroma::{self, gamut, ChromaOptions, FillStyle, Marker, PixelStyle, Plane};

#[derive(Args)]
pub(crate) struct ChromaArgs {
    /// Output file (PNG, or SVG with --svg).
    #[arg(short, long)]
    output: PathBuf,
    /// Plane: xy (CIE 1931), uv (CIE 1960) or u'v' (CIE 1976).
    #[arg(long, default_value = "xy")]
    diagram: String,
    /// Width and height in pixels.
    #[arg(long, default_value_t = 1024)]
    size: u32,
    /// Comma-separated gamuts: srgb, bt709, display-p3, dci-p3, rec2020, adobe-rgb, cie-rgb,
    /// or six numbers x1,y1,x2,y2,x3,y3 for custom primaries (white D65).
    #[arg(long)]
    gamut: Option<String>,
    /// Comma-separated illuminants to mark: a, c, d50, d65, e, or a temperature like 5000K
    /// (a black body).
    #[arg(long)]
    white: Option<String>,
    /// Draw the Planckian locus with iso-temperature ticks.
    #[arg(long)]
    planckian: bool,
    /// Plot the chromaticities of an image's pixels (PNG or JPEG, sRGB).
    #[arg(long)]
    pixels: Option<PathBuf>,
    /// Draw --pixels as a density heat map instead of coloured dots.
    #[arg(long)]
    density: bool,
    /// CSV of points to mark: x,y[,label] per line (xy chromaticities; a header is skipped).
    #[arg(long)]
    points: Option<PathBuf>,
    /// Write SVG instead of PNG.
    #[arg(long)]
    svg: bool,
    /// Fill of the horseshoe: smooth (default), colour-science (their clipped look) or none.
    #[arg(long, default_value = "smooth")]
    fill: String,
    /// Observer: 1931 (2 degree) or 1964 (10 degree).
    #[arg(long, default_value = "1931")]
    observer: String,
    /// Title (default: the gamuts' names).
    #[arg(long)]
    title: Option<String>,
}

/// Parses `--gamut`: names, or runs of six numbers for custom primaries.
pub(crate) fn parse_gamuts(s: &str) -> Result<Vec<RgbSpace>> {
    let tokens: Vec<&str> = s
        .split(',')
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .collect();
    let mut out = Vec::new();
    let mut i = 0;
    let mut custom = 0;
    while i < tokens.len() {
        if tokens[i].parse::<f64>().is_ok() {
            let nums: Vec<f64> = tokens
                .get(i..i + 6)
                .context("custom gamut needs six numbers x1,y1,x2,y2,x3,y3")?
                .iter()
                .map(|t| {
                    t.parse::<f64>()
                        .with_context(|| format!("bad number '{t}' in --gamut"))
                })
                .collect::<Result<_>>()?;
            custom += 1;
            let p = [[nums[0], nums[1]], [nums[2], nums[3]], [nums[4], nums[5]]];
            let d65 = Illuminant::D65.xy(Observer::Cie1931);
            let space =
                RgbSpace::new(&format!("custom {custom}"), p, d65, "D65", Transfer::Srgb)
                    .map_err(|e| anyhow::anyhow!("--gamut {}: {e}", tokens[i..i + 6].join(",")))?;
            if p.iter().flatten().any(|v| !(-0.5..=1.5).contains(v)) {
                bail!("--gamut custom primaries must be chromaticities (got {nums:?})");
            }
            out.push(space);
            i += 6;
        } else {
            let space = RgbSpace::named(tokens[i]).with_context(|| {
                format!(
                    "unknown gamut '{}' (expected {} or six numbers)",
                    tokens[i],
                    RgbSpace::NAMES.join(", ")
                )
            })?;
            out.push(space);
            i += 1;
        }
    }
    Ok(out)
}

/// Parses `--white`: illuminant names or temperatures (`5000K`).
pub(crate) fn parse_whites(s: &str, observer: Observer) -> Result<Vec<Marker>> {
    s.split(',')
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .map(|t| {
            if let Some(k) = t.strip_suffix(['K', 'k']) {
                let kelvin: f64 = k.parse().with_context(|| format!("bad temperature '{t}' in --white"))?;
                if !(500.0..=1e6).contains(&kelvin) {
                    bail!("--white temperature {t} outside 500..1000000 K");
                }
                return Ok(Marker { xy: color::planckian_xy(kelvin), label: format!("{kelvin} K") });
            }
            let ill = Illuminant::named(t)
                .with_context(|| format!("unknown illuminant '{t}' in --white (expected a, c, d50, d65, e or e.g. 5000K)"))?;
            Ok(Marker { xy: ill.xy(observer), label: ill.name().to_owned() })
        })
        .collect()
}

/// Parses a CSV of `x,y[,label]` lines; a first line that does not start with a number is a
/// header. Errors name the file and line.
pub(crate) fn parse_points(path: &std::path::Path, text: &str) -> Result<Vec<Marker>> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let num = |i: usize| {
            fields
                .get(i)
                .and_then(|f| f.parse::<f64>().ok())
                .filter(|v| v.is_finite())
        };
        match (num(0), num(1)) {
            (Some(x), Some(y)) => out.push(Marker {
                xy: [x, y],
                label: fields.get(2..).map(|r| r.join(",")).unwrap_or_default(),
            }),
            _ if n == 0 => {}
            _ => bail!(
                "{}:{}: expected x,y[,label], got '{line}'",
                path.display(),
                n + 1
            ),
        }
        if out.len() > 100_000 {
            bail!("{}: more than 100000 points", path.display());
        }
    }
    Ok(out)
}

pub(crate) fn chroma(args: &ChromaArgs) -> Result<()> {
    let plane = Plane::named(&args.diagram).with_context(|| {
        format!(
            "unknown --diagram '{}' (expected xy, uv or u'v')",
            args.diagram
        )
    })?;
    let observer = match args.observer.as_str() {
        "1931" | "2" => Observer::Cie1931,
        "1964" | "10" => Observer::Cie1964,
        o => bail!("unknown --observer '{o}' (expected 1931 or 1964)"),
    };
    let fill = match args.fill.to_ascii_lowercase().as_str() {
        "smooth" => FillStyle::Smooth,
        "colour-science" | "color-science" => FillStyle::ColourScience,
        "none" => FillStyle::None,
        f => bail!("unknown --fill '{f}' (expected smooth, colour-science or none)"),
    };
    if !(128..=8192).contains(&args.size) {
        bail!("--size must be between 128 and 8192");
    }
    let gamuts = match &args.gamut {
        Some(g) => parse_gamuts(g)?,
        None => Vec::new(),
    };
    let illuminants = match &args.white {
        Some(w) => parse_whites(w, observer)?,
        None => Vec::new(),
    };
    let points = match &args.points {
        Some(p) => {
            let text = std::fs::read_to_string(p).with_context(|| format!("{}", p.display()))?;
            parse_points(p, &text)?
        }
        None => Vec::new(),
    };
    let pixels = match &args.pixels {
        Some(p) => {
            let image = realist::load::load_texture(p)?;
            let analysed = if gamuts.is_empty() {
                vec![RgbSpace::srgb()]
            } else {
                gamuts.clone()
            };
            Some(chroma::pixels::analyse(&image, &analysed))
        }
        None => None,
    };
    let opts = ChromaOptions {
        plane,
        size: args.size,
        observer,
        fill,
        gamuts: gamuts.clone(),
        illuminants,
        planckian: args.planckian,
        points,
        pixels,
        pixel_style: if args.density {
            PixelStyle::Density
        } else {
            PixelStyle::Scatter
        },
        title: args.title.clone(),
    };
    let start = Instant::now();
    let canvas = chroma::diagram(&opts);
    let bytes = if args.svg {
        canvas.to_svg().into_bytes()
    } else {
        canvas
            .to_png()
            .map_err(|e| anyhow::anyhow!("encoding PNG: {e}"))?
    };
    let ms = start.elapsed().as_secs_f64() * 1e3;
    std::fs::write(&args.output, bytes)
        .with_context(|| format!("writing {}", args.output.display()))?;
    say!(
        "wrote {} ({} px, {:.0} ms)",
        args.output.display(),
        args.size,
        ms
    );
    report_coverage(&gamuts, observer)?;
    if let Some(px) = &opts.pixels {
        let lit = px.total - px.dark;
        say!(
            "{}: {} pixels, {} too dark for a chromaticity (Y < {})",
            px.name,
            px.total,
            px.dark,
            chroma::pixels::DARK_Y
        );
        for (name, frac) in &px.outside {
            say!("  outside {name}: {:.4}% of {lit} pixels", frac * 100.0);
        }
    }
    Ok(())
}

fn report_coverage(gamuts: &[RgbSpace], observer: Observer) -> Result<()> {
    if gamuts.is_empty() {
        return Ok(());
    }
    let srgb = RgbSpace::srgb();
    say!("gamut                 area xy  visible xy  area u'v'  visible u'v'  vs sRGB xy  vs sRGB u'v'");
    for g in gamuts {
        let (axy, auv) = (gamut::area(g, Plane::Xy), gamut::area(g, Plane::UvPrime));
        say!(
            "{:<20} {:>8.4} {:>10.1}% {:>10.4} {:>12.1}% {:>10.1}% {:>12.1}%",
            g.name,
            axy,
            100.0 * gamut::visible_coverage(g, observer, Plane::Xy),
            auv,
            100.0 * gamut::visible_coverage(g, observer, Plane::UvPrime),
            100.0 * axy / gamut::area(&srgb, Plane::Xy),
            100.0 * auv / gamut::area(&srgb, Plane::UvPrime),
        );
    }
    if gamuts.len() > 1 {
        say!("coverage (row covers this much of column), xy / u'v':");
        for a in gamuts {
            let cells: Vec<String> = gamuts
                .iter()
                .map(|b| {
                    format!(
                        "{:>5.1}/{:>5.1}%",
                        100.0 * gamut::coverage(a, b, Plane::Xy),
                        100.0 * gamut::coverage(a, b, Plane::UvPrime)
                    )
                })
                .collect();
            say!("  {:<20} {}", a.name, cells.join("  "));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gamut_white_and_points_parsing() {
        let g = parse_gamuts("srgb, display-p3,0.7,0.3,0.2,0.7,0.15,0.05,rec2020").unwrap();
        let names: Vec<&str> = g.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["sRGB", "Display P3", "custom 1", "ITU-R BT.2020"]);
        assert!(parse_gamuts("srgb,0.7,0.3").is_err());
        assert!(parse_gamuts("0.1,0.1,0.2,0.2,0.3,0.3")
            .unwrap_err()
            .to_string()
            .contains("collinear"));
        assert!(parse_gamuts("nope")
            .unwrap_err()
            .to_string()
            .contains("unknown gamut 'nope'"));
        let w = parse_whites("d65,A,5000K", Observer::Cie1931).unwrap();
        assert_eq!(w[0].xy, [0.3127, 0.329]);
        assert_eq!(w[1].label, "A");
        assert!((w[2].xy[0] - 0.3451).abs() < 1e-3, "{:?}", w[2].xy);
        assert!(parse_whites("d66", Observer::Cie1931).is_err());
        let p = std::path::Path::new("p.csv");
        let pts = parse_points(p, "x,y,name\n0.3,0.3,a, b\n\n0.4,0.5\n").unwrap();
        assert_eq!(pts.len(), 2);
        assert_eq!(pts[0].label, "a,b");
        let err = parse_points(p, "0.3,0.3\n0.3,zz\n")
            .unwrap_err()
            .to_string();
        assert_eq!(err, "p.csv:2: expected x,y[,label], got '0.3,zz'");
    }
}
