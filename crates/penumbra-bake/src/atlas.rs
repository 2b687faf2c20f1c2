//! The light-map atlas: unique, non-overlapping texture coordinates for
//! every instance of the scene, packed into pages of texels.
//!
//! Each mesh gets one layout in its own unit square, and each of its
//! instances a rectangle of an atlas page that holds that layout at the
//! instance's world scale (the scheme of Bevy's `Lightmap::uv_rect`), so
//! every instance has its own texels. Charts are made by `uvunwrap`
//! (segmentation by normal cones, LSCM flattening, shape packing with
//! padding): from scratch, or from the islands of the mesh's own light-map
//! UVs (glTF `TEXCOORD_1`) when it has them, rescaled to a uniform density.
//!
//! Texture coordinates follow wgpu: (0, 0) is the top-left corner of texel
//! (0, 0), u grows with the column and v with the row, so texel (x, y)
//! covers `[x/W, (x+1)/W] × [y/H, (y+1)/H]` and its centre is
//! `((x + ½)/W, (y + ½)/H)`.

use crate::error::BakeError;
use glam::Vec2;
use penumbra_scene::Scene;

/// Largest page edge in texels (the texture limit wgpu guarantees).
pub const MAX_PAGE_EDGE: u32 = 8192;

/// Largest number of texels over all pages (2²⁸, sixteen 4096² pages).
pub const MAX_TEXELS: u64 = 1 << 28;

/// How densely the atlas samples the scene's surfaces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Density {
    /// The highest density at which every chart fits one page of at most
    /// this edge (`--max-size`).
    MaxSize(u32),
    /// A fixed number of texels per scene unit of length, on one page that
    /// grows to fit (`--texels-per-unit`).
    TexelsPerUnit(f32),
    /// A fixed density on as many pages of the given edge as needed
    /// (`--texels-per-unit D --max-size N`).
    TexelsPerUnitPaged { texels_per_unit: f32, page: u32 },
}

/// Atlas parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AtlasSettings {
    pub density: Density,
    /// Empty texels around each chart (charts are at least twice this
    /// apart): room for dilation, so bilinear lookups at a chart's border
    /// read baked values only.
    pub padding: u32,
}

impl Default for AtlasSettings {
    fn default() -> Self {
        Self {
            density: Density::MaxSize(512),
            padding: 2,
        }
    }
}

impl AtlasSettings {
    pub fn validate(&self) -> Result<(), BakeError> {
        let check_edge = |n: u32, what: &str| {
            if !(8..=MAX_PAGE_EDGE).contains(&n) {
                return Err(BakeError::Settings(format!(
                    "{what} {n} is out of range (8 to {MAX_PAGE_EDGE} texels)"
                )));
            }
            Ok(())
        };
        let check_density = |d: f32| {
            if !(d > 0.0 && d.is_finite()) {
                return Err(BakeError::Settings(format!(
                    "texels per unit {d} must be a positive number"
                )));
            }
            Ok(())
        };
        match self.density {
            Density::MaxSize(n) => check_edge(n, "atlas size")?,
            Density::TexelsPerUnit(d) => check_density(d)?,
            Density::TexelsPerUnitPaged {
                texels_per_unit,
                page,
            } => {
                check_density(texels_per_unit)?;
                check_edge(page, "atlas size")?;
            }
        }
        if self.padding == 0 || self.padding > 64 {
            return Err(BakeError::Settings(format!(
                "padding {} is out of range (1 to 64 texels)",
                self.padding
            )));
        }
        Ok(())
    }
}

/// Where a mesh's layout came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UvSource {
    /// Charts generated from the geometry.
    Generated,
    /// The islands of the mesh's own light-map UVs (`TEXCOORD_1`), repacked.
    Texcoord1,
}

/// One mesh's light-map layout, in the mesh's unit square.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshLayout {
    /// Per triangle (mesh order), the layout coordinate of each corner.
    pub corner_uvs: Vec<[Vec2; 3]>,
    /// Per triangle, its chart (numbered over the whole atlas).
    pub charts: Vec<u32>,
    pub source: UvSource,
}

/// Where an instance's layout lies: a rectangle of one page; the page
/// coordinate of layout coordinate `uv` is `min + uv (max − min)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InstanceRect {
    pub page: u32,
    pub min: Vec2,
    pub max: Vec2,
}

impl InstanceRect {
    /// Page coordinate of layout coordinate `uv`.
    pub fn map(&self, uv: Vec2) -> Vec2 {
        self.min + uv * (self.max - self.min)
    }
}

