//! The fast path of the OBJ loader: the text is cut into line-aligned chunks parsed in
//! parallel, then merged in order into exactly the `tobj` models that [`super::scan`] and
//! `tobj` would have produced (same groups, materials, first-use vertex order and
//! fallbacks for missing indices).
//!
//! The fast path only takes files it can read without doubt, and files without points and
//! lines (`p`, `l`: the pre-scan reads those). Anything else — a line the
//! pre-scan rejects or would warn about, an index out of range, colours on some `v` lines
//! only, a non-ASCII geometry line, a parse that would need more memory than the budget has
//! left — makes it step aside ([`Parsed::Fallback`]) and the file is read again by the
//! sequential path, which finds and words the error (with its line) as it always did.
//! The fast path therefore never words an error itself, and everything it does accept is
//! accepted by the sequential path with the same result (`tests::fast_matches_tobj`).
//!
//! Cost per line: no allocation (numbers are parsed from the bytes; a correctly rounded
//! short path covers the usual `-0.0378297` decimals and anything longer goes through
//! `str::parse`, so values are bit-identical to `tobj`'s).

use std::collections::{HashMap, HashSet};
use std::ops::Range;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use super::scan::Scan;
use crate::progress::{Progress, Tracker};
use crate::{Budget, LoadError};

/// Lines between two cancellation and memory checks in a chunk (a power of two).
const CHECK_EVERY: usize = 4096;
/// Chunk sizes: a file is cut into about four chunks a thread, each within these bounds.
const MIN_CHUNK: usize = 64 << 10;
const MAX_CHUNK: usize = 1 << 20;
/// Sentinel of a missing texture or normal index in a corner (tobj's `MISSING_INDEX`).
const MISSING: u32 = u32::MAX;

/// A file's elements, joined in order, with what the pre-scan would have counted.
pub(super) struct Joined<'a> {
    pub scan: Scan<'a>,
    elements: Elements,
    events: Vec<Event<'a>>,
    lines: usize,
}

/// Why a chunk stopped.
enum Stop {
    Fallback,
    Cancelled,
}

/// An `o`/`g`, `usemtl` or `mtllib` line, where it is among the faces and elements.
struct Event<'a> {
    /// Faces, corners, texture coordinates and normals before it (in its chunk, then in the
    /// file once merged).
    faces: usize,
    corners: usize,
    texcoords: usize,
    normals: usize,
    /// 0-based line (in its chunk, then in the file).
    line: usize,
    kind: EventKind<'a>,
}

#[derive(Clone, Copy)]
enum EventKind<'a> {
    Group(&'a str),
    Usemtl(&'a str),
    Mtllib(&'a str),
}

/// One chunk's elements, indices still relative to the chunk where they must be.
#[derive(Default)]
struct Part<'a> {
    /// Lines that end in this chunk with a '\n'.
    newlines: usize,
    positions: Vec<f32>,
    colors: Vec<f32>,
    /// Whether the `v` lines have colours (all of them, or none: else a fallback).
    has_color: Option<bool>,
    texcoords: Vec<f32>,
    normals: Vec<f32>,
    /// Position, texture and normal index of each corner (0-based, file-wide, but see
    /// `relative`).
    corners: Vec<[u32; 3]>,
    arities: Vec<u32>,
    /// Corners given by a negative index: (corner, kind, index relative to the chunk's
    /// first element of that kind, possibly negative).
    relative: Vec<(u32, u8, i64)>,
    /// How many elements of each kind the file must have before the chunk for every index
    /// in it to be in range.
    need: [i64; 3],
    events: Vec<Event<'a>>,
    objects: u64,
    line_elements: u64,
    point_elements: u64,
    /// Whether the pre-scan would rewrite a line, and by how many bytes it would change
    /// the text's length (the budget is charged for the rewritten text).
    rewritten: bool,
    rewrite_delta: i64,
}

impl Part<'_> {
    /// Bytes this chunk holds (what it may allocate is charged against the budget).
    fn bytes(&self) -> u64 {
        let floats = self.positions.capacity()
            + self.colors.capacity()
            + self.texcoords.capacity()
            + self.normals.capacity();
        (floats * 4
            + self.corners.capacity() * 12
            + self.arities.capacity() * 4
            + self.relative.capacity() * 16
            + self.events.capacity() * std::mem::size_of::<Event>()) as u64
    }
}

