//! glTF 2.0 (`.gltf` with external or `data:` buffers, and `.glb`) into a [`Scene`].
//!
//! The file is parsed into the `gltf` crate's JSON types only, and only the parts that are
//! drawn ([`Json`]: animations and skins are kept as plain JSON and read one at a time, so
//! their quirks cannot reject a file); the crate's `Document` wrapper and its validation are not used, because they
//! index without checks and panic on unresolved references. Instead every index is looked up with `get`,
//! buffers and images are resolved here ([`uri`], GLB chunks by [`glb`]), and accessors are
//! read by [`accessor`] with checked byte ranges (including sparse accessors and accessors
//! without a bufferView, which read as zeros).
//!
//! What is drawn: the scene [`LoadOptions::scene`] asks for, else the default scene (else
//! scene 0, else every root node), walked iteratively by [`nodes`]; every primitive of
//! every node with a mesh (triangles, strips, fans, and points, lines, line loops and line
//! strips, which become meshes of points or line segments) becomes one [`Mesh`] (built
//! once, shared by all nodes that use it) and one [`Instance`] with the node's world
//! matrix. Meshes without NORMAL get flat normals, as the
//! spec requires; positions are welded so topology reports mean something.
//!
//! **Mirroring transforms:** a node whose world matrix has a negative determinant turns its
//! triangles' winding around. The loader leaves the mesh as it is; the renderer checks
//! `instance.world.determinant() < 0` and flips its back-face test for that instance.
//!
//! Materials keep every texture slot (base colour, metallic-roughness, normal, occlusion,
//! emissive), each with its sampler, `TEXCOORD_n` set and `KHR_texture_transform`
//! ([`material`]); primitives keep their UV sets and tangents ([`primitive`]).
//!
//! The node tree is kept ([`Scene::graph`], [`nodes`]) with skins, morph targets
//! ([`skin`]; deformable primitives are not welded) and animations ([`animation`]), so
//! [`crate::render::PreparedScene::pose_at`] can pose the scene at any time.
//!
//! **Compressed glTF.** A bufferView with `EXT_meshopt_compression` or
//! `KHR_meshopt_compression` is decoded on first use by [`Doc::view`] ([`meshopt`]), so
//! every reader of views (accessors, sparse data, images, animation samplers) sees the
//! decoded bytes; its placeholder buffer (`{"byteLength": n}`, no URI, possibly
//! `fallback: true`) is never read. A primitive with `KHR_draco_mesh_compression` is decoded
//! before its accessors are read, and the accessors it lists (and its indices) come from the
//! decoded mesh ([`draco`]). Images may be KTX2 with Basis Universal data
//! (`KHR_texture_basisu`, transcoded by `load::ktx2`) or WebP (`EXT_texture_webp`, by the
//! `image` crate); a texture names them in its extension, and its `source` is then only a
//! fallback. All three decoders are pure Rust crates (`meshoptimizer-rs`, `draco-core`,
//! `basisu`), run under `catch_unwind`: bad geometry data is an error naming the bufferView
//! or the mesh and primitive; a bad image is a warning and the texture is dropped.
//!
//! Cameras (perspective and
//! orthographic) go to [`Scene::cameras`] and `KHR_lights_punctual` lights to
//! [`Scene::lights`] (see [`lights`] for the units). The extensions supported are
//! `KHR_mesh_quantization`, `KHR_lights_punctual`, `KHR_texture_transform`,
//! `KHR_materials_emissive_strength`, `_unlit`, `_ior`, `_specular`, `_clearcoat`, `_sheen`
//! and `_variants`,
//! `KHR_animation_pointer` (node transforms and material factors), `EXT_mesh_gpu_instancing`,
//! `EXT_meshopt_compression`, `KHR_meshopt_compression`, `KHR_draco_mesh_compression`,
//! `KHR_texture_basisu` and `EXT_texture_webp` ([`SUPPORTED`]); a file that *requires* any
//! other is refused, naming it.

use std::borrow::Cow;
use std::cell::OnceCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use gltf::json::mesh::Semantic;
use gltf::json::validation::Checked;

use super::progress::{Stage, Tracker};
use super::{files, Budget, LoadError, LoadOptions};
use crate::mesh::MeshError;
use crate::scene::{LoadReport, Scene};

mod accessor;
mod animation;
pub(crate) mod draco;
pub(super) mod glb;
mod instancing;
mod lights;
mod material;
pub(crate) mod meshopt;
mod nodes;
mod primitive;
mod schema;
mod skin;
mod uri;
mod variants;

