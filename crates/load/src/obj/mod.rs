//! Wavefront OBJ + MTL through `tobj`, into a [`Scene`].
//!
//! Polygons are kept as facets (no triangulation): position indices are the topology, and
//! normals and texture coordinates become per-corner-indexed [`Channel`]s, so a UV seam or
//! a crease in the file does not cut the mesh. Every `o`/`g` group (and every material
//! change inside one, as `tobj` splits them) becomes one mesh, placed by one instance with
//! an identity world matrix. Texture `v` is flipped (v' = 1 - v) into the crate's top-left
//! UV convention. Files without normals get averaged normals ([`NormalPolicy::Average`]).
//! Points and lines (`p`, `l`) are read by the pre-scan ([`scan`]) and become one mesh per
//! run under the same `o`/`g` and `usemtl` (no facets; unlit), drawn with a point size and
//! line width in pixels; the fast path leaves files that have them to the sequential path.
//!
//! Before `tobj` runs, [`scan`] checks every line (so errors carry line numbers) and
//! rewrites what `tobj` would misread; [`mtl`] does the same for material libraries.

use std::borrow::Cow;
use std::collections::HashSet;
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::progress::{Stage, Tracker};
use super::{files, mesh_bytes, retain_facets, Budget, Dropped, LoadError, LoadOptions};
use crate::mesh::{Channel, Mesh, MeshData, MeshError, NormalPolicy};
use crate::scene::{Instance, LoadReport, Scene, Style};

mod fast;
mod mtl;
mod reader;
mod scan;

/// Where each stage ends on the progress bar: the shares of a load's time measured on a
/// 2-million-triangle grid (75 MB) and on the Stanford bunny (2.4 MB), which agree within
/// a few percent: reading and UTF-8 checking 7%, the pre-scan 23%, `tobj` 47%, textures
/// (none there) and meshes 23%.
const READ_UNTIL: f32 = 0.07;
/// The fast path: parsing the chunks (the joining and assembling of the models, which have
/// no checkpoint inside, follow at this mark).
pub(super) const FAST_UNTIL: f32 = 0.5;
/// The sequential path (a file the fast path leaves).
const SCAN_UNTIL: f32 = 0.30;
const TOBJ_UNTIL: f32 = 0.77;
const TEXTURES_UNTIL: f32 = 0.78;

/// Why an OBJ file could not be loaded. Messages are one line starting with the path.
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    /// A line that cannot be read (`line` is 1-based).
    #[error("{path}:{line}: {message}")]
    Syntax {
        path: PathBuf,
        line: usize,
        message: String,
    },
    /// A face corner refers to a `kind` ("vertex", "texture coordinate", "normal") that is
    /// not defined before the face; `count` were.
    #[error("{path}:{line}: face refers to {kind} {index}, but only {count} are defined before this line")]
    Index {
        path: PathBuf,
        line: usize,
        kind: &'static str,
        index: i64,
        count: u64,
    },
    /// `tobj` rejected the (pre-checked) text.
    #[error("{path}: {message}")]
    Parse { path: PathBuf, message: String },
    /// A group's data could not become a mesh.
    #[error("{path}: object '{object}': {source}")]
    Mesh {
        path: PathBuf,
        object: String,
        source: MeshError,
    },
}

