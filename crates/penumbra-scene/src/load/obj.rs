//! OBJ + MTL loader (`tobj`, triangulated, single index so that positions,
//! normals and texture coordinates line up).
//!
//! A first pass (`scan.rs`) checks the text and reports the 1-based line of
//! a bad statement (non-finite vertex, face index out of range, ...), which
//! `tobj` cannot. `mtllib` files are resolved with
//! [`crate::paths::resolve_uri`] (they cannot leave the OBJ's folder); a
//! missing one is a warning, and its objects get the default grey material.
//! Texture coordinates are flipped to penumbra's convention (v = 0 at the
//! top row, as glTF). An OBJ has no camera: `Scene::camera` stays `None`.

mod mtl;
mod scan;

use self::mtl::{MtlSource, prepare_mtl};
use super::LoadOptions;
use crate::error::{Location, SceneError};
use crate::material::{Material, MaterialId};
use crate::mesh::Mesh;
use crate::scene::Scene;
use crate::texture::TextureId;
use glam::{Mat4, Vec2, Vec3};
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// State of one load.
#[derive(Debug)]
struct ObjLoader<'a> {
    file: &'a Path,
    options: &'a LoadOptions,
    scene: Scene,
    /// Resolved texture path → texture.
    textures: HashMap<PathBuf, TextureId>,
}

/// What the `mtllib` callback collected.
#[derive(Debug, Default)]
struct MtlState {
    /// One entry per material tobj appended, in order.
    sources: Vec<MtlSource>,
    warnings: Vec<String>,
    error: Option<SceneError>,
    /// How many times each mtllib argument was seen (to find its line).
    seen: HashMap<String, usize>,
}

/// Loads an `.obj` file with its `.mtl` libraries.
pub fn load_obj(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let bytes = super::read_file(path)?;
    load_obj_text(path, &String::from_utf8_lossy(&bytes), options)
}

