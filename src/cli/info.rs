//! `realist info`: the load report, the bounds of what is drawn, the topology of every mesh
//! (with its points and lines), the scenes of the file (`--scene N` reports another), the
//! cameras and lights.

use anyhow::Result;

use realist::load::{self, LoadOptions};
use realist::mesh::Mesh;
use realist::scenefile::schema::UvChoice;

use super::InfoArgs;

/// A mesh's points and lines for the text report, e.g. `, points 7, lines 6`, or nothing.
fn strokes(m: &Mesh) -> String {
    let mut out = String::new();
    if !m.points.is_empty() {
        out += &format!(", points {}", m.points.len());
    }
    if !m.lines.is_empty() {
        out += &format!(", lines {}", m.lines.len());
    }
    out
}

/// A mesh's texture coordinate sets for the text report, e.g. `TEXCOORD_0 (24 values,
/// indexed per corner), TEXCOORD_1 (8 values, per vertex)`, or `none`.
fn uv_sets(m: &Mesh) -> String {
    if m.uvs.is_empty() {
        return "none".into();
    }
    m.uvs
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let how = if c.indices.is_some() {
                "indexed per corner"
            } else {
                "per vertex"
            };
            format!("TEXCOORD_{i} ({} values, {how})", c.values.len())
        })
        .collect::<Vec<_>>()
        .join(", ")
}