use schema::Json;

#[cfg(test)]
mod tests;

/// Why a glTF file could not be loaded. Messages are one line starting with the path.
#[derive(Debug, thiserror::Error)]
pub enum GltfError {
    #[error("{path}: malformed GLB: {reason}")]
    Glb { path: PathBuf, reason: String },
    #[error("{path}: invalid glTF JSON: {message}")]
    Json { path: PathBuf, message: String },
    #[error("{path}: asset version {version} is not glTF 2.x")]
    Version { path: PathBuf, version: String },
    #[error("{path}: requires extension {name}, which realist does not support")]
    Extension { path: PathBuf, name: String },
    /// `from` (e.g. "mesh 0 primitive 1 POSITION") names a `kind` index that does not exist.
    #[error("{path}: {from} refers to {kind} {index}, but there are only {count}")]
    Reference {
        path: PathBuf,
        from: String,
        kind: &'static str,
        index: usize,
        count: usize,
    },
    #[error("{path}: buffer {buffer}: {reason}")]
    Buffer {
        path: PathBuf,
        buffer: usize,
        reason: String,
    },
    /// A buffer with neither a `uri` nor the GLB binary chunk: valid glTF, but there are no
    /// bytes. Primitives that need it are skipped (with a note) rather than failing the file.
    #[error("{path}: buffer {buffer} has no uri and the file has no GLB binary chunk: no data")]
    NoData { path: PathBuf, buffer: usize },
    #[error("{path}: bufferView {view}: {reason}")]
    View {
        path: PathBuf,
        view: usize,
        reason: String,
    },
    /// An accessor is malformed or of the wrong type for its use (`used_by`).
    #[error("{path}: accessor {accessor} ({used_by}): {reason}")]
    Accessor {
        path: PathBuf,
        accessor: usize,
        used_by: String,
        reason: String,
    },
    #[error("{path}: mesh {mesh} primitive {primitive}: {reason}")]
    Primitive {
        path: PathBuf,
        mesh: usize,
        primitive: usize,
        reason: String,
    },
    #[error("{path}: mesh {mesh} primitive {primitive}: {source}")]
    Mesh {
        path: PathBuf,
        mesh: usize,
        primitive: usize,
        source: MeshError,
    },
}

/// The parsed file and its lazily loaded buffers.
pub(super) struct Doc<'a> {
    pub path: &'a Path,
    /// Canonical model folder: URIs may not leave it.
    pub root: PathBuf,
    pub json: Json,
    /// The GLB `BIN\0` chunk.
    pub bin: Option<&'a [u8]>,
    pub budget: &'a Budget,
    /// Progress of the load: checked before each buffer is loaded and each primitive built.
    pub tracker: &'a Tracker,
    buffers: Vec<OnceCell<Cow<'a, [u8]>>>,
    /// Decoded meshopt-compressed bufferViews, by view index.
    decoded_views: Vec<OnceCell<Vec<u8>>>,
    /// Accessors of the Draco-compressed primitive being read, packed from its decoded mesh
    /// ([`draco`]); `packed` reads them instead of their bufferViews.
    pub draco_accessors: std::cell::RefCell<HashMap<usize, draco::Packed>>,
}

impl<'a> Doc<'a> {
    /// A `Reference` error.
    pub fn missing(
        &self,
        from: impl Into<String>,
        kind: &'static str,
        index: usize,
        count: usize,
    ) -> LoadError {
        GltfError::Reference {
            path: self.path.to_owned(),
            from: from.into(),
            kind,
            index,
            count,
        }
        .into()
    }

