//! MTL material libraries: reading them for `tobj` (inside the model's folder, size-capped,
//! pre-checked so `tobj` cannot panic), converting `tobj` materials into [`Material`]s, and
//! loading their `map_Kd` (base colour) and `map_Ks` (gloss) textures once each.
//!
//! MTL colours are taken as linear RGB. Problems in an MTL file never fail the load: the
//! offending line (or library) is skipped and the report says so.

use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Vec3;

use crate::progress::Tracker;
use crate::scene::{AlphaMode, Material, Slot, TextureSlot};
use crate::texture::Texture;
use crate::{files, images, Budget, LoadError};

/// The material loader handed to `tobj`, with what it learnt on the way.
pub(super) struct MtlLibs<'a> {
    /// Canonical model folder: nothing outside it is read.
    pub root: &'a Path,
    pub budget: &'a Budget,
    pub warnings: RefCell<Vec<String>>,
    /// Folder of the library each material came from, in `tobj`'s material order.
    pub dirs: RefCell<Vec<PathBuf>>,
    /// A budget overrun inside the loader; reported after `tobj` returns.
    pub fatal: RefCell<Option<LoadError>>,
}

impl MtlLibs<'_> {
    /// Loads the library named by an `mtllib` line. Failures become warnings and an empty
    /// library, so the model still loads with default materials.
    pub fn load(&self, reference: &Path) -> tobj::MTLLoadResult {
        let mut library: tobj::MTLLoadResult = Ok(Default::default());
        let Ok((materials, names)) = &mut library else {
            return library;
        };
        for path in self.candidates(reference) {
            let Ok((mats, map)) = self.load_one(&path) else {
                continue;
            };
            let offset = materials.len();
            names.extend(map.into_iter().map(|(k, v)| (k, v + offset)));
            let dir = path.parent().unwrap_or(self.root).to_owned();
            self.dirs
                .borrow_mut()
                .extend(std::iter::repeat_n(dir, mats.len()));
            materials.extend(mats);
        }
        library
    }

    /// The files an `mtllib` line names: the whole text, or else each word of it
    /// (`mtllib a.mtl b.mtl`). Unresolvable names become warnings.
    fn candidates(&self, reference: &Path) -> Vec<PathBuf> {
        match files::resolve_inside(self.root, self.root, reference) {
            Ok(p) => vec![p],
            Err(reason) => {
                let text = reference.to_string_lossy();
                let words: Vec<&str> = text.split_whitespace().collect();
                let parts: Vec<PathBuf> = words
                    .iter()
                    .filter_map(|w| files::resolve_inside(self.root, self.root, Path::new(w)).ok())
                    .collect();
                if words.len() < 2 || parts.len() != words.len() {
                    self.warn(format!("material library not loaded: {reason}"));
                }
                if words.len() < 2 {
                    Vec::new()
                } else {
                    parts
                }
            }
        }
    }

    /// One library file; `Err` after a warning (or a fatal budget error).
    fn load_one(&self, path: &Path) -> tobj::MTLLoadResult {
        let skip = Err(tobj::LoadError::GenericFailure);
        if self.fatal.borrow().is_some() {
            return skip;
        }
        let bytes = match files::read_capped(path, self.budget, "material library") {
            Ok(b) => b,
            Err(e @ LoadError::TooLarge { .. }) => {
                *self.fatal.borrow_mut() = Some(e);
                return skip;
            }
            Err(e) => {
                self.warn(format!("material library not loaded: {e}"));
                return skip;
            }
        };
        let name = path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let text = crate::files::text(&bytes);
        let (clean, warnings) = sanitize(&name, &text);
        self.warnings.borrow_mut().extend(warnings);
        let library = tobj::load_mtl_buf(&mut clean.as_bytes());
        if let Err(e) = &library {
            self.warn(format!("{name}: material library not loaded: {e}"));
        }
        library
    }

    fn warn(&self, w: String) {
        self.warnings.borrow_mut().push(w);
    }
}

