//! The chromaticity diagram: colour-science's fill and plot defaults (from
//! `$REALIST_SHARED/color/reference.json`, ignored when unset), a golden image, and the
//! `realist chroma` command line.

mod common;

use std::process::Command;

use realist::color::{Observer, RgbSpace};
use realist::overlay::chroma::{self, fill, ChromaOptions, Plane, PLANCKIAN_LABELS_K};
use serde_json::Value;

fn reference() -> Value {
    common::colour_reference("the colour-science diagram reference")
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn colour_science_fill_and_plot_defaults() {
    let r = reference();
    let srgb = RgbSpace::srgb();
    let points = r["diagram_fill"]["points"].as_object().unwrap();
    assert_eq!(points.len(), 11);
    for (name, p) in points {
        let xy = floats(&p["xy"]);
        let xy = [xy[0], xy[1]];
        for (got, key) in [
            (
                fill::colour_science_unclipped(&srgb, xy),
                "srgb_encoded_unclipped",
            ),
            (fill::colour_science_fill(&srgb, xy), "fill_rgb"),
        ] {
            let want = floats(&p[key]);
            let d = got
                .iter()
                .zip(&want)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            // Unclipped values reach -145 at the far violet: relative 1e-12.
            let scale = want.iter().map(|v| v.abs()).fold(1.0, f64::max);
            assert!(d <= 1e-12 * scale, "{name} {key}: {got:?} vs {want:?}");
        }
        // Our smooth fill agrees on the hue where colour-science's is in range: same
        // largest channel for the saturated primaries.
        let smooth = fill::smooth_fill(&srgb, xy);
        assert!(
            smooth.iter().all(|v| (0.0..=1.0).contains(v)),
            "{name}: {smooth:?}"
        );
    }
    let d = &r["plot_defaults"];
    let labels = &d["spectral_locus_labels_nm"];
    for (key, plane) in [
        ("CIE 1931", Plane::Xy),
        ("CIE 1960 UCS", Plane::Uv),
        ("CIE 1976 UCS", Plane::UvPrime),
    ] {
        let want: Vec<u32> = labels[key]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_u64().unwrap() as u32)
            .collect();
        assert_eq!(plane.wavelength_labels(), want.as_slice(), "{key}");
    }
    assert_eq!(
        floats(&d["planckian_locus_labels_K"]),
        PLANCKIAN_LABELS_K.to_vec()
    );
    let boxes = &d["bounding_box"];
    for (key, plane) in [
        ("CIE 1931 overlays", Plane::Xy),
        ("CIE 1960 UCS overlays", Plane::Uv),
        ("CIE 1976 UCS overlays", Plane::UvPrime),
    ] {
        assert_eq!(floats(&boxes[key]), plane.bounds().to_vec(), "{key}");
    }
    assert_eq!(d["planckian_iso_line_D_uv"].as_f64(), Some(0.05));
}

fn rgb_of(pm: &tiny_skia::Pixmap) -> Vec<u8> {
    pm.pixels()
        .iter()
        .flat_map(|p| {
            let c = p.demultiply();
            [c.red(), c.green(), c.blue()]
        })
        .collect()
}

#[test]
fn golden_diagram_with_gamuts_and_planckian_locus() {
    let opts = ChromaOptions {
        size: 512,
        gamuts: vec![
            RgbSpace::srgb(),
            RgbSpace::display_p3(),
            RgbSpace::rec2020(),
        ],
        planckian: true,
        ..ChromaOptions::default()
    };
    let pm = chroma::diagram_pixmap(&opts);
    // tiny-skia is deterministic, but the fill goes through powf/exp/ln (libm may differ in
    // the last bit between platforms) and text edges are anti-aliased: SHADED.
    common::check_golden_rgb(
        "chroma_xy_srgb_p3_2020",
        512,
        512,
        rgb_of(&pm),
        common::SHADED,
    );
    for plane in [Plane::Uv, Plane::UvPrime] {
        let opts = ChromaOptions {
            plane,
            size: 384,
            observer: Observer::Cie1964,
            ..opts.clone()
        };
        let name = format!(
            "chroma_{}_1964",
            if plane == Plane::Uv { "uv" } else { "upvp" }
        );
        common::check_golden_rgb(
            &name,
            384,
            384,
            rgb_of(&chroma::diagram_pixmap(&opts)),
            common::SHADED,
        );
    }
}

/// The stdout of a run that must have succeeded (else its stderr is the failure).
fn succeeded(out: &std::process::Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn realist(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_realist"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn chroma_command_line() {
    let dir = common::temp_dir("chroma-cli");
    let png = dir.join("cie.png");
    let out = realist(&[
        "chroma",
        "-o",
        png.to_str().unwrap(),
        "--size",
        "256",
        "--gamut",
        "srgb,display-p3,rec2020",
        "--planckian",
    ]);
    let stdout = succeeded(&out);
    assert!(
        stdout.contains("ITU-R BT.2020") && stdout.contains("189.1%"),
        "{stdout}"
    );
    let img = image::open(&png).unwrap();
    assert_eq!((img.width(), img.height()), (256, 256));

    // An image's pixels: half pure sRGB green, half a neutral grey; a custom gamut that
    // holds only the neutrals sees half of the pixels outside.
    let pixels = dir.join("pixels.png");
    let mut im = image::RgbImage::new(8, 8);
    for (x, _, p) in im.enumerate_pixels_mut() {
        *p = if x < 4 {
            image::Rgb([0, 255, 0])
        } else {
            image::Rgb([120, 120, 120])
        };
    }
    im.save(&pixels).unwrap();
    let points = dir.join("points.csv");
    std::fs::write(&points, "x,y,label\n0.3127,0.329,D65 again\n").unwrap();
    let svg = dir.join("cie.svg");
    let out = realist(&[
        "chroma",
        "-o",
        svg.to_str().unwrap(),
        "--svg",
        "--size",
        "256",
        "--diagram",
        "u'v'",
        "--gamut",
        "srgb,0.33,0.31,0.31,0.35,0.30,0.30",
        "--pixels",
        pixels.to_str().unwrap(),
        "--density",
        "--points",
        points.to_str().unwrap(),
        "--white",
        "d50,3000K",
    ]);
    let stdout = succeeded(&out);
    assert!(
        stdout.contains("outside sRGB: 0.0000% of 64 pixels"),
        "{stdout}"
    );
    assert!(
        stdout.contains("outside custom 1: 50.0000% of 64 pixels"),
        "{stdout}"
    );
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(
        text.starts_with("<?xml")
            && text.contains("aria-label=\"D65 again\"")
            && text.trim_end().ends_with("</svg>")
    );

    for (args, expect) in [
        (vec!["--gamut", "srgb,nope"], "unknown gamut 'nope'"),
        (vec!["--diagram", "lab"], "unknown --diagram 'lab'"),
        (vec!["--pixels", "/nonexistent.png"], "/nonexistent.png"),
        (vec!["--white", "d99"], "unknown illuminant 'd99'"),
        (vec!["--size", "100000"], "--size must be between"),
    ] {
        let mut all = vec!["chroma", "-o", "/tmp/never.png"];
        all.extend(args);
        let out = realist(&all);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            !out.status.success() && err.contains(expect) && err.trim().lines().count() == 1,
            "{all:?}: {err}"
        );
    }
}
