//! Acceleration structure: a compressed wide BVH (CWBVH, 8-wide; Ylitie et
//! al. 2017) built by `obvhs` with PLOC + reinsertion, over world-space
//! triangles, traversed with our watertight triangle test.

mod watertight;

pub use watertight::{TriangleHit, WatertightRay};

use crate::ray::Ray;
use glam::{Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::aabb::Aabb;
use obvhs::cwbvh::CwBvh;
use obvhs::triangle::Triangle;
use std::time::Duration;

/// Relative padding of primitive boxes (≈ 32 ulps of the largest coordinate).
const BOX_PAD_RELATIVE: f32 = 4.0e-6;

/// Closest hit: triangle index (in the order given to [`Accel::build`]),
/// distance and barycentrics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub triangle: u32,
    pub t: f32,
    pub b1: f32,
    pub b2: f32,
}

/// BVH over a triangle soup.
#[derive(Debug)]
pub struct Accel {
    bvh: CwBvh,
    /// Triangles in BVH leaf order (`bvh.primitive_indices` order).
    ordered: Vec<[Vec3A; 3]>,
    triangle_count: usize,
}

/// BVH build quality preset.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BuildQuality {
    Fast,
    #[default]
    Medium,
}

impl Accel {
    /// Builds over `triangles` (world space). An empty list gives an
    /// accelerator that misses every ray.
    pub fn build(triangles: &[[Vec3; 3]], quality: BuildQuality) -> Self {
        if triangles.is_empty() {
            return Self {
                bvh: CwBvh::default(),
                ordered: Vec::new(),
                triangle_count: 0,
            };
        }
        let tris: Vec<Triangle> = triangles
            .iter()
            .map(|t| Triangle {
                v0: t[0].into(),
                v1: t[1].into(),
                v2: t[2].into(),
            })
            .collect();
        let params = match quality {
            BuildQuality::Fast => BvhBuildParams::fast_build(),
            BuildQuality::Medium => BvhBuildParams::medium_build(),
        };
        // Boxes padded by a few ulps of their coordinates make the float slab
        // test conservative (cf. Ize 2013, "Robust BVH Ray Traversal"): a ray
        // through a vertex on a box corner must not skip the box, or the
        // watertight triangle test cannot do its job.
        let boxes: Vec<Aabb> = tris
            .iter()
            .map(|t| {
                let b = t.aabb();
                let pad = b.min.abs().max(b.max.abs()).max_element() * BOX_PAD_RELATIVE
                    + f32::MIN_POSITIVE;
                Aabb::new(b.min - pad, b.max + pad)
            })
            .collect();
        let bvh = obvhs::cwbvh::builder::build_cwbvh(&boxes, params, &mut Duration::default());
        let ordered = bvh
            .primitive_indices
            .iter()
            .map(|&i| {
                let t = &tris[i as usize];
                [t.v0, t.v1, t.v2]
            })
            .collect();
        Self {
            bvh,
            ordered,
            triangle_count: triangles.len(),
        }
    }

    pub fn triangle_count(&self) -> usize {
        self.triangle_count
    }

    /// Closest hit along `ray` in (0, ray.tmax).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        self.intersect_where(ray, |_, _, _| true)
    }

    /// Closest hit along `ray` in (0, ray.tmax) among the triangle hits
    /// that `keep(triangle, b1, b2)` accepts (an any-hit filter: alpha
    /// masks); rejected hits are passed through.
    #[inline]
    pub fn intersect_where(&self, ray: &Ray, keep: impl Fn(u32, f32, f32) -> bool) -> Option<Hit> {
        if self.ordered.is_empty() {
            return None;
        }
        let wt = WatertightRay::new(ray.origin, ray.direction);
        let r = bvh_ray(ray);
        let mut hit = obvhs::ray::RayHit::none();
        let found = self.bvh.ray_traverse(r, &mut hit, |r, id| {
            self.leaf_hit(&wt, id, r.tmax, &keep)
                .map_or(f32::INFINITY, |h| h.t)
        });
        if !found {
            return None;
        }
        let id = hit.primitive_id as usize;
        let [a, b, c] = self.ordered[id];
        let h = wt.intersect_a(a, b, c, f32::INFINITY)?;
        Some(Hit {
            triangle: self.bvh.primitive_indices[id],
            t: h.t,
            b1: h.b1,
            b2: h.b2,
        })
    }

    /// True if anything lies along `ray` in (0, ray.tmax) (shadow rays).
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.occluded_where(ray, |_, _, _| true)
    }

    /// True if a triangle hit that `keep(triangle, b1, b2)` accepts lies
    /// along `ray` in (0, ray.tmax).
    #[inline]
    pub fn occluded_where(&self, ray: &Ray, keep: impl Fn(u32, f32, f32) -> bool) -> bool {
        if self.ordered.is_empty() {
            return false;
        }
        let wt = WatertightRay::new(ray.origin, ray.direction);
        let r = bvh_ray(ray);
        !self.bvh.ray_traverse_miss(r, |r, id| {
            self.leaf_hit(&wt, id, r.tmax, &keep)
                .map_or(f32::INFINITY, |h| h.t)
        })
    }

    /// The hit of the triangle in leaf slot `id` before `tmax`, if `keep`
    /// accepts it.
    #[inline(always)]
    fn leaf_hit(
        &self,
        wt: &WatertightRay,
        id: usize,
        tmax: f32,
        keep: &impl Fn(u32, f32, f32) -> bool,
    ) -> Option<TriangleHit> {
        let [a, b, c] = self.ordered[id];
        wt.intersect_a(a, b, c, tmax)
            .filter(|h| keep(self.bvh.primitive_indices[id], h.b1, h.b2))
    }

    /// Checks the BVH structure: every triangle is reachable from the root
    /// and every node's bounds contain its children. Returns a description of
    /// the first problem.
    pub fn validate(&self) -> Result<(), String> {
        if self.ordered.is_empty() {
            return Ok(());
        }
        let mut seen = vec![false; self.triangle_count];
        for &i in &self.bvh.primitive_indices {
            match seen.get_mut(i as usize) {
                Some(s) => *s = true,
                None => return Err(format!("primitive index {i} out of range")),
            }
        }
        if let Some(missing) = seen.iter().position(|s| !s) {
            return Err(format!("triangle {missing} is not in the BVH"));
        }
        let tris: Vec<Triangle> = self
            .ordered
            .iter()
            .map(|t| Triangle {
                v0: t[0],
                v1: t[1],
                v2: t[2],
            })
            .collect();
        let result = self.bvh.validate(&tris, true);
        if result.prim_count < self.triangle_count {
            return Err(format!(
                "traversal reaches {} of {} triangles",
                result.prim_count, self.triangle_count
            ));
        }
        Ok(())
    }
}

