//! The scene file's serde types: what the file says, before it is checked against the
//! model. Every table denies unknown keys. Numbers are `f64` here (the file's precision);
//! [`super::convert`] checks ranges and converts to the renderer's `f32` types, and
//! [`super::export`] writes the shortest decimals that read back to the same `f32`.

use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::render::ToneMap;
use crate::scene::{LightKind, Up};
use crate::shade::{FogDistance, Shading};
use crate::texture::{Axis, Filter, UvGenerator};

/// A type written in the file as one of a fixed set of names.
pub trait Keyword: Sized + Copy {
    fn keyword(self) -> &'static str;
    /// # Errors
    /// A message listing the accepted names.
    fn parse_keyword(s: &str) -> Result<Self, String>;
}

/// A [`Keyword`] as a serde value: a string in the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Kw<T>(pub T);

impl<T: Keyword> Serialize for Kw<T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.0.keyword())
    }
}

impl<'de, T: Keyword> Deserialize<'de> for Kw<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        T::parse_keyword(&s).map(Kw).map_err(D::Error::custom)
    }
}

macro_rules! keyword_by_fromstr {
    ($($t:ty),*) => {$(
        impl Keyword for $t {
            fn keyword(self) -> &'static str {
                self.name()
            }
            fn parse_keyword(s: &str) -> Result<Self, String> {
                s.parse()
            }
        }
    )*};
}
keyword_by_fromstr!(Shading, ToneMap, FogDistance, LightKind, Up);

impl Keyword for Filter {
    fn keyword(self) -> &'static str {
        self.name()
    }
    /// `nearest`, `bilinear`, `trilinear` or `aniso:N` ([`Filter`]'s `FromStr`).
    fn parse_keyword(s: &str) -> Result<Self, String> {
        s.parse()
            .map_err(|e: crate::texture::ParseFilterError| e.to_string())
    }
}

/// `uv` (and `realist render --uv`): where texture coordinates come from: `"mesh"`, the
/// model's own, or a generator of the textbook's §9.5 that replaces UV set 0 of every mesh
/// (`planar:x|y|z`, `cylindrical[:x|y|z]`, `spherical[:x|y|z]`, `box`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UvChoice {
    Mesh,
    Generated(UvGenerator),
}

impl UvChoice {
    /// The generator, `None` for the mesh's own UVs.
    #[must_use]
    pub fn generator(self) -> Option<UvGenerator> {
        match self {
            UvChoice::Mesh => None,
            UvChoice::Generated(g) => Some(g),
        }
    }
}

impl std::str::FromStr for UvChoice {
    type Err = String;

    /// `mesh` or a generator name ([`UvGenerator`]'s `FromStr`), case-insensitive.
    fn from_str(s: &str) -> Result<Self, String> {
        if s.trim().eq_ignore_ascii_case("mesh") {
            return Ok(UvChoice::Mesh);
        }
        s.parse().map(UvChoice::Generated).map_err(|_| {
            format!(
                "unknown uv '{s}' (expected mesh, planar:x|y|z, cylindrical[:x|y|z], \
                 spherical[:x|y|z] or box)"
            )
        })
    }
}

impl Keyword for UvChoice {
    /// The name [`UvGenerator`]'s `Display` writes (`"mesh"` for the mesh's own).
    fn keyword(self) -> &'static str {
        use UvGenerator::{Box, Cylindrical, Planar, Spherical};
        match self {
            UvChoice::Mesh => "mesh",
            UvChoice::Generated(g) => match g {
                Planar { axis: Axis::X } => "planar:x",
                Planar { axis: Axis::Y } => "planar:y",
                Planar { axis: Axis::Z } => "planar:z",
                Cylindrical { axis: Axis::X } => "cylindrical:x",
                Cylindrical { axis: Axis::Y } => "cylindrical",
                Cylindrical { axis: Axis::Z } => "cylindrical:z",
                Spherical { axis: Axis::X } => "spherical:x",
                Spherical { axis: Axis::Y } => "spherical",
                Spherical { axis: Axis::Z } => "spherical:z",
                Box => "box",
            },
        }
    }
    fn parse_keyword(s: &str) -> Result<Self, String> {
        s.parse()
    }
}

