//! glTF 2.0 loader: `.gltf` (+ external or `data:` buffers) and `.glb`.
//!
//! The JSON is parsed with the `gltf` crate's typed model (`gltf::json`), but
//! the GLB container, buffers, images and accessors are read here, with every
//! range checked before it is read, so a malformed file gives a
//! [`SceneError`] naming the file, the JSON path and the problem, never a
//! panic. External URIs go through [`crate::paths::resolve_uri`] and cannot
//! leave the scene's folder.
//!
//! What is read: the node hierarchy of the default scene (or scene 0)
//! with TRS/matrix transforms; TRIANGLES primitives (POSITION, NORMAL,
//! TEXCOORD_0/1, COLOR_0 (RGB or RGBA, alpha dropped), indexed or not, sparse accessors, any component type) as one
//! [`Mesh`] per primitive shared by all [`Instance`]s; the first camera;
//! `KHR_lights_punctual` (cd and lux → W/sr and W/m² with 683 lm/W);
//! materials as Lambertian (see `material.rs` for what is exact).

mod accessor;
mod container;
mod instancing;
mod material;
pub(crate) mod texture;
mod topology;

use super::LoadOptions;
use crate::camera::{Camera, Projection};
use crate::error::{Location, SceneError};
use crate::material::{Material, MaterialId};
use crate::mesh::{Instance, Mesh, MeshId};
use crate::paths::resolve_uri;
use crate::scene::{Scene, SceneLight};
use crate::texture::TextureId;
use ::gltf::json;
use ::gltf::json::validation::{Checked, Validate};
use glam::{Mat3, Mat4, Quat, Vec3};
use penumbra_shading::Rgb;
use penumbra_shading::light::{DirectionalLight, Light, PointLight, SpotLight};
use penumbra_shading::radiometry::{candela_to_watts_per_sr, lux_to_watts_per_m2};
use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;
use topology::Topology;

/// Extensions that may appear in `extensionsRequired`: read exactly, or
/// approximated with a warning (any `KHR_materials_*` is approximated).
const LOADABLE_REQUIRED: &[&str] = &[
    "EXT_mesh_gpu_instancing",
    "KHR_lights_punctual",
    "KHR_mesh_quantization",
    "KHR_texture_transform",
];

/// Extensions that need no file-level warning: read here, or reported per
/// material.
fn extension_is_handled(name: &str) -> bool {
    name.starts_with("KHR_materials_")
        || matches!(
            name,
            "EXT_mesh_gpu_instancing"
                | "KHR_lights_punctual"
                | "KHR_mesh_quantization"
                | "KHR_texture_transform"
        )
}

/// Loads a `.gltf` (+ external buffers) or `.glb` file.
pub fn load_gltf(path: &Path, options: &LoadOptions) -> Result<Scene, SceneError> {
    let bytes = super::read_file(path)?;
    load_gltf_bytes(path, &bytes, options)
}

/// Loads glTF or GLB content `bytes`; `path` names it in messages and
/// anchors relative URIs.
fn load_gltf_bytes(path: &Path, bytes: &[u8], options: &LoadOptions) -> Result<Scene, SceneError> {
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Err(SceneError::in_file(path, "file is empty"));
    }
    let binary_ext = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    let (json_bytes, bin, is_glb) = if container::is_glb(bytes) || binary_ext {
        let glb = container::split_glb(path, bytes)?;
        (glb.json, glb.bin, true)
    } else {
        (bytes, None, false)
    };
    let json_bytes = json_bytes
        .strip_prefix(b"\xEF\xBB\xBF".as_slice())
        .unwrap_or(json_bytes);

    let value: json::Value = json::deserialize::from_slice(json_bytes)
        .map_err(|e| json_error(path, &e, is_glb, "invalid JSON"))?;
    check_version(path, &value)?;
    let root: json::Root = json::deserialize::from_slice(json_bytes)
        .map_err(|e| json_error(path, &e, is_glb, "invalid glTF"))?;
    validate(path, &root)?;
    let buffers = load_buffers(path, options, &root, bin)?;

    let mut loader = Loader {
        file: path,
        options,
        root: &root,
        value: &value,
        buffers,
        scene: Scene::default(),
        meshes: HashMap::new(),
        materials: HashMap::new(),
        textures: HashMap::new(),
        default_material: None,
        degenerate: 0,
        notes: Notes::default(),
    };
    loader.walk()?;
    loader.finish();
    Ok(loader.scene)
}

