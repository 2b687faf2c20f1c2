//! Raster against the CPU `local` integrator (same model: every abstract
//! light, no shadows): mean HDR-FLIP ≤ 0.02 on the spheres-direct reference
//! scene (a point and a directional light) and on a scene built here with a
//! point, a directional and a spot light and every Phong–Blinn variant,
//! through a perspective and an orthographic camera.

mod common;

use glam::{Mat4, Vec3};
use penumbra_image::{Image, ToneMapping, hdr_flip, write_image};
use penumbra_raster::{ForwardRenderer, GpuContext, RasterOptions};
use penumbra_scene::camera::{Camera, Projection};
use penumbra_scene::{
    IntegratorKind, LoadOptions, Material, Scene, SceneLight, load_scene, primitives,
};
use penumbra_shading::bsdf::{Bsdf, PhongBlinn, PhongVariant};
use penumbra_shading::light::{DirectionalLight, Light, PointLight, SpotLight};
use penumbra_trace::{RenderOptions, render, scene_camera};

const MAX_MEAN_FLIP: f64 = 0.02;

fn cpu_local(scene: &Scene, camera: Camera, width: u32, height: u32, spp: u32) -> Image {
    let mut scene = scene.clone();
    scene.camera = Some(camera);
    let mut settings = scene.settings.clone();
    settings.width = width;
    settings.height = height;
    settings.spp = spp;
    settings.integrator = IntegratorKind::Local;
    render(&scene, &settings, &RenderOptions::default())
        .unwrap()
        .image
}

fn luminance_stats(img: &Image) -> (f32, f32) {
    let lum = |p: Vec3| 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z;
    let covered = img.pixels.iter().filter(|p| lum(**p) > 1e-4).count();
    (
        img.pixels.iter().map(|p| lum(*p)).sum::<f32>() / img.pixels.len() as f32,
        covered as f32 / img.pixels.len() as f32,
    )
}

/// Renders both ways and returns the mean FLIP (after checking that the
/// image has content, so that two black images cannot pass), at MSAA 1 and 4.
fn parity(ctx: &GpuContext, name: &str, scene: &Scene, camera: Camera, size: u32) -> f64 {
    parity_at(ctx, name, scene, camera, size, &[1, 4])
}

/// [`parity`] at the given MSAA sample counts.
fn parity_at(
    ctx: &GpuContext,
    name: &str,
    scene: &Scene,
    camera: Camera,
    size: u32,
    samples: &[u32],
) -> f64 {
    let cpu = cpu_local(scene, camera, size, size, 16);
    let mut best = f64::INFINITY;
    for &msaa in samples {
        let renderer = match ForwardRenderer::new(
            ctx,
            RasterOptions {
                msaa,
                ..Default::default()
            },
        ) {
            Ok(r) => r,
            // Every adapter wgpu accepts supports 4× MSAA of the formats
            // used: a renderer that cannot be created is a failure.
            Err(e) => panic!("{name}: MSAA {msaa}: {e}"),
        };
        let out = renderer
            .render(ctx, scene, &camera, size, size)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let (mean, covered) = luminance_stats(&out.image);
        let (cpu_mean, _) = luminance_stats(&cpu);
        assert!(out.image.all_finite(), "{name}: non-finite raster pixels");
        assert!(
            covered > 0.3 && mean > 0.01,
            "{name}: raster image nearly empty (mean {mean}, covered {covered})"
        );
        let (flip, _) = hdr_flip(&cpu, &out.image).expect("flip");
        eprintln!(
            "{name}: {size}x{size} MSAA {msaa}: mean HDR-FLIP {flip:.4}, mean luminance raster {mean:.4} vs CPU {cpu_mean:.4}, frame {:.1} ms",
            out.frame_ms
        );
        if flip > MAX_MEAN_FLIP || std::env::var_os("PENUMBRA_TEST_IMAGES").is_some() {
            let dir = std::env::temp_dir();
            let stem = name.replace(' ', "-");
            let tm = ToneMapping::default();
            for (what, img) in [("cpu", &cpu), ("raster", &out.image)] {
                let path = dir.join(format!("{stem}-msaa{msaa}-{what}.png"));
                write_image(&path, img, &[], &tm).expect("write");
                eprintln!("{name}: wrote {}", path.display());
            }
        }
        assert!(
            flip <= MAX_MEAN_FLIP,
            "{name} MSAA {msaa}: mean HDR-FLIP {flip:.4} > {MAX_MEAN_FLIP}"
        );
        best = best.min(flip);
    }
    best
}

