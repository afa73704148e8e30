//! Texture slots: which texture a material reads for which of its parameters, and how.
//!
//! A [`TextureSlot`] is glTF's `textureInfo` made whole: the decoded image (an index into
//! [`Scene::textures`](super::Scene::textures)), the sampler (filters and a wrap mode per
//! axis; glTF keeps it on the texture object, so two slots may sample one image two ways),
//! the texture coordinate set (`TEXCOORD_n`), the `KHR_texture_transform` of the UVs, and
//! the slot's scalar (`normalTexture.scale`, `occlusionTexture.strength`, the bump height).
//!
//! Which slots exist and what each means is [`Slot`]; the colour space of a slot's image
//! follows from the slot ([`Slot::srgb`]): colours (base colour, emissive, the gloss map) are
//! sRGB-encoded, data (normals, occlusion, metallic-roughness, heights) is linear.

use std::sync::Arc;

use glam::{Mat3, Vec2};

use crate::texture::{Domain, ProceduralTexture, Sampler, Texture};

/// A material parameter that a texture can drive.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Slot {
    /// Diffuse / base colour (`Kd`, `map_Kd`, glTF `baseColorTexture`): RGB and alpha.
    BaseColor,
    /// The gloss map (the pipeline chapter's §7, MTL `map_Ks`): RGB multiplies `Ks`.
    Specular,
    /// Tangent-space normal map (glTF `normalTexture`, MTL `norm`): RGB = (n + 1) / 2.
    Normal,
    /// Ambient occlusion (glTF `occlusionTexture`): R.
    Occlusion,
    /// Emitted light (glTF `emissiveTexture`, MTL `map_Ke`): RGB multiplies the factor.
    Emissive,
    /// glTF `metallicRoughnessTexture`: G roughness, B metallic.
    MetallicRoughness,
    /// A height map for bump mapping (MTL `bump` / `map_Bump`): R is the height, times the
    /// slot's scale: in texels for an image (MTL's `-bm`: 1 makes a full step over one texel
    /// a 45° slope), in units of UV for a 2D pattern, and in units of the model's bounding
    /// radius for a solid texture.
    Bump,
    /// `KHR_materials_specular` `specularTexture`: A multiplies `specularFactor` (the
    /// dielectric lobe's strength).
    SpecularStrength,
    /// `KHR_materials_specular` `specularColorTexture`: RGB multiplies
    /// `specularColorFactor` (the tint of the dielectric lobe's `F0`).
    SpecularColor,
    /// `KHR_materials_clearcoat` `clearcoatTexture`: R multiplies `clearcoatFactor`.
    Clearcoat,
    /// `KHR_materials_clearcoat` `clearcoatRoughnessTexture`: G multiplies
    /// `clearcoatRoughnessFactor`.
    ClearcoatRoughness,
    /// `KHR_materials_clearcoat` `clearcoatNormalTexture`: the coat's own tangent-space
    /// normal map (its `scale` on x and y), over the interpolated normal.
    ClearcoatNormal,
    /// `KHR_materials_sheen` `sheenColorTexture`: RGB multiplies `sheenColorFactor`.
    SheenColor,
    /// `KHR_materials_sheen` `sheenRoughnessTexture`: A multiplies `sheenRoughnessFactor`.
    SheenRoughness,
    /// `KHR_materials_iridescence` `iridescenceTexture`: R multiplies `iridescenceFactor`.
    Iridescence,
    /// `KHR_materials_iridescence` `iridescenceThicknessTexture`: G mixes the film's
    /// thickness from `iridescenceThicknessMinimum` (0) to `Maximum` (1).
    IridescenceThickness,
    /// `KHR_materials_anisotropy` `anisotropyTexture`: RG the direction in the tangent
    /// frame (from [0, 1] to [-1, 1]), B multiplies `anisotropyStrength`.
    Anisotropy,
    /// `KHR_materials_diffuse_transmission` `diffuseTransmissionTexture`: A multiplies
    /// `diffuseTransmissionFactor`.
    DiffuseTransmission,
    /// `KHR_materials_diffuse_transmission` `diffuseTransmissionColorTexture`: RGB
    /// multiplies `diffuseTransmissionColorFactor`.
    DiffuseTransmissionColor,
    /// `KHR_materials_transmission` `transmissionTexture`: R multiplies
    /// `transmissionFactor`.
    Transmission,
    /// `KHR_materials_volume` `thicknessTexture`: G multiplies `thicknessFactor`.
    Thickness,
}

