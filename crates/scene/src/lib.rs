//! The scene model every loader produces and the renderer consumes: meshes, materials,
//! textures, instances with world matrices, lights and cameras. No rasterizing, no I/O.

// The crates below this one, under the module names the code uses (`crate::scene::...`).
use realist_mesh as mesh;
use realist_texture as texture;

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use crate::mesh::Mesh;
use crate::texture::Texture;

pub mod anim;
mod camera;
mod demo;
pub mod graph;
mod light;
mod slot;
mod tube;
mod uvgen;

pub use camera::{clamp_fov, Camera, Lens, Up, DEFAULT_YFOV};
pub use demo::{demo, DEMO_SLICES, DEMO_STACKS};
pub use light::{Attenuation, Light, LightKind, MIN_D2};
pub use slot::{
    Slot, SlotOverride, SlotOverrides, TextureSlot, TextureSource, UvTransform, DEFAULT_BUMP_SCALE,
};
pub use tube::{skinned_tube, TubeError, MAX_TUBE_VERTICES};
pub use uvgen::UvOutcome;

pub use anim::{Animation, Interpolation, Play, Property};
pub use graph::{Graph, Local, Node, Pose, Trs};

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

/// Surface description: the Phong parameters of the textbook plus the glTF PBR core.
/// Colours are linear RGB.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// Base colour and alpha: MTL's `Kd` and `d`, glTF's `baseColorFactor` (the Phong modes
    /// draw a metallic-roughness material with `K_d = base (1 - metallic)`).
    pub base_color: Vec4,
    /// [`Slot::BaseColor`]: multiplies `base_color` (RGB and alpha).
    pub base_color_texture: Option<TextureSlot>,
    /// Ambient reflectance `Ka`.
    pub ambient: Vec3,
    /// Specular reflectance `Ks`.
    pub specular: Vec3,
    /// [`Slot::Specular`], the gloss map (the pipeline chapter's §7, MTL `map_Ks`): its RGB
    /// multiplies `specular` per pixel in the per-pixel modes.
    pub specular_texture: Option<TextureSlot>,
    /// Phong exponent `Ns` (the textbook's n, 1..2000).
    pub shininess: f32,
    /// Emitted light, linear RGB (glTF `emissiveFactor`, MTL `Ke`).
    pub emissive: Vec3,
    /// [`Slot::Emissive`]: multiplies `emissive`.
    pub emissive_texture: Option<TextureSlot>,
    /// [`Slot::Normal`]: a tangent-space normal map, its `scale` on x and y.
    pub normal_texture: Option<TextureSlot>,
    /// [`Slot::Occlusion`]: ambient occlusion in R, its `scale` the strength.
    pub occlusion_texture: Option<TextureSlot>,
    /// [`Slot::Bump`]: a height map (R), its `scale` the height of 1.0 in UV units.
    pub bump_texture: Option<TextureSlot>,
    pub metallic: f32,
    pub roughness: f32,
    /// [`Slot::MetallicRoughness`]: G multiplies `roughness`, B `metallic`.
    pub metallic_roughness_texture: Option<TextureSlot>,
    /// The slots of the `KHR_materials_*` extensions ([`Slot::LAYERS`], in its order), if
    /// the material has any (boxed: most have none).
    pub layer_textures: Option<Box<LayerTextures>>,
    pub alpha_mode: AlphaMode,
    pub double_sided: bool,
    /// `Some` for a material authored as glTF metallic-roughness (or an MTL with PBR keys):
    /// what the `pbr` mode reads beyond `metallic`, `roughness` and the slots.
    pub pbr: Option<PbrMaterial>,
}

