//! What to render, in two parts: [`Settings`], which change rarely (shading, lights,
//! materials, quality), and the per-frame [`View`] (camera and size). A viewer keeps one
//! `Settings` while the user drags the camera, and sends a new `View` every frame.

use std::sync::Arc;

use glam::{Mat4, Vec4};

use crate::scene::{Camera, Light, Material, Scene, SlotOverrides, Style};
use crate::shade::{Fog, Shading, ShadowSettings};
use crate::simd::KernelKind;
use crate::texture::env::{default_cache_dir, EnvCache, EnvImage, EnvView, Prefiltered};
use crate::texture::Filter;

/// [`Settings::ray_depth`]'s default: deep enough that a white room's paths lose well under
/// 0.1% of their light to the limit (0.8³² of it), while Russian roulette ends most paths
/// long before.
pub const DEFAULT_RAY_DEPTH: u32 = 32;
/// The largest [`Settings::ray_depth`] accepted: Whitted's rays recurse once per surface,
/// and 64 levels stay far inside a rendering thread's stack.
pub const MAX_RAY_DEPTH: u32 = 64;

/// The lights a frame uses.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Lights {
    /// The scene's lights; if it has none, [`Light::default_rig`] attached to the camera,
    /// except for a scene drawn entirely in the `pbr` mode under an environment, which the
    /// environment alone lights, as the Khronos glTF Sample Viewer does
    /// ([`Settings::default_rig`]).
    #[default]
    Auto,
    /// These lights instead of the scene's. With `follow_camera`, positions and directions
    /// are in camera space (x right, y up, z towards the viewer) and move with the camera;
    /// otherwise they are in world space.
    Custom {
        lights: Vec<Light>,
        follow_camera: bool,
    },
}

/// What the frame shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Output {
    /// The shaded image.
    #[default]
    Shaded,
    /// How many fragments each pixel received (every triangle that survives culling and
    /// clipping, depth test off), as a colour ramp: see [`overdraw_color`](super::overdraw_color).
    Overdraw,
}

/// What happens to colours outside [0, 1] (the textbook's pipeline chapter, §4.2) before they are
/// encoded. The background colour is never tone mapped (nor exposed); an environment shown
/// as the background is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ToneMap {
    /// [`ToneMap::PbrNeutral`] for a scene drawn entirely in the `pbr` mode (a glTF file's
    /// own look, as the Khronos glTF Sample Viewer shows it), else [`ToneMap::Clamp`] (the
    /// textbook's modes, whose colours are meant to be shown as they are):
    /// [`Settings::tone_for`].
    #[default]
    Auto,
    /// Each channel clamped to [0, 1]: (1, 2, 1) becomes white.
    Clamp,
    /// A colour whose largest channel exceeds 1 is divided by it, keeping its hue:
    /// (1, 2, 1) becomes (0.5, 1, 0.5), light green.
    ScaleMax,
    /// Reinhard's operator on luminance, `L / (1 + L)`, applied as a scale to the colour
    /// (then scaled by the largest channel if one still exceeds 1): every colour stays in
    /// range and keeps its hue; darkens everything a little.
    Reinhard,
    /// Khronos PBR Neutral (KhronosGroup/ToneMapping): colours in [0.08, 0.8] lose 0.04
    /// and keep their hue, brighter ones roll off towards white and desaturate.
    PbrNeutral,
    /// ACES filmic, Narkowicz's per-channel fit (2016): 1 becomes about 0.80.
    AcesNarkowicz,
    /// ACES filmic, Hill's fit of the RRT and ODT (BakingLab `ACES.hlsl`), in its own
    /// colour space: 1 becomes about 0.62 (three.js's `ACESFilmicToneMapping` is this on
    /// x / 0.6).
    AcesHill,
}

impl ToneMap {
    pub const ALL: [ToneMap; 7] = [
        ToneMap::Auto,
        ToneMap::Clamp,
        ToneMap::ScaleMax,
        ToneMap::Reinhard,
        ToneMap::PbrNeutral,
        ToneMap::AcesNarkowicz,
        ToneMap::AcesHill,
    ];