/// Where [`Slot::LAYERS`] begins in [`Slot::ALL`].
const FIRST_LAYER: usize = Slot::SpecularStrength.index();

/// Every slot's name, scene-file key and whether its RGB is sRGB-encoded, in the order of
/// [`Slot::ALL`].
const INFO: [(&str, &str, bool); Slot::ALL.len()] = [
    ("base colour", "base_color", true),
    ("gloss", "gloss", true),
    ("normal", "normal", false),
    ("occlusion", "occlusion", false),
    ("emissive", "emissive", true),
    ("metallic-roughness", "metallic_roughness", false),
    ("bump", "bump", false),
    ("specular strength", "specular_strength", false),
    ("specular colour", "specular_color", true),
    ("clear coat", "clearcoat", false),
    ("clear-coat roughness", "clearcoat_roughness", false),
    ("clear-coat normal", "clearcoat_normal", false),
    ("sheen colour", "sheen_color", true),
    ("sheen roughness", "sheen_roughness", false),
    ("iridescence", "iridescence", false),
    ("iridescence thickness", "iridescence_thickness", false),
    ("anisotropy", "anisotropy", false),
    ("diffuse transmission", "diffuse_transmission", false),
    (
        "diffuse transmission colour",
        "diffuse_transmission_color",
        true,
    ),
    ("transmission", "transmission", false),
    ("thickness", "thickness", false),
];

impl Slot {
    /// Every slot, in the order panels and reports list them: the core ones, then
    /// [`Slot::LAYERS`].
    pub const ALL: [Slot; 21] = [
        Slot::BaseColor,
        Slot::Specular,
        Slot::Normal,
        Slot::Occlusion,
        Slot::Emissive,
        Slot::MetallicRoughness,
        Slot::Bump,
        Slot::SpecularStrength,
        Slot::SpecularColor,
        Slot::Clearcoat,
        Slot::ClearcoatRoughness,
        Slot::ClearcoatNormal,
        Slot::SheenColor,
        Slot::SheenRoughness,
        Slot::Iridescence,
        Slot::IridescenceThickness,
        Slot::Anisotropy,
        Slot::DiffuseTransmission,
        Slot::DiffuseTransmissionColor,
        Slot::Transmission,
        Slot::Thickness,
    ];

    /// The slots of the `KHR_materials_*` extensions, which only the `pbr` mode reads (in
    /// the order of [`Slot::layer_index`]): the end of [`Slot::ALL`].
    pub const LAYERS: [Slot; Slot::ALL.len() - FIRST_LAYER] = {
        let mut out = [Slot::BaseColor; Slot::ALL.len() - FIRST_LAYER];
        let mut i = 0;
        while i < out.len() {
            out[i] = Slot::ALL[FIRST_LAYER + i];
            i += 1;
        }
        out
    };

    /// The slot's position in [`Slot::LAYERS`], if it is one of them.
    #[must_use]
    pub const fn layer_index(self) -> Option<usize> {
        self.index().checked_sub(FIRST_LAYER)
    }

    /// The slot's name in reports, scene files and the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        INFO[self.index()].0
    }

    /// The slot's position in [`Slot::ALL`].
    #[must_use]
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The slot's name in scene-file keys (`base_color`, `bump`, ...).
    #[must_use]
    pub fn key(self) -> &'static str {
        INFO[self.index()].1
    }

    /// True if the slot's RGB is sRGB-encoded colour (decoded to linear light before
    /// filtering); false for linear data. Alpha is linear in every slot.
    #[must_use]
    pub fn srgb(self) -> bool {
        INFO[self.index()].2
    }
}

