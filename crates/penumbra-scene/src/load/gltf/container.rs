//! The byte-level parts of glTF: the GLB container, `data:` URIs and the
//! loading of buffers, all bounds-checked (the `gltf` crate's own GLB reader
//! can panic on a header that declares fewer than 12 bytes).

use crate::error::{Location, SceneError};
use std::path::Path;

/// The chunks of a `.glb` file.
#[derive(Debug)]
pub(super) struct Glb<'a> {
    pub json: &'a [u8],
    pub bin: Option<&'a [u8]>,
}

const GLB_MAGIC: &[u8; 4] = b"glTF";
const CHUNK_JSON: u32 = 0x4E4F_534A; // "JSON"
const CHUNK_BIN: u32 = 0x004E_4942; // "BIN\0"

/// True if `bytes` starts with the GLB magic.
pub(super) fn is_glb(bytes: &[u8]) -> bool {
    bytes.starts_with(GLB_MAGIC)
}

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

fn chunk_name(ty: u32) -> String {
    match ty {
        CHUNK_JSON => "JSON".into(),
        CHUNK_BIN => "BIN".into(),
        _ => format!("type 0x{ty:08x}"),
    }
}

/// Splits a GLB file into its JSON and (optional) BIN chunks.
pub(super) fn split_glb<'a>(file: &Path, bytes: &'a [u8]) -> Result<Glb<'a>, SceneError> {
    let header = || Location::Path("GLB header".into());
    if bytes.len() < 12 {
        return Err(SceneError::invalid(
            file,
            header(),
            format!(
                "truncated GLB: the file has {} bytes, fewer than the 12-byte header",
                bytes.len()
            ),
        ));
    }
    if !is_glb(bytes) {
        return Err(SceneError::invalid(
            file,
            header(),
            "not a GLB file (the first 4 bytes are not 'glTF')",
        ));
    }
    let version = u32_at(bytes, 4).unwrap_or(0);
    if version != 2 {
        return Err(SceneError::invalid(
            file,
            header(),
            format!("GLB container version {version} is not supported (expected 2)"),
        ));
    }
    let declared = u32_at(bytes, 8).unwrap_or(0) as usize;
    if declared > bytes.len() {
        return Err(SceneError::invalid(
            file,
            header(),
            format!(
                "truncated GLB: the header declares {declared} bytes but the file has only {}",
                bytes.len()
            ),
        ));
    }
    if declared < 20 {
        return Err(SceneError::invalid(
            file,
            header(),
            format!("GLB length {declared} is too small to hold a JSON chunk"),
        ));
    }
    let data = &bytes[..declared];
    let mut offset = 12usize;
    let mut json = None;
    let mut bin = None;
    let mut index = 0usize;
    while offset < data.len() {
        let (Some(len), Some(ty)) = (u32_at(data, offset), u32_at(data, offset + 4)) else {
            return Err(SceneError::invalid(
                file,
                Location::Path(format!("GLB chunk {index}")),
                format!(
                    "truncated GLB: chunk header at byte offset {offset} is cut off at byte {}",
                    data.len()
                ),
            ));
        };
        let start = offset + 8;
        let end = start.checked_add(len as usize).filter(|&e| e <= data.len());
        let Some(end) = end else {
            return Err(SceneError::invalid(
                file,
                Location::Path(format!("GLB chunk {index} ({})", chunk_name(ty))),
                format!(
                    "truncated GLB: the chunk declares {len} bytes at byte offset {start} but only {} remain",
                    data.len() - start
                ),
            ));
        };
        let chunk = &data[start..end];
        match (index, ty) {
            (0, CHUNK_JSON) => json = Some(chunk),
            (0, _) => {
                return Err(SceneError::invalid(
                    file,
                    Location::Path(format!("GLB chunk 0 ({})", chunk_name(ty))),
                    "the first GLB chunk must be the JSON chunk",
                ));
            }
            (1, CHUNK_BIN) => bin = Some(chunk),
            (_, CHUNK_JSON) | (_, CHUNK_BIN) => {
                return Err(SceneError::invalid(
                    file,
                    Location::Path(format!("GLB chunk {index} ({})", chunk_name(ty))),
                    "unexpected extra chunk (only one JSON and one BIN chunk are allowed)",
                ));
            }
            // Unknown chunk types must be ignored (glTF 2.0, 4.4.3).
            _ => {}
        }
        offset = end;
        index += 1;
    }
    let json = json.ok_or_else(|| {
        SceneError::invalid(file, header(), "truncated GLB: there is no JSON chunk")
    })?;
    Ok(Glb { json, bin })
}