/// Parses `text` on the rayon pool, advancing `tracker` over its bytes; `None` for a file
/// the sequential path must read.
pub(super) fn parse<'a>(
    text: &'a str,
    budget: &Budget,
    tracker: &Tracker,
) -> Result<Option<Joined<'a>>, LoadError> {
    let threads = rayon::current_num_threads().max(1);
    let size = (text.len() / (4 * threads)).clamp(MIN_CHUNK, MAX_CHUNK);
    parse_in(text, &split_sized(text, size), budget, tracker)
}

/// [`parse`] with the text cut at `chunks`.
fn parse_in<'a>(
    text: &'a str,
    chunks: &[Range<usize>],
    budget: &Budget,
    tracker: &Tracker,
) -> Result<Option<Joined<'a>>, LoadError> {
    let remaining = budget.remaining();
    let spent = AtomicU64::new(0);
    let progress = tracker.progress();
    let mut parts = Vec::with_capacity(chunks.len());
    // Waves of a few chunks each, so the bar moves (the tracker is the calling thread's).
    let wave = 2 * rayon::current_num_threads().max(1);
    for group in chunks.chunks(wave) {
        let done: Vec<Result<Part, Stop>> = group
            .par_iter()
            .map(|r| parse_chunk(&text[r.clone()], progress, &spent, remaining))
            .collect();
        for p in done {
            match p {
                Ok(p) => parts.push(p),
                Err(Stop::Cancelled) => return Err(tracker.cancelled()),
                Err(Stop::Fallback) => return Ok(None),
            }
        }
        tracker.advance(group.last().map_or(0, |r| r.end) as u64)?;
    }
    Ok(join(text.len(), parts))
}

/// Line-aligned ranges of about `size` bytes covering `text`: each but the last ends just
/// after a '\n'.
fn split_sized(text: &str, size: usize) -> Vec<Range<usize>> {
    let bytes = text.as_bytes();
    let size = size.max(1);
    let mut ranges = Vec::with_capacity(bytes.len() / size + 1);
    let mut start = 0;
    while start < bytes.len() {
        let cut = start.saturating_add(size);
        let end = match bytes.get(cut..) {
            Some(rest) => memchr::memchr(b'\n', rest).map_or(bytes.len(), |i| cut + i + 1),
            None => bytes.len(),
        };
        ranges.push(start..end);
        start = end;
    }
    ranges
}

#[inline]
fn is_space(b: u8) -> bool {
    // `char::is_whitespace` on ASCII: tab, line feed, vertical tab, form feed, carriage
    // return, space.
    matches!(b, b'\t'..=b'\r' | b' ')
}

fn trim(mut s: &[u8]) -> &[u8] {
    while let [b, rest @ ..] = s {
        if !is_space(*b) {
            break;
        }
        s = rest;
    }
    while let [rest @ .., b] = s {
        if !is_space(*b) {
            break;
        }
        s = rest;
    }
    s
}

/// The next whitespace-separated word of `s` from `*at`.
#[inline]
fn word<'b>(s: &'b [u8], at: &mut usize) -> Option<&'b [u8]> {
    let mut i = *at;
    while i < s.len() && is_space(s[i]) {
        i += 1;
    }
    if i == s.len() {
        *at = i;
        return None;
    }
    let start = i;
    while i < s.len() && !is_space(s[i]) {
        i += 1;
    }
    *at = i;
    Some(&s[start..i])
}

/// Exact powers of ten in `f32`.
const POW10: [f32; 11] = [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10];