/// Loads an OBJ file (and its MTL libraries and `map_Kd`/`map_Ks` textures), reporting to
/// `tracker`.
pub(crate) fn load_obj(
    path: &Path,
    opts: &LoadOptions,
    tracker: &Tracker,
) -> Result<Scene, LoadError> {
    let budget = Budget::new(path, opts.max_bytes);
    let root = files::model_folder(path)?;
    let bytes = files::read_model(path, &budget, "OBJ file", tracker, READ_UNTIL)?;
    let report = LoadReport {
        file: path.display().to_string(),
        format: "OBJ".into(),
        ..LoadReport::default()
    };
    let mut scene = Scene {
        report,
        ..Scene::default()
    };
    let text = files::text(&bytes);
    if let Cow::Owned(t) = &text {
        budget.charge(t.len() as u64, || "UTF-8 copy of the OBJ text".into())?;
        let note = "file is not valid UTF-8: invalid bytes replaced";
        scene.report.warnings.push(note.into());
    }
    let libs = mtl::MtlLibs {
        root: &root,
        budget: &budget,
        warnings: Default::default(),
        dirs: Default::default(),
        fatal: Default::default(),
    };
    tracker.begin(Stage::Parsing, FAST_UNTIL, text.len() as u64)?;
    let (models, materials, mut scan) = match fast::parse(&text, &budget, tracker)? {
        Some(mut joined) => {
            charge_and_note(&mut joined.scan, &budget, &mut scene.report)?;
            let (models, materials, scan) = joined.assemble(|p| libs.load(p));
            tracker.check()?;
            (models, Ok(materials), scan)
        }
        None => sequential(path, &text, &budget, tracker, &libs, &mut scene.report)?,
    };
    if let Some(e) = libs.fatal.take() {
        return Err(e);
    }
    scene.report.warnings.extend(libs.warnings.take());
    let materials = materials.unwrap_or_default();
    let dirs = libs.dirs.take();
    let folders = Folders {
        root: &root,
        dirs: &dirs,
    };
    add_materials(&materials, folders, &budget, tracker, &scan, &mut scene)?;
    let strokes = stroke_meshes(path, &text, &mut scan, &materials, opts, &budget)?;
    add_meshes(
        path,
        models,
        opts,
        scan.positions,
        tracker,
        strokes,
        &mut scene,
    )?;
    Ok(scene)
}

/// One mesh per run of `p` and `l` elements ([`scan::Strokes`]): the vertices they use
/// (in order of first use), no facets, the points and segments, the material of the
/// `usemtl` in force; each with its line in the report. Unlit: OBJ elements carry no
/// normals.
fn stroke_meshes(
    path: &Path,
    text: &str,
    scan: &mut scan::Scan,
    materials: &[tobj::Material],
    opts: &LoadOptions,
    budget: &Budget,
) -> Result<Vec<(Mesh, String)>, LoadError> {
    if scan.strokes.is_empty() {
        return Ok(Vec::new());
    }
    let items: u64 = scan
        .strokes
        .iter()
        .map(|g| (g.points.len() + 2 * g.lines.len()) as u64)
        .sum();
    budget.charge(scan.positions.saturating_mul(28) + items * 40, || {
        format!("points and lines ({items} vertex references)")
    })?;
    let (positions, colors) = scan::file_vertices(text);
    let mut out = Vec::new();
    for g in std::mem::take(&mut scan.strokes) {
        let mut first_use = std::collections::HashMap::new();
        let mut used = Vec::new();
        let mut local = |v: u32| {
            *first_use.entry(v).or_insert_with(|| {
                used.push(v);
                used.len() as u32 - 1
            })
        };
        let points: Vec<u32> = g.points.iter().map(|&v| local(v)).collect();
        let lines: Vec<[u32; 2]> = g.lines.iter().map(|l| l.map(&mut local)).collect();
        let at = |v: &u32| positions.get(*v as usize).copied().unwrap_or(Vec3::NAN);
        let data = MeshData {
            name: g.object.clone(),
            positions: used.iter().map(at).collect(),
            colors: (colors.len() == positions.len())
                .then(|| Channel::per_vertex(used.iter().map(|&v| colors[v as usize]).collect())),
            material: g
                .material
                .as_deref()
                .and_then(|name| materials.iter().position(|m| m.name == name)),
            ..MeshData::default()
        };
        let mesh_error = |source| ObjError::Mesh {
            path: path.to_owned(),
            object: g.object.clone(),
            source,
        };
        let mut mesh = Mesh::new(data, NormalPolicy::Average(opts.normals)).map_err(mesh_error)?;
        let note = format!(
            "object '{}' (from line {}): {} points, {} line segments, unlit (no normals)",
            g.object,
            g.line,
            points.len(),
            lines.len()
        );
        mesh.set_strokes(points, lines).map_err(mesh_error)?;
        out.push((mesh, note));
    }
    Ok(out)
}

/// Models, materials (or why there are none) and the pre-scan's findings.
type Parsed<'a> = (
    Vec<tobj::Model>,
    Result<Vec<tobj::Material>, tobj::LoadError>,
    scan::Scan<'a>,
);

