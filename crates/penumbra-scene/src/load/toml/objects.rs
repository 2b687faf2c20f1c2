//! `[[objects]]`: a primitive `shape` or a `mesh` file, a material and a
//! transform. Shape parameters are in object space; the transform goes in
//! the instance.

use super::diag::Doc;
use super::raw::{Floats, RawObject};
use super::transform::transform;
use crate::error::{Location, SceneError};
use crate::load::{LoadOptions, load_scene};
use crate::material::Material;
use crate::mesh::{Instance, Mesh};
use crate::paths::resolve_uri;
use crate::primitives;
use crate::scene::{Scene, SceneLight};
use glam::{Mat4, Vec3};
use penumbra_shading::light::Light;
use std::collections::HashMap;

const SHAPES: &str = "sphere, quad, box, disk";

/// Adds every object to `scene` (whose materials are the file's, in order).
pub(super) fn objects(
    doc: &Doc<'_>,
    options: &LoadOptions,
    raws: &[RawObject],
    by_name: &HashMap<String, usize>,
    scene: &mut Scene,
) -> Result<(), SceneError> {
    // Objects without `material` use the file's material named "default",
    // else a grey one added on first use.
    let mut default_material = by_name.get("default").copied();
    for (i, o) in raws.iter().enumerate() {
        let path = format!("objects[{i}]");
        let xf = transform(doc, &path, o)?;
        let material = match &o.material {
            Some(name) => Some(lookup_material(doc, &path, name, by_name)?),
            None => None,
        };
        let first_instance = scene.instances.len();
        match (&o.mesh, &o.shape) {
            (Some(_), Some(_)) => {
                return Err(doc.err(
                    &format!("{path}.mesh"),
                    "an object has either shape = \"…\" or mesh = \"file\", not both",
                ));
            }
            (None, None) => {
                return Err(doc.err(
                    &path,
                    format!(
                        "an object needs shape = \"…\" ({SHAPES}) or mesh = \"file.obj|.gltf|.glb\""
                    ),
                ));
            }
            (Some(uri), None) => {
                if let Some(k) = o.shape_keys().first() {
                    return Err(doc.err(
                        &format!("{path}.{k}"),
                        format!("`{k}` is a shape parameter; a mesh object takes only name, material, mesh, planar_receiver and transform keys"),
                    ));
                }
                import_mesh(doc, options, &path, uri, material, xf, scene)?;
            }
            (None, Some(shape)) => {
                let mut mesh = shape_mesh(doc, &path, shape, o, &mut scene.warnings)?;
                mesh.name = o
                    .name
                    .clone()
                    .unwrap_or_else(|| format!("{path} ({shape})"));
                mesh.material = match material {
                    Some(m) => m,
                    None => *default_material
                        .get_or_insert_with(|| scene.add_material(Material::default_grey())),
                };
                scene.add_mesh(mesh, xf);
            }
        }
        if o.planar_receiver == Some(true) {
            for inst in &mut scene.instances[first_instance..] {
                inst.planar_receiver = true;
            }
        }
    }
    Ok(())
}

fn lookup_material(
    doc: &Doc<'_>,
    path: &str,
    name: &str,
    by_name: &HashMap<String, usize>,
) -> Result<usize, SceneError> {
    by_name.get(name).copied().ok_or_else(|| {
        let mut known: Vec<&str> = by_name.keys().map(String::as_str).collect();
        known.sort_unstable();
        let known = if known.is_empty() {
            "none; add a [[materials]] table".to_string()
        } else {
            known.join(", ")
        };
        doc.err(
            &format!("{path}.material"),
            format!("unknown material '{name}' (defined: {known})"),
        )
    })
}