/// A serde_json error as a [`SceneError`] at its line and column.
fn json_error(path: &Path, e: &json::Error, is_glb: bool, what: &str) -> SceneError {
    let full = e.to_string();
    let suffix = format!(" at line {} column {}", e.line(), e.column());
    let msg = full.strip_suffix(&suffix).unwrap_or(&full);
    let msg = if e.is_eof() {
        format!("truncated JSON: {msg}")
    } else {
        format!("{what}: {msg}")
    };
    if e.line() == 0 {
        SceneError::in_file(path, msg)
    } else if is_glb {
        SceneError::at_path(
            path,
            format!("JSON chunk, line {} column {}", e.line(), e.column()),
            msg,
        )
    } else {
        SceneError::invalid(
            path,
            Location::Line {
                line: e.line(),
                column: Some(e.column()),
            },
            msg,
        )
    }
}

/// `(major, minor)` of a version string like "2.0".
fn parse_version(s: &str) -> Option<(u32, u32)> {
    let (major, minor) = s.split_once('.')?;
    Some((major.parse().ok()?, minor.parse().ok()?))
}

/// Refuses anything but glTF 2.x (checked on the raw JSON, before the typed
/// model, whose errors would be confusing for another major version).
fn check_version(path: &Path, value: &json::Value) -> Result<(), SceneError> {
    if !value.is_object() {
        return Err(SceneError::in_file(
            path,
            "the top level of a glTF file must be a JSON object",
        ));
    }
    let version = &value["asset"]["version"];
    let Some(v) = version.as_str() else {
        let msg = if version.is_null() {
            "asset.version is missing (expected \"2.0\")".to_string()
        } else {
            format!("asset.version must be a string such as \"2.0\", found {version}")
        };
        return Err(SceneError::at_path(path, "asset.version", msg));
    };
    match parse_version(v) {
        Some((2, _)) => {}
        Some((major, _)) => {
            return Err(SceneError::at_path(
                path,
                "asset.version",
                format!(
                    "glTF version \"{v}\" is not supported (major version {major}; only 2.x is)"
                ),
            ));
        }
        None => {
            return Err(SceneError::at_path(
                path,
                "asset.version",
                format!("\"{v}\" is not a version of the form <major>.<minor>"),
            ));
        }
    }
    if let Some(min) = value["asset"]["minVersion"].as_str()
        && parse_version(min).is_none_or(|mv| mv > (2, 0))
    {
        return Err(SceneError::at_path(
            path,
            "asset.minVersion",
            format!("the file needs glTF {min}; only 2.0 is supported"),
        ));
    }
    Ok(())
}

/// `attributes["POSITION"]` → `attributes.POSITION`.
fn tidy_path(p: &str) -> String {
    p.replace("[\"", ".").replace("\"]", "")
}

/// Structural validation: the `gltf` crate's checks (indices in range,
/// required properties, enum values) plus the ones it lacks or would panic on.
fn validate(path: &Path, root: &json::Root) -> Result<(), SceneError> {
    // The crate's own validation indexes `accessors[POSITION]` unchecked.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            for (sem, acc) in &prim.attributes {
                if acc.value() >= root.accessors.len() {
                    return Err(SceneError::at_path(
                        path,
                        format!("meshes[{m}].primitives[{p}].attributes.{}", sem.to_string()),
                        format!(
                            "accessor index {} is out of range (there are {} accessors)",
                            acc.value(),
                            root.accessors.len()
                        ),
                    ));
                }
            }
        }
    }
    for (i, ext) in root.extensions_required.iter().enumerate() {
        if !(LOADABLE_REQUIRED.contains(&ext.as_str()) || ext.starts_with("KHR_materials_")) {
            return Err(SceneError::at_path(
                path,
                format!("extensionsRequired[{i}]"),
                format!("required extension {ext} is not supported"),
            ));
        }
    }
    let mut errors: Vec<(json::Path, json::validation::Error)> = Vec::new();
    root.validate(root, json::Path::new, &mut |p, e| errors.push((p(), e)));
    errors.retain(|(p, e)| {
        let p = p.as_str();
        // Checked above with our own list.
        !(p.starts_with("extensionsRequired")
            // POSITION min/max are required by the spec but not needed here.
            || (*e == json::validation::Error::Missing
                && (p.ends_with("[\"POSITION\"].min") || p.ends_with("[\"POSITION\"].max"))))
    });
    if let Some((p, e)) = errors.first() {
        use json::validation::Error as E;
        let what = match e {
            E::IndexOutOfBounds => "index out of range",
            E::Invalid => "invalid value",
            E::Missing => "required property is missing",
            E::Oversize => "value too large",
            E::Unsupported => "not supported",
        };
        let more = match errors.len() {
            1 => String::new(),
            n => format!(" (and {} more problem(s))", n - 1),
        };
        return Err(SceneError::at_path(
            path,
            tidy_path(p.as_str()),
            format!("{what}{more}"),
        ));
    }
    Ok(())
}

