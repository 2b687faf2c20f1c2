//! Image decoding into linear-RGB [`Texture`]s (shared with the OBJ loader).

use crate::texture::Texture;
use image::{ColorType, DynamicImage};
use penumbra_shading::Rgb;
use penumbra_shading::color::srgb_to_linear;

/// Decodes a PNG/JPEG (or any format the `image` crate is built with) into a
/// linear-RGB texture. 8- and 16-bit images are taken as sRGB-encoded and
/// decoded with the sRGB transfer function; float images (HDR, EXR) are
/// taken as linear. Alpha is dropped. `Err` is a message.
pub(crate) fn decode_texture(bytes: &[u8], name: String) -> Result<Texture, String> {
    let img = image::load_from_memory(bytes).map_err(|e| e.to_string())?;
    texture_from_image(&img, name)
}

fn texture_from_image(img: &DynamicImage, name: String) -> Result<Texture, String> {
    let (width, height) = (img.width(), img.height());
    if width == 0 || height == 0 {
        return Err("the image has no pixels".into());
    }
    let texels: Vec<Rgb> = match img.color() {
        ColorType::Rgb32F | ColorType::Rgba32F => img
            .to_rgb32f()
            .pixels()
            .map(|p| Rgb::new(p[0], p[1], p[2]))
            .collect(),
        ColorType::L8 | ColorType::La8 | ColorType::Rgb8 | ColorType::Rgba8 => {
            let lut: [f32; 256] = std::array::from_fn(|i| srgb_to_linear(i as f32 / 255.0));
            img.to_rgb8()
                .pixels()
                .map(|p| Rgb::new(lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize]))
                .collect()
        }
        _ => img
            .to_rgb32f()
            .pixels()
            .map(|p| {
                Rgb::new(
                    srgb_to_linear(p[0]),
                    srgb_to_linear(p[1]),
                    srgb_to_linear(p[2]),
                )
            })
            .collect(),
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
        assert!((t.texels[0].x - 1.0).abs() < 1e-6);
        assert!((t.texels[0].y - srgb_to_linear(128.0 / 255.0)).abs() < 1e-6);
        assert!((t.texels[0].y - 0.2158605).abs() < 1e-4);
        assert_eq!(t.texels[1].z, 1.0);
        assert!(decode_texture(b"not an image", "x".into()).is_err());
    }
}