/// The atlas of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Atlas {
    /// Page size in texels.
    pub width: u32,
    pub height: u32,
    pub pages: u32,
    /// Texels per scene unit of length (charts scaled down to fit a page
    /// have fewer).
    pub texels_per_unit: f32,
    pub padding: u32,
    pub charts: u32,
    /// Fraction of the pages' texels covered by charts.
    pub utilization: f32,
    /// One per scene mesh; `None` for meshes no instance uses, or without
    /// triangles.
    pub meshes: Vec<Option<MeshLayout>>,
    /// One per scene instance; `None` when its mesh has no layout.
    pub instances: Vec<Option<InstanceRect>>,
}

/// Progress of the atlas build: a stage name and counts.
pub type AtlasProgress<'a> = &'a (dyn Fn(&str, usize, Option<usize>) + Sync);

impl Atlas {
    /// Charts and packs every instance of `scene`.
    pub fn build(
        scene: &Scene,
        settings: &AtlasSettings,
        progress: Option<AtlasProgress<'_>>,
    ) -> Result<Self, BakeError> {
        settings.validate()?;
        // Per mesh: the world scale of each instance (√(world area / mesh
        // area), exact for similarity transforms).
        let mut scales: Vec<Vec<f32>> = vec![Vec::new(); scene.meshes.len()];
        let mut slot_of_instance = vec![None; scene.instances.len()];
        let mesh_areas: Vec<f32> = scene.meshes.iter().map(mesh_area).collect();
        let mut world_area = 0.0f64;
        for (i, inst) in scene.instances.iter().enumerate() {
            let area = mesh_areas[inst.mesh];
            if area.is_nan() || area <= 0.0 {
                continue;
            }
            let world = scene.instance_area(inst);
            let scale = (world / area).sqrt();
            if !(scale > 0.0 && scale.is_finite()) {
                continue;
            }
            world_area += world as f64;
            slot_of_instance[i] = Some((inst.mesh, scales[inst.mesh].len()));
            scales[inst.mesh].push(scale);
        }
        check_size(settings, world_area)?;
        let positions: Vec<Vec<[f32; 3]>> = scene
            .meshes
            .iter()
            .map(|m| m.positions.iter().map(|p| p.to_array()).collect())
            .collect();
        let indices: Vec<Vec<u32>> = scene
            .meshes
            .iter()
            .map(|m| m.indices.iter().flatten().copied().collect())
            .collect();
        let uv1: Vec<Option<Vec<[f32; 2]>>> = scene
            .meshes
            .iter()
            .map(|m| {
                m.uv1
                    .as_ref()
                    .map(|u| u.iter().map(|v| v.to_array()).collect())
            })
            .collect();
        // Meshes given to the unwrapper, and their scene index.
        let mut inputs = Vec::new();
        let mut mesh_of_input = Vec::new();
        for (m, s) in scales.iter().enumerate() {
            if s.is_empty() {
                continue;
            }
            inputs.push(uvunwrap::MeshInput {
                instance_scales: s,
                existing_uvs: uv1[m].as_deref(),
                ..uvunwrap::MeshInput::new(&positions[m], &indices[m])
            });
            mesh_of_input.push(m);
        }
        let mut meshes: Vec<Option<MeshLayout>> = vec![None; scene.meshes.len()];
        let mut instances = vec![None; scene.instances.len()];
        if inputs.is_empty() {
            return Ok(Self {
                width: 0,
                height: 0,
                pages: 0,
                texels_per_unit: 0.0,
                padding: settings.padding,
                charts: 0,
                utilization: 0.0,
                meshes,
                instances,
            });
        }
        let density = match settings.density {
            Density::MaxSize(n) => uvunwrap::Density::Auto { page_size: n },
            Density::TexelsPerUnit(d) => uvunwrap::Density::Fixed {
                texels_per_unit: d,
                page_size: None,
            },
            Density::TexelsPerUnitPaged {
                texels_per_unit,
                page,
            } => uvunwrap::Density::Fixed {
                texels_per_unit,
                page_size: Some(page),
            },
        };
        let options = uvunwrap::Options {
            density,
            padding: settings.padding,
            ..Default::default()
        };
        let report = |p: uvunwrap::Progress| {
            if let Some(cb) = progress {
                let stage = match p.stage {
                    uvunwrap::Stage::Segmenting => "segmenting charts",
                    uvunwrap::Stage::Parameterizing => "flattening charts",
                    uvunwrap::Stage::Packing => "packing charts",
                    _ => "building the atlas",
                };
                cb(stage, p.done, p.total);
            }
            true
        };
        let out = uvunwrap::generate_with_progress(&inputs, &options, report)
            .map_err(|e| BakeError::Atlas(e.to_string()))?;
        let total = out.width as u64 * out.height as u64 * out.page_count as u64;
        if total > MAX_TEXELS {
            return Err(BakeError::Atlas(format!(
                "the atlas has {} pages of {}x{} texels, more than the {MAX_TEXELS} texels a bake may have; lower --texels-per-unit",
                out.page_count, out.width, out.height
            )));
        }
        if out.width > MAX_PAGE_EDGE || out.height > MAX_PAGE_EDGE {
            return Err(BakeError::Atlas(format!(
                "the atlas page is {}x{} texels, more than {MAX_PAGE_EDGE} per edge; lower --texels-per-unit or give --max-size",
                out.width, out.height
            )));
        }
        for (k, om) in out.meshes.iter().enumerate() {
            let m = mesh_of_input[k];
            let tri_count = scene.meshes[m].indices.len();
            let mut corner_uvs = Vec::with_capacity(tri_count);
            let mut charts = Vec::with_capacity(tri_count);
            for t in 0..tri_count {
                let v = |c: usize| om.vertices[om.indices[3 * t + c] as usize];
                let (a, b, c) = (v(0), v(1), v(2));
                corner_uvs.push([a.uv, b.uv, c.uv].map(Vec2::from));
                charts.push(a.chart.or(b.chart).or(c.chart).unwrap_or(u32::MAX));
            }
            meshes[m] = Some(MeshLayout {
                corner_uvs,
                charts,
                source: if uv1[m].is_some() {
                    UvSource::Texcoord1
                } else {
                    UvSource::Generated
                },
            });
        }
        for (i, slot) in slot_of_instance.iter().enumerate() {
            let Some((m, k)) = *slot else { continue };
            let Some(input) = mesh_of_input.iter().position(|&x| x == m) else {
                continue;
            };
            let r = out.meshes[input].instances[k];
            instances[i] = Some(InstanceRect {
                page: r.page,
                min: Vec2::from(r.min),
                max: Vec2::from(r.max),
            });
        }
        Ok(Self {
            width: out.width,
            height: out.height,
            pages: out.page_count,
            texels_per_unit: out.texels_per_unit,
            padding: settings.padding,
            charts: out.chart_count,
            utilization: out.utilization,
            meshes,
            instances,
        })
    }

