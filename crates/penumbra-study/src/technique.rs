//! The techniques of the notes a study runs, as values: each one names the
//! engine, the settings a user would give on the command line, and the
//! quantity it approximates.

use penumbra_raster::ShadowMode;
use penumbra_raster::passes::ao::AoMethod;
use penumbra_scene::IntegratorKind;

/// Shadow-map edges a study tries.
pub const MAP_SIZES: [u32; 4] = [512, 1024, 2048, 4096];
/// PCF kernels a study tries with each map size.
pub const MAP_PCF: [u32; 2] = [1, 3];

/// One technique (a closed set: every row of a study is one of these).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Technique {
    /// The CPU ray tracer with one integrator at the scene's spp.
    Trace(IntegratorKind),
    /// The raster engine's direct light with one shadow technique.
    Shadows(RasterShadows),
    /// The raster engine with the environment reduced to one constant
    /// radiance (its mean): ambient = albedo × π L̄.
    Ambient,
    /// The raster engine's environment: SH9 irradiance E_env(n) and
    /// prefiltered reflections.
    Environment,
    /// Screen-space AO of the environment term.
    Ssao(AoMethod),
    /// kA baked per texel by ray tracing, multiplying the environment term.
    BakedAo,
    /// Irradiance baked by path tracing: all light, or the indirect part
    /// under real-time direct light with shadow maps.
    Lightmap { indirect_only: bool },
    /// Irradiance by classic radiosity.
    Radiosity,
}

/// A raster shadow technique and its settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RasterShadows {
    pub mode: ShadowMode,
    pub map_size: u32,
    pub pcf: u32,
}

/// Shadow maps for the real-time direct light under an indirect-only
/// light map: the common choice of 2048² with a 3×3 PCF.
pub const LIGHTMAP_SHADOWS: RasterShadows = RasterShadows {
    mode: ShadowMode::Map,
    map_size: 2048,
    pcf: 3,
};

impl Technique {
    /// Every technique, in report order.
    pub fn all() -> Vec<Technique> {
        let mut all: Vec<Technique> = [
            IntegratorKind::Local,
            IntegratorKind::Direct,
            IntegratorKind::Whitted,
            IntegratorKind::Path,
            IntegratorKind::Ao,
        ]
        .into_iter()
        .map(Technique::Trace)
        .collect();
        let shadows = |mode, map_size, pcf| {
            Technique::Shadows(RasterShadows {
                mode,
                map_size,
                pcf,
            })
        };
        all.push(shadows(ShadowMode::None, 0, 1));
        all.push(shadows(ShadowMode::Planar, 0, 1));
        for size in MAP_SIZES {
            for pcf in MAP_PCF {
                all.push(shadows(ShadowMode::Map, size, pcf));
            }
        }
        all.push(shadows(ShadowMode::Volume, 0, 1));
        all.extend([
            Technique::Ambient,
            Technique::Environment,
            Technique::Ssao(AoMethod::Hemisphere),
            Technique::Ssao(AoMethod::Gtao),
            Technique::BakedAo,
            Technique::Lightmap {
                indirect_only: false,
            },
            Technique::Lightmap {
                indirect_only: true,
            },
            Technique::Radiosity,
        ]);
        all
    }

    /// The name `--techniques` takes.
    pub fn id(&self) -> String {
        match self {
            Technique::Trace(i) => format!("trace-{}", i.name()),
            Technique::Shadows(s) => match s.mode {
                ShadowMode::None => "raster-no-shadows".into(),
                ShadowMode::Planar => "raster-planar".into(),
                ShadowMode::Volume => "raster-volume".into(),
                ShadowMode::Map => format!("raster-map-{}-pcf{}", s.map_size, s.pcf),
            },
            Technique::Ambient => "raster-ambient".into(),
            Technique::Environment => "raster-environment".into(),
            Technique::Ssao(m) => match m {
                AoMethod::Gtao => "ssao-gtao".into(),
                _ => "ssao-hemisphere".into(),
            },
            Technique::BakedAo => "bake-ao".into(),
            Technique::Lightmap {
                indirect_only: false,
            } => "lightmap".into(),
            Technique::Lightmap {
                indirect_only: true,
            } => "lightmap-indirect".into(),
            Technique::Radiosity => "radiosity".into(),
        }
    }

    /// A name for people.
    pub fn label(&self) -> String {
        match self {
            Technique::Trace(i) => match i {
                IntegratorKind::Local => "local illumination (ray traced, no shadows)".into(),
                IntegratorKind::Direct => "direct lighting (ray traced)".into(),
                IntegratorKind::Whitted => "Whitted ray tracing".into(),
                IntegratorKind::Path => "path tracing".into(),
                IntegratorKind::Ao => "ambient occlusion (ray traced)".into(),
            },
            Technique::Shadows(s) => match s.mode {
                ShadowMode::None => "raster, no shadows".into(),
                ShadowMode::Planar => "raster, planar projected shadows".into(),
                ShadowMode::Volume => "raster, stencil shadow volumes".into(),
                ShadowMode::Map => {
                    format!("raster, shadow map {0}×{0}, PCF {1}×{1}", s.map_size, s.pcf)
                }
            },
            Technique::Ambient => "raster, environment as a constant ambient".into(),
            Technique::Environment => "raster, E_env(n) + prefiltered reflections".into(),
            Technique::Ssao(AoMethod::Gtao) => "raster, GTAO".into(),
            Technique::Ssao(_) => "raster, hemisphere SSAO".into(),
            Technique::BakedAo => "raster, AO baked by ray tracing".into(),
            Technique::Lightmap {
                indirect_only: false,
            } => "raster, light map (all light)".into(),
            Technique::Lightmap {
                indirect_only: true,
            } => "raster, indirect light map + shadow maps".into(),
            Technique::Radiosity => "raster, radiosity".into(),
        }
    }

