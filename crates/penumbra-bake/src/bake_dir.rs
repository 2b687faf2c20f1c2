//! A bake on disk: a directory with `manifest.json`, the layouts
//! (`uvs.bin`) and one float EXR per map and page, written all at once
//! (into a hidden sibling directory renamed into place at the end, so a
//! failed bake leaves nothing behind and an old bake is replaced whole).
//!
//! `uvs.bin`, little-endian: the magic `PNBKUV01`, the number of layouts
//! (u32), then per layout: the scene mesh index (u32), its triangle count n
//! (u32), n × 3 corner coordinates (u, v as f32), n chart ids (u32).

use crate::atlas::{Atlas, InstanceRect, MeshLayout, UvSource};
use crate::baked::{Bake, BakeKind};
use crate::error::BakeError;
use crate::manifest::*;
use crate::scene_hash::geometry_hash;
use glam::Vec2;
use penumbra_image::{Image, ToneMapping, read_exr_layers, write_image};
use penumbra_scene::Scene;
use std::path::{Path, PathBuf};

/// The layout file of a bake directory.
pub const UVS_FILE: &str = "uvs.bin";
const UVS_MAGIC: &[u8; 8] = b"PNBKUV01";

/// Writes `bake` of `scene` as the bake directory `dir` (replacing an
/// earlier bake there). `scene_file` is recorded in the manifest.
pub fn write_bake(
    bake: &Bake,
    scene: &Scene,
    dir: &Path,
    scene_file: Option<&str>,
) -> Result<(), BakeError> {
    check_output_dir(dir)?;
    let staging = sibling(dir, "partial")?;
    if staging.exists() {
        std::fs::remove_dir_all(&staging).map_err(|e| BakeError::file(&staging, e.to_string()))?;
    }
    std::fs::create_dir(&staging).map_err(|e| BakeError::file(&staging, e.to_string()))?;
    let result =
        write_contents(bake, scene, &staging, scene_file).and_then(|()| swap_in(&staging, dir));
    if result.is_err() {
        let _ = std::fs::remove_dir_all(&staging);
    }
    result
}

/// The output must be a new path, an empty directory or an earlier bake
/// (checked again by [`write_bake`]; callers check first to fail before
/// baking).
pub fn check_output_dir(dir: &Path) -> Result<(), BakeError> {
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !parent.is_dir() {
        return Err(BakeError::file(
            dir,
            format!("the folder {} does not exist", parent.display()),
        ));
    }
    if !dir.exists() {
        return Ok(());
    }
    if !dir.is_dir() {
        return Err(BakeError::file(dir, "exists and is not a directory"));
    }
    let empty = std::fs::read_dir(dir)
        .map_err(|e| BakeError::file(dir, e.to_string()))?
        .next()
        .is_none();
    if !empty && !dir.join(MANIFEST_FILE).is_file() {
        return Err(BakeError::file(
            dir,
            "exists and is neither empty nor a bake directory (no manifest.json); choose another -o",
        ));
    }
    Ok(())
}

/// A hidden sibling of `dir` for staging (`.NAME.TAG-PID`).
fn sibling(dir: &Path, tag: &str) -> Result<PathBuf, BakeError> {
    let name = dir
        .file_name()
        .ok_or_else(|| BakeError::file(dir, "is not a directory name"))?;
    Ok(dir.with_file_name(format!(
        ".{}.{tag}-{}",
        name.to_string_lossy(),
        std::process::id()
    )))
}

fn swap_in(staging: &Path, dir: &Path) -> Result<(), BakeError> {
    let io = |p: &Path, e: std::io::Error| BakeError::file(p, e.to_string());
    if dir.exists() {
        let old = sibling(dir, "old")?;
        std::fs::rename(dir, &old).map_err(|e| io(dir, e))?;
        std::fs::rename(staging, dir).map_err(|e| io(dir, e))?;
        std::fs::remove_dir_all(&old).map_err(|e| io(&old, e))?;
    } else {
        std::fs::rename(staging, dir).map_err(|e| io(dir, e))?;
    }
    Ok(())
}

