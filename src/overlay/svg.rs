//! The SVG backend of [`Canvas`](super::Canvas): paths as `<path>`, text as outline paths
//! (with the string in `aria-label`), images as embedded PNG, clips as nested groups.

use std::fmt::Write as _;

use base64::Engine as _;

use super::canvas::{Item, Stroke};
use super::path::Color;

fn rgb(c: Color) -> String {
    format!("#{:02x}{:02x}{:02x}", c.r, c.g, c.b)
}

fn opacity(attr: &str, c: Color) -> String {
    if c.a == 255 {
        String::new()
    } else {
        format!(" {attr}=\"{:.3}\"", f32::from(c.a) / 255.0)
    }
}

/// Escapes text for XML attributes and content.
pub(crate) fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for ch in s.chars() {
        match ch {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' => {}
            c => out.push(c),
        }
    }
    out
}

fn stroke_attrs(s: &Stroke) -> String {
    let mut a = format!(" fill=\"none\" stroke-width=\"{}\"", s.width);
    if s.round {
        a.push_str(" stroke-linecap=\"round\" stroke-linejoin=\"round\"");
    }
    if let Some(d) = &s.dash {
        let list: Vec<String> = d.iter().map(|v| v.to_string()).collect();
        let _ = write!(a, " stroke-dasharray=\"{}\"", list.join(" "));
    }
    a
}

pub(crate) fn write(width: u32, height: u32, background: Option<Color>, items: &[Item]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\">"
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
    let mut clip_id = 0usize;
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
            Item::Image(x, y, img) => {
                if let Some(png) = img.to_pixmap().and_then(|p| p.encode_png().ok()) {
                    let data = base64::engine::general_purpose::STANDARD.encode(png);
                    let _ = writeln!(
                        out,
                        "<image x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" href=\"data:image/png;base64,{data}\"/>",
                        x.round(),
                        y.round(),
                        img.width,
                        img.height
                    );
                }
            }
            Item::ClipPush(p) => {
                clip_id += 1;
                let _ = writeln!(
                    out,
                    "<clipPath id=\"clip{clip_id}\"><path d=\"{}\"/></clipPath>\n<g clip-path=\"url(#clip{clip_id})\">",
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
