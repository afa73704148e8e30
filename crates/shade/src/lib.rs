//! Shading: the lighting equation and one fragment shader per shading mode. The renderer
//! that turns a scene into draws for the rasterizer is [`crate::render`].
//!
//! Modes (the textbook's §9.2.2, its illumination notes and its pipeline chapter's §5.2):
//! - `wireframe`: mesh edges (not triangulation diagonals) with hidden lines removed;
//! - `flat`: one lighting evaluation per facet, at its centroid with its plane normal;
//! - `gouraud`: lighting at the vertices, colour interpolated;
//! - `phong`: normal interpolated and renormalised, lighting per pixel (R·V highlight);
//! - `blinn`: as `phong` with the half vector (N·H);
//! - `textured`: per-pixel Blinn-Phong whose diffuse colour is modulated by the base-colour
//!   texture, filtered in linear light by its sampler: trilinear (mipmapped, level of detail
//!   from the UV's exact screen-space derivatives) unless the model's sampler asks for
//!   nearest or non-mipmapped bilinear;
//! - `pbr`: glTF 2.0 metallic-roughness (the specification's Appendix B, [`brdf`]) per
//!   pixel, with every map the textured mode reads plus the metallic-roughness texture,
//!   under the lights and the environment (image-based lighting); `KHR_materials_unlit`
//!   materials show their base colour. The default for glTF materials;
//! - `normals`, `depth`, `uv`: debug views.
//!
//! Shading happens in linear light; the framebuffer is sRGB-encoded on output.
//! This module never loops over tiles or pixels itself: the rasterizer calls the shaders.

// The crates below this one, under the module names the code uses (`crate::scene::...`).
use realist_raster as raster;
use realist_scene as scene;
use realist_simd as simd;
use realist_texture as texture;
use realist_texture::microfacet;

pub mod brdf;
pub mod iridescence;
pub mod layer_maps;
mod lighting;
pub mod maps;
pub mod mode;
mod shaders;
mod shadow;
pub mod sheen;
pub mod stages;
pub mod texlab;

pub use crate::simd::{Num, Real};
pub use lighting::{
    ambient, ambient_at, ambient_split, arriving, attenuate, cone, contribution, emission_seen,
    illuminate, pyramid, reflect, view_terms, view_vector, Fog, FogDistance, LightSet, PbrParams,
    Shade, Source, Surface, SurfaceAt, IMAGE_SAMPLER, MAX_HALF_ANGLE,
};
pub use shaders::{
    Backdrop, ColorShader, Constant, CountShader, Debug, DebugShader, DepthOnly, DrawParams,
    LitLayout, LitShader, SlotParams, TexView, UvChannel, MAX_UV_CHANNELS,
};
pub use shadow::{ShadowMap, ShadowSettings, MAX_SHADOW_SIZE, SHADOW_SIZE};

/// A shading mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shading {
    Wireframe,
    Flat,
    Gouraud,
    Phong,
    Blinn,
    Textured,
    /// glTF metallic-roughness ([`brdf`]).
    Pbr,
    /// `pbr` with ray-traced shadows, mirror reflection and refraction (the textbook's
    /// §9.6.1, Whitted's model).
    Whitted,
    /// Path tracing ([`mode::Rays::Path`]).
    Path,
    /// Radiosity ([`mode::Rays::Radiosity`], the textbook's §9.6.3).
    Radiosity,
    Normals,
    Depth,
    Uv,
    /// The lit surface with a UV test grid as its base colour (the mesh's UV set 0, or a
    /// generated one): shows stretching, seams, flips and rotations.
    UvChecker,
    /// The texture-mapping debug views ([`TexView`]).
    MipLevel,
    TexelDensity,
    Anisotropy,
    Tangents,
    TangentNormals,
}

impl Shading {
    /// Every mode, in the order the CLI lists them.
    pub const ALL: [Shading; 19] = [
        Shading::Wireframe,
        Shading::Flat,
        Shading::Gouraud,
        Shading::Phong,
        Shading::Blinn,
        Shading::Textured,
        Shading::Pbr,
        Shading::Whitted,
        Shading::Path,
        Shading::Radiosity,
        Shading::Normals,
        Shading::Depth,
        Shading::Uv,
        Shading::UvChecker,
        Shading::MipLevel,
        Shading::TexelDensity,
        Shading::Anisotropy,
        Shading::Tangents,
        Shading::TangentNormals,
    ];

    /// The mode's command-line name.
    #[must_use]
    pub fn name(self) -> &'static str {
        self.mode().name
    }

    /// The texture debug view the mode shows through the lit shader, if it is one.
    #[must_use]
    pub fn tex_view(self) -> Option<TexView> {
        let view = self.mode().view;
        (view != TexView::Lit).then_some(view)
    }

    /// True for the modes drawn by the per-pixel lit shader (its lighting or its debug
    /// views).
    #[must_use]
    pub fn per_pixel(self) -> bool {
        self.mode().pass == mode::Pass::PerPixel
    }
}

impl std::str::FromStr for Shading {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Shading::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| {
                let names: Vec<_> = Shading::ALL.iter().map(|m| m.name()).collect();
                format!(
                    "unknown shading mode '{s}' (expected one of: {})",
                    names.join(", ")
                )
            })
    }
}

impl std::fmt::Display for Shading {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