/// The metallic-roughness parameters of a material that the Phong fields cannot hold
/// (glTF 2.0 core and the `KHR_materials_*` extensions realist reads).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PbrMaterial {
    /// `KHR_materials_ior`: index of refraction (1.5 by default: F0 = 0.04; 0 means
    /// Fresnel 1 everywhere).
    pub ior: f32,
    /// `KHR_materials_specular`: `specularFactor` (F90 of the dielectric lobe, and a
    /// factor on its F0), 1 by default.
    pub specular: f32,
    /// `KHR_materials_specular`: `specularColorFactor`, linear RGB (a factor on F0).
    pub specular_color: Vec3,
    /// `KHR_materials_emissive_strength`: multiplies the emission (1 by default).
    pub emissive_strength: f32,
    /// `KHR_materials_unlit`: the base colour is shown as it is, without lighting.
    pub unlit: bool,
    /// `KHR_materials_clearcoat`: `clearcoatFactor` (0: no coat) and
    /// `clearcoatRoughnessFactor` of the clear layer over the material.
    pub clearcoat: f32,
    pub clearcoat_roughness: f32,
    /// `KHR_materials_sheen`: `sheenColorFactor` (linear RGB; black: no sheen) and
    /// `sheenRoughnessFactor` of the cloth-like layer over the base.
    pub sheen_color: Vec3,
    pub sheen_roughness: f32,
    /// `KHR_materials_iridescence`: `iridescenceFactor` (0: no film), the film's
    /// `iridescenceIor` and its thickness range in nanometres (`iridescenceThicknessMinimum`,
    /// `Maximum`; without a thickness texture the film is the maximum thick).
    pub iridescence: f32,
    pub iridescence_ior: f32,
    pub iridescence_thickness: [f32; 2],
    /// `KHR_materials_anisotropy`: `anisotropyStrength` (0: isotropic) and
    /// `anisotropyRotation` (radians, counter-clockwise from the tangent in the tangent
    /// frame) of the direction the highlight stretches along.
    pub anisotropy: f32,
    pub anisotropy_rotation: f32,
    /// `KHR_materials_diffuse_transmission`: `diffuseTransmissionFactor` (0: none), the
    /// share of the diffuse light that passes through the surface (a leaf, paper, a lamp
    /// shade), and `diffuseTransmissionColorFactor`, its colour (linear RGB).
    pub diffuse_transmission: f32,
    pub diffuse_transmission_color: Vec3,
    /// `KHR_materials_transmission`: `transmissionFactor` (0: opaque), the share of the
    /// light that passes through the base specularly (glass, water, thin plastic).
    pub transmission: f32,
    /// `KHR_materials_volume`: `thicknessFactor` (0: thin-walled; else the thickness of the
    /// volume under the surface, in the mesh's units), `attenuationDistance` (infinite: no
    /// absorption) and `attenuationColor`: white light has that colour after that distance.
    pub thickness: f32,
    pub attenuation_distance: f32,
    pub attenuation_color: Vec3,
    /// `KHR_materials_dispersion`: `dispersion` (0: none), 20 / the Abbe number.
    pub dispersion: f32,
}

impl Default for PbrMaterial {
    fn default() -> Self {
        Self {
            ior: 1.5,
            specular: 1.0,
            specular_color: Vec3::ONE,
            emissive_strength: 1.0,
            unlit: false,
            clearcoat: 0.0,
            clearcoat_roughness: 0.0,
            sheen_color: Vec3::ZERO,
            sheen_roughness: 0.0,
            iridescence: 0.0,
            iridescence_ior: 1.3,
            iridescence_thickness: [100.0, 400.0],
            anisotropy: 0.0,
            anisotropy_rotation: 0.0,
            diffuse_transmission: 0.0,
            diffuse_transmission_color: Vec3::ONE,
            transmission: 0.0,
            thickness: 0.0,
            attenuation_distance: f32::INFINITY,
            attenuation_color: Vec3::ONE,
            dispersion: 0.0,
        }
    }
}

impl PbrMaterial {
    /// The dielectric lobe's Fresnel at normal incidence and at grazing incidence:
    /// `F0 = min(F0_ior · specularColor, 1) · specular`, `F90 = specular`
    /// (`KHR_materials_specular` over `KHR_materials_ior`).
    #[must_use]
    pub fn dielectric_fresnel(&self) -> (Vec3, f32) {
        let s = if self.specular.is_finite() {
            self.specular.clamp(0.0, 1.0)
        } else {
            1.0
        };
        (self.f0_tint().min(Vec3::ONE) * s, s)
    }

    /// `F0_ior · specularColor` before the clamp (what a `specularColorTexture` multiplies).
    #[must_use]
    pub fn f0_tint(&self) -> Vec3 {
        let f0 = crate::texture::microfacet::f0_of_ior(self.ior);
        let c = if self.specular_color.is_finite() {
            self.specular_color.max(Vec3::ZERO)
        } else {
            Vec3::ONE
        };
        c * f0
    }
}

impl Material {
    /// The texture of `slot`, if the material has one.
    #[must_use]
    pub fn slot(&self, slot: Slot) -> Option<&TextureSlot> {
        match slot {
            Slot::BaseColor => self.base_color_texture.as_ref(),
            Slot::Specular => self.specular_texture.as_ref(),
            Slot::Normal => self.normal_texture.as_ref(),
            Slot::Occlusion => self.occlusion_texture.as_ref(),
            Slot::Emissive => self.emissive_texture.as_ref(),
            Slot::MetallicRoughness => self.metallic_roughness_texture.as_ref(),
            Slot::Bump => self.bump_texture.as_ref(),
            // The rest are the extensions' slots: `layer_index` is `Some`.
            layer => self.layer_textures.as_ref()?[layer.layer_index()?].as_ref(),
        }
    }

