//! `EXT_meshopt_compression` and `KHR_meshopt_compression`: bufferViews whose bytes are
//! meshoptimizer-compressed data elsewhere in a buffer.
//!
//! The view's extension object `{buffer, byteOffset, byteLength, byteStride, count, mode,
//! filter}` names the compressed bytes; they decode to `count × byteStride` bytes, which
//! are the view's own contents (the view's `buffer` is then usually a URI-less placeholder
//! `{"byteLength": n}`, possibly tagged `fallback: true`, that is never read). Modes:
//! ATTRIBUTES (the vertex codec: byteStride a multiple of 4 up to 256; EXT takes the v0
//! stream only, KHR v0 and v1), TRIANGLES (count a multiple of 3) and INDICES (byteStride
//! 2 or 4, no filter). Filters after ATTRIBUTES: OCTAHEDRAL (stride 4 or 8), QUATERNION
//! (8), EXPONENTIAL (a multiple of 4) and, KHR only, COLOR (4 or 8).
//!
//! The decoding itself is `meshoptimizer-rs` (a pure-Rust port of meshoptimizer 1.3's
//! codecs, without its SIMD module so no unsafe code is compiled); the checks of the
//! extension object against the view, the memory budget and the error messages are here.
//! The decoded size is charged to the load's budget before it is allocated, and the crate's
//! own work limit bounds the time.

use meshoptimizer_rs::codec::{self, Mode};
use meshoptimizer_rs::{Limits, Workspace};
use serde_json::Value;

use crate::{catch_decoder, Budget, LoadError};

/// The ratified extension.
pub const EXT: &str = "EXT_meshopt_compression";
/// Its Khronos successor (adds the v1 attribute stream and the COLOR filter).
pub const KHR: &str = "KHR_meshopt_compression";

/// A filter applied to ATTRIBUTES data after decoding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filter {
    None,
    Octahedral,
    Quaternion,
    Exponential,
    Color,
}

/// A bufferView's meshopt extension object, checked for shape (not yet against the data).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Compressed {
    /// Which extension (for messages and the rules that differ).
    pub extension: &'static str,
    pub buffer: usize,
    pub byte_offset: u64,
    pub byte_length: u64,
    pub byte_stride: usize,
    pub count: u64,
    pub mode: Mode,
    pub filter: Filter,
}

impl Compressed {
    /// The extension object of a bufferView, if it has one of the two: `Err` says what is
    /// wrong with it.
    pub fn of(extensions: Option<&serde_json::Map<String, Value>>) -> Option<Result<Self, String>> {
        let extensions = extensions?;
        let (extension, object) = [KHR, EXT]
            .into_iter()
            .find_map(|name| extensions.get(name).map(|v| (name, v)))?;
        Some(Self::parse(extension, object).map_err(|e| format!("{extension}: {e}")))
    }

