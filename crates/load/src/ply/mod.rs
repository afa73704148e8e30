//! PLY (Stanford polygon file format) meshes, ASCII and binary (little- and big-endian),
//! into a [`Scene`]: one mesh, placed by one identity instance, with the default material.
//!
//! - **Header**: `ply`, `format ascii|binary_little_endian|binary_big_endian 1.0`, then
//!   `element NAME COUNT` lines each followed by its `property TYPE NAME` and
//!   `property list COUNT_TYPE ITEM_TYPE NAME` lines, `comment` and `obj_info` lines
//!   anywhere, and `end_header`. Types: `char uchar short ushort int uint float double`
//!   and `int8 uint8 int16 uint16 int32 uint32 float32 float64`. Header errors name the
//!   line.
//! - **Body**: the elements in header order. ASCII has one element per line (blank lines
//!   are skipped); errors name the line. Binary errors name the element and its index
//!   (counting from 0, as vertex indices do). Elements other than `vertex` and `face` are
//!   skipped (in binary by their sizes, lists included), and so are unknown properties.
//! - **`vertex`**: `x y z` (required); `nx ny nz` (the file's normals, per vertex, used
//!   as they are); `red green blue` and `alpha` (also `diffuse_red` ...); `u v`, `s t`,
//!   `texture_u texture_v` or `texture_s texture_t` (UV set 0, flipped to the glTF
//!   convention `v' = 1 - v` as OBJ's are: PLY writers put the origin at the bottom left).
//! - **`face`**: a `vertex_indices` (or `vertex_index`) list per face, polygons of any
//!   size; every index is checked against the vertex count. Face colours and per-corner
//!   `texcoord` lists are not read.
//!
//! **Colours.** Integer colours (`uchar`, as nearly every writer stores them, or
//! `ushort`) are taken as sRGB-coded, the way 8- and 16-bit colour textures are in this
//! crate: scaled to 0..1 and decoded to linear light (`uchar` through an exact 256-entry
//! table). Float colours are taken as linear, as the OBJ loader takes the float colours of
//! `v` lines. (glTF's normalised `COLOR_0` is not decoded: its specification defines it
//! as linear; PLY has no such rule, and its 8-bit colours come from cameras and scanners,
//! sRGB-coded.) Alpha is only scaled.
//!
//! **Welding.** A PLY is indexed already, so its vertices are kept as the file has them:
//! a writer that split a vertex (at a UV seam, a colour boundary, a crease with its own
//! normals) meant it. The exception is a triangle soup (no vertex used by two face
//! corners, as converters from STL write) without normals: its vertices are welded by
//! bit-identical position, as STL's are, so that normals can be averaged across faces;
//! its colours and UVs become per-corner channels, so nothing read is lost.
//!
//! Without `nx ny nz`, normals are averaged with the crease split
//! ([`NormalPolicy::Average`], as for an OBJ without normals). A file with vertices but no
//! faces (a point cloud) is refused: points are not drawn yet.
//!
//! **Bounded work.** Before anything is allocated, every element's count times the least
//! size of one of its entries (1 byte per binary list count, 2 characters per ASCII value)
//! is checked against the bytes after the header, and the vertex arrays are charged to the
//! load's [`Budget`]; a list's count is checked against the bytes left before its items
//! are read, corners are charged as they grow, and nothing is sized by a count alone.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::progress::{Stage, Tracker};
use super::{files, mesh_bytes, retain_facets, Budget, LoadError, LoadOptions};
use crate::mesh::{Channel, Mesh, MeshData, MeshError, NormalPolicy};
use crate::scene::{Instance, LoadReport, Scene, Style};

mod header;
use header::*;
mod body;
use body::*;

/// Where reading ends on the progress bar (the rest is parsing and building the mesh).
const READ_UNTIL: f32 = 0.1;
const PARSE_UNTIL: f32 = 0.5;

