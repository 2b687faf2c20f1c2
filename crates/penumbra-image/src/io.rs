//! Reading and writing image files, chosen by extension, with atomic writes.
//!
//! * `.exr`: linear float32, see [`crate::exr_io`] (beauty channels `R,G,B`,
//!   AOVs as `<name>.R/G/B` in the same part).
//! * `.png`: tone-mapped 8-bit sRGB, see [`crate::png_io`]. AOVs are **ignored**
//!   for PNG output (they are only meaningful as float data).
//! * reading also accepts `.hdr` (Radiance RGBE, linear) and `.jpg`/`.jpeg`
//!   (sRGB, decoded to linear).
//!
//! Writes are atomic: the encoded file is written to a hidden temporary file in
//! the destination directory, flushed, and renamed over the destination. On any
//! error the temporary file is removed and no destination file is created.

use std::ffi::OsStr;
use std::fs::{self, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::{Image, ImageError, ToneMapping, exr_io, png_io};

/// Extensions accepted by [`write_image`].
pub const WRITE_EXTENSIONS: &str = ".png, .exr";
/// Extensions accepted by [`read_image`].
pub const READ_EXTENSIONS: &str = ".exr, .hdr, .png, .jpg, .jpeg";

/// Image file formats known to this crate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ImageFormat {
    /// OpenEXR, linear float (read and write).
    Exr,
    /// PNG, 8/16-bit sRGB (read and write; written as 8-bit tone-mapped sRGB).
    Png,
    /// Radiance RGBE `.hdr`, linear (read only).
    Hdr,
    /// JPEG, sRGB (read only).
    Jpeg,
}

impl ImageFormat {
    /// The format named by the path's extension (case-insensitive), if any.
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path
            .extension()
            .and_then(OsStr::to_str)?
            .to_ascii_lowercase();
        match ext.as_str() {
            "exr" => Some(Self::Exr),
            "png" => Some(Self::Png),
            "hdr" => Some(Self::Hdr),
            "jpg" | "jpeg" => Some(Self::Jpeg),
            _ => None,
        }
    }

    /// `true` for formats [`write_image`] can produce.
    pub fn is_writable(self) -> bool {
        matches!(self, Self::Exr | Self::Png)
    }
}

fn output_format(path: &Path) -> Result<ImageFormat, ImageError> {
    ImageFormat::from_path(path)
        .filter(|f| f.is_writable())
        .ok_or_else(|| ImageError::UnsupportedExtension {
            path: path.to_path_buf(),
            operation: "writing",
            supported: WRITE_EXTENSIONS,
        })
}

/// The directory a path's file lives in (`.` for a bare file name).
fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Validates an output path without writing anything, so a caller can fail
/// before a long render: the extension must be `.png` or `.exr`
/// (case-insensitive), the path must name a file (not an existing directory),
/// and its parent directory must exist and be a directory.
pub fn check_output_path(path: &Path) -> Result<(), ImageError> {
    output_format(path)?;
    if path.file_name().is_none() || path.is_dir() {
        return Err(ImageError::Io {
            path: path.to_path_buf(),
            action: "write to this path",
            cause: std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file path"),
        });
    }
    let dir = parent_dir(path);
    match fs::metadata(dir) {
        Ok(meta) if meta.is_dir() => Ok(()),
        Ok(_) => Err(ImageError::NotADirectory {
            path: path.to_path_buf(),
            dir: dir.to_path_buf(),
        }),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(ImageError::MissingDirectory {
            path: path.to_path_buf(),
            dir: dir.to_path_buf(),
        }),
        Err(cause) => Err(ImageError::Io {
            path: dir.to_path_buf(),
            action: "access output directory",
            cause,
        }),
    }
}

/// Writes `img` to `path`, format chosen by extension (case-insensitive):
///
/// * `.exr`: linear float32 RGB in channels `R,G,B`; each AOV `(name, image)`
///   adds channels `name.R, name.G, name.B` (written only when `aovs` is
///   non-empty). `tm` is not used. AOVs must have the image's size; names must
///   be unique, 1 to 250 printable ASCII characters without spaces.
/// * `.png`: `img` tone-mapped with `tm` to 8-bit sRGB ([`crate::tonemap_to_srgb8`]);
///   `aovs` are ignored.
///
/// The write is atomic (temporary file in the same directory, then rename);
/// on error neither the destination nor a temporary file is left behind.
pub fn write_image(
    path: &Path,
    img: &Image,
    aovs: &[(&str, &Image)],
    tm: &ToneMapping,
) -> Result<(), ImageError> {
    check_output_path(path)?;
    let format = output_format(path)?;
    let bytes = match format {
        ImageFormat::Exr => exr_io::encode(path, img, aovs)?,
        _ => png_io::encode(path, img, tm)?,
    };
    write_atomic(path, &bytes)
}