    /// The name on the command line and in scene files.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ToneMap::Auto => "auto",
            ToneMap::Clamp => "clamp",
            ToneMap::ScaleMax => "scale-max",
            ToneMap::Reinhard => "reinhard",
            ToneMap::PbrNeutral => "pbr-neutral",
            ToneMap::AcesNarkowicz => "aces-narkowicz",
            ToneMap::AcesHill => "aces-hill",
        }
    }

    /// Maps one linear colour (alpha kept); [`ToneMap::Auto`], not resolved, clamps.
    #[must_use]
    #[inline]
    pub fn apply(self, c: Vec4) -> Vec4 {
        let rgb = c.truncate();
        let scale_max = |rgb: glam::Vec3| {
            let m = rgb.max_element();
            if m > 1.0 && m.is_finite() {
                rgb / m
            } else {
                rgb
            }
        };
        let out = match self {
            ToneMap::Auto | ToneMap::Clamp => return c,
            ToneMap::ScaleMax => scale_max(rgb),
            ToneMap::Reinhard => {
                let l = rgb.dot(glam::Vec3::new(0.2126, 0.7152, 0.0722));
                if l > 0.0 && l.is_finite() {
                    scale_max(rgb / (1.0 + l))
                } else {
                    rgb
                }
            }
            ToneMap::PbrNeutral => pbr_neutral(rgb),
            ToneMap::AcesNarkowicz => rgb.map(aces_narkowicz),
            ToneMap::AcesHill => aces_hill(rgb),
        };
        // Non-finite input stays what it was (the operators would turn NaN into NaN and
        // infinity into NaN or 1 depending on the formula).
        if rgb.is_finite() {
            out.extend(c.w)
        } else {
            c
        }
    }
}

/// Khronos PBR Neutral on one linear colour (the reference GLSL, operation for operation).
fn pbr_neutral(c: glam::Vec3) -> glam::Vec3 {
    const START: f32 = 0.8 - 0.04;
    const DESATURATION: f32 = 0.15;
    let x = c.min_element();
    let offset = if x < 0.08 { x - 6.25 * x * x } else { 0.04 };
    let c = c - offset;
    let peak = c.max_element();
    if peak < START {
        return c;
    }
    let d = 1.0 - START;
    let new_peak = 1.0 - d * d / (peak + d - START);
    let c = c * (new_peak / peak);
    let g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    c.lerp(glam::Vec3::splat(new_peak), g)
}

/// Narkowicz's ACES fit on one channel, clamped to [0, 1].
fn aces_narkowicz(x: f32) -> f32 {
    let x = x.max(0.0);
    (x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)).clamp(0.0, 1.0)
}

/// Hill's ACES fit: into the fit's colour space, the RRT + ODT rational curve, back out,
/// clamped to [0, 1].
fn aces_hill(c: glam::Vec3) -> glam::Vec3 {
    // Rows of the input and output matrices (glam's from_cols takes columns: transposed).
    let input = glam::Mat3::from_cols_array(&[
        0.59719, 0.07600, 0.02840, 0.35458, 0.90834, 0.13383, 0.04823, 0.01566, 0.83777,
    ]);
    let output = glam::Mat3::from_cols_array(&[
        1.60475, -0.10208, -0.00327, -0.53108, 1.10813, -0.07276, -0.07367, -0.00605, 1.07602,
    ]);
    let v = input * c.max(glam::Vec3::ZERO);
    let v = (v * (v + 0.024_578_6) - 0.000_090_537) / (v * (0.983_729 * v + 0.432_951) + 0.238_081);
    (output * v).clamp(glam::Vec3::ZERO, glam::Vec3::ONE)
}

impl std::str::FromStr for ToneMap {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        ToneMap::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| {
                format!(
                    "unknown tone map '{s}' (expected auto, clamp, scale-max, reinhard, \
                     pbr-neutral, aces-narkowicz or aces-hill)"
                )
            })
    }
}

