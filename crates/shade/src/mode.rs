//! The one description of every shading mode: its name, what it shows, how it draws and
//! what it reads. The renderer's frame set-up and passes, the probe, the f64 reference
//! (through `render::Policy`) and the command line's help read [`Shading::mode`]; a new
//! mode is a variant and a row here.

use super::{Debug, Shading, TexView};

/// How a mode's triangles are drawn: which pass and which shader.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    /// The mesh's edges, hidden lines removed.
    Edges,
    /// One colour per facet, lit once (the textbook's §9.2.2 flat shading).
    Facets,
    /// Colours lit at the vertices and interpolated (Gouraud).
    Vertices,
    /// The per-pixel lit shader: its lighting, or one of its texture debug views.
    PerPixel,
    /// A geometry debug view of its own shader.
    Debug(Debug),
}

/// What the lit surface's base colour is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Base {
    /// The material's Phong colour (diffuse, or the glTF base colour when that is all).
    Material,
    /// The glTF base colour, for the metallic-roughness BRDF.
    Pbr,
    /// White under the UV test grid, which replaces the base-colour map.
    UvGrid,
}

/// What rays a mode traces beside rasterizing (the textbook's §9.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rays {
    /// None: rasterized only.
    None,
    /// Whitted's model: shadow rays to every light (in place of shadow maps), mirror
    /// reflection and refraction on smooth and transmissive surfaces.
    Whitted,
    /// Path tracing: every pixel by random light paths, nothing rasterized.
    Path,
    /// Radiosity: the diffuse interreflection solved once for the scene, drawn by Gouraud.
    Radiosity,
}

/// One shading mode.
#[derive(Clone, Copy, Debug)]
pub struct Mode {
    /// The name on the command line, in scene files and in the viewer.
    pub name: &'static str,
    /// What it shows, for the help text.
    pub shows: &'static str,
    pub pass: Pass,
    /// Reads every map of the material (base colour, normal, occlusion, emissive, bump,
    /// metallic-roughness); the other per-pixel modes read the gloss map only.
    pub maps: bool,
    /// The highlight is Blinn's `N·H` (else Phong's `R·V`, or the BRDF in `pbr`).
    pub blinn: bool,
    pub base: Base,
    /// The texture debug view of the lit shader ([`TexView::Lit`]: the lit surface).
    pub view: TexView,
    pub rays: Rays,
}

impl Mode {
    /// Shows a debug view (geometry or texture) rather than a lit surface: drawn opaque,
    /// never blended.
    #[must_use]
    pub fn debug(&self) -> bool {
        matches!(self.pass, Pass::Debug(_)) || self.view != TexView::Lit
    }
}

const fn lit(name: &'static str, shows: &'static str, maps: bool, blinn: bool, base: Base) -> Mode {
    Mode {
        name,
        shows,
        pass: Pass::PerPixel,
        maps,
        blinn,
        base,
        view: TexView::Lit,
        rays: Rays::None,
    }
}

const fn unlit(name: &'static str, shows: &'static str, pass: Pass) -> Mode {
    Mode {
        name,
        shows,
        pass,
        maps: false,
        blinn: false,
        base: Base::Material,
        view: TexView::Lit,
        rays: Rays::None,
    }
}

const fn texture_view(name: &'static str, shows: &'static str, maps: bool, view: TexView) -> Mode {
    Mode {
        name,
        shows,
        pass: Pass::PerPixel,
        maps,
        blinn: false,
        base: Base::Material,
        view,
        rays: Rays::None,
    }
}

const fn traced(name: &'static str, shows: &'static str, rays: Rays) -> Mode {
    Mode {
        rays,
        ..lit(name, shows, true, false, Base::Pbr)
    }
}

