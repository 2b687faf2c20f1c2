//! Images, film accumulation, tone mapping, file I/O and error metrics for penumbra.
//!
//! * [`Image`]: a row-major linear Rec.709 float RGB image (row 0 = top).
//! * [`Film`] / [`FilmTile`]: per-pixel sample count, exact sum and sum of
//!   squares with a 1-pixel box filter; tiles let threads accumulate disjoint
//!   rectangles.
//! * [`PartialFilm`]: part of a render (a sample range over a window) as an
//!   EXR file, and [`merge_parts`] to add parts into the image.
//! * [`ToneMapping`]: exposure, [`ToneOperator`] and the sRGB OETF for 8-bit output.
//! * [`write_image`] / [`read_image`]: atomic EXR/PNG writing, EXR/HDR/PNG/JPEG reading.
//! * [`compare`]: RMSE, relMSE, PSNR and HDR-FLIP against a reference.

pub mod buffer;
pub mod error;
pub mod exr_io;
pub mod film;
pub mod flip;
mod flip_ldr;
pub mod io;
pub mod memory;
pub mod metrics;
pub mod partial_film;
pub mod png_io;
pub mod tonemap;

/// Linear Rec.709 RGB radiance (or any linear RGB quantity, e.g. an albedo AOV).
pub use penumbra_shading::Rgb;

pub use crate::buffer::Image;
pub use crate::error::ImageError;
pub use crate::exr_io::{ExrLayers, read_exr_layers};
pub use crate::film::{Film, FilmTile};
pub use crate::flip::{
    DEFAULT_PIXELS_PER_DEGREE, ExposureRange, FlipBackend, FlipOptions, flip_exposure_range,
    flip_heatmap, hdr_flip, hdr_flip_with,
};
pub use crate::io::{ImageFormat, check_output_path, read_image, write_atomic, write_image};
pub use crate::memory::available_memory;
pub use crate::metrics::{
    Metrics, compare, nearest_rank, noise_rel_mse, percentile, psnr, rel_mse, rmse,
};
pub use crate::partial_film::{
    PartialFilm, key_differences, merge_parts, parse_range, read_partial_film, render_key,
    write_partial_film,
};
pub use crate::tonemap::{
    Exposure, ToneMapping, ToneOperator, aces_filmic, auto_exposure_ev, srgb_eotf, srgb_oetf,
    tonemap_to_srgb8,
};