/// Loads OBJ `text`; `path` names it in messages and anchors `mtllib` paths.
fn load_obj_text(path: &Path, text: &str, options: &LoadOptions) -> Result<Scene, SceneError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.trim().is_empty() {
        return Err(SceneError::in_file(path, "file is empty"));
    }
    let scan = scan::scan_obj(path, text)?;
    if scan.faces == 0 {
        return Err(SceneError::in_file(
            path,
            "no faces: the file has no 'f' statement with three or more vertices",
        ));
    }

    let state = RefCell::new(MtlState::default());
    let tobj_options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let result = tobj::load_obj_buf(
        &mut std::io::Cursor::new(scan.text.as_bytes()),
        &tobj_options,
        |lib: &Path| load_mtllib(path, options, &scan.mtllibs, &state, lib),
    );
    let mut state = state.into_inner();
    if let Some(e) = state.error.take() {
        return Err(e);
    }
    let (models, materials) =
        result.map_err(|e| SceneError::in_file(path, format!("cannot parse OBJ: {e}")))?;
    // Err here means no library loaded; that was already reported.
    let materials = materials.unwrap_or_default();

    let mut loader = ObjLoader {
        file: path,
        options,
        scene: Scene::default(),
        textures: HashMap::new(),
    };
    loader.scene.warnings.append(&mut state.warnings);
    let f = path.display().to_string();

    // Unknown `usemtl` names (tobj silently uses no material).
    let mut unknown: Vec<String> = Vec::new();
    for (line, name) in &scan.usemtls {
        if !materials.iter().any(|m| &m.name == name)
            && !unknown.iter().any(|u| u.starts_with(&format!("'{name}'")))
        {
            unknown.push(format!("'{name}' (line {line})"));
        }
    }
    if !unknown.is_empty() {
        loader.scene.warnings.push(format!(
            "{f}: material(s) not found in any material library, default grey used: {}",
            unknown.join(", ")
        ));
    }

    let mut converted: HashMap<usize, MaterialId> = HashMap::new();
    let mut default_material: Option<MaterialId> = None;
    let mut degenerate = 0usize;
    let mut partial_normals: Vec<String> = Vec::new();
    let mut partial_uvs: Vec<String> = Vec::new();
    for model in &models {
        let m = &model.mesh;
        if m.indices.is_empty() {
            continue;
        }
        let positions: Vec<Vec3> = m
            .positions
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect();
        let n = positions.len();
        let normals = match m.normals.len() {
            0 => None,
            len if len == 3 * n => Some(
                m.normals
                    .chunks_exact(3)
                    .map(|c| Vec3::new(c[0], c[1], c[2]))
                    .collect(),
            ),
            _ => {
                partial_normals.push(format!("'{}'", model.name));
                None
            }
        };
        let uv0 = match m.texcoords.len() {
            0 => None,
            len if len == 2 * n => Some(
                m.texcoords
                    .chunks_exact(2)
                    .map(|c| Vec2::new(c[0], 1.0 - c[1]))
                    .collect(),
            ),
            _ => {
                partial_uvs.push(format!("'{}'", model.name));
                None
            }
        };
        let material = match m.material_id {
            Some(k) if k < materials.len() && k < state.sources.len() => match converted.get(&k) {
                Some(&id) => id,
                None => {
                    let id = loader.convert_material(&materials[k], &state.sources[k])?;
                    converted.insert(k, id);
                    id
                }
            },
            _ => *default_material
                .get_or_insert_with(|| loader.scene.add_material(Material::default_grey())),
        };
        let mut mesh = Mesh {
            name: model.name.clone(),
            positions,
            normals,
            uv0,
            uv1: None,
            tangents: None,
            colors: None,
            indices: m
                .indices
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect(),
            material,
        };
        // The scan checked every statement; this is a safety net.
        mesh.validate()
            .map_err(|msg| SceneError::in_file(path, format!("object '{}': {msg}", model.name)))?;
        degenerate += mesh.remove_degenerate().degenerate_triangles;
        if !mesh.indices.is_empty() {
            loader.scene.add_mesh(mesh, Mat4::IDENTITY);
        }
    }

    let w = &mut loader.scene.warnings;
    if degenerate > 0 {
        w.push(format!(
            "{f}: skipped {degenerate} degenerate triangle(s) (zero area)"
        ));
    }
    if scan.short_faces > 0 {
        w.push(format!(
            "{f}: skipped {} face(s) with fewer than three vertices",
            scan.short_faces
        ));
    }
    if !partial_normals.is_empty() {
        w.push(format!(
            "{f}: some faces lack vertex normals; flat shading used for {}",
            partial_normals.join(", ")
        ));
    }
    if !partial_uvs.is_empty() {
        w.push(format!(
            "{f}: some faces lack texture coordinates; none used for {}",
            partial_uvs.join(", ")
        ));
    }
    if loader.scene.instances.is_empty() {
        w.push(format!("{f}: no triangles left to render"));
    }
    Ok(loader.scene)
}

