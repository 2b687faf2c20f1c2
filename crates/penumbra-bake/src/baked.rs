//! A finished bake in memory: what was baked, the atlas, and the maps.

use crate::atlas::Atlas;
use crate::texels::Texels;
use penumbra_image::Image;

/// The quantity a bake holds and the settings that define it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BakeKind {
    /// Ambient occlusion kA (1 = open), with the `ao` integrator's
    /// definition; rays longer than `distance` are unoccluded.
    Ao { distance: f32 },
    /// Irradiance E [W/m²] by path tracing, light scattered by at most
    /// `bounces` surfaces on its way; without the light arriving directly
    /// from the lights when `indirect_only`.
    Lightmap { bounces: u32, indirect_only: bool },
    /// Irradiance E [W/m²] by classic radiosity (progressive refinement).
    Radiosity { patches: u32, tolerance: f32 },
}

impl BakeKind {
    /// The name used on the command line and in manifests.
    pub fn name(&self) -> &'static str {
        match self {
            BakeKind::Ao { .. } => "ao",
            BakeKind::Lightmap { .. } => "lightmap",
            BakeKind::Radiosity { .. } => "radiosity",
        }
    }

    /// An irradiance map (light map or radiosity), as opposed to AO.
    pub fn is_irradiance(&self) -> bool {
        !matches!(self, BakeKind::Ao { .. })
    }

    /// The map leaves out the light arriving directly from the lights.
    pub fn indirect_only(&self) -> bool {
        matches!(
            self,
            BakeKind::Lightmap {
                indirect_only: true,
                ..
            }
        )
    }

    /// What the values are, in words.
    pub fn quantity(&self) -> &'static str {
        match self {
            BakeKind::Ao { .. } => {
                "ambient occlusion kA = (1/π) ∫ v(p,l) (n·l) dl (1 = unoccluded), the same in R, G and B"
            }
            BakeKind::Lightmap {
                indirect_only: true,
                ..
            } => {
                "indirect irradiance E(p) = ∫ Li cos θ dω without the light arriving directly from the lights"
            }
            _ => "irradiance E(p) = ∫ Li cos θ dω on the side of the geometric normal",
        }
    }

    pub fn units(&self) -> &'static str {
        match self {
            BakeKind::Ao { .. } => "1",
            _ => "W/m^2",
        }
    }
}

/// One baked map: every page of the atlas.
#[derive(Clone, Debug)]
pub struct BakedMap {
    /// `total`, or `light-K` for the map of one light.
    pub name: String,
    /// The light a per-light map holds, described (`None` for the total).
    pub light: Option<String>,
    /// Per page: the value (kA, or E in W/m²), dilated into unbaked texels.
    pub pages: Vec<Image>,
    /// Per page: the variance of each texel's estimate (0 where exact).
    pub variance: Vec<Image>,
}

/// Figures of a bake.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BakeStats {
    /// BVH, atlas, coverage and validity [s].
    pub prepare_seconds: f64,
    /// The estimation itself [s].
    pub bake_seconds: f64,
    /// Rays traced by the estimation (validity rays not included).
    pub rays: u64,
    /// Texels covered by triangles, of which baked and found inside geometry.
    pub covered: u64,
    pub valid: u64,
    pub invalid: u64,
}

/// A finished bake.
#[derive(Clone, Debug)]
pub struct Bake {
    pub kind: BakeKind,
    /// Samples per texel (light maps, AO) or rays per patch (radiosity).
    pub samples: u32,
    pub seed: u32,
    pub atlas: Atlas,
    /// The texels and their surface points (for tests and tools).
    pub texels: Texels,
    /// `total` first, then one map per light with `--per-light`.
    pub maps: Vec<BakedMap>,
    /// Per page: 1 baked, 0.5 inside geometry (dilated), 0 not covered.
    pub coverage: Vec<Image>,
    pub stats: BakeStats,
    /// Approximations made for this scene.
    pub warnings: Vec<String>,
    /// Radiosity only: the convergence record.
    pub convergence: Vec<crate::ConvergenceStep>,
}