#[test]
fn spheres_direct_matches_cpu_local() {
    let Some(ctx) = common::gpu("spheres_direct_matches_cpu_local") else {
        return;
    };
    let path = common::reference_dir("spheres-direct").join("spheres-direct.gltf");
    let scene = load_scene(&path, &LoadOptions::default()).expect("load spheres-direct");
    assert!(
        scene.lights.len() >= 2 && scene.area_lights.is_empty(),
        "spheres-direct changed: {} lights, {} area lights",
        scene.lights.len(),
        scene.area_lights.len()
    );
    let camera = scene_camera(&scene);
    parity(&ctx, "spheres-direct", &scene, camera, 256);
}

/// A ground wider than the views (no long aliased edge against the black
/// background: the raster path takes one sample per pixel, the CPU 16) and four spheres (Lambert and three Phong–Blinn variants, one
/// single-sided), a point, a directional and a spot light.
fn lights_scene() -> Scene {
    let mut scene = Scene::default();
    let ground = scene.add_material(Material::lambert("ground", Vec3::new(0.6, 0.6, 0.55)));
    let mut g = primitives::quad(
        Vec3::new(-20.0, 0.0, 20.0),
        Vec3::new(40.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -40.0),
    );
    g.material = ground;
    scene.add_mesh(g, Mat4::IDENTITY);
    let phong = |name: &str, albedo: Vec3, v: PhongVariant, ks: f32, shininess: f32| Material {
        bsdf: Bsdf::PhongBlinn(PhongBlinn::from_albedo(
            albedo,
            Vec3::splat(ks),
            shininess,
            v,
        )),
        ..Material::lambert(name, albedo)
    };
    let mats = [
        Material::lambert("lambert", Vec3::new(0.8, 0.2, 0.1)),
        phong(
            "normalized",
            Vec3::new(0.1, 0.6, 0.2),
            PhongVariant::Normalized,
            0.3,
            40.0,
        ),
        phong(
            "max-blinn",
            Vec3::new(0.15, 0.3, 0.8),
            PhongVariant::MaxBlinn,
            0.4,
            20.0,
        ),
        Material {
            double_sided: false,
            ..phong(
                "halfway",
                Vec3::new(0.7, 0.6, 0.2),
                PhongVariant::HalfwaySquared,
                0.5,
                60.0,
            )
        },
    ];
    for (i, m) in mats.into_iter().enumerate() {
        let id = scene.add_material(m);
        let mut s = primitives::sphere(Vec3::ZERO, 1.0, 24);
        s.material = id;
        let x = -3.3 + 2.2 * i as f32;
        // Non-uniform scale and a rotation: normals through the inverse transpose.
        let t = Mat4::from_translation(Vec3::new(x, 0.9, 0.2 * i as f32))
            * Mat4::from_rotation_y(0.3 * i as f32)
            * Mat4::from_scale(Vec3::new(0.9, 0.9 + 0.05 * i as f32, 0.9));
        scene.add_mesh(s, t);
    }
    let light = |name: &str, light| SceneLight {
        name: name.into(),
        light,
    };
    scene.lights = vec![
        light(
            "point",
            Light::Point(PointLight {
                position: Vec3::new(-2.0, 4.0, 3.0),
                intensity: Vec3::new(12.0, 11.0, 10.0),
                range: f32::INFINITY,
            }),
        ),
        light(
            "sun",
            Light::Directional(DirectionalLight {
                direction: Vec3::new(0.4, -1.0, -0.3).normalize(),
                irradiance: Vec3::new(0.5, 0.55, 0.7),
            }),
        ),
        light(
            "spot",
            Light::Spot(SpotLight {
                position: Vec3::new(2.5, 5.0, 2.0),
                direction: (Vec3::new(1.0, 0.5, 0.0) - Vec3::new(2.5, 5.0, 2.0)).normalize(),
                intensity: Vec3::new(40.0, 30.0, 20.0),
                cos_inner: 25f32.to_radians().cos(),
                cos_outer: 40f32.to_radians().cos(),
                range: f32::INFINITY,
            }),
        ),
    ];
    scene
}