/// A ground plane that catches shadows, placed just under the scene's bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ground {
    /// Linear RGB diffuse colour.
    pub color: glam::Vec3,
    /// Half-size as a multiple of the scene's bounding radius.
    pub extent: f32,
}

impl Default for Ground {
    fn default() -> Self {
        Self {
            color: glam::Vec3::splat(0.5),
            extent: 4.0,
        }
    }
}

/// The environment that lights the `pbr` draws (image-based lighting): diffuse irradiance
/// from its spherical harmonics, specular from its prefiltered chain (the split sum).
#[derive(Clone, Debug, Default)]
pub enum Environment {
    /// The built-in studio ([`EnvImage::studio`]), as [`Environment::builtin`] gives it.
    #[default]
    Auto,
    /// No environment: the lights, and the ambient light as a uniform environment.
    Off,
    On(EnvView),
}

impl PartialEq for Environment {
    fn eq(&self, o: &Self) -> bool {
        match (self, o) {
            (Environment::Auto, Environment::Auto) | (Environment::Off, Environment::Off) => true,
            (Environment::On(a), Environment::On(b)) => {
                Arc::ptr_eq(&a.env, &b.env)
                    && a.rotation_deg == b.rotation_deg
                    && a.intensity == b.intensity
            }
            (Environment::Auto | Environment::Off | Environment::On(_), _) => false,
        }
    }
}

impl Environment {
    /// The built-in environment `name` ("studio", "sky", "uniform": radiance 1),
    /// prefiltered on first use and kept for the process and, like a file's, on disk in
    /// [`default_cache_dir`] (prefiltering the studio costs about 200 ms of CPU; reading it
    /// back about 2 ms). A cache that cannot be read or written is passed over silently:
    /// the result is the same either way.
    #[must_use]
    pub fn builtin(name: &str) -> Option<Arc<Prefiltered>> {
        let image = EnvImage::builtin(name)?;
        let disk = default_cache_dir();
        Some(EnvCache::global().get_or_build(image, disk.as_deref()).env)
    }

    /// The environment a command line or scene file names: `none` (or `off`), a built-in
    /// (`studio`, `sky`, `uniform`) or an equirectangular `.hdr` / `.exr` image at
    /// `path(name)`, prefiltered once and kept by content (in memory, and on disk in
    /// `cache`). Returns it with a note for the user when the disk cache could not be
    /// used, or an error naming the file and the problem.
    ///
    /// # Errors
    /// The image cannot be read or is not a usable environment.
    pub fn named(
        name: &str,
        path: impl FnOnce(&str) -> std::path::PathBuf,
        cache: Option<&std::path::Path>,
    ) -> Result<(Environment, Option<String>), String> {
        if matches!(name, "none" | "off") {
            return Ok((Environment::Off, None));
        }
        if let Some(env) = Environment::builtin(name) {
            return Ok((Environment::On(EnvView::new(env)), None));
        }
        let image = EnvImage::load(&path(name)).map_err(|e| e.to_string())?;
        let cached = EnvCache::global().get_or_build(image, cache);
        Ok((Environment::On(EnvView::new(cached.env)), cached.disk_note))
    }

    /// This environment turned to `rotate` degrees and scaled to `intensity` (each if
    /// given): an error names the bad value, or says there is no environment to turn.
    ///
    /// # Errors
    /// A value is not finite (or the intensity negative), or the environment is off.
    pub fn adjusted(
        self,
        rotate: Option<f32>,
        intensity: Option<f32>,
    ) -> Result<Environment, String> {
        if rotate.is_none() && intensity.is_none() {
            return Ok(self);
        }
        let Some(mut view) = self.view() else {
            return Err("the environment is off: nothing to turn or scale".into());
        };
        if let Some(deg) = rotate {
            if !deg.is_finite() {
                return Err(format!("rotation {deg}: expected degrees"));
            }
            view.rotation_deg = deg;
        }
        if let Some(x) = intensity {
            if !(x.is_finite() && x >= 0.0) {
                return Err(format!("intensity {x}: expected a number at least 0"));
            }
            view.intensity = x;
        }
        Ok(Environment::On(view))
    }