/// Parses a number exactly as `str::parse::<f32>` does (`None` where that fails).
///
/// Plain decimals (`-12.5`, `0.0378297`) with at most 24 bits of significand and 10
/// fraction digits are one correctly rounded division of two exact `f32`s, so the result
/// is the correctly rounded value, as `parse`'s is; anything else is `parse`'s.
#[inline]
pub(super) fn parse_f32(t: &[u8]) -> Option<f32> {
    let (neg, digits) = match t {
        [b'-', rest @ ..] => (true, rest),
        [b'+', rest @ ..] => (false, rest),
        _ => (false, t),
    };
    let mut m: u64 = 0;
    let mut frac: usize = 0;
    let mut seen_dot = false;
    let mut any = false;
    let mut ok = digits.len() <= 19;
    for &b in digits {
        match b {
            b'0'..=b'9' => {
                m = m * 10 + u64::from(b - b'0');
                frac += usize::from(seen_dot);
                any = true;
            }
            b'.' if !seen_dot => seen_dot = true,
            _ => {
                ok = false;
                break;
            }
        }
    }
    if ok && any {
        while frac > 0 && m.is_multiple_of(10) && m != 0 {
            m /= 10;
            frac -= 1;
        }
        if m <= 1 << 24 && frac < POW10.len() {
            let v = m as f32 / POW10[frac];
            return Some(if neg { -v } else { v });
        }
    }
    std::str::from_utf8(t).ok()?.parse().ok()
}

/// Parses an integer exactly as `str::parse::<i64>` does.
#[inline]
fn parse_i64(t: &[u8]) -> Option<i64> {
    let (neg, digits) = match t {
        [b'-', rest @ ..] => (true, rest),
        _ => (false, t),
    };
    if !digits.is_empty() && digits.len() <= 18 && digits.iter().all(u8::is_ascii_digit) {
        let v = digits
            .iter()
            .fold(0i64, |v, &d| v * 10 + i64::from(d - b'0'));
        return Some(if neg { -v } else { v });
    }
    std::str::from_utf8(t).ok()?.parse().ok()
}

fn parse_chunk<'a>(
    text: &'a str,
    progress: &Progress,
    spent: &AtomicU64,
    remaining: u64,
) -> Result<Part<'a>, Stop> {
    let mut p = Part::default();
    let bytes = text.as_bytes();
    let mut start = 0;
    let mut charged = 0u64;
    let mut i = 0usize;
    while start < bytes.len() {
        if i & (CHECK_EVERY - 1) == 0 {
            if progress.is_cancelled() {
                return Err(Stop::Cancelled);
            }
            let now = p.bytes();
            let total = spent.fetch_add(now - charged, Ordering::Relaxed) + now - charged;
            charged = now;
            if total > remaining {
                return Err(Stop::Fallback);
            }
        }
        let end = memchr::memchr(b'\n', &bytes[start..]).map_or(bytes.len(), |n| start + n);
        let raw = &text[start..end];
        line(&mut p, raw, i)?;
        if end < bytes.len() {
            p.newlines += 1;
        }
        start = end + 1;
        i += 1;
    }
    Ok(p)
}