/// The rows, in [`Shading::ALL`] order (a test checks each row's name against its variant).
static MODES: [Mode; 19] = [
    unlit(
        "wireframe",
        "the mesh's edges, hidden lines removed",
        Pass::Edges,
    ),
    unlit(
        "flat",
        "one colour per facet, lit at its centroid (the textbook's §9.2.2)",
        Pass::Facets,
    ),
    unlit(
        "gouraud",
        "colours lit at the vertices and interpolated (the textbook's §9.2.2)",
        Pass::Vertices,
    ),
    lit(
        "phong",
        "normals interpolated and lit per pixel, Phong's R·V highlight (the textbook's §9.2.2)",
        false,
        false,
        Base::Material,
    ),
    lit(
        "blinn",
        "per-pixel lighting with Blinn's N·H highlight",
        false,
        true,
        Base::Material,
    ),
    lit(
        "textured",
        "Blinn per pixel with every map of the material (the textbook's §9.5)",
        true,
        true,
        Base::Material,
    ),
    lit(
        "pbr",
        "glTF metallic-roughness with image-based light",
        true,
        false,
        Base::Pbr,
    ),
    traced(
        "whitted",
        "pbr with ray-traced shadows to every light, mirror reflection and refraction \
         (Whitted's model, the textbook's §9.6.1)",
        Rays::Whitted,
    ),
    traced(
        "path",
        "path tracing: the rendering equation by random light paths, the ground truth \
         (the textbook's §9.6); one path per pixel per supersampling pass",
        Rays::Path,
    ),
    traced(
        "radiosity",
        "progressive-refinement radiosity with hemicube form factors, solved once and drawn \
         with Gouraud shading from any view (the textbook's §9.6.3)",
        Rays::Radiosity,
    ),
    unlit(
        "normals",
        "world normals as colours",
        Pass::Debug(Debug::Normals),
    ),
    unlit(
        "depth",
        "view distance, white at the near plane to black at the far",
        Pass::Debug(Debug::Depth),
    ),
    unlit(
        "uv",
        "texture coordinates as colours (fract(u), fract(v), 0)",
        Pass::Debug(Debug::Uv),
    ),
    lit(
        "uv-checker",
        "the lit surface under a UV test grid: stretching, seams, flips",
        false,
        true,
        Base::UvGrid,
    ),
    texture_view(
        "mip-level",
        "the mip level the trilinear filter reads",
        false,
        TexView::MipLevel,
    ),
    texture_view(
        "texel-density",
        "texels per pixel: blue magnified, green 1:1, red minified",
        false,
        TexView::TexelDensity,
    ),
    texture_view(
        "anisotropy",
        "the pixel footprint's anisotropy in texture space",
        false,
        TexView::Anisotropy,
    ),
    texture_view(
        "tangents",
        "the world tangent as a colour",
        false,
        TexView::Tangents,
    ),
    texture_view(
        "tangent-normals",
        "the shading normal in the tangent frame, as a normal map stores it",
        true,
        TexView::TangentNormals,
    ),
];

impl Shading {
    /// The mode's description.
    #[must_use]
    pub fn mode(self) -> &'static Mode {
        &MODES[self as usize]
    }

    /// Every mode with what it shows, one per line: the command line's help.
    #[must_use]
    pub fn help() -> String {
        Shading::ALL
            .iter()
            .map(|m| format!("{}: {}", m.name(), m.mode().shows))
            .collect::<Vec<_>>()
            .join("\n")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_row_is_its_variants_and_the_names_are_unique() {
        let expected = [
            (Shading::Wireframe, "wireframe"),
            (Shading::Flat, "flat"),
            (Shading::Gouraud, "gouraud"),
            (Shading::Phong, "phong"),
            (Shading::Blinn, "blinn"),
            (Shading::Textured, "textured"),
            (Shading::Pbr, "pbr"),
            (Shading::Whitted, "whitted"),
            (Shading::Path, "path"),
            (Shading::Radiosity, "radiosity"),
            (Shading::Normals, "normals"),
            (Shading::Depth, "depth"),
            (Shading::Uv, "uv"),
            (Shading::UvChecker, "uv-checker"),
            (Shading::MipLevel, "mip-level"),
            (Shading::TexelDensity, "texel-density"),
            (Shading::Anisotropy, "anisotropy"),
            (Shading::Tangents, "tangents"),
            (Shading::TangentNormals, "tangent-normals"),
        ];
        assert_eq!(expected.len(), Shading::ALL.len());
        for (k, (m, name)) in expected.into_iter().enumerate() {
            assert_eq!(Shading::ALL[k], m);
            assert_eq!(m.mode().name, name);
            assert_eq!(m.name().parse::<Shading>(), Ok(m));
        }
        assert_eq!(Shading::help().lines().count(), Shading::ALL.len());
    }
}
