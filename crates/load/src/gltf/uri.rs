//! glTF URIs for buffers and images, resolved by hand: `data:` URIs (base64, or
//! percent-encoded), and relative paths (percent-decoded) that stay inside the model's
//! folder and name regular files. Every other scheme (`file:`, `http:`, ...) and every
//! absolute path is refused, so a model cannot read `/dev/zero` or the user's files.

use std::path::Path;

use base64::engine::general_purpose::{GeneralPurpose, GeneralPurposeConfig};
use base64::engine::DecodePaddingMode;
use base64::Engine as _;

use crate::{files, Budget, LoadError};

/// Standard base64, padding optional (some exporters drop it).
const BASE64: GeneralPurpose = GeneralPurpose::new(
    &base64::alphabet::STANDARD,
    GeneralPurposeConfig::new().with_decode_padding_mode(DecodePaddingMode::Indifferent),
);

/// Longest URI quoted in a message.
const QUOTE: usize = 60;

/// The bytes a URI names. The outer `Result` is a budget overrun (fatal); the inner one a
/// reason the URI is unusable (the caller decides between error and warning).
pub(super) fn load(
    uri: &str,
    root: &Path,
    budget: &Budget,
    what: &str,
) -> Result<Result<Vec<u8>, String>, LoadError> {
    if let Some(rest) = uri.strip_prefix("data:") {
        return data_uri(rest, budget, what);
    }
    let quoted = quote(uri);
    if let Some(scheme) = scheme(uri) {
        return Ok(Err(format!(
            "URI `{quoted}`: scheme `{scheme}:` is not supported (only data: and relative paths)"
        )));
    }
    if uri.starts_with('/') || uri.starts_with('\\') {
        return Ok(Err(format!(
            "URI `{quoted}`: absolute paths are not allowed"
        )));
    }
    let decoded = match percent_decode(uri).map(String::from_utf8) {
        Some(Ok(s)) => s,
        _ => return Ok(Err(format!("URI `{quoted}`: bad percent-encoding"))),
    };
    let path = match files::resolve_inside(root, root, Path::new(&decoded)) {
        Ok(p) => p,
        Err(reason) => return Ok(Err(reason)),
    };
    match files::read_capped(&path, budget, what) {
        Ok(bytes) => Ok(Ok(bytes)),
        Err(e @ LoadError::TooLarge { .. }) => Err(e),
        Err(e) => Ok(Err(e.to_string())),
    }
}

/// `rest` is what follows `data:`: `[mediatype][;base64],payload`.
fn data_uri(rest: &str, budget: &Budget, what: &str) -> Result<Result<Vec<u8>, String>, LoadError> {
    let Some((header, payload)) = rest.split_once(',') else {
        return Ok(Err("data: URI without a comma".into()));
    };
    let estimate = (payload.len() as u64 / 4 + 1) * 3;
    budget.charge(estimate, || format!("{what} (data: URI)"))?;
    if header.ends_with(";base64") {
        Ok(BASE64
            .decode(payload.trim_end())
            .map_err(|e| format!("data: URI: bad base64: {e}")))
    } else {
        Ok(percent_decode(payload).ok_or_else(|| "data: URI: bad percent-encoding".to_string()))
    }
}

/// The scheme of an absolute URI (`file` in `file:///x`), if any. A scheme is a letter
/// followed by letters, digits, `+`, `-` or `.`, then `:`, before any `/`.
fn scheme(uri: &str) -> Option<&str> {
    let (head, _) = uri.split_once(':')?;
    let mut chars = head.chars();
    let first_ok = chars.next().is_some_and(|c| c.is_ascii_alphabetic());
    let rest_ok = chars.all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'));
    (first_ok && rest_ok).then_some(head)
}

/// Decodes `%XX` escapes; `None` on a malformed escape.
fn percent_decode(s: &str) -> Option<Vec<u8>> {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while let Some(&b) = bytes.get(i) {
        if b == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b);
            i += 1;
        }
    }
    Some(out)
}

/// At most [`QUOTE`] characters of `uri`, for messages.
fn quote(uri: &str) -> String {
    match uri.char_indices().nth(QUOTE) {
        Some((cut, _)) => format!("{}...", &uri[..cut]),
        None => uri.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decodes_and_refuses() {
        let budget = Budget::new(Path::new("t"), 1 << 20);
        let root = std::env::temp_dir().canonicalize().unwrap();
        let ok = |u: &str| load(u, &root, &budget, "buffer 0").unwrap();
        assert_eq!(
            ok("data:application/octet-stream;base64,AQID").unwrap(),
            [1, 2, 3]
        );
        assert_eq!(
            ok("data:application/octet-stream;base64,AQI").unwrap(),
            [1, 2]
        );
        assert_eq!(ok("data:,a%20b").unwrap(), b"a b");
        assert!(ok("file:///dev/zero")
            .unwrap_err()
            .contains("scheme `file:`"));
        assert!(ok("http://example.com/x.bin")
            .unwrap_err()
            .contains("scheme"));
        assert!(ok("/dev/zero").unwrap_err().contains("absolute"));
        assert!(ok("%zz").unwrap_err().contains("percent"));
        assert_eq!(percent_decode("a%2Fb%C3%A9").unwrap(), "a/bé".as_bytes());
        assert_eq!(scheme("C:/x"), Some("C"));
        assert_eq!(scheme("dir/a:b.bin"), None);
        let small = Budget::new(Path::new("t"), 2);
        assert!(load("data:;base64,AAAAAAAA", &root, &small, "buffer 0").is_err());
    }
}
