//! 1024 point lights of finite range (glTF's window) over a floor with a
//! few objects: the tiled light culling must give the same image as the
//! loop over every light (bit for bit: a culling bug shows up as seams
//! along tile edges), cull most lights from most tiles, and match the CPU
//! `local` integrator with the same lights (mean HDR-FLIP ≤ 0.02).

mod common;

use glam::{Mat4, Vec3};
use penumbra_image::{Image, ToneMapping, hdr_flip, write_image};
use penumbra_raster::{ForwardRenderer, GpuContext, RasterOptions};
use penumbra_scene::camera::{Camera, Projection};
use penumbra_scene::{IntegratorKind, Material, Scene, SceneLight, primitives};
use penumbra_shading::bsdf::{Bsdf, PhongBlinn, PhongVariant};
use penumbra_shading::light::{Light, PointLight, SpotLight};
use penumbra_trace::{RenderOptions, render};

const RES: u32 = 256;
const LIGHTS: usize = 1024;
const MAX_MEAN_FLIP: f64 = 0.02;

/// A small deterministic generator (SplitMix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn scene() -> Scene {
    let mut s = Scene::default();
    let floor = s.add_material(Material::lambert("floor", Vec3::splat(0.6)));
    let plastic = s.add_material(Material {
        bsdf: Bsdf::PhongBlinn(PhongBlinn::from_albedo(
            Vec3::new(0.6, 0.3, 0.2),
            Vec3::splat(0.2),
            40.0,
            PhongVariant::Normalized,
        )),
        ..Material::lambert("plastic", Vec3::ONE)
    });
    let mut ground = primitives::quad(
        Vec3::new(-6.0, 0.0, 6.0),
        Vec3::new(12.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -12.0),
    );
    ground.material = floor;
    s.add_mesh(ground, Mat4::IDENTITY);
    for (c, r) in [
        (Vec3::new(-2.0, 0.8, 0.0), 0.8),
        (Vec3::new(1.5, 0.6, 1.5), 0.6),
        (Vec3::new(2.0, 1.0, -2.5), 1.0),
    ] {
        let mut m = primitives::sphere(c, r, 24);
        m.material = plastic;
        s.add_mesh(m, Mat4::IDENTITY);
    }
    let mut b = primitives::cuboid(Vec3::new(-3.5, 0.0, -3.5), Vec3::new(-1.5, 1.5, -2.0));
    b.material = floor;
    s.add_mesh(b, Mat4::IDENTITY);
    // A 32 × 32 jittered grid of lights a little above the floor, ranges
    // 0.7–1.5, random colours; every 64th one a spot pointing down.
    let mut rng = Rng(7);
    for i in 0..LIGHTS {
        let (gx, gz) = ((i % 32) as f32, (i / 32) as f32);
        let p = Vec3::new(
            -5.6 + (gx + rng.next()) * 11.2 / 32.0,
            0.25 + 1.2 * rng.next(),
            -5.6 + (gz + rng.next()) * 11.2 / 32.0,
        );
        let colour = Vec3::new(rng.next(), rng.next(), rng.next()) * 0.6 + Vec3::splat(0.1);
        let range = 0.7 + 0.8 * rng.next();
        let light = if i % 64 == 0 {
            Light::Spot(SpotLight {
                position: p + Vec3::Y,
                direction: Vec3::NEG_Y,
                intensity: colour * 2.0,
                cos_inner: 20f32.to_radians().cos(),
                cos_outer: 35f32.to_radians().cos(),
                range: range + 1.0,
            })
        } else {
            Light::Point(PointLight {
                range,
                ..PointLight::new(p, colour)
            })
        };
        s.lights.push(SceneLight {
            name: format!("light {i}"),
            light,
        });
    }
    s
}

fn camera() -> Camera {
    Camera::look_at(
        Vec3::new(0.0, 7.0, 7.5),
        Vec3::new(0.0, 0.0, -0.5),
        Vec3::Y,
        Projection::Perspective {
            fov_y: 55f32.to_radians(),
        },
    )
}

fn raster(ctx: &GpuContext, s: &Scene, msaa: u32, culling: bool) -> penumbra_raster::RasterOutput {
    let options = RasterOptions {
        msaa,
        light_culling: culling,
        culling_stats: culling,
        ..Default::default()
    };
    let r = ForwardRenderer::new(ctx, options).expect("renderer");
    let out = r.render(ctx, s, &camera(), RES, RES).expect("render");
    assert!(out.image.all_finite());
    out
}