    fn parse(extension: &'static str, v: &Value) -> Result<Self, String> {
        let int = |key: &str, required: bool| -> Result<Option<u64>, String> {
            match v.get(key) {
                None if required => Err(format!("missing {key}")),
                None => Ok(None),
                Some(x) => x
                    .as_u64()
                    .map(Some)
                    .ok_or_else(|| format!("{key} is not a non-negative integer")),
            }
        };
        let khr = extension == KHR;
        let buffer = int("buffer", true)?.unwrap_or(0);
        let byte_offset = int("byteOffset", false)?.unwrap_or(0);
        let byte_length = int("byteLength", true)?.unwrap_or(0);
        let byte_stride = int("byteStride", true)?.unwrap_or(0);
        let count = int("count", true)?.unwrap_or(0);
        let mode = match v.get("mode").and_then(Value::as_str) {
            Some("ATTRIBUTES") => Mode::Attributes,
            Some("TRIANGLES") => Mode::Triangles,
            Some("INDICES") => Mode::Indices,
            Some(other) => return Err(format!("unknown mode {other:?}")),
            None => return Err("missing mode".into()),
        };
        let filter = match v.get("filter").and_then(Value::as_str) {
            None | Some("NONE") => Filter::None,
            Some("OCTAHEDRAL") => Filter::Octahedral,
            Some("QUATERNION") => Filter::Quaternion,
            Some("EXPONENTIAL") => Filter::Exponential,
            Some("COLOR") if khr => Filter::Color,
            Some(other) => return Err(format!("unknown filter {other:?}")),
        };
        let stride_ok = match mode {
            Mode::Attributes => byte_stride.is_multiple_of(4) && (4..=256).contains(&byte_stride),
            Mode::Triangles | Mode::Indices => byte_stride == 2 || byte_stride == 4,
        };
        if !stride_ok {
            return Err(format!(
                "byteStride {byte_stride} is not valid for {mode:?}"
            ));
        }
        if mode == Mode::Triangles && !count.is_multiple_of(3) {
            return Err(format!("TRIANGLES count {count} is not a multiple of 3"));
        }
        let filter_ok = match filter {
            Filter::None => true,
            _ if mode != Mode::Attributes => false,
            Filter::Octahedral | Filter::Color => byte_stride == 4 || byte_stride == 8,
            Filter::Quaternion => byte_stride == 8,
            Filter::Exponential => byte_stride.is_multiple_of(4),
        };
        if !filter_ok {
            return Err(format!(
                "filter {filter:?} does not go with {mode:?} and byteStride {byte_stride}"
            ));
        }
        Ok(Self {
            extension,
            buffer: usize::try_from(buffer).unwrap_or(usize::MAX),
            byte_offset,
            byte_length,
            byte_stride: byte_stride as usize,
            count,
            mode,
            filter,
        })
    }

    /// Bytes the data decodes to (`count × byteStride`), if that fits.
    pub fn decoded_len(&self) -> Option<usize> {
        self.count
            .checked_mul(self.byte_stride as u64)
            .filter(|&n| n <= isize::MAX as u64)
            .map(|n| n as usize)
    }
}

/// Decodes `source` (the compressed bytes) as described by `c`, charging the result to
/// `budget` (as `what`) first. The outer error is the budget's; the inner one says why the
/// data cannot be decoded.
pub fn decode(
    c: &Compressed,
    source: &[u8],
    budget: &Budget,
    what: &str,
) -> Result<Result<Vec<u8>, String>, LoadError> {
    let Some(len) = c.decoded_len() else {
        return Ok(Err(format!(
            "count {} × byteStride {} is too large",
            c.count, c.byte_stride
        )));
    };
    budget.charge(len as u64, || format!("{what} ({len} bytes decoded)"))?;
    Ok(decode_unbudgeted(c, source, len))
}

