//! Looking a bake up where a surface is seen: the CPU twin of the raster
//! engine's light-map pass. A hit's atlas coordinate is its triangle's
//! corner coordinates interpolated with the hit's barycentrics; a page is
//! read bilinearly between texel centres (edges clamped), as the GPU reads
//! it, so both display the same values.

use crate::atlas::Atlas;
use glam::Vec2;
use penumbra_image::{Image, Rgb};
use penumbra_scene::Scene;
use penumbra_trace::geometry::{SceneGeometry, SurfaceHit};

/// Bilinear lookup of `page` at page coordinate `uv` (texel (x, y) has its
/// centre at ((x + ½)/W, (y + ½)/H); beyond the outer centres the edge
/// texels are repeated).
pub fn bilinear(page: &Image, uv: Vec2) -> Rgb {
    let (w, h) = (page.width as f32, page.height as f32);
    let p = Vec2::new(uv.x * w - 0.5, uv.y * h - 0.5);
    let f = p - p.floor();
    let (x0, y0) = (p.x.floor() as i64, p.y.floor() as i64);
    let at = |x: i64, y: i64| {
        let x = x.clamp(0, page.width as i64 - 1) as u32;
        let y = y.clamp(0, page.height as i64 - 1) as u32;
        page.get(x, y)
    };
    let top = at(x0, y0) * (1.0 - f.x) + at(x0 + 1, y0) * f.x;
    let bottom = at(x0, y0 + 1) * (1.0 - f.x) + at(x0 + 1, y0 + 1) * f.x;
    top * (1.0 - f.y) + bottom * f.y
}

impl Atlas {
    /// Page and page coordinate of a surface hit (`None` for lights and
    /// instances without texels).
    pub fn locate(
        &self,
        scene: &Scene,
        geometry: &SceneGeometry,
        hit: &SurfaceHit,
    ) -> Option<(u32, Vec2)> {
        if hit.light.is_some() {
            return None;
        }
        let (instance, local) = geometry.triangle_source(hit.triangle);
        let (page, [a, b, c]) = self.triangle_uvs(scene, instance, local)?;
        let uv = a * (1.0 - hit.b1 - hit.b2) + b * hit.b1 + c * hit.b2;
        Some((page, uv))
    }

    /// The bilinear lookup of `pages` at a surface hit (see [`bilinear`]).
    pub fn sample(
        &self,
        pages: &[Image],
        scene: &Scene,
        geometry: &SceneGeometry,
        hit: &SurfaceHit,
    ) -> Option<Rgb> {
        let (page, uv) = self.locate(scene, geometry, hit)?;
        Some(bilinear(pages.get(page as usize)?, uv))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bilinear_interpolates_between_texel_centres() {
        let page = Image {
            width: 2,
            height: 1,
            pixels: vec![Rgb::splat(1.0), Rgb::splat(3.0)],
        };
        // At the texel centres, exactly the texels; halfway, the mean.
        assert_eq!(bilinear(&page, Vec2::new(0.25, 0.5)), Rgb::splat(1.0));
        assert_eq!(bilinear(&page, Vec2::new(0.75, 0.5)), Rgb::splat(3.0));
        assert_eq!(bilinear(&page, Vec2::new(0.5, 0.5)), Rgb::splat(2.0));
        // A quarter texel past the first centre: 1 + 0.5·(3 − 1)·0.5.
        assert_eq!(bilinear(&page, Vec2::new(0.375, 0.2)), Rgb::splat(1.5));
        // Beyond the outer centres: clamped.
        assert_eq!(bilinear(&page, Vec2::new(0.0, 0.0)), Rgb::splat(1.0));
        assert_eq!(bilinear(&page, Vec2::new(1.0, 1.0)), Rgb::splat(3.0));
    }
}
