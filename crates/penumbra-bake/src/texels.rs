//! The texels of an atlas as surface points: the bake's "camera".
//!
//! Coverage is conservative: a texel belongs to every triangle whose UV
//! triangle overlaps the texel's square (separating-axis test), not only to
//! triangles that contain its centre, so texels a triangle covers in part
//! are baked too. Each covered texel is baked at one point: its centre when
//! a triangle contains it, else the point of the overlapping triangles
//! nearest to the centre (in texel units). Lookups interpolate texel
//! centres bilinearly, so the value at the centre is what a texel stores.

use crate::atlas::Atlas;
use glam::Vec2;
use penumbra_scene::Scene;
use penumbra_trace::geometry::SceneGeometry;
use rayon::prelude::*;

/// A covered texel and the surface point it is baked at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Texel {
    pub page: u32,
    pub x: u32,
    pub y: u32,
    pub instance: u32,
    /// Triangle index in [`SceneGeometry`] order.
    pub triangle: u32,
    /// Triangle index inside the instance's mesh.
    pub local_triangle: u32,
    /// Barycentrics of the baked point for the triangle's vertices 1 and 2.
    pub b1: f32,
    pub b2: f32,
    /// The triangle contains the texel's centre (else the point is the
    /// nearest one on the triangle).
    pub centre_inside: bool,
}

/// Every covered texel of an atlas, in page, row, column order.
#[derive(Clone, Debug)]
pub struct Texels {
    pub width: u32,
    pub height: u32,
    pub pages: u32,
    pub texels: Vec<Texel>,
    /// Per page texel (`page · W·H + y · W + x`): index into `texels`, or
    /// `u32::MAX` where no triangle overlaps.
    pub index: Vec<u32>,
}

/// The best candidate for a texel so far.
#[derive(Clone, Copy)]
struct Candidate {
    /// Squared distance from the texel centre to the triangle (texels²).
    distance2: f32,
    instance: u32,
    local: u32,
    b1: f32,
    b2: f32,
}

impl Texels {
    /// The texels of `atlas` over the instances of `scene`.
    pub fn cover(scene: &Scene, geometry: &SceneGeometry, atlas: &Atlas) -> Self {
        let (w, h) = (atlas.width, atlas.height);
        let page_len = w as usize * h as usize;
        // Pages are covered in parallel; within a page instances and
        // triangles go in order, so ties break the same way every time.
        let pages: Vec<Vec<Option<Candidate>>> = (0..atlas.pages)
            .into_par_iter()
            .map(|page| {
                let mut best: Vec<Option<Candidate>> = vec![None; page_len];
                for instance in 0..scene.instances.len() {
                    let Some(rect) = atlas.instances[instance] else {
                        continue;
                    };
                    if rect.page != page {
                        continue;
                    }
                    let n = scene.meshes[scene.instances[instance].mesh].indices.len();
                    for t in 0..n {
                        let Some((_, uv)) = atlas.triangle_uvs(scene, instance, t) else {
                            continue;
                        };
                        let size = Vec2::new(w as f32, h as f32);
                        let tri = uv.map(|c| c * size);
                        rasterize(&tri, w, h, |x, y| {
                            let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                            let (d2, b1, b2) = closest_point(&tri, centre);
                            let slot = &mut best[y as usize * w as usize + x as usize];
                            if slot.is_none_or(|c| d2 < c.distance2) {
                                *slot = Some(Candidate {
                                    distance2: d2,
                                    instance: instance as u32,
                                    local: t as u32,
                                    b1,
                                    b2,
                                });
                            }
                        });
                    }
                }
                best
            })
            .collect();
        let mut texels = Vec::new();
        let mut index = vec![u32::MAX; page_len * atlas.pages as usize];
        for (page, best) in pages.iter().enumerate() {
            for (i, c) in best.iter().enumerate() {
                let Some(c) = c else { continue };
                let first = geometry.instance_triangles(c.instance as usize).start;
                index[page * page_len + i] = texels.len() as u32;
                texels.push(Texel {
                    page: page as u32,
                    x: (i % w as usize) as u32,
                    y: (i / w as usize) as u32,
                    instance: c.instance,
                    triangle: first + c.local,
                    local_triangle: c.local,
                    b1: c.b1,
                    b2: c.b2,
                    centre_inside: c.distance2 == 0.0,
                });
            }
        }
        Self {
            width: w,
            height: h,
            pages: atlas.pages,
            texels,
            index,
        }
    }

    /// The texel at (page, x, y), if covered.
    pub fn at(&self, page: u32, x: u32, y: u32) -> Option<&Texel> {
        if x >= self.width || y >= self.height || page >= self.pages {
            return None;
        }
        let i = self.index[self.page_offset(page) + y as usize * self.width as usize + x as usize];
        self.texels.get(i as usize)
    }

    fn page_offset(&self, page: u32) -> usize {
        page as usize * self.width as usize * self.height as usize
    }
}

