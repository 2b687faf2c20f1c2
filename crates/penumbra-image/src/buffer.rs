//! [`Image`]: a row-major linear float RGB image.

use crate::{ImageError, Rgb};

/// Row-major float RGB image, row 0 = top, `pixels[y * width + x]`.
///
/// Values are linear Rec.709 RGB (radiance for renders). The fields are public;
/// functions that consume an image check `pixels.len() == width * height`
/// ([`Image::validate`]) and report an error instead of panicking.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` pixels, row-major, top row first.
    pub pixels: Vec<Rgb>,
}

impl Image {
    /// A black image.
    pub fn new(width: u32, height: u32) -> Self {
        Self::filled(width, height, Rgb::ZERO)
    }

    /// An image with every pixel set to `value`.
    pub fn filled(width: u32, height: u32, value: Rgb) -> Self {
        Self {
            width,
            height,
            pixels: vec![value; pixel_count(width, height)],
        }
    }

    /// An image whose pixel (x, y) is `f(x, y)`, evaluated in row-major order.
    pub fn from_fn(width: u32, height: u32, mut f: impl FnMut(u32, u32) -> Rgb) -> Self {
        let mut pixels = Vec::with_capacity(pixel_count(width, height));
        for y in 0..height {
            for x in 0..width {
                pixels.push(f(x, y));
            }
        }
        Self {
            width,
            height,
            pixels,
        }
    }

    /// Wraps `pixels` (row-major, top row first); errors if the count is not `width * height`.
    pub fn from_pixels(width: u32, height: u32, pixels: Vec<Rgb>) -> Result<Self, ImageError> {
        let image = Self {
            width,
            height,
            pixels,
        };
        image.validate("image")?;
        Ok(image)
    }

    /// Checks that `pixels.len() == width * height`; `what` names the image in the error.
    pub fn validate(&self, what: &str) -> Result<(), ImageError> {
        let expected = pixel_count(self.width, self.height);
        if self.pixels.len() == expected {
            Ok(())
        } else {
            Err(ImageError::InvalidImage {
                what: what.to_string(),
                message: format!(
                    "{}x{} image has {} pixels, expected {expected}",
                    self.width,
                    self.height,
                    self.pixels.len()
                ),
            })
        }
    }

    /// `true` when the image has no pixels.
    pub fn is_empty(&self) -> bool {
        self.pixels.is_empty()
    }

    /// Index of pixel (x, y) in `pixels`: `y * width + x`.
    pub fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.width as usize + x as usize
    }

    /// Pixel (x, y).
    ///
    /// # Panics
    /// If `x >= width` or `y >= height` (a caller bug, like slice indexing).
    pub fn get(&self, x: u32, y: u32) -> Rgb {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside {}x{} image",
            self.width,
            self.height
        );
        self.pixels[self.index(x, y)]
    }

    /// Sets pixel (x, y).
    ///
    /// # Panics
    /// If `x >= width` or `y >= height` (a caller bug, like slice indexing).
    pub fn set(&mut self, x: u32, y: u32, v: Rgb) {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside {}x{} image",
            self.width,
            self.height
        );
        let i = self.index(x, y);
        self.pixels[i] = v;
    }

    /// Mean pixel value, `Σ p / N`, accumulated in f64; zero for an empty image.
    pub fn mean(&self) -> Rgb {
        if self.pixels.is_empty() {
            return Rgb::ZERO;
        }
        let sum = self
            .pixels
            .iter()
            .fold(glam::DVec3::ZERO, |acc, p| acc + p.as_dvec3());
        (sum / self.pixels.len() as f64).as_vec3()
    }

    /// `true` when every channel of every pixel is finite.
    pub fn all_finite(&self) -> bool {
        self.pixels.iter().all(|p| p.is_finite())
    }

    /// Largest channel value over all pixels, ignoring non-finite values
    /// (`f32::NEG_INFINITY` when there is none).
    pub fn max_value(&self) -> f32 {
        self.pixels
            .iter()
            .flat_map(|p| p.to_array())
            .filter(|v| v.is_finite())
            .fold(f32::NEG_INFINITY, f32::max)
    }
}

/// `width * height` as usize (cannot overflow on 64-bit targets).
pub(crate) fn pixel_count(width: u32, height: u32) -> usize {
    width as usize * height as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn get_set_row_major() {
        let mut img = Image::new(3, 2);
        img.set(2, 1, Rgb::new(1.0, 2.0, 3.0));
        assert_eq!(img.pixels[5], Rgb::new(1.0, 2.0, 3.0));
        assert_eq!(img.get(2, 1), Rgb::new(1.0, 2.0, 3.0));
        assert_eq!(img.get(0, 0), Rgb::ZERO);
    }

    #[test]
    fn mean_uses_f64() {
        // 1 + many tiny values: f32 accumulation would lose the tiny ones.
        let mut img = Image::filled(1000, 1000, Rgb::splat(1e-8));
        img.set(0, 0, Rgb::splat(1.0));
        let m = img.mean().x as f64;
        let expected = (1.0 + 999_999.0 * 1e-8) / 1e6;
        assert!((m - expected).abs() < 1e-12, "{m} vs {expected}");
        assert_eq!(Image::new(0, 0).mean(), Rgb::ZERO);
    }

    #[test]
    fn from_pixels_checks_length() {
        assert!(Image::from_pixels(2, 2, vec![Rgb::ZERO; 3]).is_err());
        assert!(Image::from_pixels(2, 2, vec![Rgb::ZERO; 4]).is_ok());
    }

    #[test]
    fn from_fn_order() {
        let img = Image::from_fn(2, 2, |x, y| Rgb::new(x as f32, y as f32, 0.0));
        assert_eq!(img.pixels[1], Rgb::new(1.0, 0.0, 0.0));
        assert_eq!(img.pixels[2], Rgb::new(0.0, 1.0, 0.0));
    }
}