/// The sequential path: the pre-scan (which words every error with its line), then
/// `tobj`.
fn sequential<'a>(
    path: &Path,
    text: &'a str,
    budget: &Budget,
    tracker: &Tracker,
    libs: &mtl::MtlLibs,
    report: &mut LoadReport,
) -> Result<Parsed<'a>, LoadError> {
    tracker.begin(Stage::Parsing, SCAN_UNTIL, text.len() as u64)?;
    let mut scan = scan::scan(path, text, tracker)?;
    charge_and_note(&mut scan, budget, report)?;
    let tobj_opts = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ..Default::default()
    };
    tracker.begin(Stage::Parsing, TOBJ_UNTIL, scan.text.len() as u64)?;
    let mut reader = reader::Checked::new(scan.text.as_bytes(), tracker);
    let (models, materials) = tobj::load_obj_buf(&mut reader, &tobj_opts, |p| libs.load(p))
        .map_err(|e| match tracker.is_cancelled() {
            true => tracker.cancelled(),
            false => LoadError::from(ObjError::Parse {
                path: path.to_owned(),
                message: format!("tobj: {e}"),
            }),
        })?;
    Ok((models, materials, scan))
}

/// Charges what parsing and building will need, and reports what the scan found.
fn charge_and_note(
    scan: &mut scan::Scan,
    budget: &Budget,
    report: &mut LoadReport,
) -> Result<(), LoadError> {
    if let Some(len) = scan.rewritten_len {
        budget.charge(len, || "rewritten OBJ text".into())?;
    }
    let (v, f) = (scan.positions, scan.faces);
    budget.charge(parse_bytes(scan), || {
        format!("parsing {v} vertices and {f} faces")
    })?;
    budget.charge(mesh_bytes(v, scan.corners, f), || {
        format!("meshes of {v} vertices and {f} faces")
    })?;
    report.warnings.append(&mut scan.warnings);
    Ok(())
}

/// The model's folder and the folder of each material's library.
#[derive(Clone, Copy)]
struct Folders<'a> {
    root: &'a Path,
    dirs: &'a [PathBuf],
}

/// Converts the `tobj` materials (read from `folders.dirs`) into scene materials, in
/// order (the [`Stage::Textures`] stage), and warns about `usemtl` names that none of them
/// has.
fn add_materials(
    materials: &[tobj::Material],
    folders: Folders,
    budget: &Budget,
    tracker: &Tracker,
    scan: &scan::Scan,
    scene: &mut Scene,
) -> Result<(), LoadError> {
    let root = folders.root;
    tracker.begin(Stage::Textures, TEXTURES_UNTIL, materials.len() as u64)?;
    let mut converter = mtl::Converter::new(root, budget, tracker);
    for (i, m) in materials.iter().enumerate() {
        let dir = folders.dirs.get(i).map_or(root, PathBuf::as_path);
        scene.materials.push(converter.convert(m, dir)?);
        tracker.advance(i as u64 + 1)?;
    }
    scene.textures = converter.textures;
    scene.report.warnings.append(&mut converter.warnings);
    let defined: HashSet<&str> = materials.iter().map(|m| m.name.as_str()).collect();
    for (line, name) in &scan.materials_used {
        if !defined.contains(name.as_str()) {
            scene.report.warnings.push(format!(
                "line {line}: `usemtl {name}`: no such material, default used"
            ));
        }
    }
    Ok(())
}

