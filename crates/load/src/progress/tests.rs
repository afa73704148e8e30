//! Progress and cancellation: the shared handle on its own, and through [`load`] for OBJ,
//! glTF and GLB (pre-cancelled, cancelled from another thread, watched from another
//! thread), on generated grids of a few hundred thousand triangles.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use serde_json::json;

use super::*;
use crate::gltf::glb;
use crate::scene::Scene;
use crate::tests::{shared, TempDir};
use crate::{load, LoadOptions};

/// An `n` x `n` vertex grid as OBJ text without normals (so they are averaged):
/// 2 (n-1)^2 triangles.
fn grid_obj(n: usize) -> String {
    let mut text = String::with_capacity(n * n * 60);
    for j in 0..n {
        for i in 0..n {
            let z = ((i * 7 + j * 13) % 17) as f32 * 0.01;
            text.push_str(&format!("v {} {} {z}\n", i as f32, j as f32));
        }
    }
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = j * n + i + 1;
            let (b, c, d) = (a + 1, a + n, a + n + 1);
            text.push_str(&format!("f {a} {b} {c}\nf {b} {d} {c}\n"));
        }
    }
    text
}

/// The same grid as a GLB: one primitive with POSITION and u32 indices, no normals.
fn grid_glb(n: usize) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let z = ((i * 7 + j * 13) % 17) as f32 * 0.01;
            for x in [i as f32, j as f32, z] {
                bin.extend(x.to_le_bytes());
            }
        }
    }
    let positions = bin.len();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = (j * n + i) as u32;
            let (b, c, d) = (a + 1, a + n as u32, a + n as u32 + 1);
            for v in [a, b, c, b, d, c] {
                bin.extend(v.to_le_bytes());
            }
        }
    }
    let indices = bin.len() - positions;
    let (lo, hi) = ([0.0, 0.0, 0.0], [n as f32, n as f32, 1.0]);
    let doc = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteLength": positions},
            {"buffer": 0, "byteOffset": positions, "byteLength": indices}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n * n, "type": "VEC3",
             "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5125, "count": indices / 4, "type": "SCALAR"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}]});
    glb::build(doc.to_string().as_bytes(), Some(&bin))
}

/// A one-triangle glTF with a `data:` buffer.
fn triangle_gltf() -> String {
    let bin: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    use base64::Engine as _;
    let uri = format!(
        "data:application/octet-stream;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(&bin)
    );
    json!({"asset": {"version": "2.0"}, "buffers": [{"byteLength": 36, "uri": uri}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}], "nodes": [{"mesh": 0}]})
    .to_string()
}

fn with(progress: &Arc<Progress>) -> LoadOptions {
    LoadOptions {
        progress: Some(progress.clone()),
        ..LoadOptions::default()
    }
}

fn timed_load(path: &Path, opts: &LoadOptions) -> (Result<Scene, LoadError>, Duration) {
    let start = Instant::now();
    let result = load(path, opts);
    (result, start.elapsed())
}

/// Median of three loads without a `Progress`.
fn full_load_time(path: &Path) -> Duration {
    let mut times: Vec<Duration> = (0..3)
        .map(|_| {
            let (scene, t) = timed_load(path, &LoadOptions::default());
            scene.unwrap_or_else(|e| panic!("{e}"));
            t
        })
        .collect();
    times.sort();
    times[1]
}

/// Loads `path`, cancelling from another thread as soon as the load shows `stage` with a
/// fraction above `after`; returns the time from the cancel to `load` returning, and the
/// whole load's time.
fn cancel_at(path: &Path, stage: Stage, after: f32) -> (Duration, Duration) {
    let progress = Progress::new();
    let watcher = {
        let progress = progress.clone();
        std::thread::spawn(move || loop {
            match progress.snapshot() {
                (s, Some(f)) if s == stage && f > after => {
                    progress.cancel();
                    return Some(Instant::now());
                }
                (Stage::Done, _) => return None,
                _ => std::thread::sleep(Duration::from_micros(50)),
            }
        })
    };
    let (result, total) = timed_load(path, &with(&progress));
    let end = Instant::now();
    progress.cancel(); // Stops a watcher that never saw the stage.
    let cancelled_at = watcher.join().unwrap();
    let Some(cancelled_at) = cancelled_at else {
        panic!(
            "{}: the load never showed {stage} above {after}",
            path.display()
        );
    };
    match result {
        Err(LoadError::Cancelled { path: p }) => assert_eq!(p, path),
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("{}: not cancelled at {stage}", path.display()),
    }
    (end.saturating_duration_since(cancelled_at), total)
}