/// A whole number in the file, read as any number so that a fraction or a value beyond
/// `u32` gets the setting's own message ([`crate::render::Numeric::check`]) rather than
/// a type error; written as an integer when it is one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Count(pub f64);

impl From<u32> for Count {
    fn from(n: u32) -> Self {
        Count(f64::from(n))
    }
}

impl Serialize for Count {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let v = self.0;
        if v.fract() == 0.0 && v.abs() < 9.0e15 {
            s.serialize_i64(v as i64)
        } else {
            s.serialize_f64(v)
        }
    }
}

impl<'de> Deserialize<'de> for Count {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        f64::deserialize(d).map(Count)
    }
}

/// Defines a keyword enum local to the file format.
macro_rules! keywords {
    ($(#[$m:meta])* $name:ident { $($variant:ident = $word:literal),* $(,)? }) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum $name { $($variant),* }
        impl Keyword for $name {
            fn keyword(self) -> &'static str {
                match self { $($name::$variant => $word),* }
            }
            fn parse_keyword(s: &str) -> Result<Self, String> {
                match s.to_ascii_lowercase().as_str() {
                    $($word => Ok($name::$variant),)*
                    _ => Err(format!(
                        "unknown {} '{s}' (expected {})",
                        stringify!($name).to_ascii_lowercase(),
                        [$($word),*].join(", ")
                    )),
                }
            }
        }
    };
}

keywords!(
    /// `lights = "auto" | "custom"`.
    LightsMode { Auto = "auto", Custom = "custom" }
);
keywords!(
    /// A light's `attenuation.mode`.
    AttenuationMode { None = "none", Linear = "linear", InverseSquare = "inverse-square", Range = "range" }
);
keywords!(
    /// A material's `alpha_mode`.
    AlphaKind { Opaque = "opaque", Mask = "mask", Blend = "blend" }
);
keywords!(
    /// A `[primitive]`'s `shape`.
    Shape { Sphere = "sphere", Cylinder = "cylinder", Cone = "cone", Torus = "torus", Cube = "cube" }
);

/// A colour: `[r, g, b]` or `[r, g, b, a]` in linear RGB (any non-negative values; light
/// colours may exceed 1), or `"#rrggbb"` / `"#rrggbbaa"` in sRGB, decoded to linear.
/// Always written as an array.
#[derive(Clone, Debug, PartialEq)]
pub struct Rgba(pub Vec<f64>);

impl Serialize for Rgba {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(s)
    }
}

impl<'de> Deserialize<'de> for Rgba {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Either {
            List(Vec<f64>),
            Hex(String),
        }
        let err = || D::Error::custom("expected [r, g, b], [r, g, b, a] or \"#rrggbb\"");
        let v = match Either::deserialize(d).map_err(|_| err())? {
            Either::List(v) => v,
            Either::Hex(s) => {
                let hex = s.strip_prefix('#').unwrap_or(&s);
                if !(hex.len() == 6 || hex.len() == 8) || !hex.is_ascii() {
                    return Err(D::Error::custom(format!(
                        "colour \"{s}\": expected \"#rrggbb\" or \"#rrggbbaa\""
                    )));
                }
                let bytes = (0..hex.len() / 2)
                    .map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16))
                    .collect::<Result<Vec<u8>, _>>()
                    .map_err(|_| D::Error::custom(format!("colour \"{s}\": bad hex digits")))?;
                bytes
                    .iter()
                    .enumerate()
                    .map(|(i, &b)| {
                        let c = f64::from(b) / 255.0;
                        if i < 3 {
                            crate::color::srgb_decode(c)
                        } else {
                            c
                        }
                    })
                    .collect()
            }
        };
        if !(v.len() == 3 || v.len() == 4) {
            return Err(D::Error::custom(format!(
                "a colour has 3 or 4 components, not {}",
                v.len()
            )));
        }
        Ok(Rgba(v))
    }
}