fn write_contents(
    bake: &Bake,
    scene: &Scene,
    dir: &Path,
    scene_file: Option<&str>,
) -> Result<(), BakeError> {
    let uvs = encode_layouts(&bake.atlas);
    let uvs_path = dir.join(UVS_FILE);
    std::fs::write(&uvs_path, &uvs).map_err(|e| BakeError::file(&uvs_path, e.to_string()))?;
    let mut maps = Vec::new();
    for map in &bake.maps {
        let mut pages = Vec::new();
        for (p, (img, var)) in map.pages.iter().zip(&map.variance).enumerate() {
            let name = format!("{}-{p}.exr", map.name);
            let layers = [("variance", var), ("coverage", &bake.coverage[p])];
            write_image(&dir.join(&name), img, &layers, &ToneMapping::default())?;
            pages.push(name);
        }
        maps.push(MapInfo {
            name: map.name.clone(),
            light: map.light.clone(),
            pages,
        });
    }
    let convergence = if bake.convergence.is_empty() {
        None
    } else {
        let csv = crate::plot::convergence_csv(&bake.convergence);
        let svg = crate::plot::convergence_svg(&bake.convergence);
        for (name, text) in [("convergence.csv", &csv), ("convergence.svg", &svg)] {
            let p = dir.join(name);
            std::fs::write(&p, text).map_err(|e| BakeError::file(&p, e.to_string()))?;
        }
        let last = bake.convergence.last();
        Some(ConvergenceInfo {
            csv: "convergence.csv".into(),
            plot: "convergence.svg".into(),
            iterations: last.map_or(0, |s| s.iteration),
            final_unshot_fraction: last.map_or(0.0, |s| s.unshot_fraction),
        })
    };
    let manifest = manifest_of(bake, scene, scene_file, uvs.len() as u64, maps, convergence);
    let text = serde_json::to_string_pretty(&manifest)
        .map_err(|e| BakeError::file(dir.join(MANIFEST_FILE), e.to_string()))?;
    let path = dir.join(MANIFEST_FILE);
    std::fs::write(&path, text + "\n").map_err(|e| BakeError::file(&path, e.to_string()))
}

fn manifest_of(
    bake: &Bake,
    scene: &Scene,
    scene_file: Option<&str>,
    uvs_bytes: u64,
    maps: Vec<MapInfo>,
    convergence: Option<ConvergenceInfo>,
) -> Manifest {
    let a = &bake.atlas;
    let mut settings = SettingsInfo {
        samples: bake.samples,
        seed: bake.seed,
        ao_distance: None,
        bounces: None,
        indirect_only: false,
        per_light: bake.maps.len() > 1,
        patches: None,
        tolerance: None,
    };
    match bake.kind {
        BakeKind::Ao { distance } => {
            settings.ao_distance = distance.is_finite().then_some(distance)
        }
        BakeKind::Lightmap {
            bounces,
            indirect_only,
        } => {
            settings.bounces = Some(bounces);
            settings.indirect_only = indirect_only;
        }
        BakeKind::Radiosity { patches, tolerance } => {
            settings.patches = Some(patches);
            settings.tolerance = Some(tolerance);
        }
    }
    let instances = a
        .instances
        .iter()
        .enumerate()
        .filter_map(|(i, r)| {
            let r = r.as_ref()?;
            let mesh = scene.instances[i].mesh;
            let layout = a.meshes[mesh].as_ref()?;
            Some(InstanceInfo {
                instance: i,
                mesh,
                name: scene.meshes[mesh].name.clone(),
                page: r.page,
                uv_min: r.min.to_array(),
                uv_max: r.max.to_array(),
                uv_source: match layout.source {
                    UvSource::Generated => "generated",
                    UvSource::Texcoord1 => "texcoord1",
                }
                .into(),
            })
        })
        .collect();
    let s = &bake.stats;
    Manifest {
        format: FORMAT.into(),
        version: VERSION,
        kind: bake.kind.name().into(),
        quantity: bake.kind.quantity().into(),
        units: bake.kind.units().into(),
        scene: SceneInfo {
            file: scene_file.map(str::to_string),
            geometry_hash: geometry_hash(scene),
            instances: scene.instances.len(),
            triangles: scene.triangle_count(),
        },
        settings,
        atlas: AtlasInfo::of(a, UVS_FILE, uvs_bytes),
        instances,
        maps,
        texels: TexelInfo {
            covered: s.covered,
            valid: s.valid,
            invalid: s.invalid,
        },
        timing: TimingInfo {
            prepare_seconds: s.prepare_seconds,
            bake_seconds: s.bake_seconds,
            rays: s.rays,
            rays_per_second: if s.bake_seconds > 0.0 {
                s.rays as f64 / s.bake_seconds
            } else {
                0.0
            },
        },
        convergence,
        warnings: bake.warnings.clone(),
    }
}

