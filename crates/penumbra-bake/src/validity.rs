//! Texels inside geometry: a texel whose point lies inside a wall or under
//! another surface sees the back faces of what surrounds it. Such texels
//! are never seen from outside; their baked values would be dark and leak
//! into their visible neighbours through bilinear lookups, so they are
//! marked invalid and filled by dilation instead.
//!
//! Test: [`VALIDITY_RAYS`] cosine-distributed rays from the texel's point
//! (front side), closest hit each; the texel is invalid when more than
//! [`BACKFACE_LIMIT`] of them hit a triangle from its back (the side
//! opposite its geometric normal, whatever the material).

use crate::texels::Texels;
use penumbra_scene::Scene;
use penumbra_shading::Frame;
use penumbra_shading::sampling::{Sampler, square_to_cosine_hemisphere};
use penumbra_trace::geometry::SceneGeometry;
use penumbra_trace::ray::{Ray, offset_ray_origin};
use rayon::prelude::*;

/// Rays per texel of the validity test.
pub const VALIDITY_RAYS: u32 = 64;

/// Fraction of back-face hits above which a texel is invalid (Unity's
/// light baker uses the same rule with its "backface tolerance" 0.9).
pub const BACKFACE_LIMIT: f32 = 0.1;

/// Per texel (in `texels` order): its fraction of back-face hits.
pub fn backface_fractions(scene: &Scene, geometry: &SceneGeometry, texels: &Texels) -> Vec<f32> {
    let h = texels.height;
    texels
        .texels
        .par_iter()
        .map(|t| {
            let hit = geometry.surface_point(scene, t.triangle, t.b1, t.b2);
            let frame = Frame::from_normal(hit.ng);
            let origin = offset_ray_origin(hit.p, hit.ng);
            let mut back = 0u32;
            // A seed apart from the bakes' own (their samplers use seed 0
            // and up) so the test and the estimate are independent.
            let mut sampler = Sampler::for_pixel(t.x, t.y + t.page * h, 0x5eed_ba6e);
            for s in 0..VALIDITY_RAYS {
                sampler.start_sample(s);
                let d = frame.to_world(square_to_cosine_hemisphere(sampler.next_2d()));
                if let Some(h) = geometry.intersect(scene, &Ray::new(origin, d))
                    && h.light.is_none()
                    && h.ng.dot(d) > 0.0
                {
                    back += 1;
                }
            }
            back as f32 / VALIDITY_RAYS as f32
        })
        .collect()
}
