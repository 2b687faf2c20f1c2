//! Render settings carried by a scene file and overridden by the CLI.

use std::fmt;
use std::str::FromStr;

/// The integrators, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum IntegratorKind {
    /// Local illumination: direct light from every light, no shadow rays.
    Local,
    /// Direct lighting with shadow rays and MIS.
    Direct,
    /// Path tracing (global illumination).
    #[default]
    Path,
    /// Ambient occlusion kA.
    Ao,
    /// Recursive (Whitted) ray tracing: direct light with shadow rays,
    /// ideal reflection and refraction followed recursively.
    Whitted,
}

impl IntegratorKind {
    pub const ALL: [IntegratorKind; 5] = [
        Self::Local,
        Self::Direct,
        Self::Path,
        Self::Ao,
        Self::Whitted,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Self::Local => "local",
            Self::Direct => "direct",
            Self::Path => "path",
            Self::Ao => "ao",
            Self::Whitted => "whitted",
        }
    }
}

impl fmt::Display for IntegratorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for IntegratorKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| {
                let names: Vec<_> = Self::ALL.iter().map(|k| k.name()).collect();
                format!(
                    "unknown integrator '{s}' (expected one of: {})",
                    names.join(", ")
                )
            })
    }
}

/// How to render. Defaults match the reference renders (box filter 1 px).
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    /// Maximum path segments from the camera, as Mitsuba's `max_depth`
    /// (1 = emitters seen directly, 2 = direct lighting).
    pub max_depth: u32,
    pub integrator: IntegratorKind,
    pub seed: u32,
    /// AO ray length (world units); infinite by default.
    pub ao_distance: f32,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 512,
            height: 512,
            spp: 64,
            max_depth: 8,
            integrator: IntegratorKind::Path,
            seed: 0,
            ao_distance: f32::INFINITY,
        }
    }
}