/// Calls `f(x, y)` for every texel whose square `[x, x+1] × [y, y+1]`
/// overlaps triangle `tri` (texel units) in an area (touching along an edge
/// or at a point does not count): a separating-axis test on the
/// square's two axes (the bounding box) and the triangle's three edge
/// normals. Degenerate triangles cover nothing.
fn rasterize(tri: &[Vec2; 3], w: u32, h: u32, mut f: impl FnMut(u32, u32)) {
    let lo = tri[0].min(tri[1]).min(tri[2]);
    let hi = tri[0].max(tri[1]).max(tri[2]);
    let area2 = (tri[1] - tri[0]).perp_dot(tri[2] - tri[0]);
    if area2 == 0.0 || !area2.is_finite() {
        return;
    }
    let x0 = lo.x.floor().max(0.0) as u32;
    let y0 = lo.y.floor().max(0.0) as u32;
    let x1 = (hi.x.ceil() as i64).clamp(0, w as i64) as u32;
    let y1 = (hi.y.ceil() as i64).clamp(0, h as i64) as u32;
    // Edge normals pointing out of the triangle, and the triangle's extent
    // along each (the opposite vertex).
    let sign = area2.signum();
    let edges: [(Vec2, f32); 3] = std::array::from_fn(|k| {
        let (a, b) = (tri[k], tri[(k + 1) % 3]);
        let n = Vec2::new(b.y - a.y, a.x - b.x) * sign;
        (n, n.dot(a))
    });
    for y in y0..y1 {
        for x in x0..x1 {
            let corner = Vec2::new(x as f32, y as f32);
            let separated = edges.iter().any(|&(n, d)| {
                // The square's vertex least far along n.
                let nearest =
                    corner + Vec2::new((n.x < 0.0) as u8 as f32, (n.y < 0.0) as u8 as f32);
                n.dot(nearest) >= d
            });
            if !separated {
                f(x, y);
            }
        }
    }
}

/// Squared distance from `p` to triangle `tri` and the barycentrics (b1,
/// b2) of the nearest point (0 and `p`'s own barycentrics when inside).
pub(crate) fn closest_point(tri: &[Vec2; 3], p: Vec2) -> (f32, f32, f32) {
    let [a, b, c] = *tri;
    let area2 = (b - a).perp_dot(c - a);
    let b1 = (p - a).perp_dot(c - a) / area2;
    let b2 = (b - a).perp_dot(p - a) / area2;
    if b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 {
        return (0.0, b1, b2);
    }
    // Nearest point on each edge, as (distance², b1, b2).
    let on_edge = |from: Vec2, to: Vec2, bary: &dyn Fn(f32) -> (f32, f32)| {
        let e = to - from;
        let t = ((p - from).dot(e) / e.length_squared()).clamp(0.0, 1.0);
        let q = from + e * t;
        let (u, v) = bary(t);
        ((p - q).length_squared(), u, v)
    };
    let candidates = [
        on_edge(a, b, &|t| (t, 0.0)),
        on_edge(b, c, &|t| (1.0 - t, t)),
        on_edge(c, a, &|t| (0.0, 1.0 - t)),
    ];
    candidates
        .into_iter()
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .unwrap_or((f32::INFINITY, 0.0, 0.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conservative_coverage_includes_partly_covered_texels() {
        // A thin sliver inside texel row 2 crossing columns 1..4: it covers
        // no texel centre, yet every texel it passes through is covered.
        let tri = [
            Vec2::new(1.2, 2.1),
            Vec2::new(4.8, 2.2),
            Vec2::new(1.2, 2.3),
        ];
        let mut hit = Vec::new();
        rasterize(&tri, 8, 8, |x, y| hit.push((x, y)));
        assert_eq!(hit, vec![(1, 2), (2, 2), (3, 2), (4, 2)]);
        // A right triangle with its hypotenuse through texel corners: the
        // texels beyond the diagonal are not covered, those on it are.
        let tri = [Vec2::ZERO, Vec2::new(4.0, 0.0), Vec2::new(0.0, 4.0)];
        let mut hit = Vec::new();
        rasterize(&tri, 8, 8, |x, y| hit.push((x, y)));
        for y in 0..4 {
            for x in 0..4 {
                // Texel (x, y) overlaps the open triangle iff x + y < 4.
                assert_eq!(hit.contains(&(x, y)), x + y < 4, "({x}, {y})");
            }
        }
    }

    #[test]
    fn closest_point_clamps_to_the_nearest_edge() {
        let tri = [Vec2::ZERO, Vec2::new(2.0, 0.0), Vec2::new(0.0, 2.0)];
        assert_eq!(closest_point(&tri, Vec2::new(0.5, 0.5)), (0.0, 0.25, 0.25));
        // Below the edge a–b: nearest point (1, 0), b1 = 0.5.
        let (d2, b1, b2) = closest_point(&tri, Vec2::new(1.0, -0.5));
        assert!((d2 - 0.25).abs() < 1e-6 && (b1 - 0.5).abs() < 1e-6 && b2 == 0.0);
        // Beyond the hypotenuse from (2, 0) to (0, 2): (2, 2) projects to
        // (1, 1), at distance² 2, with b1 = b2 = 0.5.
        let (d2, b1, b2) = closest_point(&tri, Vec2::new(2.0, 2.0));
        assert!((d2 - 2.0).abs() < 1e-5 && (b1 - 0.5).abs() < 1e-6 && (b2 - 0.5).abs() < 1e-6);
        // Past vertex c: the vertex itself.
        let (d2, b1, b2) = closest_point(&tri, Vec2::new(-1.0, 3.0));
        assert!((d2 - 2.0).abs() < 1e-5 && b1.abs() < 1e-6 && (b2 - 1.0).abs() < 1e-6);
    }
}