    /// What the frame lights with: `None` when off.
    #[must_use]
    pub fn view(&self) -> Option<EnvView> {
        match self {
            Environment::Auto => {
                static STUDIO: std::sync::OnceLock<Option<Arc<Prefiltered>>> =
                    std::sync::OnceLock::new();
                let env = STUDIO.get_or_init(|| Environment::builtin("studio"));
                env.clone().map(EnvView::new)
            }
            Environment::Off => None,
            Environment::On(v) => Some(v.clone()),
        }
    }
}

/// Settings that change rarely: everything but the camera and the size.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Forces one mode on every instance; `None` = each instance's style, else textured
    /// for meshes with a texture, else Phong.
    pub shading: Option<Shading>,
    /// Draws the mesh edges (hidden lines removed) over the shaded opaque instances.
    pub wireframe_overlay: bool,
    pub output: Output,
    /// Linear RGBA.
    pub background: Vec4,
    /// Draw every material double-sided: no back-face culling, back faces lit from behind.
    pub double_sided: bool,
    /// Sub-pixel bits of the vertex snap (see [`crate::raster::DrawState::subpixel_bits`]).
    pub subpixel_bits: u8,
    /// Per-slot replacements of every material's textures (`--texture`, `--bump`,
    /// `--normal-map off`; the viewer's texture panel): a slot's source, or the slot off.
    pub slots: SlotOverrides,
    /// Reads every texture with this filter instead of its sampler's.
    pub filter: Option<Filter>,
    pub lights: Lights,
    /// Replaces the scene's materials (same order and count; missing entries keep the
    /// scene's): what a material editor changes.
    pub materials: Option<Vec<Material>>,
    /// Supersampling: `samples` x `samples` sub-pixel positions per pixel on a regular grid,
    /// each rendered as a whole pass with the projection shifted by a fraction of a pixel
    /// and averaged in linear light (1 = one sample at the pixel centre). Clamped to 1..=8.
    pub samples: u32,
    /// Multisampling: coverage and depth samples per pixel, 1 or 4 (see
    /// [`crate::raster::Target::set_samples`]), shaded once per pixel and triangle and
    /// resolved in linear light. Combines with `samples` (each supersampling pass is
    /// multisampled).
    pub msaa: u32,
    /// The most surfaces a traced ray may meet after the first (the textbook's depth
    /// limit, §9.6.1): Whitted's reflection and refraction depth, the path tracer's bounce
    /// limit. 0 to [`MAX_RAY_DEPTH`]; a ray at the limit keeps its surface's environment
    /// light (Whitted) or ends (path; its last surface's direct light is complete: 0 gives
    /// the direct light alone).
    pub ray_depth: u32,
    /// The kernel the fill and shaders run with; `None` is [`KernelKind::best`] (a kernel the
    /// CPU lacks runs as the portable one).
    pub kernel: Option<KernelKind>,
    /// Linear fog: per pixel in the per-pixel modes, per vertex in Gouraud, per facet in
    /// flat; `None` costs nothing.
    pub fog: Option<Fog>,
    /// Exposure in EV: colours are multiplied by `2^exposure` before the tone map (0: as
    /// rendered). glTF light units (lux, candela) and environments in cd/m² need it.
    pub exposure: f32,
    /// Out-of-range colour handling.
    pub tone: ToneMap,
    /// The environment of the `pbr` draws.
    pub environment: Environment,
    /// Shows the environment behind the scene, blurred to this roughness (0: sharp), instead
    /// of the background colour; `None`: the colour.
    pub env_background: Option<f32>,
    /// Shadow-map size and filtering for the lights that cast shadows (each light's
    /// `shadow` flag turns them on; none costs nothing).
    pub shadow: ShadowSettings,
    /// Shows a ground plane under the scene (it catches shadows).
    pub ground: Option<Ground>,
    /// Size of the meshes' points, in pixels of the image (default 1; rounded to whole
    /// pixels, 1 to [`crate::raster::MAX_STROKE_PX`]; see [`crate::raster::draw_points`]).
    pub point_size: f32,
    /// Width of the meshes' lines, in pixels of the image (default 1; rounded to whole
    /// pixels, 1 to [`crate::raster::MAX_STROKE_PX`]; see [`crate::raster::draw_wide_lines`]).
    pub line_width: f32,
    /// How Gouraud and flat shading light their vertices and facets.
    pub vertex_lighting: VertexLighting,
    /// Section planes that cut the model open, with caps where a solid's inside shows.
    pub sections: Sections,
    /// The punctual lights reflect off `pbr` surfaces by the specification's
    /// single-scattering BRDF, without the compensation for the energy rough surfaces lose
    /// between microfacets (on by default, as in three.js; the environment is always
    /// compensated).
    pub single_scatter: bool,
    /// Scene instances left out (the viewer's hide and isolate in its node tree).
    pub hidden: Hidden,
    /// The material variant drawn, by name (`KHR_materials_variants`; one of
    /// [`crate::scene::Scene::variants`]), or `None` for the file's default materials. A
    /// name the scene does not have draws the defaults (the command line and scene files
    /// check it against the model first).
    pub variant: Option<String>,
}