/// Reads a linear RGB image, format chosen by extension (case-insensitive):
/// `.exr` (float; the beauty `R,G,B` channels, see [`crate::read_exr_layers`]),
/// `.hdr` (linear), `.png`/`.jpg`/`.jpeg` (sRGB decoded to linear with the
/// sRGB EOTF; alpha is dropped). Missing, truncated or malformed files give an
/// error naming the file; decoders never panic the caller.
pub fn read_image(path: &Path) -> Result<Image, ImageError> {
    let format = ImageFormat::from_path(path).ok_or_else(|| ImageError::UnsupportedExtension {
        path: path.to_path_buf(),
        operation: "reading",
        supported: READ_EXTENSIONS,
    })?;
    let bytes = read_file(path)?;
    match format {
        ImageFormat::Exr => exr_io::decode(path, &bytes).map(|layers| layers.rgb),
        other => png_io::decode(path, &bytes, other),
    }
}

/// Refuses images an encoder cannot write: non-finite data is allowed
/// (EXR stores it), but the buffer must match its size and not be empty.
/// `err` wraps a message in the encoder's error.
pub(crate) fn check_encodable(
    img: &Image,
    err: &dyn Fn(String) -> ImageError,
) -> Result<(), ImageError> {
    img.validate("image").map_err(|e| err(e.to_string()))?;
    if img.is_empty() {
        return Err(err(format!(
            "image has zero size ({}x{})",
            img.width, img.height
        )));
    }
    Ok(())
}

pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>, ImageError> {
    fs::read(path).map_err(|cause| ImageError::Io {
        path: path.to_path_buf(),
        action: "read file",
        cause,
    })
}

/// Runs a third-party decoder/encoder, turning a panic inside it into an error
/// (defence in depth: malformed files must never take the process down).
pub(crate) fn guard<T>(
    f: impl FnOnce() -> Result<T, String>,
    on_error: impl FnOnce(String) -> ImageError,
) -> Result<T, ImageError> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(message)) => Err(on_error(message)),
        Err(_) => Err(on_error("internal decoder/encoder panic".to_string())),
    }
}

/// Removes the temporary file on drop unless it was renamed into place.
struct TempFile {
    path: PathBuf,
    keep: bool,
}

impl Drop for TempFile {
    fn drop(&mut self) {
        if !self.keep {
            let _ = fs::remove_file(&self.path);
        }
    }
}

static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `bytes` to `path` atomically: create `.<name>.<pid>.<n>.tmp` next to
/// it (exclusive create), write, fsync, rename over `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ImageError> {
    let dir = parent_dir(path);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let io_err = |path: &Path, action, cause| ImageError::Io {
        path: path.to_path_buf(),
        action,
        cause,
    };

    let mut attempt = 0;
    let (mut file, mut temp) = loop {
        let n = TEMP_COUNTER.fetch_add(1, Ordering::Relaxed);
        let temp_path = dir.join(format!(".{name}.{}.{n}.tmp", std::process::id()));
        match OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temp_path)
        {
            Ok(file) => {
                break (
                    file,
                    TempFile {
                        path: temp_path,
                        keep: false,
                    },
                );
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && attempt < 100 => {
                attempt += 1;
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Err(ImageError::MissingDirectory {
                    path: path.to_path_buf(),
                    dir: dir.to_path_buf(),
                });
            }
            Err(cause) => return Err(io_err(&temp_path, "create temporary file", cause)),
        }
    };
    file.write_all(bytes)
        .map_err(|c| io_err(&temp.path, "write temporary file", c))?;
    file.sync_all()
        .map_err(|c| io_err(&temp.path, "flush temporary file", c))?;
    drop(file);
    fs::rename(&temp.path, path)
        .map_err(|c| io_err(path, "rename temporary file into place", c))?;
    temp.keep = true;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn format_from_extension() {
        assert_eq!(
            ImageFormat::from_path(Path::new("a/b.EXR")),
            Some(ImageFormat::Exr)
        );
        assert_eq!(
            ImageFormat::from_path(Path::new("b.Png")),
            Some(ImageFormat::Png)
        );
        assert_eq!(
            ImageFormat::from_path(Path::new("b.jpeg")),
            Some(ImageFormat::Jpeg)
        );
        assert_eq!(ImageFormat::from_path(Path::new("b.tiff")), None);
        assert_eq!(ImageFormat::from_path(Path::new("exr")), None);
    }

    #[test]
    fn check_output_path_errors() {
        let dir = tempfile::tempdir().expect("tempdir");
        assert!(check_output_path(&dir.path().join("x.png")).is_ok());
        assert!(check_output_path(&dir.path().join("x.EXR")).is_ok());

        let e = check_output_path(&dir.path().join("x.tiff")).expect_err("bad extension");
        let msg = e.to_string();
        assert!(
            msg.contains("x.tiff") && msg.contains(".png") && msg.contains(".exr"),
            "{msg}"
        );

        let missing = dir.path().join("nope");
        let e = check_output_path(&missing.join("x.exr")).expect_err("missing dir");
        assert!(matches!(e, ImageError::MissingDirectory { .. }));
        assert!(
            e.to_string().contains(&missing.display().to_string()),
            "{e}"
        );

        let file = dir.path().join("file");
        fs::write(&file, b"x").expect("write");
        let e = check_output_path(&file.join("x.exr")).expect_err("parent is a file");
        assert!(
            matches!(e, ImageError::NotADirectory { .. } | ImageError::Io { .. }),
            "{e:?}"
        );

        let subdir = dir.path().join("d.png");
        fs::create_dir(&subdir).expect("mkdir");
        assert!(check_output_path(&subdir).is_err());
    }
}
