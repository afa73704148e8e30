//! The fast path against the sequential one (pre-scan, then `tobj`), which stays the
//! reference: same models, bit for bit, or a fallback.

use std::io::Cursor;
use std::path::Path;

use super::*;
use crate::obj::scan;

/// A material loader: `m.mtl` has materials `a` and `b`, `n.mtl` has `b` (again) and `c`,
/// anything else is empty.
fn libs(p: &Path) -> tobj::MTLLoadResult {
    let lib = |names: &[&str]| {
        let mats: Vec<tobj::Material> = names
            .iter()
            .map(|n| tobj::Material {
                name: (*n).into(),
                ..Default::default()
            })
            .collect();
        let map = names
            .iter()
            .enumerate()
            .map(|(i, n)| ((*n).into(), i))
            .collect();
        Ok((mats, map))
    };
    match p.to_str() {
        Some("m.mtl") => lib(&["a", "b"]),
        Some("n.mtl") => lib(&["b", "c"]),
        _ => Ok(Default::default()),
    }
}

/// What a path made of a text: models, material names, and the pre-scan's findings.
#[derive(Debug, PartialEq)]
struct Outcome {
    models: Vec<String>,
    materials: Vec<String>,
    counts: [u64; 8],
    used: Vec<(usize, String)>,
    rewritten: Option<u64>,
}

fn bits(v: &[f32]) -> Vec<u32> {
    v.iter().map(|f| f.to_bits()).collect()
}

fn describe(models: &[tobj::Model], materials: &[tobj::Material], s: &scan::Scan) -> Outcome {
    Outcome {
        models: models
            .iter()
            .map(|m| {
                let x = &m.mesh;
                format!(
                    "{} {:?} p{:?} c{:?} n{:?} t{:?} i{:?} f{:?} ti{:?} ni{:?}",
                    m.name,
                    x.material_id,
                    bits(&x.positions),
                    bits(&x.vertex_color),
                    bits(&x.normals),
                    bits(&x.texcoords),
                    x.indices,
                    x.face_arities,
                    x.texcoord_indices,
                    x.normal_indices
                )
            })
            .collect(),
        materials: materials.iter().map(|m| m.name.clone()).collect(),
        counts: [
            s.positions,
            s.texcoords,
            s.normals,
            s.faces,
            s.corners,
            s.objects,
            s.line_elements,
            s.point_elements,
        ],
        used: s.materials_used.clone(),
        rewritten: s.rewritten_len,
    }
}

fn sequential(text: &str) -> Result<Outcome, String> {
    let path = Path::new("m.obj");
    let tracker = Tracker::new(path, None);
    let s = scan::scan(path, text, &tracker).map_err(|e| e.to_string())?;
    if !s.warnings.is_empty() {
        return Err(format!("warnings: {:?}", s.warnings));
    }
    let opts = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ..Default::default()
    };
    let (models, materials) = tobj::load_obj_buf(&mut Cursor::new(s.text.as_bytes()), &opts, libs)
        .map_err(|e| format!("tobj: {e}"))?;
    Ok(describe(&models, &materials.unwrap_or_default(), &s))
}

/// The fast path with chunks of about `size` bytes (`None` for a fallback).
fn fast(text: &str, size: usize) -> Option<Outcome> {
    let tracker = Tracker::new(Path::new("m.obj"), None);
    let budget = Budget::new(Path::new("m.obj"), u64::MAX);
    let joined = parse_in(text, &split_sized(text, size), &budget, &tracker).unwrap()?;
    let (models, materials, s) = joined.assemble(libs);
    Some(describe(&models, &materials, &s))
}

/// Either the fast path steps aside, or it agrees with the sequential path, for every
/// chunk size; and a file the sequential path refuses is never taken.
#[track_caller]
fn check(text: &str) -> Option<Outcome> {
    check_sized(text, &[1, 7, 64, 1 << 20])
}

#[track_caller]
fn check_sized(text: &str, sizes: &[usize]) -> Option<Outcome> {
    let reference = sequential(text);
    let mut taken = None;
    for &size in sizes {
        match (fast(text, size), &reference) {
            (None, _) => {}
            (Some(got), Ok(want)) => {
                assert_eq!(&got, want, "chunks of {size}:\n{text}");
                taken = Some(got);
            }
            (Some(_), Err(e)) => panic!("fast path took what fails with {e}:\n{text}"),
        }
    }
    taken
}

