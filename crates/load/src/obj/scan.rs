//! A validating pass over OBJ text before `tobj` sees it.
//!
//! `tobj` reports errors without line numbers, fails a whole file on an unknown index,
//! treats `l` (line) elements as faces, and can overflow on wild negative indices. This
//! pass checks every `v`/`vt`/`vn`/`f` line the way `tobj` will read it, so every error the
//! user sees names its line, and rewrites the few lines `tobj` would misread:
//!
//! - `l` elements are blanked (tobj would read them as faces); they and the `p` elements
//!   are read here instead, checked like face corners, into [`Scan::strokes`];
//! - inline `# comments` after geometry are cut;
//! - `vt u` gets its optional `v` = 0;
//! - `o`, `g`, `usemtl`, `mtllib` are normalised to `keyword name` (tobj splits at the
//!   first space of the raw line); an empty `usemtl`/`mtllib` is blanked with a warning.
//!
//! Line numbers stay the same (rewritten lines keep their place), and nothing is copied
//! unless a line actually changes.

use std::borrow::Cow;
use std::path::Path;

use super::ObjError;
use crate::progress::Tracker;
use crate::LoadError;

/// Lines between two progress checkpoints (a power of two: the test is a mask).
const CHECK_EVERY: usize = 4096;

/// Counts and findings of the pass.
#[derive(Debug, Default)]
pub(super) struct Scan<'a> {
    /// The text to give to `tobj`.
    pub text: Cow<'a, str>,
    /// The length of the text once rewritten, if a line was.
    pub rewritten_len: Option<u64>,
    pub positions: u64,
    pub texcoords: u64,
    pub normals: u64,
    pub faces: u64,
    pub corners: u64,
    pub objects: u64,
    /// `l` elements removed.
    pub line_elements: u64,
    /// `p` elements (ignored by tobj).
    pub point_elements: u64,
    /// The `p` and `l` elements, as 0-based vertex indices, grouped by the `o`/`g` and
    /// `usemtl` in force, in file order.
    pub strokes: Vec<Strokes>,
    /// First use of each material name, with its 1-based line.
    pub materials_used: Vec<(usize, String)>,
    pub warnings: Vec<String>,
}

/// The points and lines of one run of `p` and `l` elements under the same object and
/// material.
#[derive(Debug, Default, PartialEq)]
pub(super) struct Strokes {
    /// The `o` or `g` name in force (`unnamed` before any).
    pub object: String,
    /// The `usemtl` name in force.
    pub material: Option<String>,
    /// 1-based line of the first element.
    pub line: usize,
    /// File vertex indices (0-based) of the points.
    pub points: Vec<u32>,
    /// File vertex index pairs (0-based) of the line segments: an `l` of n vertices gives
    /// n - 1 segments.
    pub lines: Vec<[u32; 2]>,
}

/// Copies the source, replacing some lines, only once the first line changes.
struct Editor<'a> {
    src: &'a str,
    out: Option<String>,
    copied: usize,
}

impl<'a> Editor<'a> {
    fn replace(&mut self, start: usize, end: usize, with: &str) {
        let out = self
            .out
            .get_or_insert_with(|| String::with_capacity(self.src.len()));
        out.push_str(self.src.get(self.copied..start).unwrap_or(""));
        out.push_str(with);
        self.copied = end;
    }

    fn finish(self) -> Cow<'a, str> {
        match self.out {
            None => Cow::Borrowed(self.src),
            Some(mut out) => {
                out.push_str(self.src.get(self.copied..).unwrap_or(""));
                Cow::Owned(out)
            }
        }
    }
}

