//! The WGSL sources: the shading library (BRDF and light twins of the Rust
//! models) and the forward pass built on it.
//!
//! The library's metallic–roughness twin reads the Kulla–Conty tables
//! through a table source ([`crate::material_tables`]): every module built
//! here appends one after the library.

use crate::material_tables::{kulla_conty_binding_wgsl, kulla_conty_fallback_wgsl};

/// Structs, BRDFs and lights shared by every pass and by the tests
/// (shading.wgsl followed by the GGX models of microfacet.wgsl). Needs a
/// table source after it (see the module doc).
pub const SHADING_WGSL: &str = concat!(
    include_str!("shaders/shading.wgsl"),
    "\n",
    include_str!("shaders/microfacet.wgsl")
);

/// The forward pass (vertex and fragment entry points), without the library.
pub const FORWARD_WGSL: &str = include_str!("shaders/forward.wgsl");

/// Whether the forward pipeline binds the Kulla–Conty table at
/// `@group(0) @binding(8)` ([`crate::material_tables::KULLA_CONTY_BINDING`]).
/// While false, [`forward_source`] uses the binding-free fallback
/// ([`crate::material_tables::kulla_conty_fallback_wgsl`]: the smooth row for
/// every roughness) and `SceneData` warns about the metallic–roughness
/// materials that it approximates; set it to true together with the binding
/// in the renderer.
pub const FORWARD_BINDS_MATERIAL_TABLES: bool = false;

/// The complete forward shader module: library + table source + pass.
pub fn forward_source() -> String {
    let tables = if FORWARD_BINDS_MATERIAL_TABLES {
        kulla_conty_binding_wgsl()
    } else {
        kulla_conty_fallback_wgsl()
    };
    format!("{SHADING_WGSL}\n{tables}\n{FORWARD_WGSL}")
}

/// A shader module made of the library, the Kulla–Conty table as a storage
/// buffer at `@group(0) @binding(8)`, and `entry_points` (compute kernels of
/// the tests, further passes). Only entry points that evaluate a
/// metallic–roughness material use the binding.
pub fn with_library(entry_points: &str) -> String {
    format!(
        "{SHADING_WGSL}\n{}\n{entry_points}",
        kulla_conty_binding_wgsl()
    )
}

/// [`with_library`] with the binding-free fallback table source, as
/// [`forward_source`] has it while the forward pipeline does not bind the
/// table.
pub fn with_library_fallback_tables(entry_points: &str) -> String {
    format!(
        "{SHADING_WGSL}\n{}\n{entry_points}",
        kulla_conty_fallback_wgsl()
    )
}
