//! `Scene`: a model loaded from a file, or made from numpy arrays, and prepared once for
//! every render that uses it.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat4, Vec2, Vec3, Vec4};
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyFileNotFoundError, PyValueError};
use pyo3::prelude::*;

use realist::load::{self, LoadError, LoadOptions};
use realist::mesh::{Channel, Mesh, MeshData, NormalOptions, NormalPolicy};
use realist::render::PreparedScene;
use realist::scene::{Instance, LoadReport, Scene as RScene, Style};

use crate::RealistError;

/// The most vertices or faces `Scene.from_arrays` takes (as the loaders' budget would).
const MAX_ELEMENTS: usize = 1 << 28;

/// A scene ready to render: a model file loaded (OBJ, glTF/GLB, STL, PLY) or a triangle mesh
/// made from numpy arrays, prepared once (triangulated, its materials resolved) and shared
/// by every render that uses it. Immutable; safe to share between threads.
#[pyclass(module = "realist", frozen)]
pub struct Scene {
    pub(crate) prepared: Arc<PreparedScene>,
    /// For messages and `repr`: the file, or "arrays".
    pub(crate) source: String,
}

impl Scene {
    /// Loads `path` as `realist render` does (its messages name the file); an empty model
    /// is an error, not an empty image.
    pub(crate) fn load_path(path: &Path) -> Result<Scene, LoadFailure> {
        let scene = load::load(path, &LoadOptions::default()).map_err(LoadFailure::from)?;
        scene
            .check_drawable(path)
            .map_err(|m| LoadFailure::Other(m.to_string()))?;
        Ok(Scene {
            prepared: Arc::new(PreparedScene::new(scene)),
            source: path.display().to_string(),
        })
    }
}

/// Why a file could not become a scene: a missing file is told apart (FileNotFoundError).
#[derive(Debug)]
pub(crate) enum LoadFailure {
    NotFound(String),
    Other(String),
}

impl From<LoadError> for LoadFailure {
    fn from(e: LoadError) -> Self {
        match &e {
            LoadError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound => {
                LoadFailure::NotFound(e.to_string())
            }
            _ => LoadFailure::Other(e.to_string()),
        }
    }
}

impl LoadFailure {
    pub(crate) fn message(&self) -> &str {
        match self {
            LoadFailure::NotFound(m) | LoadFailure::Other(m) => m,
        }
    }

    pub(crate) fn into_py(self) -> PyErr {
        match self {
            LoadFailure::NotFound(m) => PyFileNotFoundError::new_err(m),
            LoadFailure::Other(m) => RealistError::new_err(m),
        }
    }
}

#[pymethods]
impl Scene {
    /// Loads a model file (.obj, .gltf, .glb, .stl, .ply) as `realist render` does.
    ///
    /// Raises FileNotFoundError for a missing file and RealistError for a file realist cannot
    /// read (the message names the file and the problem).
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Scene> {
        py.detach(|| Scene::load_path(&path))
            .map_err(LoadFailure::into_py)
    }