/// Checks every MTL line `tobj` would parse and blanks the ones it would choke on (with a
/// warning naming `name` and the line): colours with 2 numbers (which make tobj 4.0.5
/// panic), spectral/XYZ colours, missing or non-finite numbers, empty texture names.
/// `Kd r` is expanded to `Kd r r r` as the MTL format defines.
pub(super) fn sanitize(name: &str, text: &str) -> (String, Vec<String>) {
    let mut out = String::with_capacity(text.len());
    let mut warnings = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let keyword = words.next().unwrap_or("");
        let args: Vec<&str> = words.take(4).collect();
        let num = |t: &&str| t.parse::<f32>().ok().filter(|x| x.is_finite());
        let problem = match keyword {
            "Ka" | "Kd" | "Ks" | "Ke" => {
                let nums: Option<Vec<f32>> = args.iter().take(3).map(num).collect();
                match nums.as_deref() {
                    Some([_, _, _]) => None,
                    Some([r]) if args.len() == 1 => {
                        out.push_str(&format!("{keyword} {r} {r} {r}\n"));
                        continue;
                    }
                    _ => Some(format!(
                        "`{keyword}` needs 3 finite numbers, found `{}`",
                        args.join(" ")
                    )),
                }
            }
            "Ns" | "Ni" | "d" | "Tr" => match args.first().and_then(num) {
                Some(_) => None,
                None => Some(format!("`{keyword}` needs a finite number")),
            },
            "illum" => match args.first().map(|t| t.parse::<u8>()) {
                Some(Ok(_)) => None,
                _ => Some("`illum` needs a model number 0-255".to_string()),
            },
            k if (k.starts_with("map_") || k == "bump") && args.is_empty() => {
                Some(format!("`{k}` without a file name"))
            }
            "newmtl" if args.is_empty() => {
                out.push_str("newmtl unnamed\n");
                warnings.push(format!(
                    "{name}:{}: `newmtl` without a name; called 'unnamed'",
                    i + 1
                ));
                continue;
            }
            _ => None,
        };
        match problem {
            Some(p) => {
                warnings.push(format!("{name}:{}: {p}; line ignored", i + 1));
                out.push('\n');
            }
            None => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    (out, warnings)
}

/// Converts `tobj` materials, decoding each `map_Kd` and `map_Ks` texture once (by
/// canonical path).
pub(super) struct Converter<'a> {
    /// Canonical model folder: textures outside it are refused.
    root: &'a Path,
    budget: &'a Budget,
    /// Checked before each texture is read and decoded.
    tracker: &'a Tracker,
    /// The decoded textures, in scene order.
    pub textures: Vec<Arc<Texture>>,
    pub warnings: Vec<String>,
    /// Texture index by canonical path and colour space (`None` = failed, already warned
    /// about).
    by_path: HashMap<(PathBuf, bool), Option<usize>>,
}

impl<'a> Converter<'a> {
    pub fn new(root: &'a Path, budget: &'a Budget, tracker: &'a Tracker) -> Self {
        Self {
            root,
            budget,
            tracker,
            textures: Vec::new(),
            warnings: Vec::new(),
            by_path: HashMap::new(),
        }
    }

    /// Converts a material read from folder `dir`. Shininess is clamped to the textbook's range
    /// 1..=2000; roughness is derived from it as (2 / (Ns + 2))^(1/4) (Blinn-Phong to GGX);
    /// `d` < 1 (or `Tr` > 0) makes the material blended.
    pub fn convert(&mut self, m: &tobj::Material, dir: &Path) -> Result<Material, LoadError> {
        let d = Material::default();
        let rgb = |c: Option<[f32; 3]>, default: Vec3| c.map_or(default, Vec3::from);
        let tr = m
            .unknown_param
            .get("Tr")
            .and_then(|t| t.trim().parse::<f32>().ok());
        let alpha = m.dissolve.or(tr.map(|t| 1.0 - t)).filter(|a| a.is_finite());
        let alpha = alpha.unwrap_or(1.0).clamp(0.0, 1.0);
        let shininess = m.shininess.unwrap_or(d.shininess).clamp(1.0, 2000.0);
        let mut material = Material {
            name: m.name.clone(),
            base_color: rgb(m.diffuse, d.base_color.truncate()).extend(alpha),
            ambient: rgb(m.ambient, d.ambient),
            specular: rgb(m.specular, d.specular),
            shininess,
            emissive: rgb(m.emissive, d.emissive),
            metallic: 0.0,
            roughness: libm::powf(2.0 / (shininess + 2.0), 0.25),
            alpha_mode: if alpha < 1.0 {
                AlphaMode::Blend
            } else {
                AlphaMode::Opaque
            },
            double_sided: false,
            ..Material::default()
        };
        // `map_Kd` the base colour, `map_Ks` the gloss map (multiplying `Ks` per pixel),
        // `map_Ke` the emissive map, `bump` / `map_Bump` a height map (`-bm` its scale),
        // `norm` a tangent-space normal map.
        let unknown = |k: &str| m.unknown_param.get(k);
        let maps = [
            (Slot::BaseColor, m.diffuse_texture.as_ref()),
            (Slot::Specular, m.specular_texture.as_ref()),
            (Slot::Emissive, unknown("map_Ke")),
            (Slot::Bump, m.normal_texture.as_ref()),
            (Slot::Normal, unknown("norm")),
        ];
        for (slot, value) in maps {
            let Some(value) = value else { continue };
            if let Some(texture) = self.texture(value, dir, &m.name, slot.srgb())? {
                *material.slot_mut(slot) = Some(TextureSlot {
                    scale: option_number(value, "-bm").unwrap_or(1.0),
                    ..TextureSlot::new(texture)
                });
            }
        }
        Ok(material)
    }