/// Reads every buffer: the GLB BIN chunk, a `data:` URI or a file inside
/// the scene's folder. Each must hold at least `byteLength` bytes.
fn load_buffers<'a>(
    path: &Path,
    options: &LoadOptions,
    root: &json::Root,
    bin: Option<&'a [u8]>,
) -> Result<Vec<Cow<'a, [u8]>>, SceneError> {
    let mut out = Vec::with_capacity(root.buffers.len());
    for (i, buffer) in root.buffers.iter().enumerate() {
        let bpath = format!("buffers[{i}]");
        let (data, what): (Cow<'a, [u8]>, String) = match &buffer.uri {
            None => match (i, bin) {
                (0, Some(bin)) => (Cow::Borrowed(bin), "the GLB BIN chunk".into()),
                (0, None) => {
                    return Err(SceneError::at_path(
                        path,
                        bpath,
                        "buffer has no uri and the file has no GLB BIN chunk",
                    ));
                }
                _ => {
                    return Err(SceneError::at_path(
                        path,
                        format!("{bpath}.uri"),
                        "uri is missing (only buffers[0] may refer to the GLB BIN chunk)",
                    ));
                }
            },
            Some(uri) if uri.starts_with("data:") => {
                let data = container::decode_data_uri(uri)
                    .map_err(|e| SceneError::at_path(path, format!("{bpath}.uri"), e))?;
                (Cow::Owned(data), "the data: URI".into())
            }
            Some(uri) => {
                let file = resolve_uri(
                    path,
                    uri,
                    &options.allowed_absolute_paths,
                    Location::Path(format!("{bpath}.uri")),
                )?;
                let data = std::fs::read(&file).map_err(|e| {
                    SceneError::at_path(
                        path,
                        format!("{bpath}.uri"),
                        format!("cannot read buffer file '{}': {e}", file.display()),
                    )
                })?;
                (Cow::Owned(data), format!("'{}'", file.display()))
            }
        };
        let declared = buffer.byte_length.0;
        if (data.len() as u64) < declared {
            return Err(SceneError::at_path(
                path,
                format!("{bpath}.byteLength"),
                format!(
                    "byteLength is {declared} but {what} holds only {} bytes (truncated?)",
                    data.len()
                ),
            ));
        }
        out.push(data);
    }
    Ok(out)
}

/// Non-fatal problems, aggregated into one warning per kind at the end.
#[derive(Debug, Default)]
struct Notes {
    skipped_modes: Vec<String>,
    /// Primitives whose normal map has no tangent frame (no NORMAL or not
    /// the map's UV set to build one).
    no_tangent_frame: Vec<String>,
    /// Primitives whose material reads a UV set they lack, with the set.
    missing_uv_set: Vec<String>,
    morph_targets: Vec<String>,
    skins: Vec<usize>,
    singular: Vec<usize>,
    cameras: Vec<usize>,
}

/// State of one load.
#[derive(Debug)]
struct Loader<'a> {
    file: &'a Path,
    options: &'a LoadOptions,
    root: &'a json::Root,
    /// The same document as raw JSON, for extensions the typed model drops.
    value: &'a json::Value,
    buffers: Vec<Cow<'a, [u8]>>,
    scene: Scene,
    /// (glTF mesh, primitive) → scene mesh (`None`: skipped or empty).
    meshes: HashMap<(usize, usize), Option<MeshId>>,
    materials: HashMap<usize, MaterialId>,
    /// Scene textures by glTF texture and UV transform (bits of its columns).
    textures: HashMap<(usize, usize, [u32; 6]), TextureId>,
    default_material: Option<MaterialId>,
    degenerate: usize,
    notes: Notes,
}

