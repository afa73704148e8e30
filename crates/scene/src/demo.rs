//! The built-in demo scene: the textbook program's signature figure (the textbook's §9.7, figure
//! 9-8), three latitude/longitude spheres side by side - wireframe, faceted, smooth - standing on a
//! floor, under a floodlight (an omni light) and a spotlight whose cone draws a pool of light on
//! the floor (hotspot and falloff visible) and throws the spheres' shadows.

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
            node: None,
            skin: None,
            copies: None,
        });
        scene.meshes.push(mesh);
    }
    // The floor the spheres stand on: dark, matte, finely cut so Gouraud shading (when
    // forced) still shows the spotlight's pool.
    let mut floor = Mesh::grid(10.0, 7.0, 80, 56).expect("demo floor parameters are valid");
    floor.name = "floor".into();
    floor.material = Some(scene.materials.len());
    scene.materials.push(Material {
        name: "floor".into(),
        base_color: Vec4::new(0.3, 0.3, 0.32, 1.0),
        specular: Vec3::splat(0.04),
        shininess: 8.0,
        ..Material::default()
    });
    scene.instances.push(Instance {
        mesh: scene.meshes.len(),
        world: Mat4::from_translation(Vec3::new(0.0, -1.0, -3.0)),
        name: "floor".into(),
        style: Style::Inherit,
        node: None,
        skin: None,
        copies: None,
    });
    scene.meshes.push(floor);
    let spot_at = Vec3::new(3.5, 7.5, 4.0);
    let spot_to = Vec3::new(0.9, -1.0, -0.6);
    scene.lights = vec![
        Light::ambient(Vec3::splat(0.06)).with_name("ambient"),
        // The floodlight: a soft omni light above, left and in front.
        Light::point(Vec3::new(-5.0, 5.0, 6.0), Vec3::new(0.42, 0.44, 0.5)).with_name("floodlight"),
        // The spotlight: warm white from above right, aimed between the faceted and the
        // smooth sphere, 14 degree hotspot inside a 22 degree falloff, casting shadows.
        Light::spot(
            spot_at,
            spot_to - spot_at,
            Vec3::new(1.0, 0.93, 0.8),
            14f32.to_radians(),
            22f32.to_radians(),
        )
        .with_intensity(1.3)
        .with_shadow(true)
        .with_name("spotlight"),
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
