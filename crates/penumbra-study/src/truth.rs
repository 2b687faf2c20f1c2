//! The truths rows are judged against: full global illumination (`path`,
//! or a reference EXR the user gives), direct light (`direct`) and
//! ray-traced ambient occlusion (`ao`). Each is rendered until a target
//! relMSE, estimated from the film's variance, or a number of samples per
//! pixel, within an optional time budget; its own remaining noise is
//! reported so no technique is judged against noise.

use penumbra_image::Image;
use penumbra_image::noise_rel_mse;
use penumbra_scene::{IntegratorKind, RenderSettings, Scene};
use penumbra_trace::{RenderOptions, SceneTooLarge, render};
use std::time::{Duration, Instant};

/// When a truth is good enough.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// A fixed number of samples per pixel.
    Spp(u32),
    /// The expected relMSE of the image against its own converged limit.
    RelMse(f64),
}

/// Samples of the first pass of a relMSE target, from which the remaining
/// count is predicted (relMSE ∝ 1/spp).
pub const PILOT_SPP: u32 = 16;
/// Most samples per pixel a relMSE target may ask for.
pub const MAX_SPP: u32 = 1 << 16;
/// Most rounds of prediction and rendering after the pilot.
const MAX_ROUNDS: u32 = 6;

/// A converged (or budget-limited) render.
#[derive(Clone, Debug)]
pub struct Converged {
    pub image: Image,
    pub variance: Image,
    pub spp: u32,
    /// Render time, BVH builds excluded [s].
    pub seconds: f64,
    /// Whether the time budget stopped it before the target.
    pub stopped_by_budget: bool,
}

impl Converged {
    /// The remaining noise as relMSE.
    pub fn noise(&self) -> f64 {
        noise_rel_mse(&self.image, &self.variance)
    }

    /// Render time per sample per pixel [s].
    pub fn seconds_per_spp(&self) -> f64 {
        self.seconds / f64::from(self.spp.max(1))
    }
}

/// Renders `integrator` until `target` or `budget` seconds.
pub fn converge(
    scene: &Scene,
    base: &RenderSettings,
    integrator: IntegratorKind,
    target: Target,
    budget: Option<f64>,
) -> Result<Converged, SceneTooLarge> {
    let start = Instant::now();
    let pass = |spp: u32, seed: u32, limit: Option<f64>| {
        let settings = RenderSettings {
            integrator,
            spp,
            seed,
            ..base.clone()
        };
        let options = RenderOptions {
            time_limit: limit.map(|s| Duration::from_secs_f64(s.max(0.0))),
            ..Default::default()
        };
        render(scene, &settings, &options)
    };
    let remaining = |start: Instant| budget.map(|b| b - start.elapsed().as_secs_f64());
    match target {
        Target::Spp(n) => {
            let out = pass(n, base.seed, budget)?;
            Ok(Converged {
                stopped_by_budget: out.spp < n,
                image: out.image,
                variance: out.variance,
                spp: out.spp,
                seconds: out.render_seconds,
            })
        }
        Target::RelMse(goal) => {
            let first = pass(PILOT_SPP, base.seed, budget)?;
            let mut c = Converged {
                stopped_by_budget: first.spp < PILOT_SPP,
                image: first.image,
                variance: first.variance,
                spp: first.spp,
                seconds: first.render_seconds,
            };
            // relMSE ∝ 1/spp predicts the samples still needed; the pilot's
            // variance misses rare paths (it grows as they appear), so
            // predict again after each round.
            for round in 1..=MAX_ROUNDS {
                let noise = c.noise();
                if c.stopped_by_budget || noise <= goal || c.spp >= MAX_SPP {
                    break;
                }
                let needed = (f64::from(c.spp) * noise / goal)
                    .ceil()
                    .min(f64::from(MAX_SPP)) as u32;
                let more = needed.saturating_sub(c.spp).max(c.spp / 4).max(1);
                let limit = remaining(start);
                if limit.is_some_and(|l| l <= 0.0) {
                    c.stopped_by_budget = true;
                    break;
                }
                // Independent samples: another seed decorrelates the sampler.
                let seed = base.seed.wrapping_add(0x9e37_79b9u32.wrapping_mul(round));
                let next = pass(more, seed, limit)?;
                c.stopped_by_budget = next.spp < more;
                merge(&mut c, &next.image, &next.variance, next.spp);
                c.seconds += next.render_seconds;
            }
            Ok(c)
        }
    }
}