/// A set of [`crate::scene::Scene::instances`] indices that the frame leaves out: they are
/// not drawn, cast no shadow and are not picked by the probe or the measurement. One bit
/// per instance up to the highest hidden one, so equal sets compare equal however they
/// were made.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Hidden {
    bits: Vec<u64>,
}

impl Hidden {
    /// The highest instance number a set takes (a scene file's `hidden` is checked
    /// against it, so a stray number cannot make the set huge).
    pub const MAX_INSTANCE: usize = (1 << 24) - 1;

    /// The hidden instance numbers, ascending.
    pub fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        self.bits.iter().enumerate().flat_map(|(w, &bits)| {
            (0..64)
                .filter(move |b| bits & (1u64 << b) != 0)
                .map(move |b| w * 64 + b)
        })
    }

    /// Whether instance `k` is hidden.
    #[must_use]
    #[inline]
    pub fn contains(&self, k: usize) -> bool {
        self.bits
            .get(k / 64)
            .is_some_and(|w| w & (1u64 << (k % 64)) != 0)
    }

    /// Hides (`hidden`) or shows instance `k` (numbers above [`Hidden::MAX_INSTANCE`] are
    /// ignored).
    pub fn set(&mut self, k: usize, hidden: bool) {
        if k > Self::MAX_INSTANCE {
            return;
        }
        let (word, bit) = (k / 64, 1u64 << (k % 64));
        if hidden {
            if self.bits.len() <= word {
                self.bits.resize(word + 1, 0);
            }
            self.bits[word] |= bit;
        } else if let Some(w) = self.bits.get_mut(word) {
            *w &= !bit;
            while self.bits.last() == Some(&0) {
                self.bits.pop();
            }
        }
    }

    /// Every one of the `count` instances hidden except those of `keep` (isolate).
    #[must_use]
    pub fn all_but(count: usize, keep: impl IntoIterator<Item = usize>) -> Self {
        let mut h = Self::default();
        for k in 0..count {
            h.set(k, true);
        }
        for k in keep {
            h.set(k, false);
        }
        h
    }

    /// How many instances are hidden.
    #[must_use]
    pub fn count(&self) -> usize {
        self.bits.iter().map(|w| w.count_ones() as usize).sum()
    }

    /// Nothing hidden.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.bits.is_empty()
    }
}

/// Section planes: what lies on a plane's negative side is cut away, and where the inside
/// of a closed mesh shows through the cut it is filled with the cap colour. A cap is drawn
/// where a back face is seen, so an open surface seen from behind gets it too. The ground
/// plane is never cut; shadows are cast by the whole model.
#[derive(Clone, Debug, PartialEq)]
pub struct Sections {
    /// At most [`Sections::MAX`] world-space planes `(nx, ny, nz, d)` with unit normals:
    /// a point `p` is kept where `n·p + d >= 0` for every plane.
    pub planes: Vec<Vec4>,
    /// Linear RGB of the caps, or `None` to leave the cut open.
    pub cap: Option<glam::Vec3>,
}

