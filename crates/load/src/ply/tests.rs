//! PLY files written in memory (ASCII, binary little- and big-endian) and loaded from a
//! temp dir.

use std::path::Path;

use glam::{Vec2, Vec3, Vec4};

use super::super::tests::TempDir;
use super::super::{load, LoadOptions};
use crate::mesh::NormalSource;
use crate::scene::Scene;

/// A property: `(type, name)` or, for a list, `(count type, item type, name)`.
#[derive(Clone, Copy)]
enum P {
    S(&'static str, &'static str),
    L(&'static str, &'static str, &'static str),
}

/// An element: its name, properties, and per entry per property the values (one for a
/// scalar).
#[derive(Clone)]
struct E {
    name: &'static str,
    props: Vec<P>,
    rows: Vec<Vec<Vec<f64>>>,
}

fn encode(ty: &str, v: f64, big: bool, out: &mut Vec<u8>) {
    macro_rules! put {
        ($t:ty) => {{
            let x = v as $t;
            out.extend(
                if big {
                    x.to_be_bytes()
                } else {
                    x.to_le_bytes()
                }
                .iter(),
            )
        }};
    }
    match ty {
        "char" | "int8" => put!(i8),
        "uchar" | "uint8" => put!(u8),
        "short" | "int16" => put!(i16),
        "ushort" | "uint16" => put!(u16),
        "int" | "int32" => put!(i32),
        "uint" | "uint32" => put!(u32),
        "float" | "float32" => put!(f32),
        "double" | "float64" => put!(f64),
        _ => panic!("type {ty}"),
    }
}

/// A PLY file of `elements` in `format` (`ascii`, `binary_little_endian`, ...).
fn ply(format: &str, elements: &[E]) -> Vec<u8> {
    let mut head = format!("ply\nformat {format} 1.0\ncomment written by the tests\n");
    for e in elements {
        head += &format!("element {} {}\n", e.name, e.rows.len());
        for p in &e.props {
            head += &match p {
                P::S(t, n) => format!("property {t} {n}\n"),
                P::L(c, t, n) => format!("property list {c} {t} {n}\n"),
            };
        }
    }
    head += "obj_info also skipped\nend_header\n";
    let mut out = head.into_bytes();
    let big = format == "binary_big_endian";
    for e in elements {
        for row in &e.rows {
            let mut words = Vec::new();
            for (p, values) in e.props.iter().zip(row) {
                match *p {
                    P::S(t, _) if format == "ascii" => {
                        let _ = t;
                        words.push(values[0].to_string());
                    }
                    P::S(t, _) => encode(t, values[0], big, &mut out),
                    P::L(..) if format == "ascii" => {
                        words.push(values.len().to_string());
                        words.extend(values.iter().map(f64::to_string));
                    }
                    P::L(c, t, _) => {
                        encode(c, values.len() as f64, big, &mut out);
                        for &v in values {
                            encode(t, v, big, &mut out);
                        }
                    }
                }
            }
            if format == "ascii" {
                out.extend(words.join(" ").bytes());
                out.push(b'\n');
            }
        }
    }
    out
}

/// A unit cube's corners.
fn corner(i: u32) -> Vec3 {
    Vec3::new((i & 1) as f32, (i >> 1 & 1) as f32, (i >> 2 & 1) as f32)
}

/// The cube's six quads, counter-clockwise seen from outside.
const QUADS: [[u32; 4]; 6] = [
    [0, 2, 3, 1],
    [4, 5, 7, 6],
    [0, 1, 5, 4],
    [2, 6, 7, 3],
    [0, 4, 6, 2],
    [1, 3, 7, 5],
];

fn xyz(ty: &'static str) -> Vec<P> {
    vec![P::S(ty, "x"), P::S(ty, "y"), P::S(ty, "z")]
}

fn cube_vertices(ty: &'static str) -> E {
    E {
        name: "vertex",
        props: xyz(ty),
        rows: (0..8)
            .map(|i| corner(i).to_array().map(|c| vec![f64::from(c)]).to_vec())
            .collect(),
    }
}

fn cube_faces(count: &'static str, item: &'static str) -> E {
    E {
        name: "face",
        props: vec![P::L(count, item, "vertex_indices")],
        rows: QUADS
            .iter()
            .map(|q| vec![q.iter().map(|&v| f64::from(v)).collect()])
            .collect(),
    }
}

fn load_ok(path: &Path) -> Scene {
    let scene = load(path, &LoadOptions::default()).unwrap();
    assert!(
        scene.report.warnings.is_empty(),
        "{}: {:?}",
        path.display(),
        scene.report.warnings
    );
    scene
}

/// The same quad cube as ASCII, binary little-endian (float, uchar counts, int indices)
/// and binary big-endian (double, uint counts, uint indices) loads the same: 8 vertices
/// as the file has them (not welded), 6 quads, averaged normals split at the 90-degree
/// creases, the format in the report; the extension is matched in any case.
#[test]
fn ascii_and_binary_quad_cubes_load_the_same() {
    let dir = TempDir::new("ply");
    let files = [
        (
            "a.ply",
            ply(
                "ascii",
                &[cube_vertices("float"), cube_faces("uchar", "int")],
            ),
            "PLY (ASCII)",
        ),
        (
            "le.ply",
            ply(
                "binary_little_endian",
                &[cube_vertices("float"), cube_faces("uchar", "int")],
            ),
            "PLY (binary, little-endian)",
        ),
        (
            "be.PLY",
            ply(
                "binary_big_endian",
                &[cube_vertices("double"), cube_faces("uint", "uint32")],
            ),
            "PLY (binary, big-endian)",
        ),
    ];
    let mut first: Option<Scene> = None;
    for (name, bytes, format) in files {
        let scene = load_ok(&dir.write(name, bytes));
        assert_eq!(scene.report.format, format);
        assert_eq!(scene.meshes.len(), 1);
        assert_eq!(scene.instances.len(), 1);
        let m = &scene.meshes[0];
        assert_eq!(
            m.positions,
            (0..8).map(corner).collect::<Vec<_>>(),
            "{name}"
        );
        assert_eq!(m.facets().len(), 6, "{name}");
        assert!(m.facets().iter().all(|f| f.len == 4), "{name}");
        assert_eq!(m.corners, QUADS.concat(), "{name}");
        assert!(m.colors.is_none() && m.uvs.is_empty(), "{name}");
        assert!(matches!(m.normal_source, NormalSource::Averaged(_)));
        for f in m.facets() {
            let outward = f.normal.dot(
                m.corners[f.first as usize..(f.first + f.len) as usize]
                    .iter()
                    .map(|&v| m.positions[v as usize] - Vec3::splat(0.5))
                    .sum::<Vec3>(),
            );
            assert!(outward > 0.0, "{name}: facet normal {}", f.normal);
        }
        for n in &m.normals.values {
            assert!((n.abs().max_element() - 1.0).abs() < 1e-6, "{name}: {n}");
        }
        if let Some(a) = &first {
            let b = &a.meshes[0];
            assert_eq!(b.normals.values, m.normals.values, "{name}");
        } else {
            first = Some(scene);
        }
    }
}

/// Normals are the file's; `uchar` colours are sRGB-decoded (alpha only scaled), float
/// colours kept; UVs flipped to the glTF convention.
#[test]
fn normals_colours_and_uvs_are_read() {
    let dir = TempDir::new("ply-attr");
    let quad = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
    let tilted = Vec3::new(0.0, 0.6, 0.8);
    let faces = E {
        name: "face",
        props: vec![P::L("uchar", "int", "vertex_index")],
        rows: vec![vec![vec![0.0, 1.0, 2.0]], vec![vec![0.0, 2.0, 3.0]]],
    };
    let vertices = |color: &'static str, scale: f64| E {
        name: "vertex",
        props: vec![
            P::S("float", "x"),
            P::S("float", "y"),
            P::S("float", "z"),
            P::S("float", "nx"),
            P::S("float", "ny"),
            P::S("float", "nz"),
            P::S(color, "red"),
            P::S(color, "green"),
            P::S(color, "blue"),
            P::S(color, "alpha"),
            P::S("float", "u"),
            P::S("float", "v"),
        ],
        rows: quad
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let mut row: Vec<Vec<f64>> = p.to_array().map(|c| vec![f64::from(c)]).to_vec();
                row.extend(tilted.to_array().map(|c| vec![f64::from(c)]));
                let rgba = [255.0, 128.0, 0.0, 128.0].map(|c| c * scale);
                row.extend(rgba.map(|c| vec![if i == 0 { c } else { 0.0 }]));
                row.extend([vec![f64::from(p.x) * 0.5], vec![f64::from(p.y) * 0.25]]);
                row
            })
            .collect(),
    };
    let srgb_half = crate::color::srgb_decode(128.0 / 255.0) as f32;
    for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
        for (color, scale) in [("uchar", 1.0), ("float", 1.0 / 255.0)] {
            let bytes = ply(format, &[vertices(color, scale), faces.clone()]);
            let scene = load_ok(&dir.write(&format!("{format}-{color}.ply"), bytes));
            let m = &scene.meshes[0];
            assert_eq!(m.positions.len(), 4);
            assert_eq!(m.normal_source, NormalSource::File);
            assert!(m
                .normals
                .values
                .iter()
                .all(|n| (*n - tilted).length() < 1e-6));
            let c = m.colors.as_ref().expect("colours").values[0];
            let want = match color {
                "uchar" => Vec4::new(1.0, srgb_half, 0.0, 128.0 / 255.0),
                _ => Vec4::new(1.0, 128.0 / 255.0, 0.0, 128.0 / 255.0),
            };
            assert!(
                (c - want).abs().max_element() < 1e-6,
                "{format} {color}: {c}"
            );
            assert_eq!(m.uvs.len(), 1);
            assert_eq!(m.uvs[0].values[2], Vec2::new(0.5, 0.75), "{format}");
            assert!(
                scene.report.generated.is_empty(),
                "{:?}",
                scene.report.generated
            );
        }
    }
}

