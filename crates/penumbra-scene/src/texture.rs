//! Textures in linear RGB, sampled bilinearly with repeat wrapping.

use glam::Vec2;
use penumbra_shading::Rgb;

/// Index of a texture in [`crate::Scene::textures`].
pub type TextureId = usize;

/// A linear-RGB image (sRGB-encoded inputs are decoded on load).
#[derive(Clone, Debug)]
pub struct Texture {
    pub name: String,
    pub width: u32,
    pub height: u32,
    /// Row-major, row 0 at the top (v = 0 in glTF's convention).
    pub texels: Vec<Rgb>,
}

impl Texture {
    /// Bilinear lookup at `uv` with repeat wrapping (glTF default sampler).
    pub fn sample(&self, uv: Vec2) -> Rgb {
        let (w, h) = (self.width as i64, self.height as i64);
        if w == 0 || h == 0 {
            return Rgb::ONE;
        }
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let at = |xi: i64, yi: i64| -> Rgb {
            let xi = xi.rem_euclid(w) as usize;
            let yi = yi.rem_euclid(h) as usize;
            self.texels[yi * self.width as usize + xi]
        };
        let (x0, y0) = (x0 as i64, y0 as i64);
        let top = at(x0, y0).lerp(at(x0 + 1, y0), fx);
        let bottom = at(x0, y0 + 1).lerp(at(x0 + 1, y0 + 1), fx);
        top.lerp(bottom, fy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bilinear_and_wrap() {
        let t = Texture {
            name: "t".into(),
            width: 2,
            height: 1,
            texels: vec![Rgb::ZERO, Rgb::ONE],
        };
        assert!((t.sample(Vec2::new(0.25, 0.5)) - Rgb::ZERO).length() < 1e-6);
        assert!((t.sample(Vec2::new(0.5, 0.5)) - Rgb::splat(0.5)).length() < 1e-6);
        assert!((t.sample(Vec2::new(1.25, 0.5)) - Rgb::ZERO).length() < 1e-6);
    }
}
