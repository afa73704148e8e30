//! Canvas tests: exact coverage of aligned shapes, clips, strokes, text boxes, images, and
//! the SVG's structure.

use super::*;

const RED: Color = Color::rgb(255, 0, 0);
const BLUE: Color = Color::rgb(0, 0, 255);

fn px(pm: &tiny_skia::Pixmap, x: u32, y: u32) -> [u8; 4] {
    let c = pm.pixel(x, y).unwrap().demultiply();
    [c.red(), c.green(), c.blue(), c.alpha()]
}

/// Bounding box `(x0, y0, x1, y1)` (inclusive) of pixels with alpha above `min`.
fn ink(pm: &tiny_skia::Pixmap, min: u8) -> Option<(u32, u32, u32, u32)> {
    let mut b: Option<(u32, u32, u32, u32)> = None;
    for y in 0..pm.height() {
        for x in 0..pm.width() {
            if px(pm, x, y)[3] > min {
                b = Some(match b {
                    None => (x, y, x, y),
                    Some((a, c, d, e)) => (a.min(x), c.min(y), d.max(x), e.max(y)),
                });
            }
        }
    }
    b
}

#[test]
fn aligned_rect_covers_exactly_its_pixels() {
    let mut c = Canvas::new(20, 10);
    c.fill(&Path2::new().rect(3.0, 2.0, 5.0, 4.0), RED);
    let pm = c.to_pixmap();
    for y in 0..10 {
        for x in 0..20 {
            let inside = (3..8).contains(&x) && (2..6).contains(&y);
            assert_eq!(
                px(&pm, x, y),
                if inside { [255, 0, 0, 255] } else { [0; 4] },
                "({x}, {y})"
            );
        }
    }
}

#[test]
fn clips_intersect_and_pop() {
    let mut c = Canvas::new(20, 20);
    c.clip_push(&Path2::new().rect(0.0, 0.0, 10.0, 20.0));
    c.clip_push(&Path2::new().rect(5.0, 0.0, 15.0, 10.0));
    c.fill(&Path2::new().rect(0.0, 0.0, 20.0, 20.0), RED);
    c.clip_pop();
    c.fill(&Path2::new().rect(0.0, 15.0, 20.0, 5.0), BLUE);
    c.clip_pop();
    c.fill(&Path2::new().rect(15.0, 0.0, 5.0, 5.0), BLUE);
    let pm = c.to_pixmap();
    assert_eq!(px(&pm, 7, 5), [255, 0, 0, 255], "inside both clips");
    assert_eq!(px(&pm, 2, 5)[3], 0, "outside the inner clip");
    assert_eq!(
        px(&pm, 17, 2),
        [0, 0, 255, 255],
        "no clip after the last pop"
    );
    assert_eq!(px(&pm, 12, 5)[3], 0, "outside the outer clip");
    assert_eq!(
        px(&pm, 7, 12)[3],
        0,
        "outside the inner clip, inside the outer"
    );
    assert_eq!(px(&pm, 5, 17), [0, 0, 255, 255], "outer clip only");
    assert_eq!(px(&pm, 15, 17)[3], 0, "outer clip still applies");
    assert_eq!(ink(&pm, 0), Some((0, 0, 19, 19)));
}

#[test]
fn stroke_width_is_in_pixels() {
    let mut c = Canvas::new(20, 20);
    c.stroke(
        &Path2::new().move_to(2.0, 10.0).line_to(18.0, 10.0),
        RED,
        &Stroke::solid(2.0),
    );
    let pm = c.to_pixmap();
    assert_eq!(ink(&pm, 200), Some((2, 9, 17, 10)));
    assert_eq!(ink(&pm, 0), Some((2, 9, 17, 10)));
}

