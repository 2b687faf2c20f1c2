//! A first pass over OBJ text, before `tobj` parses it. `tobj` reports no
//! line numbers and can panic (index arithmetic overflow on a bad relative
//! index) or silently misread (texcoord index 0 is taken as "missing"; `l`
//! statements with three or more vertices become faces), so this pass
//!
//! * checks every `v`/`vt`/`vn` statement (numbers, finiteness, `w ≠ 0`) and
//!   every `f` index against the data defined so far, reporting the 1-based
//!   line of the first offending statement, and
//! * rewrites the text into what `tobj` reads safely, line for line (so line
//!   numbers still match): trailing `#` comments and vertex colours are
//!   dropped, `vt u` becomes `vt u 0`, `l` statements are commented out and
//!   `mtllib`/`usemtl` are separated by a single space.

use crate::error::SceneError;
use std::path::Path;

/// What the scan found.
#[derive(Debug, Default)]
pub(super) struct ObjScan {
    /// The text to give `tobj` (same number of lines).
    pub text: String,
    /// `f` statements with at least three vertices.
    pub faces: usize,
    /// `f` statements with fewer than three vertices (skipped).
    pub short_faces: usize,
    /// (line, argument) of each `mtllib`.
    pub mtllibs: Vec<(usize, String)>,
    /// (line, name) of each `usemtl`.
    pub usemtls: Vec<(usize, String)>,
}

fn parse_f32s(tokens: &[&str]) -> Result<Vec<f32>, String> {
    tokens
        .iter()
        .map(|t| {
            t.parse::<f32>()
                .map_err(|_| format!("'{t}' is not a number"))
        })
        .collect()
}

/// Resolves one OBJ index (1-based, or negative = relative to the end) of a
/// kind of which `defined` exist so far. `Err` is a message.
fn check_index(token: &str, kind: &str, defined: usize) -> Result<(), String> {
    let k: i64 = token
        .parse()
        .map_err(|_| format!("face {kind} index '{token}' is not an integer"))?;
    if k == 0 {
        return Err(format!(
            "face {kind} index 0 is invalid (OBJ indices start at 1)"
        ));
    }
    let ok = if k > 0 {
        k as u64 <= defined as u64
    } else {
        k.unsigned_abs() <= defined as u64
    };
    if ok {
        Ok(())
    } else {
        let kinds = match (kind, defined) {
            (_, 1) => kind.to_string(),
            ("vertex", _) => "vertices".to_string(),
            _ => format!("{kind}s"),
        };
        Err(format!(
            "face {kind} index {k} is out of range ({defined} {kinds} defined so far)"
        ))
    }
}