#[test]
fn a_fresh_progress_is_unknown_and_a_cancel_is_seen() {
    let p = Progress::default();
    assert_eq!(p.snapshot(), (Stage::Reading, None));
    assert!(!p.is_cancelled());
    p.cancel();
    assert!(p.is_cancelled());
    assert_eq!(
        format!("{p:?}"),
        "Progress { stage: Reading, fraction: None, cancelled: true }"
    );
    let names: Vec<&str> = Stage::ALL.iter().map(|s| s.name()).collect();
    assert_eq!(
        names,
        ["reading", "parsing", "geometry", "normals", "textures", "done"]
    );
    assert_eq!(Stage::from_bits(4), Stage::Textures);
}

#[test]
fn the_tracker_maps_stages_into_one_bar_that_never_goes_back() {
    let progress = Progress::new();
    let t = Tracker::new(Path::new("m.obj"), Some(&progress));
    assert_eq!(progress.snapshot(), (Stage::Reading, Some(0.0)));
    t.begin(Stage::Reading, 0.25, 100).unwrap();
    t.advance(50).unwrap();
    assert_eq!(progress.snapshot(), (Stage::Reading, Some(0.125)));
    t.advance(10).unwrap(); // Backwards within a stage: ignored.
    t.advance(1000).unwrap(); // Past the total: clamped.
    assert_eq!(progress.fraction(), Some(0.25));
    t.begin(Stage::Parsing, 0.1, 4).unwrap(); // A share ending behind the bar: empty.
    t.advance(3).unwrap();
    assert_eq!(t.done(), 3);
    assert_eq!(progress.snapshot(), (Stage::Parsing, Some(0.25)));
    t.begin(Stage::Geometry, 0.75, 0).unwrap(); // No units: the share fills at once.
    t.advance(1).unwrap();
    t.label(Stage::Textures).unwrap();
    assert_eq!(progress.snapshot(), (Stage::Textures, Some(0.75)));
    t.finish();
    assert_eq!(progress.snapshot(), (Stage::Done, Some(1.0)));
    progress.cancel();
    let err = t.advance(0).unwrap_err();
    assert_eq!(err.to_string(), "m.obj: load cancelled");
}