    /// The texture for a map value of `material` (`map_Kd`, `bump`, ...), decoded on first
    /// use for a slot of colour space `srgb`. `value` may carry options before the file name
    /// (`-s 1 1 1 wood.png`): if the whole value names no file, its last word is tried.
    fn texture(
        &mut self,
        value: &str,
        dir: &Path,
        material: &str,
        srgb: bool,
    ) -> Result<Option<usize>, LoadError> {
        let resolve = |name: &str| files::resolve_inside(self.root, dir, Path::new(name));
        let resolved = resolve(value).or_else(|reason| {
            let last = value.split_whitespace().last().filter(|l| *l != value);
            last.ok_or(reason.clone())
                .and_then(|l| resolve(l).map_err(|_| reason))
        });
        let path = match resolved {
            Ok(p) => p,
            Err(reason) => {
                let warning = format!("material '{material}': texture not loaded: {reason}");
                self.warnings.push(warning);
                return Ok(None);
            }
        };
        let key = (path, srgb);
        if let Some(&cached) = self.by_path.get(&key) {
            return Ok(cached);
        }
        let path = &key.0;
        let name = path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        self.tracker.check()?;
        let decoded = match files::read_capped(path, self.budget, "texture") {
            Ok(bytes) => images::decode(&bytes, &name, self.budget, srgb),
            Err(e @ LoadError::TooLarge { .. }) => return Err(e),
            Err(e) => Err(images::DecodeError::Invalid(e.to_string())),
        };
        let index = match decoded {
            Ok(t) => {
                self.textures.push(Arc::new(t));
                Some(self.textures.len() - 1)
            }
            Err(images::DecodeError::Budget(e)) => return Err(e),
            Err(images::DecodeError::Invalid(reason)) => {
                let warning = format!("material '{material}': texture {name} not loaded: {reason}");
                self.warnings.push(warning);
                None
            }
        };
        self.by_path.insert(key, index);
        Ok(index)
    }
}

/// The number after option `flag` in a map value (`-bm 0.5 bumps.png` gives 0.5 for
/// `-bm`), if it is there and finite.
fn option_number(value: &str, flag: &str) -> Option<f32> {
    let mut words = value.split_whitespace();
    words.find(|w| *w == flag)?;
    words
        .next()
        .and_then(|w| w.parse::<f32>().ok())
        .filter(|v| v.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sanitize_blanks_lines_tobj_would_panic_on() {
        let (clean, w) = sanitize(
            "kd2.mtl",
            "newmtl m\nKd 1 1\nKs 0.5\nNs -1e999\nmap_Kd\nillum 999\n",
        );
        assert_eq!(clean, "newmtl m\n\nKs 0.5 0.5 0.5\n\n\n\n");
        assert_eq!(w.len(), 4, "{w:?}");
        assert!(
            w[0].starts_with("kd2.mtl:2: `Kd` needs 3 finite numbers, found `1 1`"),
            "{w:?}"
        );
        let (mats, _) = tobj::load_mtl_buf(&mut clean.as_bytes()).unwrap();
        assert_eq!(mats[0].specular, Some([0.5; 3]));
    }
}
