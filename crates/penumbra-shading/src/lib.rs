//! penumbra-shading: radiometry, colour, sampling warps, BSDFs and lights.
//!
//! Conventions (see `docs/conventions.md`): linear Rec.709 RGB radiance in
//! W/(sr·m²) per band, right-handed world frame, directions are unit vectors
//! pointing *away* from the shaded point, BSDF values in 1/sr without the cosine.

pub mod bsdf;
pub mod color;
pub mod frame;
pub mod light;
pub mod radiometry;
pub mod sampling;
pub mod stats;

pub use color::Rgb;
pub use frame::Frame;