fn save(name: &str, img: &Image) {
    if std::env::var_os("PENUMBRA_TEST_IMAGES").is_some() {
        let path = std::env::temp_dir().join(format!("many-lights-{name}.png"));
        write_image(&path, img, &[], &ToneMapping::default()).expect("write");
        eprintln!("wrote {}", path.display());
    }
}

#[test]
fn tiled_culling_is_exact_and_matches_cpu_local_with_1024_lights() {
    let Some(ctx) = common::gpu("tiled_culling_is_exact_and_matches_cpu_local_with_1024_lights")
    else {
        return;
    };
    let s = scene();
    let mut cpu_scene = s.clone();
    cpu_scene.camera = Some(camera());
    let mut settings = cpu_scene.settings.clone();
    (settings.width, settings.height, settings.spp) = (RES, RES, 4);
    settings.integrator = IntegratorKind::Local;
    let cpu = render(&cpu_scene, &settings, &RenderOptions::default())
        .unwrap()
        .image;
    save("cpu-local", &cpu);
    for msaa in [1, 4] {
        let culled = raster(&ctx, &s, msaa, true);
        let all = raster(&ctx, &s, msaa, false);
        save(&format!("culled-msaa{msaa}"), &culled.image);
        let stats = culled.culling.clone().expect("culling stats");
        // Same image with and without culling: no seams, nothing dropped.
        let mut worst = 0.0f32;
        let mut differing = 0;
        for (a, b) in culled.image.pixels.iter().zip(&all.image.pixels) {
            let d = (*a - *b).abs().max_element() / b.max_element().max(1e-3);
            if d > 0.0 {
                differing += 1;
            }
            worst = worst.max(d);
        }
        let (flip, _) = hdr_flip(&cpu, &culled.image).expect("flip");
        let mean = |img: &Image| {
            img.pixels.iter().map(|p| p.element_sum()).sum::<f32>() / img.pixels.len() as f32
        };
        eprintln!(
            "MSAA {msaa}: {} tiles, mean {:.1} lights per tile (max {}, {} overflowed) of {}; culled vs all lights: {differing} pixels differ, worst relative {worst:.2e}; mean HDR-FLIP vs CPU local {flip:.4}; mean radiance raster {:.4} CPU {:.4}",
            stats.tiles,
            stats.mean_lights,
            stats.max_lights,
            stats.overflowed,
            stats.lights,
            mean(&culled.image),
            mean(&cpu),
        );
        assert!(mean(&cpu) > 0.01, "the lights light nothing");
        assert_eq!(stats.lights as usize, LIGHTS);
        assert_eq!(stats.overflowed, 0);
        assert!(
            stats.mean_lights < LIGHTS as f64 / 20.0,
            "culling keeps {:.1} lights per tile",
            stats.mean_lights
        );
        if msaa == 1 {
            assert_eq!(
                differing, 0,
                "culling changed {differing} pixels (worst {worst})"
            );
        } else {
            // Multisampled edge pixels shade at the pixel centre, which may
            // lie off the triangle, beyond the tile's sampled depth bounds.
            assert!(
                worst < 1e-3 && differing < (RES * RES / 200) as usize,
                "{differing} {worst}"
            );
        }
        assert!(flip <= MAX_MEAN_FLIP, "MSAA {msaa}: mean FLIP {flip:.4}");
    }
}

/// A light whose range does not reach the view is culled from every tile;
/// lights without a range are in every tile's list.
#[test]
fn lists_hold_exactly_what_can_reach_the_tile() {
    let Some(ctx) = common::gpu("lists_hold_exactly_what_can_reach_the_tile") else {
        return;
    };
    let mut s = scene();
    s.lights.truncate(2);
    // Far away with a short range: reaches nothing.
    s.lights.push(SceneLight {
        name: "far".into(),
        light: Light::Point(PointLight {
            range: 1.0,
            ..PointLight::new(Vec3::new(40.0, 1.0, 0.0), Vec3::ONE)
        }),
    });
    // Everywhere.
    s.lights.push(SceneLight {
        name: "unbounded".into(),
        light: Light::Point(PointLight::new(Vec3::new(0.0, 4.0, 0.0), Vec3::ONE)),
    });
    let out = raster(&ctx, &s, 1, true);
    let stats = out.culling.unwrap();
    eprintln!("{stats:?}");
    // Every tile with geometry holds the unbounded light, the far light
    // none; the first two reach few tiles.
    let per_lit_tile = stats.mean_lights * stats.tiles as f64 / stats.tiles_with_lights as f64;
    assert!(stats.tiles_with_lights > stats.tiles / 2, "{stats:?}");
    assert!((1.0..1.5).contains(&per_lit_tile), "{stats:?}");
    assert!(stats.max_lights <= 3, "{stats:?}");
}