/// One line (`raw`, without its '\n'; `line` is its 0-based number in the chunk).
#[inline]
fn line<'a>(p: &mut Part<'a>, raw: &'a str, line: usize) -> Result<(), Stop> {
    let fallback = Err(Stop::Fallback);
    let l = raw.strip_suffix('\r').unwrap_or(raw);
    if !l.is_ascii() {
        return non_ascii(p, raw, l, line);
    }
    let bytes = trim(l.as_bytes());
    let mut at = 0;
    let Some(keyword) = word(bytes, &mut at) else {
        return Ok(());
    };
    let geometry = matches!(keyword, b"v" | b"vt" | b"vn" | b"f" | b"l");
    if !geometry {
        return match keyword {
            // Points and lines are read by the pre-scan of the sequential path.
            b"p" => fallback,
            b"o" | b"g" | b"usemtl" | b"mtllib" => {
                // ASCII throughout: byte offsets are char boundaries.
                let trimmed = std::str::from_utf8(bytes).unwrap_or("");
                named(p, raw, l, trimmed, keyword.len(), line)
            }
            _ => Ok(()),
        };
    }
    // Geometry lines never legitimately hold '#': the pre-scan cuts inline comments.
    let body = match memchr::memchr(b'#', bytes) {
        Some(hash) => {
            let body = trim(&bytes[..hash]);
            p.rewritten = true;
            p.rewrite_delta += body.len() as i64 - raw.len() as i64;
            body
        }
        None => bytes,
    };
    let commented = body.len() != bytes.len();
    match keyword {
        b"v" => {
            let mut n = [0f32; 7];
            let mut count = 0;
            while let Some(w) = word(body, &mut at) {
                if count == 7 {
                    break;
                }
                n[count] = parse_f32(w).ok_or(Stop::Fallback)?;
                count += 1;
            }
            let has_color = match count {
                3 => {
                    p.positions.extend_from_slice(&n[..3]);
                    false
                }
                4 if n[3] != 0.0 => {
                    let w = n[3];
                    p.positions
                        .extend_from_slice(&[n[0] / w, n[1] / w, n[2] / w]);
                    false
                }
                6 => {
                    p.positions.extend_from_slice(&n[..3]);
                    p.colors.extend_from_slice(&n[3..6]);
                    true
                }
                _ => return fallback,
            };
            match p.has_color {
                None => p.has_color = Some(has_color),
                Some(c) if c != has_color => return fallback,
                Some(_) => {}
            }
        }
        b"vt" => {
            let u = word(body, &mut at).ok_or(Stop::Fallback)?;
            let uv = parse_f32(u).ok_or(Stop::Fallback)?;
            let v = match word(body, &mut at) {
                Some(w) => parse_f32(w).ok_or(Stop::Fallback)?,
                None => {
                    // `vt u` becomes `vt u 0`; with a comment too the pre-scan's two
                    // rewrites of one line garble it: the sequential path says how.
                    if commented {
                        return fallback;
                    }
                    p.rewritten = true;
                    p.rewrite_delta += (u.len() + 5) as i64 - raw.len() as i64;
                    0.0
                }
            };
            p.texcoords.extend_from_slice(&[uv, v]);
        }
        b"vn" => {
            for _ in 0..3 {
                let w = word(body, &mut at).ok_or(Stop::Fallback)?;
                p.normals.push(parse_f32(w).ok_or(Stop::Fallback)?);
            }
        }
        b"f" => {
            let counts = [
                (p.positions.len() / 3) as i64,
                (p.texcoords.len() / 2) as i64,
                (p.normals.len() / 3) as i64,
            ];
            let first = p.corners.len();
            while let Some(w) = word(body, &mut at) {
                let corner = p.corners.len() as u32;
                let mut c = [MISSING; 3];
                for (k, part) in w.split(|&b| b == b'/').enumerate() {
                    if k > 2 || (k == 0 && part.is_empty()) {
                        return fallback;
                    }
                    if part.is_empty() {
                        continue;
                    }
                    let index = parse_i64(part).ok_or(Stop::Fallback)?;
                    let need = index.unsigned_abs().min(i64::MAX as u64) as i64 - counts[k];
                    p.need[k] = p.need[k].max(need);
                    c[k] = match index {
                        1..=0xFFFF_FFFE => (index - 1) as u32,
                        i if i < 0 => {
                            p.relative.push((corner, k as u8, counts[k] + i));
                            0
                        }
                        _ => return fallback,
                    };
                }
                p.corners.push(c);
            }
            p.arities.push((p.corners.len() - first) as u32);
        }
        // `l`: points and lines are read by the pre-scan of the sequential path.
        _ => return fallback,
    }
    Ok(())
}

/// A line with non-ASCII bytes: names are read as the pre-scan reads them; geometry goes
/// to the sequential path.
fn non_ascii<'a>(p: &mut Part<'a>, raw: &'a str, l: &'a str, line: usize) -> Result<(), Stop> {
    let trimmed = l.trim();
    let keyword = trimmed.split_whitespace().next().unwrap_or("");
    match keyword {
        "v" | "vt" | "vn" | "f" | "l" | "p" => Err(Stop::Fallback),
        "o" | "g" | "usemtl" | "mtllib" => named(p, raw, l, trimmed, keyword.len(), line),
        _ => Ok(()),
    }
}