/// Tessellates `shape` with the object's parameters.
fn shape_mesh(
    doc: &Doc<'_>,
    path: &str,
    shape: &str,
    o: &RawObject,
    warnings: &mut Vec<String>,
) -> Result<Mesh, SceneError> {
    let at = |k: &str| format!("{path}.{k}");
    let present = o.shape_keys();
    let point = |k: &str, v: &Option<Floats>| -> Result<Vec3, SceneError> {
        v.as_ref().map_or(Ok(Vec3::ZERO), |v| doc.vec3(&at(k), v))
    };
    match shape {
        "sphere" => {
            let keys = ["center", "radius", "subdivisions"];
            doc.only_keys(path, "a sphere", &present, &keys)?;
            let r = o
                .radius
                .ok_or_else(|| doc.err(path, "a sphere needs radius (> 0)"))?;
            let r = doc.positive(&at("radius"), r)?;
            let rings = match o.subdivisions {
                Some(n) => doc.int_in(&at("subdivisions"), n, 2, 1024)?,
                None => primitives::DEFAULT_SPHERE_RINGS,
            };
            Ok(primitives::sphere(point("center", &o.center)?, r, rings))
        }
        "quad" => quad(doc, path, o, warnings),
        "box" => {
            doc.only_keys(path, "a box", &present, &["min", "max", "center", "size"])?;
            match (&o.min, &o.max, &o.size) {
                (Some(lo), Some(hi), None) if o.center.is_none() => {
                    let (lo, hi) = (doc.vec3(&at("min"), lo)?, doc.vec3(&at("max"), hi)?);
                    if !lo.cmplt(hi).all() {
                        return Err(doc.err(
                            &at("max"),
                            format!("max must exceed min in every axis, got min {lo} max {hi}"),
                        ));
                    }
                    Ok(primitives::cuboid(lo, hi))
                }
                (None, None, Some(size)) => {
                    let c = point("center", &o.center)?;
                    let h = 0.5 * doc.extent3(&at("size"), size)?;
                    Ok(primitives::cuboid(c - h, c + h))
                }
                _ => Err(doc.err(
                    path,
                    "a box is given by min + max, or by size (+ center, default [0, 0, 0])",
                )),
            }
        }
        "disk" => {
            let keys = ["center", "normal", "radius", "segments"];
            doc.only_keys(path, "a disk", &present, &keys)?;
            let r = o
                .radius
                .ok_or_else(|| doc.err(path, "a disk needs radius (> 0)"))?;
            let r = doc.positive(&at("radius"), r)?;
            let n = match &o.normal {
                Some(n) => doc.direction(&at("normal"), n)?,
                None => Vec3::Y,
            };
            let segments = match o.segments {
                Some(s) => doc.int_in(&at("segments"), s, 3, 65_536)?,
                None => primitives::DEFAULT_DISK_SEGMENTS,
            };
            Ok(primitives::disk(
                point("center", &o.center)?,
                n,
                r,
                segments,
            ))
        }
        other => Err(doc.err(
            &at("shape"),
            format!("unknown shape '{other}' (expected one of: {SHAPES}, or use mesh = \"file\")"),
        )),
    }
}

/// A quad from corner + edge1 + edge2, from 4 vertices, or from center +
/// size (a rectangle in the object's xz-plane facing +y).
fn quad(
    doc: &Doc<'_>,
    path: &str,
    o: &RawObject,
    warnings: &mut Vec<String>,
) -> Result<Mesh, SceneError> {
    let at = |k: &str| format!("{path}.{k}");
    let keys = ["corner", "edge1", "edge2", "vertices", "center", "size"];
    doc.only_keys(path, "a quad", &o.shape_keys(), &keys)?;
    let forms = [
        o.corner.is_some() || o.edge1.is_some() || o.edge2.is_some(),
        o.vertices.is_some(),
        o.center.is_some() || o.size.is_some(),
    ];
    let usage = "a quad is given by corner + edge1 + edge2, or by vertices = [4 points], or by size (+ center): one of them";
    if forms.iter().filter(|f| **f).count() != 1 {
        return Err(doc.err(path, usage));
    }
    if let (Some(c), Some(e1), Some(e2)) = (&o.corner, &o.edge1, &o.edge2) {
        let c = doc.vec3(&at("corner"), c)?;
        let (e1, e2) = (doc.vec3(&at("edge1"), e1)?, doc.vec3(&at("edge2"), e2)?);
        if e1.cross(e2).length() <= 1e-6 * e1.length() * e2.length() || e1.cross(e2) == Vec3::ZERO {
            return Err(doc.err(
                &at("edge2"),
                format!("edge1 {e1} and edge2 {e2} are parallel or zero: the quad has no area"),
            ));
        }
        return Ok(primitives::quad(c, e1, e2));
    }
    if let Some(vs) = &o.vertices {
        if vs.len() != 4 {
            return Err(doc.err(
                &at("vertices"),
                format!("vertices must list 4 points [x, y, z], got {}", vs.len()),
            ));
        }
        let mut v = [Vec3::ZERO; 4];
        for (k, p) in vs.iter().enumerate() {
            v[k] = doc.vec3(&format!("{path}.vertices[{k}]"), p)?;
        }
        let n1 = (v[1] - v[0]).cross(v[2] - v[0]);
        let n2 = (v[2] - v[0]).cross(v[3] - v[0]);
        if n1 == Vec3::ZERO || n2 == Vec3::ZERO || n1.dot(n2) <= 0.0 {
            return Err(doc.err(
                &at("vertices"),
                "the 4 vertices must go round a convex quadrilateral in order (triangles (0,1,2) and (0,2,3) must both have area and face the same way)",
            ));
        }
        let size = (v[2] - v[0]).length().max((v[3] - v[1]).length());
        let off_plane = (v[3] - v[0]).dot(n1.normalize()).abs();
        if off_plane > 1e-2 * size {
            warnings.push(format!(
                "{}: {path}.vertices: the quad is not planar (vertex 3 is {off_plane} off the plane of 0, 1, 2); rendered as its two triangles",
                doc.file.display()
            ));
        }
        return Ok(primitives::quad_from_vertices(v));
    }
    match &o.size {
        Some(size) => {
            let c = match &o.center {
                Some(c) => doc.vec3(&at("center"), c)?,
                None => Vec3::ZERO,
            };
            Ok(primitives::rectangle(c, doc.extent2(&at("size"), size)?))
        }
        None => Err(doc.err(path, usage)),
    }
}