impl Default for Sections {
    fn default() -> Self {
        Self {
            planes: Vec::new(),
            cap: Some(Self::CAP),
        }
    }
}

impl Sections {
    /// Most planes at once.
    pub const MAX: usize = crate::raster::MAX_SECTIONS;
    /// The default cap colour (linear RGB; sRGB #db6050), a red that stands apart from
    /// most materials.
    pub const CAP: glam::Vec3 = glam::Vec3::new(0.708, 0.117, 0.080);

    /// The plane `n·p + d = 0` scaled to a unit normal, keeping the side `n` points to.
    ///
    /// # Errors
    /// A zero or non-finite normal, or a non-finite offset.
    pub fn plane(n: glam::Vec3, d: f32) -> Result<Vec4, String> {
        let len = n.length();
        if !(n.is_finite() && d.is_finite()) || len < 1e-12 || !len.is_finite() {
            return Err(format!(
                "section plane {},{},{},{}: the normal must be finite and not zero, the offset finite",
                n.x, n.y, n.z, d
            ));
        }
        Ok((n / len).extend(d / len))
    }

    /// `NX,NY,NZ,D` (the command line's `--section`).
    ///
    /// # Errors
    /// Not four numbers, or not a plane ([`Sections::plane`]).
    pub fn parse_plane(s: &str) -> Result<Vec4, String> {
        let v: Vec<f32> = s
            .split(',')
            .map(|p| p.trim().parse::<f32>())
            .collect::<Result<_, _>>()
            .map_err(|_| format!("section plane '{s}': expected NX,NY,NZ,D (four numbers)"))?;
        match v[..] {
            [x, y, z, d] => Self::plane(glam::Vec3::new(x, y, z), d),
            _ => Err(format!(
                "section plane '{s}': expected NX,NY,NZ,D (four numbers)"
            )),
        }
    }

    /// Adds a plane.
    ///
    /// # Errors
    /// Already [`Sections::MAX`] planes.
    pub fn push(&mut self, plane: Vec4) -> Result<(), String> {
        if self.planes.len() >= Self::MAX {
            return Err(format!("at most {} section planes", Self::MAX));
        }
        self.planes.push(plane);
        Ok(())
    }

    /// No plane cuts.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.planes.is_empty()
    }

    /// The planes in the clip space of `view_projection` (world to clip), into `out`;
    /// returns how many. A world plane `P` becomes `(VP)^-T P`, computed in f64.
    pub fn to_clip(&self, view_projection: Mat4, out: &mut [Vec4; Self::MAX]) -> usize {
        let inv_t = view_projection.as_dmat4().inverse().transpose();
        let mut n = 0;
        for p in self.planes.iter().take(Self::MAX) {
            let c = (inv_t * p.as_dvec4()).as_vec4();
            if c.is_finite() {
                out[n] = c;
                n += 1;
            }
        }
        n
    }
}

/// The lighting formulas of the vertex modes (Gouraud and flat). The default is the
/// textbook's: Phong's `R·V` highlight, and flat shading lit once per facet at its centroid
/// (the textbook's §9.2.2). [`VertexLighting::GL`] is what GPU shaders and Mesa's llvmpipe
/// commonly do: Blinn's `N·H`, and flat shading lit at each triangle's last vertex (OpenGL's
/// provoking vertex) with the triangle's plane normal.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VertexLighting {
    /// Blinn's `N·H` highlight instead of Phong's `R·V`.
    pub blinn: bool,
    /// Flat shading lights each triangle at its last vertex, with the triangle's own plane
    /// normal, instead of each facet at its centroid.
    pub provoking_vertex: bool,
}