/// An `o`, `g`, `usemtl` or `mtllib` line: `trimmed` starts with the keyword, `len` long.
fn named<'a>(
    p: &mut Part<'a>,
    raw: &'a str,
    l: &'a str,
    trimmed: &'a str,
    len: usize,
    line: usize,
) -> Result<(), Stop> {
    let keyword = &trimmed[..len];
    let name = trimmed[len..].trim();
    let kind = match keyword {
        "o" | "g" => {
            p.objects += 1;
            EventKind::Group(name)
        }
        // An empty `usemtl`/`mtllib` is a warning: the sequential path words it.
        _ if name.is_empty() => return Err(Stop::Fallback),
        "usemtl" => EventKind::Usemtl(name),
        _ => EventKind::Mtllib(name),
    };
    let canonical = match name.is_empty() {
        true => keyword.len(),
        false => keyword.len() + 1 + name.len(),
    };
    let is_canonical = l.len() == canonical
        && l.starts_with(keyword)
        && (name.is_empty() || l.as_bytes()[len] == b' ');
    if !is_canonical {
        p.rewritten = true;
        p.rewrite_delta += canonical as i64 - raw.len() as i64;
    }
    p.events.push(Event {
        faces: p.arities.len(),
        corners: p.corners.len(),
        texcoords: p.texcoords.len() / 2,
        normals: p.normals.len() / 3,
        line,
        kind,
    });
    Ok(())
}

/// One model to build: a run of faces with its name and material, and whether the file had
/// texture coordinates and normals when `tobj` would have built it.
struct Spec {
    name: String,
    material: Option<usize>,
    corners: Range<usize>,
    faces: Range<usize>,
    texcoords: bool,
    normals: bool,
}

/// The models found so far, and where the next one starts.
#[derive(Default)]
struct Specs {
    specs: Vec<Spec>,
    first_face: usize,
    first_corner: usize,
}

impl Specs {
    /// Ends the current model just before `at` (`tobj`'s `pop_model`).
    fn pop(&mut self, name: &str, material: Option<usize>, at: &Event) {
        self.specs.push(Spec {
            name: name.to_owned(),
            material,
            corners: self.first_corner..at.corners,
            faces: self.first_face..at.faces,
            texcoords: at.texcoords > 0,
            normals: at.normals > 0,
        });
        (self.first_face, self.first_corner) = (at.faces, at.corners);
    }
}

/// The whole file's elements.
struct Elements {
    positions: Vec<f32>,
    colors: Vec<f32>,
    texcoords: Vec<f32>,
    normals: Vec<f32>,
    corners: Vec<[u32; 3]>,
    arities: Vec<u32>,
}

