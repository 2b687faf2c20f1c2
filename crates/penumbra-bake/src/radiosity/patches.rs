//! Patches: the valid texels of a coarse light-map atlas, each with the
//! piece of surface it covers (its *footprint*), the footprint's world
//! area, a point and normal to describe it, its reflectance and its
//! emitted exitance.
//!
//! **Footprint and area.** Texel (x, y) covers the square
//! `[x, x+1] × [y, y+1]` of its page (texel units). Every triangle of the
//! texel's instance is clipped against that square (Sutherland–Hodgman);
//! each clipped polygon has page area `a` and world area `a · J`, with the
//! triangle's Jacobian `J = A_world / A_page` (constant over a triangle:
//! the chart map is affine per triangle). The pieces are kept as fans of
//! triangles in the source triangle's barycentrics, so shooting can pick
//! points uniformly over the footprint. Pages partition every triangle, so
//! the footprints of all covered texels add up to the surface area of the
//! baked instances (less the triangles degenerate in the atlas).
//!
//! A valid texel whose chart covers less than [`MIN_COVER`] of its square
//! (a sliver at a chart's border) is not a patch of its own: it joins the
//! nearest patch of its instance (below), which takes its footprint and
//! area and whose E it shows in the map (an instance with slivers only
//! keeps them as patches). A tiny patch would receive almost no rays, and
//! its noisy or zero E would leak into its neighbours through bilinear
//! lookups.
//!
//! Covered texels found inside geometry (invalid) are not patches: their
//! footprints are hidden surface (under a block, above a light), which no
//! light reaches from the front, and giving their area to a neighbour
//! would dilute that neighbour's irradiance. Their area is reported apart
//! ([`super::RadiositySolution::unpatched_area`]).
//!
//! **Hits to patches.** A ray hit is located on its page
//! ([`crate::Atlas::locate`]); its texel is a patch, or (a sliver of an
//! invalid texel that is visible, a float at a chart edge) maps to the
//! nearest patch of the same instance: a multi-source breadth-first fill
//! over the page's 8-neighbourhood, seeded with the patches, that enters a
//! covered texel only from a patch of its own instance (uncovered padding
//! texels take the first label that reaches them). Ties go to the label
//! that comes first in texel order, so the map is the same on every run.

use crate::atlas::Atlas;
use crate::baker::Prepared;
use crate::texels::Texel;
use glam::{Vec2, Vec3};
use penumbra_scene::Scene;
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::Bsdf;
use penumbra_trace::geometry::SceneGeometry;
use std::collections::VecDeque;
use std::f32::consts::PI;

/// No patch (texel → patch maps).
pub(crate) const NONE: u32 = u32::MAX;

/// Fraction of its square a texel's chart must cover for the texel to be a
/// patch of its own; a less covered valid texel (a sliver at a chart's
/// border) joins the nearest patch of its instance (its footprint and area
/// are added to that patch's), so no patch is too small to receive rays.
pub const MIN_COVER: f64 = 0.5;

/// One radiosity patch (a valid texel of the coarse atlas) and its solution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Patch {
    /// The texel (page, x, y, instance) and the surface point it is baked at.
    pub texel: Texel,
    /// The texel's surface point and front geometric normal.
    pub point: Vec3,
    pub normal: Vec3,
    /// World area of the footprint [scene units²].
    pub area: f32,
    /// Diffuse reflectance ρ used by the solve (the material's albedo,
    /// clamped to [0, 1]).
    pub reflectance: Rgb,
    /// Emitted exitance from the front side, `π Le` [W/m²].
    pub exitance: Rgb,
    /// The material also emits from its back side (double-sided emitter):
    /// the back shoots `π Le A` once, into the back hemisphere.
    pub emits_back: bool,
    /// The solution: irradiance E on the front side [W/m²], the mean over
    /// the footprint of the light arriving from every emitter and bounce.
    pub irradiance: Rgb,
}

/// A triangle of a footprint: corners in the barycentrics (b1, b2) of
/// geometry triangle `triangle`, and its world area.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Piece {
    pub triangle: u32,
    pub corners: [Vec2; 3],
    pub area: f32,
}