#[test]
fn point_directional_spot_and_phong_match_cpu_local() {
    let Some(ctx) = common::gpu("point_directional_spot_and_phong_match_cpu_local") else {
        return;
    };
    let scene = lights_scene();
    let eye = Vec3::new(0.5, 4.0, 9.0);
    let target = Vec3::new(0.0, 0.7, 0.0);
    let persp = Camera::look_at(
        eye,
        target,
        Vec3::Y,
        Projection::Perspective {
            fov_y: 45f32.to_radians(),
        },
    );
    parity(&ctx, "lights perspective", &scene, persp, 256);
    let ortho = Camera::look_at(
        eye,
        target,
        Vec3::Y,
        Projection::Orthographic { height: 7.0 },
    );
    parity(&ctx, "lights orthographic", &scene, ortho, 256);
}

/// Indices of the pixels whose whole 3 × 3 neighbourhood satisfies `keep`
/// (away from silhouettes, which the CPU anti-aliases).
fn interior_pixels(img: &Image, keep: impl Fn(Vec3) -> bool) -> Vec<usize> {
    let (w, h) = (img.width as usize, img.height as usize);
    let mut out = Vec::new();
    for y in 1..h.saturating_sub(1) {
        for x in 1..w.saturating_sub(1) {
            let inside =
                (y - 1..=y + 1).all(|v| (x - 1..=x + 1).all(|u| keep(img.pixels[v * w + u])));
            if inside {
                out.push(y * w + x);
            }
        }
    }
    out
}

/// Area lights shade as their far fields: a sphere light that every point
/// of a Lambertian floor sees whole gives the exact irradiance (per pixel
/// within the CPU's noise), a small disk far from the floor within a few
/// per cent; both emitters are drawn, and the images agree by FLIP.
#[test]
fn area_lights_shade_as_far_field_point_lights() {
    let Some(ctx) = common::gpu("area_lights_shade_as_far_field_point_lights") else {
        return;
    };
    use penumbra_scene::SceneAreaLight;
    use penumbra_shading::light::{AreaLight, Shape};
    for (name, shape, two_sided, tolerance) in [
        (
            "sphere",
            Shape::Sphere {
                center: Vec3::new(0.5, 2.5, -0.5),
                radius: 0.4,
            },
            false,
            0.03,
        ),
        (
            "disk",
            Shape::Disk {
                center: Vec3::new(-0.5, 3.0, 0.0),
                normal: Vec3::new(0.2, -1.0, 0.6).normalize(),
                radius: 0.25,
            },
            true,
            0.05,
        ),
    ] {
        let mut scene = Scene::default();
        let floor = scene.add_material(Material::lambert("floor", Vec3::splat(0.7)));
        let mut g = primitives::quad(
            Vec3::new(-4.0, 0.0, 4.0),
            Vec3::new(8.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, -8.0),
        );
        g.material = floor;
        scene.add_mesh(g, Mat4::IDENTITY);
        scene.area_lights.push(SceneAreaLight {
            name: name.into(),
            light: AreaLight {
                shape,
                radiance: Vec3::new(6.0, 5.0, 4.0),
                two_sided,
            },
        });
        let camera = Camera::look_at(
            Vec3::new(0.0, 4.0, 6.0),
            Vec3::new(0.0, 0.8, 0.0),
            Vec3::Y,
            Projection::Perspective {
                fov_y: 50f32.to_radians(),
            },
        );
        let size = 128;
        let cpu = cpu_local(&scene, camera, size, size, 64);
        let r = ForwardRenderer::new(&ctx, RasterOptions::default()).expect("renderer");
        let out = r.render(&ctx, &scene, &camera, size, size).expect("render");
        assert!(out.warnings.iter().any(|w| w.contains("far-field")));
        // Floor pixels whose 3 × 3 neighbourhood is all floor in the CPU
        // image (neither background, 0, nor the emitter, > 3).
        let floor_like = |p: Vec3| p.max_element() > 1e-4 && p.max_element() < 3.0;
        let floor = interior_pixels(&cpu, floor_like);
        let floor_pixels = floor.len();
        let worst = floor
            .iter()
            .map(|&i| ((out.image.pixels[i] - cpu.pixels[i]).abs() / cpu.pixels[i]).max_element())
            .fold(0.0f32, f32::max);
        // The emitter itself, in both images.
        let emitter_pixels = cpu
            .pixels
            .iter()
            .zip(&out.image.pixels)
            .filter(|(c, g)| c.max_element() > 3.0 && g.max_element() > 3.0)
            .count();
        let (flip, _) = hdr_flip(&cpu, &out.image).expect("flip");
        eprintln!(
            "{name} light: {floor_pixels} floor pixels, worst relative difference {worst:.4}; {emitter_pixels} emitter pixels; mean HDR-FLIP {flip:.4}"
        );
        assert!(floor_pixels > (size * size / 3) as usize && emitter_pixels > 20);
        assert!(worst <= tolerance, "{name}: {worst}");
        assert!(flip <= MAX_MEAN_FLIP, "{name}: FLIP {flip}");
    }
}

