//! Where things are in the TOML text: key paths ↔ lines, and the errors
//! that name them.
//!
//! The text is parsed twice: once into toml's spanned document tree, from
//! which an index of every key path (`objects[2].radius`) and its byte span
//! is built, and once by serde into the [`super::raw`] structs. Serde errors
//! carry a span, which the index turns into a key path; validation errors
//! carry a key path, which the index turns into a line.

use crate::error::{Location, SceneError};
use ::toml::de::{DeTable, DeValue};
use serde::de::DeserializeOwned;
use std::fmt::Display;
use std::ops::Range;
use std::path::Path;

/// One key or array element of the document.
#[derive(Debug)]
struct Entry {
    path: String,
    /// Span of the key (none for array elements).
    key: Option<Range<usize>>,
    /// Span of the value (for `[table]` / `[[array]]` headers: the header).
    value: Range<usize>,
}

/// The TOML text with its key-path index.
#[derive(Debug)]
pub(super) struct Doc<'a> {
    pub file: &'a Path,
    text: &'a str,
    entries: Vec<Entry>,
}

impl<'a> Doc<'a> {
    /// Parses `text` (syntax only). Syntax errors become line:column errors.
    pub fn parse(text: &'a str, file: &'a Path) -> Result<Self, SceneError> {
        let mut doc = Doc {
            file,
            text,
            entries: Vec::new(),
        };
        let table = DeTable::parse(text).map_err(|e| doc.syntax_error(&e))?;
        index_table(&mut doc.entries, "", table.get_ref());
        Ok(doc)
    }

    /// Deserializes the text into `T`; type errors and unknown keys become
    /// line:column errors that also name the key path.
    pub fn deserialize<T: DeserializeOwned>(&self) -> Result<T, SceneError> {
        ::toml::from_str(self.text).map_err(|e| self.toml_error(&e))
    }

    /// A syntax error, quoting the line it was found on.
    fn syntax_error(&self, e: &::toml::de::Error) -> SceneError {
        let err = self.toml_error(e);
        let near = e.span().and_then(|s| {
            let (line, _) = self.line_col(s.start);
            let text = self.text.lines().nth(line - 1)?.trim();
            (!text.is_empty()).then(|| text.chars().take(60).collect::<String>())
        });
        match (err, near) {
            (
                SceneError::Invalid {
                    file,
                    location,
                    message,
                },
                Some(near),
            ) => SceneError::Invalid {
                file,
                location,
                message: format!("{message} (near `{near}`)"),
            },
            (err, _) => err,
        }
    }

    /// Converts one of toml's errors (syntax or serde) into a [`SceneError`].
    fn toml_error(&self, e: &::toml::de::Error) -> SceneError {
        let message = e.message().trim().replace('\n', "; ");
        match e.span() {
            Some(span) => {
                let (line, column) = self.line_col(span.start);
                let message = match self.path_at(span.start) {
                    Some(path) => format!("{path}: {message}"),
                    None => message,
                };
                SceneError::invalid(
                    self.file,
                    Location::Line {
                        line,
                        column: Some(column),
                    },
                    message,
                )
            }
            None => SceneError::in_file(self.file, message),
        }
    }

    /// 1-based (line, column) of a byte offset; the column counts characters.
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let before = &self.text.as_bytes()[..offset];
        let line = 1 + before.iter().filter(|&&b| b == b'\n').count();
        let line_start = before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |i| i + 1);
        let column = 1 + String::from_utf8_lossy(&before[line_start..])
            .chars()
            .count();
        (line, column)
    }

    /// The innermost key path whose key or value contains byte `offset`.
    fn path_at(&self, offset: usize) -> Option<&str> {
        self.entries
            .iter()
            .flat_map(|e| {
                e.key
                    .iter()
                    .chain(std::iter::once(&e.value))
                    .map(move |r| (e, r))
            })
            .filter(|(_, r)| r.start <= offset && offset < r.end)
            .min_by_key(|(_, r)| r.end - r.start)
            .map(|(e, _)| e.path.as_str())
    }

    /// 1-based line where `path` is written (its key, or its table header).
    pub fn line_of(&self, path: &str) -> Option<usize> {
        self.entries
            .iter()
            .find(|e| e.path == path)
            .map(|e| self.line_col(e.key.as_ref().unwrap_or(&e.value).start).0)
    }

    /// An error at a key path; the message gets the line appended when the
    /// path is written in the file.
    pub fn err(&self, path: &str, message: impl Display) -> SceneError {
        let message = match self.line_of(path) {
            Some(line) => format!("{message} (line {line})"),
            None => message.to_string(),
        };
        SceneError::at_path(self.file, path, message)
    }

    /// An error about the file as a whole.
    pub fn whole(&self, message: impl Display) -> SceneError {
        SceneError::in_file(self.file, message.to_string())
    }

    /// Re-anchors an error produced elsewhere (e.g. by path resolution) at
    /// `path`, keeping its message.
    pub fn reanchor(&self, path: &str, e: SceneError) -> SceneError {
        match e {
            SceneError::Invalid { message, .. } => self.err(path, message),
            other => other,
        }
    }
}

fn index_table(out: &mut Vec<Entry>, prefix: &str, table: &DeTable<'_>) {
    for (key, value) in table.iter() {
        let path = if prefix.is_empty() {
            key_text(key.get_ref())
        } else {
            format!("{prefix}.{}", key_text(key.get_ref()))
        };
        out.push(Entry {
            path: path.clone(),
            key: Some(key.span()),
            value: value.span(),
        });
        index_value(out, &path, value.get_ref());
    }
}

fn index_value(out: &mut Vec<Entry>, path: &str, value: &DeValue<'_>) {
    if let Some(t) = value.as_table() {
        index_table(out, path, t);
    } else if let Some(a) = value.as_array() {
        for (i, v) in a.iter().enumerate() {
            let p = format!("{path}[{i}]");
            out.push(Entry {
                path: p.clone(),
                key: None,
                value: v.span(),
            });
            index_value(out, &p, v.get_ref());
        }
    }
}

/// A key as it would be written: bare if possible, else quoted.
fn key_text(k: &str) -> String {
    if !k.is_empty()
        && k.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        k.to_string()
    } else {
        format!("{k:?}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_and_lines() {
        let text =
            "a = 1\n[[objects]]\nradius = 2\n\n[[objects]]\nshape = \"box\"\nsize = [1, 2]\n";
        let doc = Doc::parse(text, Path::new("x.toml")).unwrap();
        assert_eq!(doc.line_of("objects[1].size"), Some(7));
        assert_eq!(doc.line_of("objects[1]"), Some(5));
        assert_eq!(doc.line_of("objects[0].radius"), Some(3));
        assert_eq!(doc.line_of("objects[1].size[1]"), Some(7));
        let off = text.find("2]").unwrap();
        assert_eq!(doc.path_at(off), Some("objects[1].size[1]"));
        assert_eq!(doc.line_col(off), (7, 12));
    }
}
