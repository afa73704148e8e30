//! STL (stereolithography) meshes, binary and ASCII, into a [`Scene`]: one mesh, placed by
//! one identity instance, with the default material.
//!
//! - **Binary**: an 80-byte header, a little-endian `u32` triangle count, then 50 bytes per
//!   triangle (facet normal, three vertices, a 16-bit attribute). A file is read as binary
//!   when its length is exactly `84 + 50 n` for the count it declares (some binary files
//!   start with the word `solid` too), so the count is checked against the bytes present
//!   before anything is allocated.
//! - **ASCII**: `solid NAME`, then per triangle `facet normal nx ny nz`, `outer loop`, three
//!   `vertex x y z` lines, `endloop`, `endfacet`; `endsolid`. Several solids in one file
//!   are read as one mesh. Errors name the line.
//!
//! STL stores every triangle's corners separately. Corners at bit-identical positions are
//! welded into one vertex, so the mesh has topology (edges, neighbours) and averaged
//! normals split at creases ([`NormalPolicy::Average`], as for an OBJ without normals);
//! the facet normals in the file are ignored (many writers leave them zero), the winding
//! decides the front face, as every STL viewer does. The 16-bit attribute (colour in some
//! writers' dialects) is not read.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};

use super::progress::{Stage, Tracker};
use super::{files, mesh_bytes, retain_facets, Budget, LoadError, LoadOptions};
use crate::mesh::{Mesh, MeshData, MeshError, NormalPolicy};
use crate::scene::{Instance, LoadReport, Scene, Style};

/// Where reading ends on the progress bar (the rest is parsing and building the mesh).
const READ_UNTIL: f32 = 0.1;
const PARSE_UNTIL: f32 = 0.4;

/// Why an STL file could not be loaded. Messages are one line starting with the path.
#[derive(Debug, thiserror::Error)]
pub enum StlError {
    /// An ASCII line that cannot be read (`line` is 1-based).
    #[error("{path}:{line}: {message}")]
    Syntax {
        path: PathBuf,
        line: usize,
        message: String,
    },
    /// A binary file whose length does not match its triangle count, or neither form.
    #[error("{path}: {message}")]
    Format { path: PathBuf, message: String },
    #[error("{path}: {source}")]
    Mesh { path: PathBuf, source: MeshError },
}

