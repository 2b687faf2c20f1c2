//! glTF export of an AO bake: the scene as one binary glTF 2.0 file (GLB)
//! whose materials carry the baked kA as their `occlusionTexture`, read
//! through `TEXCOORD_1` (the light-map atlas), so any glTF viewer shows the
//! bake.
//!
//! What is written:
//!
//! * one glTF mesh per scene instance (instances of one mesh have their own
//!   atlas rectangles, so their own `TEXCOORD_1`): `POSITION` (object space,
//!   with min/max), `NORMAL` (normalised) if the mesh has normals,
//!   `TEXCOORD_0` if it has UVs, `TEXCOORD_1` = the instance's atlas page
//!   coordinates, indices. The atlas coordinates belong to triangle corners,
//!   so vertices are split where one vertex has several (the split is the
//!   same for every instance of a mesh: position, normal, UV and index data
//!   are shared, only `TEXCOORD_1` is per instance). Both penumbra and glTF
//!   put UV (0, 0) at the top-left of the image: no flip;
//! * one node per instance with its transform as TRS; a transform that is no
//!   TRS (shear) is applied to the vertices instead (glTF forbids such node
//!   matrices), keeping the front faces of mirrored instances;
//! * the camera (perspective: `yfov`, aspect from the render resolution;
//!   orthographic: `xmag`/`ymag`), `KHR_lights_punctual` for point, spot and
//!   directional lights (W/sr and W/m² → cd and lux with 683 lm/W, the
//!   inverse of penumbra's loader), analytic area lights as emissive meshes;
//! * one material per (penumbra material, atlas page) pair, converted to
//!   glTF metallic–roughness (exactly where glTF can express the model, the
//!   nearest sensible approximation otherwise, with a warning), emission
//!   (`KHR_materials_emissive_strength` above 1), `doubleSided`, textures,
//!   and `occlusionTexture { index: <page>, texCoord: 1 }`;
//! * each atlas page as an 8-bit RGB PNG with R = G = B = kA, linear (glTF
//!   occlusion textures are linear data, read from R), sampled LINEAR with
//!   CLAMP_TO_EDGE, embedded in the BIN chunk.
//!
//! The file is written beside its final name and renamed into place, so a
//! failure leaves no partial file.

use crate::baked::{Bake, BakeKind};
use crate::error::BakeError;
use glam::{Mat3, Mat4, Quat, Vec2, Vec3};
use image::ImageEncoder;
use penumbra_scene::{Camera, Material, Mesh, Projection, Scene, Texture};
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{Bsdf, FresnelModel, optics::f0_from_ior};
use penumbra_shading::light::{Light, Shape};
use penumbra_shading::radiometry::LUMENS_PER_WATT;
use serde_json::{Map, Value, json};
use std::collections::{BTreeSet, HashMap};
use std::io::Write;
use std::path::{Path, PathBuf};

mod camera_lights;
mod container;
mod geometry;
mod materials;

use geometry::*;

/// `asset.generator` of every file written.
pub const GENERATOR: &str = "penumbra";

// glTF / OpenGL enums.
const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const LINEAR: u32 = 9729;
const CLAMP_TO_EDGE: u32 = 33071;
const REPEAT: u32 = 10497;

/// Writes `scene` as a binary glTF 2.0 file with the AO of `bake` as each
/// material's occlusionTexture on TEXCOORD_1 (see the module docs). The
/// approximations made are dropped; [`write_glb_with_warnings`] returns them.
pub fn write_glb(bake: &Bake, scene: &Scene, path: &Path) -> Result<(), BakeError> {
    write_glb_with_warnings(bake, scene, path).map(|_| ())
}

/// [`write_glb`], returning what glTF could only approximate (materials,
/// lights, the environment), one sentence each.
pub fn write_glb_with_warnings(
    bake: &Bake,
    scene: &Scene,
    path: &Path,
) -> Result<Vec<String>, BakeError> {
    check_bake(bake, scene)?;
    check_output_file(path)?;
    let mut b = Builder::new(bake, scene, path);
    b.build()?;
    let bytes = b.glb()?;
    write_atomically(path, &bytes)?;
    Ok(b.warnings)
}

/// The bake must be AO and fit the scene.
fn check_bake(bake: &Bake, scene: &Scene) -> Result<(), BakeError> {
    if !matches!(bake.kind, BakeKind::Ao { .. }) {
        return Err(BakeError::Settings(format!(
            "glTF export takes an AO bake (its kA becomes the occlusionTexture); this is a {} bake",
            bake.kind.name()
        )));
    }
    let a = &bake.atlas;
    let pages = bake.maps.first().map_or(0, |m| m.pages.len());
    if a.instances.len() != scene.instances.len()
        || a.meshes.len() != scene.meshes.len()
        || pages != a.pages as usize
    {
        return Err(BakeError::Settings(format!(
            "the bake does not fit the scene (its atlas has {} instances, {} meshes and {} pages, its map {pages} pages; the scene has {} instances and {} meshes): was it made for another scene?",
            a.instances.len(),
            a.meshes.len(),
            a.pages,
            scene.instances.len(),
            scene.meshes.len()
        )));
    }
    for (m, layout) in a.meshes.iter().enumerate() {
        if let Some(l) = layout
            && l.corner_uvs.len() != scene.meshes[m].indices.len()
        {
            return Err(BakeError::Settings(format!(
                "the bake does not fit the scene: mesh {m} has {} triangles, its layout {}",
                scene.meshes[m].indices.len(),
                l.corner_uvs.len()
            )));
        }
    }
    let map_pages = bake.maps.first().map_or(&[][..], |m| m.pages.as_slice());
    for (p, img) in map_pages.iter().enumerate() {
        if img.width != a.width || img.height != a.height {
            return Err(BakeError::Settings(format!(
                "page {p} of the bake is {}x{}, its atlas {}x{}",
                img.width, img.height, a.width, a.height
            )));
        }
    }
    Ok(())
}

