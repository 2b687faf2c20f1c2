//! Classic radiosity: E [W/m²] per texel by patches, form factors by ray
//! casting and progressive refinement, written in the format of the
//! light-map bake (`total` map of irradiance on the side of the geometric
//! normal, dilated; `B = ρ E`, `L = Le + ρ E / π`).
//!
//! * [`patches`]: one patch per valid texel of a coarse atlas (its page
//!   edge chosen so that the valid texels number about
//!   [`RadiositySettings::patches`]), with its footprint and world area;
//! * [`first_shot`]: iteration 0, the lights that are not patches
//!   (abstract lights, analytic area lights, the environment) shoot first;
//! * [`shoot`]: progressive refinement until the unshot power is below the
//!   tolerance.
//!
//! Every material is treated as Lambertian with reflectance ρ = its
//! albedo (one warning names the others). The solution is the radiosity of
//! all bounces, not of a bounce-limited path tracer.

pub mod first_shot;
mod max_tree;
pub mod patches;
pub mod shoot;

pub use patches::Patch;

use crate::atlas::{AtlasSettings, Density, MAX_PAGE_EDGE};
use crate::baked::{Bake, BakeKind, BakeStats, BakedMap};
use crate::baker::{BakeProgress, Prepared};
use crate::dilate::{TexelState, dilate};
use crate::error::BakeError;
use penumbra_image::{Image, Rgb};
use penumbra_scene::Scene;
use std::time::Instant;

/// Settings of a radiosity bake.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadiositySettings {
    /// About how many patches to solve for.
    pub patches: u32,
    /// Stop when the unshot power is below this fraction of the emitted power.
    pub tolerance: f32,
    /// Form-factor rays per patch of the scene, over the whole solve.
    pub rays_per_patch: u32,
    pub seed: u32,
}

/// Most patches a bake may ask for.
pub const MAX_PATCHES: u32 = 1 << 24;

/// Fraction of an atlas page's texels that the first guess assumes valid.
const FIRST_GUESS_FILL: f64 = 0.6;

/// Atlas builds at most, and the relative patch-count error that stops
/// the search earlier.
const SIZING_BUILDS: usize = 4;
const SIZING_TOLERANCE: f64 = 0.05;

/// Empty texels around each chart of the coarse atlas (as light maps).
const PADDING: u32 = 2;

/// A radiosity bake and the patches behind it.
#[derive(Clone, Debug)]
pub struct RadiositySolution {
    /// The bake (`total` map of E; variance pages are zeros: the error of
    /// radiosity is discretisation and form-factor noise, not a per-texel
    /// sampling variance).
    pub bake: Bake,
    /// Every patch with its area, reflectance, emission and solved E.
    pub patches: Vec<Patch>,
    /// World area of covered texels that are not patches (inside geometry).
    pub unpatched_area: f64,
    /// World area of triangles degenerate in the atlas.
    pub lost_area: f64,
    /// Power emitted into the scene [W, luminance-weighted]: patch
    /// emission plus what the lights outside the patches delivered.
    pub emitted_power: f64,
}

/// Bakes E by classic radiosity (see the module docs).
pub fn bake_radiosity(
    scene: &Scene,
    settings: &RadiositySettings,
    progress: Option<BakeProgress<'_>>,
) -> Result<Bake, BakeError> {
    solve_radiosity(scene, settings, progress).map(|s| s.bake)
}

/// Checks the settings.
pub fn validate(settings: &RadiositySettings) -> Result<(), BakeError> {
    if settings.patches == 0 || settings.patches > MAX_PATCHES {
        return Err(BakeError::Settings(format!(
            "--patches {} is out of range (1 to {MAX_PATCHES})",
            settings.patches
        )));
    }
    if !(settings.tolerance > 0.0 && settings.tolerance < 1.0) {
        return Err(BakeError::Settings(format!(
            "--tolerance {} must lie between 0 and 1 (a fraction of the emitted power)",
            settings.tolerance
        )));
    }
    if settings.rays_per_patch == 0 {
        return Err(BakeError::Settings(
            "--rays-per-patch must be at least 1".into(),
        ));
    }
    Ok(())
}