/// Loads a `mesh = "file"` object and appends its meshes, instances,
/// materials (unless `material` overrides them), textures and lights.
fn import_mesh(
    doc: &Doc<'_>,
    options: &LoadOptions,
    path: &str,
    uri: &str,
    material: Option<usize>,
    xf: Mat4,
    scene: &mut Scene,
) -> Result<(), SceneError> {
    let mp = format!("{path}.mesh");
    let location = Location::Path(mp.clone());
    let resolved = resolve_uri(doc.file, uri, &options.allowed_absolute_paths, location)
        .map_err(|e| doc.reanchor(&mp, e))?;
    let ext = resolved
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("obj" | "gltf" | "glb")) {
        return Err(doc.err(
            &mp,
            format!("mesh '{uri}' must be a .obj, .gltf or .glb file"),
        ));
    }
    if !resolved.is_file() {
        return Err(doc.err(
            &mp,
            format!(
                "mesh file '{uri}' not found (looked for {})",
                resolved.display()
            ),
        ));
    }
    let sub = load_scene(&resolved, options)
        .map_err(|e| doc.err(&mp, format!("cannot load mesh '{uri}': {e}")))?;
    if sub.instances.is_empty() {
        return Err(doc.err(&mp, format!("mesh file '{uri}' contains no geometry")));
    }
    merge(scene, sub, material, xf, uri);
    Ok(())
}

fn merge(scene: &mut Scene, sub: Scene, material: Option<usize>, xf: Mat4, uri: &str) {
    let (tex_off, mat_off, mesh_off) = (
        scene.textures.len(),
        scene.materials.len(),
        scene.meshes.len(),
    );
    if material.is_none() {
        scene.textures.extend(sub.textures);
        scene
            .materials
            .extend(sub.materials.into_iter().map(|mut m| {
                m.albedo_texture = m.albedo_texture.map(|t| t + tex_off);
                m
            }));
    }
    scene.meshes.extend(sub.meshes.into_iter().map(|mut m| {
        m.material = material.unwrap_or(m.material + mat_off);
        m
    }));
    scene
        .instances
        .extend(sub.instances.into_iter().map(|inst| Instance {
            mesh: inst.mesh + mesh_off,
            transform: xf * inst.transform,
            material: match material {
                Some(_) => None,
                None => inst.material.map(|m| m + mat_off),
            },
            planar_receiver: inst.planar_receiver,
        }));
    scene
        .lights
        .extend(sub.lights.into_iter().map(|l| transform_light(l, xf)));
    scene
        .warnings
        .extend(sub.warnings.into_iter().map(|w| format!("{uri}: {w}")));
    if sub.camera.is_some() {
        scene.warnings.push(format!(
            "{uri}: its camera is ignored; the TOML [camera] defines the view"
        ));
    }
}

fn transform_light(mut l: SceneLight, xf: Mat4) -> SceneLight {
    let dir = |d: Vec3| xf.transform_vector3(d).normalize_or(d);
    l.light = match l.light {
        Light::Point(mut p) => {
            p.position = xf.transform_point3(p.position);
            Light::Point(p)
        }
        Light::Directional(mut d) => {
            d.direction = dir(d.direction);
            Light::Directional(d)
        }
        Light::Spot(mut s) => {
            s.position = xf.transform_point3(s.position);
            s.direction = dir(s.direction);
            Light::Spot(s)
        }
    };
    l
}