fn list(items: &[impl ToString]) -> String {
    items
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

impl Loader<'_> {
    fn err(&self, place: impl Into<String>, msg: impl Into<String>) -> SceneError {
        SceneError::at_path(self.file, place, msg)
    }

    /// Depth-first walk of the scene's node forest (explicit stack: no
    /// recursion limit), composing transforms.
    fn walk(&mut self) -> Result<(), SceneError> {
        let root = self.root;
        let roots: Vec<usize> = match (root.scene, root.scenes.first()) {
            (Some(s), _) => root
                .scenes
                .get(s.value())
                .ok_or_else(|| self.err("scene", format!("scene {} does not exist", s.value())))?
                .nodes
                .iter()
                .map(|n| n.value())
                .collect(),
            (None, Some(s0)) => s0.nodes.iter().map(|n| n.value()).collect(),
            (None, None) => {
                // No scenes at all: render every node that has no parent.
                let mut is_child = vec![false; root.nodes.len()];
                for n in &root.nodes {
                    for c in n.children.iter().flatten() {
                        if let Some(f) = is_child.get_mut(c.value()) {
                            *f = true;
                        }
                    }
                }
                (0..root.nodes.len()).filter(|&i| !is_child[i]).collect()
            }
        };
        let mut visited = vec![false; root.nodes.len()];
        let mut stack: Vec<(usize, Mat4)> =
            roots.iter().rev().map(|&n| (n, Mat4::IDENTITY)).collect();
        while let Some((n, parent)) = stack.pop() {
            let npath = format!("nodes[{n}]");
            let Some(node) = root.nodes.get(n) else {
                return Err(self.err(npath, "node does not exist"));
            };
            if std::mem::replace(&mut visited[n], true) {
                return Err(self.err(
                    npath,
                    "node is reached twice in the hierarchy (a node may have only one parent, and cycles are not allowed)",
                ));
            }
            let world = parent * self.local_transform(n, node)?;
            if !world.is_finite() {
                return Err(self.err(npath, "the node's world transform is not finite"));
            }
            if let Some(c) = node.camera {
                self.camera(n, c.value(), world)?;
            }
            if let Some(l) = node
                .extensions
                .as_ref()
                .and_then(|e| e.khr_lights_punctual.as_ref())
            {
                self.light(n, node, l.light.value(), world)?;
            }
            if let Some(m) = node.mesh {
                if node.skin.is_some() {
                    self.notes.skins.push(n);
                }
                for world in self.mesh_instances(n, world)? {
                    if !world.is_finite() {
                        return Err(self.err(
                            format!("{npath}.extensions.EXT_mesh_gpu_instancing"),
                            "an instance's world transform is not finite",
                        ));
                    }
                    self.instance_mesh(n, m.value(), world)?;
                }
            }
            for c in node.children.iter().flatten().rev() {
                stack.push((c.value(), world));
            }
        }
        Ok(())
    }

    fn local_transform(&self, n: usize, node: &json::Node) -> Result<Mat4, SceneError> {
        if let Some(m) = node.matrix {
            let m = Mat4::from_cols_array(&m);
            if !m.is_finite() {
                return Err(self.err(format!("nodes[{n}].matrix"), "matrix is not finite"));
            }
            return Ok(m);
        }
        let t = Vec3::from(node.translation.unwrap_or([0.0; 3]));
        let s = Vec3::from(node.scale.unwrap_or([1.0; 3]));
        let [x, y, z, w] = node.rotation.as_ref().map_or([0.0, 0.0, 0.0, 1.0], |r| r.0);
        let q = Quat::from_xyzw(x, y, z, w);
        for (what, ok) in [
            ("translation", t.is_finite()),
            ("scale", s.is_finite()),
            ("rotation", q.is_finite() && q.length_squared() > 0.0),
        ] {
            if !ok {
                return Err(self.err(
                    format!("nodes[{n}].{what}"),
                    format!("{what} is not finite (or a zero quaternion)"),
                ));
            }
        }
        Ok(Mat4::from_scale_rotation_translation(s, q.normalize(), t))
    }

    fn camera(&mut self, n: usize, c: usize, world: Mat4) -> Result<(), SceneError> {
        self.notes.cameras.push(n);
        let cpath = format!("cameras[{c}]");
        let cam = self
            .root
            .cameras
            .get(c)
            .ok_or_else(|| self.err(format!("nodes[{n}].camera"), "camera does not exist"))?;
        let (projection, aspect) = match cam.type_ {
            Checked::Valid(json::camera::Type::Perspective) => {
                let p = cam.perspective.as_ref().ok_or_else(|| {
                    self.err(format!("{cpath}.perspective"), "perspective is missing")
                })?;
                if !(p.yfov.is_finite() && p.yfov > 0.0 && p.yfov < std::f32::consts::PI) {
                    return Err(self.err(
                        format!("{cpath}.perspective.yfov"),
                        format!("yfov {} must be in (0, π)", p.yfov),
                    ));
                }
                (Projection::Perspective { fov_y: p.yfov }, p.aspect_ratio)
            }
            Checked::Valid(json::camera::Type::Orthographic) => {
                let o = cam.orthographic.as_ref().ok_or_else(|| {
                    self.err(format!("{cpath}.orthographic"), "orthographic is missing")
                })?;
                let ymag = o.ymag.abs();
                if !(ymag.is_finite() && ymag > 0.0) {
                    return Err(self.err(
                        format!("{cpath}.orthographic.ymag"),
                        format!("ymag {} must be finite and non-zero", o.ymag),
                    ));
                }
                let xmag = o.xmag.abs();
                let aspect = (xmag.is_finite() && xmag > 0.0).then(|| xmag / ymag);
                (Projection::Orthographic { height: 2.0 * ymag }, aspect)
            }
            Checked::Invalid => {
                return Err(self.err(format!("{cpath}.type"), "invalid camera type"));
            }
        };
        if let Some(a) = aspect
            && !(a.is_finite() && a > 0.0)
        {
            return Err(self.err(
                format!("{cpath}.perspective.aspectRatio"),
                format!("aspectRatio {a} must be positive"),
            ));
        }
        // The camera transform must be rigid: drop any scale.
        let (_, rotation, translation) = world.to_scale_rotation_translation();
        let rotation = rotation.normalize();
        if !(rotation.is_finite() && translation.is_finite()) {
            return Err(self.err(
                format!("nodes[{n}]"),
                "the camera's transform has no valid rotation (zero scale?)",
            ));
        }
        let camera = Camera {
            camera_to_world: Mat4::from_rotation_translation(rotation, translation),
            projection,
        };
        let name = cam
            .name
            .clone()
            .or_else(|| self.root.nodes.get(n).and_then(|node| node.name.clone()))
            .unwrap_or_else(|| format!("cameras[{c}]"));
        let named = crate::NamedCamera {
            name,
            camera,
            aspect,
        };
        if self.scene.camera.is_none() {
            self.scene.set_camera(&named);
        }
        self.scene.cameras.push(named);
        Ok(())
    }

    fn light(
        &mut self,
        n: usize,
        node: &json::Node,
        l: usize,
        world: Mat4,
    ) -> Result<(), SceneError> {
        use json::extensions::scene::khr_lights_punctual::Type;
        let lpath = format!("extensions.KHR_lights_punctual.lights[{l}]");
        let light = self
            .root
            .extensions
            .as_ref()
            .and_then(|e| e.khr_lights_punctual.as_ref())
            .and_then(|k| k.lights.get(l))
            .ok_or_else(|| {
                self.err(
                    format!("nodes[{n}].extensions.KHR_lights_punctual.light"),
                    format!("light {l} does not exist"),
                )
            })?;
        let color = Rgb::from(light.color);
        if !color.is_finite() || color.min_element() < 0.0 {
            return Err(self.err(
                format!("{lpath}.color"),
                "color must be finite and non-negative",
            ));
        }
        if !light.intensity.is_finite() || light.intensity < 0.0 {
            return Err(self.err(
                format!("{lpath}.intensity"),
                format!(
                    "intensity {} must be finite and non-negative",
                    light.intensity
                ),
            ));
        }
        let range = match light.range {
            None => f32::INFINITY,
            Some(r) if r.is_finite() && r > 0.0 => r,
            Some(r) => {
                return Err(self.err(
                    format!("{lpath}.range"),
                    format!("range {r} must be finite and positive"),
                ));
            }
        };
        let position = world.transform_point3(Vec3::ZERO);
        let direction = world.transform_vector3(-Vec3::Z).normalize_or_zero();
        let needs_direction = !matches!(light.type_, Checked::Valid(Type::Point));
        if needs_direction && direction == Vec3::ZERO {
            return Err(self.err(
                format!("nodes[{n}]"),
                "the light's direction (−Z of the node) is undefined: the transform is singular",
            ));
        }
        let light_value = match light.type_ {
            Checked::Valid(Type::Point) => Light::Point(PointLight {
                position,
                intensity: color * candela_to_watts_per_sr(light.intensity),
                range,
            }),
            Checked::Valid(Type::Directional) => Light::Directional(DirectionalLight {
                direction,
                irradiance: color * lux_to_watts_per_m2(light.intensity),
            }),
            Checked::Valid(Type::Spot) => {
                let spot = light.spot.clone().unwrap_or_default();
                let (inner, outer) = (spot.inner_cone_angle, spot.outer_cone_angle);
                if !(inner >= 0.0 && inner <= outer && outer <= std::f32::consts::FRAC_PI_2) {
                    return Err(self.err(
                        format!("{lpath}.spot"),
                        format!(
                            "cone angles must satisfy 0 ≤ innerConeAngle ({inner}) ≤ outerConeAngle ({outer}) ≤ π/2"
                        ),
                    ));
                }
                Light::Spot(SpotLight {
                    position,
                    direction,
                    intensity: color * candela_to_watts_per_sr(light.intensity),
                    cos_inner: inner.cos(),
                    cos_outer: outer.cos(),
                    range,
                })
            }
            Checked::Invalid => return Err(self.err(format!("{lpath}.type"), "invalid light type")),
        };
        let name = light
            .name
            .clone()
            .or_else(|| node.name.clone())
            .unwrap_or_else(|| format!("lights[{l}]"));
        self.scene.lights.push(SceneLight {
            name,
            light: light_value,
        });
        Ok(())
    }

    fn instance_mesh(&mut self, n: usize, m: usize, world: Mat4) -> Result<(), SceneError> {
        let mesh = self.root.meshes.get(m).ok_or_else(|| {
            self.err(
                format!("nodes[{n}].mesh"),
                format!("mesh {m} does not exist"),
            )
        })?;
        let det = Mat3::from_mat4(world).determinant();
        if det == 0.0 || !det.is_finite() {
            self.notes.singular.push(n);
            return Ok(());
        }
        for p in 0..mesh.primitives.len() {
            let id = match self.meshes.get(&(m, p)) {
                Some(&id) => id,
                None => {
                    let id = self.build_primitive(m, p)?;
                    self.meshes.insert((m, p), id);
                    id
                }
            };
            if let Some(id) = id {
                self.scene.instances.push(Instance::new(id, world));
            }
        }
        Ok(())
    }

    fn default_material(&mut self) -> MaterialId {
        *self
            .default_material
            .get_or_insert_with(|| self.scene.add_material(Material::default_grey()))
    }

    /// Converts `meshes[m].primitives[p]`; `None` if skipped (not triangles)
    /// or empty after removing degenerate triangles.
    fn build_primitive(&mut self, m: usize, p: usize) -> Result<Option<MeshId>, SceneError> {
        use json::mesh::{Mode, Semantic};
        let mesh = &self.root.meshes[m];
        let prim = &mesh.primitives[p];
        let base = format!("meshes[{m}].primitives[{p}]");
        let topology = match prim.mode {
            Checked::Valid(Mode::Triangles) => Topology::Triangles,
            Checked::Valid(Mode::TriangleStrip) => Topology::Strip,
            Checked::Valid(Mode::TriangleFan) => Topology::Fan,
            Checked::Valid(mode) => {
                let name = match mode {
                    Mode::Points => "POINTS",
                    Mode::Lines => "LINES",
                    Mode::LineLoop => "LINE_LOOP",
                    _ => "LINE_STRIP",
                };
                self.notes.skipped_modes.push(format!("{base} ({name})"));
                return Ok(None);
            }
            Checked::Invalid => return Err(self.err(format!("{base}.mode"), "invalid mode")),
        };
        if prim.targets.as_ref().is_some_and(|t| !t.is_empty()) {
            self.notes.morph_targets.push(base.clone());
        }
        let attr = |s: Semantic| prim.attributes.get(&Checked::Valid(s)).map(|a| a.value());
        let pos_acc = attr(Semantic::Positions).ok_or_else(|| {
            self.err(format!("{base}.attributes.POSITION"), "POSITION is missing")
        })?;
        let pos_path = format!("{base}.attributes.POSITION");
        let positions = self.read_vec3(pos_acc, &pos_path)?;
        let nverts = positions.len();
        let count_check = |name: &str, len: usize| {
            if len == nverts {
                Ok(())
            } else {
                Err(self.err(
                    format!("{base}.attributes.{name}"),
                    format!("{name} has {len} entries but POSITION has {nverts}"),
                ))
            }
        };
        let normals = match attr(Semantic::Normals) {
            Some(a) => {
                let v = self.read_vec3(a, &format!("{base}.attributes.NORMAL"))?;
                count_check("NORMAL", v.len())?;
                Some(v)
            }
            None => None,
        };
        let mut uvs = [None, None];
        for (set, slot) in uvs.iter_mut().enumerate() {
            if let Some(a) = attr(Semantic::TexCoords(set as u32)) {
                let name = format!("TEXCOORD_{set}");
                let v = self.read_vec2(a, &format!("{base}.attributes.{name}"))?;
                count_check(&name, v.len())?;
                if let Some(i) = v.iter().position(|t| !t.is_finite()) {
                    return Err(self.err(
                        format!("{base}.attributes.{name}"),
                        format!("vertex {i} has a non-finite texture coordinate (accessors[{a}])"),
                    ));
                }
                *slot = Some(v);
            }
        }
        let [uv0, uv1] = uvs;
        let tangents = match attr(Semantic::Tangents) {
            Some(a) => {
                let usage = format!("{base}.attributes.TANGENT");
                let v = self.read_vec4(a, &usage)?;
                count_check("TANGENT", v.len())?;
                if let Some(i) = v.iter().position(|t| !t.is_finite()) {
                    return Err(self.err(
                        usage,
                        format!("vertex {i} has a non-finite tangent (accessors[{a}])"),
                    ));
                }
                Some(v)
            }
            None => None,
        };
        let colors = match attr(Semantic::Colors(0)) {
            Some(a) => {
                let usage = format!("{base}.attributes.COLOR_0");
                let v = self.read_colors(a, &usage)?;
                count_check("COLOR_0", v.len())?;
                if let Some(i) = v
                    .iter()
                    .position(|c| !c.is_finite() || c.min_element() < 0.0)
                {
                    return Err(self.err(
                        usage,
                        format!("vertex {i} has a negative or non-finite colour (accessors[{a}])"),
                    ));
                }
                Some(v)
            }
            None => None,
        };
        let (sequence, index_acc) = match prim.indices {
            Some(ix) => {
                let ix = ix.value();
                (self.read_indices(ix, &format!("{base}.indices"))?, Some(ix))
            }
            None => {
                if nverts > u32::MAX as usize {
                    return Err(self.err(pos_path, format!("{nverts} vertices is too many")));
                }
                ((0..nverts as u32).collect(), None)
            }
        };
        let triangles = topology::triangles(topology, &sequence).map_err(|e| match index_acc {
            Some(ix) => self.err(format!("{base}.indices"), format!("{e} (accessors[{ix}])")),
            None => self.err(pos_path.clone(), format!("a non-indexed primitive: {e}")),
        })?;
        let material = match prim.material {
            Some(mi) => self.material(mi.value())?,
            None => self.default_material(),
        };
        let mesh_name = mesh.name.clone().unwrap_or_else(|| format!("meshes[{m}]"));
        let name = if mesh.primitives.len() > 1 {
            format!("{mesh_name}.{p}")
        } else {
            mesh_name
        };
        let mut out = Mesh {
            name,
            positions,
            normals,
            uv0,
            uv1,
            colors,
            tangents,
            indices: triangles,
            material,
        };
        if let Err(msg) = out.validate() {
            let normal_acc = attr(Semantic::Normals);
            let (place, acc) = if msg.contains("non-finite position") {
                (pos_path, Some(pos_acc))
            } else if msg.contains("non-finite normal") {
                (format!("{base}.attributes.NORMAL"), normal_acc)
            } else if msg.starts_with("triangle") {
                match index_acc {
                    Some(ix) => (format!("{base}.indices"), Some(ix)),
                    None => (pos_path, Some(pos_acc)),
                }
            } else {
                (base, None)
            };
            let msg = match acc {
                Some(a) => format!("{msg} (accessors[{a}])"),
                None => msg,
            };
            return Err(self.err(place, msg));
        }
        self.degenerate += out.remove_degenerate().degenerate_triangles;
        if out.indices.is_empty() {
            return Ok(None);
        }
        // A normal map needs a tangent frame: MikkTSpace when the file has
        // no TANGENT (as glTF asks), which needs normals and the map's UV set.
        let uses = self.scene.materials[material].textures();
        let sets: Vec<usize> = uses.map(|t| self.scene.textures[t].uv_set).collect();
        if let Some(&set) = sets.iter().find(|&&set| out.uv_set(set).is_none()) {
            self.notes
                .missing_uv_set
                .push(format!("{base} (TEXCOORD_{set})"));
        }
        if let Some(map) = self.scene.materials[material].normal_map
            && out.tangents.is_none()
        {
            let set = self.scene.textures[map.texture].uv_set;
            if out.normals.is_some() && out.uv_set(set).is_some() {
                out.tangents = Some(crate::tangents::mikktspace_tangents(&out, set));
            } else {
                self.notes.no_tangent_frame.push(base.clone());
            }
        }
        self.scene.meshes.push(out);
        Ok(Some(self.scene.meshes.len() - 1))
    }

    /// Turns the aggregated notes into warnings.
    fn finish(&mut self) {
        let f = self.file.display().to_string();
        let w = &mut self.scene.warnings;
        let n = &self.notes;
        if self.degenerate > 0 {
            w.push(format!(
                "{f}: skipped {} degenerate triangle(s) (zero area)",
                self.degenerate
            ));
        }
        if !n.no_tangent_frame.is_empty() {
            w.push(format!(
                "{f}: normal map not applied (no NORMAL, or not the UV set the map reads, to build a tangent frame from) on {}",
                list(&n.no_tangent_frame)
            ));
        }
        if !n.missing_uv_set.is_empty() {
            w.push(format!(
                "{f}: textures read a UV set the primitive does not have (texture coordinates are undefined there: the texture looks flat or smeared) on {}",
                list(&n.missing_uv_set)
            ));
        }
        if !n.skipped_modes.is_empty() {
            w.push(format!(
                "{f}: skipped {} primitive(s) of points or lines (only triangles are rendered): {}",
                n.skipped_modes.len(),
                list(&n.skipped_modes)
            ));
        }
        if !n.morph_targets.is_empty() {
            w.push(format!(
                "{f}: morph targets ignored (base shape used) on {}",
                list(&n.morph_targets)
            ));
        }
        if !n.skins.is_empty() {
            let nodes: Vec<String> = n.skins.iter().map(|i| format!("nodes[{i}]")).collect();
            w.push(format!(
                "{f}: skinning ignored (bind pose with the node transform) on {}",
                list(&nodes)
            ));
        }
        if !n.singular.is_empty() {
            let nodes: Vec<String> = n.singular.iter().map(|i| format!("nodes[{i}]")).collect();
            w.push(format!(
                "{f}: skipped the meshes of node(s) with a singular (zero-scale) transform: {}",
                list(&nodes)
            ));
        }
        if n.cameras.len() > 1 {
            w.push(format!(
                "{f}: {} camera nodes; using the first (nodes[{}]); --camera NAME|INDEX picks another",
                n.cameras.len(),
                n.cameras[0]
            ));
        }
        let unsupported: Vec<&String> = self
            .root
            .extensions_used
            .iter()
            .filter(|e| !extension_is_handled(e))
            .collect();
        if !unsupported.is_empty() {
            w.push(format!(
                "{f}: extension(s) not supported, ignored: {}",
                list(&unsupported)
            ));
        }
        if self.scene.instances.is_empty() {
            w.push(format!("{f}: the scene has no triangle geometry"));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GLB: &[u8] = include_bytes!("../../tests/corpus/gltf/ok_triangle.glb");
    const FEATURES: &str = include_str!("../../tests/corpus/gltf/ok_features.gltf");

    /// Corrupted copies of valid files: any result but a panic is fine.
    #[test]
    fn corrupted_content_never_panics() {
        let options = LoadOptions::default();
        let glb = Path::new("mem.glb");
        assert!(load_gltf_bytes(glb, GLB, &options).is_ok());
        for cut in 0..GLB.len() {
            let _ = load_gltf_bytes(glb, &GLB[..cut], &options);
        }
        for i in 0..GLB.len() {
            for v in [0x00, 0xff, 0x7f, 0x80] {
                let mut m = GLB.to_vec();
                m[i] = v;
                let _ = load_gltf_bytes(glb, &m, &options);
            }
        }
        let gltf = Path::new("mem.gltf");
        assert!(load_gltf_bytes(gltf, FEATURES.as_bytes(), &options).is_ok());
        // Every digit of the JSON (outside the base64 data) replaced.
        let json_part = FEATURES.find("\"buffers\"").unwrap_or(FEATURES.len());
        for (i, c) in FEATURES[..json_part].char_indices() {
            if c.is_ascii_digit() {
                for r in ["9", "99999999999", "-1", "0.5", "1e40", "\"x\""] {
                    let m = format!("{}{r}{}", &FEATURES[..i], &FEATURES[i + 1..]);
                    let _ = load_gltf_bytes(gltf, m.as_bytes(), &options);
                }
            }
        }
        for cut in 0..FEATURES.len() {
            let _ = load_gltf_bytes(gltf, &FEATURES.as_bytes()[..cut], &options);
        }
        // Every byte of the base64 buffer data flipped (its values change).
        let data = FEATURES.find("base64,AAAA").unwrap() + 7;
        let end = data + FEATURES[data..].find('"').unwrap();
        for i in data..end {
            let m = format!("{}A{}", &FEATURES[..i], &FEATURES[i + 1..]);
            let _ = load_gltf_bytes(gltf, m.as_bytes(), &options);
        }
    }

    #[test]
    fn versions_and_paths() {
        assert_eq!(parse_version("2.0"), Some((2, 0)));
        assert_eq!(parse_version("10.1"), Some((10, 1)));
        assert_eq!(parse_version("2"), None);
        assert_eq!(
            tidy_path("meshes[0].primitives[1].attributes[\"POSITION\"]"),
            "meshes[0].primitives[1].attributes.POSITION"
        );
    }
}
