//! Scene loading errors: every one names the file, the place in it and what
//! is wrong.

use std::fmt;
use std::path::PathBuf;

/// Where in a file a problem is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Location {
    /// The whole file (e.g. it is empty or unreadable).
    File,
    /// A 1-based line (OBJ, MTL, TOML), with an optional 1-based column.
    Line { line: usize, column: Option<usize> },
    /// A JSON path into a glTF document, e.g. `meshes[2].primitives[0].indices`,
    /// or a TOML key path, e.g. `objects[1].material.albedo`.
    Path(String),
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::File => Ok(()),
            Location::Line {
                line,
                column: Some(c),
            } => write!(f, ":{line}:{c}"),
            Location::Line { line, column: None } => write!(f, ":{line}"),
            Location::Path(p) => write!(f, " at {p}"),
        }
    }
}

/// A scene that cannot be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read. The reason is in the message, so it is
    /// not also a `source()` (a reporter printing the chain would repeat it).
    #[error("{}: cannot read file: {cause}", file.display())]
    Io {
        file: PathBuf,
        cause: std::io::Error,
    },
    /// The content is invalid at a known place.
    #[error("{}{location}: {message}", file.display())]
    Invalid {
        file: PathBuf,
        location: Location,
        message: String,
    },
    /// The file's extension names no format penumbra reads.
    #[error("{}: unknown scene format (expected .gltf, .glb, .obj or .toml)", file.display())]
    UnknownFormat { file: PathBuf },
}

impl SceneError {
    /// Shorthand for [`SceneError::Invalid`].
    pub fn invalid(
        file: impl Into<PathBuf>,
        location: Location,
        message: impl Into<String>,
    ) -> Self {
        SceneError::Invalid {
            file: file.into(),
            location,
            message: message.into(),
        }
    }

    /// Invalid at a JSON or TOML key path.
    pub fn at_path(
        file: impl Into<PathBuf>,
        path: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Self::invalid(file, Location::Path(path.into()), message)
    }

    /// Invalid at a 1-based line.
    pub fn at_line(file: impl Into<PathBuf>, line: usize, message: impl Into<String>) -> Self {
        Self::invalid(file, Location::Line { line, column: None }, message)
    }

    /// Invalid as a whole.
    pub fn in_file(file: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Self::invalid(file, Location::File, message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_file_place_and_problem() {
        let e = SceneError::at_path(
            "a/b.gltf",
            "meshes[0].primitives[1].indices",
            "index 9 out of range (3 vertices)",
        );
        assert_eq!(
            e.to_string(),
            "a/b.gltf at meshes[0].primitives[1].indices: index 9 out of range (3 vertices)"
        );
        let e = SceneError::at_line("m.obj", 12, "NaN position");
        assert_eq!(e.to_string(), "m.obj:12: NaN position");
    }
}