    /// The bytes of buffer `i` (at most its `byteLength`), loaded on first use.
    pub fn buffer(&self, i: usize, from: &str) -> Result<&[u8], LoadError> {
        let cell = self
            .buffers
            .get(i)
            .ok_or_else(|| self.missing(from, "buffer", i, self.buffers.len()))?;
        if let Some(bytes) = cell.get() {
            return Ok(bytes);
        }
        self.tracker.check()?;
        let err = |reason: String| {
            LoadError::from(GltfError::Buffer {
                path: self.path.to_owned(),
                buffer: i,
                reason,
            })
        };
        let buffer = self
            .json
            .buffers
            .get(i)
            .ok_or_else(|| self.missing(from, "buffer", i, 0))?;
        let bytes: Cow<'a, [u8]> = match (&buffer.uri, self.bin) {
            (Some(uri), _) => Cow::Owned(
                uri::load(uri, &self.root, self.budget, &format!("buffer {i}"))?.map_err(err)?,
            ),
            (None, Some(bin)) if i == 0 => Cow::Borrowed(bin),
            (None, _) => {
                return Err(GltfError::NoData {
                    path: self.path.to_owned(),
                    buffer: i,
                }
                .into())
            }
        };
        let declared = buffer.byte_length.0;
        if (bytes.len() as u64) < declared {
            return Err(err(format!(
                "byteLength is {declared}, but the data has only {} bytes",
                bytes.len()
            )));
        }
        let bytes = match bytes {
            Cow::Borrowed(b) => Cow::Borrowed(b.get(..declared as usize).unwrap_or(b)),
            Cow::Owned(mut v) => {
                v.truncate(declared as usize);
                Cow::Owned(v)
            }
        };
        Ok(cell.get_or_init(|| bytes))
    }

    /// The bytes of bufferView `i` and its byteStride. A view compressed with
    /// `EXT_meshopt_compression` or `KHR_meshopt_compression` is decoded on first use
    /// ([`meshopt`]) and its decoded bytes returned.
    pub fn view(&self, i: usize, from: &str) -> Result<(&[u8], Option<usize>), LoadError> {
        let count = self.json.buffer_views.len();
        let view = self
            .json
            .buffer_views
            .get(i)
            .ok_or_else(|| self.missing(from, "bufferView", i, count))?;
        let stride = view.byte_stride.map(|s| s.0);
        let view_error = |reason: String| {
            LoadError::from(GltfError::View {
                path: self.path.to_owned(),
                view: i,
                reason,
            })
        };
        let extensions = view.extensions.as_ref().map(|e| &e.others);
        if let Some(compressed) = meshopt::Compressed::of(extensions) {
            let cell = self
                .decoded_views
                .get(i)
                .ok_or_else(|| self.missing(from, "bufferView", i, count))?;
            if let Some(bytes) = cell.get() {
                return Ok((bytes, stride));
            }
            let c = compressed.map_err(view_error)?;
            let decoded = self.decode_meshopt(i, &c, view.byte_length.0, stride)?;
            return Ok((cell.get_or_init(|| decoded), stride));
        }
        let buffer = self.buffer(view.buffer.value(), &format!("bufferView {i}"))?;
        let bytes = Self::range(
            buffer,
            view.byte_offset.map_or(0, |o| o.0),
            view.byte_length.0,
        )
        .ok_or_else(|| {
            view_error(format!(
                "bytes {}..{} do not fit buffer {} of {} bytes",
                view.byte_offset.map_or(0, |o| o.0),
                view.byte_offset
                    .map_or(0, |o| o.0)
                    .saturating_add(view.byte_length.0),
                view.buffer.value(),
                buffer.len()
            ))
        })?;
        Ok((bytes, stride))
    }

    /// `len` bytes of `buffer` from `start`, if they are there.
    fn range(buffer: &[u8], start: u64, len: u64) -> Option<&[u8]> {
        let end = start.checked_add(len)?;
        buffer.get(usize::try_from(start).ok()?..usize::try_from(end).ok()?)
    }

    /// Decodes meshopt-compressed bufferView `i` (declared `byte_length` and `stride`).
    fn decode_meshopt(
        &self,
        i: usize,
        c: &meshopt::Compressed,
        byte_length: u64,
        stride: Option<usize>,
    ) -> Result<Vec<u8>, LoadError> {
        let ext = c.extension;
        let view_error = |reason: String| {
            LoadError::from(GltfError::View {
                path: self.path.to_owned(),
                view: i,
                reason: format!("{ext}: {reason}"),
            })
        };
        let decoded = c.decoded_len();
        if decoded != Some(byte_length as usize) || byte_length > isize::MAX as u64 {
            return Err(view_error(format!(
                "count {} × byteStride {} does not match the view's byteLength {byte_length}",
                c.count, c.byte_stride
            )));
        }
        if stride.is_some_and(|s| s != c.byte_stride) {
            return Err(view_error(format!(
                "byteStride {} differs from the view's {}",
                c.byte_stride,
                stride.unwrap_or(0)
            )));
        }
        let buffer = self.buffer(c.buffer, &format!("bufferView {i} ({ext})"))?;
        let source = Self::range(buffer, c.byte_offset, c.byte_length).ok_or_else(|| {
            view_error(format!(
                "compressed bytes {}..{} do not fit buffer {} of {} bytes",
                c.byte_offset,
                c.byte_offset.saturating_add(c.byte_length),
                c.buffer,
                buffer.len()
            ))
        })?;
        meshopt::decode(c, source, self.budget, &format!("bufferView {i}"))?.map_err(view_error)
    }
}