    /// Page and page coordinates of the corners of triangle `triangle` (mesh
    /// order) of instance `instance`; `None` if the instance has no texels.
    pub fn triangle_uvs(
        &self,
        scene: &Scene,
        instance: usize,
        triangle: usize,
    ) -> Option<(u32, [Vec2; 3])> {
        let rect = self.instances.get(instance)?.as_ref()?;
        let layout = self.meshes[scene.instances[instance].mesh].as_ref()?;
        let uvs = layout.corner_uvs.get(triangle)?;
        Some((rect.page, uvs.map(|uv| rect.map(uv))))
    }

    /// Texels in all pages.
    pub fn texel_count(&self) -> u64 {
        self.width as u64 * self.height as u64 * self.pages as u64
    }
}

/// Surface area of a mesh in its own units.
fn mesh_area(mesh: &penumbra_scene::Mesh) -> f32 {
    mesh.indices
        .iter()
        .map(|t| {
            let p = |i: u32| mesh.positions[i as usize];
            0.5 * (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).length()
        })
        .sum()
}

/// Refuses fixed densities whose pages could not exist, before the packer
/// tries to allocate them: charts cover at most their pages, so the pages
/// hold at least `area · density²` texels.
fn check_size(settings: &AtlasSettings, world_area: f64) -> Result<(), BakeError> {
    let (d, limit, what) = match settings.density {
        Density::MaxSize(_) => return Ok(()),
        Density::TexelsPerUnit(d) => (
            d,
            (MAX_PAGE_EDGE as f64).powi(2),
            format!(
                "one {MAX_PAGE_EDGE}x{MAX_PAGE_EDGE} page; lower --texels-per-unit or add --max-size to use several pages"
            ),
        ),
        Density::TexelsPerUnitPaged {
            texels_per_unit, ..
        } => (
            texels_per_unit,
            MAX_TEXELS as f64,
            format!("the {MAX_TEXELS} texels a bake may have; lower --texels-per-unit"),
        ),
    };
    let texels = world_area * (d as f64).powi(2);
    if texels > limit {
        return Err(BakeError::Atlas(format!(
            "{d} texels per unit over {world_area:.4e} units² of surface needs at least {texels:.3e} texels, more than {what}"
        )));
    }
    Ok(())
}