/// Elements other than vertex and face (before, between and after them, with lists) and
/// unknown properties are skipped in every format, giving the plain cube.
#[test]
fn extra_elements_and_properties_are_skipped() {
    let dir = TempDir::new("ply-extra");
    let material = E {
        name: "material",
        props: vec![
            P::S("uchar", "ambient_red"),
            P::L("uchar", "float", "coefficients"),
            P::S("double", "power"),
        ],
        rows: vec![
            vec![vec![10.0], vec![0.5, 0.25], vec![2.0]],
            vec![vec![20.0], vec![], vec![3.0]],
        ],
    };
    let mut vertices = cube_vertices("float");
    vertices.props.insert(1, P::S("ushort", "quality"));
    vertices.props.push(P::L("uchar", "int", "neighbours"));
    vertices.props.push(P::S("float", "nx")); // Without ny, nz: not read, one warning.
    for row in &mut vertices.rows {
        row.insert(1, vec![7.0]);
        row.push(vec![1.0, 2.0, 3.0]);
        row.push(vec![0.0]);
    }
    let mut faces = cube_faces("uchar", "int");
    faces.props.insert(0, P::S("int", "flags"));
    faces.props.push(P::L("uchar", "float", "texcoord"));
    for row in &mut faces.rows {
        row.insert(0, vec![-3.0]);
        row.push(vec![0.0; 8]);
    }
    let edges = E {
        name: "edge",
        props: vec![P::S("int", "vertex1"), P::S("int", "vertex2")],
        rows: vec![vec![vec![0.0], vec![1.0]]; 3],
    };
    for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
        let bytes = ply(
            format,
            &[
                material.clone(),
                vertices.clone(),
                edges.clone(),
                faces.clone(),
                edges.clone(),
            ],
        );
        let path = dir.write(&format!("{format}.ply"), bytes);
        let scene = load(&path, &LoadOptions::default()).unwrap();
        assert_eq!(
            scene.report.warnings.len(),
            1,
            "{:?}",
            scene.report.warnings
        );
        assert!(scene.report.warnings[0].contains("normals"));
        let m = &scene.meshes[0];
        assert_eq!(
            m.positions,
            (0..8).map(corner).collect::<Vec<_>>(),
            "{format}"
        );
        assert_eq!(m.corners, QUADS.concat(), "{format}");
        assert!(matches!(m.normal_source, NormalSource::Averaged(_)));
    }
}

