//! Image decoding into linear-RGB [`Texture`]s (shared with the OBJ loader).

use crate::texture::{Texels, Texture};
use image::{ColorType, DynamicImage};
use penumbra_shading::Rgb;
use penumbra_shading::color::srgb_to_linear;

/// Whether `img` has 8 bits per channel (kept as bytes in [`Texels`]).
pub(crate) fn is_eight_bit(img: &DynamicImage) -> bool {
    matches!(
        img.color(),
        ColorType::L8 | ColorType::La8 | ColorType::Rgb8 | ColorType::Rgba8
    )
}

/// Decodes a PNG/JPEG (or any format the `image` crate is built with) into a
/// linear-RGB texture. 8- and 16-bit images are taken as sRGB-encoded and
/// decoded with the sRGB transfer function (8-bit ones keep their bytes,
/// [`Texels::Srgb8`]); float images (HDR, EXR) are taken as linear. Alpha is
/// dropped. `Err` is a message.
pub(crate) fn decode_texture(bytes: &[u8], name: String) -> Result<Texture, String> {
    let img = image::load_from_memory(bytes).map_err(|e| e.to_string())?;
    texture_from_image(&img, name)
}

fn texture_from_image(img: &DynamicImage, name: String) -> Result<Texture, String> {
    let (width, height) = (img.width(), img.height());
    if width == 0 || height == 0 {
        return Err("the image has no pixels".into());
    }
    let texels = match img.color() {
        ColorType::Rgb32F | ColorType::Rgba32F => Texels::Linear(
            img.to_rgb32f()
                .pixels()
                .map(|p| Rgb::new(p[0], p[1], p[2]))
                .collect(),
        ),
        _ if is_eight_bit(img) => Texels::Srgb8(
            img.to_rgb8()
                .pixels()
                .map(|p| [p[0], p[1], p[2], 0])
                .collect(),
        ),
        _ => Texels::Linear(
            img.to_rgb32f()
                .pixels()
                .map(|p| {
                    Rgb::new(
                        srgb_to_linear(p[0]),
                        srgb_to_linear(p[1]),
                        srgb_to_linear(p[2]),
                    )
                })
                .collect(),
        ),
    };
    Ok(Texture {
        name,
        width,
        height,
        texels,
        wrap: Default::default(),
        uv_transform: glam::Affine2::IDENTITY,
        uv_set: 0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_is_decoded_from_srgb() {
        let mut img = image::RgbImage::new(2, 1);
        img.put_pixel(0, 0, image::Rgb([255, 128, 0]));
        img.put_pixel(1, 0, image::Rgb([0, 0, 255]));
        let mut png = Vec::new();
        image::DynamicImage::ImageRgb8(img)
            .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .unwrap();
        let t = decode_texture(&png, "t".into()).unwrap();
        assert_eq!((t.width, t.height), (2, 1));
        // Kept as bytes.
        assert_eq!(
            t.texels,
            Texels::Srgb8(vec![[255, 128, 0, 0], [0, 0, 255, 0]])
        );
        assert!((t.texels.get(0).x - 1.0).abs() < 1e-6);
        assert!((t.texels.get(0).y - srgb_to_linear(128.0 / 255.0)).abs() < 1e-6);
        assert!((t.texels.get(0).y - 0.2158605).abs() < 1e-4);
        assert_eq!(t.texels.get(1).z, 1.0);
        assert!(decode_texture(b"not an image", "x".into()).is_err());
    }
}