/// [`bake_radiosity`], also returning the patches.
pub fn solve_radiosity(
    scene: &Scene,
    settings: &RadiositySettings,
    progress: Option<BakeProgress<'_>>,
) -> Result<RadiositySolution, BakeError> {
    validate(settings)?;
    let t_prep = Instant::now();
    let (prep, patches) = coarse_atlas(scene, settings.patches, progress)?;
    let prepare_seconds = t_prep.elapsed().as_secs_f64();
    let n = patches.patches.len();
    let mut warnings = Vec::new();
    if n == 0 {
        return Err(BakeError::Settings(
            "the scene has no patches: every texel of its atlas lies inside geometry".into(),
        ));
    }
    let ratio = n as f64 / settings.patches as f64;
    if !(0.75..=1.25).contains(&ratio) {
        warnings.push(format!(
            "{n} patches instead of the {} asked for: the atlas packs the charts of this scene no closer",
            settings.patches
        ));
    }
    if !patches.non_lambert.is_empty() {
        warnings.push(format!(
            "radiosity treats every surface as Lambertian: material(s) {} are approximated by their albedo (no specular, mirror or transmitted light)",
            quoted(&patches.non_lambert)
        ));
    }
    if !patches.textured.is_empty() {
        warnings.push(format!(
            "material(s) {} have albedo textures: radiosity uses their constant base colour for the light they reflect (the map itself is irradiance, to be multiplied by the texture)",
            quoted(&patches.textured)
        ));
    }
    let rays0 = penumbra_trace::stats::rays_traced();
    let start = Instant::now();
    let first = if first_shot::has_non_patch_lights(&prep) {
        first_shot::direct_from_non_patch_lights(&prep, &patches, settings.seed, progress)
    } else {
        vec![Rgb::ZERO; n]
    };
    let solution = shoot::solve(
        &prep,
        &patches,
        &first,
        settings.tolerance as f64,
        settings.rays_per_patch,
        settings.seed,
        start,
        progress,
    );
    let bake_seconds = start.elapsed().as_secs_f64();
    let rays = penumbra_trace::stats::rays_traced() - rays0;
    if solution.emitted_power.is_nan() || solution.emitted_power <= 0.0 {
        warnings.push("the scene emits no light: the radiosity map is black".to_string());
    }
    if solution.capped {
        let last = solution.steps.last().map_or(0.0, |s| s.unshot_fraction);
        warnings.push(format!(
            "radiosity stopped after {} shots with {:.3e} of the emitted power unshot, above the tolerance {} (are some reflectances 1?)",
            solution.steps.len() - 1,
            last,
            settings.tolerance
        ));
    }
    // The maps: each patch's E at its texels (its own and the slivers that
    // joined it), dilated into the others.
    let (w, h) = (prep.atlas.width, prep.atlas.height);
    let page_len = w as usize * h as usize;
    let states: Vec<TexelState> = (0..page_len * prep.atlas.pages as usize)
        .map(|i| {
            if patches.owner[i] != patches::NONE {
                TexelState::Baked
            } else if prep.texels.index[i] != u32::MAX {
                TexelState::Invalid
            } else {
                TexelState::Empty
            }
        })
        .collect();
    let mut pages: Vec<Image> = (0..prep.atlas.pages).map(|_| Image::new(w, h)).collect();
    let mut solved = patches.patches.clone();
    for (patch, &e) in solved.iter_mut().zip(&solution.irradiance) {
        patch.irradiance = e;
    }
    for (i, &owner) in patches.owner.iter().enumerate() {
        if owner != patches::NONE {
            let (p, t) = (i / page_len, i % page_len);
            pages[p].pixels[t] = solution.irradiance[owner as usize];
        }
    }
    for (p, page) in pages.iter_mut().enumerate() {
        dilate(page, &states[p * page_len..][..page_len]);
    }
    let coverage = (0..prep.atlas.pages as usize)
        .map(|p| Image {
            width: w,
            height: h,
            pixels: states[p * page_len..][..page_len]
                .iter()
                .map(|s| Rgb::splat(s.coverage()))
                .collect(),
        })
        .collect();
    let covered = prep.texels.texels.len() as u64;
    let bake = Bake {
        kind: BakeKind::Radiosity {
            patches: n as u32,
            tolerance: settings.tolerance,
        },
        samples: settings.rays_per_patch,
        seed: settings.seed,
        coverage,
        maps: vec![BakedMap {
            name: "total".into(),
            light: None,
            variance: (0..prep.atlas.pages).map(|_| Image::new(w, h)).collect(),
            pages,
        }],
        stats: BakeStats {
            prepare_seconds,
            bake_seconds,
            rays,
            covered,
            valid: n as u64,
            invalid: covered - n as u64,
        },
        warnings,
        convergence: solution.steps,
        atlas: prep.atlas,
        texels: prep.texels,
    };
    Ok(RadiositySolution {
        bake,
        patches: solved,
        unpatched_area: patches.unpatched_area,
        lost_area: patches.lost_area,
        emitted_power: solution.emitted_power,
    })
}

