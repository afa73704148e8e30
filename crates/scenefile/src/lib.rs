//! Scene files: an experiment saved as TOML or JSON (the extension decides) that names a
//! model and sets the camera, image size, shading, lights, material overrides, fog, tone
//! mapping, shadows, the ground plane and output options, and optionally a comparison
//! layout of labelled variants. The README's "Scene files" section is the schema: every
//! key, its type, default and meaning.
//!
//! Reading happens in two steps, so a caller can put its own overrides in between:
//!
//! 1. [`SceneFile::read`] parses the file and checks everything that does not need the
//!    model: unknown keys (serde `deny_unknown_fields`), value ranges, keys that exclude
//!    each other. Every error is one line naming the file and the key.
//! 2. [`SceneFile::load_model`], [`SceneFile::settings`], [`SceneFile::camera`] and
//!    [`SceneFile::comparison`] resolve it against the model (material names and
//!    indices, glTF camera numbers, images relative to the file). [`SceneFile::load`] does
//!    both steps at once.
//!
//! The other way, [`SceneFile::from_settings`] turns a renderer state ([`Settings`] and
//! [`View`]) into a file and [`SceneFile::save`] writes it, with paths relative to where it
//! is written; reading it back gives the same `Settings` (tested).
//!
//! Paths in a file are relative to the file's folder. Unlike model files, a scene file is
//! the user's own instruction, so its paths may point anywhere (e.g. `../../models/`).
//! Sizes are bounded (image sides, shadow-map size, sample counts, the number of lights and
//! comparison cells), so no value in a file can ask for a huge allocation.

// The crates below this one, under the module names the code uses (`crate::scene::...`).
use realist_color as color;
use realist_load as load;
use realist_mesh as mesh;
use realist_overlay as overlay;
use realist_raster as raster;
use realist_render as render;
use realist_scene as scene;
use realist_shade as shade;
use realist_texture as texture;

use std::path::{Path, PathBuf};

use crate::load::{LoadError, LoadOptions};
use crate::render::{Settings, View};
use crate::scene::{Camera, Scene};

mod compare;
mod convert;
mod export;
mod paths;
pub use paths::lexically_absolute;
pub mod schema;
mod settings;

#[cfg(test)]
mod tests;

pub use compare::RgbImage;
pub use compare::{compose, Comparison, Variant};
pub use convert::{orbit_camera, parse_light, LIGHT_SYNTAX};
pub use schema::SceneDoc;
pub use settings::{add_lights, shadow_every_light, variant_list};

/// Largest scene file read.
pub const MAX_FILE_BYTES: u64 = 4 << 20;
/// Largest image side (pixels), for a frame and for a whole comparison.
pub const MAX_SIDE: u32 = 16384;
/// Most pixels of a frame (times its multisamples) and of a comparison grid: an 8K frame.
pub const MAX_PIXELS: u64 = 1 << 25;
/// Most lights in a file.
pub const MAX_LIGHTS: usize = 256;
/// Most comparison variants.
pub const MAX_VARIANTS: usize = 64;

/// Why a scene file could not be read, used or written. Messages are one line that
/// starts with the file's path.
#[derive(Debug, thiserror::Error)]
pub enum SceneFileError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: {size} bytes is too large for a scene file (at most {MAX_FILE_BYTES})")]
    TooLarge { path: PathBuf, size: u64 },
    #[error("{path}: a scene file's name must end in .toml or .json")]
    Extension { path: PathBuf },
    /// The text is not valid TOML/JSON, has an unknown key, or a value of the wrong type;
    /// the message names the key (and for TOML the line).
    #[error("{path}: {message}")]
    Parse { path: PathBuf, message: String },
    /// A value is out of range or contradicts another.
    #[error("{path}: {key}: {reason}")]
    Invalid {
        path: PathBuf,
        key: String,
        reason: String,
    },
    /// A numeric setting is out of its range: the message is the setting's own
    /// ([`crate::render::Numeric::check`]), the same as the command line's.
    #[error("{path}: {message}")]
    Setting { path: PathBuf, message: String },
    /// The model (or an image) could not be loaded; the message names that file.
    #[error("{path}: {source}")]
    Load { path: PathBuf, source: LoadError },
}

/// The format of a scene file, from its extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Toml,
    Json,
}

impl Format {
    /// The format a path's extension names, if any.
    #[must_use]
    pub fn of(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "toml" => Some(Format::Toml),
            "json" => Some(Format::Json),
            _ => None,
        }
    }
}

/// What a scene file draws.
#[derive(Clone, Debug, PartialEq)]
pub enum ModelSource {
    /// The built-in demo ([`crate::scene::demo`]).
    Demo,
    /// A model file (absolute, or relative to the working directory).
    File(PathBuf),
    /// A generated mesh.
    Primitive(schema::PrimitiveSpec),
}

/// A parsed and checked scene file.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneFile {
    /// Where it was read from (or will be written to); relative paths in `doc` are
    /// relative to its folder.
    pub path: PathBuf,
    pub doc: SceneDoc,
}

