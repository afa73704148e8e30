//! `realist bench frame`: the JSON line, and the PNG's centre pixel against the peer
//! harness's lighting formula evaluated on the exact sphere; bad input is an error, not a
//! panic. `realist bench micro`: its rows and their pixel counts.

use std::process::Command;

use glam::DVec3;
use serde_json::Value;

/// 8-bit units allowed between the tessellated sphere's pixel (22 x 44 facets, interpolated
/// normals) and the exact sphere's.
const CENTRE_TOLERANCE: i32 = 3;

fn realist(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_realist"))
        .args(args)
        .output()
        .expect("realist runs")
}

/// The peer's colour at pixel (x, y) of a `w` x `h` image of the unit sphere, as 8-bit
/// linear values: a ray through the pixel centre from the peer's camera, N the sphere's
/// normal, colour = A (0.1 + 0.9 max(N.L, 0)) + 0.4 max(N.H, 0)^32.
fn expected_pixel(x: u32, y: u32, w: u32, h: u32) -> [i32; 3] {
    let eye = DVec3::new(1.6, 1.2, 2.0).normalize() * 2.8;
    let f = -eye.normalize();
    let s = f.cross(DVec3::Y).normalize();
    let u = s.cross(f);
    let t = libm::tan((22.5f64).to_radians());
    let ndc_x = (f64::from(x) + 0.5) / f64::from(w) * 2.0 - 1.0;
    let ndc_y = 1.0 - (f64::from(y) + 0.5) / f64::from(h) * 2.0;
    let aspect = f64::from(w) / f64::from(h);
    let d = (f + s * ndc_x * t * aspect + u * ndc_y * t).normalize();
    // |eye + k d| = 1: k^2 + 2 (eye.d) k + |eye|^2 - 1 = 0, the nearer root.
    let b = eye.dot(d);
    let k = -b - (b * b - (eye.length_squared() - 1.0)).sqrt();
    let n = (eye + d * k).normalize();
    let l = DVec3::new(0.5, 1.0, 0.8).normalize();
    let hv = (l - d).normalize();
    let diffuse = 0.1 + 0.9 * n.dot(l).max(0.0);
    let spec = 0.4 * n.dot(hv).max(0.0).powi(32);
    let albedo = [0.8, 0.7, 0.6];
    albedo.map(|a: f64| ((a * diffuse + spec).clamp(0.0, 1.0) * 255.0).round() as i32)
}