/// Scene under construction, with the caches that make every glTF mesh, material and
/// image be converted once.
pub(super) struct Builder<'a> {
    pub doc: Doc<'a>,
    pub scene: Scene,
    /// (mesh, primitive) -> scene mesh (`None`: skipped).
    pub meshes: HashMap<(usize, usize), Option<usize>>,
    /// glTF material -> scene material (`None`: unusable, default used).
    pub materials: HashMap<usize, Option<usize>>,
    /// The specification's default material, added once for the primitives without one.
    pub default_material: Option<usize>,
    /// (image, decoded as sRGB) -> scene texture (`None`: unusable, already reported).
    pub textures: HashMap<(usize, bool), Option<usize>>,
    /// Images that could not be read or decoded (already reported).
    pub failed_images: std::collections::HashSet<usize>,
    /// `KHR_lights_punctual` lights and the nodes that place them.
    lights: lights::PunctualLights,
    /// The scene asked for ([`LoadOptions::scene`]); `None`: the file's default.
    pub chosen_scene: Option<usize>,
    /// (glTF light, scene light) for every light a node placed (animation pointers name
    /// the file's lights).
    pub placed_lights: Vec<(usize, usize)>,
    /// (glTF camera, scene camera) for every camera a node placed.
    pub placed_cameras: Vec<(usize, usize)>,
}

/// Where reading and parsing end on the progress bar; the rest is geometry (in units of
/// vertices, see [`geometry_units`]), with images decoded as the materials that use them
/// are first met. Geometry dominates a big file (96% of a 2M-triangle GLB, reading 4%);
/// a `.gltf` with `data:` buffers spends more in parsing.
const READ_UNTIL: f32 = 0.05;
const PARSE_UNTIL: f32 = 0.10;

/// Loads a `.gltf` or `.glb` file, reporting to `tracker`.
pub(crate) fn load_gltf(
    path: &Path,
    opts: &LoadOptions,
    tracker: &Tracker,
) -> Result<Scene, LoadError> {
    let budget = Budget::new(path, opts.max_bytes);
    let root = files::model_folder(path)?;
    let bytes = files::read_model(path, &budget, "glTF file", tracker, READ_UNTIL)?;
    let is_glb = bytes.starts_with(b"glTF");
    let glb_err = |reason: String| {
        LoadError::from(GltfError::Glb {
            path: path.to_owned(),
            reason,
        })
    };
    let (json_bytes, bin) = if is_glb {
        let chunks = glb::split(&bytes).map_err(glb_err)?;
        (chunks.json, chunks.bin)
    } else if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("glb"))
    {
        return Err(glb_err("missing the `glTF` magic".into()));
    } else {
        (bytes.as_slice(), None)
    };
    let json_bytes = json_bytes
        .strip_prefix(b"\xEF\xBB\xBF")
        .unwrap_or(json_bytes);
    tracker.begin(Stage::Parsing, PARSE_UNTIL, 1)?;
    let json = schema::parse(json_bytes, &budget)?.map_err(|e| GltfError::Json {
        path: path.to_owned(),
        message: e.to_string(),
    })?;
    check_header(path, &json)?;
    tracker.begin(Stage::Geometry, 1.0, geometry_units(&json))?;

    let mut report = LoadReport {
        file: path.display().to_string(),
        format: if is_glb { "GLB" } else { "glTF" }.into(),
        ..LoadReport::default()
    };
    note_unsupported(&json, &mut report);
    let punctual = if lights::used(&json) {
        // The narrow second parse keeps little, but serde_json's values for the light
        // entries and node extensions are charged as the first parse was.
        budget.charge((json_bytes.len() as u64).saturating_mul(2), || {
            format!("{} (second parse)", lights::EXTENSION)
        })?;
        lights::parse(json_bytes, &mut report.warnings)
    } else {
        lights::PunctualLights::default()
    };
    let buffers = json.buffers.iter().map(|_| OnceCell::new()).collect();
    let decoded_views = json.buffer_views.iter().map(|_| OnceCell::new()).collect();
    let doc = Doc {
        path,
        root,
        json,
        bin,
        budget: &budget,
        tracker,
        buffers,
        decoded_views,
        draco_accessors: Default::default(),
    };
    let variants = variants::names(doc.json.extensions.as_ref(), &mut report.warnings);
    let mut b = Builder {
        doc,
        scene: Scene {
            report,
            variants,
            ..Scene::default()
        },
        meshes: HashMap::new(),
        materials: HashMap::new(),
        default_material: None,
        textures: HashMap::new(),
        failed_images: std::collections::HashSet::new(),
        lights: punctual,
        chosen_scene: opts.scene,
        placed_lights: Vec::new(),
        placed_cameras: Vec::new(),
    };
    b.walk()?;
    if b.scene.instances.is_empty() {
        b.scene
            .report
            .warnings
            .push("the scene has nothing to draw".into());
    }
    Ok(b.scene)
}

