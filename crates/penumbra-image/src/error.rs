//! The crate's error type. Every variant that concerns a file names that file.

use std::path::PathBuf;

/// Errors from reading, writing, validating and comparing images.
///
/// Messages start with the file path where one is involved, so they can be
/// shown to a user as they are. Underlying causes (I/O, decoder messages) are
/// part of the message rather than a separate `source()`, so printing the
/// error once shows everything without repetition.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImageError {
    /// The extension does not name a format supported for this operation.
    #[error(
        "{}: unsupported image file extension for {operation} (supported: {supported})",
        path.display()
    )]
    UnsupportedExtension {
        /// The offending path.
        path: PathBuf,
        /// `"writing"` or `"reading"`.
        operation: &'static str,
        /// The supported extensions, e.g. `".png, .exr"`.
        supported: &'static str,
    },
    /// The directory an output file should go into does not exist.
    #[error("{}: output directory {} does not exist", path.display(), dir.display())]
    MissingDirectory {
        /// The output path.
        path: PathBuf,
        /// Its parent directory.
        dir: PathBuf,
    },
    /// The parent of an output path exists but is not a directory.
    #[error("{}: {} is not a directory", path.display(), dir.display())]
    NotADirectory {
        /// The output path.
        path: PathBuf,
        /// Its parent, which is not a directory.
        dir: PathBuf,
    },
    /// An operating-system level I/O error.
    #[error("{}: cannot {action}: {cause}", path.display())]
    Io {
        /// The file involved.
        path: PathBuf,
        /// What was attempted, e.g. `"read file"`.
        action: &'static str,
        /// The underlying error.
        cause: std::io::Error,
    },
    /// The file exists but its content could not be decoded (truncated, garbage, unsupported).
    #[error("{}: cannot decode {format} image: {message}", path.display())]
    Decode {
        /// The file.
        path: PathBuf,
        /// `"EXR"`, `"PNG"`, ...
        format: &'static str,
        /// Decoder message.
        message: String,
    },
    /// The image could not be encoded for this file (e.g. zero size, bad AOV name).
    #[error("{}: cannot encode {format} image: {message}", path.display())]
    Encode {
        /// The file.
        path: PathBuf,
        /// `"EXR"` or `"PNG"`.
        format: &'static str,
        /// What went wrong.
        message: String,
    },
    /// An in-memory image is inconsistent (pixel count differs from width × height, or empty).
    #[error("invalid {what}: {message}")]
    InvalidImage {
        /// Which image, e.g. `"reference image"`.
        what: String,
        /// What is wrong with it.
        message: String,
    },
    /// Partial films that cannot be merged (another render's part, an
    /// overlap, missing samples); the message names the parts.
    #[error("cannot merge: {message}")]
    Merge {
        /// What is wrong, naming the parts.
        message: String,
    },
    /// Two images that must have the same size do not.
    #[error(
        "image sizes differ: reference is {}x{}, test is {}x{}",
        reference.0, reference.1, test.0, test.1
    )]
    SizeMismatch {
        /// Reference (width, height).
        reference: (u32, u32),
        /// Test (width, height).
        test: (u32, u32),
    },
}