/// The output's folder must exist and the output must not be a folder.
fn check_output_file(path: &Path) -> Result<(), BakeError> {
    if path.file_name().is_none() {
        return Err(BakeError::file(path, "is not a file name"));
    }
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !parent.is_dir() {
        return Err(BakeError::file(
            path,
            format!("the folder {} does not exist", parent.display()),
        ));
    }
    if path.is_dir() {
        return Err(BakeError::file(path, "is a folder, not a file"));
    }
    Ok(())
}

/// Writes `bytes` to a hidden sibling of `path`, then renames it over
/// `path`; on failure the sibling is removed.
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), BakeError> {
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    let tmp: PathBuf = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        BakeError::file(path, format!("cannot write the glTF file: {e}"))
    })
}

/// A JSON number of an f32 in its shortest decimal form (it reads back as
/// the same f32); non-finite values, which no valid scene has, become 0.
fn num(x: f32) -> Value {
    if !x.is_finite() {
        return json!(0.0);
    }
    match x.to_string().parse::<f64>() {
        Ok(v) => json!(v),
        Err(_) => json!(x as f64),
    }
}

fn nums(v: &[f32]) -> Value {
    Value::Array(v.iter().map(|&x| num(x)).collect())
}

fn rgb(c: Rgb) -> Value {
    nums(&c.to_array())
}

fn rgba(c: Rgb) -> Value {
    nums(&[c.x, c.y, c.z, 1.0])
}

/// Key of an exported material: penumbra material, atlas page (`None`: no
/// occlusion), and whether the primitive has TEXCOORD_0 (textures need it).
type MaterialKey = (usize, Option<u32>, bool);

struct Builder<'a> {
    bake: &'a Bake,
    scene: &'a Scene,
    /// The output file, named in errors.
    path: &'a Path,
    bin: Vec<u8>,
    buffer_views: Vec<Value>,
    accessors: Vec<Value>,
    images: Vec<Value>,
    textures: Vec<Value>,
    samplers: Vec<Value>,
    materials: Vec<Value>,
    meshes: Vec<Value>,
    nodes: Vec<Value>,
    cameras: Vec<Value>,
    lights: Vec<Value>,
    extensions_used: BTreeSet<String>,
    warnings: Vec<String>,
    /// Atlas page → glTF texture of its kA.
    page_textures: HashMap<u32, usize>,
    /// (penumbra texture, sRGB) → glTF texture.
    scene_textures: HashMap<(usize, bool), usize>,
    material_index: HashMap<MaterialKey, usize>,
    clamp_sampler: Option<usize>,
    repeat_sampler: Option<usize>,
    split: HashMap<usize, (SplitMesh, MeshAccessors)>,
}

impl<'a> Builder<'a> {
    fn new(bake: &'a Bake, scene: &'a Scene, path: &'a Path) -> Self {
        Self {
            bake,
            scene,
            path,
            bin: Vec::new(),
            buffer_views: Vec::new(),
            accessors: Vec::new(),
            images: Vec::new(),
            textures: Vec::new(),
            samplers: Vec::new(),
            materials: Vec::new(),
            meshes: Vec::new(),
            nodes: Vec::new(),
            cameras: Vec::new(),
            lights: Vec::new(),
            extensions_used: BTreeSet::new(),
            warnings: Vec::new(),
            page_textures: HashMap::new(),
            scene_textures: HashMap::new(),
            material_index: HashMap::new(),
            clamp_sampler: None,
            repeat_sampler: None,
            split: HashMap::new(),
        }
    }

    fn build(&mut self) -> Result<(), BakeError> {
        for i in 0..self.scene.instances.len() {
            self.instance(i)?;
        }
        for l in 0..self.scene.area_lights.len() {
            self.area_light(l)?;
        }
        if let Some(cam) = self.scene.camera {
            self.camera(&cam);
        }
        for l in 0..self.scene.lights.len() {
            self.light(l);
        }
        let s = self.scene;
        if s.environment_map.is_some() {
            self.warnings
                .push("the environment map is not exported (glTF has no environment)".into());
        } else if s.background.max_element() > 0.0 {
            self.warnings.push(format!(
                "the constant background {} is not exported (glTF has no environment)",
                s.background
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::container::{linear8, srgb8};
    use super::*;

    #[test]
    fn trs_detection() {
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(2.0, 3.0, 0.5),
            Quat::from_rotation_y(0.7),
            Vec3::new(1.0, -2.0, 3.0),
        );
        let (t, r, s) = as_trs(m).unwrap();
        assert!((t - Vec3::new(1.0, -2.0, 3.0)).length() < 1e-6);
        assert!((s - Vec3::new(2.0, 3.0, 0.5)).length() < 1e-5);
        assert!(r.angle_between(Quat::from_rotation_y(0.7)) < 1e-5);
        // Mirrored: still a TRS (negative scale).
        assert!(as_trs(Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0))).is_some());
        // Shear is not.
        let mut shear = Mat4::IDENTITY;
        shear.y_axis.x = 0.5;
        assert!(as_trs(shear).is_none());
    }

    #[test]
    fn numbers_are_shortest_decimals() {
        assert_eq!(num(0.1).to_string(), "0.1");
        assert_eq!(num(0.885809).to_string(), "0.885809");
        assert_eq!(num(f32::NAN).to_string(), "0.0");
        assert_eq!(srgb8(1.0), 255);
        assert_eq!(srgb8(0.0), 0);
        assert!((127..=128).contains(&srgb8(0.214_041_14)));
        assert_eq!(linear8(0.5), 128);
    }
}