/// The whole file. See the README's "Scene files" for every key's meaning and default.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDoc {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub light_scale: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub output: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<[u32; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shading: Option<Kw<Shading>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub msaa: Option<Count>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<Count>,
    /// Traced rays' depth limit (`whitted`, `path`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ray_depth: Option<Count>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub background: Option<Rgba>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub double_sided: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wireframe_overlay: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertex_blinn: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flat_last_vertex: Option<bool>,
    /// The punctual lights reflect off `pbr` surfaces without the multiple-scattering
    /// compensation (the specification's single-scattering BRDF).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub single_scatter: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub overdraw: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub subpixel_bits: Option<Count>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point_size: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub line_width: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filter: Option<Kw<Filter>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bump: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bump_scale: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_map: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uv: Option<Kw<UvChoice>>,
    /// The world's up axis, `y` or `z`: the default view, orbit cameras and turntables turn
    /// about it (`z` for scans and CAD models that lie on their back).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<Kw<Up>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tone: Option<Kw<ToneMap>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exposure: Option<f64>,
    /// `none`, `studio`, `sky`, `uniform` or an equirectangular `.hdr` / `.exr` path.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub env: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub env_rotate: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub env_intensity: Option<f64>,
    /// The environment drawn as the background, blurred to this roughness (0 to 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub env_background: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lights: Option<Kw<LightsMode>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lights_follow_camera: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub primitive: Option<PrimitiveSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera: Option<CameraSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fog: Option<FogSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shadow: Option<ShadowSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ground: Option<GroundSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub section: Option<SectionSpec>,
    /// The material variant drawn (`KHR_materials_variants`), by name.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material_variant: Option<String>,
    /// Parts not drawn: instance numbers as the viewer's Instances list shows them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hidden: Vec<Count>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub light: Vec<LightSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub material: Vec<MaterialSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compare: Option<CompareSpec>,
}

/// `[primitive]`: a generated mesh instead of a model file.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrimitiveSpec {
    pub shape: Kw<Shape>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub minor: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slices: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stacks: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub caps: Option<bool>,
}

impl Default for Kw<Shape> {
    fn default() -> Self {
        Kw(Shape::Sphere)
    }
}

/// `[camera]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gltf: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eye: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub azimuth: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elevation: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distance: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub yfov: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub near: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub far: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ortho: Option<f64>,
}

/// One `[[light]]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightSpec {
    pub kind: Kw<LightKind>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<Rgba>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub intensity: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inner: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outer: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rect: Option<[f64; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<[f64; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub image: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attenuation: Option<AttenuationSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shadow: Option<bool>,
}

impl Default for Kw<LightKind> {
    fn default() -> Self {
        Kw(LightKind::Directional)
    }
}

/// A light's `attenuation = { mode, near, far, range }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AttenuationSpec {
    pub mode: Kw<AttenuationMode>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub near: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub far: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<f64>,
}

/// One `[[material]]` override (or one in a comparison variant).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub index: Option<usize>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base_color: Option<Rgba>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub specular: Option<Rgba>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shininess: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ambient: Option<Rgba>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub double_sided: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_mode: Option<Kw<AlphaKind>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_cutoff: Option<f64>,
}

/// `[fog]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FogSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<Rgba>,
    pub near: f64,
    pub far: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distance: Option<Kw<FogDistance>>,
}

/// `[section]`: planes that cut the model open, `[nx, ny, nz, d]` each (what lies where
/// `n·p + d < 0` is removed), at most three; `caps` (default true) fills the cut where a
/// solid's inside shows, in `cap_color`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionSpec {
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub planes: Vec<[f64; 4]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub caps: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cap_color: Option<Rgba>,
}

/// `[shadow]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShadowSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<Count>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pcf: Option<Count>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bias: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slope: Option<f64>,
    /// Turns shadows on for every light that can cast them (as `--shadows`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub all_lights: Option<bool>,
}

/// `[ground]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroundSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub on: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color: Option<Rgba>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extent: Option<f64>,
}

/// `[compare]`: several variants of the scene side by side, each labelled.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CompareSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub title: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub columns: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub label_size: Option<f64>,
    #[serde(default)]
    pub variant: Vec<VariantSpec>,
}

/// One `[[compare.variant]]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VariantSpec {
    pub label: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shading: Option<Kw<Shading>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub material: Vec<MaterialSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filter: Option<Kw<Filter>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bump: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bump_scale: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uv: Option<Kw<UvChoice>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertex_blinn: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flat_last_vertex: Option<bool>,
}