    /// The family the report groups rows by.
    pub fn group(&self) -> &'static str {
        match self {
            Technique::Trace(_) => "ray tracing",
            Technique::Shadows(_) => "shadows",
            Technique::Ambient | Technique::Environment => "environment",
            Technique::Ssao(_) | Technique::BakedAo => "ambient occlusion",
            Technique::Lightmap { .. } | Technique::Radiosity => "bakes",
        }
    }

    /// The quantity the technique approximates, as a truth id: shadows and
    /// local shading approximate direct light, AO techniques the ray-traced
    /// kA, everything else full global illumination.
    pub fn approximates(&self) -> TruthKind {
        match self {
            Technique::Trace(IntegratorKind::Local) | Technique::Shadows(_) => TruthKind::Direct,
            Technique::Trace(IntegratorKind::Ao) | Technique::Ssao(_) | Technique::BakedAo => {
                TruthKind::Ao
            }
            Technique::Trace(IntegratorKind::Direct) => TruthKind::Direct,
            _ => TruthKind::Path,
        }
    }

    pub fn engine(&self) -> &'static str {
        match self {
            Technique::Trace(_) => "trace",
            _ => "raster",
        }
    }
}

/// The truths a study renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TruthKind {
    /// Full global illumination: `path` (or the given reference).
    Path,
    /// Direct light with exact shadows: `direct`.
    Direct,
    /// Ray-traced ambient occlusion with the study's AO radius: `ao`.
    Ao,
}

impl TruthKind {
    pub fn id(self) -> &'static str {
        match self {
            TruthKind::Path => "path",
            TruthKind::Direct => "direct",
            TruthKind::Ao => "ao",
        }
    }
}

/// The techniques named in a comma-separated list (ids as [`Technique::id`],
/// or a group: `trace`, `shadows`, `maps`, `environment`, `ao`, `bakes`,
/// `all`), in report order, each once.
pub fn parse_list(list: &str) -> Result<Vec<Technique>, String> {
    let all = Technique::all();
    let mut chosen = vec![false; all.len()];
    for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let matches: Vec<usize> = all
            .iter()
            .enumerate()
            .filter(|(_, t)| in_set(name, t))
            .map(|(i, _)| i)
            .collect();
        if matches.is_empty() {
            let ids: Vec<String> = all.iter().map(Technique::id).collect();
            return Err(format!(
                "unknown technique '{name}' (expected a group: all, trace, shadows, maps, environment, ao, bakes; or one of: {})",
                ids.join(", ")
            ));
        }
        for i in matches {
            chosen[i] = true;
        }
    }
    if !chosen.contains(&true) {
        return Err("the technique list is empty".into());
    }
    Ok(all
        .into_iter()
        .zip(chosen)
        .filter_map(|(t, c)| c.then_some(t))
        .collect())
}

fn in_set(name: &str, t: &Technique) -> bool {
    match name {
        "all" => true,
        "trace" => matches!(t, Technique::Trace(_)),
        "shadows" => matches!(t, Technique::Shadows(_)),
        "maps" => matches!(t, Technique::Shadows(s) if s.mode == ShadowMode::Map),
        "environment" => t.group() == "environment",
        "ao" => t.group() == "ambient occlusion",
        "bakes" => t.group() == "bakes",
        id => t.id() == id,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_unique_and_parse_back() {
        let all = Technique::all();
        // 5 integrators, none/planar/volume, 4 sizes × 2 PCF, 8 more.
        assert_eq!(all.len(), 5 + 3 + 8 + 8);
        for t in &all {
            assert_eq!(parse_list(&t.id()).unwrap(), vec![*t], "{}", t.id());
        }
        let mut ids: Vec<String> = all.iter().map(Technique::id).collect();
        ids.sort();
        ids.dedup();
        assert_eq!(ids.len(), all.len());
    }

    #[test]
    fn groups_and_order() {
        let maps = parse_list("maps").unwrap();
        assert_eq!(maps.len(), 8);
        let two = parse_list("raster-volume, trace-local").unwrap();
        // Report order, not the order given.
        assert_eq!(two[0], Technique::Trace(IntegratorKind::Local));
        assert_eq!(parse_list("all").unwrap(), Technique::all());
        assert_eq!(parse_list("ao,ssao-gtao").unwrap().len(), 3);
    }

    #[test]
    fn unknown_names_are_refused() {
        let e = parse_list("trace-path,raster-mapp").unwrap_err();
        assert!(
            e.contains("'raster-mapp'") && e.contains("raster-map-512-pcf1"),
            "{e}"
        );
        assert!(parse_list(" , ").is_err());
    }
}
