//! `penumbra bench --engine raster`: GPU time of every pass of the raster
//! path (shadow maps, forward shading, …) for the same scene lit by 1, 8
//! and 1024 generated point lights (or the scene's own lights), from GPU
//! timestamp queries where the adapter has them, else the wall time of the
//! frame with the device polled until idle.

use anyhow::{Result, bail};
use glam::{Mat4, Vec2, Vec3};
use penumbra_raster::{BakedMaps, ForwardRenderer, GpuContext, PassTiming, RasterOptions};
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
    /// Bakes to show (`--bake`): each light count is then measured without
    /// and with them, in the same run.
    pub bakes: Vec<penumbra_bake::LoadedBake>,
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

/// `count` point lights of finite range just above the scene's surfaces:
/// each at a point drawn in proportion to area (a fixed low-discrepancy
/// sequence, so runs are reproducible), lifted along the face normal by
/// 2 % of the bounds radius R, with range `2.5 R / √count` (so the lights
/// cover about the same total area, and a pixel sees a similar number of
/// lights, at every count) and intensity ∝ range² / count. With many lights
/// most of them reach a small part of the image: what tiled culling is for.
pub fn generated_lights(scene: &Scene, count: u32) -> Vec<SceneLight> {
    let Some((lo, hi)) = scene.bounds() else {
        return Vec::new();
    };
    let radius = (0.5 * (hi - lo).length()).max(1e-3);
    // Every world triangle with its area (prefix sums for the draw).
    let mut triangles = Vec::new();
    let mut cdf = Vec::new();
    let mut total_area = 0.0f64;
    for inst in &scene.instances {
        let mesh = &scene.meshes[inst.mesh];
        for t in &mesh.indices {
            let [a, b, c] = t.map(|i| inst.transform.transform_point3(mesh.positions[i as usize]));
            let n = (b - a).cross(c - a);
            let area = 0.5 * n.length() as f64;
            if area > 0.0 {
                total_area += area;
                triangles.push((a, b, c, n.normalize()));
                cdf.push(total_area);
            }
        }
    }
    if triangles.is_empty() {
        return Vec::new();
    }
    let range = 2.5 * radius / (count as f32).sqrt();
    let lift = (0.02 * radius).min(0.3 * range);
    let intensity = 8.0 * range * range / count as f32;
    let centre = 0.5 * (lo + hi);
    (0..count)
        .map(|i| {
            // Additive recurrences with the plastic constant's powers.
            let u = ((i as f64 + 0.5) * 0.754_877_666_246_692_8).fract();
            let v = ((i as f64 + 0.5) * 0.569_840_290_998_053_3).fract() as f32;
            let w = ((i as f64 + 0.5) * 0.618_033_988_749_894_9).fract() as f32;
            let k = cdf
                .partition_point(|&c| c < u * total_area)
                .min(triangles.len() - 1);
            let (a, b, c, n) = triangles[k];
            let (su, sv) = if v + w > 1.0 {
                (1.0 - v, 1.0 - w)
            } else {
                (v, w)
            };
            let p = a + (b - a) * su + (c - a) * sv;
            // Above the side of the face the camera is more likely to see:
            // away from the bounds' centre for closed objects.
            let up = if n.dot(p - centre) >= 0.0 || n.y > 0.5 {
                n
            } else {
                -n
            };
            SceneLight {
                name: format!("bench light {i}"),
                light: Light::Point(PointLight {
                    range,
                    ..PointLight::new(p + up * lift, Rgb::splat(intensity))
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
    // The warm-up frame also reads the tile lists back (outside the timed
    // frames, whose wall time would include the copy).
    let probe = ForwardRenderer::new(
        &ctx,
        RasterOptions {
            culling_stats: true,
            ..bench.options
        },
    )?;
    let camera = scene_camera(scene);
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
    let with_bakes = BakedMaps::from_bakes(&bench.bakes)?;
    let variants: Vec<(&str, BakedMaps<'_>)> = if bench.bakes.is_empty() {
        vec![("", BakedMaps::default())]
    } else {
        vec![
            ("without bakes", BakedMaps::default()),
            ("with bakes", with_bakes),
        ]
    };
    for &count in &bench.light_counts {
        for (label, maps) in &variants {
            let mut lit = scene.clone();
            if count > 0 {
                lit.lights = generated_lights(scene, count);
            }
            let lights = lit.lights.len();
            let mut frame_ms = Vec::new();
            let mut passes = Vec::new();
            let (w, h) = (bench.width, bench.height);
            // Warm-up: pipeline caches, first-use allocations.
            let culling = probe
                .render_baked(&ctx, &lit, &camera, w, h, maps, false)?
                .culling;
            // The environment prefilter runs once per environment, in this
            // frame: reported apart from the timed frames.
            let prefilter = renderer
                .render_baked(&ctx, &lit, &camera, w, h, maps, false)?
                .passes
                .iter()
                .find(|p| p.name == "environment prefilter")
                .map(|p| p.ms);
            for _ in 0..bench.frames {
                let out = renderer.render_baked(&ctx, &lit, &camera, w, h, maps, false)?;
                frame_ms.push(out.frame_ms);
                passes.push(out.passes);
            }
            let frame = median(&mut frame_ms);
            let kinds = median_by_kind(&passes);
            if bench.json {
                let fields: String = kinds
                    .iter()
                    .map(|(k, n, ms)| {
                        format!(
                            ",\"{k}\":{{\"passes\":{n},\"ms\":{ms:.4},\"ms_each\":{:.4}}}",
                            ms / *n as f64
                        )
                    })
                    .collect();
                let tiles = culling.as_ref().map_or(String::new(), |c| {
                    format!(
                        ",\"lights_per_tile\":{{\"mean\":{:.2},\"max\":{},\"overflowed\":{}}}",
                        c.mean_lights, c.max_lights, c.overflowed
                    )
                });
                let bakes = if label.is_empty() {
                    String::new()
                } else {
                    format!(",\"bakes\":{}", !maps.is_empty())
                };
                let prefilter = prefilter.map_or(String::new(), |ms| {
                    format!(",\"environment_prefilter_once_ms\":{ms:.4}")
                });
                println!(
                    "{{\"lights\":{lights}{bakes},\"frame_ms\":{frame:.4}{fields}{tiles}{prefilter}}}"
                );
            } else {
                let tiles = culling.as_ref().map_or(String::new(), |c| {
                format!(
                    "; tiled culling: {:.1} lights per tile on average (max {}, {} of {} tiles overflowed)",
                    c.mean_lights, c.max_lights, c.overflowed, c.tiles
                )
            });
                let label = if label.is_empty() {
                    String::new()
                } else {
                    format!(", {label}")
                };
                println!(
                    "{lights} light(s){label}: frame {frame:.2} ms (wall, submit to idle){tiles}"
                );
                if let Some(ms) = prefilter {
                    let label = "environment prefilter (once)";
                    println!("  {label:<28} {ms:>10.3} ms");
                }
                for (kind, n, ms) in kinds {
                    if n > 1 {
                        let label = format!("{kind} ×{n}");
                        println!("  {label:<28} {ms:>10.3} ms ({:.3} ms each)", ms / n as f64);
                    } else {
                        println!("  {kind:<28} {ms:>10.3} ms");
                    }
                }
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_lights_sit_above_the_surfaces_within_their_range() {
        let scene = raster_bench_scene(2000);
        let (lo, hi) = scene.bounds().unwrap();
        let radius = 0.5 * (hi - lo).length();
        for count in [1, 8, 1024] {
            let lights = generated_lights(&scene, count);
            assert_eq!(lights.len(), count as usize);
            let mut sum_range2_i = 0.0;
            for (i, l) in lights.iter().enumerate() {
                let Light::Point(p) = l.light else {
                    panic!("not a point light")
                };
                let expect = 2.5 * radius / (count as f32).sqrt();
                assert!((p.range - expect).abs() < 1e-4 * expect);
                // Inside the bounds (lifted a little at most) and distinct.
                let margin = Vec3::splat(0.03 * radius);
                assert!(p.position.cmpge(lo - margin).all() && p.position.cmple(hi + margin).all());
                for other in &lights[..i] {
                    let Light::Point(q) = other.light else {
                        unreachable!()
                    };
                    assert!((q.position - p.position).length() > 1e-4);
                }
                sum_range2_i += p.intensity.x / (p.range * p.range);
            }
            // Intensity ∝ range² / count: the same sum for every count.
            assert!((sum_range2_i - 8.0).abs() < 1e-3 * 8.0, "{sum_range2_i}");
        }
        // The 1024 lights are spread: both the ball and the floor get some.
        let lights = generated_lights(&scene, 1024);
        let on_floor = lights
            .iter()
            .filter(|l| matches!(l.light, Light::Point(p) if p.position.y < -1.0))
            .count();
        assert!(on_floor > 100 && on_floor < 1000, "{on_floor}");
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
