//! The committed example scenes (`examples/scenes/`): together they use every key of the
//! scene-file format, and `realist render` draws each of them.
//!
//! The format's keys are not listed here by hand: each table's keys are read from the
//! parser itself (a table holding an unknown key makes serde list the keys it accepts),
//! so a key added to the format without an example fails this test.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use realist::scenefile::{Format, SceneFile};

fn examples() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| Format::of(p).is_some())
        .collect();
    files.sort();
    assert!(files.len() >= 2, "no examples in {}", dir.display());
    files
}

/// The file as a JSON value (TOML converted), for walking its keys.
fn value(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap();
    match Format::of(path) {
        Some(Format::Toml) => {
            let v: toml::Value = toml::from_str(&text).unwrap();
            serde_json::to_value(v).unwrap()
        }
        _ => serde_json::from_str(&text).unwrap(),
    }
}

/// Every key path in `v` (`light[].attenuation.mode`), tables in arrays as `[]`.
fn key_paths(v: &serde_json::Value, prefix: &str, out: &mut BTreeSet<String>) {
    if let Some(map) = v.as_object() {
        for (k, child) in map {
            let path = if prefix.is_empty() {
                k.clone()
            } else {
                format!("{prefix}.{k}")
            };
            out.insert(path.clone());
            match child {
                serde_json::Value::Array(items) if items.iter().all(|i| i.is_object()) => {
                    for item in items {
                        key_paths(item, &format!("{path}[]"), out);
                    }
                }
                other => key_paths(other, &path, out),
            }
        }
    }
}

/// The keys the parser accepts in the table at `path` (e.g. `light[].attenuation`),
/// from its error for an unknown key.
fn accepted_keys(path: &str) -> Vec<String> {
    // The unknown key, placed in a document holding only the tables on the way to it.
    let mut doc = serde_json::json!({ "zzz_unknown": 1 });
    for part in path.split('.').filter(|p| !p.is_empty()).rev() {
        doc = match part.strip_suffix("[]") {
            Some(name) => serde_json::json!({ name: [doc] }),
            None => serde_json::json!({ part: doc }),
        };
    }
    let text = doc.to_string();
    let err = SceneFile::parse(&text, Format::Json, Path::new("probe.json"))
        .expect_err("an unknown key is refused")
        .to_string();
    let list = err
        .split("expected one of ")
        .nth(1)
        .unwrap_or_else(|| panic!("{path}: no key list in: {err}"));
    // `a`, `b`, ... `z` at line 1 column 15: the names between backquotes.
    list.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_owned)
        .collect()
}

#[test]
fn the_examples_use_every_key_of_the_format() {
    let mut used = BTreeSet::new();
    for f in examples() {
        key_paths(&value(&f), "", &mut used);
        SceneFile::read(&f).unwrap_or_else(|e| panic!("{e}"));
    }
    // Walk the format from the root: every key it accepts must be used, and every key
    // that is a table (or an array of tables) in the examples is walked in turn.
    let mut missing = Vec::new();
    let mut tables = vec![String::new()];
    let mut walked = 0;
    let mut seen = Vec::new();
    while let Some(table) = tables.pop() {
        walked += 1;
        seen.push(table.clone());
        for key in accepted_keys(&table) {
            let path = if table.is_empty() {
                key
            } else {
                format!("{table}.{key}")
            };
            if !used.contains(&path) {
                missing.push(path.clone());
            }
            let array = format!("{path}[]");
            if used.iter().any(|u| u.starts_with(&format!("{array}."))) {
                tables.push(array);
            } else if used.iter().any(|u| u.starts_with(&format!("{path}."))) {
                tables.push(path);
            }
        }
    }
    assert!(walked >= 12, "only {walked} tables walked: {seen:?}");
    assert!(
        missing.is_empty(),
        "keys of the format no example uses: {missing:?}"
    );
}