#[test]
fn floats_parse_as_std_does() {
    let cases = [
        "0",
        "-0",
        "+0",
        "1",
        "-1",
        "1.",
        ".5",
        "-.5",
        "+.5",
        ".",
        "-",
        "+",
        "",
        "1.2.3",
        "0.0378297",
        "-0.0378297",
        "16777216",
        "16777217",
        "16777215.5",
        "0.1",
        "0.3",
        "1e5",
        "1E-3",
        "inf",
        "-inf",
        "nan",
        "NaN",
        "infinity",
        "1_0",
        "0x10",
        "00001.5",
        "1.0000000000",
        "123456789012345678901234567890",
        "0.00000000001",
        "3.4e38",
        "1e39",
        "9999999999",
        "0.9999999999",
        "12345.678",
        "--1",
        "1-",
        " 1",
    ];
    for c in cases {
        let want = c.parse::<f32>().ok().map(f32::to_bits);
        assert_eq!(parse_f32(c.as_bytes()).map(f32::to_bits), want, "{c:?}");
    }
    // Random decimals of every shape the short path takes, and some it does not.
    let mut x = 0x2545_F491_4F6C_DD1Du64;
    for _ in 0..200_000 {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        let int = x % 100_000_000;
        let frac_digits = (x >> 32) % 12;
        let frac = (x >> 40) % 10u64.pow(frac_digits as u32).max(1);
        let sign = if x & 1 == 1 { "-" } else { "" };
        let s = match frac_digits {
            0 => format!("{sign}{}", int % 100_000),
            d => format!("{sign}{}.{frac:0w$}", int % 1000, w = d as usize),
        };
        let want = s.parse::<f32>().unwrap().to_bits();
        assert_eq!(parse_f32(s.as_bytes()).map(f32::to_bits), Some(want), "{s}");
    }
}

#[test]
fn integers_parse_as_std_does() {
    for c in [
        "1",
        "-1",
        "+1",
        "0",
        "-0",
        "",
        "-",
        "12a",
        "999999999999999999",
        "9223372036854775807",
        "9223372036854775808",
        "-9223372036854775808",
        "1.0",
    ] {
        assert_eq!(parse_i64(c.as_bytes()), c.parse::<i64>().ok(), "{c:?}");
    }
}

#[test]
fn fast_matches_tobj() {
    let texts = [
        // Quads, negative indices, groups and objects.
        "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\ng first\nf -4 -3 -2 -1\n\
         v 0 0 1\nv 1 0 1\nv 0 1 1\no second\nf 5 6 7\nf 1 2\n",
        // Materials across libraries, with a redefinition and an unknown name.
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\nusemtl a\nf 3 2 1\n\
         usemtl nope\nf 1 2 3\nmtllib n.mtl\nusemtl b\nf 1 2 3\ng\nusemtl c\nf 1 3 2\n\
         usemtl b\ng  other   name  \nf 2 3 1\n",
        // Missing texture and normal indices, first and later corners.
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.75\nvt 0.5\nvn 0 0 1\nvn 0 1 0\n\
         f 1 2/2/1 3//2\nf 1/1/2 2 3\ng x\nf 3 2 1\nf -1/-1/-1 -2/-2/-2 -3//-1\n",
        // Colours, w, comments, CRLF, blank and unknown lines, exotic whitespace.
        "# c\r\nv 0 0 0 1 0 0\r\nv 2 0 0 0 1 0 # x\r\n\tv\x0b0 2 0 0 0 1\r\n\r\ns 1\n\
         vn 0 0 1 extra\nf 1//1 2//1 3//1 # tri\nvp 1 2\n",
        "v 0 0 0 2\nv 1 0 0 0.5\nv 0 1 0 -1\nf 1 2 3\nf\nf 1 2 3 1 2\n",
        "v 1e3 -2E-2 +.5\nv nan inf -inf\nv 0.1 0.2 0.3\nf 1 2 3\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nusemtl ünïcode\ng grüppe\nf 1 2 3\no\n",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0 0\nf 1/1 2/1 3/1\n",
        "",
        "\n\n",
        "v 0 0 0",
    ];
    for t in texts {
        assert!(check(t).is_some(), "not taken:\n{t}");
    }
}