/// The ray as obvhs traverses it. Zero direction components (of either
/// sign) become a tiny positive value: the slab test multiplies by 1/d, and
/// 1/(−0) = −∞ times a zero distance gives NaN, which dropped axis-parallel
/// rays such as −Vec3::Y. The triangle test still uses the exact direction.
#[inline]
fn bvh_ray(ray: &Ray) -> obvhs::ray::Ray {
    let d = ray.direction;
    let safe = Vec3::select(d.cmpeq(Vec3::ZERO), Vec3::splat(1e-30), d);
    obvhs::ray::Ray::new(ray.origin.into(), safe.into(), 0.0, ray.tmax)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute_force(tris: &[[Vec3; 3]], ray: &Ray) -> Option<(u32, f32)> {
        let wt = WatertightRay::new(ray.origin, ray.direction);
        let mut best: Option<(u32, f32)> = None;
        for (i, t) in tris.iter().enumerate() {
            if let Some(h) = wt.intersect(t[0], t[1], t[2], best.map_or(ray.tmax, |b| b.1)) {
                best = Some((i as u32, h.t));
            }
        }
        best
    }

    #[test]
    fn matches_brute_force_on_random_soup() {
        let mut s = penumbra_shading::sampling::Sampler::new(0, 0, 0, 1);
        let mut rnd = || {
            let [a, b] = s.next_2d();
            let [c, _] = s.next_2d();
            Vec3::new(a, b, c) * 10.0
        };
        let tris: Vec<[Vec3; 3]> = (0..2000)
            .map(|_| {
                let c = rnd();
                [c, c + rnd() * 0.1, c + rnd() * 0.1]
            })
            .collect();
        let accel = Accel::build(&tris, BuildQuality::Medium);
        accel.validate().unwrap();
        let mut hits = 0;
        for _ in 0..3000 {
            let o = rnd() - Vec3::splat(2.0);
            let d = (rnd() - Vec3::splat(5.0)).normalize();
            let ray = Ray::new(o, d);
            let a = accel.intersect(&ray).map(|h| (h.triangle, h.t));
            let b = brute_force(&tris, &ray);
            assert_eq!(a.map(|x| x.0), b.map(|x| x.0));
            assert_eq!(accel.occluded(&ray), b.is_some());
            hits += b.is_some() as u32;
        }
        assert!(hits > 100, "test should exercise hits, got {hits}");
    }

    #[test]
    fn empty_misses() {
        let a = Accel::build(&[], BuildQuality::Fast);
        assert!(a.intersect(&Ray::new(Vec3::ZERO, Vec3::X)).is_none());
        assert!(!a.occluded(&Ray::new(Vec3::ZERO, Vec3::X)));
    }
}

#[cfg(test)]
mod signed_zero_tests {
    use super::*;

    /// Axis-parallel rays hit a flat quad whatever the sign of their zero
    /// direction components (−0.0 makes 1/d = −∞ in slab tests).
    #[test]
    fn axis_parallel_rays_with_negative_zero_components_hit() {
        let (a, b, c, d) = (
            Vec3::new(-5.0, 0.0, -5.0),
            Vec3::new(5.0, 0.0, -5.0),
            Vec3::new(5.0, 0.0, 5.0),
            Vec3::new(-5.0, 0.0, 5.0),
        );
        let accel = Accel::build(&[[a, b, c], [a, c, d]], BuildQuality::Medium);
        for o in [
            Vec3::new(3.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-2.0, 1.0, 4.0),
        ] {
            for dir in [
                -Vec3::Y,
                Vec3::new(0.0, -1.0, 0.0),
                Vec3::new(-0.0, -1.0, 0.0),
            ] {
                let ray = Ray::new(o, dir);
                let hit = accel.intersect(&ray);
                assert!(hit.is_some_and(|h| (h.t - 1.0).abs() < 1e-6), "{o} {dir:?}");
                assert!(accel.occluded(&ray), "{o} {dir:?}");
            }
        }
    }
}
