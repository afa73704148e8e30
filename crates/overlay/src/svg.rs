//! The SVG backend of [`Canvas`](super::Canvas): a standalone SVG 1.1 document.
//!
//! One recorded item becomes one element, in paint order, so the document mirrors the
//! display list: a fill, stroke or text is one `<path>` (text as its outlines, the string
//! in `aria-label` so the document stays searchable without a font), an image is one
//! `<image>` holding a base64 PNG, and a clip is a `<clipPath>` (one `<path>`) plus a
//! `<g clip-path>` that encloses everything up to its pop, so nested clips intersect as in
//! the raster backend. Colours are `#rrggbb` with a separate `*-opacity` when not opaque.
//! Items are already normalised by the canvas (finite, drawable), so nothing is dropped
//! here and no NaN can reach the output. Text content is escaped, and characters XML 1.0
//! forbids are left out, so the output is well-formed XML.

use std::fmt::Write as _;

use base64::Engine as _;

use super::canvas::{Item, Stroke};
use super::path::Color;

/// Prefix of clip ids, to keep them apart from ids of a page this SVG is inlined in.
const CLIP_ID: &str = "realist-clip";

fn rgb(c: Color) -> String {
    format!("#{:02x}{:02x}{:02x}", c.r, c.g, c.b)
}

/// ` attr="alpha"` with three decimals (finer than 8-bit alpha), or nothing if opaque.
fn opacity(attr: &str, c: Color) -> String {
    if c.a == u8::MAX {
        String::new()
    } else {
        format!(" {attr}=\"{:.3}\"", f32::from(c.a) / 255.0)
    }
}

/// Escapes text for XML attributes and content, dropping characters XML 1.0 forbids
/// (control characters other than tab and newline, U+FFFE and U+FFFF).
pub(crate) fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' => out.push(ch),
            c if c < ' ' || c == '\u{fffe}' || c == '\u{ffff}' => {}
            c => out.push(c),
        }
    }
    out
}

/// Attributes of a normalised stroke (finite positive width, valid even dash list).
fn stroke_attrs(s: &Stroke) -> String {
    let mut a = format!(" fill=\"none\" stroke-width=\"{}\"", s.width);
    if s.round {
        a.push_str(" stroke-linecap=\"round\" stroke-linejoin=\"round\"");
    }
    if let Some(d) = &s.dash {
        let list: Vec<String> = d.iter().map(f32::to_string).collect();
        let _ = write!(a, " stroke-dasharray=\"{}\"", list.join(" "));
    }
    a
}