impl VertexLighting {
    /// Blinn's highlight and the provoking vertex: the formulas of `bench frame`'s peer.
    pub const GL: VertexLighting = VertexLighting {
        blinn: true,
        provoking_vertex: true,
    };
}

impl Settings {
    /// Every instance of `scene` that draws triangles is drawn in the `pbr` mode (glTF
    /// materials as authored, or `pbr` forced), and there is one: the glTF look, whose
    /// defaults are the Khronos glTF Sample Viewer's ([`ToneMap::Auto`], [`Lights::Auto`]).
    #[must_use]
    pub fn pbr_look(&self, scene: &Scene) -> bool {
        if let Some(mode) = self.shading {
            return mode.mode().base == crate::shade::mode::Base::Pbr
                && !scene.instances.is_empty();
        }
        let mut any = false;
        for inst in &scene.instances {
            let Some(mesh) = scene.meshes.get(inst.mesh) else {
                continue;
            };
            if mesh.corners.is_empty() {
                // Points and lines only: not shaded by a mode.
                continue;
            }
            let material = mesh.material_in(self.variant_index(scene)).and_then(|k| {
                self.materials
                    .as_ref()
                    .and_then(|ms| ms.get(k))
                    .or_else(|| scene.materials.get(k))
            });
            let pbr = material.is_some_and(|m| m.pbr.is_some());
            if !pbr || inst.style != Style::Inherit {
                return false;
            }
            any = true;
        }
        any
    }

    /// The index in `scene`'s [`crate::scene::Scene::variants`] of [`Settings::variant`].
    #[must_use]
    pub fn variant_index(&self, scene: &Scene) -> Option<usize> {
        let name = self.variant.as_deref()?;
        scene.variants.iter().position(|v| v == name)
    }

    /// What rays the shading mode traces beside rasterizing (the textbook's §9.6).
    #[must_use]
    pub fn rays(&self) -> crate::shade::mode::Rays {
        self.shading
            .map_or(crate::shade::mode::Rays::None, |s| s.mode().rays)
    }

    /// [`Lights::Auto`] with no lights in `scene` lights the frame with the default rig;
    /// not when the pbr look ([`Settings::pbr_look`]) is lit by an environment.
    #[must_use]
    pub fn default_rig(&self, scene: &Scene) -> bool {
        matches!(self.lights, Lights::Auto)
            && scene.lights.is_empty()
            && (self.environment == Environment::Off || !self.pbr_look(scene))
    }

    /// The tone map of a frame of `scene`: [`ToneMap::Auto`] resolved.
    #[must_use]
    pub fn tone_for(&self, scene: &Scene) -> ToneMap {
        match self.tone {
            ToneMap::Auto if self.pbr_look(scene) => ToneMap::PbrNeutral,
            ToneMap::Auto => ToneMap::Clamp,
            t => t,
        }
    }

    /// `2^exposure`, or 1 when the exposure is not finite or beyond +-64 EV.
    #[must_use]
    pub fn exposure_scale(&self) -> f32 {
        if self.exposure.is_finite() && self.exposure.abs() <= 64.0 {
            self.exposure.exp2()
        } else {
            1.0
        }
    }
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            shading: None,
            wireframe_overlay: false,
            output: Output::Shaded,
            background: Vec4::new(0.018, 0.02, 0.026, 1.0),
            double_sided: false,
            subpixel_bits: crate::raster::SUBPIXEL_BITS as u8,
            slots: SlotOverrides::default(),
            filter: None,
            lights: Lights::Auto,
            materials: None,
            samples: 1,
            msaa: 1,
            kernel: None,
            fog: None,
            exposure: 0.0,
            tone: ToneMap::Auto,
            environment: Environment::Auto,
            env_background: None,
            shadow: ShadowSettings::default(),
            ground: None,
            point_size: 1.0,
            line_width: 1.0,
            vertex_lighting: VertexLighting::default(),
            sections: Sections::default(),
            hidden: Hidden::default(),
            variant: None,
            single_scatter: false,
            ray_depth: DEFAULT_RAY_DEPTH,
        }
    }
}

