//! PNG encoding, and decoding of PNG, JPEG and Radiance HDR (via the `image` crate).
//!
//! PNG output is 8-bit RGB, tone-mapped with [`crate::tonemap_to_srgb8`]
//! (`L · 2^EV` → operator → sRGB OETF → 8 bit). Decoded PNG/JPEG samples are
//! sRGB-encoded and converted to linear with the sRGB EOTF
//! (`((V + 0.055) / 1.055)^2.4`, or `V / 12.92` for `V ≤ 0.04045`); 16-bit PNGs
//! keep their precision. Radiance `.hdr` data is linear already. Alpha is dropped.

use std::path::Path;

use ::image::{ExtendedColorType, ImageEncoder};

use crate::io::{ImageFormat, guard};
use crate::{Image, ImageError, Rgb, ToneMapping, srgb_eotf, tonemap_to_srgb8};

/// Encodes `img` as an 8-bit sRGB PNG in memory.
pub(crate) fn encode(path: &Path, img: &Image, tm: &ToneMapping) -> Result<Vec<u8>, ImageError> {
    let err = |message: String| ImageError::Encode {
        path: path.to_path_buf(),
        format: "PNG",
        message,
    };
    crate::io::check_encodable(img, &err)?;
    let bytes = tonemap_to_srgb8(img, tm);
    let mut out = Vec::new();
    guard(
        || {
            ::image::codecs::png::PngEncoder::new(&mut out)
                .write_image(&bytes, img.width, img.height, ExtendedColorType::Rgb8)
                .map_err(|e| e.to_string())
        },
        err,
    )?;
    Ok(out)
}

/// Decodes a PNG, JPEG or Radiance HDR file held in memory to linear RGB.
pub(crate) fn decode(path: &Path, bytes: &[u8], format: ImageFormat) -> Result<Image, ImageError> {
    let (image_format, name, srgb) = match format {
        ImageFormat::Png => (::image::ImageFormat::Png, "PNG", true),
        ImageFormat::Jpeg => (::image::ImageFormat::Jpeg, "JPEG", true),
        ImageFormat::Hdr => (::image::ImageFormat::Hdr, "HDR", false),
        ImageFormat::Exr => (::image::ImageFormat::OpenExr, "EXR", false),
    };
    let err = |message: String| ImageError::Decode {
        path: path.to_path_buf(),
        format: name,
        message,
    };
    let decoded = guard(
        || ::image::load_from_memory_with_format(bytes, image_format).map_err(|e| e.to_string()),
        err,
    )?;
    let rgb = decoded.to_rgb32f();
    let (width, height) = rgb.dimensions();
    let pixels = rgb
        .pixels()
        .map(|p| {
            let v = Rgb::from_array(p.0);
            if srgb {
                Rgb::new(srgb_eotf(v.x), srgb_eotf(v.y), srgb_eotf(v.z))
            } else {
                v
            }
        })
        .collect();
    Image::from_pixels(width, height, pixels).map_err(|e| err(e.to_string()))
}