    /// A triangle mesh from numpy arrays (trimesh's vertices and faces work as they are).
    ///
    /// vertices: (n, 3) floats; faces: (m, 3) integer vertex indices (counter-clockwise
    /// seen from the front); normals: (n, 3) per-vertex normals (default: averaged from the
    /// faces, as for an OBJ file without normals); uvs: (n, 2) texture coordinates with the
    /// origin at the bottom left (OBJ's and trimesh's convention); colors: (n, 3) or (n, 4)
    /// per-vertex colours, floats in linear light or uint8 sRGB (trimesh's). Values must be
    /// finite and indices in range: ValueError names the array and the problem. The mesh
    /// gets realist's default material, as an OBJ file without a material library does.
    #[staticmethod]
    #[pyo3(signature = (vertices, faces, normals=None, uvs=None, colors=None))]
    fn from_arrays(
        py: Python<'_>,
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        normals: Option<&Bound<'_, PyAny>>,
        uvs: Option<&Bound<'_, PyAny>>,
        colors: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Scene> {
        // Dtypes and shapes in Python (realist/_arrays.py), values here.
        let converted = py
            .import("realist._arrays")?
            .getattr("prepare")?
            .call1((vertices, faces, normals, uvs, colors))?;
        #[allow(clippy::type_complexity)]
        let (vertices, faces, normals, uvs, colors): (
            PyReadonlyArray2<'_, f64>,
            PyReadonlyArray2<'_, i64>,
            Option<PyReadonlyArray2<'_, f64>>,
            Option<PyReadonlyArray2<'_, f64>>,
            Option<PyReadonlyArray2<'_, f64>>,
        ) = converted.extract()?;
        let positions: Vec<Vec3> = rows(&vertices, "vertices", 3, None)?
            .into_iter()
            .map(|r| Vec3::new(r[0], r[1], r[2]))
            .collect();
        let n = positions.len();
        if n == 0 {
            return Err(PyValueError::new_err("vertices: the array is empty"));
        }
        let corners = face_corners(&faces, n)?;
        let normals = match &normals {
            Some(a) => Some(
                rows(a, "normals", 3, Some(n))?
                    .into_iter()
                    .map(|r| Vec3::new(r[0], r[1], r[2]))
                    .collect::<Vec<_>>(),
            ),
            None => None,
        };
        let uvs = match &uvs {
            // OBJ's and trimesh's v runs up the image; realist's (glTF's) runs down.
            Some(a) => Some(
                rows(a, "uvs", 2, Some(n))?
                    .into_iter()
                    .map(|r| Vec2::new(r[0], 1.0 - r[1]))
                    .collect::<Vec<_>>(),
            ),
            None => None,
        };
        let colors = match &colors {
            Some(a) => Some(
                rows(a, "colors", 4, Some(n))?
                    .into_iter()
                    .map(|r| Vec4::new(r[0], r[1], r[2], r[3]))
                    .collect::<Vec<_>>(),
            ),
            None => None,
        };
        let data = MeshData {
            name: "arrays".into(),
            positions,
            corners,
            facet_sizes: None,
            normals: normals.map(Channel::per_vertex),
            uvs: uvs.map(Channel::per_vertex).into_iter().collect(),
            colors: colors.map(Channel::per_vertex),
            tangents: None,
            material: None,
        };
        py.detach(|| from_mesh_data(data))
            .map_err(PyValueError::new_err)
    }

    /// The file the scene was loaded from, or "arrays".
    #[getter]
    fn source(&self) -> &str {
        &self.source
    }

    /// The axis-aligned bounds of everything drawn, as ((xmin, ymin, zmin), (xmax, ymax,
    /// zmax)), or None for a scene with nothing to draw.
    #[getter]
    #[allow(clippy::type_complexity)]
    fn bounds(&self) -> Option<((f32, f32, f32), (f32, f32, f32))> {
        self.prepared
            .scene()
            .bounds()
            .map(|(lo, hi)| (lo.into(), hi.into()))
    }

    /// How many triangles the scene draws (every instance counted).
    #[getter]
    fn triangles(&self) -> usize {
        let s = self.prepared.scene();
        s.instances
            .iter()
            .map(|i| s.meshes.get(i.mesh).map_or(0, |m| m.facet_count()) * i.copy_count())
            .sum()
    }

    /// How many instances (placed meshes) the scene has: `Frame.ids` numbers them.
    #[getter]
    fn instances(&self) -> usize {
        self.prepared.scene().instances.len()
    }

    /// What the loader could not use or changed (missing textures, dropped faces, ...).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.prepared.scene().report.warnings.clone()
    }

    fn __repr__(&self) -> String {
        format!(
            "realist.Scene({:?}, {} instance(s), {} triangle(s))",
            self.source,
            self.instances(),
            self.triangles()
        )
    }
}