/// Why a PLY file could not be loaded. Messages are one line starting with the path.
#[derive(Debug, thiserror::Error)]
pub enum PlyError {
    /// A header line, or an ASCII body line, that cannot be read (`line` is 1-based).
    #[error("{path}:{line}: {message}")]
    Syntax {
        path: PathBuf,
        line: usize,
        message: String,
    },
    /// A binary body that cannot be read (the message names the element and its index),
    /// or a file that is not a PLY file or has nothing to draw.
    #[error("{path}: {message}")]
    Format { path: PathBuf, message: String },
    #[error("{path}: {source}")]
    Mesh { path: PathBuf, source: MeshError },
}

/// A scalar property type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(word: &str) -> Option<Scalar> {
        Some(match word {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    /// Bytes in binary.
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_float(self) -> bool {
        matches!(self, Scalar::F32 | Scalar::F64)
    }

    /// The largest value (integers), by which integer colours are scaled to 0..1.
    fn max(self) -> f64 {
        match self {
            Scalar::I8 => 127.0,
            Scalar::U8 => 255.0,
            Scalar::I16 => 32767.0,
            Scalar::U16 => 65535.0,
            Scalar::I32 => 2_147_483_647.0,
            Scalar::U32 => 4_294_967_295.0,
            Scalar::F32 | Scalar::F64 => 1.0,
        }
    }
}

/// A property: one scalar, or a list of `item`s preceded by its `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Clone, Debug)]
struct Property {
    name: String,
    kind: Kind,
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: u64,
    props: Vec<Property>,
    /// The header line of `element`.
    line: usize,
}

impl Element {
    /// The least bytes one entry takes: binary sizes (a list: its count alone), or for
    /// ASCII one character per value and one separator between values.
    fn min_bytes(&self, ascii: bool) -> u64 {
        if ascii {
            (2 * self.props.len() as u64).saturating_sub(1)
        } else {
            self.props
                .iter()
                .map(|p| match p.kind {
                    Kind::Scalar(t) => t.size() as u64,
                    Kind::List { count, .. } => count.size() as u64,
                })
                .sum()
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Ascii,
    Little,
    Big,
}

struct Header {
    format: Format,
    elements: Vec<Element>,
    /// Byte offset of the body.
    body: usize,
    /// Lines in the header (the body's first line is `lines + 1`).
    lines: usize,
}

/// Loads a PLY file, reporting to `tracker`.
pub(crate) fn load_ply(
    path: &Path,
    opts: &LoadOptions,
    tracker: &Tracker,
) -> Result<Scene, LoadError> {
    let budget = Budget::new(path, opts.max_bytes);
    let bytes = files::read_model(path, &budget, "PLY file", tracker, READ_UNTIL)?;
    let syntax = |line: usize, message: String| {
        LoadError::from(PlyError::Syntax {
            path: path.to_owned(),
            line,
            message,
        })
    };
    let format_error = |message: String| {
        LoadError::from(PlyError::Format {
            path: path.to_owned(),
            message,
        })
    };
    let header = parse_header(&bytes).map_err(|(line, message)| match line {
        0 => format_error(message),
        _ => syntax(line, message),
    })?;
    let body = bytes.get(header.body..).unwrap_or_default();
    let ascii = header.format == Format::Ascii;
    for e in &header.elements {
        let least = e.min_bytes(ascii);
        if e.count.saturating_mul(least) > body.len() as u64 {
            return Err(syntax(
                e.line,
                format!(
                    "element `{}` declares {} entries of at least {least} bytes each, but only {} bytes follow the header",
                    e.name,
                    e.count,
                    body.len()
                ),
            ));
        }
    }
    let layout = Layout::new(&header.elements).map_err(|(line, message)| syntax(line, message))?;
    let vertex_count = header.elements[layout.vertex].count;
    let face_count = layout.face.map_or(0, |f| header.elements[f].count);
    if face_count == 0 && vertex_count > 0 {
        return Err(format_error(format!(
            "{vertex_count} vertices and no faces: point clouds are not drawn yet"
        )));
    }
    // Fits: the count check above bounds it by the file's length.
    let (vertices, faces) = (vertex_count as usize, face_count as usize);
    let per_vertex = 12
        + if layout.normals { 12 } else { 0 }
        + if layout.colors { 16 } else { 0 }
        + if layout.uvs { 8 } else { 0 };
    if vertex_count >= u64::from(u32::MAX) {
        return Err(format_error(format!(
            "{vertex_count} vertices: more than a mesh can index"
        )));
    }
    let arrays = vertex_count
        .saturating_mul(per_vertex)
        .saturating_add(face_count.saturating_mul(16));
    budget.charge(arrays, || {
        format!("{vertex_count} vertices and {face_count} faces")
    })?;
    tracker.begin(Stage::Parsing, PARSE_UNTIL, body.len() as u64)?;
    let mut sink = Sink {
        layout: &layout,
        vertex_count,
        positions: Vec::with_capacity(vertices),
        normals: Vec::with_capacity(if layout.normals { vertices } else { 0 }),
        colors: Vec::with_capacity(if layout.colors { vertices } else { 0 }),
        uvs: Vec::with_capacity(if layout.uvs { vertices } else { 0 }),
        corners: Vec::with_capacity(faces.saturating_mul(3)),
        sizes: Vec::with_capacity(faces),
        charged_corners: face_count.saturating_mul(3),
        budget: &budget,
        warnings: Vec::new(),
    };
    let format = match header.format {
        Format::Ascii => {
            read_ascii(path, body, &header, &mut sink, tracker)?;
            "PLY (ASCII)"
        }
        Format::Little | Format::Big => {
            let big = header.format == Format::Big;
            let left = read_binary(path, body, big, &header, &mut sink, tracker)?;
            if left > 0 {
                sink.warnings
                    .push(format!("{left} bytes after the last element ignored"));
            }
            if big {
                "PLY (binary, big-endian)"
            } else {
                "PLY (binary, little-endian)"
            }
        }
    };
    drop(bytes);
    let name = path
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let mut scene = Scene {
        report: LoadReport {
            file: path.display().to_string(),
            format: format.into(),
            ..LoadReport::default()
        },
        ..Scene::default()
    };
    scene.report.warnings.append(&mut sink.warnings);
    scene
        .report
        .warnings
        .extend(layout.warnings.iter().cloned());
    let (v, c, f) = (
        sink.positions.len() as u64,
        sink.corners.len() as u64,
        sink.sizes.len() as u64,
    );
    budget.charge(mesh_bytes(v, c, f), || {
        format!("a mesh of {v} vertices and {f} faces")
    })?;
    tracker.begin(Stage::Geometry, 1.0, c)?;
    let (mut data, welded) = sink.into_mesh_data(name.clone());
    tracker.check()?;
    let dropped = retain_facets(&mut data);
    scene.report.warnings.extend(dropped.warnings("PLY"));
    if data.corners.is_empty() {
        scene.report.warnings.push("no faces to draw".into());
        return Ok(scene);
    }
    if let Some((before, after)) = welded {
        scene.report.generated.push(format!(
            "a triangle soup (no vertex shared by two corners): {before} vertices welded into {after}"
        ));
    }
    if data.normals.is_none() {
        scene.report.generated.push(format!(
            "normals averaged (crease {})",
            opts.normals
                .crease_degrees
                .map_or("none".into(), |c| format!("{c} degrees")),
        ));
        tracker.label(Stage::Normals)?;
    }
    let mesh =
        Mesh::new(data, NormalPolicy::Average(opts.normals)).map_err(|source| PlyError::Mesh {
            path: path.to_owned(),
            source,
        })?;
    tracker.advance(c)?;
    scene.instances.push(Instance {
        mesh: 0,
        world: Mat4::IDENTITY,
        name,
        style: Style::Inherit,
        node: None,
        skin: None,
        copies: None,
    });
    scene.meshes.push(mesh);
    Ok(scene)
}

/// Where a vertex property goes: an index into a row of [`SLOTS`] values.
const X: usize = 0;
const NX: usize = 3;
const RED: usize = 6;
const ALPHA: usize = 9;
const U: usize = 10;
const V: usize = 11;
/// Read and thrown away.
const SKIP: usize = 12;
/// The face's index list.
const INDICES: usize = 13;
const SLOTS: usize = 14;

/// Which element is which, and where each property of the vertex and face elements goes.
struct Layout {
    vertex: usize,
    face: Option<usize>,
    /// Per element, per property: its slot.
    slots: Vec<Vec<usize>>,
    normals: bool,
    colors: bool,
    uvs: bool,
    /// The types of red, green, blue and alpha (`None` where absent).
    color_types: [Option<Scalar>; 4],
    warnings: Vec<String>,
}

impl Layout {
    fn new(elements: &[Element]) -> Result<Layout, (usize, String)> {
        let find = |name: &str| -> Result<Option<usize>, (usize, String)> {
            let mut found = elements.iter().enumerate().filter(|(_, e)| e.name == name);
            let first = found.next().map(|(i, _)| i);
            match found.next() {
                Some((_, e)) => Err((e.line, format!("a second `{name}` element"))),
                None => Ok(first),
            }
        };
        let Some(vertex) = find("vertex")? else {
            return Err((0, "the header declares no `vertex` element".into()));
        };
        let face = find("face")?;
        let mut slots: Vec<Vec<usize>> =
            elements.iter().map(|e| vec![SKIP; e.props.len()]).collect();
        let mut color_types = [None; 4];
        let mut present = [false; SKIP];
        for (p, slot) in elements[vertex].props.iter().zip(&mut slots[vertex]) {
            let Kind::Scalar(t) = p.kind else { continue };
            let s = match p.name.as_str() {
                "x" => X,
                "y" => X + 1,
                "z" => X + 2,
                "nx" => NX,
                "ny" => NX + 1,
                "nz" => NX + 2,
                "red" | "diffuse_red" => RED,
                "green" | "diffuse_green" => RED + 1,
                "blue" | "diffuse_blue" => RED + 2,
                "alpha" | "diffuse_alpha" => ALPHA,
                "u" | "s" | "texture_u" | "texture_s" => U,
                "v" | "t" | "texture_v" | "texture_t" => V,
                _ => continue,
            };
            if present[s] {
                continue; // The first of two spellings wins.
            }
            present[s] = true;
            *slot = s;
            if (RED..=ALPHA).contains(&s) {
                color_types[s - RED] = Some(t);
            }
        }
        let e = &elements[vertex];
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            if !present[X + k] {
                return Err((
                    e.line,
                    format!("element `vertex` has no number property `{axis}`"),
                ));
            }
        }
        let mut warnings = Vec::new();
        let mut all = |range: std::ops::Range<usize>, what: &str, slots: &mut Vec<usize>| {
            let n = range.clone().filter(|&s| present[s]).count();
            if n > 0 && n < range.len() {
                warnings.push(format!("vertex {what} incomplete: not read"));
                for s in slots.iter_mut().filter(|s| range.contains(s)) {
                    *s = SKIP;
                }
            }
            n == range.len()
        };
        let normals = all(NX..NX + 3, "normals (nx, ny, nz)", &mut slots[vertex]);
        let colors = all(
            RED..RED + 3,
            "colours (red, green, blue)",
            &mut slots[vertex],
        );
        let uvs = all(U..V + 1, "texture coordinates (u, v)", &mut slots[vertex]);
        if !colors {
            for s in slots[vertex].iter_mut().filter(|s| **s == ALPHA) {
                *s = SKIP;
            }
        }
        if let Some(f) = face {
            let e = &elements[f];
            let list = e.props.iter().position(|p| {
                matches!(p.kind, Kind::List { .. })
                    && (p.name == "vertex_indices" || p.name == "vertex_index")
            });
            match list.map(|i| (i, e.props[i].kind)) {
                Some((i, Kind::List { item, .. })) if !item.is_float() => slots[f][i] = INDICES,
                Some(_) => {
                    return Err((
                        e.line,
                        "face vertex indices must have an integer type".into(),
                    ))
                }
                None if e.count == 0 => {}
                None => return Err((e.line, "element `face` has no `vertex_indices` list".into())),
            }
        }
        Ok(Layout {
            vertex,
            face,
            slots,
            normals,
            colors,
            uvs,
            color_types,
            warnings,
        })
    }
}

/// What the body is read into.
struct Sink<'a> {
    layout: &'a Layout,
    vertex_count: u64,
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    colors: Vec<Vec4>,
    uvs: Vec<Vec2>,
    corners: Vec<u32>,
    sizes: Vec<u32>,
    /// Corners charged to the budget so far.
    charged_corners: u64,
    budget: &'a Budget,
    warnings: Vec<String>,
}

impl Sink<'_> {
    /// Stores one vertex row.
    fn vertex(&mut self, row: &[f64; SLOTS], table: &[f32; 256]) {
        let v3 = |s: usize| Vec3::new(row[s] as f32, row[s + 1] as f32, row[s + 2] as f32);
        self.positions.push(v3(X));
        if self.layout.normals {
            self.normals.push(v3(NX));
        }
        if self.layout.colors {
            let types = self.layout.color_types;
            let c = |k: usize| {
                let (t, v) = (types[k].unwrap_or(Scalar::F32), row[RED + k]);
                match t {
                    _ if t.is_float() => v as f32,
                    Scalar::U8 => table[v.clamp(0.0, 255.0) as usize],
                    _ if k == 3 => (v / t.max()).clamp(0.0, 1.0) as f32,
                    _ => crate::color::srgb_decode((v / t.max()).clamp(0.0, 1.0)) as f32,
                }
            };
            let alpha = match types[3] {
                None => 1.0,
                Some(Scalar::U8) => (row[ALPHA].clamp(0.0, 255.0) / 255.0) as f32,
                Some(_) => c(3),
            };
            self.colors.push(Vec4::new(c(0), c(1), c(2), alpha));
        }
        if self.layout.uvs {
            self.uvs.push(Vec2::new(row[U] as f32, 1.0 - row[V] as f32));
        }
    }

    /// Checks a vertex index, or says why it is out of range.
    fn index(&self, v: i64) -> Result<u32, String> {
        if v >= 0 && (v as u64) < self.vertex_count {
            Ok(v as u32)
        } else {
            Err(format!(
                "vertex index {v} is out of range ({} vertices)",
                self.vertex_count
            ))
        }
    }

    /// Charges the corners beyond what was charged, in doubling steps.
    fn charge_corners(&mut self) -> Result<(), LoadError> {
        let have = self.corners.len() as u64;
        if have > self.charged_corners {
            let more = have.max(self.charged_corners);
            self.budget
                .charge(more * 4, || format!("{} face corners", have + more))?;
            self.charged_corners += more;
        }
        Ok(())
    }

    /// The mesh data, and `(before, after)` vertex counts if a triangle soup was welded.
    fn into_mesh_data(self, name: String) -> (MeshData, Option<(usize, usize)>) {
        let facet_sizes = (!self.sizes.iter().all(|&n| n == 3)).then_some(self.sizes);
        let mut data = MeshData {
            name,
            positions: self.positions,
            corners: self.corners,
            facet_sizes,
            normals: self
                .layout
                .normals
                .then(|| Channel::per_vertex(self.normals)),
            uvs: if self.layout.uvs {
                vec![Channel::per_vertex(self.uvs)]
            } else {
                Vec::new()
            },
            colors: self.layout.colors.then(|| Channel::per_vertex(self.colors)),
            tangents: None,
            material: None,
        };
        let welded = (data.normals.is_none() && is_soup(&data)).then(|| weld_soup(&mut data));
        (data, welded)
    }
}

#[cfg(test)]
mod tests;
