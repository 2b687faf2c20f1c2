//! `penumbra bench --engine raster`: GPU time of every pass of the raster
//! path (shadow maps, forward shading, …) for the same scene lit by 1, 8
//! and 1024 generated point lights (or the scene's own lights), from GPU
//! timestamp queries where the adapter has them, else the wall time of the
//! frame with the device polled until idle.

use anyhow::{Result, bail};
use glam::{Mat4, Vec2, Vec3};
use penumbra_raster::{ForwardRenderer, GpuContext, PassTiming, RasterOptions};
use penumbra_scene::{Camera, Material, Projection, Scene, SceneLight, primitives};
use penumbra_shading::Rgb;
use penumbra_shading::light::{Light, PointLight};
use penumbra_trace::bench::bench_mesh;
use penumbra_trace::scene_camera;

/// What one raster benchmark measures.
#[derive(Clone, Debug)]
pub struct RasterBench {
    pub width: u32,
    pub height: u32,
    /// Light counts to measure; 0 = the scene's own lights.
    pub light_counts: Vec<u32>,
    /// Timed frames per light count (after one untimed warm-up frame).
    pub frames: u32,
    pub options: RasterOptions,
    pub json: bool,
}

/// The generated raster bench scene: the bumpy bench sphere (radius ≈ 1,
/// `triangles` triangles) above a floor, grey Lambert, seen from a camera
/// that it fills most of.
pub fn raster_bench_scene(triangles: usize) -> Scene {
    let mut scene = Scene::default();
    let grey = scene.add_material(Material::lambert("grey", Rgb::splat(0.7)));
    let mut ball = bench_mesh(triangles);
    ball.material = grey;
    scene.add_mesh(ball, Mat4::IDENTITY);
    let mut floor = primitives::rectangle(Vec3::new(0.0, -1.2, 0.0), Vec2::splat(8.0));
    floor.material = grey;
    scene.add_mesh(floor, Mat4::IDENTITY);
    scene.background = Rgb::splat(0.05);
    // The ball fills most of a 16:9 frame, the floor the rest.
    scene.camera = Some(Camera::look_at(
        Vec3::new(0.0, 0.9, 3.6),
        Vec3::new(0.0, -0.15, 0.0),
        Vec3::Y,
        Projection::Perspective {
            fov_y: 40f32.to_radians(),
        },
    ));
    scene
}

/// `count` point lights spread evenly (a Fibonacci spiral) over the upper
/// part of a shell of radius 1.6 r around the bounds' centre (r = bounds
/// radius / 2), with a total intensity that does not depend on `count`.
pub fn generated_lights(bounds: (Vec3, Vec3), count: u32) -> Vec<SceneLight> {
    let (lo, hi) = bounds;
    let centre = 0.5 * (lo + hi);
    let r = 0.25 * (hi - lo).length().max(1e-3);
    let total = 8.0 * r * r;
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..count)
        .map(|i| {
            // Heights from 0.95 down to -0.2 of the shell radius.
            let t = (i as f32 + 0.5) / count as f32;
            let y = 0.95 - 1.15 * t;
            let ring = (1.0 - y * y).max(0.0).sqrt();
            let phi = golden * i as f32;
            let dir = Vec3::new(ring * phi.cos(), y, ring * phi.sin());
            SceneLight {
                name: format!("bench light {i}"),
                light: Light::Point(PointLight {
                    position: centre + 1.6 * r * dir,
                    intensity: Rgb::splat(total / count as f32),
                    range: f32::INFINITY,
                }),
            }
        })
        .collect()
}

/// Per pass kind, the median over frames of its total GPU time [ms].
fn median_by_kind(frames: &[Vec<PassTiming>]) -> Vec<(String, usize, f64)> {
    let mut kinds: Vec<(String, usize, Vec<f64>)> = Vec::new();
    for f in frames {
        for (kind, n, ms) in penumbra_raster::timing::by_kind(f) {
            match kinds.iter_mut().find(|k| k.0 == kind) {
                Some(k) => k.2.push(ms),
                None => kinds.push((kind, n, vec![ms])),
            }
        }
    }
    kinds
        .into_iter()
        .map(|(kind, n, mut v)| (kind, n, median(&mut v)))
        .collect()
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        f64::NAN
    } else {
        v[v.len() / 2]
    }
}

