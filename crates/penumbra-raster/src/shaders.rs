//! The WGSL sources: the shading library (BRDF and light twins of the Rust
//! models) and the forward pass built on it.

/// Structs, BRDFs and lights shared by every pass and by the tests.
pub const SHADING_WGSL: &str = include_str!("shaders/shading.wgsl");

/// The forward pass (vertex and fragment entry points), without the library.
pub const FORWARD_WGSL: &str = include_str!("shaders/forward.wgsl");

/// The complete forward shader module: library + pass.
pub fn forward_source() -> String {
    format!("{SHADING_WGSL}\n{FORWARD_WGSL}")
}

/// A shader module made of the library followed by `entry_points`
/// (compute kernels of the tests, further passes).
pub fn with_library(entry_points: &str) -> String {
    format!("{SHADING_WGSL}\n{entry_points}")
}
