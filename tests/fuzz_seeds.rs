//! The fuzz targets' seeds (`fuzz/seeds/`, which keep every finding as a regression input)
//! replayed through the same entry points as the targets, on every `cargo test`: no loader or
//! decoder panic, every error message on one line, and a loaded animated scene poses with
//! finite bounds. The fuzz targets themselves need cargo-fuzz (see `fuzz/README.md`).

use std::path::{Path, PathBuf};

use realist::load::{fuzzing, load, LoadError, LoadOptions};
use realist::render::PreparedScene;
use realist::scene::{Play, Scene};

mod common;

fn seeds(target: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz/seeds")
        .join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("entry").path())
        .collect();
    files.sort();
    assert!(!files.is_empty(), "{}: no seeds", dir.display());
    files
        .into_iter()
        .map(|p| {
            let bytes = std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            (p, bytes)
        })
        .collect()
}

/// Loads `bytes` as a file `name` (in a scratch folder) the way the fuzz targets do: a
/// panic or a multi-line message fails the test.
fn load_as(seed: &Path, name: &str, bytes: &[u8]) -> Option<Scene> {
    let dir = common::temp_dir("fuzz-seeds");
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("write");
    let opts = LoadOptions {
        max_bytes: 256 << 20,
        ..LoadOptions::default()
    };
    match load(&path, &opts) {
        Ok(scene) => Some(scene),
        Err(LoadError::Panic { message, .. }) => {
            panic!("{}: loader panicked: {message}", seed.display())
        }
        Err(e) => {
            let msg = e.to_string();
            assert!(!msg.contains('\n'), "{}: {msg:?}", seed.display());
            None
        }
    }
}

/// The first byte picks the file name as the targets do (even: `even`, odd: `odd`); the rest is
/// the file. `None` for an empty seed.
fn selected<'a>(bytes: &'a [u8], even: &'a str, odd: &'a str) -> Option<(&'a str, &'a [u8])> {
    let (&selector, body) = bytes.split_first()?;
    Some((if selector & 1 == 0 { even } else { odd }, body))
}

fn assert_decoded<T>(seed: &Path, result: Result<T, String>) {
    if let Err(e) = result {
        assert!(!e.contains("decoder panicked"), "{}: {e}", seed.display());
        assert!(!e.contains('\n'), "{}: {e:?}", seed.display());
    }
}

#[test]
fn gltf_seeds_load_without_panicking() {
    for (seed, bytes) in seeds("gltf_bytes") {
        let name = if bytes.starts_with(b"glTF") {
            "case.glb"
        } else {
            "case.gltf"
        };
        load_as(&seed, name, &bytes);
    }
}

#[test]
fn animation_seeds_load_and_pose_with_finite_bounds() {
    for (seed, bytes) in seeds("anim_pose") {
        let Some((name, body)) = selected(&bytes, "case.gltf", "case.glb") else {
            continue;
        };
        let Some(scene) = load_as(&seed, name, body) else {
            continue;
        };
        let animations = scene.animations.len();
        let mut prepared = PreparedScene::new(scene);
        for play in [Play::Rest, Play::All]
            .into_iter()
            .chain((0..animations.min(4)).map(Play::One))
        {
            for t in [0.0, 0.5, 1e9, f32::NAN] {
                prepared.pose_at(play, t, true);
                for p in prepared.world_positions().iter().flatten() {
                    assert!(p.is_finite(), "{}: {play:?} at {t}: {p}", seed.display());
                }
            }
        }
    }
}

#[test]
fn mesh_seeds_load_with_finite_bounds() {
    for (seed, bytes) in seeds("mesh_bytes") {
        let Some((name, body)) = selected(&bytes, "case.stl", "case.ply") else {
            continue;
        };
        if let Some((lo, hi)) = load_as(&seed, name, body).and_then(|s| s.bounds()) {
            assert!(lo.is_finite() && hi.is_finite(), "{}", seed.display());
        }
    }
}

#[test]
fn decoder_seeds_decode_or_fail_on_one_line() {
    for (seed, bytes) in seeds("meshopt_decode") {
        assert_decoded(&seed, fuzzing::meshopt(&bytes));
    }
    for (seed, bytes) in seeds("draco_decode") {
        assert_decoded(&seed, fuzzing::draco(&bytes));
    }
    for (seed, bytes) in seeds("ktx2_decode") {
        assert_decoded(&seed, fuzzing::ktx2(&bytes));
    }
}