/// A triangle soup without normals (every face its own three vertices) is welded by
/// position, keeping its colours per corner; NaN positions drop their faces with the
/// shared warning.
#[test]
fn triangle_soup_is_welded_and_nan_faces_dropped() {
    let dir = TempDir::new("ply-soup");
    let tris: Vec<[u32; 3]> = QUADS
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    let soup = |nan: bool| {
        let mut props = xyz("float");
        props.extend([
            P::S("uchar", "red"),
            P::S("uchar", "green"),
            P::S("uchar", "blue"),
        ]);
        let vertices = E {
            name: "vertex",
            props,
            rows: tris
                .iter()
                .flatten()
                .enumerate()
                .map(|(k, &i)| {
                    let p = if nan && k == 1 { Vec3::NAN } else { corner(i) };
                    let mut row: Vec<Vec<f64>> = p.to_array().map(|c| vec![f64::from(c)]).to_vec();
                    row.extend([vec![255.0], vec![(k / 3) as f64], vec![0.0]]);
                    row
                })
                .collect(),
        };
        let faces = E {
            name: "face",
            props: vec![P::L("uchar", "int", "vertex_indices")],
            rows: (0..tris.len())
                .map(|t| vec![(0..3).map(|k| (3 * t + k) as f64).collect()])
                .collect(),
        };
        ply("binary_little_endian", &[vertices, faces])
    };
    let scene = load_ok(&dir.write("soup.ply", soup(false)));
    let m = &scene.meshes[0];
    assert_eq!(m.positions.len(), 8);
    assert_eq!(m.facets().len(), 12);
    assert_eq!(m.edges().len(), 18);
    let colors = m.colors.as_ref().unwrap();
    assert_eq!(colors.indices.as_ref().map(Vec::len), Some(36));
    assert_eq!(colors.at(35, m.corners[35]).x, 1.0);
    assert!(
        scene.report.generated.iter().any(|g| g.contains("welded")),
        "{:?}",
        scene.report.generated
    );

    for format in ["ascii", "binary_little_endian"] {
        let mut vertices = cube_vertices("float");
        vertices.rows[7][1] = vec![f64::NAN];
        let bytes = ply(format, &[vertices, cube_faces("uchar", "int")]);
        let scene = load(&dir.write("nan.ply", bytes), &LoadOptions::default()).unwrap();
        assert_eq!(scene.meshes[0].facets().len(), 3, "{format}");
        assert_eq!(
            scene.report.warnings,
            ["PLY: dropped 3 face(s) with NaN or infinite positions"],
            "{format}"
        );
    }
    let scene = load(
        &dir.write("soup-nan.ply", soup(true)),
        &LoadOptions::default(),
    )
    .unwrap();
    assert_eq!(scene.meshes[0].facets().len(), 11);
}