/// A constant environment lights a Lambertian scene as ambient light: the
/// CPU `local` integrator's unoccluded environment light gives ρ·Le, which
/// the raster path adds exactly (means over the floor and the sphere within
/// 0.5 %; measured 0.07 %, the CPU's own noise).
#[test]
fn a_constant_environment_is_ambient_light() {
    let Some(ctx) = common::gpu("a_constant_environment_is_ambient_light") else {
        return;
    };
    let mut scene = Scene::default();
    let floor = scene.add_material(Material::lambert("floor", Vec3::new(0.7, 0.5, 0.3)));
    let ball = scene.add_material(Material::lambert("ball", Vec3::new(0.2, 0.4, 0.8)));
    let mut g = primitives::quad(
        Vec3::new(-4.0, 0.0, 4.0),
        Vec3::new(8.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -8.0),
    );
    g.material = floor;
    scene.add_mesh(g, Mat4::IDENTITY);
    let mut s = primitives::sphere(Vec3::new(0.0, 1.0, 0.0), 1.0, 24);
    s.material = ball;
    scene.add_mesh(s, Mat4::IDENTITY);
    scene.background = Vec3::new(0.5, 0.6, 0.7);
    let camera = Camera::look_at(
        Vec3::new(0.0, 2.0, 5.0),
        Vec3::new(0.0, 0.6, 0.0),
        Vec3::Y,
        Projection::Perspective {
            fov_y: 50f32.to_radians(),
        },
    );
    let size = 64;
    let cpu = cpu_local(&scene, camera, size, size, 1024);
    let r = ForwardRenderer::new(&ctx, RasterOptions::default()).expect("renderer");
    let out = r.render(&ctx, &scene, &camera, size, size).expect("render");
    // Group pixels by what the raster image shows: ρ_floor·Le, ρ_ball·Le
    // or the background, exactly.
    let floor_value = Vec3::new(0.7, 0.5, 0.3) * scene.background;
    let ball_value = Vec3::new(0.2, 0.4, 0.8) * scene.background;
    for (what, value) in [("floor", floor_value), ("ball", ball_value)] {
        // Pixels whose 3 × 3 neighbourhood shows the same surface (the CPU
        // anti-aliases silhouettes).
        let same = interior_pixels(&out.image, |p| (p - value).abs().max_element() < 1e-5);
        let n = same.len();
        let sum_cpu: Vec3 = same.iter().map(|&i| cpu.pixels[i]).sum();
        let mean = sum_cpu / n.max(1) as f32;
        let err = ((mean - value).abs() / value).max_element();
        eprintln!("{what}: {n} pixels, raster {value}, CPU mean {mean}, relative {err:.4}");
        assert!(n > (size * size / 16) as usize, "{what}: {n} pixels");
        assert!(err < 0.005, "{what}: {err}");
    }
}