/// `KHR_texture_transform`: `uv' = offset + R(rotation) (scale ⊙ uv)`, with the rotation
/// turning UVs the way the implementations (and the extension's own example) do:
/// `u' = cos r · u₁ + sin r · v₁ + oₓ`, `v' = -sin r · u₁ + cos r · v₁ + o_y` where
/// `(u₁, v₁) = scale ⊙ uv`. (The extension's GLSL snippet turns the other way; glTF issue
/// #1563. glTF-Sample-Viewer, CesiumJS and gltfpack agree with the formula here.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    pub offset: Vec2,
    /// Radians.
    pub rotation: f32,
    pub scale: Vec2,
}

impl Default for UvTransform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl UvTransform {
    pub const IDENTITY: UvTransform = UvTransform {
        offset: Vec2::ZERO,
        rotation: 0.0,
        scale: Vec2::ONE,
    };

    /// True if it leaves every UV as it is.
    #[must_use]
    pub fn is_identity(&self) -> bool {
        *self == Self::IDENTITY
    }

    /// The transform as a 3x3 matrix on `(u, v, 1)`.
    #[must_use]
    pub fn matrix(&self) -> Mat3 {
        let (s, c) = libm::sincosf(self.rotation);
        let translation = Mat3::from_cols_array(&[
            1.0,
            0.0,
            0.0,
            0.0,
            1.0,
            0.0,
            self.offset.x,
            self.offset.y,
            1.0,
        ]);
        // Columns: u' = c u1 + s v1, v' = -s u1 + c v1.
        let rotation = Mat3::from_cols_array(&[c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0]);
        let scale = Mat3::from_diagonal(self.scale.extend(1.0));
        translation * rotation * scale
    }

    /// Transforms one UV.
    #[must_use]
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        if self.is_identity() {
            return uv;
        }
        self.matrix().transform_point2(uv)
    }

    /// The transform with every non-finite number replaced by its identity value (offset 0,
    /// rotation 0, scale 1), and whether anything was replaced.
    #[must_use]
    pub fn sanitized(self) -> (UvTransform, bool) {
        let fix = |v: f32, d: f32| if v.is_finite() { v } else { d };
        let t = UvTransform {
            offset: Vec2::new(fix(self.offset.x, 0.0), fix(self.offset.y, 0.0)),
            rotation: fix(self.rotation, 0.0),
            scale: Vec2::new(fix(self.scale.x, 1.0), fix(self.scale.y, 1.0)),
        };
        let changed = t != self;
        (t, changed)
    }
}

/// One slot's texture and how it is read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureSlot {
    /// Index into [`Scene::textures`](super::Scene::textures).
    pub texture: usize,
    /// Filters and wrap modes (glTF's sampler; OBJ has none: repeat, mipmapped).
    pub sampler: Sampler,
    /// Which texture coordinate set the slot reads (`TEXCOORD_n`).
    pub uv_set: u32,
    /// Applied to the UVs before sampling.
    pub transform: UvTransform,
    /// `normalTexture.scale` (x and y of the tangent-space normal), `occlusionTexture.strength`,
    /// or the bump map's height scale; 1 for the other slots.
    pub scale: f32,
}

