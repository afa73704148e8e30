//! Every real model in `$REALIST_SHARED/models` renders in every shading mode: no panic, no
//! NaN pixel, something drawn; the bunny's topology satisfies Euler-Poincare; spot's texture
//! shows. Reported as ignored when `REALIST_SHARED` is unset.

mod common;

use std::path::PathBuf;
use std::sync::Arc;

use realist::load::{load, load_texture, LoadOptions};
use realist::render::{PreparedScene, Settings, Shot};
use realist::shade::Shading;

/// `$REALIST_SHARED/models` (for tests marked as needing it).
fn shared() -> PathBuf {
    realist_testkit::shared("the shared-model tests").join("models")
}

fn models(root: &std::path::Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for sub in ["obj", "gltf"] {
        if let Ok(entries) = std::fs::read_dir(root.join(sub)) {
            out.extend(entries.flatten().map(|e| e.path()).filter(|p| p.is_file()));
        }
    }
    if let Ok(entries) = std::fs::read_dir(root.join("gltf/khronos")) {
        for dir in entries.flatten().map(|e| e.path()).filter(|p| p.is_dir()) {
            if let Ok(files) = std::fs::read_dir(&dir) {
                out.extend(files.flatten().map(|e| e.path()));
            }
        }
    }
    out.retain(|p| {
        matches!(
            p.extension().and_then(|e| e.to_str()),
            Some("obj" | "gltf" | "glb")
        )
    });
    out.sort();
    out
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn every_model_renders_in_every_mode() {
    let root = shared();
    let files = models(&root);
    assert!(
        files.len() >= 20,
        "expected the shared models, found {}",
        files.len()
    );
    let mut renders = 0;
    for path in &files {
        let scene = load(path, &LoadOptions::default()).unwrap_or_else(|e| panic!("{e}"));
        let prepared = PreparedScene::new(scene);
        for mode in Shading::ALL {
            let opts = Shot {
                width: 96,
                height: 72,
                settings: Settings {
                    shading: Some(mode),
                    ..Settings::default()
                },
                ..Shot::default()
            };
            let fb = realist::render::render(&prepared, &opts).image();
            let what = format!("{} {mode}", path.display());
            common::assert_finite(&fb, &what);
            assert!(
                common::covered(&fb) >= 20,
                "{what}: almost nothing drawn ({} pixels)",
                common::covered(&fb)
            );
            renders += 1;
        }
    }
    println!(
        "rendered {} models x {} modes = {renders} images",
        files.len(),
        Shading::ALL.len()
    );
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn bunny_topology_is_consistent_with_euler() {
    let root = shared();
    let scene = load(
        &root.join("obj/stanford-bunny.obj"),
        &LoadOptions::default(),
    )
    .expect("bunny");
    let t = scene.meshes[0].topology();
    assert_eq!(t.facets, 69_451);
    // The file has 35,947 vertices, 1,113 of them used by no face; the loader keeps the used ones.
    assert_eq!(t.vertices + 1_113, 35_947);
    assert_eq!(t.non_manifold_edges, 0);
    assert_eq!(t.components, 1);
    // Euler-Poincare for a connected orientable surface with b holes: V - E + F = 2 - 2g - b.
    assert_eq!(
        t.euler_characteristic_used,
        2 - 2 * t.genus.expect("manifold") - t.boundary_loops as i64
    );
    assert_eq!(t.genus, Some(0));
    // Every edge is used by one or two facets: 2E = 3F + boundary edges.
    assert_eq!(2 * t.edges, 3 * t.facets + t.boundary_edges);
}

#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn spot_shows_its_texture() {
    let root = shared();
    let scene = load(&root.join("obj/spot.obj"), &LoadOptions::default()).expect("spot");
    let texture = Arc::new(load_texture(&root.join("obj/spot_texture.png")).expect("texture"));
    let prepared = PreparedScene::new(scene);
    let render = |texture: Option<Arc<realist::texture::Texture>>| {
        let mut slots = realist::scene::SlotOverrides::default();
        slots.set(
            realist::scene::Slot::BaseColor,
            texture.map(|t| {
                realist::scene::SlotOverride::source(realist::scene::TextureSource::Image(t), 1.0)
            }),
        );
        let opts = Shot {
            width: 160,
            height: 120,
            settings: Settings {
                shading: Some(Shading::Textured),
                slots,
                ..Settings::default()
            },
            ..Shot::default()
        };
        realist::render::render(&prepared, &opts).image()
    };
    let plain = render(None);
    let textured = render(Some(texture));
    // Spot's black patches: pixels much darker than anything the untextured render has on
    // the cow, and a warm (red > blue) muzzle/horn colour.
    let bg = Shot::default().settings.background;
    let dark = |fb: &realist::raster::Framebuffer| {
        fb.color
            .iter()
            .filter(|c| **c != bg && c.x < 0.03 && c.y < 0.03 && c.z < 0.03)
            .count()
    };
    let warm = |fb: &realist::raster::Framebuffer| {
        fb.color
            .iter()
            .filter(|c| c.x > 0.1 && c.x > 1.5 * c.z)
            .count()
    };
    assert!(
        dark(&textured) > dark(&plain) + 100,
        "no black patches: {} vs {}",
        dark(&textured),
        dark(&plain)
    );
    assert!(
        warm(&textured) > 20 && warm(&plain) == 0,
        "no warm texels: {} vs {}",
        warm(&textured),
        warm(&plain)
    );
}
