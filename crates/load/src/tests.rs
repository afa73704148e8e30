//! Tests of the loader entry points, plus runs over the shared models and the malformed
//! corpus (`$REALIST_SHARED`, reported as ignored when unset).

use std::path::{Path, PathBuf};

use super::*;

pub(crate) use realist_testkit::{shared, TempDir};

/// Triangles the scene draws (facets fanned: n corners = n - 2 triangles), counted per
/// instance.
pub(crate) fn drawn_triangles(scene: &Scene) -> usize {
    scene
        .instances
        .iter()
        .filter_map(|i| scene.meshes.get(i.mesh))
        .map(|m| m.facets().iter().map(|f| f.len as usize - 2).sum::<usize>())
        .sum()
}

#[test]
fn unknown_extension_and_missing_file() {
    let err = load(Path::new("model.3ds"), &LoadOptions::default()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "model.3ds: unknown model format (expected .obj, .gltf, .glb, .stl or .ply)"
    );
    let err = load(
        Path::new("/nonexistent/realist/x.OBJ"),
        &LoadOptions::default(),
    )
    .unwrap_err();
    assert!(matches!(err, LoadError::Io { .. }), "{err}");
    assert!(
        err.to_string().starts_with("/nonexistent/realist/x.OBJ: "),
        "{err}"
    );
}

#[test]
fn a_panic_becomes_an_error_naming_the_file() {
    let err = guarded(Path::new("bad.obj"), || -> Result<(), LoadError> {
        panic!("boom")
    })
    .unwrap_err();
    assert_eq!(err.to_string(), "bad.obj: loader panicked: boom");
}

#[test]
fn decoder_messages_and_panics_come_back_on_one_line() {
    // draco-core wraps a long message (the fuzzer's first draco_decode finding).
    let wrapped = "Buffer decode error: declared 2304 raw corrections of 1 bytes, more than the \n                         2029 bytes left in the stream";
    assert_eq!(
        catch_decoder(|| -> Result<(), String> { Err(wrapped.into()) }).unwrap_err(),
        "Buffer decode error: declared 2304 raw corrections of 1 bytes, more than the 2029 bytes left in the stream"
    );
    assert_eq!(
        catch_decoder(|| -> Result<(), String> { panic!("first\r\n  second\n") }).unwrap_err(),
        "decoder panicked: first second"
    );
    let err = guarded(Path::new("bad.obj"), || -> Result<(), LoadError> {
        panic!("two\nlines")
    })
    .unwrap_err();
    assert_eq!(err.to_string(), "bad.obj: loader panicked: two lines");
    assert_eq!(one_line("one line, as it was "), "one line, as it was ");
}

#[test]
fn budget_counts_the_file() {
    let dir = TempDir::new("budget");
    let path = dir.write("big.obj", "v 0 0 0\n".repeat(1000));
    let opts = LoadOptions {
        max_bytes: 4000,
        ..LoadOptions::default()
    };
    let err = load(&path, &opts).unwrap_err();
    assert!(matches!(err, LoadError::TooLarge { .. }), "{err}");
    assert!(err.to_string().contains("OBJ file"), "{err}");
}

#[test]
fn load_texture_decodes_and_refuses_garbage() {
    let dir = TempDir::new("texture");
    let img = ::image::RgbaImage::from_pixel(3, 2, ::image::Rgba([1, 2, 3, 4]));
    let path = dir.0.join("t.png");
    img.save(&path).unwrap();
    let t = load_texture(&path).unwrap();
    assert_eq!((t.width, t.height), (3, 2));
    assert_eq!(
        t.texels,
        crate::texture::Texels::Srgb8(vec![[1, 2, 3, 4]; 6])
    );
    let bad = dir.write("bad.png", b"not an image");
    let err = load_texture(&bad).unwrap_err().to_string();
    assert!(
        err.starts_with(&format!("{}: cannot use image", bad.display())),
        "{err}"
    );
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn shared_models_load_with_sensible_counts() {
    let shared = shared("shared_models_load_with_sensible_counts");
    let models = shared.join("models");
    let opts = LoadOptions::default();
    let mut paths: Vec<PathBuf> = std::fs::read_dir(models.join("obj"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "obj"))
        .collect();
    paths.push(models.join("gltf/Box.glb"));
    paths.push(models.join("gltf/box_sparse.glb"));
    for dir in std::fs::read_dir(models.join("gltf/khronos")).unwrap() {
        let dir = dir.unwrap().path();
        if dir.is_dir() {
            paths.extend(std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()));
        }
    }
    paths.sort();
    for path in &paths {
        let start = std::time::Instant::now();
        let scene = load(path, &opts).unwrap_or_else(|e| panic!("{e}"));
        let elapsed = start.elapsed();
        let tris = drawn_triangles(&scene);
        eprintln!(
            "{}: {} meshes, {} instances, {} triangles drawn, {} cameras, {} warnings, {} skipped, {elapsed:?}",
            path.file_name().unwrap().to_string_lossy(),
            scene.meshes.len(),
            scene.instances.len(),
            tris,
            scene.cameras.len(),
            scene.report.warnings.len(),
            scene.report.skipped.len()
        );
        for line in scene.report.warnings.iter().chain(&scene.report.skipped) {
            eprintln!("    {line}");
        }
        assert!(tris > 0, "{}: nothing to draw", path.display());
        let name = path.file_name().unwrap().to_string_lossy();
        if name == "stanford-bunny.obj" {
            // The file has 35,947 `v` lines; 1,113 of them are used by no face.
            assert_eq!(scene.meshes[0].positions.len(), 34_834);
            assert_eq!(scene.meshes[0].facets().len(), 69_451);
        }
        if name == "Box.glb" || name == "box_sparse.glb" {
            assert_eq!(tris, 12, "{name}");
        }
    }
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn malformed_corpus_never_panics() {
    let shared = shared("malformed_corpus_never_panics");
    let corpus = shared.join("corpus");
    let mut stack = vec![corpus.join("obj-malformed"), corpus.join("gltf-validator")];
    let mut files = Vec::new();
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p
                .extension()
                .is_some_and(|e| e == "obj" || e == "gltf" || e == "glb")
            {
                files.push(p);
            }
        }
    }
    files.sort();
    let opts = LoadOptions {
        max_bytes: 256 << 20,
        ..LoadOptions::default()
    };
    let (mut ok, mut failed) = (0, 0);
    for path in &files {
        match load(path, &opts) {
            Ok(_) => ok += 1,
            Err(LoadError::Panic { message, .. }) => {
                panic!("{}: panicked: {message}", path.display())
            }
            Err(e) => {
                let text = e.to_string();
                assert!(!text.contains('\n'), "multi-line error: {text}");
                assert!(text.starts_with(&path.display().to_string()), "{text}");
                eprintln!("refused: {text}");
                failed += 1;
            }
        }
    }
    eprintln!(
        "corpus: {} files, {ok} loaded, {failed} refused",
        files.len()
    );
}