/// Joins the chunks in order and resolves relative indices; `None` for a file the
/// sequential path must read.
fn join(text_len: usize, parts: Vec<Part<'_>>) -> Option<Joined<'_>> {
    let mut colors = None;
    for p in &parts {
        match (colors, p.has_color) {
            (_, None) => {}
            (None, c) => colors = c,
            (Some(a), Some(b)) if a != b => return None,
            _ => {}
        }
    }
    let sum = |f: &dyn Fn(&Part) -> usize| parts.iter().map(f).sum::<usize>();
    let mut e = Elements {
        positions: Vec::with_capacity(sum(&|p| p.positions.len())),
        colors: Vec::with_capacity(sum(&|p| p.colors.len())),
        texcoords: Vec::with_capacity(sum(&|p| p.texcoords.len())),
        normals: Vec::with_capacity(sum(&|p| p.normals.len())),
        corners: Vec::with_capacity(sum(&|p| p.corners.len())),
        arities: Vec::with_capacity(sum(&|p| p.arities.len())),
    };
    let mut scan = Scan::default();
    let mut events = Vec::new();
    let mut lines = 0usize;
    let mut rewritten: Option<i64> = None;
    for mut p in parts {
        let base = [
            e.positions.len() / 3,
            e.texcoords.len() / 2,
            e.normals.len() / 3,
        ];
        if (0..3).any(|k| p.need[k] > base[k] as i64) {
            return None;
        }
        let corner_base = e.corners.len();
        for &(corner, kind, rel) in &p.relative {
            let index = u32::try_from(base[kind as usize] as i64 + rel)
                .ok()
                .filter(|&i| i != MISSING)?;
            p.corners[corner as usize][kind as usize] = index;
        }
        for mut ev in p.events.drain(..) {
            ev.faces += e.arities.len();
            ev.corners += corner_base;
            ev.texcoords += base[1];
            ev.normals += base[2];
            ev.line += lines;
            events.push(ev);
        }
        lines += p.newlines;
        e.positions.append(&mut p.positions);
        e.colors.append(&mut p.colors);
        e.texcoords.append(&mut p.texcoords);
        e.normals.append(&mut p.normals);
        e.corners.append(&mut p.corners);
        e.arities.append(&mut p.arities);
        scan.objects += p.objects;
        scan.line_elements += p.line_elements;
        scan.point_elements += p.point_elements;
        if p.rewritten {
            rewritten = Some(rewritten.unwrap_or(0) + p.rewrite_delta);
        }
    }
    scan.rewritten_len = rewritten.map(|d| (text_len as i64 + d).max(0) as u64);
    scan.positions = (e.positions.len() / 3) as u64;
    scan.texcoords = (e.texcoords.len() / 2) as u64;
    scan.normals = (e.normals.len() / 3) as u64;
    scan.faces = e.arities.len() as u64;
    scan.corners = e.corners.len() as u64;
    if u32::try_from(e.corners.len()).is_err() {
        return None;
    }
    Some(Joined {
        scan,
        elements: e,
        events,
        lines,
    })
}

impl<'a> Joined<'a> {
    /// The models as `tobj` builds them, and the materials of the libraries (loaded
    /// through `load_mtl`, in file order); the pre-scan's list of used materials is added
    /// to the returned scan.
    pub(super) fn assemble(
        self,
        load_mtl: impl Fn(&Path) -> tobj::MTLLoadResult,
    ) -> (Vec<tobj::Model>, Vec<tobj::Material>, Scan<'a>) {
        let Joined {
            mut scan,
            elements: e,
            events,
            lines,
        } = self;

        // `tobj`'s state machine over the named lines, in file order.
        let mut materials: Vec<tobj::Material> = Vec::new();
        let mut names: HashMap<String, usize> = HashMap::new();
        let mut used = HashSet::new();
        let mut specs = Specs::default();
        let mut name = "unnamed_object";
        let mut material = None;
        for ev in &events {
            let pending = ev.faces > specs.first_face;
            match ev.kind {
                EventKind::Group(n) => {
                    if pending {
                        specs.pop(name, material, ev);
                    }
                    name = match n {
                        "" => "unnamed_object",
                        n => n,
                    };
                }
                EventKind::Mtllib(file) => {
                    // The loader turns every failure into a warning and an empty library.
                    if let Ok((mut mats, map)) = load_mtl(Path::new(file)) {
                        let offset = materials.len();
                        materials.append(&mut mats);
                        names.extend(map.into_iter().map(|(k, v)| (k, v + offset)));
                    }
                }
                EventKind::Usemtl(n) => {
                    if used.insert(n) {
                        scan.materials_used.push((ev.line + 1, n.to_owned()));
                    }
                    let new = names.get(n).copied();
                    if material != new && pending {
                        specs.pop(name, material, ev);
                    }
                    material = new;
                }
            }
        }
        let end = Event {
            faces: e.arities.len(),
            corners: e.corners.len(),
            texcoords: e.texcoords.len() / 2,
            normals: e.normals.len() / 3,
            line: lines,
            kind: EventKind::Group(""),
        };
        specs.pop(name, material, &end);
        let specs = specs.specs;
        let models = specs.par_iter().map(|s| build(&e, s)).collect();
        (models, materials, scan)
    }
}

/// First-use numbering of one index kind within a model: dense for a model that uses a
/// good share of the file's elements, hashed for a small one.
enum Remap {
    Dense(Vec<u32>),
    Sparse(HashMap<u32, u32>),
}

impl Remap {
    fn new(model_corners: usize, elements: usize) -> Self {
        match model_corners.saturating_mul(16) >= elements {
            true => Remap::Dense(vec![0; elements]),
            false => Remap::Sparse(HashMap::new()),
        }
    }

    /// The model's number for file element `i`, given `next` if it is new (then `true`).
    #[inline]
    fn get_or_insert(&mut self, i: u32, next: u32) -> (u32, bool) {
        match self {
            Remap::Dense(v) => match v[i as usize] {
                0 => {
                    v[i as usize] = next + 1;
                    (next, true)
                }
                n => (n - 1, false),
            },
            Remap::Sparse(m) => match m.get(&i) {
                Some(&n) => (n, false),
                None => {
                    m.insert(i, next);
                    (next, true)
                }
            },
        }
    }
}

/// One model as `tobj::export_faces_multi_index` builds it (without triangulation).
fn build(e: &Elements, s: &Spec) -> tobj::Model {
    let corners = &e.corners[s.corners.clone()];
    let arities = &e.arities[s.faces.clone()];
    let mut m = tobj::Mesh {
        material_id: s.material,
        ..Default::default()
    };
    m.indices.reserve_exact(corners.len());
    let mut pos = Remap::new(corners.len(), e.positions.len() / 3);
    let mut tex = s
        .texcoords
        .then(|| Remap::new(corners.len(), e.texcoords.len() / 2));
    let mut nor = s
        .normals
        .then(|| Remap::new(corners.len(), e.normals.len() / 3));
    if tex.is_some() {
        m.texcoord_indices.reserve_exact(corners.len());
    }
    if nor.is_some() {
        m.normal_indices.reserve_exact(corners.len());
    }
    for c in corners {
        let next = (m.positions.len() / 3) as u32;
        let (i, new) = pos.get_or_insert(c[0], next);
        if new {
            let v = c[0] as usize * 3;
            m.positions.extend_from_slice(&e.positions[v..v + 3]);
            if !e.colors.is_empty() {
                m.vertex_color.extend_from_slice(&e.colors[v..v + 3]);
            }
        }
        m.indices.push(i);
        if let Some(tex) = &mut tex {
            attribute(
                tex,
                c[1],
                &e.texcoords,
                2,
                &mut m.texcoords,
                &mut m.texcoord_indices,
            );
        }
        if let Some(nor) = &mut nor {
            attribute(
                nor,
                c[2],
                &e.normals,
                3,
                &mut m.normals,
                &mut m.normal_indices,
            );
        }
    }
    if arities.iter().any(|&a| a != 3) {
        m.face_arities = arities.to_vec();
    }
    tobj::Model {
        mesh: m,
        name: s.name.clone(),
    }
}

/// A corner's texture coordinate or normal (`n` floats each), with `tobj`'s fallbacks for
/// a missing index: the file's first element for the model's first corner, else the
/// previous corner's.
#[inline]
fn attribute(
    remap: &mut Remap,
    index: u32,
    file: &[f32],
    n: usize,
    values: &mut Vec<f32>,
    indices: &mut Vec<u32>,
) {
    let index = match (index, indices.last()) {
        (MISSING, Some(&last)) => {
            indices.push(last);
            return;
        }
        (MISSING, None) => 0,
        (i, _) => i,
    };
    let (i, new) = remap.get_or_insert(index, (values.len() / n) as u32);
    if new {
        let at = index as usize * n;
        values.extend_from_slice(&file[at..at + n]);
    }
    indices.push(i);
}

#[cfg(test)]
mod tests;
