//! The GLB container: a 12-byte header (`glTF`, version 2, total length) followed by chunks
//! (length, type, data padded to 4 bytes): first `JSON`, then optionally `BIN\0`; other
//! chunk types are skipped. Every length is checked against the bytes actually present, so
//! a lying header can never size an allocation; the chunks are borrowed, not copied.

/// The JSON chunk and the optional binary chunk of a GLB file.
#[derive(Debug)]
pub(super) struct Chunks<'a> {
    pub json: &'a [u8],
    pub bin: Option<&'a [u8]>,
}

const JSON: u32 = 0x4E4F_534A;
const BIN: u32 = 0x004E_4942;

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Splits a GLB file into its chunks, or says why it cannot.
pub(super) fn split(bytes: &[u8]) -> Result<Chunks<'_>, String> {
    if bytes.get(..4) != Some(b"glTF".as_slice()) {
        return Err("missing the `glTF` magic".into());
    }
    let (Some(version), Some(length)) = (u32_at(bytes, 4), u32_at(bytes, 8)) else {
        return Err(format!(
            "header needs 12 bytes, the file has {}",
            bytes.len()
        ));
    };
    if version != 2 {
        return Err(format!("container version {version}, expected 2"));
    }
    let length = length as usize;
    if length < 12 {
        return Err(format!(
            "declared length {length} is smaller than the 12-byte header"
        ));
    }
    if length > bytes.len() {
        return Err(format!(
            "header says {length} bytes, the file has {}",
            bytes.len()
        ));
    }
    let body = bytes.get(..length).unwrap_or(bytes);
    let mut at = 12usize;
    let mut json = None;
    let mut bin = None;
    while at < body.len() {
        let (Some(len), Some(kind)) = (u32_at(body, at), u32_at(body, at + 4)) else {
            return Err(format!("truncated chunk header at byte {at}"));
        };
        let start = at + 8;
        let data = start
            .checked_add(len as usize)
            .and_then(|end| body.get(start..end))
            .ok_or_else(|| {
                format!(
                    "chunk at byte {at} claims {len} bytes, only {} remain",
                    body.len() - start.min(body.len())
                )
            })?;
        match kind {
            JSON if json.is_none() && at == 12 => json = Some(data),
            _ if at == 12 => {
                return Err(format!("first chunk has type {kind:#010x}, expected JSON"))
            }
            BIN if bin.is_none() && json.is_some() => bin = Some(data),
            JSON | BIN => return Err(format!("unexpected chunk order at byte {at}")),
            _ => {}
        }
        // Chunks are padded to 4 bytes.
        at = start + (len as usize).next_multiple_of(4);
    }
    let json = json.ok_or("no JSON chunk")?;
    Ok(Chunks { json, bin })
}

#[cfg(test)]
pub(crate) fn build(json: &[u8], bin: Option<&[u8]>) -> Vec<u8> {
    let pad = |v: &[u8], fill: u8| {
        let mut v = v.to_vec();
        while !v.len().is_multiple_of(4) {
            v.push(fill);
        }
        v
    };
    let json = pad(json, b' ');
    let mut body = Vec::new();
    body.extend((json.len() as u32).to_le_bytes());
    body.extend(JSON.to_le_bytes());
    body.extend(&json);
    if let Some(bin) = bin {
        let bin = pad(bin, 0);
        body.extend((bin.len() as u32).to_le_bytes());
        body.extend(BIN.to_le_bytes());
        body.extend(&bin);
    }
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend(((body.len() + 12) as u32).to_le_bytes());
    out.extend(body);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splits_and_rejects_lies() {
        let glb = build(br#"{"asset":{"version":"2.0"}}"#, Some(&[1, 2, 3]));
        let c = split(&glb).unwrap();
        assert!(c.json.starts_with(b"{"));
        assert_eq!(c.bin.map(|b| b.len()), Some(4));
        let mut lying = glb.clone();
        lying[12..16].copy_from_slice(&0xFFFF_FFF0u32.to_le_bytes());
        assert!(split(&lying)
            .unwrap_err()
            .contains("claims 4294967280 bytes"));
        let mut long = glb.clone();
        long[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(split(&long).unwrap_err().contains("header says"));
        assert!(split(b"glTF\x02\0\0\0").is_err());
        let mut zero = glb;
        zero[8..12].copy_from_slice(&0u32.to_le_bytes());
        assert!(split(&zero)
            .unwrap_err()
            .contains("smaller than the 12-byte header"));
        assert!(split(&build(b"", None)[..12])
            .unwrap_err()
            .contains("header says"));
    }
}