impl TextureSlot {
    /// One line for panels and reports: texture, UV set, sampler, transform, scale (the
    /// parts at their defaults left out).
    #[must_use]
    pub fn describe(&self) -> String {
        let s = self.sampler;
        let wrap = |w: crate::texture::Wrap| format!("{w:?}").to_lowercase();
        let mut d = format!(
            "texture {}, TEXCOORD_{}, {}",
            self.texture,
            self.uv_set,
            s.filter.name()
        );
        if s.wrap_u == s.wrap_v {
            d += &format!(", {}", wrap(s.wrap_u));
        } else {
            d += &format!(", {} x {}", wrap(s.wrap_u), wrap(s.wrap_v));
        }
        let t = self.transform;
        if !t.is_identity() {
            d += &format!(
                ", offset ({}, {}) rotation {:.1}° scale ({}, {})",
                t.offset.x,
                t.offset.y,
                t.rotation.to_degrees(),
                t.scale.x,
                t.scale.y
            );
        }
        if self.scale != 1.0 {
            d += &format!(", scale {}", self.scale);
        }
        d
    }

    /// Texture `texture` read with the default sampler from UV set 0, untransformed.
    #[must_use]
    pub fn new(texture: usize) -> Self {
        Self {
            texture,
            sampler: Sampler::default(),
            uv_set: 0,
            transform: UvTransform::IDENTITY,
            scale: 1.0,
        }
    }
}

/// Where a slot's values come from: a decoded image, or a procedural texture evaluated at
/// every pixel (the textbook's §9.5: a 2D pattern read at the UV, or a solid texture read
/// at the object-space position, which needs no UVs at all).
#[derive(Clone, Debug, PartialEq)]
pub enum TextureSource {
    Image(Arc<Texture>),
    Procedural(Arc<ProceduralTexture>),
}

impl TextureSource {
    /// The image's name (its path when loaded from a file) or the procedural's kind.
    #[must_use]
    pub fn name(&self) -> String {
        match self {
            TextureSource::Image(t) => t.name.clone(),
            TextureSource::Procedural(p) => p.source().name().to_owned(),
        }
    }

    /// True if the source reads texture coordinates (images and 2D patterns); solid
    /// textures read the object-space position instead.
    #[must_use]
    pub fn needs_uv(&self) -> bool {
        match self {
            TextureSource::Image(_) => true,
            TextureSource::Procedural(p) => p.domain() == Domain::Uv,
        }
    }

    /// The image, if it is one.
    #[must_use]
    pub fn image(&self) -> Option<&Arc<Texture>> {
        match self {
            TextureSource::Image(t) => Some(t),
            TextureSource::Procedural(_) => None,
        }
    }
}

/// The bump height of a height image, a 2D pattern and a solid texture when none is given
/// (see [`Slot::Bump`] for the units of each).
pub const DEFAULT_BUMP_SCALE: [f32; 3] = [1.0, 0.05, 0.02];

impl TextureSource {
    /// The source a command-line or scene-file value names: a procedural texture
    /// (`checker[:N]`, `grid[:N]`, `wood`, `marble`, `noise[:OCTAVES]`, case-insensitive)
    /// or else an image file, read by `image(path, srgb)` in the colour space of `slot`
    /// (write `./wood` for a file called `wood`). Errors are one line, without the value's
    /// origin (the caller names the flag or key).
    pub fn from_spec<E: std::fmt::Display>(
        spec: &str,
        slot: Slot,
        image: impl FnOnce(&std::path::Path, bool) -> Result<Arc<Texture>, E>,
    ) -> Result<TextureSource, String> {
        use crate::texture::{ParseProceduralError, Procedural};
        match spec.parse::<Procedural>() {
            Ok(p) => Ok(TextureSource::Procedural(Arc::new(ProceduralTexture::new(
                p,
            )))),
            Err(e @ ParseProceduralError::Count { .. }) => Err(e.to_string()),
            Err(ParseProceduralError::Unknown(_)) => {
                let path = std::path::Path::new(spec);
                if spec.trim().is_empty() {
                    return Err("empty texture: give an image file or checker[:N], grid[:N],                                 wood, marble or noise[:OCTAVES]"
                        .into());
                }
                image(path, slot.srgb())
                    .map(TextureSource::Image)
                    .map_err(|e| e.to_string())
            }
        }
    }