#[test]
fn text_ink_stays_in_its_predicted_box() {
    let (size, x, y) = (20.0, 10.0, 30.0);
    let mut c = Canvas::new(80, 50);
    c.text("Hg", x, y, size, RED, HAlign::Left, VAlign::Baseline);
    let (w, ascent, descent) = text_extent("Hg", size);
    let (x0, y0, x1, y1) = ink(&c.to_pixmap(), 0).expect("text draws ink");
    assert!(
        x0 as f32 >= x - 1.0 && x1 as f32 <= x + w + 1.0,
        "{x0}..{x1} vs {w}"
    );
    assert!(
        y0 as f32 >= y - ascent - 1.0 && y1 as f32 <= y + descent + 1.0,
        "{y0}..{y1}"
    );
    // H reaches the cap height and g descends below the baseline.
    assert!(
        (y0 as f32) < y - 0.6 * size && y1 as f32 > y + 0.1 * size,
        "{y0}..{y1}"
    );
    assert!(text_extent("ii", 20.0).0 < text_extent("WW", 20.0).0);

    let mut c = Canvas::new(100, 40);
    c.text(
        "centre",
        50.0,
        20.0,
        16.0,
        RED,
        HAlign::Center,
        VAlign::Middle,
    );
    let (x0, y0, x1, y1) = ink(&c.to_pixmap(), 0).unwrap();
    assert!((((x0 + x1) as f32 / 2.0) - 50.0).abs() <= 2.0, "{x0}..{x1}");
    assert!((((y0 + y1) as f32 / 2.0) - 20.0).abs() <= 3.0, "{y0}..{y1}");

    let mut c = Canvas::new(60, 120);
    c.text_rotated(
        "rotated",
        30.0,
        60.0,
        14.0,
        RED,
        HAlign::Center,
        VAlign::Middle,
        -90.0,
    );
    let (x0, y0, x1, y1) = ink(&c.to_pixmap(), 0).unwrap();
    assert!(
        y1 - y0 > 2 * (x1 - x0),
        "tall after rotation: {x0}..{x1} x {y0}..{y1}"
    );

    // Characters beyond ASCII exist in the font.
    for s in ["\u{2212}0.1", "u\u{2032}v\u{2032}", "\u{0394}E \u{00b0}"] {
        let mut c = Canvas::new(80, 30);
        c.text(s, 2.0, 15.0, 14.0, RED, HAlign::Left, VAlign::Middle);
        assert!(ink(&c.to_pixmap(), 0).is_some(), "{s}");
    }
}

#[test]
fn images_land_where_placed() {
    let pixels: Vec<[u8; 4]> = (0..16).map(|i| [i as u8 * 10, 100, 200, 255]).collect();
    let mut c = Canvas::new(10, 10);
    c.image(
        3.0,
        5.0,
        RgbaImage {
            width: 4,
            height: 4,
            pixels: pixels.clone(),
        },
    );
    let pm = c.to_pixmap();
    for j in 0..4u32 {
        for i in 0..4u32 {
            assert_eq!(px(&pm, 3 + i, 5 + j), pixels[(j * 4 + i) as usize]);
        }
    }
    assert_eq!(ink(&pm, 0), Some((3, 5, 6, 8)));
    // A malformed image is skipped, not a panic.
    c.image(
        0.0,
        0.0,
        RgbaImage {
            width: 3,
            height: 3,
            pixels: vec![[0; 4]; 2],
        },
    );
    let _ = c.to_pixmap();
    let _ = c.to_svg();
}

/// A minimal XML well-formedness check: tags balance, attributes are quoted, no stray `<`
/// or `&`.
fn check_xml(s: &str) -> Result<usize, String> {
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
    assert!(svg.contains("href=\"data:image/png;base64,iVBORw0KGgo"));
    assert!(svg.contains("aria-label=\"a&lt;b &amp; &quot;c&quot;\""));
    assert!(svg.contains("stroke-dasharray=\"4 2\"") && svg.contains("fill-opacity=\"0.502\""));
    assert!(
        check_xml("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg><g></svg>").is_err(),
        "the checker can fail"
    );
}