#[test]
fn bench_frame_json_and_centre_pixel() {
    let png = std::env::temp_dir().join(format!("realist-bench-frame-{}.png", std::process::id()));
    let out = realist(&[
        "bench",
        "frame",
        "sphere:2000",
        "--size",
        "160x120",
        "--shading",
        "phong",
        "--frames",
        "3",
        "--threads",
        "2",
        "--png",
        png.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 1, "one JSON line: {stdout}");
    let j: Value = serde_json::from_str(lines[0]).expect("JSON");
    println!("{j}");
    assert_eq!(j["mesh"], "sphere:2000");
    // round(sqrt(2000 / 4)) = 22 stacks, 44 slices, 2 * 22 * 44 triangles.
    assert_eq!(j["triangles"], 1936);
    assert_eq!(j["size"], "160x120");
    assert_eq!(j["shading"], "phong");
    assert_eq!(j["realist_mode"], "blinn");
    assert_eq!(j["threads"], 2);
    assert_eq!(j["frames"], 3);
    let ms = |k: &str| j[k].as_f64().unwrap_or_else(|| panic!("{k} is a number"));
    assert!(ms("min_ms") > 0.0 && ms("min_ms") <= ms("median_ms"));
    assert!(ms("median_ms") <= ms("max_ms"));
    assert!(ms("read_ms") > 0.0 && ms("frame_read_ms") >= ms("read_ms"));
    // The stages are parts of the frame: their medians add up to about the median total
    // (medians of parts need not add up exactly), which lies within the frames' range.
    let stage = |k: &str| {
        j["stages_ms"][k]
            .as_f64()
            .unwrap_or_else(|| panic!("stage {k} is a number"))
    };
    let total = stage("total");
    assert!(ms("min_ms") <= total && total <= ms("max_ms"), "{j}");
    let parts: f64 = ["setup", "vertex", "raster", "fill", "resolve"]
        .iter()
        .map(|k| stage(k))
        .sum();
    assert!(parts > 0.0 && parts <= total * 1.1 + 0.05, "{j}");

    let img = image::open(&png).expect("the PNG").to_rgba8();
    let _ = std::fs::remove_file(&png);
    assert_eq!(img.dimensions(), (160, 120));
    let (x, y) = (80, 60);
    let got = img.get_pixel(x, y);
    let want = expected_pixel(x, y, 160, 120);
    println!("centre pixel {got:?}, formula {want:?}");
    assert_eq!(got[3], 255, "the sphere covers the centre");
    for c in 0..3 {
        assert!(
            (i32::from(got[c]) - want[c]).abs() <= CENTRE_TOLERANCE,
            "channel {c}: {} vs {}",
            got[c],
            want[c]
        );
    }
    // The corner is background, stored as the peer stores it: linear x 255, alpha 0.
    assert_eq!(img.get_pixel(0, 0).0, [26, 26, 31, 0]);
}

#[test]
fn bench_frame_bad_input_is_an_error() {
    for (model, needle) in [
        ("sphere:abc", "whole number"),
        ("sphere:0", "too few"),
        ("sphere:99999999999", "too many"),
        ("no-such-model.obj", "could not read"),
        ("model.gltf", "expected an .obj"),
    ] {
        let out = realist(&["bench", "frame", model, "--size", "32x32", "--frames", "1"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{model} should fail");
        assert!(err.contains(needle), "{model}: {err}");
        assert!(!err.contains("panicked"), "{model}: {err}");
    }
    let out = realist(&["bench", "frame", "sphere:100", "--shading", "shiny"]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown shading"));
}

/// `bench micro`: one JSON line per row; the plane covers every pixel exactly once in each
/// mode (its triangles neither overlap nor leave gaps, by the fill rule), the empty frame
/// shades nothing, and the set-up grid has two triangles per 2 x 2-pixel cell.
#[test]
fn bench_micro_rows_cover_the_image_once() {
    let (w, h) = (64u64, 48u64);
    let out = realist(&[
        "bench",
        "micro",
        "--size",
        "64x48",
        "--frames",
        "2",
        "--threads",
        "2",
        "--json",
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows: Vec<Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON"))
        .collect();
    let names: Vec<&str> = rows.iter().map(|r| r["row"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        [
            "empty",
            "flat",
            "gouraud",
            "blinn-phong",
            "textured",
            "pbr",
            "set-up"
        ]
    );
    for r in &rows {
        println!("{r}");
        assert_eq!(r["size"], "64x48");
        assert_eq!(r["threads"], 2);
        let shaded = r["pixels_shaded"].as_u64().unwrap();
        match r["row"].as_str().unwrap() {
            "empty" => {
                assert_eq!(shaded, 0);
                assert!(r["ns_per_pixel"].as_f64().unwrap() > 0.0);
            }
            "set-up" => {
                assert_eq!(shaded, w * h);
                assert!(r["work"].as_str().unwrap().starts_with("1536 triangles"));
                assert!(r["ns_per_triangle"].as_f64().unwrap() > 0.0);
                assert!(r["model_ns"].as_f64().unwrap() > 0.0, "{r}");
            }
            _ => {
                assert_eq!(shaded, w * h, "{r}");
                assert!(r["ns_per_pixel"].as_f64().unwrap() > 0.0);
                let lanes = r["lanes_in_use"].as_f64().unwrap();
                // Quads of 16 x 12 pixels: the diagonal splits rows in the forward modes.
                assert!(lanes > 0.5 && lanes <= 1.0, "{r}");
            }
        }
    }
    // The machine model's figures are the README's (not restated here): each shaded row
    // but PBR has one, and its `times_model` is its time over it.
    for r in &rows[1..5] {
        let (model, ns) = (r["model_ns"].as_f64(), r["ns_per_pixel"].as_f64());
        let (Some(model), Some(ns)) = (model, ns) else {
            panic!("{r}: model_ns and ns_per_pixel are numbers");
        };
        let x = r["times_model"]
            .as_f64()
            .unwrap_or_else(|| panic!("{r}: times_model"));
        assert!(
            model > 0.0 && (x - ns / model).abs() <= 0.01 * x.max(1.0),
            "{r}"
        );
    }
    assert!(rows[5]["model_ns"].is_null());
}

#[test]
fn bench_micro_bad_input_is_an_error() {
    for (args, needle) in [
        (&["--size", "8x8"][..], "16 to 8192"),
        (&["--threads", "0"][..], "1 to 256"),
    ] {
        let mut all = vec!["bench", "micro", "--frames", "1"];
        all.extend_from_slice(args);
        let out = realist(&all);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} should fail");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}