    /// A bump source and its height: `noise:SCALE` (fBm noise displaced by SCALE), another
    /// [`from_spec`](Self::from_spec) value with the default height of its kind
    /// ([`DEFAULT_BUMP_SCALE`]).
    pub fn bump_from_spec<E: std::fmt::Display>(
        spec: &str,
        image: impl FnOnce(&std::path::Path, bool) -> Result<Arc<Texture>, E>,
    ) -> Result<(TextureSource, f32), String> {
        use crate::texture::Procedural;
        let lower = spec.trim().to_ascii_lowercase();
        if let Some(scale) = lower.strip_prefix("noise:") {
            let scale: f32 = scale
                .trim()
                .parse()
                .ok()
                .filter(|s: &f32| s.is_finite())
                .ok_or_else(|| format!("noise:SCALE: '{scale}' is not a finite number"))?;
            let p = ProceduralTexture::new(Procedural::noise(5));
            return Ok((TextureSource::Procedural(Arc::new(p)), scale));
        }
        let source = Self::from_spec(spec, Slot::Bump, image)?;
        let scale = match &source {
            TextureSource::Image(_) => DEFAULT_BUMP_SCALE[0],
            TextureSource::Procedural(p) if p.domain() == Domain::Uv => DEFAULT_BUMP_SCALE[1],
            TextureSource::Procedural(_) => DEFAULT_BUMP_SCALE[2],
        };
        Ok((source, scale))
    }

    /// The value [`from_spec`](Self::from_spec) reads back: the image's name (a path when it
    /// was loaded from one) or the procedural's name with its count.
    #[must_use]
    pub fn spec(&self) -> String {
        use crate::texture::Procedural;
        match self {
            TextureSource::Image(t) => t.name.clone(),
            TextureSource::Procedural(p) => match p.source() {
                Procedural::Checker { n, .. } => format!("checker:{n}"),
                Procedural::Grid { cells } => format!("grid:{cells}"),
                Procedural::Noise { octaves, .. } => format!("noise:{octaves}"),
                other => other.name().to_owned(),
            },
        }
    }
}

/// A replacement for one slot of every material (the command line's `--texture`, `--bump`,
/// `--normal-map off`, the scene file's keys, the viewer's texture panel).
#[derive(Clone, Debug, PartialEq)]
pub enum SlotOverride {
    /// The slot is off: the materials' textures in it are not read.
    Off,
    /// Every material reads `source` in the slot, from UV set `uv_set` through `transform`
    /// with `sampler` (`None`: the sampler of the material's own texture in the slot, else
    /// the default), and the slot's scalar `scale`.
    Source {
        source: TextureSource,
        uv_set: u32,
        transform: UvTransform,
        sampler: Option<Sampler>,
        scale: f32,
    },
}

impl SlotOverride {
    /// `source` from UV set 0, untransformed, with the material's sampler and scale `scale`.
    #[must_use]
    pub fn source(source: TextureSource, scale: f32) -> Self {
        SlotOverride::Source {
            source,
            uv_set: 0,
            transform: UvTransform::IDENTITY,
            sampler: None,
            scale,
        }
    }
}

/// One optional [`SlotOverride`] per [`Slot`].
#[derive(Clone, Debug, PartialEq, Default)]
pub struct SlotOverrides([Option<SlotOverride>; Slot::ALL.len()]);

impl SlotOverrides {
    /// The override of `slot`, if any.
    #[must_use]
    pub fn get(&self, slot: Slot) -> Option<&SlotOverride> {
        self.0[slot.index()].as_ref()
    }

    /// The override of `slot` to change in place, if any.
    pub fn get_mut(&mut self, slot: Slot) -> Option<&mut SlotOverride> {
        self.0[slot.index()].as_mut()
    }

    /// Sets (or with `None` removes) the override of `slot`.
    pub fn set(&mut self, slot: Slot, o: Option<SlotOverride>) {
        self.0[slot.index()] = o;
    }