    /// The texture of `slot`, to set or change.
    pub fn slot_mut(&mut self, slot: Slot) -> &mut Option<TextureSlot> {
        match slot {
            Slot::BaseColor => &mut self.base_color_texture,
            Slot::Specular => &mut self.specular_texture,
            Slot::Normal => &mut self.normal_texture,
            Slot::Occlusion => &mut self.occlusion_texture,
            Slot::Emissive => &mut self.emissive_texture,
            Slot::MetallicRoughness => &mut self.metallic_roughness_texture,
            Slot::Bump => &mut self.bump_texture,
            // The rest are the extensions' slots: `layer_index` is `Some`.
            layer => {
                let all = self.layer_textures.get_or_insert_with(Box::default);
                &mut all[layer.layer_index().unwrap_or_default()]
            }
        }
    }
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
            emissive_texture: None,
            normal_texture: None,
            occlusion_texture: None,
            bump_texture: None,
            metallic: 0.0,
            roughness: 0.5,
            metallic_roughness_texture: None,
            layer_textures: None,
            alpha_mode: AlphaMode::Opaque,
            double_sided: false,
            pbr: None,
        }
    }
}

/// The textures of a material's [`Slot::LAYERS`], in that order.
pub type LayerTextures = [Option<TextureSlot>; Slot::LAYERS.len()];

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
    /// The node that places it ([`Scene::graph`]); `None` for formats without nodes.
    pub node: Option<usize>,
    /// The skin that deforms it ([`Scene::skins`]); its mesh then has joints and weights,
    /// and `world` is ignored when posed (the joints place the vertices).
    pub skin: Option<usize>,
    /// `EXT_mesh_gpu_instancing`: the mesh is drawn once per matrix, copy `i` placed by
    /// `world * copies[i]`, the copies sharing the mesh and its material (a forest of a
    /// million trees is one mesh and a million matrices). `None`: drawn once, at `world`.
    pub copies: Option<Arc<[Mat4]>>,
}

impl Instance {
    /// How many times the instance is drawn (1 without [`Self::copies`]).
    #[must_use]
    pub fn copy_count(&self) -> usize {
        self.copies.as_ref().map_or(1, |c| c.len())
    }

    /// The model -> world matrix of copy `i` (`world` itself without copies).
    #[must_use]
    pub fn placement(&self, i: usize) -> Mat4 {
        match &self.copies {
            Some(c) => self.world * c[i],
            None => self.world,
        }
    }

    /// Every copy's model -> world matrix, in order.
    pub fn placements(&self) -> impl Iterator<Item = Mat4> + '_ {
        (0..self.copy_count()).map(|i| self.placement(i))
    }
}

/// A glTF skin: the joints (nodes) whose world matrices, times their inverse bind
/// matrices, deform the vertices of the meshes bound to it.
#[derive(Clone, Debug, PartialEq)]
pub struct Skin {
    pub name: String,
    /// Nodes of [`Scene::graph`].
    pub joints: Vec<usize>,
    /// One per joint (the identity where the file gives none).
    pub inverse_bind: Vec<Mat4>,
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
    /// Primitives skipped (unsupported or empty), with the reason.
    pub skipped: Vec<String>,
    /// What was generated rather than read (normals, tangents, texture coordinates), per
    /// mesh, with how.
    pub generated: Vec<String>,
    /// Points and lines loaded (glTF primitives, OBJ `p` and `l`), each with its count
    /// and whether it is lit.
    pub loaded: Vec<String>,
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
    /// The node tree (empty for formats without nodes).
    pub graph: Graph,
    pub skins: Vec<Skin>,
    pub animations: Vec<Animation>,
    /// The names of the file's material variants (`KHR_materials_variants`), in file order;
    /// each mesh maps them to materials ([`crate::mesh::Mesh::material_in`]).
    pub variants: Vec<String>,
    pub report: LoadReport,
}

/// The world-space axis-aligned box around model-space boxes placed by matrices (each box's
/// eight corners transformed; non-finite corners left out), or `None` when nothing is left.
#[must_use]
pub fn world_bounds(boxes: impl IntoIterator<Item = (Mat4, (Vec3, Vec3))>) -> Option<(Vec3, Vec3)> {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for (world, (mlo, mhi)) in boxes {
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { mlo.x } else { mhi.x },
                if i & 2 == 0 { mlo.y } else { mhi.y },
                if i & 4 == 0 { mlo.z } else { mhi.z },
            );
            let w = world.transform_point3(c);
            if w.is_finite() {
                lo = lo.min(w);
                hi = hi.max(w);
            }
        }
    }
    (lo.x <= hi.x).then_some((lo, hi))
}