/// The GGX models (rough conductors with exact and Schlick Fresnel,
/// metallic–roughness plastic and glass, a rough dielectric pane seen from
/// its back) match CPU `local` (MSAA 4, mean FLIP ≤ 0.02).
#[test]
fn microfacet_materials_match_cpu_local() {
    let Some(ctx) = common::gpu("microfacet_materials_match_cpu_local") else {
        return;
    };
    use penumbra_shading::bsdf::{
        FresnelModel, MetallicRoughness, RoughConductor, RoughDielectric, conductor_preset,
    };
    let mut scene = lights_scene();
    let gold = conductor_preset("gold").expect("gold");
    let copper = conductor_preset("copper").expect("copper");
    let models = [
        Bsdf::RoughConductor(RoughConductor::new(gold.0, gold.1, 0.3 * 0.3)),
        Bsdf::RoughConductor(RoughConductor {
            fresnel: FresnelModel::Schlick,
            ..RoughConductor::new(copper.0, copper.1, 0.5 * 0.5)
        }),
        Bsdf::MetallicRoughness(MetallicRoughness::new(Vec3::new(0.7, 0.1, 0.1), 0.0, 0.45)),
        Bsdf::MetallicRoughness(MetallicRoughness {
            transmission: 0.8,
            ..MetallicRoughness::new(Vec3::new(0.9, 0.9, 0.6), 0.0, 0.4)
        }),
    ];
    // The four spheres of the lights scene get the GGX materials.
    for (i, bsdf) in models.into_iter().enumerate() {
        let id = scene.add_material(Material {
            bsdf,
            double_sided: true,
            ..Material::lambert(format!("ggx {i}"), Vec3::ONE)
        });
        scene.meshes[i + 1].material = id;
    }
    // A frosted glass pane, its front facing away from the camera.
    let glass = scene.add_material(Material {
        bsdf: Bsdf::RoughDielectric(RoughDielectric::new(1.5, 0.35 * 0.35)),
        double_sided: false,
        ..Material::lambert("frosted", Vec3::ONE)
    });
    let mut pane = primitives::quad(
        Vec3::new(1.5, 0.1, 2.2),
        Vec3::new(0.0, 1.6, 0.0),
        Vec3::new(1.6, 0.0, 0.0),
    );
    pane.material = glass;
    scene.add_mesh(pane, Mat4::IDENTITY);
    // A lamp on the far side of the pane: its light reaches the camera
    // through the glass (the transmission lobe).
    scene.lights.push(SceneLight {
        name: "behind the pane".into(),
        light: Light::Point(PointLight::new(Vec3::new(2.3, 0.9, 1.2), Vec3::splat(2.0))),
    });
    let data = penumbra_raster::SceneData::from_scene(&scene);
    assert!(
        !data.warnings.iter().any(|w| w.contains("twin")),
        "{:?}",
        data.warnings
    );
    let camera = Camera::look_at(
        Vec3::new(0.5, 4.0, 9.0),
        Vec3::new(0.0, 0.7, 0.0),
        Vec3::Y,
        Projection::Perspective {
            fov_y: 45f32.to_radians(),
        },
    );
    // Narrow highlights alias at one sample per pixel (measured 0.0205 at
    // MSAA 1): compare with 4 samples, as the CPU takes 16.
    parity_at(&ctx, "microfacet", &scene, camera, 256, &[4]);

    // The pane, seen from its back, is shaded from inside the glass (η →
    // 1/η, as the CPU's seen_from_back): mean luminance over its pixels.
    let size = 128;
    let mut mask_scene = scene.clone();
    mask_scene.lights.clear();
    for (i, m) in mask_scene.materials.iter_mut().enumerate() {
        *m = if i == glass {
            Material {
                double_sided: true,
                ..Material::emitter("pane", Vec3::ONE)
            }
        } else {
            Material::lambert("black", Vec3::ZERO)
        };
    }
    let plain = ForwardRenderer::new(&ctx, RasterOptions::default()).expect("renderer");
    let mask = plain
        .render(&ctx, &mask_scene, &camera, size, size)
        .expect("render")
        .image;
    let r = ForwardRenderer::new(
        &ctx,
        RasterOptions {
            msaa: 4,
            ..Default::default()
        },
    )
    .expect("renderer");
    let gpu = r
        .render(&ctx, &scene, &camera, size, size)
        .expect("render")
        .image;
    let cpu = cpu_local(&scene, camera, size, size, 16);
    let pane = interior_pixels(&mask, |p| p.x > 0.5);
    let lum = |p: Vec3| 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z;
    let mean =
        |img: &Image| pane.iter().map(|&i| lum(img.pixels[i])).sum::<f32>() / pane.len() as f32;
    let (g, c) = (mean(&gpu), mean(&cpu));
    eprintln!(
        "pane seen from its back: {} pixels, mean luminance raster {g:.5} CPU {c:.5}",
        pane.len()
    );
    assert!(pane.len() > 300 && c > 1e-3, "{} {c}", pane.len());
    assert!((g - c).abs() <= 0.02 * c, "pane: raster {g} vs CPU {c}");
}