/// [`decode`] without the budget (the size `len` = `count × byteStride` is checked by the
/// caller); a panic inside the decoder is an error.
pub fn decode_unbudgeted(c: &Compressed, source: &[u8], len: usize) -> Result<Vec<u8>, String> {
    let (count, stride) = (len / c.byte_stride.max(1), c.byte_stride);
    let version = |headers: &[u8]| match source.first() {
        Some(&b) if headers.contains(&(b & 0xf0)) => Ok(b & 0x0f),
        Some(&b) => Err(format!("unexpected header byte {b:#04x}")),
        None => Err("no compressed data".to_string()),
    };
    match c.mode {
        Mode::Attributes => {
            let v = version(&[0xa0])?;
            let allowed = if c.extension == KHR { 1 } else { 0 };
            if v > allowed {
                return Err(format!(
                    "attribute stream version {v} is not allowed by {}",
                    c.extension
                ));
            }
        }
        Mode::Triangles => {
            version(&[0xe0])?;
        }
        Mode::Indices => {
            version(&[0xd0])?;
        }
    }
    catch_decoder(|| {
        let mut ws = Workspace::new(Limits {
            // The output is already charged to the load's budget; the crate's scratch is
            // small and its work limit bounds the time.
            max_bytes: len.saturating_add(1 << 20),
            max_work: (len as u64)
                .saturating_mul(8)
                .saturating_add(source.len() as u64 * 8)
                + (1 << 20),
        });
        let err = |e: meshoptimizer_rs::Error| format!("{:?} data: {e}", c.mode);
        let mut out = match c.mode {
            Mode::Attributes => codec::decode_vertex_buffer(count, stride, source, &mut ws),
            Mode::Triangles => codec::decode_index_buffer(count, stride, source, &mut ws),
            Mode::Indices => codec::decode_index_sequence(count, stride, source, &mut ws),
        }
        .map_err(err)?;
        let filtered = match c.filter {
            Filter::None => Ok(()),
            Filter::Octahedral => codec::decode_filter_oct(&mut out, count, stride, &mut ws),
            Filter::Quaternion => codec::decode_filter_quat(&mut out, count, stride, &mut ws),
            Filter::Exponential => codec::decode_filter_exp(&mut out, count, stride, &mut ws),
            Filter::Color => codec::decode_filter_color(&mut out, count, stride, &mut ws),
        };
        filtered.map_err(|e| format!("{:?} filter: {e}", c.filter))?;
        if out.len() != len {
            return Err(format!("decoded {} bytes, expected {len}", out.len()));
        }
        Ok(out)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn parse(ext: &str, v: Value) -> Result<Compressed, String> {
        let mut map = serde_json::Map::new();
        map.insert(ext.into(), v);
        Compressed::of(Some(&map)).expect("has the extension")
    }

    #[test]
    fn extension_objects_are_checked() {
        let ok = json!({"buffer": 0, "byteLength": 10, "byteStride": 8, "count": 3,
            "mode": "ATTRIBUTES", "filter": "QUATERNION"});
        let c = parse(EXT, ok.clone()).unwrap();
        assert_eq!(
            (c.count, c.byte_stride, c.filter),
            (3, 8, Filter::Quaternion)
        );
        assert_eq!(c.decoded_len(), Some(24));
        let mut colour = ok.clone();
        colour["filter"] = json!("COLOR");
        assert!(parse(EXT, colour.clone())
            .unwrap_err()
            .contains("unknown filter"));
        assert_eq!(parse(KHR, colour).unwrap().filter, Filter::Color);
        let mut tri = ok.clone();
        tri["mode"] = json!("TRIANGLES");
        tri["filter"] = json!("NONE");
        tri["byteStride"] = json!(2);
        assert!(parse(KHR, tri.clone()).is_ok());
        tri["count"] = json!(4);
        assert!(parse(KHR, tri).unwrap_err().contains("multiple of 3"));
        let mut wide = ok.clone();
        wide["byteStride"] = json!(260);
        assert!(parse(EXT, wide).unwrap_err().contains("byteStride 260"));
        let mut huge = ok;
        huge["count"] = json!(u64::MAX);
        assert_eq!(parse(EXT, huge).unwrap().decoded_len(), None);
    }

    #[test]
    fn round_trip_and_corruption() {
        // Four u16x4 vertices through the crate's encoder (v0 and v1), then decoded here.
        let data: Vec<u8> = (0..32u8).map(|i| i.wrapping_mul(37)).collect();
        for (extension, version) in [(EXT, 0), (KHR, 1)] {
            let encoding = codec::VertexEncoding::new(version, 2).unwrap();
            let mut ws = Workspace::default();
            let encoded = codec::encode_vertex_buffer(&data, 4, 8, encoding, &mut ws).unwrap();
            let c = Compressed {
                extension,
                buffer: 0,
                byte_offset: 0,
                byte_length: encoded.len() as u64,
                byte_stride: 8,
                count: 4,
                mode: Mode::Attributes,
                filter: Filter::None,
            };
            assert_eq!(decode_unbudgeted(&c, &encoded, 32).unwrap(), data);
            let truncated = &encoded[..encoded.len() / 2];
            assert!(decode_unbudgeted(&c, truncated, 32).is_err());
            if version == 1 {
                let ext = Compressed {
                    extension: EXT,
                    ..c
                };
                let e = decode_unbudgeted(&ext, &encoded, 32).unwrap_err();
                assert!(e.contains("version 1"), "{e}");
            }
        }
    }
}