/// The rows of a 2D array with `cols` columns (and `count` rows if given), finite, as f32.
fn rows(
    a: &PyReadonlyArray2<'_, f64>,
    name: &str,
    cols: usize,
    count: Option<usize>,
) -> PyResult<Vec<[f32; 4]>> {
    let shape = a.shape();
    let (n, c) = (shape[0], shape[1]);
    if c != cols {
        return Err(PyValueError::new_err(format!(
            "{name}: expected shape ({}, {cols}), got ({n}, {c})",
            count.map_or("n".into(), |k| k.to_string())
        )));
    }
    if let Some(k) = count.filter(|&k| k != n) {
        return Err(PyValueError::new_err(format!(
            "{name}: expected one row per vertex, ({k}, {cols}), got ({n}, {c})"
        )));
    }
    if n > MAX_ELEMENTS {
        return Err(PyValueError::new_err(format!(
            "{name}: {n} rows, over the limit of {MAX_ELEMENTS}"
        )));
    }
    let view = a.as_array();
    let mut out = Vec::with_capacity(n);
    for (i, row) in view.outer_iter().enumerate() {
        let mut r = [0f32; 4];
        for (k, &v) in row.iter().enumerate() {
            let f = v as f32;
            if !f.is_finite() {
                return Err(PyValueError::new_err(format!(
                    "{name}: row {i} holds {v}, not a finite number (in float32)"
                )));
            }
            r[k] = f;
        }
        out.push(r);
    }
    Ok(out)
}

/// The corners of (m, 3) faces, each index checked against `n` vertices.
fn face_corners(faces: &PyReadonlyArray2<'_, i64>, n: usize) -> PyResult<Vec<u32>> {
    let shape = faces.shape();
    if shape[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "faces: expected shape (m, 3) (triangles), got ({}, {})",
            shape[0], shape[1]
        )));
    }
    if shape[0] == 0 {
        return Err(PyValueError::new_err("faces: the array is empty"));
    }
    if shape[0] > MAX_ELEMENTS {
        return Err(PyValueError::new_err(format!(
            "faces: {} rows, over the limit of {MAX_ELEMENTS}",
            shape[0]
        )));
    }
    let view = faces.as_array();
    let mut corners = Vec::with_capacity(shape[0] * 3);
    for (f, row) in view.outer_iter().enumerate() {
        for &i in row {
            if i < 0 || i as u64 >= n as u64 {
                return Err(PyValueError::new_err(format!(
                    "faces: face {f} refers to vertex {i}, but there are {n} vertices (0 to {})",
                    n - 1
                )));
            }
            corners.push(i as u32);
        }
    }
    Ok(corners)
}

/// One mesh placed once, with the default material: what the OBJ loader makes of a file
/// of `v` and `f` lines (faces that cannot be drawn dropped, normals averaged where none
/// are given).
fn from_mesh_data(mut data: MeshData) -> Result<Scene, String> {
    // Degenerate faces (two equal corners) are dropped, as every loader drops them.
    let tris = data.corners.len() / 3;
    let mut kept = Vec::with_capacity(data.corners.len());
    for t in data.corners.chunks_exact(3) {
        if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
            kept.extend_from_slice(t);
        }
    }
    let dropped = tris - kept.len() / 3;
    if kept.is_empty() {
        return Err(format!(
            "faces: all {tris} faces repeat a vertex: nothing to draw"
        ));
    }
    data.corners = kept;
    let mesh = Mesh::new(data, NormalPolicy::Average(NormalOptions::default()))
        .map_err(|e| format!("arrays: {e}"))?;
    let mut report = LoadReport {
        file: "arrays".into(),
        format: "arrays".into(),
        ..LoadReport::default()
    };
    if dropped > 0 {
        report
            .warnings
            .push(format!("{dropped} face(s) repeating a vertex dropped"));
    }
    let scene = RScene {
        meshes: vec![mesh],
        instances: vec![Instance {
            mesh: 0,
            world: Mat4::IDENTITY,
            name: "arrays".into(),
            style: Style::Inherit,
            node: None,
            skin: None,
            copies: None,
        }],
        report,
        ..RScene::default()
    };
    Ok(Scene {
        prepared: Arc::new(PreparedScene::new(scene)),
        source: "arrays".into(),
    })
}