/// The per-frame part: the camera and the image size in pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct View {
    pub camera: Camera,
    /// Image width in pixels (at least 1).
    pub width: u32,
    /// Image height in pixels (at least 1).
    pub height: u32,
}

impl View {
    /// Width over height.
    #[must_use]
    pub fn aspect(&self) -> f32 {
        self.width.max(1) as f32 / self.height.max(1) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec3, Vec4};

    fn tone(t: ToneMap, c: Vec3) -> Vec3 {
        t.apply(c.extend(0.5)).truncate()
    }

    #[test]
    fn pbr_neutral_keeps_the_middle_range_and_rolls_off_the_highlights() {
        // In [0.08, 0.8] - 0.04 per channel: the colour minus 0.04, hue kept.
        let c = Vec3::new(0.1, 0.4, 0.7);
        assert!(
            (tone(ToneMap::PbrNeutral, c) - (c - 0.04))
                .abs()
                .max_element()
                < 1e-6
        );
        // Black stays black; the toe is x - 6.25 x^2 below 0.08 (continuous at 0.08).
        assert_eq!(tone(ToneMap::PbrNeutral, Vec3::ZERO), Vec3::ZERO);
        let g = 0.05f32;
        let want = g - (g - 6.25 * g * g);
        assert!((tone(ToneMap::PbrNeutral, Vec3::splat(g)).x - want).abs() < 1e-7);
        // Highlights: below 1, increasing, and desaturated towards white.
        let mut last = 0.0;
        for k in 1..200 {
            let v = tone(ToneMap::PbrNeutral, Vec3::splat(k as f32 * 0.1)).x;
            assert!(v > last && v < 1.0, "{k}: {v}");
            last = v;
        }
        let red = tone(ToneMap::PbrNeutral, Vec3::new(8.0, 0.5, 0.5));
        assert!(red.x < 1.0 && red.y > 0.5 - 0.04, "desaturated: {red}");
    }

    #[test]
    fn the_aces_fits_give_their_published_values() {
        // Narkowicz: f(1) = 2.54 / 3.16.
        let n = tone(ToneMap::AcesNarkowicz, Vec3::ONE);
        assert!(
            (n - Vec3::splat(2.54 / 3.16)).abs().max_element() < 1e-6,
            "{n}"
        );
        // Hill: the matrices keep grey grey (rows sum to 1), so f(1) is the rational
        // curve at 1: (1.0245786 - 0.000090537) / (0.983729 + 0.432951 + 0.238081).
        let h = tone(ToneMap::AcesHill, Vec3::ONE);
        let want = (1.024_578_6 - 0.000_090_537) / (0.983_729 + 0.432_951 + 0.238_081);
        assert!((h - Vec3::splat(want)).abs().max_element() < 1e-5, "{h}");
        for t in [ToneMap::AcesNarkowicz, ToneMap::AcesHill] {
            assert_eq!(tone(t, Vec3::ZERO), Vec3::ZERO, "{t:?}: black stays black");
            let big = tone(t, Vec3::splat(1e6));
            assert!(
                big.max_element() <= 1.0 && big.min_element() > 0.99,
                "{t:?}: {big}"
            );
        }
    }

    #[test]
    fn every_tone_map_keeps_alpha_parses_its_name_and_leaves_non_finite_colours() {
        for t in ToneMap::ALL {
            assert_eq!(t.name().parse::<ToneMap>(), Ok(t));
            let c = t.apply(Vec4::new(2.0, 1.0, 0.5, 0.25));
            assert_eq!(c.w, 0.25, "{t:?}");
            assert!(
                c.truncate().max_element() <= 1.0 + 1e-6
                    || matches!(t, ToneMap::Clamp | ToneMap::Auto)
            );
            let nan = Vec4::new(f32::NAN, 0.5, 0.5, 1.0);
            assert!(t.apply(nan).x.is_nan(), "{t:?}");
        }
        assert!("aces".parse::<ToneMap>().unwrap_err().contains("aces-hill"));
    }
}
