//! Sampling: hashing, Owen-scrambled Sobol points, and warps from [0,1)² to
//! directions and shapes. Every warp states its measure and returns/has a pdf.

pub mod distribution;
mod sobol;
mod sobol_block;
mod warp;

pub use distribution::{Distribution1D, Distribution2D};
pub use sobol::{Sampler, hash_combine, hash_u32};
pub use warp::*;