#[test]
fn every_example_renders_from_the_command_line() {
    let out = std::env::temp_dir().join(format!("realist-scene-examples-{}", std::process::id()));
    std::fs::create_dir_all(&out).unwrap();
    for f in examples() {
        let png = out.join(format!("{}.png", f.file_stem().unwrap().to_string_lossy()));
        let result = std::process::Command::new(env!("CARGO_BIN_EXE_realist"))
            .args(["render", f.to_str().unwrap(), "--size", "96x64", "-o"])
            .arg(&png)
            .args(["--stats"])
            .output()
            .unwrap();
        assert!(
            result.status.success(),
            "{}: {}",
            f.display(),
            String::from_utf8_lossy(&result.stderr)
        );
        let stats: serde_json::Value = serde_json::from_slice(&result.stdout).unwrap();
        for key in ["lights_skipped", "shadow_maps", "drawn"] {
            assert!(stats[key].is_u64(), "{}: {key} in {stats}", f.display());
        }
        let img = image::open(&png).unwrap();
        let file = SceneFile::read(&f).unwrap();
        // A comparison is wider than one frame; a single frame has the size asked for.
        if file.doc.compare.is_some() {
            assert!(
                img.width() >= 96 * 2 && img.height() > 64,
                "{}",
                f.display()
            );
        } else {
            assert_eq!((img.width(), img.height()), (96, 64), "{}", f.display());
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn flags_override_the_file_and_errors_name_it() {
    let dir = std::env::temp_dir().join(format!("realist-scene-flags-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("s.toml");
    std::fs::write(
        &scene,
        "model = \"demo\"\nsize = [50, 40]\noutput = \"from-file.png\"\n",
    )
    .unwrap();
    let run = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_realist"))
            .arg("render")
            .arg(&scene)
            .args(args)
            .current_dir(&dir)
            .output()
            .unwrap()
    };
    let r = run(&[]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let img = image::open(dir.join("from-file.png")).unwrap();
    assert_eq!((img.width(), img.height()), (50, 40));
    let r = run(&[
        "--size", "30x20", "-o", "flag.png", "--fog", "1,5", "--tone", "reinhard",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let img = image::open(dir.join("flag.png")).unwrap();
    assert_eq!((img.width(), img.height()), (30, 20));
    let r = run(&["--camera", "gltf:4", "-o", "x.png"]);
    let e = String::from_utf8_lossy(&r.stderr);
    assert!(
        !r.status.success() && e.contains("gltf:4") && e.contains("the demo scene has 1 camera"),
        "{e}"
    );
    std::fs::write(&scene, "model = \"demo\"\n[fog]\nnear = 3\nfar = 1\n").unwrap();
    let r = run(&["-o", "x.png"]);
    let e = String::from_utf8_lossy(&r.stderr);
    assert!(
        !r.status.success() && e.contains("s.toml: fog.near: 3 is not below far (1)"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bench_accuracy_measures_a_scene_file() {
    let out = std::env::temp_dir().join(format!("realist-scene-accuracy-{}", std::process::id()));
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/lit_stage.json");
    let r = std::process::Command::new(env!("CARGO_BIN_EXE_realist"))
        .args(["bench", "accuracy"])
        .arg(&scene)
        .args(["--size", "48x32", "--runs", "1", "--samples", "2", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert!(r.status.success(), "{stderr}");
    // The file's lights cast shadows, which the reference does not draw: said, not hidden.
    assert!(
        stderr.contains("shadows and the ground plane are not in the f64 reference"),
        "{stderr}"
    );
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert!(csv.lines().count() > 4 && csv.contains("blinn"), "{csv}");
    assert!(out.join("reference.png").is_file());
    let _ = std::fs::remove_dir_all(&out);
}

/// `bench accuracy` on a scene file with a material variant and a hidden part: the f64
/// reference draws them as the renders do (the left sphere blue, the right one gone).
#[test]
fn bench_accuracy_draws_the_files_variant_and_hidden_parts() {
    let out = std::env::temp_dir().join(format!(
        "realist-scene-accuracy-variant-{}",
        std::process::id()
    ));
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/material_variant.toml");
    let r = std::process::Command::new(env!("CARGO_BIN_EXE_realist"))
        .args(["bench", "accuracy"])
        .arg(&scene)
        .args(["--size", "48x48", "--runs", "1", "--samples", "2", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let reference = image::open(out.join("reference.png")).unwrap().into_rgb8();
    let dominant = |c: usize| {
        reference
            .pixels()
            .filter(|p| (0..3).all(|k| k == c || p[c] > p[k].saturating_add(30)))
            .count()
    };
    assert!(
        dominant(2) > 50,
        "the blue variant: {} blue pixels",
        dominant(2)
    );
    assert_eq!(dominant(1), 0, "the green sphere is hidden");
    let _ = std::fs::remove_dir_all(&out);
}

/// A value outside `n`'s range, as the command line and the file both write it.
fn out_of_range(n: &realist::render::Numeric) -> f64 {
    use realist::render::Range;
    match n.range {
        Range::Between(_, hi) => hi * 2.0 + 1.0,
        Range::Whole(_, hi) => f64::from(hi) + 1.0,
        Range::OneOf(set) => (1..)
            .map(f64::from)
            .find(|v| !set.iter().any(|&s| f64::from(s) == *v))
            .unwrap(),
    }
}

/// The scene file (as JSON) that sets `key` to `v` on the demo: a dotted key is a table's
/// (`shadow.size` is `{"shadow": {"size": v}}`). A setting that lives in a part the file
/// must also turn on (the fog's two distances, the bump map) gets that part's other key.
fn scene_setting(key: &str, v: f64) -> serde_json::Value {
    let mut doc = serde_json::json!({ "model": "demo" });
    let (table, leaf) = match key.split_once('.') {
        Some((t, l)) => (Some(t), l),
        None => (None, key),
    };
    let target = match table {
        Some(t) => &mut doc
            .as_object_mut()
            .unwrap()
            .entry(t)
            .or_insert(serde_json::json!({})),
        None => &mut doc,
    };
    target[leaf] = if v.fract() == 0.0 {
        serde_json::json!(v as i64)
    } else {
        serde_json::json!(v)
    };
    match key {
        "fog.near" => target["far"] = serde_json::json!(1e7),
        "fog.far" => target["near"] = serde_json::json!(0.0),
        "bump_scale" => target["bump"] = serde_json::json!("noise"),
        _ => {}
    }
    doc
}

#[test]
fn every_numeric_setting_out_of_range_gives_one_message_from_the_command_line_and_both_file_formats(
) {
    let dir = std::env::temp_dir().join(format!("realist-numeric-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |args: &[String]| {
        let r = std::process::Command::new(env!("CARGO_BIN_EXE_realist"))
            .arg("render")
            .args(args)
            .current_dir(&dir)
            .output()
            .unwrap();
        assert!(!r.status.success(), "{args:?} was accepted");
        String::from_utf8_lossy(&r.stderr).into_owned()
    };
    let mut flags = 0;
    for n in realist::render::NUMERIC {
        let v = out_of_range(n);
        let message = n.check(v).unwrap_err();
        let key = n.key;
        assert!(message.starts_with(&format!("{key} = ")), "{message}");
        if let Some(args) = n.flag_args(&v.to_string()) {
            let mut all = vec!["--demo".to_owned(), "-o".into(), "x.png".into()];
            all.extend(args);
            let e = run(&all);
            assert!(
                e.contains(&message),
                "{key} on the command line: {e}\nwanted: {message}"
            );
            flags += 1;
        }
        let doc = scene_setting(key, v);
        let json = dir.join("s.json");
        std::fs::write(&json, serde_json::to_string(&doc).unwrap()).unwrap();
        let toml_file = dir.join("s.toml");
        std::fs::write(&toml_file, toml::to_string(&doc).unwrap()).unwrap();
        for file in [json, toml_file] {
            let e = run(&[file.display().to_string(), "-o".into(), "x.png".into()]);
            let want = format!("{}: {message}", file.display());
            assert!(e.contains(&want), "{key} in a file: {e}\nwanted: {want}");
        }
    }
    assert!(flags >= 12, "only {flags} settings have a flag");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn up_z_stands_a_z_up_model_up_from_the_command_line_and_a_scene_file() {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("up-z");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let house = root.join("models/house-z-up.obj");
    let render = |args: &[&str], png: &Path| {
        let r = std::process::Command::new(env!("CARGO_BIN_EXE_realist"))
            .arg("render")
            .args(args)
            .args(["--size", "96x96", "-o"])
            .arg(png)
            .output()
            .unwrap();
        assert!(
            r.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&r.stderr)
        );
    };
    // The same house with +Y up (each vertex turned -90 degrees about X: (x, y, z) ->
    // (x, z, -y)), drawn Y-up, is what --up z draws of the Z-up one; without --up the
    // Z-up house lies on its back and the images differ.
    let text = std::fs::read_to_string(&house).unwrap();
    let turned: String = text
        .lines()
        .map(|l| match l.strip_prefix("v ") {
            Some(v) => {
                let p: Vec<f32> = v.split(' ').map(|t| t.parse().unwrap()).collect();
                format!("v {} {} {}\n", p[0], p[2], -p[1])
            }
            None => format!("{l}\n"),
        })
        .collect();
    let house_y = out.join("house-y-up.obj");
    std::fs::write(&house_y, turned).unwrap();
    let rgb = |p: &Path| image::open(p).unwrap().to_rgb8();
    let differing = |a: &image::RgbImage, b: &image::RgbImage| {
        a.pixels()
            .zip(b.pixels())
            .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 2))
            .count()
    };
    for camera in [None, Some("30,15"), Some("0,0")] {
        let cam: Vec<&str> = camera.map_or(vec![], |c| vec!["--camera", c]);
        let (y_up, z_up, lying) = (out.join("y.png"), out.join("z.png"), out.join("lying.png"));
        render(&[&[house_y.to_str().unwrap()], &cam[..]].concat(), &y_up);
        render(
            &[&[house.to_str().unwrap(), "--up", "z"], &cam[..]].concat(),
            &z_up,
        );
        render(&[&[house.to_str().unwrap()], &cam[..]].concat(), &lying);
        let (y, z, l) = (rgb(&y_up), rgb(&z_up), rgb(&lying));
        let n = y.pixels().len();
        let same = differing(&y, &z);
        assert!(
            same * 200 < n,
            "{camera:?}: {same} pixels differ with --up z"
        );
        let lies = differing(&y, &l);
        assert!(
            lies * 10 > n,
            "{camera:?}: only {lies} pixels differ without --up"
        );
    }
    // The scene file's `up = "z"` gives the same image as the flag with its camera.
    let from_file = out.join("file.png");
    let scene = root.join("examples/scenes/z_up_house.toml");
    render(&[scene.to_str().unwrap()], &from_file);
    let flag = out.join("flag.png");
    render(
        &[
            house.to_str().unwrap(),
            "--up",
            "z",
            "--camera",
            "30,15",
            "--msaa",
            "4",
        ],
        &flag,
    );
    let (a, b) = (
        image::open(&from_file).unwrap().to_rgb8(),
        image::open(&flag).unwrap().to_rgb8(),
    );
    assert!(a == b, "the scene file and the flags draw the same image");
    // A turntable turns about +Z: the house stays standing in every frame.
    let frames = out.join("turn_{}.png");
    render(
        &[house.to_str().unwrap(), "--up", "z", "--turntable", "4"],
        &frames,
    );
    let frames_y = out.join("turn_y_{}.png");
    render(&[house_y.to_str().unwrap(), "--turntable", "4"], &frames_y);
    for i in 0..4 {
        let (z, y) = (
            rgb(&out.join(format!("turn_{i}.png"))),
            rgb(&out.join(format!("turn_y_{i}.png"))),
        );
        let d = differing(&z, &y);
        assert!(
            d * 200 < z.pixels().len(),
            "turntable frame {i}: {d} pixels differ"
        );
    }
}