/// Loads an STL file, reporting to `tracker`.
pub(crate) fn load_stl(
    path: &Path,
    opts: &LoadOptions,
    tracker: &Tracker,
) -> Result<Scene, LoadError> {
    let budget = Budget::new(path, opts.max_bytes);
    let bytes = files::read_model(path, &budget, "STL file", tracker, READ_UNTIL)?;
    let binary = binary_count(&bytes);
    let ascii = bytes.trim_ascii_start().starts_with(b"solid");
    let (corners, format) = match (binary, ascii) {
        (Some(n), _) => {
            let n = n as u64;
            budget.charge(n * 36, || format!("{n} triangles"))?;
            tracker.begin(Stage::Parsing, PARSE_UNTIL, n)?;
            (parse_binary(&bytes, tracker)?, "STL (binary)")
        }
        (None, true) => {
            tracker.begin(Stage::Parsing, PARSE_UNTIL, bytes.len() as u64)?;
            (parse_ascii(path, &bytes, tracker)?, "STL (ASCII)")
        }
        (None, false) => {
            let message = match bytes.get(80..84) {
                Some(c) => format!(
                    "not an STL file: {} bytes, but a binary STL declaring {} triangles \
                     has {} bytes, and an ASCII one starts with `solid`",
                    bytes.len(),
                    u32::from_le_bytes([c[0], c[1], c[2], c[3]]),
                    84 + 50 * u64::from(u32::from_le_bytes([c[0], c[1], c[2], c[3]])),
                ),
                None => format!(
                    "not an STL file: {} bytes, shorter than a binary header (84 bytes), \
                     and not ASCII (`solid ...`)",
                    bytes.len()
                ),
            };
            return Err(StlError::Format {
                path: path.to_owned(),
                message,
            }
            .into());
        }
    };
    drop(bytes);
    let triangles = corners.len() / 3;
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
    let (t, c) = (triangles as u64, corners.len() as u64);
    budget.charge(mesh_bytes(c, c, t), || {
        format!("a mesh of {triangles} triangles")
    })?;
    tracker.begin(Stage::Geometry, 1.0, c)?;
    let mut data = weld(name.clone(), &corners);
    tracker.check()?;
    let dropped = retain_facets(&mut data);
    scene.report.warnings.extend(dropped.warnings("STL"));
    if data.corners.is_empty() {
        scene.report.warnings.push("no faces to draw".into());
        return Ok(scene);
    }
    scene.report.generated.push(format!(
        "{} corners welded into {} vertices; normals averaged (crease {})",
        corners.len(),
        data.positions.len(),
        opts.normals
            .crease_degrees
            .map_or("none".into(), |c| format!("{c} degrees")),
    ));
    tracker.label(Stage::Normals)?;
    let mesh =
        Mesh::new(data, NormalPolicy::Average(opts.normals)).map_err(|source| StlError::Mesh {
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

/// The triangle count of a binary STL, if the length is exactly what it declares.
fn binary_count(bytes: &[u8]) -> Option<u32> {
    let c = bytes.get(80..84)?;
    let n = u32::from_le_bytes([c[0], c[1], c[2], c[3]]);
    (bytes.len() as u64 == 84 + 50 * u64::from(n)).then_some(n)
}

/// The corner positions of a binary STL whose length [`binary_count`] checked.
fn parse_binary(bytes: &[u8], tracker: &Tracker) -> Result<Vec<Vec3>, LoadError> {
    let records = bytes.get(84..).unwrap_or_default().chunks_exact(50);
    let mut corners = Vec::with_capacity(records.len() * 3);
    let f = |b: &[u8], i: usize| f32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
    for (t, r) in records.enumerate() {
        for k in 0..3 {
            let at = 12 + 12 * k;
            corners.push(Vec3::new(f(r, at), f(r, at + 4), f(r, at + 8)));
        }
        if t % 65536 == 0 {
            tracker.advance(t as u64)?;
        }
    }
    Ok(corners)
}

/// The corner positions of an ASCII STL: every `vertex` line, checked to come in threes
/// inside `outer loop` ... `endloop`.
fn parse_ascii(path: &Path, bytes: &[u8], tracker: &Tracker) -> Result<Vec<Vec3>, LoadError> {
    let text = crate::files::text(bytes);
    let err = |line: usize, message: String| {
        LoadError::from(StlError::Syntax {
            path: path.to_owned(),
            line,
            message,
        })
    };
    let mut corners = Vec::new();
    // Corners of the loop being read (None outside `outer loop`).
    let mut open: Option<(usize, usize)> = None;
    let mut done = 0u64;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        done += raw.len() as u64 + 1;
        if line % 65536 == 0 {
            tracker.advance(done)?;
        }
        let mut words = raw.split_ascii_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        match keyword {
            "solid" | "endsolid" | "facet" | "endfacet" => {}
            "outer" => {
                if open.is_some() {
                    return Err(err(line, "`outer loop` inside a loop".into()));
                }
                open = Some((line, 0));
            }
            "vertex" => {
                let Some((_, n)) = open.as_mut() else {
                    return Err(err(line, "`vertex` outside `outer loop`".into()));
                };
                let mut xyz = [0f32; 3];
                for v in &mut xyz {
                    let w = words
                        .next()
                        .ok_or_else(|| err(line, "`vertex` needs three numbers".into()))?;
                    *v = w
                        .parse()
                        .map_err(|_| err(line, format!("`vertex`: `{w}` is not a number")))?;
                }
                *n += 1;
                corners.push(Vec3::from_array(xyz));
            }
            "endloop" => match open.take() {
                Some((_, 3)) => {}
                Some((start, n)) => {
                    return Err(err(
                        line,
                        format!("the loop opened on line {start} has {n} vertices, not 3"),
                    ))
                }
                None => return Err(err(line, "`endloop` without `outer loop`".into())),
            },
            other => {
                let shown: String = other.chars().take(24).collect();
                return Err(err(line, format!("unknown keyword `{shown}`")));
            }
        }
    }
    if let Some((start, _)) = open {
        return Err(err(start, "`outer loop` never closed".into()));
    }
    Ok(corners)
}

/// Mesh data of the triangles `corners` (three per triangle), with corners at
/// bit-identical positions sharing one vertex (`-0.0` and `0.0` are one position).
fn weld(name: String, corners: &[Vec3]) -> MeshData {
    let key = |p: Vec3| (p + Vec3::ZERO).to_array().map(f32::to_bits);
    let mut index: HashMap<[u32; 3], u32> = HashMap::with_capacity(corners.len() / 4);
    let mut positions = Vec::with_capacity(corners.len() / 4);
    let welded = corners
        .iter()
        .map(|&p| {
            *index.entry(key(p)).or_insert_with(|| {
                positions.push(p);
                positions.len() as u32 - 1
            })
        })
        .collect();
    MeshData {
        name,
        positions,
        corners: welded,
        facet_sizes: None,
        normals: None,
        uvs: Vec::new(),
        colors: None,
        tangents: None,
        material: None,
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use glam::Vec3;

    use super::super::tests::TempDir;
    use super::super::{load, LoadOptions};

    /// A unit cube's 12 triangles, counter-clockwise seen from outside.
    fn cube() -> Vec<[Vec3; 3]> {
        let v = |i: u32| Vec3::new((i & 1) as f32, (i >> 1 & 1) as f32, (i >> 2 & 1) as f32);
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        quads
            .iter()
            .flat_map(|q| [[v(q[0]), v(q[1]), v(q[2])], [v(q[0]), v(q[2]), v(q[3])]])
            .collect()
    }

    fn binary(tris: &[[Vec3; 3]], header: &[u8]) -> Vec<u8> {
        let mut out = vec![0u8; 80];
        out[..header.len()].copy_from_slice(header);
        out.extend((tris.len() as u32).to_le_bytes());
        for t in tris {
            out.extend([0u8; 12]);
            for p in t {
                for c in p.to_array() {
                    out.extend(c.to_le_bytes());
                }
            }
            out.extend([0u8; 2]);
        }
        out
    }

    fn ascii(tris: &[[Vec3; 3]]) -> String {
        let mut s = String::from("solid cube\n");
        for t in tris {
            s += "  facet normal 0 0 0\n    outer loop\n";
            for p in t {
                s += &format!("      vertex {} {} {}\n", p.x, p.y, p.z);
            }
            s += "    endloop\n  endfacet\n";
        }
        s + "endsolid cube\n"
    }

    /// Binary (also with a header starting `solid`) and ASCII cubes load the same: 8
    /// welded vertices, 12 triangles, one instance, the format in the report; the crease
    /// split gives each corner its face's normal.
    #[test]
    fn binary_and_ascii_cubes_weld_into_eight_vertices() {
        let dir = TempDir::new("stl");
        let tris = cube();
        for (name, bytes) in [
            ("b.stl", binary(&tris, b"binary cube")),
            ("s.STL", binary(&tris, b"solid but binary")),
            ("a.stl", ascii(&tris).into_bytes()),
        ] {
            let path = dir.write(name, bytes);
            let scene = load(&path, &LoadOptions::default()).unwrap();
            assert_eq!(scene.meshes.len(), 1, "{name}");
            let m = &scene.meshes[0];
            assert_eq!(m.positions.len(), 8, "{name}");
            assert_eq!(m.facets().len(), 12, "{name}");
            assert_eq!(scene.instances.len(), 1);
            let format = &scene.report.format;
            assert!(format.starts_with("STL"), "{format}");
            assert_eq!(format.contains("ASCII"), name == "a.stl", "{format}");
            assert!(
                scene.report.warnings.is_empty(),
                "{:?}",
                scene.report.warnings
            );
            // Every normal is a face normal (90-degree creases split).
            for n in m.normals.values.iter() {
                let axis = n.abs().max_element();
                assert!((axis - 1.0).abs() < 1e-6, "{name}: normal {n}");
            }
        }
    }

    /// Bad files: one-line errors naming the file (and the line for ASCII), never a panic;
    /// a huge declared count is refused by the length check before any allocation.
    #[test]
    fn malformed_stl_files_give_clear_errors() {
        let dir = TempDir::new("stl-bad");
        let tris = cube();
        let mut huge = binary(&tris, b"x");
        huge[80..84].copy_from_slice(&u32::MAX.to_le_bytes());
        let mut truncated = binary(&tris, b"x");
        truncated.truncate(84 + 50 * 11 + 7);
        let two = ascii(&tris).replacen("      vertex 0 0 0\n", "", 1);
        let cases: [(&str, Vec<u8>, &str); 6] = [
            ("huge.stl", huge, "declaring 4294967295 triangles"),
            ("short.stl", truncated, "not an STL file"),
            ("tiny.stl", b"abc".to_vec(), "shorter than a binary header"),
            (
                "two.stl",
                two.into_bytes(),
                ":6: the loop opened on line 3 has 2",
            ),
            (
                "word.stl",
                b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zero\n".to_vec(),
                ":4: `vertex`: `zero` is not a number",
            ),
            (
                "open.stl",
                b"solid x\nouter loop\nvertex 0 0 0\n".to_vec(),
                ":2: `outer loop` never closed",
            ),
        ];
        for (name, bytes, want) in cases {
            let path = dir.write(name, bytes);
            let e = load(&path, &LoadOptions::default())
                .unwrap_err()
                .to_string();
            assert!(e.starts_with(&path.display().to_string()), "{e}");
            assert!(e.contains(want), "{name}: {e}");
            assert!(!e.contains('\n'), "{e}");
        }
        // NaN corners drop their triangles with a warning; the rest loads.
        let mut nan = tris.clone();
        nan[0][1] = Vec3::NAN;
        let path = dir.write("nan.stl", binary(&nan, b""));
        let scene = load(&path, &LoadOptions::default()).unwrap();
        assert_eq!(scene.meshes[0].facets().len(), 11);
        assert!(
            scene.report.warnings.iter().any(|w| w.contains("STL")),
            "{:?}",
            scene.report.warnings
        );
        assert!(load(
            Path::new("/nonexistent/realist/x.stl"),
            &LoadOptions::default()
        )
        .is_err());
    }
}