impl Scene {
    /// World-space axis-aligned bounds of all instances, or `None` for an empty scene
    /// (or one whose every position is non-finite).
    #[must_use]
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        world_bounds(self.instances.iter().flat_map(|inst| {
            let b = self.meshes.get(inst.mesh).and_then(Mesh::bounds);
            inst.placements().filter_map(move |w| Some((w, b?)))
        }))
    }

    /// Whether some instance draws something: a mesh with a face, a point or a line.
    #[must_use]
    pub fn draws_anything(&self) -> bool {
        self.instances.iter().any(|i| {
            self.meshes.get(i.mesh).is_some_and(|m| {
                !m.corners.is_empty() || !m.points.is_empty() || !m.lines.is_empty()
            })
        })
    }

    /// `Err` with the one-line message naming `path` when the scene draws nothing (a text
    /// file named `.obj`, a PLY point cloud, a glTF with only cameras): opening it would
    /// only replace what is on screen with an empty view.
    ///
    /// # Errors
    /// The scene draws nothing.
    pub fn check_drawable(&self, path: &std::path::Path) -> Result<(), String> {
        if self.draws_anything() {
            return Ok(());
        }
        let why = self
            .report
            .warnings
            .first()
            .map_or(String::new(), |w| format!(" ({w})"));
        Err(format!(
            "{}: nothing to draw: no faces, points or lines{why}",
            path.display()
        ))
    }

    /// Checks every mesh against its material's texture slots, once after loading: a slot
    /// that reads a UV set the mesh does not have is named in the load report (it is drawn
    /// without that texture), and a mesh with a normal map but no tangents gets MikkTSpace
    /// tangents from the normal map's UV set ([`Mesh::generate_tangents`]), noted as
    /// generated.
    pub fn check_texture_slots(&mut self) {
        for mesh in &mut self.meshes {
            let Some(m) = mesh.material.and_then(|m| self.materials.get(m)) else {
                continue;
            };
            for slot in Slot::ALL {
                let Some(s) = m.slot(slot) else { continue };
                if mesh.uvs.len() <= s.uv_set as usize {
                    self.report.warnings.push(missing_uv_set(
                        &mesh.name,
                        &m.name,
                        slot,
                        s.uv_set,
                        mesh.uvs.len(),
                    ));
                }
            }
            // The clear coat's normal map reads the same tangents, and so does anisotropy
            // (its direction is in the tangent frame), with or without a texture.
            let normal_map = (m.normal_texture.as_ref().map(|n| (n.uv_set, Slot::Normal)))
                .or_else(|| {
                    m.slot(Slot::ClearcoatNormal)
                        .map(|n| (n.uv_set, Slot::ClearcoatNormal))
                })
                .or_else(|| {
                    m.slot(Slot::Anisotropy)
                        .map(|n| (n.uv_set, Slot::Anisotropy))
                })
                .or_else(|| {
                    m.pbr
                        .is_some_and(|p| p.anisotropy > 0.0)
                        .then_some((0, Slot::Anisotropy))
                });
            if let (Some((set, slot)), None) = (normal_map, &mesh.tangents) {
                match mesh.generate_tangents(set) {
                    Ok(()) => self.report.generated.push(format!(
                        "mesh '{}': MikkTSpace tangents from TEXCOORD_{set} ({} of material \
                         '{}')",
                        mesh.name,
                        if slot == Slot::Anisotropy {
                            "anisotropy".to_owned()
                        } else {
                            format!("{} map", slot.name())
                        },
                        m.name
                    )),
                    Err(_) if slot == Slot::Anisotropy => self.report.warnings.push(format!(
                        "mesh '{}': material '{}' is anisotropic but the mesh has neither \
                         tangents nor TEXCOORD_{set} to make them from: drawn isotropic",
                        mesh.name, m.name
                    )),
                    Err(_) => {}
                }
            }
        }
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

/// The load report's warning for a mesh whose material reads its `slot` texture from UV set
/// `set` when the mesh has only `has` sets ([`Scene::check_texture_slots`]; removed again by
/// [`Scene::apply_uv_generator`] when it adds set 0).
pub(crate) fn missing_uv_set(
    mesh: &str,
    material: &str,
    slot: Slot,
    set: u32,
    has: usize,
) -> String {
    format!(
        "mesh '{mesh}': material '{material}' reads its {} texture from TEXCOORD_{set}, which \
         the mesh does not have (it has {has}); drawn without it",
        slot.name()
    )
}