fn encode_layouts(atlas: &Atlas) -> Vec<u8> {
    let mut out = UVS_MAGIC.to_vec();
    let layouts: Vec<(usize, &MeshLayout)> = atlas
        .meshes
        .iter()
        .enumerate()
        .filter_map(|(m, l)| Some((m, l.as_ref()?)))
        .collect();
    out.extend((layouts.len() as u32).to_le_bytes());
    for (m, l) in layouts {
        out.extend((m as u32).to_le_bytes());
        out.extend((l.corner_uvs.len() as u32).to_le_bytes());
        for c in l.corner_uvs.iter().flatten() {
            out.extend(c.x.to_le_bytes());
            out.extend(c.y.to_le_bytes());
        }
        for &c in &l.charts {
            out.extend(c.to_le_bytes());
        }
    }
    out
}

/// One mesh's layout as stored: corner coordinates and chart ids.
type DecodedLayout = (Vec<[Vec2; 3]>, Vec<u32>);

/// Reads `uvs.bin` into per-mesh layouts (`meshes` slots).
fn decode_layouts(
    path: &Path,
    bytes: &[u8],
    meshes: usize,
) -> Result<Vec<Option<DecodedLayout>>, BakeError> {
    let err = |m: String| BakeError::file(path, m);
    let mut pos = 0usize;
    let mut take = |n: usize| -> Result<&[u8], BakeError> {
        let s = bytes
            .get(pos..pos + n)
            .ok_or_else(|| err(format!("truncated at byte {pos} of {}", bytes.len())))?;
        pos += n;
        Ok(s)
    };
    if take(8)? != UVS_MAGIC {
        return Err(err("not a penumbra layout file (bad magic)".into()));
    }
    let u32_at = |b: &[u8]| u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    let count = u32_at(take(4)?) as usize;
    let mut out = vec![None; meshes];
    for _ in 0..count {
        let m = u32_at(take(4)?) as usize;
        let n = u32_at(take(4)?) as usize;
        if m >= meshes {
            return Err(err(format!(
                "layout for mesh {m}, but the scene has {meshes} meshes"
            )));
        }
        let uv_bytes = take(
            n.checked_mul(24)
                .ok_or_else(|| err("size overflow".into()))?,
        )?;
        let f = |k: usize| {
            f32::from_le_bytes([
                uv_bytes[4 * k],
                uv_bytes[4 * k + 1],
                uv_bytes[4 * k + 2],
                uv_bytes[4 * k + 3],
            ])
        };
        let corners: Vec<[Vec2; 3]> = (0..n)
            .map(|t| std::array::from_fn(|c| Vec2::new(f(6 * t + 2 * c), f(6 * t + 2 * c + 1))))
            .collect();
        let chart_bytes = take(n * 4)?;
        let charts = chart_bytes.chunks_exact(4).map(u32_at).collect();
        if corners.iter().flatten().any(|c| !c.is_finite()) {
            return Err(err(format!("mesh {m} has non-finite coordinates")));
        }
        out[m] = Some((corners, charts));
    }
    if pos != bytes.len() {
        return Err(err(format!(
            "{} bytes after the last layout",
            bytes.len() - pos
        )));
    }
    Ok(out)
}

/// A bake read back from disk: what the raster engine shows.
#[derive(Clone, Debug)]
pub struct LoadedBake {
    pub dir: PathBuf,
    pub manifest: Manifest,
    pub kind: BakeKind,
    pub atlas: Atlas,
    /// The `total` map, per page.
    pub pages: Vec<Image>,
    /// The `coverage` layer per page.
    pub coverage: Vec<Image>,
}