/// Scans `text` (the content of `file`).
pub(super) fn scan_obj(file: &Path, text: &str) -> Result<ObjScan, SceneError> {
    let mut out = ObjScan {
        text: String::with_capacity(text.len() + 64),
        ..Default::default()
    };
    let (mut nv, mut nvt, mut nvn) = (0usize, 0usize, 0usize);
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let err = |msg: String| SceneError::at_line(file, line_no, msg);
        let mut words = raw.split_whitespace();
        let keyword = words.next();
        // For data statements, a '#' starts a comment.
        let data: Vec<&str> = words.take_while(|w| !w.starts_with('#')).collect();
        let rest_of_line = |kw: &str| raw.trim_start()[kw.len()..].trim().to_string();
        let rewritten: Option<String> = match keyword {
            Some("v") => {
                let vals = parse_f32s(&data).map_err(|m| err(format!("bad vertex: {m}")))?;
                let p = match vals.len() {
                    3 | 6 => [vals[0], vals[1], vals[2]],
                    4 => {
                        if vals[3] == 0.0 {
                            return Err(err("vertex has w = 0".into()));
                        }
                        [vals[0] / vals[3], vals[1] / vals[3], vals[2] / vals[3]]
                    }
                    n => {
                        return Err(err(format!(
                            "vertex has {n} numbers (expected x y z, x y z w or x y z r g b)"
                        )));
                    }
                };
                if p.iter().any(|c| !c.is_finite()) {
                    return Err(err(format!(
                        "vertex {} has a non-finite position ({}, {}, {})",
                        nv + 1,
                        p[0],
                        p[1],
                        p[2]
                    )));
                }
                nv += 1;
                // Drop vertex colours (unused, and tobj fails if only some
                // vertices have them).
                let keep = if data.len() == 4 { 4 } else { 3 };
                Some(format!("v {}", data[..keep].join(" ")))
            }
            Some("vt") => {
                let vals =
                    parse_f32s(&data).map_err(|m| err(format!("bad texture coordinate: {m}")))?;
                if vals.is_empty() || vals.len() > 3 {
                    return Err(err(format!(
                        "texture coordinate has {} numbers (expected u [v [w]])",
                        vals.len()
                    )));
                }
                if vals.iter().any(|c| !c.is_finite()) {
                    return Err(err("texture coordinate is not finite".into()));
                }
                nvt += 1;
                let v = data.get(1).copied().unwrap_or("0");
                Some(format!("vt {} {v}", data[0]))
            }
            Some("vn") => {
                let vals = parse_f32s(&data).map_err(|m| err(format!("bad normal: {m}")))?;
                if vals.len() != 3 {
                    return Err(err(format!(
                        "normal has {} numbers (expected 3)",
                        vals.len()
                    )));
                }
                if vals.iter().any(|c| !c.is_finite()) {
                    return Err(err(format!(
                        "normal {} is not finite ({}, {}, {})",
                        nvn + 1,
                        vals[0],
                        vals[1],
                        vals[2]
                    )));
                }
                nvn += 1;
                Some(format!("vn {}", data.join(" ")))
            }
            Some("f") => {
                for corner in &data {
                    let parts: Vec<&str> = corner.split('/').collect();
                    if parts.len() > 3 || parts[0].is_empty() {
                        return Err(err(format!("malformed face vertex '{corner}'")));
                    }
                    check_index(parts[0], "vertex", nv).map_err(err)?;
                    if let Some(t) = parts.get(1).filter(|t| !t.is_empty()) {
                        check_index(t, "texture coordinate", nvt).map_err(err)?;
                    }
                    if let Some(n) = parts.get(2).filter(|n| !n.is_empty()) {
                        check_index(n, "normal", nvn).map_err(err)?;
                    }
                }
                if data.len() >= 3 {
                    out.faces += 1;
                } else {
                    out.short_faces += 1;
                }
                Some(format!("f {}", data.join(" ")))
            }
            // Polylines are not surfaces; tobj would turn long ones into faces.
            Some("l") => Some(String::from("# l")),
            Some("mtllib") => {
                let arg = rest_of_line("mtllib");
                if arg.is_empty() {
                    return Err(err("mtllib names no file".into()));
                }
                out.mtllibs.push((line_no, arg.clone()));
                Some(format!("mtllib {arg}"))
            }
            Some("usemtl") => {
                let arg = rest_of_line("usemtl");
                if arg.is_empty() {
                    return Err(err("usemtl names no material".into()));
                }
                out.usemtls.push((line_no, arg.clone()));
                Some(format!("usemtl {arg}"))
            }
            _ => None,
        };
        match rewritten {
            Some(s) => out.text.push_str(&s),
            None => out.text.push_str(raw),
        }
        out.text.push('\n');
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scan(s: &str) -> Result<ObjScan, String> {
        scan_obj(Path::new("t.obj"), s).map_err(|e| e.to_string())
    }

    #[test]
    fn finds_bad_lines() {
        let ok =
            "v 0 0 0\nv 1 0 0 # c\nv 0 1 0 1 0 0\nvt 0.5\nf 1 2 3\nf -3/1 -2/1 -1/1\nl 1 2 3\n";
        let s = scan(ok).unwrap();
        assert_eq!(s.faces, 2);
        assert_eq!(s.text.lines().count(), 7);
        assert!(s.text.contains("vt 0.5 0\n"));
        assert!(s.text.contains("v 0 1 0\n"));
        assert!(s.text.contains("v 1 0 0\n"));
        assert_eq!(
            scan("v 0 0 0\nv nan 0 0\n").unwrap_err(),
            "t.obj:2: vertex 2 has a non-finite position (NaN, 0, 0)"
        );
        assert!(
            scan("v 0 0 0\nv 1 inf 0\n")
                .unwrap_err()
                .starts_with("t.obj:2:")
        );
        assert!(scan("v 0 0 0 0\n").unwrap_err().contains("w = 0"));
        let e = scan("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n").unwrap_err();
        assert!(e.starts_with("t.obj:4:") && e.contains("index 4"), "{e}");
        assert!(scan("v 0 0 0\nf 1 -2 1\n").unwrap_err().contains("-2"));
        assert!(
            scan("v 0 0 0\nf 1/0 1 1\n")
                .unwrap_err()
                .contains("index 0")
        );
        assert!(
            scan("v 0 0 0\nf 1//1 1 1\n")
                .unwrap_err()
                .contains("normal")
        );
        assert!(
            scan("v 0 0 0\nf 1/-99999999999999999999 1 1\n")
                .unwrap_err()
                .contains("not an integer")
        );
        assert!(scan("v 0 0\n").unwrap_err().contains("2 numbers"));
        assert!(scan("v a b c\n").unwrap_err().contains("'a'"));
    }
}