/// The document for a canvas of `width` x `height` pixels.
pub(crate) fn write(width: u32, height: u32, background: Option<Color>, items: &[Item]) -> String {
    let mut out = String::new();
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\" \
         version=\"1.1\" width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\">"
    );
    if let Some(bg) = background {
        let _ = writeln!(
            out,
            "<rect width=\"{width}\" height=\"{height}\" fill=\"{}\"{}/>",
            rgb(bg),
            opacity("fill-opacity", bg)
        );
    }
    let mut depth = 0usize;
    let mut clips = 0usize;
    for item in items {
        match item {
            Item::Fill(p, c) => {
                let _ = writeln!(
                    out,
                    "<path d=\"{}\" fill=\"{}\"{}/>",
                    p.to_svg_data(),
                    rgb(*c),
                    opacity("fill-opacity", *c)
                );
            }
            Item::Text(p, c, text) => {
                let _ = writeln!(
                    out,
                    "<path d=\"{}\" fill=\"{}\"{} role=\"img\" aria-label=\"{}\"/>",
                    p.to_svg_data(),
                    rgb(*c),
                    opacity("fill-opacity", *c),
                    escape(text)
                );
            }
            Item::Stroke(p, c, s) => {
                let _ = writeln!(
                    out,
                    "<path d=\"{}\" stroke=\"{}\"{}{}/>",
                    p.to_svg_data(),
                    rgb(*c),
                    opacity("stroke-opacity", *c),
                    stroke_attrs(s)
                );
            }
            Item::Image(x, y, pm) => {
                // Encoding a valid in-memory pixmap does not fail in practice; if it did,
                // the image would be missing from the SVG only.
                if let Ok(png) = pm.encode_png() {
                    let data = base64::engine::general_purpose::STANDARD.encode(png);
                    let _ = writeln!(
                        out,
                        "<image x=\"{x}\" y=\"{y}\" width=\"{}\" height=\"{}\" \
                         xlink:href=\"data:image/png;base64,{data}\"/>",
                        pm.width(),
                        pm.height()
                    );
                }
            }
            Item::ClipPush(p) => {
                clips += 1;
                // An empty `d` renders nothing, so the clip hides everything, as in the
                // raster backend.
                let _ = writeln!(
                    out,
                    "<clipPath id=\"{CLIP_ID}{clips}\"><path d=\"{}\"/></clipPath>\n\
                     <g clip-path=\"url(#{CLIP_ID}{clips})\">",
                    p.to_svg_data()
                );
                depth += 1;
            }
            Item::ClipPop => {
                if depth > 0 {
                    depth -= 1;
                    out.push_str("</g>\n");
                }
            }
        }
    }
    for _ in 0..depth {
        out.push_str("</g>\n");
    }
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::super::tests::{BLUE, RED};
    use super::super::{Canvas, Color, HAlign, Path2, RgbaImage, Stroke, VAlign};
    use super::*;

    /// A minimal XML well-formedness check: tags balance, attributes are quoted, no stray `<`
    /// or `&`.
    pub(crate) fn check_xml(s: &str) -> Result<usize, String> {
        let body = s
            .strip_prefix("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n")
            .ok_or("no XML declaration")?;
        let mut stack: Vec<String> = Vec::new();
        let mut elements = 0;
        let mut rest = body;
        while let Some(start) = rest.find('<') {
            let text = &rest[..start];
            if text.contains('>') {
                return Err(format!("stray '>' in {text:?}"));
            }
            let end = rest[start..].find('>').ok_or("unclosed tag")? + start;
            let tag = &rest[start + 1..end];
            if tag.matches('"').count() % 2 != 0 || tag.contains('<') {
                return Err(format!("bad tag {tag:?}"));
            }
            if let Some(name) = tag.strip_prefix('/') {
                if stack.pop().as_deref() != Some(name) {
                    return Err(format!("mismatched </{name}>"));
                }
            } else {
                elements += 1;
                let name: String = tag
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric())
                    .collect();
                if !tag.ends_with('/') {
                    stack.push(name);
                }
            }
            rest = &rest[end + 1..];
        }
        if stack.is_empty() {
            Ok(elements)
        } else {
            Err(format!("unclosed {stack:?}"))
        }
    }

    #[test]
    fn svg_is_well_formed_and_complete() {
        let mut c = Canvas::new(40, 30);
        c.background(Color::rgb(250, 250, 250));
        c.clip_push(&Path2::new().circle(20.0, 15.0, 10.0));
        c.fill(
            &Path2::new().rect(0.0, 0.0, 40.0, 30.0),
            RED.with_alpha(128),
        );
        c.image(
            1.0,
            1.0,
            RgbaImage {
                width: 2,
                height: 2,
                pixels: vec![[1, 2, 3, 255]; 4],
            },
        );
        c.clip_pop();
        c.stroke(
            &Path2::new().move_to(0.0, 0.0).line_to(40.0, 30.0),
            BLUE,
            &Stroke {
                width: 1.5,
                dash: Some(vec![4.0, 2.0]),
                round: true,
            },
        );
        c.text(
            "a<b & \"c\"",
            2.0,
            28.0,
            10.0,
            BLUE,
            HAlign::Left,
            VAlign::Baseline,
        );
        c.clip_push(&Path2::new().rect(0.0, 0.0, 1.0, 1.0));
        let svg = c.to_svg();
        let elements = check_xml(&svg).unwrap_or_else(|e| panic!("{e}\n{svg}"));
        assert!(elements >= 9, "{elements}");
        assert_eq!(svg.matches("<clipPath").count(), 2);
        assert_eq!(
            svg.matches("<path").count(),
            5,
            "fill, stroke, text, two clips:\n{svg}"
        );
        assert!(svg.contains("xlink:href=\"data:image/png;base64,iVBORw0KGgo"));
        // One `<path` per fill, stroke and text item and per clip.
        let drawn = c
            .items
            .iter()
            .filter(|i| !matches!(i, Item::Image(..) | Item::ClipPop))
            .count();
        assert_eq!(svg.matches("<path").count(), drawn);
        assert!(svg.contains("aria-label=\"a&lt;b &amp; &quot;c&quot;\""));
        assert!(svg.contains("stroke-dasharray=\"4 2\"") && svg.contains("fill-opacity=\"0.502\""));
        assert!(
            check_xml("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg><g></svg>").is_err(),
            "the checker can fail"
        );
    }
}