/// Decodes a `data:` URI (base64 or percent-encoded). `Err` is a message.
pub(super) fn decode_data_uri(uri: &str) -> Result<Vec<u8>, String> {
    let rest = uri
        .strip_prefix("data:")
        .ok_or_else(|| "not a data: URI".to_string())?;
    let (meta, payload) = rest
        .split_once(',')
        .ok_or_else(|| "malformed data: URI (no ',' before the data)".to_string())?;
    if meta.ends_with(";base64") {
        decode_base64(payload)
    } else {
        Ok(crate::paths::percent_decode_bytes(payload))
    }
}

/// Standard base64 (RFC 4648, `+/`, optional `=` padding; the URL-safe
/// alphabet `-_` is accepted too). Whitespace is skipped.
pub(super) fn decode_base64(s: &str) -> Result<Vec<u8>, String> {
    fn value(c: u8) -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            _ => return None,
        } as u32)
    }
    let mut out = Vec::with_capacity(s.len() / 4 * 3 + 3);
    let mut acc = 0u32;
    let mut bits = 0u32;
    let mut padding = 0usize;
    for (i, c) in s.bytes().enumerate() {
        if c.is_ascii_whitespace() {
            continue;
        }
        if c == b'=' {
            padding += 1;
            continue;
        }
        if padding > 0 {
            return Err(format!(
                "invalid base64: data after '=' padding at character {i}"
            ));
        }
        let v = value(c).ok_or_else(|| {
            format!(
                "invalid base64: unexpected character '{}' at {i}",
                c as char
            )
        })?;
        acc = (acc << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
            acc &= (1 << bits) - 1;
        }
    }
    if bits >= 6 {
        return Err("invalid base64: truncated (dangling character)".into());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_round_trips_known_vectors() {
        assert_eq!(decode_base64("").unwrap(), b"");
        assert_eq!(decode_base64("Zg==").unwrap(), b"f");
        assert_eq!(decode_base64("Zm8=").unwrap(), b"fo");
        assert_eq!(decode_base64("Zm9v").unwrap(), b"foo");
        assert_eq!(decode_base64("Zm9vYmFy").unwrap(), b"foobar");
        assert_eq!(decode_base64("Zm9vYg").unwrap(), b"foob");
        assert_eq!(decode_base64("AAAAwP8=").unwrap(), [0, 0, 0, 0xc0, 0xff]);
        assert!(decode_base64("Zm9v!").is_err());
        assert!(decode_base64("Z").is_err());
        assert!(decode_base64("Zg==Zg").is_err());
    }

    #[test]
    fn data_uris() {
        assert_eq!(
            decode_data_uri("data:application/octet-stream;base64,Zm9v").unwrap(),
            b"foo"
        );
        assert_eq!(decode_data_uri("data:,a%20b").unwrap(), b"a b");
        assert!(decode_data_uri("data:foo").is_err());
    }

    #[test]
    fn glb_split_and_truncation() {
        let json = br#"{"asset":{"version":"2.0"}}"#;
        let mut jpad = json.to_vec();
        while !jpad.len().is_multiple_of(4) {
            jpad.push(b' ');
        }
        let bin = [1u8, 2, 3, 4];
        let total = 12 + 8 + jpad.len() + 8 + bin.len();
        let mut glb = Vec::new();
        glb.extend_from_slice(b"glTF");
        glb.extend_from_slice(&2u32.to_le_bytes());
        glb.extend_from_slice(&(total as u32).to_le_bytes());
        glb.extend_from_slice(&(jpad.len() as u32).to_le_bytes());
        glb.extend_from_slice(&CHUNK_JSON.to_le_bytes());
        glb.extend_from_slice(&jpad);
        glb.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        glb.extend_from_slice(&CHUNK_BIN.to_le_bytes());
        glb.extend_from_slice(&bin);
        let f = Path::new("a.glb");
        let g = split_glb(f, &glb).unwrap();
        assert_eq!(g.json, &jpad[..]);
        assert_eq!(g.bin, Some(&bin[..]));
        for cut in [0, 5, 11, 12, 19, 30, total - 1] {
            let e = split_glb(f, &glb[..cut]).unwrap_err().to_string();
            assert!(e.starts_with("a.glb"), "{e}");
            assert!(e.contains("GLB") || e.contains("truncated"), "{e}");
        }
        // A header length below 12 must not underflow.
        let mut bad = glb.clone();
        bad[8..12].copy_from_slice(&3u32.to_le_bytes());
        assert!(split_glb(f, &bad).is_err());
        // A chunk length that overflows.
        let mut bad = glb.clone();
        bad[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(
            split_glb(f, &bad)
                .unwrap_err()
                .to_string()
                .contains("chunk 0")
        );
    }
}
