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

mod join;
use join::*;

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

#[cfg(test)]
mod tests;
