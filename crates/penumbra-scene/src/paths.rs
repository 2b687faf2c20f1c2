//! Resolving URIs referenced by scene files without letting a file read
//! outside its own folder tree.
//!
//! A relative URI is joined to the referencing file's folder and must stay
//! inside it after `..` and symbolic links are resolved. Absolute paths are
//! refused unless the user named them explicitly (see [`crate::LoadOptions`]).

use crate::error::{Location, SceneError};
use std::path::{Component, Path, PathBuf};

/// Resolves `uri` (percent-decoded, relative or absolute) referenced from
/// `scene_file`. `allowed_absolute` lists absolute paths the user named on the
/// command line. `location` is where the URI appears, for the error message.
pub fn resolve_uri(
    scene_file: &Path,
    uri: &str,
    allowed_absolute: &[PathBuf],
    location: Location,
) -> Result<PathBuf, SceneError> {
    let decoded = percent_decode(uri);
    if decoded.starts_with("data:") {
        return Err(SceneError::invalid(
            scene_file,
            location,
            "data: URIs are resolved by the loader, not as files",
        ));
    }
    if decoded.contains("://") {
        return Err(SceneError::invalid(
            scene_file,
            location,
            format!("URI '{uri}' is not a local file; only relative paths are allowed"),
        ));
    }
    let candidate = Path::new(&decoded);
    let root = scene_file
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let root = if root.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        root
    };
    if candidate.is_absolute() {
        if allowed_absolute.iter().any(|a| a == candidate) {
            return Ok(candidate.to_path_buf());
        }
        return Err(SceneError::invalid(
            scene_file,
            location,
            format!(
                "absolute path '{decoded}' is not allowed; reference files relative to the scene, inside its folder"
            ),
        ));
    }
    // Lexical check first (works even if the file does not exist yet).
    let mut depth: i64 = 0;
    for c in candidate.components() {
        match c {
            Component::ParentDir => depth -= 1,
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            _ => depth = -1,
        }
        if depth < 0 {
            return Err(SceneError::invalid(
                scene_file,
                location,
                format!("path '{decoded}' leaves the scene's folder"),
            ));
        }
    }
    let joined = root.join(candidate);
    // Then the real check through symbolic links, when the file exists.
    if let (Ok(real_root), Ok(real)) = (root.canonicalize(), joined.canonicalize())
        && !real.starts_with(&real_root)
    {
        return Err(SceneError::invalid(
            scene_file,
            location,
            format!("path '{decoded}' resolves outside the scene's folder"),
        ));
    }
    Ok(joined)
}

/// Decodes `%XX` escapes (glTF URIs are URI-encoded) to raw bytes; a `%`
/// not followed by two hex digits is kept as it is.
pub fn percent_decode_bytes(s: &str) -> Vec<u8> {
    let hex = |c: u8| (c as char).to_digit(16).map(|d| d as u8);
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%'
            && let (Some(h), Some(l)) = (
                b.get(i + 1).and_then(|&c| hex(c)),
                b.get(i + 2).and_then(|&c| hex(c)),
            )
        {
            out.push(h << 4 | l);
            i += 3;
            continue;
        }
        out.push(b[i]);
        i += 1;
    }
    out
}

/// [`percent_decode_bytes`] as text (invalid UTF-8 replaced).
pub fn percent_decode(s: &str) -> String {
    String::from_utf8_lossy(&percent_decode_bytes(s)).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_escape_and_absolute() {
        let f = Path::new("/tmp/scenes/a.gltf");
        assert!(resolve_uri(f, "../secret.bin", &[], Location::File).is_err());
        assert!(resolve_uri(f, "sub/../../x.bin", &[], Location::File).is_err());
        assert!(resolve_uri(f, "/etc/passwd", &[], Location::File).is_err());
        assert!(resolve_uri(f, "http://x/y.bin", &[], Location::File).is_err());
        assert_eq!(
            resolve_uri(f, "sub/b%20c.bin", &[], Location::File).unwrap(),
            Path::new("/tmp/scenes/sub/b c.bin")
        );
        let allowed = vec![PathBuf::from("/data/mesh.obj")];
        assert!(resolve_uri(f, "/data/mesh.obj", &allowed, Location::File).is_ok());
    }
}