/// Pools two independent estimates of the same pixels, weighted by their
/// sample counts: `m = (n₁m₁ + n₂m₂)/(n₁+n₂)`, and for the variance of the
/// mean `v = (n₁²v₁ + n₂²v₂)/(n₁+n₂)²`.
fn merge(into: &mut Converged, image: &Image, variance: &Image, spp: u32) {
    let (n1, n2) = (into.spp as f32, spp as f32);
    let n = n1 + n2;
    for (m, m2) in into.image.pixels.iter_mut().zip(&image.pixels) {
        *m = (*m * n1 + *m2 * n2) / n;
    }
    for (v, v2) in into.variance.pixels.iter_mut().zip(&variance.pixels) {
        *v = (*v * (n1 * n1) + *v2 * (n2 * n2)) / (n * n);
    }
    into.spp += spp;
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_image::Rgb;

    #[test]
    fn pooled_estimates() {
        let mut a = Converged {
            image: Image::filled(1, 1, Rgb::splat(1.0)),
            variance: Image::filled(1, 1, Rgb::splat(0.4)),
            spp: 1,
            seconds: 0.0,
            stopped_by_budget: false,
        };
        merge(
            &mut a,
            &Image::filled(1, 1, Rgb::splat(4.0)),
            &Image::filled(1, 1, Rgb::splat(0.1)),
            3,
        );
        // m = (1 + 12)/4; v = (0.4 + 9 · 0.1)/16.
        assert_eq!(a.spp, 4);
        assert!((a.image.pixels[0][0] - 3.25).abs() < 1e-6);
        assert!((a.variance.pixels[0][0] - 1.3 / 16.0).abs() < 1e-7);
    }

    #[test]
    fn a_relmse_target_is_reached() {
        let mut scene = penumbra_scene::builtin::cornell_box();
        scene.settings.width = 24;
        scene.settings.height = 24;
        scene.settings.max_depth = 3;
        let goal = 0.002;
        let c = converge(
            &scene,
            &scene.settings,
            IntegratorKind::Path,
            Target::RelMse(goal),
            None,
        )
        .unwrap();
        assert!(!c.stopped_by_budget);
        assert!(c.spp > PILOT_SPP, "{} spp", c.spp);
        // The prediction assumes relMSE ∝ 1/spp; allow its own noise.
        assert!(
            c.noise() < 1.5 * goal,
            "noise {} after {} spp",
            c.noise(),
            c.spp
        );
    }

    /// A scene of 2²⁷ triangles (a 2²⁰-triangle mesh placed 128 times),
    /// one more than the BVH holds: the truth render is an error, not a
    /// panic.
    #[test]
    fn a_scene_past_the_bvh_limit_is_an_error() {
        let mut scene = penumbra_scene::Scene::default();
        let mesh = penumbra_scene::Mesh {
            positions: vec![glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Y],
            indices: vec![[0, 1, 2]; 1 << 20],
            ..Default::default()
        };
        scene.add_mesh(mesh, glam::Mat4::IDENTITY);
        scene.instances.resize(128, scene.instances[0].clone());
        let settings = scene.settings.clone();
        let err = converge(
            &scene,
            &settings,
            IntegratorKind::Path,
            Target::Spp(1),
            None,
        )
        .err();
        assert_eq!(err.map(|e| e.triangles), Some(1 << 27));
    }
}