/// One mesh and one identity-placed instance per `tobj` model with faces left after
/// dropping bad ones; `file_vertices` is the number of `v` lines, for the report. The
/// [`Stage::Geometry`] stage, in corners, shown as [`Stage::Normals`] while a mesh whose
/// normals are generated is built.
fn add_meshes(
    path: &Path,
    models: Vec<tobj::Model>,
    opts: &LoadOptions,
    file_vertices: u64,
    tracker: &Tracker,
    strokes: Vec<(Mesh, String)>,
    scene: &mut Scene,
) -> Result<(), LoadError> {
    let mut dropped = Dropped::default();
    let mut averaged = Vec::new();
    let corners: usize = models.iter().map(|m| m.mesh.indices.len()).sum();
    tracker.begin(Stage::Geometry, 1.0, corners as u64)?;
    let mut done = 0u64;
    for model in models {
        let before = done;
        done += model.mesh.indices.len() as u64;
        let name = model.name.clone();
        let mut data = mesh_data(model, scene.materials.len());
        let d = retain_facets(&mut data);
        // Building the mesh takes about nine times as long as converting it.
        tracker.advance(before + (done - before) / 10)?;
        dropped.too_small += d.too_small;
        dropped.non_finite += d.non_finite;
        dropped.degenerate += d.degenerate;
        if data.corners.is_empty() {
            continue;
        }
        if data.normals.is_none() {
            averaged.push(name.clone());
            tracker.label(Stage::Normals)?;
        }
        let mesh = Mesh::new(data, NormalPolicy::Average(opts.normals)).map_err(|source| {
            ObjError::Mesh {
                path: path.to_owned(),
                object: name.clone(),
                source,
            }
        })?;
        tracker.label(Stage::Geometry)?;
        tracker.advance(done)?;
        scene.instances.push(Instance {
            mesh: scene.meshes.len(),
            world: Mat4::IDENTITY,
            name,
            style: Style::Inherit,
            node: None,
            skin: None,
            copies: None,
        });
        scene.meshes.push(mesh);
    }
    for (mesh, note) in strokes {
        scene.instances.push(Instance {
            mesh: scene.meshes.len(),
            world: Mat4::IDENTITY,
            name: mesh.name.clone(),
            style: Style::Inherit,
            node: None,
            skin: None,
            copies: None,
        });
        scene.meshes.push(mesh);
        scene.report.loaded.push(note);
    }
    let report = &mut scene.report;
    report.warnings.extend(dropped.warnings("OBJ"));
    let kept: u64 = scene.meshes.iter().map(|m| m.positions.len() as u64).sum();
    if kept < file_vertices {
        report.warnings.push(format!(
            "at least {} of the file's {file_vertices} vertices are used by no face (not loaded)",
            file_vertices - kept
        ));
    }
    if !averaged.is_empty() {
        let crease = opts.normals.crease_degrees;
        report.generated.push(format!(
            "normals averaged ({:?} weighting, {}) for {} object(s): {}",
            opts.normals.weighting,
            crease.map_or("no crease split".into(), |c| format!("crease {c} degrees")),
            averaged.len(),
            name_list(&averaged)
        ));
    }
    if scene.meshes.is_empty() {
        report
            .warnings
            .push("no faces, points or lines to draw".into());
    }
    Ok(())
}

/// Bytes `tobj` needs while parsing what `scan` counted (its face list, the per-group
/// copies and index maps), generously rounded.
fn parse_bytes(scan: &scan::Scan) -> u64 {
    let elements = scan.positions.saturating_mul(12)
        + scan.texcoords.saturating_mul(8)
        + scan.normals.saturating_mul(12);
    elements
        .saturating_mul(3)
        .saturating_add(scan.faces.saturating_mul(112))
        .saturating_add(scan.corners.saturating_mul(96))
        .saturating_add(scan.objects.saturating_mul(256))
}

/// Up to eight names, then "and N more".
fn name_list(names: &[String]) -> String {
    let shown: Vec<&str> = names.iter().take(8).map(String::as_str).collect();
    match names.len().saturating_sub(shown.len()) {
        0 => shown.join(", "),
        more => format!("{} and {more} more", shown.join(", ")),
    }
}

/// One `tobj` model as mesh data; `materials` is how many scene materials exist.
fn mesh_data(model: tobj::Model, materials: usize) -> MeshData {
    let m = model.mesh;
    let corners = m.indices.len();
    let vec3s = |v: &[f32]| {
        v.chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect::<Vec<_>>()
    };
    let positions = vec3s(&m.positions);
    let normals = (!m.normals.is_empty() && m.normal_indices.len() == corners).then(|| Channel {
        values: vec3s(&m.normals),
        indices: Some(m.normal_indices),
    });
    let uvs = (!m.texcoords.is_empty() && m.texcoord_indices.len() == corners).then(|| Channel {
        values: m
            .texcoords
            .chunks_exact(2)
            .map(|c| Vec2::new(c[0], 1.0 - c[1]))
            .collect(),
        indices: Some(m.texcoord_indices),
    });
    let colors = (m.vertex_color.len() == m.positions.len() && !positions.is_empty()).then(|| {
        Channel::per_vertex(
            m.vertex_color
                .chunks_exact(3)
                .map(|c| Vec4::new(c[0], c[1], c[2], 1.0))
                .collect(),
        )
    });
    MeshData {
        name: model.name,
        positions,
        corners: m.indices,
        facet_sizes: (!m.face_arities.is_empty()).then_some(m.face_arities),
        normals,
        uvs: uvs.into_iter().collect(),
        colors,
        tangents: None,
        material: m.material_id.filter(|&i| i < materials),
    }
}

#[cfg(test)]
mod tests;