    /// True if no slot is overridden.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.0.iter().all(Option::is_none)
    }

    /// The overridden slots and their overrides, in [`Slot::ALL`] order.
    pub fn iter(&self) -> impl Iterator<Item = (Slot, &SlotOverride)> {
        Slot::ALL
            .into_iter()
            .zip(&self.0)
            .filter_map(|(s, o)| Some((s, o.as_ref()?)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::FRAC_PI_2;

    fn near(a: Vec2, b: Vec2) -> bool {
        (a - b).abs().max_element() < 1e-6
    }

    #[test]
    fn the_extensions_own_example_turns_the_lower_left_quadrant_clockwise() {
        // KHR_texture_transform README: offset [0, 1], rotation π/2, scale [0.5, 0.5] maps
        // the texture's lower-left quadrant, turned 90° clockwise, onto the whole surface.
        let t = UvTransform {
            offset: Vec2::new(0.0, 1.0),
            rotation: FRAC_PI_2,
            scale: Vec2::splat(0.5),
        };
        assert!(near(t.apply(Vec2::ZERO), Vec2::new(0.0, 1.0)));
        assert!(near(t.apply(Vec2::ONE), Vec2::new(0.5, 0.5)));
        assert!(near(t.apply(Vec2::new(1.0, 0.0)), Vec2::new(0.0, 0.5)));
        assert!(near(t.apply(Vec2::new(0.0, 1.0)), Vec2::new(0.5, 1.0)));
    }

    #[test]
    fn scale_comes_before_rotation_and_offset_last() {
        let t = UvTransform {
            offset: Vec2::new(0.25, -0.5),
            rotation: 0.3,
            scale: Vec2::new(2.0, 3.0),
        };
        let (s, c) = libm::sincosf(0.3f32);
        for uv in [Vec2::new(0.1, 0.7), Vec2::new(-2.0, 5.0)] {
            let (u1, v1) = (2.0 * uv.x, 3.0 * uv.y);
            let want = Vec2::new(c * u1 + s * v1 + 0.25, -s * u1 + c * v1 - 0.5);
            assert!(near(t.apply(uv), want), "{uv}");
        }
        assert_eq!(
            UvTransform::IDENTITY.apply(Vec2::new(3.5, -1.0)),
            Vec2::new(3.5, -1.0)
        );
    }

    #[test]
    fn non_finite_parts_fall_back_to_the_identity() {
        let bad = UvTransform {
            offset: Vec2::new(f32::NAN, 2.0),
            rotation: f32::INFINITY,
            scale: Vec2::new(3.0, f32::NEG_INFINITY),
        };
        let (t, changed) = bad.sanitized();
        assert!(changed);
        assert_eq!(t.offset, Vec2::new(0.0, 2.0));
        assert_eq!((t.rotation, t.scale), (0.0, Vec2::new(3.0, 1.0)));
        assert_eq!(
            UvTransform::IDENTITY.sanitized(),
            (UvTransform::IDENTITY, false)
        );
    }

    #[test]
    fn colour_slots_are_srgb_and_data_slots_linear() {
        let srgb: Vec<_> = Slot::ALL.into_iter().filter(|s| s.srgb()).collect();
        assert_eq!(
            srgb,
            [
                Slot::BaseColor,
                Slot::Specular,
                Slot::Emissive,
                Slot::SpecularColor,
                Slot::SheenColor,
                Slot::DiffuseTransmissionColor
            ]
        );
        // `ALL` is in the enum's order, and every extension slot has its place in `LAYERS`.
        for (i, s) in Slot::ALL.into_iter().enumerate() {
            assert_eq!(s.index(), i);
        }
        for (i, s) in Slot::LAYERS.into_iter().enumerate() {
            assert_eq!(s.layer_index(), Some(i));
        }
        assert_eq!(Slot::Bump.layer_index(), None);
    }
}