/// Checks and normalises OBJ `text` from `path`, telling `tracker` how many bytes are done
/// every [`CHECK_EVERY`] lines.
pub(super) fn scan<'a>(
    path: &Path,
    text: &'a str,
    tracker: &Tracker,
) -> Result<Scan<'a>, LoadError> {
    let mut s = Scan::default();
    let mut ed = Editor {
        src: text,
        out: None,
        copied: 0,
    };
    let mut colors: Option<(bool, usize)> = None;
    let mut used = std::collections::HashSet::new();
    let (mut object, mut material): (&str, Option<&str>) = ("unnamed", None);
    let mut start = 0usize;
    for (i, raw) in text.split('\n').enumerate() {
        if i & (CHECK_EVERY - 1) == 0 {
            tracker.advance(start as u64)?;
        }
        let line_no = i + 1;
        let end = start + raw.len();
        let line = raw.strip_suffix('\r').unwrap_or(raw);
        let err = |message: String| {
            LoadError::from(ObjError::Syntax {
                path: path.to_owned(),
                line: line_no,
                message,
            })
        };
        // A face, point or line corner that fails: a bad index names its kind and range.
        let corner_err = |(message, index): CornerError| match index {
            Some((kind, index, count)) => LoadError::from(ObjError::Index {
                path: path.to_owned(),
                line: line_no,
                kind,
                index,
                count,
            }),
            None => err(message),
        };
        let trimmed = line.trim();
        let keyword = trimmed.split_whitespace().next().unwrap_or("");
        let geometry = matches!(keyword, "v" | "vt" | "vn" | "f" | "l");
        // Geometry lines never legitimately hold '#': cut inline comments.
        let (body, commented) = match trimmed.split_once('#') {
            Some((before, _)) if geometry => (before.trim_end(), true),
            _ => (trimmed, false),
        };
        let mut words = body.split_whitespace();
        words.next();
        match keyword {
            "v" => {
                let nums: Vec<&str> = words.by_ref().take(7).collect();
                let has_color = match nums.as_slice() {
                    [_, _, _] => false,
                    [_, _, _, w] => {
                        if parse_num(w).map_err(err)? == 0.0 {
                            return Err(err("`v` has w = 0".into()));
                        }
                        false
                    }
                    [_, _, _, _, _, _] => true,
                    other => {
                        let n = if other.len() == 7 {
                            "more than 6".to_string()
                        } else {
                            other.len().to_string()
                        };
                        return Err(err(format!(
                            "`v` needs 3 numbers (4 with w, 6 with a colour), found {n}"
                        )));
                    }
                };
                for t in &nums {
                    parse_num(t).map_err(err)?;
                }
                match colors {
                    None => colors = Some((has_color, line_no)),
                    Some((c, first)) if c != has_color => {
                        return Err(err(format!(
                            "vertex colours on some `v` lines but not others (compare line {first})"
                        )));
                    }
                    Some(_) => {}
                }
                s.positions += 1;
            }
            "vt" => {
                let nums: Vec<&str> = words.by_ref().take(2).collect();
                for t in &nums {
                    parse_num(t).map_err(err)?;
                }
                match nums.as_slice() {
                    [] => return Err(err("`vt` needs at least 1 number".into())),
                    [u] => ed.replace(start, end, &format!("vt {u} 0")),
                    _ => {}
                }
                s.texcoords += 1;
            }
            "vn" => {
                let nums: Vec<&str> = words.by_ref().take(3).collect();
                if nums.len() < 3 {
                    return Err(err(format!("`vn` needs 3 numbers, found {}", nums.len())));
                }
                for t in &nums {
                    parse_num(t).map_err(err)?;
                }
                s.normals += 1;
            }
            "f" => {
                for corner in words {
                    check_corner(corner, &s).map_err(corner_err)?;
                    s.corners += 1;
                }
                s.faces += 1;
            }
            "l" | "p" => {
                let mut ix = Vec::new();
                for corner in words {
                    ix.push(vertex_index(corner, &s).map_err(corner_err)?);
                }
                let group = match s.strokes.last_mut() {
                    Some(g) if g.object == object && g.material.as_deref() == material => g,
                    _ => {
                        s.strokes.push(Strokes {
                            object: object.to_owned(),
                            material: material.map(str::to_owned),
                            line: line_no,
                            ..Strokes::default()
                        });
                        s.strokes.last_mut().expect("just pushed")
                    }
                };
                if keyword == "p" {
                    s.point_elements += 1;
                    if ix.is_empty() {
                        s.warnings
                            .push(format!("line {line_no}: `p` without vertices ignored"));
                    }
                    group.points.extend_from_slice(&ix);
                } else {
                    s.line_elements += 1;
                    if ix.len() < 2 {
                        s.warnings.push(format!(
                            "line {line_no}: `l` needs at least 2 vertices, has {}; ignored",
                            ix.len()
                        ));
                    }
                    group.lines.extend(ix.windows(2).map(|w| [w[0], w[1]]));
                    // tobj would read an `l` as a face.
                    ed.replace(start, end, "");
                    start = end + 1;
                    continue;
                }
            }
            "o" | "g" | "usemtl" | "mtllib" => {
                let name = trimmed.get(keyword.len()..).unwrap_or("").trim();
                if keyword == "o" || keyword == "g" {
                    s.objects += 1;
                    object = if name.is_empty() { "unnamed" } else { name };
                } else if name.is_empty() {
                    s.warnings.push(format!(
                        "line {line_no}: `{keyword}` without a name ignored"
                    ));
                    ed.replace(start, end, "");
                    start = end + 1;
                    continue;
                } else if keyword == "usemtl" {
                    material = Some(name);
                    if used.insert(name) {
                        s.materials_used.push((line_no, name.to_owned()));
                    }
                }
                let canonical = if name.is_empty() {
                    keyword.to_owned()
                } else {
                    format!("{keyword} {name}")
                };
                if line != canonical {
                    ed.replace(start, end, &canonical);
                }
                start = end + 1;
                continue;
            }
            _ => {}
        }
        if commented {
            ed.replace(start, end, body);
        }
        start = end + 1;
    }
    s.text = ed.finish();
    if let Cow::Owned(t) = &s.text {
        s.rewritten_len = Some(t.len() as u64);
    }
    Ok(s)
}

