//! Canvas tests: exact coverage of aligned shapes, clips, strokes, text boxes and images
//! in the raster, and that degenerate input is dropped alike by both backends. The SVG's
//! structure is tested in `svg.rs`, font coverage and metrics in `text.rs`.

use super::svg::tests::check_xml;
use super::*;

pub(super) const RED: Color = Color::rgb(255, 0, 0);
pub(super) const BLUE: Color = Color::rgb(0, 0, 255);

/// Pixels that anti-aliasing may add around a shape's exact outline.
const AA_SLOP: f32 = 1.0;

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
    // Ink pixel (i, j) covers [i, i + 1) x [j, j + 1): allow AA_SLOP on each side.
    assert!(x0 as f32 >= x - AA_SLOP, "{x0} left of {x}");
    assert!(x1 as f32 <= x + w + AA_SLOP, "{x1} right of {x} + {w}");
    assert!(y0 as f32 >= y - ascent - AA_SLOP, "{y0} above the ascent");
    assert!(y1 as f32 <= y + descent + AA_SLOP, "{y1} below the descent");
    // ... and the box is not vacuous: H reaches the cap height, g descends, the ink spans
    // most of the advance.
    assert!(
        (y0 as f32) < y - 0.6 * size && y1 as f32 > y + 0.1 * size,
        "{y0}..{y1}"
    );
    assert!((x1 - x0) as f32 > 0.8 * w, "{x0}..{x1} of {w}");
    assert!(text_extent("ii", 20.0).0 < text_extent("WW", 20.0).0);
}

#[test]
fn text_alignment_places_the_ink() {
    /// Side bearings and AA: how far ink may sit from an alignment line, in pixels.
    const BEARING: f32 = 2.0;
    let ink_box = |h, v| {
        let mut c = Canvas::new(100, 40);
        c.text("centre", 50.0, 20.0, 16.0, RED, h, v);
        let (x0, y0, x1, y1) = ink(&c.to_pixmap(), 0).expect("text draws ink");
        // Edges of the ink in continuous coordinates.
        [x0 as f32, y0 as f32, (x1 + 1) as f32, (y1 + 1) as f32]
    };
    let [x0, y0, x1, y1] = ink_box(HAlign::Center, VAlign::Middle);
    assert!(
        ((x0 + x1) / 2.0 - 50.0).abs() <= BEARING / 2.0,
        "{x0}..{x1}"
    );
    // Middle is halfway between ascent and descent, not the ink's centre: lower-case
    // ink sits between the baseline and the x-height, a little below the anchor.
    assert!(((y0 + y1) / 2.0 - 20.0).abs() <= 3.0, "{y0}..{y1}");
    let [left, ..] = ink_box(HAlign::Left, VAlign::Middle);
    let [_, _, right, _] = ink_box(HAlign::Right, VAlign::Middle);
    assert!((left - 50.0).abs() <= BEARING && (right - 50.0).abs() <= BEARING);
    // Top: ink starts below the anchor (ascent line); Bottom: ink ends above it.
    let [_, top, ..] = ink_box(HAlign::Center, VAlign::Top);
    let [.., bottom] = ink_box(HAlign::Center, VAlign::Bottom);
    assert!(
        (20.0..=24.0).contains(&top) && (16.0..=20.0).contains(&bottom),
        "{top} {bottom}"
    );
}

#[test]
fn rotated_text_swaps_the_ink_box() {
    let boxed = |degrees| {
        let mut c = Canvas::new(120, 120);
        c.text_rotated(
            "rotated",
            60.0,
            60.0,
            14.0,
            RED,
            HAlign::Center,
            VAlign::Middle,
            degrees,
        );
        let (x0, y0, x1, y1) = ink(&c.to_pixmap(), 0).expect("text draws ink");
        (x1 - x0 + 1, y1 - y0 + 1, y0)
    };
    let (w, h, _) = boxed(0.0);
    assert!(w > 2 * h, "{w} x {h}");
    for deg in [90.0, -90.0] {
        let (rw, rh, _) = boxed(deg);
        assert!(
            rw.abs_diff(h) <= 1 && rh.abs_diff(w) <= 1,
            "{deg}: {rw} x {rh} vs {w} x {h}"
        );
    }
    // -90 reads bottom to top: the "M" of "M   " (centred on its advance, so the ink is
    // ~0.48 em before the anchor) ends up below the anchor; +90 reads top to bottom.
    let centroid_y = |degrees| {
        let mut c = Canvas::new(60, 120);
        c.text_rotated(
            "M   ",
            30.0,
            60.0,
            20.0,
            RED,
            HAlign::Center,
            VAlign::Middle,
            degrees,
        );
        let pm = c.to_pixmap();
        let (mut sum, mut weight) = (0.0, 0.0);
        for y in 0..120 {
            for x in 0..60 {
                let a = f32::from(px(&pm, x, y)[3]);
                sum += a * (y as f32 + 0.5);
                weight += a;
            }
        }
        sum / weight
    };
    let (up, down) = (centroid_y(-90.0), centroid_y(90.0));
    assert!(up > 66.0 && down < 54.0, "{up} {down}");
}