/// The patches of a prepared scene.
pub(crate) struct Patches {
    pub patches: Vec<Patch>,
    /// Footprint pieces of patch `i`: `pieces[piece_start[i]..piece_start[i+1]]`.
    pub pieces: Vec<Piece>,
    pub piece_start: Vec<u32>,
    /// Per page texel (page-major): the patch a hit there deposits on, or
    /// [`NONE`].
    pub texel_patch: Vec<u32>,
    /// Per page texel: the patch it belongs to (its own, or the one a
    /// sliver joined), [`NONE`] for texels inside geometry or uncovered.
    pub owner: Vec<u32>,
    /// World area of covered texels that are not patches (inside geometry).
    pub unpatched_area: f64,
    /// World area of triangles degenerate in the atlas (no texel covers it).
    pub lost_area: f64,
    /// Names of the materials that are not Lambertian (approximated by
    /// their albedo), and of those with an albedo texture (approximated by
    /// the constant base colour), each once.
    pub non_lambert: Vec<String>,
    pub textured: Vec<String>,
}

impl Patches {
    /// Footprints, areas and materials of every valid texel of `prep`.
    pub fn new(prep: &Prepared<'_>) -> Self {
        let (scene, geometry, atlas) = (prep.scene, &prep.geometry, &prep.atlas);
        let (w, h) = (atlas.width as usize, atlas.height as usize);
        let pages = atlas.pages as usize;
        let page_len = w * h;
        let total = page_len * pages;
        let (per_texel, lost_area) = clip_footprints(scene, geometry, atlas);
        // Per page texel: world area and covered fraction of its square.
        let mut area = vec![0.0f64; total];
        let mut cover = vec![0.0f64; total];
        for &(t, piece, page_area) in &per_texel {
            area[t] += piece.area as f64;
            cover[t] += page_area as f64;
        }
        let offset = |t: &Texel| t.page as usize * page_len + t.y as usize * w + t.x as usize;
        let instance_of_texel: Vec<u32> = prep
            .texels
            .index
            .iter()
            .map(|&i| {
                prep.texels
                    .texels
                    .get(i as usize)
                    .map_or(NONE, |t| t.instance)
            })
            .collect();
        let valid: Vec<bool> = {
            let mut v = vec![false; total];
            for t in &prep.texels.texels {
                let o = offset(t);
                v[o] = prep.is_valid(t) && area[o] > 0.0;
            }
            v
        };
        // Patches: the valid texels covered at least MIN_COVER, and the
        // valid slivers with no such texel of their instance to join.
        let mut seed: Vec<u32> = (0..total)
            .map(|o| {
                if valid[o] && cover[o] >= MIN_COVER {
                    o as u32
                } else {
                    NONE
                }
            })
            .collect();
        let joined = nearest_patch_map(&seed, &instance_of_texel, w, h, pages);
        for o in 0..total {
            if valid[o] && joined[o] == NONE {
                seed[o] = o as u32;
            }
        }
        let mut patch_of_texel = vec![NONE; total];
        let mut patches = Vec::new();
        let mut non_lambert = Vec::new();
        let mut textured = Vec::new();
        for t in &prep.texels.texels {
            let o = offset(t);
            if seed[o] == NONE {
                continue;
            }
            let hit = geometry.surface_point(scene, t.triangle, t.b1, t.b2);
            let material = &scene.materials[geometry.material_of(t.triangle)];
            if !matches!(material.bsdf, Bsdf::Lambert(_)) && !non_lambert.contains(&material.name) {
                non_lambert.push(material.name.clone());
            }
            if material.albedo_texture.is_some() && !textured.contains(&material.name) {
                textured.push(material.name.clone());
            }
            patch_of_texel[o] = patches.len() as u32;
            patches.push(Patch {
                texel: *t,
                point: hit.p,
                normal: hit.ng,
                area: 0.0,
                reflectance: material.bsdf.albedo().clamp(Rgb::ZERO, Rgb::ONE),
                exitance: material.emission * PI,
                emits_back: material.double_sided && material.is_emissive(),
                irradiance: Rgb::ZERO,
            });
        }
        let texel_patch = nearest_patch_map(&patch_of_texel, &instance_of_texel, w, h, pages);
        // Every valid texel belongs to its patch, or joins the nearest one.
        let owner: Vec<u32> = (0..total)
            .map(|o| if valid[o] { texel_patch[o] } else { NONE })
            .collect();
        let mut unpatched_area = 0.0f64;
        for o in 0..total {
            match owner[o] {
                NONE => unpatched_area += area[o],
                p => patches[p as usize].area += area[o] as f32,
            }
        }
        // Pieces grouped by patch, each group in clipping order.
        let mut counts = vec![0u32; patches.len() + 1];
        for &(t, _, _) in &per_texel {
            if owner[t] != NONE {
                counts[owner[t] as usize + 1] += 1;
            }
        }
        for i in 1..counts.len() {
            counts[i] += counts[i - 1];
        }
        let piece_start = counts.clone();
        let mut fill = counts;
        let mut pieces = vec![
            Piece {
                triangle: 0,
                corners: [Vec2::ZERO; 3],
                area: 0.0
            };
            *piece_start.last().unwrap_or(&0) as usize
        ];
        for &(t, piece, _) in &per_texel {
            let p = owner[t];
            if p != NONE {
                pieces[fill[p as usize] as usize] = piece;
                fill[p as usize] += 1;
            }
        }
        Self {
            patches,
            pieces,
            piece_start,
            texel_patch,
            owner,
            unpatched_area,
            lost_area,
            non_lambert,
            textured,
        }
    }