pub fn run(bench: &RasterBench, scene: &Scene) -> Result<()> {
    if scene.triangle_count() == 0 {
        bail!("the scene has no triangles to benchmark");
    }
    let ctx = GpuContext::new()?;
    let renderer = ForwardRenderer::new(&ctx, bench.options)?;
    let camera = scene_camera(scene);
    let bounds = scene
        .bounds()
        .unwrap_or((Vec3::splat(-1.0), Vec3::splat(1.0)));
    let timestamps = ctx
        .device
        .features()
        .contains(penumbra_raster::wgpu::Features::TIMESTAMP_QUERY);
    if !bench.json {
        println!(
            "penumbra bench --engine raster: {} | {}x{} MSAA {} | shadows {:?} | {} triangles | {} frames each | {}",
            ctx.summary,
            bench.width,
            bench.height,
            bench.options.msaa,
            bench.options.shadows,
            scene.triangle_count(),
            bench.frames,
            if timestamps {
                "GPU timestamps"
            } else {
                "no timestamp queries: wall time per frame only"
            }
        );
    }
    for &count in &bench.light_counts {
        let mut lit = scene.clone();
        if count > 0 {
            lit.lights = generated_lights(bounds, count);
        }
        let lights = lit.lights.len();
        let mut frame_ms = Vec::new();
        let mut passes = Vec::new();
        for frame in 0..=bench.frames {
            let out = renderer.render(&ctx, &lit, &camera, bench.width, bench.height)?;
            if frame == 0 {
                continue; // warm-up: pipeline caches, first-use allocations
            }
            frame_ms.push(out.frame_ms);
            passes.push(out.passes);
        }
        let frame = median(&mut frame_ms);
        let kinds = median_by_kind(&passes);
        if bench.json {
            let fields: String = kinds
                .iter()
                .map(|(k, n, ms)| format!(",\"{k}\":{{\"passes\":{n},\"ms\":{ms:.4}}}"))
                .collect();
            println!("{{\"lights\":{lights},\"frame_ms\":{frame:.4}{fields}}}");
        } else {
            println!("{lights} light(s): frame {frame:.2} ms (wall, submit to idle)");
            for (kind, n, ms) in kinds {
                let label = if n > 1 { format!("{kind} ×{n}") } else { kind };
                println!("  {label:<28} {ms:>10.3} ms");
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_lights_are_distinct_share_the_intensity_and_stay_outside_the_ball() {
        let bounds = (Vec3::splat(-1.0), Vec3::splat(1.0));
        for count in [1, 8, 1024] {
            let lights = generated_lights(bounds, count);
            assert_eq!(lights.len(), count as usize);
            let mut total = 0.0;
            for (i, l) in lights.iter().enumerate() {
                let Light::Point(p) = l.light else {
                    panic!("not a point light")
                };
                total += p.intensity.x;
                // r = √12 / 4 ≈ 0.866: the shell is at 1.39 from the centre.
                assert!((p.position.length() - 1.6 * 0.75f32.sqrt()).abs() < 1e-4);
                for other in &lights[..i] {
                    let Light::Point(q) = other.light else {
                        unreachable!()
                    };
                    assert!((q.position - p.position).length() > 1e-3);
                }
            }
            assert!((total - 6.0).abs() < 1e-3 * 6.0, "{total}");
        }
    }

    #[test]
    fn median_takes_the_middle_frame_of_each_kind() {
        let p = |name: &str, ms| PassTiming {
            name: name.into(),
            ms,
        };
        let frames = vec![
            vec![
                p("shadow map 0", 1.0),
                p("shadow map 1", 1.0),
                p("forward", 9.0),
            ],
            vec![
                p("shadow map 0", 5.0),
                p("shadow map 1", 5.0),
                p("forward", 3.0),
            ],
            vec![
                p("shadow map 0", 2.0),
                p("shadow map 1", 2.0),
                p("forward", 4.0),
            ],
        ];
        assert_eq!(
            median_by_kind(&frames),
            [
                ("shadow map".to_string(), 2, 4.0),
                ("forward".to_string(), 1, 4.0)
            ]
        );
    }
}