/// The `tobj` material loader: resolves `lib` (an `mtllib` argument) inside
/// the OBJ's folder, checks and parses it. A missing file is a warning; a
/// path leaving the folder or a malformed file is an error (stored in
/// `state`, since tobj only passes its own error type through).
fn load_mtllib(
    obj: &Path,
    options: &LoadOptions,
    mtllibs: &[(usize, String)],
    state: &RefCell<MtlState>,
    lib: &Path,
) -> tobj::MTLLoadResult {
    let mut st = state.borrow_mut();
    if st.error.is_some() {
        return Err(tobj::LoadError::OpenFileFailed);
    }
    let arg = lib.to_string_lossy().into_owned();
    // The line of this mtllib statement (the n-th one with this argument).
    let nth = st.seen.entry(arg.clone()).or_insert(0);
    let line = mtllibs
        .iter()
        .filter(|(_, a)| *a == arg)
        .nth(*nth)
        .map(|(l, _)| *l);
    *nth += 1;
    let location = || match line {
        Some(line) => Location::Line { line, column: None },
        None => Location::File,
    };
    let at = match line {
        Some(l) => format!("{}:{l}", obj.display()),
        None => obj.display().to_string(),
    };
    // `mtllib a.mtl b.mtl` names two files, unless a file has that name.
    let whole = obj.parent().unwrap_or(Path::new("")).join(&arg);
    let names: Vec<&str> = if arg.contains(char::is_whitespace) && !whole.exists() {
        arg.split_whitespace().collect()
    } else {
        vec![arg.as_str()]
    };
    // tobj's map type is private: start from the first parsed library's.
    let mut merged: Option<tobj::MTLLoadResult> = None;
    for name in names {
        let file =
            match crate::paths::resolve_uri(obj, name, &options.allowed_absolute_paths, location())
            {
                Ok(f) => f,
                Err(e) => {
                    st.error = Some(e);
                    return Err(tobj::LoadError::OpenFileFailed);
                }
            };
        let bytes = match std::fs::read(&file) {
            Ok(b) => b,
            Err(e) => {
                st.warnings.push(format!(
                    "{at}: material library '{name}' cannot be read ({e}); its materials are replaced by the default grey material"
                ));
                continue;
            }
        };
        let text = String::from_utf8_lossy(&bytes);
        let prepared = match prepare_mtl(&file, &text) {
            Ok(p) => p,
            Err(e) => {
                st.error = Some(with_context(e, &at));
                return Err(tobj::LoadError::MaterialParseError);
            }
        };
        let (mats, names_map) =
            match tobj::load_mtl_buf(&mut std::io::Cursor::new(prepared.text.as_bytes())) {
                Ok(r) => r,
                Err(e) => {
                    st.error = Some(with_context(
                        SceneError::in_file(&file, format!("cannot parse MTL: {e}")),
                        &at,
                    ));
                    return Err(tobj::LoadError::MaterialParseError);
                }
            };
        let source = MtlSource {
            file: file.clone(),
            lines: prepared.lines,
            notes: prepared.notes,
        };
        st.sources.extend(std::iter::repeat_n(source, mats.len()));
        match &mut merged {
            Some(Ok((materials, map))) => {
                let offset = materials.len();
                for (k, v) in names_map {
                    map.insert(k, v + offset);
                }
                materials.extend(mats);
            }
            _ => merged = Some(Ok((mats, names_map))),
        }
    }
    // Nothing loaded (all files missing): an error, which tobj keeps only if
    // no library loaded at all.
    merged.unwrap_or(Err(tobj::LoadError::OpenFileFailed))
}

/// Adds "(material library of OBJ:LINE)" to an error in an MTL file.
fn with_context(e: SceneError, at: &str) -> SceneError {
    match e {
        SceneError::Invalid {
            file,
            location,
            message,
        } => SceneError::Invalid {
            file,
            location,
            message: format!("{message} (material library named at {at})"),
        },
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each line of a valid file replaced by hostile statements: any result
    /// but a panic is fine.
    #[test]
    fn edited_content_never_panics() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/corpus/obj/ok_materials.obj");
        let text = std::fs::read_to_string(&path).unwrap();
        let options = LoadOptions::default();
        assert!(load_obj_text(&path, &text, &options).is_ok());
        let hostile = [
            "",
            "f 1/-99999999999 2 3",
            "f 1//-5 2 3",
            "f 1/-1/-1 2/-2/-2 3",
            "f 0 0 0",
            "f 1/2/3/4 2 3",
            "f -1 -1",
            "f 1 1 1 1 1 1",
            "v 1e39 0 0",
            "v 1 2",
            "v 1 2 3 0",
            "v 1 2 3 4 5",
            "v 1 2 3 0.5 0.5 0.5",
            "vt",
            "vt 1 2 3 4",
            "vn 0 0",
            "vn nan 0 0",
            "mtllib",
            "mtllib \t ",
            "mtllib /etc/passwd",
            "mtllib ok_materials.mtl ok_materials.mtl",
            "usemtl",
            "usemtl nothing",
            "o",
            "g",
            "l 1 2 3",
            "p 1",
            "\u{feff}v 0 0 0",
            "s 1",
        ];
        let lines: Vec<&str> = text.lines().collect();
        for i in 0..lines.len() {
            for h in hostile {
                let mut m = lines.clone();
                m[i] = h;
                let _ = load_obj_text(&path, &m.join("\n"), &options);
            }
        }
        for cut in 0..text.len() {
            if text.is_char_boundary(cut) {
                let _ = load_obj_text(&path, &text[..cut], &options);
            }
        }
    }
}