/// Everything a scene file sets, resolved against its model.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub file: SceneFile,
    pub model: ModelSource,
    /// The factor the model's own lights were scaled by (`light_scale`; pass it back to
    /// [`SceneFile::from_settings`]).
    pub light_scale: f32,
    pub scene: Scene,
    pub settings: Settings,
    /// The file's camera (or the default view) at the file's size (or 1280x720).
    pub view: View,
    /// The output image the file names, relative to the working directory.
    pub output: Option<PathBuf>,
    pub comparison: Option<Comparison>,
}

/// The image size used when neither the file nor the caller sets one.
pub const DEFAULT_SIZE: (u32, u32) = (1280, 720);

impl SceneFile {
    /// Reads and checks `path` (`.toml` or `.json`).
    ///
    /// # Errors
    /// The file cannot be read, is not TOML/JSON, has unknown keys, or a value is invalid.
    pub fn read(path: &Path) -> Result<SceneFile, SceneFileError> {
        let format = Format::of(path).ok_or_else(|| SceneFileError::Extension {
            path: path.to_owned(),
        })?;
        let io = |source| SceneFileError::Io {
            path: path.to_owned(),
            source,
        };
        let size = std::fs::metadata(path).map_err(io)?.len();
        if size > MAX_FILE_BYTES {
            return Err(SceneFileError::TooLarge {
                path: path.to_owned(),
                size,
            });
        }
        let text = std::fs::read_to_string(path).map_err(io)?;
        Self::parse(&text, format, path)
    }

    /// Parses and checks `text` as if read from `path`.
    ///
    /// # Errors
    /// As [`SceneFile::read`].
    pub fn parse(text: &str, format: Format, path: &Path) -> Result<SceneFile, SceneFileError> {
        let parsed = match format {
            Format::Toml => toml::from_str::<SceneDoc>(text).map_err(|e| {
                // toml's message spans several lines (a snippet of the file); one line.
                let msg = e.message().to_owned();
                match e.span().map(|s| line_of(text, s.start)) {
                    Some(line) => format!("line {line}: {msg}"),
                    None => msg,
                }
            }),
            Format::Json => serde_json::from_str::<SceneDoc>(text).map_err(|e| e.to_string()),
        };
        let doc = parsed.map_err(|message| SceneFileError::Parse {
            path: path.to_owned(),
            message,
        })?;
        let file = SceneFile {
            path: path.to_owned(),
            doc,
        };
        file.check()?;
        Ok(file)
    }

    /// Reads `path` and resolves it against its model: the one call for "open this
    /// experiment".
    ///
    /// # Errors
    /// As [`SceneFile::read`], or the model, an image, a material or camera reference
    /// cannot be resolved.
    pub fn load(path: &Path) -> Result<Loaded, SceneFileError> {
        let file = Self::read(path)?;
        file.resolve(&LoadOptions::default())
    }

    /// Resolves a read file against its model (loaded with `opts`).
    ///
    /// # Errors
    /// As [`SceneFile::load`].
    pub fn resolve(self, opts: &LoadOptions) -> Result<Loaded, SceneFileError> {
        let model = self.model()?;
        let scene = self.load_model(opts)?;
        let settings = self.settings(&scene)?;
        let (width, height) = self.size().unwrap_or(DEFAULT_SIZE);
        let camera = match self.camera(&scene, width as f32 / height as f32)? {
            Some(c) => c,
            None => {
                crate::render::default_camera_up(&scene, width as f32 / height as f32, self.up())
            }
        };
        let comparison = self.comparison(&scene, &settings)?;
        let output = self.output();
        Ok(Loaded {
            model,
            light_scale: self.doc.light_scale.unwrap_or(1.0) as f32,
            scene,
            settings,
            view: View {
                camera,
                width,
                height,
            },
            output,
            comparison,
            file: self,
        })
    }