/// Parses a number the way tobj does (as f32; "nan", "inf" and overflow to infinity are
/// accepted here and dealt with per face later).
fn parse_num(t: &str) -> Result<f32, String> {
    t.parse::<f32>()
        .map_err(|_| format!("`{t}` is not a number"))
}

/// An index problem: a message, or (kind, index, count) for an out-of-range index.
type CornerError = (String, Option<(&'static str, i64, u64)>);

/// Checks one face corner `v`, `v/vt`, `v//vn` or `v/vt/vn` against the counts so far.
fn check_corner(corner: &str, s: &Scan) -> Result<(), CornerError> {
    let mut parts = corner.split('/');
    let kinds = [
        ("vertex", s.positions),
        ("texture coordinate", s.texcoords),
        ("normal", s.normals),
    ];
    for (k, (kind, count)) in kinds.into_iter().enumerate() {
        let part = match parts.next() {
            Some(p) => p,
            None => break,
        };
        if part.is_empty() {
            if k == 0 {
                return Err((format!("face corner `{corner}` has no vertex index"), None));
            }
            continue;
        }
        let index: i64 = part.parse().map_err(|_| {
            (
                format!("face index `{part}` is not an integer in range"),
                None,
            )
        })?;
        if index == 0 {
            return Err(("face index 0 (OBJ indices start at 1)".into(), None));
        }
        // 1..=count from the front, -1..=-count from the back.
        if index.unsigned_abs() > count {
            return Err((String::new(), Some((kind, index, count))));
        }
    }
    if parts.next().is_some() {
        return Err((
            format!("face corner `{corner}` has more than 3 parts"),
            None,
        ));
    }
    Ok(())
}

/// The 0-based file vertex of a `p` or `l` element's `v` or `v/vt`, checked as a face
/// corner is.
fn vertex_index(corner: &str, s: &Scan) -> Result<u32, CornerError> {
    check_corner(corner, s)?;
    let first = corner.split('/').next().unwrap_or("");
    let index: i64 = first
        .parse()
        .map_err(|_| (format!("index `{first}` is not an integer"), None))?;
    // check_corner keeps 1 <= |index| <= positions (< 2^32 lines in practice).
    let absolute = if index > 0 {
        index - 1
    } else {
        s.positions as i64 + index
    };
    u32::try_from(absolute).map_err(|_| (format!("vertex index `{first}` is too large"), None))
}

/// Every `v` line's position (divided by w when there is one) and colour (when the
/// lines have one) of text the pre-scan accepted, in file order: what `p` and `l`
/// elements index.
pub(super) fn file_vertices(text: &str) -> (Vec<glam::Vec3>, Vec<glam::Vec4>) {
    let (mut positions, mut colors) = (Vec::new(), Vec::new());
    for raw in text.split('\n') {
        let body = raw.split('#').next().unwrap_or("");
        let mut words = body.split_whitespace();
        if words.next() != Some("v") {
            continue;
        }
        let mut n = [0f32; 6];
        let count = n
            .iter_mut()
            .zip(words)
            .map(|(slot, w)| *slot = w.parse().unwrap_or(f32::NAN))
            .count();
        let p = glam::Vec3::new(n[0], n[1], n[2]);
        match count {
            4 => positions.push(p / n[3]),
            6 => {
                positions.push(p);
                colors.push(glam::Vec4::new(n[3], n[4], n[5], 1.0));
            }
            _ => positions.push(p),
        }
    }
    (positions, colors)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(text: &str) -> Result<Scan<'_>, String> {
        let tracker = Tracker::new(Path::new("m.obj"), None);
        scan(Path::new("m.obj"), text, &tracker).map_err(|e| e.to_string())
    }

    #[test]
    fn counts_and_borrows_when_nothing_changes() {
        let s = run("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 -1/1/1\n").unwrap();
        assert_eq!(
            (s.positions, s.texcoords, s.normals, s.faces, s.corners),
            (3, 1, 1, 1, 3)
        );
        assert!(matches!(s.text, Cow::Borrowed(_)));
    }

    #[test]
    fn rewrites_lines_tobj_misreads() {
        let s = run("v 0 0 0 # c\r\nvt 0.5\n  g  name \nl 1 1\nusemtl\nf 1 1 1").unwrap();
        assert_eq!(s.text, "v 0 0 0\nvt 0.5 0\ng name\n\n\nf 1 1 1");
        assert_eq!((s.line_elements, s.objects, s.warnings.len()), (1, 1, 1));
    }

    #[test]
    fn points_and_lines_are_read() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\ng a\nl 1 2 -1\np 3\nusemtl m\nl 2 3\nl 1\n";
        let s = run(text).unwrap();
        assert_eq!(
            s.text,
            "v 0 0 0\nv 1 0 0\nv 0 1 0\ng a\n\np 3\nusemtl m\n\n\n"
        );
        assert_eq!(s.strokes.len(), 2);
        assert_eq!(s.strokes[0].object, "a");
        assert_eq!(s.strokes[0].lines, vec![[0, 1], [1, 2]]);
        assert_eq!(s.strokes[0].points, vec![2]);
        assert_eq!(s.strokes[1].material.as_deref(), Some("m"));
        assert_eq!(s.strokes[1].lines, vec![[1, 2]]);
        assert_eq!(s.strokes[1].line, 8);
        assert!(s.warnings[0].starts_with("line 9: `l` needs at least 2"));
        assert!(run("v 0 0 0\nl 1 2")
            .unwrap_err()
            .starts_with("m.obj:2: face refers to vertex 2"));
        assert!(run("v 0 0 0\np 0").unwrap_err().contains("start at 1"));
    }

    #[test]
    fn errors_name_the_line() {
        assert_eq!(
            run("v 0 0 0\nf 1 2 3").unwrap_err(),
            "m.obj:2: face refers to vertex 2, but only 1 are defined before this line"
        );
        assert!(run("v 0 0 0\nf 1 -2 1")
            .unwrap_err()
            .starts_with("m.obj:2: face refers to vertex -2"));
        assert!(run("v 1 abc 0")
            .unwrap_err()
            .starts_with("m.obj:1: `abc` is not a number"));
        assert!(run("v 0 0\n").unwrap_err().contains("found 2"));
        assert!(run("v 0 0 0\nf 0 1 1").unwrap_err().contains("start at 1"));
        assert!(run("v 0 0 0\nf 1 1 99999999999999999999999")
            .unwrap_err()
            .contains("not an integer"));
        assert!(run("v 0 0 0\nf 1/5/9 1 1")
            .unwrap_err()
            .contains("texture coordinate 5"));
        assert!(run("v 0 0 0 1 1 1\nv 0 0 0")
            .unwrap_err()
            .contains("compare line 1"));
        assert!(run("v 0 0 0 0").unwrap_err().contains("w = 0"));
    }
}