    /// The footprint pieces of patch `i`.
    pub fn pieces_of(&self, i: usize) -> &[Piece] {
        &self.pieces[self.piece_start[i] as usize..self.piece_start[i + 1] as usize]
    }

    /// The patch a hit at page coordinate `uv` of `page` deposits on.
    pub fn patch_at(&self, atlas: &Atlas, page: u32, uv: Vec2) -> u32 {
        let (w, h) = (atlas.width, atlas.height);
        let x = ((uv.x * w as f32).floor() as i64).clamp(0, w as i64 - 1) as usize;
        let y = ((uv.y * h as f32).floor() as i64).clamp(0, h as i64 - 1) as usize;
        let page_len = w as usize * h as usize;
        self.texel_patch
            .get(page as usize * page_len + y * w as usize + x)
            .copied()
            .unwrap_or(NONE)
    }
}

/// A point of patch `pieces` chosen uniformly by area from three uniform
/// numbers: the triangle and its barycentrics (b1, b2). Uniform in a
/// triangle: corner weights `(1 − √u, √u (1 − v), √u v)`.
pub(crate) fn sample_footprint(
    pieces: &[Piece],
    area: f32,
    u_pick: f32,
    u: [f32; 2],
) -> (u32, Vec2) {
    let mut target = u_pick * area;
    let mut chosen = pieces[pieces.len() - 1];
    for p in pieces {
        if target < p.area {
            chosen = *p;
            break;
        }
        target -= p.area;
    }
    let su = u[0].sqrt();
    let [a, b, c] = chosen.corners;
    let bary = a * (1.0 - su) + b * (su * (1.0 - u[1])) + c * (su * u[1]);
    (chosen.triangle, bary)
}

/// Every (page texel, piece, piece's page area in texels²) of the
/// footprints, in instance, triangle, row, column order; and the world area of the triangles that are
/// degenerate in the atlas.
fn clip_footprints(
    scene: &Scene,
    geometry: &SceneGeometry,
    atlas: &Atlas,
) -> (Vec<(usize, Piece, f32)>, f64) {
    let (w, h) = (atlas.width, atlas.height);
    let page_len = w as usize * h as usize;
    let size = Vec2::new(w as f32, h as f32);
    let mut out = Vec::new();
    let mut lost = 0.0f64;
    for instance in 0..scene.instances.len() {
        let first = geometry.instance_triangles(instance).start;
        let n = scene.meshes[scene.instances[instance].mesh].indices.len();
        for local in 0..n {
            let triangle = first + local as u32;
            let world_area = geometry.area(triangle);
            let Some((page, uv)) = atlas.triangle_uvs(scene, instance, local) else {
                continue;
            };
            let tri = uv.map(|c| c * size);
            let area2 = (tri[1] - tri[0]).perp_dot(tri[2] - tri[0]);
            if area2 == 0.0 || !area2.is_finite() {
                lost += world_area as f64;
                continue;
            }
            let jacobian = world_area / (0.5 * area2.abs());
            let bary = |q: Vec2| {
                Vec2::new(
                    (q - tri[0]).perp_dot(tri[2] - tri[0]) / area2,
                    (tri[1] - tri[0]).perp_dot(q - tri[0]) / area2,
                )
            };
            let lo = tri[0].min(tri[1]).min(tri[2]);
            let hi = tri[0].max(tri[1]).max(tri[2]);
            let x0 = lo.x.floor().max(0.0) as u32;
            let y0 = lo.y.floor().max(0.0) as u32;
            let x1 = (hi.x.ceil() as i64).clamp(0, w as i64) as u32;
            let y1 = (hi.y.ceil() as i64).clamp(0, h as i64) as u32;
            for y in y0..y1 {
                for x in x0..x1 {
                    let poly = clip_to_square(&tri, Vec2::new(x as f32, y as f32));
                    if poly.len() < 3 {
                        continue;
                    }
                    let texel = page as usize * page_len + y as usize * w as usize + x as usize;
                    // Fan from the first vertex.
                    for k in 1..poly.len() - 1 {
                        let (a, b, c) = (poly[0], poly[k], poly[k + 1]);
                        let a2 = (b - a).perp_dot(c - a).abs();
                        if a2.is_nan() || a2 <= 0.0 {
                            continue;
                        }
                        out.push((
                            texel,
                            Piece {
                                triangle,
                                corners: [bary(a), bary(b), bary(c)],
                                area: 0.5 * a2 * jacobian,
                            },
                            0.5 * a2,
                        ));
                    }
                }
            }
        }
    }
    (out, lost)
}

