//! The scene model every loader produces and the renderer consumes: meshes, materials,
//! textures, instances with world matrices, lights and cameras. No rasterizing, no I/O.

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use crate::mesh::Mesh;
use crate::texture::Texture;

mod camera;
mod demo;
mod light;

pub use camera::{clamp_fov, Camera, DEFAULT_YFOV};
pub use demo::{demo, DEMO_SLICES, DEMO_STACKS};
pub use light::{Attenuation, Light, LightKind, MIN_D2};

/// How a material's alpha is used (glTF `alphaMode`; OBJ `d` < 1 maps to `Blend`).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum AlphaMode {
    #[default]
    Opaque,
    /// Fragments with alpha below the cutoff are discarded.
    Mask(f32),
    /// Alpha blending (drawn after opaque geometry).
    Blend,
}

/// A reference to one of the scene's textures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRef {
    /// Index into [`Scene::textures`].
    pub texture: usize,
    /// Which UV set (only 0 is carried by meshes for now).
    pub tex_coord: u32,
}

/// Surface description: the Phong parameters of the textbook plus the glTF PBR core.
/// Colours are linear RGB.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// Base (diffuse) colour `Kd` and alpha (`d` in MTL).
    pub base_color: Vec4,
    pub base_color_texture: Option<TextureRef>,
    /// Ambient reflectance `Ka`.
    pub ambient: Vec3,
    /// Specular reflectance `Ks`.
    pub specular: Vec3,
    /// Gloss map (003 §7, MTL `map_Ks`): its RGB multiplies `specular` per pixel in the
    /// per-pixel modes (textured, Phong, Blinn on a mesh with UVs).
    pub specular_texture: Option<TextureRef>,
    /// Phong exponent `Ns` (the textbook's n, 1..2000).
    pub shininess: f32,
    pub emissive: Vec3,
    pub metallic: f32,
    pub roughness: f32,
    pub alpha_mode: AlphaMode,
    pub double_sided: bool,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            name: "default".into(),
            base_color: Vec4::new(0.3, 0.32, 0.36, 1.0),
            base_color_texture: None,
            ambient: Vec3::splat(1.0),
            specular: Vec3::splat(0.6),
            specular_texture: None,
            shininess: 80.0,
            emissive: Vec3::ZERO,
            metallic: 0.0,
            roughness: 0.5,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
        }
    }
}

/// How one instance is drawn when the render does not force a mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Style {
    /// Whatever the render options say.
    #[default]
    Inherit,
    /// Always wireframe (e.g. the demo's first sphere).
    Wireframe,
    /// Always flat (faceted).
    Flat,
}

/// A mesh placed in the world.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    /// Index into [`Scene::meshes`].
    pub mesh: usize,
    /// Model -> world.
    pub world: Mat4,
    /// Name of the node it came from (for reports).
    pub name: String,
    pub style: Style,
}

/// Something the loader wants the user to know that did not stop the load.
#[derive(Clone, Debug, PartialEq)]
pub struct Warning(pub String);

/// What a loader did: counts and warnings (printed by `realist info`).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct LoadReport {
    pub file: String,
    pub format: String,
    pub warnings: Vec<String>,
    /// Primitives skipped (points, lines, unsupported), with the reason.
    pub skipped: Vec<String>,
    /// Meshes whose normals were generated rather than read, with how.
    pub generated: Vec<String>,
}

/// Everything that was loaded, ready to be prepared for rendering.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    pub meshes: Vec<Mesh>,
    /// Materials; meshes without one use [`Material::default`].
    pub materials: Vec<Material>,
    /// Decoded once, shared between materials.
    pub textures: Vec<Arc<Texture>>,
    pub instances: Vec<Instance>,
    pub lights: Vec<Light>,
    /// Cameras defined by the file (glTF); the renderer may use one of them.
    pub cameras: Vec<Camera>,
    pub report: LoadReport,
}

impl Scene {
    /// World-space axis-aligned bounds of all instances, or `None` for an empty scene
    /// (or one whose every position is non-finite).
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for inst in &self.instances {
            let Some(mesh) = self.meshes.get(inst.mesh) else {
                continue;
            };
            let Some((mlo, mhi)) = mesh.bounds() else {
                continue;
            };
            for i in 0..8 {
                let c = Vec3::new(
                    if i & 1 == 0 { mlo.x } else { mhi.x },
                    if i & 2 == 0 { mlo.y } else { mhi.y },
                    if i & 4 == 0 { mlo.z } else { mhi.z },
                );
                let w = inst.world.transform_point3(c);
                if w.is_finite() {
                    lo = lo.min(w);
                    hi = hi.max(w);
                }
            }
        }
        (lo.x <= hi.x).then_some((lo, hi))
    }

    /// Material of a mesh, falling back to the default material.
    #[must_use]
    pub fn material_of(&self, mesh: &Mesh) -> std::borrow::Cow<'_, Material> {
        match mesh.material.and_then(|m| self.materials.get(m)) {
            Some(m) => std::borrow::Cow::Borrowed(m),
            None => std::borrow::Cow::Owned(Material::default()),
        }
    }
}