#[test]
fn greek_and_symbols_draw() {
    for s in [
        "\u{2212}0.1",
        "u\u{2032}v\u{2032}",
        "\u{0394}E \u{00b0}",
        "\u{03bb}",
    ] {
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
    // Malformed images and positions are not recorded at all, so neither backend sees them.
    let bad = |w, h, n| RgbaImage {
        width: w,
        height: h,
        pixels: vec![[9; 4]; n],
    };
    c.image(0.0, 0.0, bad(3, 3, 2));
    c.image(0.0, 0.0, bad(0, 0, 0));
    c.image(f32::NAN, 0.0, bad(1, 1, 1));
    assert_eq!(c.items.len(), 1);
    // Straight alpha in, premultiplied draw: half-transparent white over black is grey.
    let mut c = Canvas::new(2, 1);
    c.background(Color::rgb(0, 0, 0));
    c.image(
        0.4,
        0.0,
        RgbaImage {
            width: 1,
            height: 1,
            pixels: vec![[10, 20, 30, 255]],
        },
    );
    c.image(
        1.0,
        0.0,
        RgbaImage {
            width: 1,
            height: 1,
            pixels: vec![[255, 255, 255, 128]],
        },
    );
    let pm = c.to_pixmap();
    assert_eq!(px(&pm, 0, 0), [10, 20, 30, 255], "x = 0.4 rounds to 0");
    assert_eq!(px(&pm, 1, 0), [128, 128, 128, 255]);
}

#[test]
fn degenerate_items_are_dropped_in_both_backends() {
    let mut c = Canvas::new(10, 10);
    let nan = Path2::new()
        .move_to(0.0, 0.0)
        .line_to(f32::NAN, 5.0)
        .line_to(5.0, 5.0);
    c.fill(&nan, RED);
    c.fill(&Path2::new().move_to(1.0, 1.0).close(), RED);
    c.stroke(
        &Path2::new().rect(1.0, 1.0, 5.0, 5.0),
        RED,
        &Stroke::solid(0.0),
    );
    c.stroke(
        &Path2::new().rect(1.0, 1.0, 5.0, 5.0),
        RED,
        &Stroke::solid(f32::INFINITY),
    );
    c.text("x", 5.0, 5.0, -3.0, RED, HAlign::Left, VAlign::Top);
    c.text("x", 5.0, 5.0, 12.0, RED, HAlign::Left, VAlign::Top);
    c.items.pop(); // the only drawable one, to check the list before it
    assert!(c.items.is_empty(), "{:?}", c.items);
    // Zero width is a hairline to tiny-skia but nothing to SVG: neither draws it.
    assert_eq!(ink(&c.to_pixmap(), 0), None);
    assert!(!c.to_svg().contains("<path"));

    // A clip that is not drawable hides everything until popped, in both backends.
    c.clip_push(&nan);
    c.fill(&Path2::new().rect(0.0, 0.0, 10.0, 5.0), RED);
    c.clip_pop();
    c.fill(&Path2::new().rect(0.0, 5.0, 10.0, 5.0), BLUE);
    c.clip_pop(); // unbalanced: ignored
    c.fill(&Path2::new().rect(0.0, 0.0, 1.0, 1.0), BLUE);
    let pm = c.to_pixmap();
    assert_eq!(px(&pm, 5, 2), [0; 4]);
    assert_eq!(px(&pm, 5, 7), [0, 0, 255, 255]);
    assert_eq!(px(&pm, 0, 0), [0, 0, 255, 255]);
    let svg = c.to_svg();
    check_xml(&svg).unwrap_or_else(|e| panic!("{e}\n{svg}"));
    assert!(
        svg.contains("<path d=\"\"/></clipPath>") && !svg.contains("NaN"),
        "{svg}"
    );
}

#[test]
fn dashes_are_normalised_for_both_backends() {
    let line = Path2::new().move_to(0.0, 2.0).line_to(16.0, 2.0);
    let dashed = |dash: Vec<f32>| {
        let mut c = Canvas::new(16, 4);
        let stroke = Stroke {
            width: 2.0,
            dash: Some(dash),
            round: false,
        };
        c.stroke(&line, RED, &stroke);
        let pm = c.to_pixmap();
        let row: Vec<bool> = (0..16).map(|x| px(&pm, x, 1)[3] > 128).collect();
        (row, c.to_svg())
    };
    // An odd list repeats (SVG's rule): [3] is 3 on, 3 off.
    let (row, svg) = dashed(vec![3.0]);
    let expect: Vec<bool> = (0..16).map(|x| (x / 3) % 2 == 0).collect();
    assert_eq!(row, expect);
    assert!(svg.contains("stroke-dasharray=\"3 3\""), "{svg}");
    // Invalid lists draw solid, and the SVG says nothing about dashes.
    for bad in [vec![], vec![0.0, 0.0], vec![2.0, -1.0], vec![f32::NAN, 2.0]] {
        let (row, svg) = dashed(bad.clone());
        assert!(row.iter().all(|&on| on), "{bad:?}: {row:?}");
        assert!(!svg.contains("dasharray"), "{bad:?}");
    }
}

#[test]
fn sizes_are_clamped_and_background_fills() {
    let c = Canvas::new(0, u32::MAX);
    assert_eq!((c.width(), c.height()), (1, Canvas::MAX_SIDE));
    let mut c = Canvas::new(3, 2);
    c.background(Color::hex("#F44336").expect("valid hex").with_alpha(128));
    let pm = c.to_pixmap();
    // Straight alpha 128 of (244, 67, 54) survives the premultiplied round trip to +-1.
    let p = px(&pm, 2, 1);
    assert_eq!(p[3], 128);
    for (got, want) in p.iter().zip([244u8, 67, 54]) {
        assert!(got.abs_diff(want) <= 1, "{p:?}");
    }
    let png = c.to_png().expect("PNG encodes");
    assert_eq!(&png[1..4], b"PNG");
}
