//! The parallel mesh building must give exactly what the serial one did (kept in
//! `reference/`): compared field by field through `Debug`, which prints every `f32` in its
//! shortest round-trip form (so two values print alike only if their bits agree, NaN
//! payloads aside).

use std::path::{Path, PathBuf};

use proptest::prelude::*;

use super::reference;
use super::{averaged, polygons, Channel, Mesh, MeshData, NormalPolicy, Weighting};
use crate::TriMesh;

fn fields_mesh(m: &Mesh) -> Vec<(&'static str, String)> {
    vec![
        ("positions", format!("{:?}", m.positions)),
        ("corners", format!("{:?}", m.corners)),
        ("facets", format!("{:?}", m.facets())),
        ("edges", format!("{:?}", m.edges())),
        ("corner_edges", format!("{:?}", m.corner_edges())),
        ("normals", format!("{:?}", m.normals)),
        ("normal_source", format!("{:?}", m.normal_source)),
        ("uvs", format!("{:?}", m.uvs)),
        ("colors", format!("{:?}", m.colors)),
        ("tangents", format!("{:?}", m.tangents)),
    ]
}

fn fields_tri(t: &TriMesh) -> Vec<(&'static str, String)> {
    vec![
        ("tri.positions", format!("{:?}", t.positions)),
        ("tri.normals", format!("{:?}", t.normals)),
        ("tri.uvs", format!("{:?}", t.uvs)),
        ("tri.colors", format!("{:?}", t.colors)),
        ("tri.tangents", format!("{:?}", t.tangents)),
        ("tri.triangles", format!("{:?}", t.triangles)),
        ("tri.triangle_facets", format!("{:?}", t.triangle_facets)),
        ("tri.facet_normals", format!("{:?}", t.facet_normals)),
        ("tri.sphere", format!("{:?}", (t.center, t.radius))),
    ]
}

/// The first field where the new build differs from the reference, if any.
fn first_difference(data: &MeshData, policy: NormalPolicy) -> Option<&'static str> {
    let new = Mesh::new(data.clone(), policy).ok()?;
    let old = reference::mesh(data.clone(), policy);
    let (a, b) = (fields_mesh(&new), fields_mesh(&old));
    if let Some(((name, _), _)) = a.iter().zip(&b).find(|(x, y)| x.1 != y.1) {
        return Some(name);
    }
    let (a, b) = (
        fields_tri(&new.triangulate()),
        fields_tri(&reference::triangulate(&old)),
    );
    a.iter().zip(&b).find(|(x, y)| x.1 != y.1).map(|(x, _)| x.0)
}

fn policies() -> Vec<NormalPolicy> {
    let mut out = vec![NormalPolicy::Flat];
    for w in [Weighting::Angle, Weighting::Area, Weighting::Uniform] {
        for crease in [None, Some(0.0), Some(30.0), Some(60.0), Some(179.0)] {
            out.push(averaged(w, crease));
        }
    }
    out
}

#[track_caller]
fn assert_same(data: &MeshData, what: &str) {
    for policy in policies() {
        if let Some(field) = first_difference(data, policy) {
            panic!("{what}, {policy:?}: `{field}` differs from the serial build");
        }
    }
}

fn model_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            model_files(&p, out);
        } else if p
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| matches!(e.to_ascii_lowercase().as_str(), "obj" | "gltf" | "glb"))
        {
            out.push(p);
        }
    }
}

/// Every mesh of every shared model, rebuilt from its raw data with every normal policy,
/// with and without its (file or generated) normals as read normals.
#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn shared_models_build_bit_identical_to_the_serial_build() {
    let shared = realist_testkit::shared("parallel build");
    let mut files = Vec::new();
    model_files(&shared.join("models"), &mut files);
    files.sort();
    assert!(!files.is_empty());
    for file in files {
        let Ok(scene) = realist_load::load(&file, &realist_load::LoadOptions::default()) else {
            continue;
        };
        for mesh in &scene.meshes {
            let sizes: Vec<u32> = mesh.facets().iter().map(|f| f.len).collect();
            let mut data = polygons(mesh.positions.clone(), mesh.corners.clone(), sizes);
            // The loader's meshes are those of its own copy of this crate (a dev-dependency
            // cycle): the channels are rebuilt from their plain data.
            macro_rules! ch {
                ($c:expr) => {
                    Channel {
                        values: $c.values.clone(),
                        indices: $c.indices.clone(),
                    }
                };
            }
            data.uvs = mesh.uvs.iter().map(|c| ch!(c)).collect();
            data.colors = mesh.colors.as_ref().map(|c| ch!(c));
            data.tangents = mesh.tangents.as_ref().map(|c| ch!(c));
            let what = format!("{} '{}'", file.display(), mesh.name);
            assert_same(&data, &what);
            data.normals = Some(ch!(mesh.normals));
            assert_same(&data, &format!("{what} with normals"));
            if mesh.facets().iter().all(|f| f.len == 3) {
                let triangles = MeshData {
                    facet_sizes: None,
                    normals: None,
                    ..data
                };
                assert_same(&triangles, &format!("{what} as a triangle list"));
            }
        }
    }
}

#[test]
fn primitives_build_bit_identical_to_the_serial_build() {
    let meshes = [
        Mesh::cube(2.0).unwrap(),
        Mesh::sphere(1.0, 24, 12).unwrap(),
        Mesh::torus(1.0, 0.3, 24, 12).unwrap(),
    ];
    for m in meshes {
        let sizes: Vec<u32> = m.facets().iter().map(|f| f.len).collect();
        let data = polygons(m.positions.clone(), m.corners.clone(), sizes);
        assert_same(&data, &m.name);
        let data = MeshData {
            normals: Some(Channel::per_vertex(vec![
                glam::Vec3::ZERO;
                m.positions.len()
            ])),
            ..data
        };
        assert_same(&data, &format!("{} with zero normals", m.name));
    }
}

proptest! {
    #[test]
    fn arbitrary_meshes_build_bit_identical_to_the_serial_build(
        data in super::build::arbitrary_mesh(),
        crease in prop::option::of(0.0f32..200.0),
    ) {
        crate::par::FORCE_SPLIT.store(true, std::sync::atomic::Ordering::Relaxed);
        for policy in [averaged(Weighting::Angle, crease), averaged(Weighting::Area, crease),
                       averaged(Weighting::Uniform, crease), NormalPolicy::Flat] {
            let generated = MeshData { normals: None, ..data.clone() };
            for d in [&data, &generated, &data.clone().weld_positions()] {
                prop_assert_eq!(first_difference(d, policy), None);
            }
        }
    }
}
