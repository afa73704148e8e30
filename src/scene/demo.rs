//! The built-in demo scene: the seed program's signature figure (seed 000, figure 9-8), three
//! latitude/longitude spheres side by side - wireframe, faceted, smooth - under a floodlight
//! and a second light (a point light standing in for the spotlight until spot lights exist).

use glam::{Mat4, Vec3, Vec4};

use super::{Camera, Instance, Light, Material, Scene, Style};
use crate::mesh::Mesh;

/// Slices (longitude) and stacks (latitude) of the demo spheres: coarse enough that the
/// faceted sphere shows its facets, fine enough that the smooth one looks round.
pub const DEMO_SLICES: u32 = 24;
pub const DEMO_STACKS: u32 = 16;

/// Builds the demo scene with its camera in `cameras[0]`.
///
/// # Panics
/// Never in practice: the sphere parameters are constants within the builder's limits.
#[must_use]
pub fn demo() -> Scene {
    let mut scene = Scene::default();
    let looks = [
        (
            "wireframe",
            Style::Wireframe,
            Vec4::new(0.35, 0.65, 1.0, 1.0),
            0.0,
        ),
        (
            "faceted",
            Style::Flat,
            Vec4::new(0.9, 0.45, 0.12, 1.0),
            0.35,
        ),
        (
            "smooth",
            Style::Inherit,
            Vec4::new(0.75, 0.1, 0.1, 1.0),
            0.6,
        ),
    ];
    for (k, (name, style, color, spec)) in looks.into_iter().enumerate() {
        let mut mesh =
            Mesh::sphere(1.0, DEMO_SLICES, DEMO_STACKS).expect("demo sphere parameters are valid");
        mesh.name = format!("{name} sphere");
        mesh.material = Some(scene.materials.len());
        scene.materials.push(Material {
            name: name.into(),
            base_color: color,
            specular: Vec3::splat(spec),
            shininess: 40.0,
            ..Material::default()
        });
        scene.instances.push(Instance {
            mesh: scene.meshes.len(),
            world: Mat4::from_translation(Vec3::new((k as f32 - 1.0) * 2.4, 0.0, 0.0)),
            name: name.into(),
            style,
        });
        scene.meshes.push(mesh);
    }
    scene.lights = vec![
        Light::ambient(Vec3::splat(0.08)),
        // The floodlight: a bright omni light above, left and in front.
        Light::point(Vec3::new(-4.0, 6.0, 7.0), Vec3::splat(0.95)),
        // Stand-in for the spotlight: a warmer, dimmer light from the right.
        Light::point(Vec3::new(6.0, 2.0, 3.0), Vec3::new(0.5, 0.42, 0.3)),
    ];
    let mut camera = Camera {
        name: "demo".into(),
        eye: Vec3::new(0.0, 1.3, 6.6),
        ..Camera::default()
    };
    camera.fit(Vec3::ZERO, 3.6);
    scene.cameras.push(camera);
    scene.report.file = "<demo>".into();
    scene.report.format = "built-in".into();
    scene
}
