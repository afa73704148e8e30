//! Reading the body of a PLY file, ASCII or binary (either byte order), into the mesh, and welding triangle soups.

use super::*;

/// Whether no vertex is used by two corners (and there is more than one face).
pub(super) fn is_soup(data: &MeshData) -> bool {
    let faces = data
        .facet_sizes
        .as_ref()
        .map_or(data.corners.len() / 3, Vec::len);
    if faces < 2 {
        return false;
    }
    let mut used = vec![false; data.positions.len()];
    for &v in &data.corners {
        match used.get_mut(v as usize) {
            Some(u) if !*u => *u = true,
            _ => return false,
        }
    }
    true
}

/// Welds the vertices of `data` at bit-identical positions (`-0.0` and `0.0` are one
/// position); per-vertex colours and UVs become per-corner channels indexed by the old
/// vertex. Returns the vertex counts before and after.
pub(super) fn weld_soup(data: &mut MeshData) -> (usize, usize) {
    let before = data.positions.len();
    let key = |p: Vec3| (p + Vec3::ZERO).to_array().map(f32::to_bits);
    let mut index: HashMap<[u32; 3], u32> = HashMap::with_capacity(before / 4);
    let mut remap = Vec::with_capacity(before);
    let mut positions = Vec::with_capacity(before / 4);
    for &p in &data.positions {
        remap.push(*index.entry(key(p)).or_insert_with(|| {
            positions.push(p);
            positions.len() as u32 - 1
        }));
    }
    let old = std::mem::take(&mut data.corners);
    data.corners = old.iter().map(|&v| remap[v as usize]).collect();
    for uv in &mut data.uvs {
        uv.indices = Some(old.clone());
    }
    if let Some(c) = data.colors.as_mut() {
        c.indices = Some(old);
    }
    data.positions = positions;
    (before, data.positions.len())
}

/// Reads an ASCII body: one element entry per line.
pub(super) fn read_ascii(
    path: &Path,
    body: &[u8],
    header: &Header,
    sink: &mut Sink,
    tracker: &Tracker,
) -> Result<(), LoadError> {
    let err = |line: usize, message: String| {
        LoadError::from(PlyError::Syntax {
            path: path.to_owned(),
            line,
            message,
        })
    };
    let table = crate::color::srgb8_decode_table();
    let mut lines = body.split(|&c| c == b'\n').enumerate();
    let mut done = 0u64;
    let mut next_line = |done: &mut u64| {
        for (i, raw) in lines.by_ref() {
            *done += raw.len() as u64 + 1;
            if !raw.trim_ascii().is_empty() {
                return Some((header.lines + 1 + i, raw));
            }
        }
        None
    };
    let layout = sink.layout;
    let mut row = [0f64; SLOTS];
    for (e, element) in header.elements.iter().enumerate() {
        if element.props.is_empty() {
            continue;
        }
        let slots = &layout.slots[e];
        let is_vertex = e == layout.vertex;
        let is_face = Some(e) == layout.face;
        // Skipped elements are read all the same (one line each), for their errors.
        for n in 0..element.count {
            let Some((line, raw)) = next_line(&mut done) else {
                let last = header.lines + body.split(|&c| c == b'\n').count()
                    - usize::from(body.ends_with(b"\n"));
                return Err(err(
                    last,
                    format!("the file ends at {} {n} of {}", element.name, element.count),
                ));
            };
            if n % 65536 == 0 {
                tracker.advance(done)?;
            }
            let what = || format!("{} {n}", element.name);
            let mut words = raw
                .split(|c| c.is_ascii_whitespace())
                .filter(|w| !w.is_empty());
            let mut word = |prop: &str| {
                words
                    .next()
                    .ok_or_else(|| err(line, format!("{}: no value for `{prop}`", what())))
            };
            let mut start = 0;
            for (p, &slot) in element.props.iter().zip(slots) {
                match p.kind {
                    Kind::Scalar(t) => {
                        let w = word(&p.name)?;
                        row[slot] = number(w, t).ok_or_else(|| {
                            err(line, format!("{}: `{}` is not a number", what(), shown(w)))
                        })?;
                    }
                    Kind::List { .. } => {
                        let w = word(&p.name)?;
                        let count = std::str::from_utf8(w)
                            .ok()
                            .and_then(|s| s.parse::<u64>().ok())
                            .ok_or_else(|| {
                                err(
                                    line,
                                    format!(
                                        "{}: `{}` is not a list count for `{}`",
                                        what(),
                                        shown(w),
                                        p.name
                                    ),
                                )
                            })?;
                        if slot == INDICES {
                            start = sink.corners.len();
                        }
                        for k in 0..count {
                            let w = word(&p.name).map_err(|_| {
                                err(
                                    line,
                                    format!(
                                        "{}: `{}` has {count} values, but the line ends after {k}",
                                        what(),
                                        p.name
                                    ),
                                )
                            })?;
                            if slot == INDICES {
                                let v = std::str::from_utf8(w)
                                    .ok()
                                    .and_then(|s| s.parse::<i64>().ok())
                                    .ok_or_else(|| {
                                        err(
                                            line,
                                            format!(
                                                "{}: `{}` is not a vertex index",
                                                what(),
                                                shown(w)
                                            ),
                                        )
                                    })?;
                                let v = sink
                                    .index(v)
                                    .map_err(|m| err(line, format!("{}: {m}", what())))?;
                                sink.corners.push(v);
                            }
                        }
                    }
                }
            }
            if words.next().is_some() {
                return Err(err(
                    line,
                    format!(
                        "{}: more values than the {} properties of `{}`",
                        what(),
                        element.props.len(),
                        element.name
                    ),
                ));
            }
            if is_vertex {
                sink.vertex(&row, table);
            } else if is_face {
                sink.sizes.push((sink.corners.len() - start) as u32);
                sink.charge_corners()?;
            }
        }
    }
    if let Some((line, _)) = next_line(&mut done) {
        sink.warnings.push(format!(
            "lines from {line} on, after the last element, ignored"
        ));
    }
    Ok(())
}