#[test]
fn what_the_pre_scan_refuses_or_warns_about_falls_back() {
    let texts = [
        "v 0 0 0\nf 1 2 3",
        "v 0 0 0\nf 1 -2 1",
        "v 1 abc 0",
        "v 0 0\n",
        "v 0 0 0\nf 0 1 1",
        "v 0 0 0\nf 1 1 99999999999999999999999",
        "v 0 0 0\nf 1/5/9 1 1",
        "v 0 0 0 1 1 1\nv 0 0 0",
        "v 0 0 0 0",
        "v 0 0 0 1 1",
        "v 0 0 0 1 1 1 1",
        "vt\n",
        "vn 0 0\n",
        "v 0 0 0\nf 1/1/1/1 1 1",
        "v 0 0 0\nf /1 1 1",
        "usemtl\n",
        "mtllib   \n",
        "vt 0.5 # c\n",
        "v 0 0 0\nf 1 1 1\nv\u{a0}1 2 3\n",
        "v 0 0 0\nf 4294967296 1 1\n",
        // Points and lines are read by the pre-scan.
        "v 0 0 0\nv 1 0 0\nl 1 2\n",
        "v 0 0 0\np 1\n",
    ];
    for t in texts {
        assert!(check(t).is_none(), "taken:\n{t}");
    }
}

/// Random files from a small grammar, good and bad lines mixed, at tiny chunk sizes.
#[test]
fn random_files_agree() {
    let mut x = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = |n: u64| {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x % n
    };
    let mut taken = 0;
    for _ in 0..3000 {
        let colors = next(4) == 0;
        let mut text = String::new();
        for _ in 0..8 {
            text += if colors {
                "v 1 2 3 0 0 1\n"
            } else {
                "v 1 2 3\n"
            };
        }
        for _ in 0..next(40) {
            let line = match next(24) {
                0..=5 if colors => format!("v {} {} 0 1 0.5 0", next(9), next(9)),
                0..=5 => format!("v {} {}.5 -{}", next(9), next(9), next(9)),
                6 => format!("vt 0.{} {}", next(99), next(2)),
                7 => format!("vt 0.{}", next(99)),
                8 => format!("vn 0 0 {}", next(2)),
                9..=14 => {
                    let mut f = "f".to_string();
                    for _ in 0..next(6) {
                        let i = [next(8) as i64 + 1, -(next(8) as i64) - 1, 0]
                            [next(3) as usize % 2 + usize::from(next(50) == 0)];
                        match next(4) {
                            0 => f += &format!(" {i}"),
                            1 => f += &format!(" {i}/{}", next(4) as i64 - 2),
                            2 => f += &format!(" {i}//{}", next(4) as i64 - 1),
                            _ => f += &format!(" {i}/{}/{}", next(3) + 1, next(3) + 1),
                        }
                    }
                    f
                }
                15 => ["g a", "o b", "g", "g  c d ", "o a"][next(5) as usize].into(),
                16 => ["usemtl a", "usemtl b", "usemtl c", "usemtl  z "][next(4) as usize].into(),
                17 => ["mtllib m.mtl", "mtllib n.mtl", "mtllib x.mtl"][next(3) as usize].into(),
                // (`l` and `p` send a file to the sequential path: see above.)
                18 => "s off".into(),
                19 => "# comment".into(),
                20 => format!("f 1 2 3 # {}", next(9)),
                21 if next(10) == 0 => "v 1 2".into(),
                22 => "s 1".into(),
                _ => String::new(),
            };
            text += &line;
            text += if next(5) == 0 { "\r\n" } else { "\n" };
        }
        taken += usize::from(check(&text).is_some());
    }
    assert!(taken > 300, "only {taken} files taken by the fast path");
}

#[test]
fn a_budget_too_small_for_the_chunks_falls_back() {
    let text: String = (0..50_000).map(|i| format!("v {i} 0 0\n")).collect();
    let tracker = Tracker::new(Path::new("m.obj"), None);
    let budget = Budget::new(Path::new("m.obj"), 100_000);
    assert!(parse(&text, &budget, &tracker).unwrap().is_none());
}

/// Every OBJ model of the shared folder (corpus files included) agrees, or falls back.
#[test]
#[cfg_attr(not(realist_shared), ignore = "needs REALIST_SHARED")]
fn shared_objs_agree() {
    let shared = crate::tests::shared("shared_objs_agree");
    let mut files = Vec::new();
    let mut dirs = vec![shared.join("models"), shared.join("corpus")];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap().flatten() {
            let p = entry.path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|e| e.eq_ignore_ascii_case("obj")) {
                files.push(p);
            }
        }
    }
    let mut taken = 0;
    for f in &files {
        let bytes = std::fs::read(f).unwrap();
        let text = String::from_utf8_lossy(&bytes);
        taken += usize::from(check_sized(&text, &[4096, 1 << 16, 1 << 20]).is_some());
    }
    eprintln!("{taken} of {} files taken by the fast path", files.len());
    assert!(taken >= 10, "{taken} of {}", files.len());
}