/// Bad files: one-line errors starting with the path and naming the header or body line
/// (ASCII) or the element and its index (binary), never a panic; counts beyond the
/// file's bytes are refused before anything is allocated.
#[test]
fn malformed_ply_files_give_clear_errors() {
    let dir = TempDir::new("ply-bad");
    let cube = |format| {
        ply(
            format,
            &[cube_vertices("float"), cube_faces("uchar", "int")],
        )
    };
    let le = cube("binary_little_endian");
    let ascii = String::from_utf8(cube("ascii")).unwrap();
    // Header lines: ply, format, comment, element vertex (4), 3 properties, element face
    // (8), the list property, obj_info, end_header (11); the vertices are lines 12-19.
    let mut truncated = le.clone();
    truncated.truncate(le.len() - 7);
    let huge_list = {
        let mut faces = cube_faces("uint", "int");
        faces.rows[2][0] = vec![1.0, 2.0, 3.0];
        let mut b = ply("binary_little_endian", &[cube_vertices("float"), faces]);
        let body = b.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        // 8 vertices of 12 bytes, two faces of a count and 4 indices, then face 2.
        let at = body + 8 * 12 + 2 * (4 + 4 * 4);
        assert_eq!(&b[at..at + 4], &3u32.to_le_bytes());
        b[at..at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
        b
    };
    let mut out_of_range = cube_faces("uchar", "int");
    out_of_range.rows[4][0][2] = 8.0;
    let negative = {
        let mut faces = cube_faces("uchar", "int");
        faces.rows[1][0][0] = -1.0;
        faces
    };
    let no_faces = ply("binary_little_endian", &[cube_vertices("float")]);
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "short.ply",
            truncated,
            "face 5: `vertex_indices` declares 4 values, but only 9 bytes are left",
        ),
        (
            "count.ply",
            ascii
                .replace("element vertex 8", "element vertex 800")
                .into_bytes(),
            ":4: element `vertex` declares 800 entries of at least 5 bytes each",
        ),
        (
            "list.ply",
            huge_list,
            "face 2: `vertex_indices` declares 4294967295 values, but only",
        ),
        (
            "range.ply",
            ply("binary_big_endian", &[cube_vertices("float"), out_of_range]),
            "face 4: vertex index 8 is out of range (8 vertices)",
        ),
        (
            "neg.ply",
            ply("ascii", &[cube_vertices("float"), negative]),
            ":21: face 1: vertex index -1 is out of range (8 vertices)",
        ),
        (
            "word.ply",
            ascii.replacen("\n1 1 0\n", "\n1 one 0\n", 1).into_bytes(),
            ":15: vertex 3: `one` is not a number",
        ),
        (
            "short-line.ply",
            ascii.replacen("\n1 1 0\n", "\n1 1\n", 1).into_bytes(),
            ":15: vertex 3: no value for `z`",
        ),
        (
            "end.ply",
            ascii.replace("end_header\n", "").into_bytes(),
            ":11: unknown header keyword `0`",
        ),
        (
            "no-end.ply",
            b"ply\nformat ascii 1.0\nelement vertex 0\n".to_vec(),
            ":3: the header has no `end_header` line",
        ),
        (
            "format.ply",
            ascii
                .replace("format ascii", "format binary_middle_endian")
                .into_bytes(),
            ":2: unknown format `binary_middle_endian` (expected ascii",
        ),
        (
            "type.ply",
            ascii.replace("float x", "float128 x").into_bytes(),
            ":5: unknown property type `float128`",
        ),
        (
            "cloud.ply",
            no_faces,
            "8 vertices and no faces: point clouds are not drawn yet",
        ),
        ("obj.ply", b"v 0 0 0\n".to_vec(), "not a PLY file"),
        ("empty.ply", Vec::new(), "not a PLY file"),
    ];
    for (name, bytes, want) in cases {
        if want.is_empty() {
            continue;
        }
        let path = dir.write(name, bytes);
        let e = load(&path, &LoadOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with(&path.display().to_string()), "{e}");
        assert!(e.contains(want), "{name}: {e}");
        assert!(!e.contains('\n'), "{e}");
    }
    // A huge vertex count in binary is refused by the length check.
    let mut huge = le.clone();
    let at = huge
        .windows(16)
        .position(|w| w == b"element vertex 8")
        .unwrap();
    huge.splice(at..at + 16, b"element vertex 4294967295".iter().copied());
    let e = load(&dir.write("many.ply", huge), &LoadOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(":4: element `vertex` declares 4294967295 entries"),
        "{e}"
    );
    assert!(load(
        Path::new("/nonexistent/realist/x.ply"),
        &LoadOptions::default()
    )
    .is_err());
}