/// Up to 24 characters of a word, for a message.
pub(super) fn shown(w: &[u8]) -> String {
    String::from_utf8_lossy(w).chars().take(24).collect()
}

/// An ASCII value of type `t` (floats parsed at their own precision).
pub(super) fn number(w: &[u8], t: Scalar) -> Option<f64> {
    let s = std::str::from_utf8(w).ok()?;
    match t {
        Scalar::F32 => s.parse::<f32>().ok().map(f64::from),
        _ => s.parse::<f64>().ok(),
    }
}

/// A cursor over a binary body.
pub(super) struct Cursor<'a> {
    pub(super) bytes: &'a [u8],
    pub(super) at: usize,
    pub(super) big: bool,
}

impl Cursor<'_> {
    pub(super) fn take<const N: usize>(&mut self) -> Option<[u8; N]> {
        let end = self.at.checked_add(N)?;
        let b: [u8; N] = self.bytes.get(self.at..end)?.try_into().ok()?;
        self.at = end;
        Some(b)
    }

    pub(super) fn scalar(&mut self, t: Scalar) -> Option<f64> {
        macro_rules! read {
            ($ty:ty, $n:literal) => {{
                let b = self.take::<$n>()?;
                if self.big {
                    <$ty>::from_be_bytes(b)
                } else {
                    <$ty>::from_le_bytes(b)
                }
            }};
        }
        Some(match t {
            Scalar::I8 => f64::from(read!(i8, 1)),
            Scalar::U8 => f64::from(read!(u8, 1)),
            Scalar::I16 => f64::from(read!(i16, 2)),
            Scalar::U16 => f64::from(read!(u16, 2)),
            Scalar::I32 => f64::from(read!(i32, 4)),
            Scalar::U32 => f64::from(read!(u32, 4)),
            Scalar::F32 => f64::from(read!(f32, 4)),
            Scalar::F64 => read!(f64, 8),
        })
    }

    pub(super) fn left(&self) -> usize {
        self.bytes.len().saturating_sub(self.at)
    }
}

/// Reads a binary body; returns the bytes left after the last element, or a message
/// naming the element and its index.
pub(super) fn read_binary(
    path: &Path,
    body: &[u8],
    big: bool,
    header: &Header,
    sink: &mut Sink,
    tracker: &Tracker,
) -> Result<usize, LoadError> {
    let err = |message: String| {
        LoadError::from(PlyError::Format {
            path: path.to_owned(),
            message,
        })
    };
    let table = crate::color::srgb8_decode_table();
    let layout = sink.layout;
    let mut cur = Cursor {
        bytes: body,
        at: 0,
        big,
    };
    let mut row = [0f64; SLOTS];
    for (e, element) in header.elements.iter().enumerate() {
        let is_vertex = e == layout.vertex;
        let is_face = Some(e) == layout.face;
        let fixed = element
            .props
            .iter()
            .all(|p| matches!(p.kind, Kind::Scalar(_)));
        if !is_vertex && !is_face && fixed {
            // Skipped whole: the count check bounded count * size by the body's length.
            let size = element.min_bytes(false).saturating_mul(element.count);
            if size > cur.left() as u64 {
                return Err(err(format!(
                    "element `{}`: {} entries of {} bytes run past the end of the file",
                    element.name,
                    element.count,
                    element.min_bytes(false)
                )));
            }
            cur.at += size as usize;
            continue;
        }
        let slots = &layout.slots[e];
        for n in 0..element.count {
            if n % 65536 == 0 {
                tracker.advance(cur.at as u64)?;
            }
            let ends = |p: &Property, at: usize| {
                err(format!(
                    "{} {n}: the file ends in `{}` (byte {at} after the header, of {})",
                    element.name,
                    p.name,
                    body.len()
                ))
            };
            let mut start = 0;
            for (p, &slot) in element.props.iter().zip(slots) {
                match p.kind {
                    Kind::Scalar(t) => {
                        row[slot] = cur.scalar(t).ok_or_else(|| ends(p, cur.at))?;
                    }
                    Kind::List { count, item } => {
                        let c = cur.scalar(count).ok_or_else(|| ends(p, cur.at))?;
                        let need = (c.max(0.0) as u64).saturating_mul(item.size() as u64);
                        if c < 0.0 || need > cur.left() as u64 {
                            return Err(err(format!(
                                "{} {n}: `{}` declares {c} values, but only {} bytes are left",
                                element.name,
                                p.name,
                                cur.left()
                            )));
                        }
                        if slot == INDICES {
                            start = sink.corners.len();
                            for _ in 0..c as u64 {
                                let v = cur.scalar(item).ok_or_else(|| ends(p, cur.at))?;
                                let v = sink
                                    .index(v as i64)
                                    .map_err(|m| err(format!("{} {n}: {m}", element.name)))?;
                                sink.corners.push(v);
                            }
                        } else {
                            cur.at += need as usize;
                        }
                    }
                }
            }
            if is_vertex {
                sink.vertex(&row, table);
            } else if is_face {
                sink.sizes.push((sink.corners.len() - start) as u32);
                sink.charge_corners()?;
            }
        }
    }
    Ok(cur.left())
}