    /// The folder relative paths in the file start from.
    #[must_use]
    pub fn folder(&self) -> PathBuf {
        match self.path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
            _ => PathBuf::from("."),
        }
    }

    /// The file's path joined to a path written in it.
    #[must_use]
    pub fn resolve_path(&self, written: &str) -> PathBuf {
        self.folder().join(written)
    }

    /// The image size the file sets.
    #[must_use]
    pub fn size(&self) -> Option<(u32, u32)> {
        self.doc.size.map(|[w, h]| (w, h))
    }

    /// The UV generator the file's `uv` key names (`None` for `"mesh"` or no key).
    #[must_use]
    pub fn uv(&self) -> Option<crate::texture::UvGenerator> {
        self.doc.uv.and_then(|schema::Kw(c)| c.generator())
    }

    /// Records the texture coordinates a state was drawn with in the file's `uv` key (what
    /// [`SceneFile::from_settings`] cannot know, as they are a load option): `None` removes
    /// the key (the model's own UVs).
    pub fn set_uv(&mut self, uv: Option<crate::texture::UvGenerator>) {
        self.doc.uv = uv.map(|g| schema::Kw(schema::UvChoice::Generated(g)));
    }

    /// The output image the file names, relative to the working directory.
    #[must_use]
    pub fn output(&self) -> Option<PathBuf> {
        self.doc.output.as_deref().map(|o| self.resolve_path(o))
    }

    /// Writes the file as TOML or JSON (by `path`'s extension), with every path in it
    /// rewritten relative to `path`'s folder; `self.path` becomes `path`.
    ///
    /// # Errors
    /// The extension is neither `.toml` nor `.json`, or the file cannot be written.
    pub fn save(&mut self, path: &Path) -> Result<(), SceneFileError> {
        let format = Format::of(path).ok_or_else(|| SceneFileError::Extension {
            path: path.to_owned(),
        })?;
        let doc = paths::rebase(&self.doc, &self.folder(), path);
        let text = match format {
            Format::Toml => toml::to_string_pretty(&doc).map_err(|e| e.to_string()),
            Format::Json => serde_json::to_string_pretty(&doc).map_err(|e| e.to_string()),
        }
        .map_err(|message| SceneFileError::Parse {
            path: path.to_owned(),
            message: format!("cannot be written: {message}"),
        })?;
        std::fs::write(path, text + "\n").map_err(|source| SceneFileError::Io {
            path: path.to_owned(),
            source,
        })?;
        self.doc = doc;
        self.path = path.to_owned();
        Ok(())
    }

    /// A file that reproduces `settings` and `view` on `model` (whose own lights are
    /// scaled by `light_scale`, 1 for none). Images are referred to by their texture's
    /// `name`, which must be the image file's path (as [`SceneFile`] and
    /// [`crate::load::load_texture`] set it); an image without one is left out, and so is
    /// the machine-specific kernel choice: the notes say what was left out. The file's
    /// `path` is empty until [`SceneFile::save`].
    #[must_use]
    pub fn from_settings(
        model: &ModelSource,
        light_scale: f32,
        settings: &Settings,
        view: &View,
    ) -> (SceneFile, Vec<String>) {
        let (doc, notes) = export::doc(model, light_scale, settings, view);
        (
            SceneFile {
                path: PathBuf::new(),
                doc,
            },
            notes,
        )
    }

    /// Loads the model the file names (with its lights scaled by `light_scale`).
    ///
    /// # Errors
    /// The model cannot be loaded or generated.
    ///
    /// Texture coordinates are generated by `opts.uv` if set, else by the file's `uv` key
    /// (the textbook's §9.5; `"mesh"` or no key keeps the model's own).
    pub fn load_model(&self, opts: &LoadOptions) -> Result<Scene, SceneFileError> {
        let uv = opts.uv.or_else(|| self.uv());
        let model = self.model()?;
        let from_file = matches!(model, ModelSource::File(_));
        let mut scene = match model {
            ModelSource::Demo => crate::scene::demo(),
            ModelSource::File(p) => {
                let opts = LoadOptions { uv, ..opts.clone() };
                crate::load::load(&p, &opts).map_err(|source| SceneFileError::Load {
                    path: self.path.clone(),
                    source,
                })?
            }
            ModelSource::Primitive(spec) => {
                convert::primitive(&spec).map_err(|reason| self.invalid("primitive", reason))?
            }
        };
        // A model file's loader applies `uv` itself (before its own slot check).
        if let (Some(g), false) = (&uv, from_file) {
            scene.apply_uv_generator(g);
            scene.check_texture_slots();
        }
        let scale = self.doc.light_scale.unwrap_or(1.0) as f32;
        for l in &mut scene.lights {
            l.intensity *= scale;
        }
        Ok(scene)
    }

    /// The numeric setting `key` ([`crate::render::NUMERIC`]) checked: `v`, or its message.
    pub(crate) fn number(&self, key: &str, v: f64) -> Result<f64, SceneFileError> {
        crate::render::numeric(key)
            .check(v)
            .map_err(|message| SceneFileError::Setting {
                path: self.path.clone(),
                message,
            })
    }

    /// An `Invalid` error for `key`.
    fn invalid(&self, key: impl Into<String>, reason: impl Into<String>) -> SceneFileError {
        SceneFileError::Invalid {
            path: self.path.clone(),
            key: key.into(),
            reason: reason.into(),
        }
    }

    /// The file's up axis (`up = "z"`; +Y when it does not say).
    #[must_use]
    pub fn up(&self) -> crate::scene::Up {
        self.doc.up.map_or(crate::scene::Up::Y, |k| k.0)
    }

    /// The file's camera, resolved against `scene` for an image of aspect `aspect`;
    /// `None` when the file has no `[camera]` (the caller's default view).
    ///
    /// # Errors
    /// A glTF camera number the model does not have, or near/far that do not fit.
    pub fn camera(&self, scene: &Scene, aspect: f32) -> Result<Option<Camera>, SceneFileError> {
        match &self.doc.camera {
            None => Ok(None),
            Some(spec) => convert::camera(spec, scene, aspect, self.up())
                .map(Some)
                .map_err(|(key, reason)| self.invalid(format!("camera.{key}"), reason)),
        }
    }
}

/// 1-based line number of byte `offset` in `text`.
fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}