/// Reads the bake directory `dir`. With `scene`, checks that the bake was
/// made for it (the geometry hash) and that its layouts fit its meshes.
pub fn read_bake(dir: &Path, scene: &Scene) -> Result<LoadedBake, BakeError> {
    let manifest_path = dir.join(MANIFEST_FILE);
    if !dir.is_dir() {
        return Err(BakeError::file(
            dir,
            "is not a bake directory (not a folder)",
        ));
    }
    let text = std::fs::read_to_string(&manifest_path).map_err(|e| {
        BakeError::file(
            &manifest_path,
            format!("cannot read the manifest ({e}); is this a bake directory?"),
        )
    })?;
    let manifest = Manifest::parse(&manifest_path, &text)?;
    let err = |m: String| BakeError::file(&manifest_path, m);
    let hash = geometry_hash(scene);
    if manifest.scene.geometry_hash != hash {
        return Err(err(format!(
            "this bake was made for another scene{} (geometry hash {}; this scene's is {hash}): bake this scene again",
            manifest
                .scene
                .file
                .as_ref()
                .map_or(String::new(), |f| format!(" ({f})")),
            manifest.scene.geometry_hash
        )));
    }
    let kind = match manifest.kind.as_str() {
        "ao" => BakeKind::Ao {
            distance: manifest.settings.ao_distance.unwrap_or(f32::INFINITY),
        },
        "lightmap" => BakeKind::Lightmap {
            bounces: manifest.settings.bounces.unwrap_or(0),
            indirect_only: manifest.settings.indirect_only,
        },
        "radiosity" => BakeKind::Radiosity {
            patches: manifest.settings.patches.unwrap_or(0),
            tolerance: manifest.settings.tolerance.unwrap_or(0.0),
        },
        other => {
            return Err(err(format!(
                "unknown bake kind \"{other}\" (expected ao, lightmap or radiosity)"
            )));
        }
    };
    let a = &manifest.atlas;
    if a.pages == 0 || a.width == 0 || a.height == 0 {
        return Err(err(format!(
            "the atlas is empty ({} pages of {}x{})",
            a.pages, a.width, a.height
        )));
    }
    let uvs_path = dir.join(&a.uvs);
    let bytes = std::fs::read(&uvs_path).map_err(|e| BakeError::file(&uvs_path, e.to_string()))?;
    if bytes.len() as u64 != a.uvs_bytes {
        return Err(BakeError::file(
            &uvs_path,
            format!(
                "is {} bytes, the manifest says {}: truncated or replaced",
                bytes.len(),
                a.uvs_bytes
            ),
        ));
    }
    let layouts = decode_layouts(&uvs_path, &bytes, scene.meshes.len())?;
    let mut meshes = vec![None; scene.meshes.len()];
    for (m, l) in layouts.into_iter().enumerate() {
        let Some((corner_uvs, charts)) = l else {
            continue;
        };
        if corner_uvs.len() != scene.meshes[m].indices.len() {
            return Err(BakeError::file(
                &uvs_path,
                format!(
                    "mesh {m} has {} triangles, its layout {}",
                    scene.meshes[m].indices.len(),
                    corner_uvs.len()
                ),
            ));
        }
        meshes[m] = Some(MeshLayout {
            corner_uvs,
            charts,
            source: UvSource::Generated,
        });
    }
    let mut instances = vec![None; scene.instances.len()];
    for info in &manifest.instances {
        if info.instance >= scene.instances.len() || info.page >= a.pages {
            return Err(err(format!(
                "instance entry {} (page {}) is out of range",
                info.instance, info.page
            )));
        }
        let mesh = scene.instances[info.instance].mesh;
        match &mut meshes[mesh] {
            Some(l) => {
                if info.uv_source == "texcoord1" {
                    l.source = UvSource::Texcoord1;
                }
            }
            None => {
                return Err(err(format!(
                    "instance {} has a rectangle but its mesh {mesh} has no layout in {}",
                    info.instance, a.uvs
                )));
            }
        }
        instances[info.instance] = Some(InstanceRect {
            page: info.page,
            min: Vec2::from(info.uv_min),
            max: Vec2::from(info.uv_max),
        });
    }
    let total = manifest
        .maps
        .first()
        .ok_or_else(|| err("lists no maps".into()))?;
    if total.pages.len() != a.pages as usize {
        return Err(err(format!(
            "map '{}' lists {} pages, the atlas has {}",
            total.name,
            total.pages.len(),
            a.pages
        )));
    }
    let mut pages = Vec::new();
    let mut coverage = Vec::new();
    for name in &total.pages {
        let path = dir.join(name);
        let layers = read_exr_layers(&path)?;
        if (layers.rgb.width, layers.rgb.height) != (a.width, a.height) {
            return Err(BakeError::file(
                &path,
                format!(
                    "is {}x{}, the manifest's atlas pages are {}x{}",
                    layers.rgb.width, layers.rgb.height, a.width, a.height
                ),
            ));
        }
        let cov = layers
            .aovs
            .into_iter()
            .find(|(n, _)| n == "coverage")
            .map(|(_, i)| i)
            .ok_or_else(|| BakeError::file(&path, "has no coverage layer"))?;
        pages.push(layers.rgb);
        coverage.push(cov);
    }
    let atlas = a.atlas(meshes, instances);
    Ok(LoadedBake {
        dir: dir.to_path_buf(),
        kind,
        manifest,
        atlas,
        pages,
        coverage,
    })
}
