//! A skinned, animated tube built in code: a fixture for skinning benchmarks
//! (`realist bench skin`), allocation tests and a first look at playback without a file.
//!
//! The tube stands on the origin along +Y, one unit per joint. `joints` nodes form a chain
//! (each one unit above its parent); every vertex is bound to the `influences` joints
//! nearest its height, with weights falling off as `1 / (1 + d)^2` and normalised. The
//! animation "bend" turns every joint but the root about +Z, keyed LINEAR at 0, 1, 2, 3, 4 s
//! to 0, +20°, 0, -20°, 0, so the tube sways one way and the other every 4 seconds.

use glam::{Mat4, Quat, Vec3};

use super::anim::{Channel, Interpolation, Property, Sampler};
use super::graph::{Graph, Local, Node, Trs};
use super::{Animation, Instance, Material, Scene, Skin, Style};
use crate::mesh::{Channel as MeshChannel, Deform, Mesh, MeshData, NormalPolicy};

/// Why a tube cannot be built.
#[derive(Debug, thiserror::Error)]
pub enum TubeError {
    #[error("a skinned tube needs at least 2 rings, 3 sides and 2 joints (got {rings}, {sides}, {joints})")]
    TooSmall {
        rings: u32,
        sides: u32,
        joints: usize,
    },
    #[error("{vertices} vertices are more than the {max} a skinned tube may have")]
    TooLarge { vertices: u64, max: u64 },
    #[error("{0} influences per vertex: expected 4 or 8")]
    Influences(usize),
    #[error(transparent)]
    Mesh(#[from] crate::mesh::MeshError),
}

/// Most vertices of a tube (16 M: about 1.5 GB with its rendering copies).
pub const MAX_TUBE_VERTICES: u64 = 1 << 24;

/// The tube of `rings` x `sides` vertices (radius 0.3), skinned to a chain of `joints`
/// joints with `influences` (4 or 8) joints per vertex, and its "bend" animation.
pub fn skinned_tube(
    rings: u32,
    sides: u32,
    joints: usize,
    influences: usize,
) -> Result<Scene, TubeError> {
    if rings < 2 || sides < 3 || joints < 2 || joints > usize::from(u16::MAX) {
        return Err(TubeError::TooSmall {
            rings,
            sides,
            joints,
        });
    }
    if influences != 4 && influences != 8 {
        return Err(TubeError::Influences(influences));
    }
    let vertices = u64::from(rings) * u64::from(sides);
    if vertices > MAX_TUBE_VERTICES {
        return Err(TubeError::TooLarge {
            vertices,
            max: MAX_TUBE_VERTICES,
        });
    }
    let length = (joints - 1) as f32;
    let (mut positions, mut normals) = (Vec::new(), Vec::new());
    let mut deform = Deform {
        influences,
        ..Deform::default()
    };
    for r in 0..rings {
        let y = length * r as f32 / (rings - 1) as f32;
        // The `influences` joints nearest y (all of them when the chain is shorter).
        let mut near: Vec<(f32, u16)> = (0..joints)
            .map(|j| ((y - j as f32).abs(), j as u16))
            .collect();
        near.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        near.truncate(influences);
        let raw: Vec<f32> = near.iter().map(|(d, _)| 1.0 / (1.0 + d).powi(2)).collect();
        let sum: f32 = raw.iter().sum();
        for s in 0..sides {
            let a = std::f32::consts::TAU * s as f32 / sides as f32;
            let n = Vec3::new(libm::cosf(a), 0.0, -libm::sinf(a));
            positions.push(Vec3::new(0.0, y, 0.0) + n * 0.3);
            normals.push(n);
            for (&(_, j), &w) in near.iter().zip(&raw) {
                deform.joints.push(j);
                deform.weights.push(w / sum);
            }
            // A chain shorter than `influences`: the rest weigh nothing.
            for _ in near.len()..influences {
                deform.joints.push(0);
                deform.weights.push(0.0);
            }
        }
    }
    let mut corners = Vec::new();
    for r in 0..rings - 1 {
        for s in 0..sides {
            let (a, b) = (r * sides + s, r * sides + (s + 1) % sides);
            let (c, d) = (a + sides, b + sides);
            corners.extend_from_slice(&[a, b, d, a, d, c]);
        }
    }
    let mut mesh = Mesh::new(
        MeshData {
            name: "tube".into(),
            positions,
            corners,
            normals: Some(MeshChannel::per_vertex(normals)),
            material: Some(0),
            ..MeshData::default()
        },
        NormalPolicy::Flat,
    )?;
    mesh.deform = Some(Box::new(deform));
    let mut nodes: Vec<Node> = (0..joints)
        .map(|j| Node {
            name: format!("joint {j}"),
            parent: j.checked_sub(1),
            children: if j + 1 < joints {
                vec![j + 1]
            } else {
                Vec::new()
            },
            local: Local::Trs(Trs {
                translation: if j == 0 { Vec3::ZERO } else { Vec3::Y },
                ..Trs::IDENTITY
            }),
            skin: None,
            weights: Vec::new(),
            instances: Vec::new(),
            cameras: Vec::new(),
            lights: Vec::new(),
        })
        .collect();
    nodes.push(Node {
        name: "tube".into(),
        parent: None,
        children: Vec::new(),
        local: Local::Trs(Trs::IDENTITY),
        skin: Some(0),
        weights: Vec::new(),
        instances: vec![0],
        cameras: Vec::new(),
        lights: Vec::new(),
    });
    let mesh_node = joints;
    let graph = Graph {
        order: (0..=joints).collect(),
        nodes,
        scenes: Vec::new(),
        drawn: None,
    };
    let angle = 20f32.to_radians();
    let keys: Vec<f32> = [0.0, angle, 0.0, -angle, 0.0]
        .iter()
        .flat_map(|&a| Quat::from_rotation_z(a).to_array())
        .collect();
    let sampler = Sampler::new(
        Interpolation::Linear,
        vec![0.0, 1.0, 2.0, 3.0, 4.0],
        keys,
        4,
    )
    .expect("the bend keys are valid");
    let bend = Animation {
        name: "bend".into(),
        samplers: vec![sampler],
        channels: (1..joints)
            .map(|node| Channel {
                node,
                property: Property::Rotation,
                sampler: 0,
            })
            .collect(),
    };
    Ok(Scene {
        meshes: vec![mesh],
        materials: vec![Material {
            name: "tube".into(),
            ..Material::default()
        }],
        instances: vec![Instance {
            mesh: 0,
            world: Mat4::IDENTITY,
            name: "tube".into(),
            style: Style::Inherit,
            node: Some(mesh_node),
            skin: Some(0),
            copies: None,
        }],
        skins: vec![Skin {
            name: "chain".into(),
            joints: (0..joints).collect(),
            inverse_bind: (0..joints)
                .map(|j| Mat4::from_translation(Vec3::new(0.0, -(j as f32), 0.0)))
                .collect(),
        }],
        animations: vec![bend],
        graph,
        ..Scene::default()
    })
}