pub(super) fn info(args: &InfoArgs) -> Result<()> {
    let opts = LoadOptions {
        normals: args.normals.options()?,
        uv: args.uv.and_then(UvChoice::generator),
        scene: args.scene,
        ..LoadOptions::default()
    };
    let scene = load::load(&args.model, &opts)?;
    let topologies: Vec<_> = scene.meshes.iter().map(|m| m.topology()).collect();
    let meshes: Vec<_> = scene
        .meshes
        .iter()
        .zip(&topologies)
        .map(|(m, t)| {
            serde_json::json!({
                "name": m.name,
                "normals": format!("{:?}", m.normal_source),
                "uvs": !m.uvs.is_empty(),
                "uv_sets": m.uvs.len(),
                "uv_set_values": m.uvs.iter().map(|c| c.values.len()).collect::<Vec<_>>(),
                "tangents": m.tangents.is_some(),
                "colors": m.colors.is_some(),
                "points": m.points.len(),
                "lines": m.lines.len(),
                "topology": t,
            })
        })
        .collect();
    let cameras: Vec<_> = scene
        .cameras
        .iter()
        .enumerate()
        .map(|(i, c)| {
            serde_json::json!({
                "index": i, "name": c.name, "eye": c.eye.to_array(), "target": c.target.to_array(),
                "yfov_degrees": c.yfov.to_degrees(), "ortho": c.ortho,
            })
        })
        .collect();
    let lights: Vec<_> = scene
        .lights
        .iter()
        .map(|l| {
            serde_json::json!({
                "name": l.name, "kind": l.kind.name(), "color": l.color.to_array(),
                "intensity": l.intensity, "position": l.position.to_array(),
                "direction": l.direction.to_array(), "attenuation": l.attenuation.name(),
            })
        })
        .collect();
    let slots: Vec<_> = scene
        .materials
        .iter()
        .enumerate()
        .flat_map(|(i, m)| {
            realist::scene::Slot::ALL
                .into_iter()
                .filter_map(move |slot| {
                    let t = m.slot(slot)?;
                    Some(serde_json::json!({
                        "material": i, "slot": slot.key(), "texture": t.texture,
                        "uv_set": t.uv_set, "description": t.describe(),
                    }))
                })
        })
        .collect();
    let animations: Vec<_> = scene
        .animations
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let sampling: std::collections::BTreeSet<&str> =
                a.samplers.iter().map(|s| s.interpolation.name()).collect();
            serde_json::json!({
                "index": i, "name": a.name, "duration": a.duration(),
                "channels": a.channels.len(), "interpolation": sampling,
            })
        })
        .collect();
    let skins: Vec<_> = scene
        .skins
        .iter()
        .map(|s| serde_json::json!({ "name": s.name, "joints": s.joints.len() }))
        .collect();
    let total = |f: fn(&realist::mesh::TopologyReport) -> usize| -> usize {
        topologies.iter().map(f).sum()
    };
    // The world-space box of what is drawn (the default pose), in the file's units (glTF:
    // metres).
    let bounds = scene.bounds();
    if args.json {
        let json = serde_json::json!({
            "report": scene.report,
            "bounds": bounds.map(|(lo, hi)| serde_json::json!({
                "min": lo.to_array(), "max": hi.to_array(), "size": (hi - lo).to_array(),
                "center": ((lo + hi) * 0.5).to_array(), "diagonal": (hi - lo).length(),
            })),
            "instances": scene.instances.len(),
            "copies": scene.instances.iter().map(|i| i.copy_count()).sum::<usize>(),
            "materials": scene.materials.len(),
            "textures": scene.textures.len(),
            "texture_slots": slots,
            "cameras": scene.cameras.len(),
            "camera_list": cameras,
            "lights": lights,
            "meshes": meshes,
            "nodes": scene.graph.nodes.len(),
            "scenes": scene.graph.scenes.iter().map(|s| &s.name).collect::<Vec<_>>(),
            "scene_roots": scene.graph.scenes.iter().map(|s| s.roots.len()).collect::<Vec<_>>(),
            "scene_drawn": scene.graph.drawn,
            "skins": skins,
            "animations": animations,
        });
        say!("{}", serde_json::to_string_pretty(&json)?);
        return Ok(());
    }
    say!("{} ({})", args.model.display(), scene.report.format);
    let copies: usize = scene.instances.iter().map(|i| i.copy_count()).sum();
    let drawn = if copies == scene.instances.len() {
        String::new()
    } else {
        format!(" ({copies} copies drawn, EXT_mesh_gpu_instancing)")
    };
    say!(
        "  {} meshes, {} instances{drawn}, {} materials, {} textures, {} cameras",
        scene.meshes.len(),
        scene.instances.len(),
        scene.materials.len(),
        scene.textures.len(),
        scene.cameras.len()
    );
    match bounds {
        Some((lo, hi)) => {
            let size = hi - lo;
            say!(
                "  bounds: min ({}, {}, {}), max ({}, {}, {}); size {} x {} x {}, diagonal {} (in the \
                 file's units{})",
                lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, size.x, size.y, size.z, size.length(),
                if matches!(scene.report.format.as_str(), "glTF" | "GLB") {
                    ": metres"
                } else {
                    ""
                }
            );
        }
        None => say!("  bounds: none (nothing to draw)"),
    }
    say!(
        "  {} vertices, {} edges, {} facets in total",
        total(|t| t.vertices),
        total(|t| t.edges),
        total(|t| t.facets)
    );
    for (m, t) in scene.meshes.iter().zip(&topologies) {
        say!(
            "  mesh '{}': V={} E={} F={} (triangles {}), boundary edges {} in {} loops, non-manifold edges {}, \
             degenerate facets {}, isolated vertices {}, components {}, V-E+F={} ({} without isolated vertices), \
             genus {}, normals {:?}, UV sets: {}{}",
            m.name,
            t.vertices,
            t.edges,
            t.facets,
            t.triangles,
            t.boundary_edges,
            t.boundary_loops,
            t.non_manifold_edges,
            t.degenerate_facets,
            t.isolated_vertices,
            t.components,
            t.euler_characteristic,
            t.euler_characteristic_used,
            t.genus.map_or("n/a".to_string(), |g| g.to_string()),
            m.normal_source,
            uv_sets(m),
            strokes(m)
        );
    }
    for (i, c) in scene.cameras.iter().enumerate() {
        say!(
            "  camera {i} '{}' (--camera gltf:{i}): eye {}, target {}, {}",
            c.name,
            c.eye,
            c.target,
            match c.ortho {
                Some(h) => format!("orthographic, half height {h}"),
                None => format!("vertical fov {:.1} degrees", c.yfov.to_degrees()),
            }
        );
    }
    if !scene.graph.nodes.is_empty() {
        say!(
            "  {} nodes, {} scene(s){}, {} skin(s), {} animation(s)",
            scene.graph.nodes.len(),
            scene.graph.scenes.len(),
            scene
                .graph
                .drawn
                .and_then(|d| scene.graph.scenes.get(d))
                .map_or(String::new(), |s| format!(" ('{}' drawn)", s.name)),
            scene.skins.len(),
            scene.animations.len()
        );
    }
    if !scene.variants.is_empty() {
        say!(
            "  material variants (--variant NAME): {}",
            scene.variants.join(", ")
        );
    }
    if scene.graph.scenes.len() > 1 {
        for (i, s) in scene.graph.scenes.iter().enumerate() {
            let drawn = if scene.graph.drawn == Some(i) {
                ", drawn"
            } else {
                ""
            };
            say!(
                "  scene {i} '{}' (--scene {i}): {} root node(s){drawn}",
                s.name,
                s.roots.len()
            );
        }
    }
    for s in &scene.skins {
        say!("  skin '{}': {} joints", s.name, s.joints.len());
    }
    for (i, a) in scene.animations.iter().enumerate() {
        let sampling: std::collections::BTreeSet<&str> =
            a.samplers.iter().map(|s| s.interpolation.name()).collect();
        say!(
            "  animation {i} '{}' (--animation {i}): {:.3} s, {} channel(s), {}",
            a.name,
            a.duration(),
            a.channels.len(),
            sampling.into_iter().collect::<Vec<_>>().join(", ")
        );
    }
    for l in &scene.lights {
        say!(
            "  light '{}': {} colour {} x {}, position {}, direction {}, attenuation {}",
            l.name,
            l.kind.name(),
            l.color,
            l.intensity,
            l.position,
            l.direction,
            l.attenuation.name()
        );
    }
    for (i, m) in scene.materials.iter().enumerate() {
        for slot in realist::scene::Slot::ALL {
            if let Some(t) = m.slot(slot) {
                say!(
                    "  material {i} '{}' {} map: {}",
                    m.name,
                    slot.name(),
                    t.describe()
                );
            }
        }
    }
    for w in &scene.report.warnings {
        say!("  warning: {w}");
    }
    for g in &scene.report.generated {
        say!("  generated: {g}");
    }
    for l in &scene.report.loaded {
        say!("  loaded: {l}");
    }
    for s in &scene.report.skipped {
        say!("  skipped: {s}");
    }
    Ok(())
}