/// Progress units of primitive `p` of mesh `m`: its vertex count (POSITION's), plus one.
fn primitive_units(json: &Json, m: usize, p: usize) -> u64 {
    let position = json
        .meshes
        .get(m)
        .and_then(|mesh| mesh.primitives.get(p))
        .and_then(|prim| prim.attributes.get(&Checked::Valid(Semantic::Positions)));
    position
        .and_then(|a| json.accessors.get(a.value()))
        .map_or(0, |a| a.count.0)
        .saturating_add(1)
}

/// Progress units of the geometry stage: those of every primitive of every mesh a node
/// uses (each is built once however many nodes share it).
fn geometry_units(json: &Json) -> u64 {
    let mut used = vec![false; json.meshes.len()];
    for m in json.nodes.iter().filter_map(|n| n.mesh) {
        if let Some(flag) = used.get_mut(m.value()) {
            *flag = true;
        }
    }
    let used = used.iter().enumerate().filter(|(_, &u)| u);
    used.flat_map(|(m, _)| {
        let primitives = json.meshes.get(m).map_or(0, |mesh| mesh.primitives.len());
        (0..primitives).map(move |p| primitive_units(json, m, p))
    })
    .fold(0u64, u64::saturating_add)
}

/// Integer vertex attributes (read and converted to floats).
const QUANTIZATION: &str = "KHR_mesh_quantization";

/// The extensions supported: [`QUANTIZATION`], punctual lights, texture transforms, the
/// material extensions of [`material`], material variants ([`variants`]), animation
/// pointers ([`animation`]), and the compressed forms of geometry ([`meshopt`],
/// [`draco`]) and images (`KHR_texture_basisu`, `EXT_texture_webp`).
const SUPPORTED: [&str; 23] = [
    QUANTIZATION,
    meshopt::EXT,
    meshopt::KHR,
    draco::EXTENSION,
    material::BASISU,
    material::WEBP,
    lights::EXTENSION,
    material::TEXTURE_TRANSFORM,
    material::EMISSIVE_STRENGTH,
    material::UNLIT,
    material::IOR,
    material::SPECULAR,
    material::CLEARCOAT,
    material::SHEEN,
    material::IRIDESCENCE,
    material::ANISOTROPY,
    material::DIFFUSE_TRANSMISSION,
    material::TRANSMISSION,
    material::VOLUME,
    material::DISPERSION,
    variants::EXTENSION,
    animation::POINTER,
    instancing::EXTENSION,
];

/// Refuses files that are not glTF 2.x or that require an extension not in [`SUPPORTED`].
fn check_header(path: &Path, json: &Json) -> Result<(), LoadError> {
    let version = &json.asset.version;
    if version.split('.').next() != Some("2") {
        return Err(GltfError::Version {
            path: path.to_owned(),
            version: version.clone(),
        }
        .into());
    }
    if let Some(name) = json
        .extensions_required
        .iter()
        .find(|e| !SUPPORTED.contains(&e.as_str()))
    {
        return Err(GltfError::Extension {
            path: path.to_owned(),
            name: name.clone(),
        }
        .into());
    }
    Ok(())
}

/// Notes file-wide features that are not loaded.
fn note_unsupported(json: &Json, report: &mut LoadReport) {
    let ignored: Vec<&str> = json
        .extensions_used
        .iter()
        .map(String::as_str)
        .filter(|e| !SUPPORTED.contains(e))
        .collect();
    if !ignored.is_empty() {
        report.skipped.push(format!(
            "extensions used but not supported (ignored): {}",
            ignored.join(", ")
        ));
    }
}
