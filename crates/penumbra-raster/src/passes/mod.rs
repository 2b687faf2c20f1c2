//! Raster techniques, one folder each: the pass's Rust beside its WGSL.

pub mod ao;
pub mod environment;
pub mod lightmap;