/// The prepared scene whose atlas has about `target` patches, and its
/// patches. The page edge n starts at `√(target / 0.6)`; √(patches) grows
/// about linearly with n (less the padding around the charts), so the next
/// edge comes from scaling by `√(target / patches)` after one build and
/// from the secant through the last two builds after that, until the count
/// is within 5 % (at most four builds; the closest is kept).
fn coarse_atlas<'a>(
    scene: &'a Scene,
    target: u32,
    progress: Option<BakeProgress<'_>>,
) -> Result<(Prepared<'a>, patches::Patches), BakeError> {
    let clamp = |n: f64| (n.round() as i64).clamp(8, MAX_PAGE_EDGE as i64) as u32;
    let goal = (target as f64).sqrt();
    let mut edge = clamp((target as f64 / FIRST_GUESS_FILL).sqrt());
    let mut best: Option<(f64, Prepared<'a>, patches::Patches)> = None;
    // (edge, √patches) of each build.
    let mut tried: Vec<(u32, f64)> = Vec::new();
    for _ in 0..SIZING_BUILDS {
        let settings = AtlasSettings {
            density: Density::MaxSize(edge),
            padding: PADDING,
        };
        let prep = Prepared::new(scene, &settings, progress)?;
        if let Some(p) = progress {
            p("radiosity: patches", 0, 0);
        }
        let patches = patches::Patches::new(&prep);
        let count = patches.patches.len().max(1) as f64;
        let error = (count / target as f64).ln().abs();
        tried.push((edge, count.sqrt()));
        if best.as_ref().is_none_or(|(e, _, _)| error < *e) {
            best = Some((error, prep, patches));
        }
        if error.exp() - 1.0 <= SIZING_TOLERANCE {
            break;
        }
        let next = match tried[..] {
            [.., (n0, r0), (n1, r1)] if (r1 - r0) * (n1 as f64 - n0 as f64) > 0.0 => {
                let slope = (r1 - r0) / (n1 as f64 - n0 as f64);
                clamp(n1 as f64 + (goal - r1) / slope)
            }
            _ => clamp(edge as f64 * goal / count.sqrt()),
        };
        if tried.iter().any(|&(n, _)| n == next) {
            break;
        }
        edge = next;
    }
    let (_, prep, patches) = best.expect("at least one atlas was built");
    Ok((prep, patches))
}

fn quoted(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("'{n}'"))
        .collect::<Vec<_>>()
        .join(", ")
}
