//! The texture-mapping test files of `models/texture/` (written by
//! `tests/texture-models/make.sh`, described in `models/README.md`) load. Only loading is
//! checked here: what the renderer makes of texture transforms, second UV sets, normal maps
//! and sampler states is for the tests of those features. Each load report is printed
//! (`cargo test --test texture_models -- --nocapture`) to show what the loader ignores today.

use std::path::Path;

use realist::load::{load, LoadOptions};

/// Every file, with the number of drawn instances (nodes with a mesh) it holds.
const FILES: [(&str, usize); 8] = [
    ("grid-torus.obj", 1),
    ("grid-torus.glb", 1),
    ("grid-torus-gltfpack.glb", 1),
    ("transform-quads.glb", 7),
    ("multi-uv.glb", 1),
    ("normal-plane.glb", 2),
    ("normal-sphere.glb", 1),
    ("sampler-quads.glb", 15),
];

#[test]
fn every_texture_model_loads() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/texture");
    for (name, instances) in FILES {
        let path = dir.join(name);
        let scene = load(&path, &LoadOptions::default())
            .unwrap_or_else(|e| panic!("{name} does not load: {e}"));
        let report = &scene.report;
        println!(
            "{name}: {} meshes, {} materials, {} textures, {} instances; warnings {:?}; \
             skipped {:?}; generated {:?}",
            scene.meshes.len(),
            scene.materials.len(),
            scene.textures.len(),
            scene.instances.len(),
            report.warnings,
            report.skipped,
            report.generated,
        );
        assert_eq!(scene.instances.len(), instances, "{name}: instances");
        assert!(
            scene.meshes.iter().all(|m| !m.facets().is_empty()),
            "{name}: a mesh without facets"
        );
    }
}