/// The part of triangle `tri` inside the unit square with lower corner
/// `corner` (Sutherland–Hodgman against its four edges).
pub(crate) fn clip_to_square(tri: &[Vec2; 3], corner: Vec2) -> Vec<Vec2> {
    let mut poly: Vec<Vec2> = tri.to_vec();
    // (axis, bound, keep the side above the bound)
    let planes = [
        (0, corner.x, true),
        (0, corner.x + 1.0, false),
        (1, corner.y, true),
        (1, corner.y + 1.0, false),
    ];
    for (axis, bound, above) in planes {
        if poly.is_empty() {
            break;
        }
        let dist = |p: Vec2| {
            if above {
                p[axis] - bound
            } else {
                bound - p[axis]
            }
        };
        let mut next = Vec::with_capacity(poly.len() + 1);
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let (da, db) = (dist(a), dist(b));
            if da >= 0.0 {
                next.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                let t = da / (da - db);
                let mut q = a + (b - a) * t;
                q[axis] = bound; // exactly on the edge
                next.push(q);
            }
        }
        poly = next;
    }
    poly
}

/// Per page texel: its own patch, else the nearest patch reachable
/// through texels of the same instance or uncovered ones (see the module
/// docs), else [`NONE`].
fn nearest_patch_map(
    patch_of_texel: &[u32],
    instance_of_texel: &[u32],
    w: usize,
    h: usize,
    pages: usize,
) -> Vec<u32> {
    let page_len = w * h;
    let mut map = patch_of_texel.to_vec();
    // The instance of each texel's label (its patch's instance).
    let mut label_instance = instance_of_texel.to_vec();
    for p in 0..pages {
        let base = p * page_len;
        let mut queue: VecDeque<usize> = (0..page_len).filter(|&i| map[base + i] != NONE).collect();
        while let Some(i) = queue.pop_front() {
            let label = map[base + i];
            let instance = label_instance[base + i];
            let (x, y) = ((i % w) as i64, (i / w) as i64);
            for dy in -1..=1i64 {
                for dx in -1..=1i64 {
                    let (nx, ny) = (x + dx, y + dy);
                    if (dx, dy) == (0, 0) || nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                        continue;
                    }
                    let j = ny as usize * w + nx as usize;
                    if map[base + j] != NONE {
                        continue;
                    }
                    let other = instance_of_texel[base + j];
                    if other != NONE && other != instance {
                        continue;
                    }
                    map[base + j] = label;
                    label_instance[base + j] = instance;
                    queue.push_back(j);
                }
            }
        }
    }
    map
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(poly: &[Vec2]) -> f32 {
        (1..poly.len().saturating_sub(1))
            .map(|k| 0.5 * (poly[k] - poly[0]).perp_dot(poly[k + 1] - poly[0]))
            .sum()
    }

    #[test]
    fn clipping_partitions_a_triangle_among_texels() {
        // A triangle over several texels: the clipped areas add up to its
        // area, 0.5 · 3.2 · 2.7.
        let tri = [
            Vec2::new(0.3, 0.4),
            Vec2::new(3.5, 0.4),
            Vec2::new(0.3, 3.1),
        ];
        let mut sum = 0.0;
        for y in 0..4 {
            for x in 0..4 {
                sum += area(&clip_to_square(&tri, Vec2::new(x as f32, y as f32)));
            }
        }
        assert!((sum - 0.5 * 3.2 * 2.7).abs() < 1e-5, "{sum}");
        // A square fully inside the triangle keeps its unit area.
        let big = [
            Vec2::new(-10.0, -10.0),
            Vec2::new(30.0, -10.0),
            Vec2::new(-10.0, 30.0),
        ];
        assert!((area(&clip_to_square(&big, Vec2::ZERO)) - 1.0).abs() < 1e-6);
        // Beyond the hypotenuse x + y = 20: nothing.
        assert!(clip_to_square(&big, Vec2::new(15.0, 15.0)).len() < 3);
        // Cut by the hypotenuse through the square's diagonal: half.
        let half = [Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)];
        assert!((area(&clip_to_square(&half, Vec2::ZERO)) - 0.5).abs() < 1e-6);
    }
}