#[test]
fn a_cancelled_progress_stops_obj_gltf_and_glb_loads() {
    let dir = TempDir::new("progress-cancelled");
    let files = [
        dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        dir.write("tri.gltf", triangle_gltf()),
        dir.write("grid.glb", grid_glb(4)),
    ];
    for path in &files {
        let progress = Progress::new();
        let scene = load(path, &with(&progress)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(scene.meshes.len(), 1, "{}", path.display());
        assert_eq!(progress.snapshot(), (Stage::Done, Some(1.0)));

        let progress = Progress::new();
        progress.cancel();
        let err = load(path, &with(&progress)).unwrap_err();
        assert!(matches!(err, LoadError::Cancelled { .. }), "{err}");
        assert_eq!(
            err.to_string(),
            format!("{}: load cancelled", path.display())
        );
        assert_ne!(progress.stage(), Stage::Done);
    }
}

/// A thread that samples `progress` until it shows [`Stage::Done`] (or is cancelled).
fn sampler(progress: &Arc<Progress>) -> std::thread::JoinHandle<Vec<(Stage, Option<f32>)>> {
    let progress = progress.clone();
    std::thread::spawn(move || {
        let mut seen = Vec::new();
        loop {
            let now = progress.snapshot();
            if seen.last() != Some(&now) {
                seen.push(now);
            }
            if now.0 == Stage::Done || progress.is_cancelled() {
                return seen;
            }
            std::thread::sleep(Duration::from_micros(50));
        }
    })
}

#[test]
fn progress_rises_monotonically_to_done_and_changes_no_result() {
    let dir = TempDir::new("progress-watch");
    let files = [
        (dir.write("grid.obj", grid_obj(400)), Stage::Parsing),
        (dir.write("grid.glb", grid_glb(450)), Stage::Geometry),
    ];
    for (path, longest) in &files {
        let progress = Progress::new();
        let watcher = sampler(&progress);
        let result = load(path, &with(&progress));
        progress.cancel(); // Ends the sampler should the load have failed.
        let seen = watcher.join().unwrap();
        let scene = result.unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(seen.last(), Some(&(Stage::Done, Some(1.0))), "{seen:?}");
        let fractions: Vec<f32> = seen.iter().filter_map(|s| s.1).collect();
        assert!(
            fractions.windows(2).all(|w| w[0] <= w[1]),
            "{}: {seen:?}",
            path.display()
        );
        // Progress was seen on the way, at least in the stage that takes most of the time
        // (bounds loose enough for a sampler starved of CPU).
        assert!(seen.len() >= 3, "{}: {seen:?}", path.display());
        assert!(seen.iter().any(|s| s.0 == *longest), "{seen:?}");

        // The watched load (on a helper thread) builds exactly what the plain one does.
        let plain = load(path, &LoadOptions::default()).unwrap();
        assert_eq!(plain.meshes.len(), scene.meshes.len());
        for (a, b) in plain.meshes.iter().zip(&scene.meshes) {
            assert_eq!(a.positions, b.positions);
            assert_eq!(a.corners, b.corners);
            assert_eq!(a.normals, b.normals);
            assert_eq!(a.edges().len(), b.edges().len());
        }
        assert_eq!(plain.report.generated, scene.report.generated);
        assert_eq!(plain.report.warnings, scene.report.warnings);
    }
}

#[test]
fn a_cancel_from_another_thread_ends_a_big_load_quickly() {
    let dir = TempDir::new("progress-cancel");
    // 250,000 vertices, 498,002 triangles, about 19 MB of text.
    let obj = dir.write("grid.obj", grid_obj(500));
    let glb = dir.write("grid.glb", grid_glb(500));
    // Where a cancel finds the loader: reading, the pre-scan, tobj assembling the one
    // group at the end of the text, building the mesh and its normals (mesh/, no
    // checkpoint inside), and glTF geometry.
    let tobj_end = super::super::obj::FAST_UNTIL - 0.002;
    let cases: [(&PathBuf, Stage, f32); 5] = [
        (&obj, Stage::Reading, 0.0),
        (&obj, Stage::Parsing, 0.0),
        (&obj, Stage::Parsing, tobj_end),
        (&obj, Stage::Normals, 0.0),
        (&glb, Stage::Geometry, 0.0),
    ];
    for (path, stage, after) in cases {
        let full = full_load_time(path);
        let (latency, total) = cancel_at(path, stage, after);
        eprintln!(
            "{} cancelled at {stage} above {after}: returned {latency:?} after the cancel, {total:?} in all (a full load takes {full:?})",
            path.file_name().unwrap().to_string_lossy(),
        );
        // Generous bounds for a busy machine: 4 ms is typical for the latency.
        assert!(latency * 8 < full, "{stage}: {latency:?} of {full:?}");
        if stage <= Stage::Parsing && after == 0.0 {
            assert!(total * 2 < full, "{stage}: {total:?} of {full:?}");
        }
    }
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn the_bunny_cancels_quickly() {
    let shared = shared("the_bunny_cancels_quickly");
    let bunny = shared.join("models/obj/stanford-bunny.obj");
    let full = full_load_time(&bunny);
    for stage in [Stage::Parsing, Stage::Normals] {
        let (latency, total) = cancel_at(&bunny, stage, 0.0);
        eprintln!(
            "stanford-bunny.obj cancelled at {stage}: returned {latency:?} after the cancel, {total:?} in all (a full load takes {full:?})"
        );
        assert!(latency * 4 < full, "{stage}: {latency:?} of {full:?}");
    }
}
