//! The raster engine showing bakes (penumbra-bake directories written and
//! read back, as `render --engine raster --bake DIR` does): against the
//! path-traced reference, against the CPU `ao` integrator, and its GPU
//! lookup against the CPU twin of the lookup.

mod common;

use glam::Vec3;
use penumbra_bake::{
    AoSettings, AtlasSettings, Bake, LightmapSettings, LoadedBake, bake_ao, bake_lightmap,
    read_bake, write_bake,
};
use penumbra_image::{Image, hdr_flip, read_image, rel_mse};
use penumbra_raster::{BakedMaps, ForwardRenderer, GpuContext, RasterOptions, ShadowMode};
use penumbra_scene::{Scene, builtin};
use penumbra_trace::accel::BuildQuality;
use penumbra_trace::geometry::SceneGeometry;
use penumbra_trace::ray::Ray;
use penumbra_trace::scene_camera;

/// Writes `bake` and reads it back: what the CLI hands the renderer.
fn round_trip(bake: &Bake, scene: &Scene, dir: &tempfile::TempDir, name: &str) -> LoadedBake {
    let path = dir.path().join(name);
    write_bake(bake, scene, &path, None).expect("write bake");
    read_bake(&path, scene).expect("read bake")
}

fn raster(
    ctx: &GpuContext,
    scene: &Scene,
    size: u32,
    msaa: u32,
    shadows: ShadowMode,
    bakes: &[LoadedBake],
    aovs: bool,
) -> penumbra_raster::RasterOutput {
    let r = ForwardRenderer::new(
        ctx,
        RasterOptions {
            msaa,
            shadows,
            ..Default::default()
        },
    )
    .expect("renderer");
    let maps = BakedMaps::from_bakes(bakes).expect("bakes");
    r.render_baked(ctx, scene, &scene_camera(scene), size, size, &maps, aovs)
        .expect("render")
}

fn channel_means(img: &Image) -> Vec3 {
    img.pixels.iter().copied().sum::<Vec3>() / img.pixels.len() as f32
}

fn aov<'a>(out: &'a penumbra_raster::RasterOutput, name: &str) -> &'a Image {
    &out.aovs.iter().find(|(n, _)| n == name).expect("aov").1
}

#[test]
fn a_full_light_map_of_the_cornell_box_matches_the_path_traced_reference() {
    let Some(ctx) = common::gpu("light map vs reference") else {
        return;
    };
    let scene = builtin::cornell_box();
    let s = LightmapSettings {
        samples: 32,
        ..Default::default()
    };
    let bake = bake_lightmap(&scene, &s, &AtlasSettings::default(), None).expect("bake");
    let dir = tempfile::tempdir().unwrap();
    let lm = round_trip(&bake, &scene, &dir, "lightmap");
    let out = raster(&ctx, &scene, 512, 4, ShadowMode::None, &[lm], false);
    let reference =
        read_image(&common::reference_dir("cornell").join("reference-path-depth8-4096spp.exr"))
            .expect("reference");
    let ratio = channel_means(&out.image) / channel_means(&reference);
    let (flip, _) = hdr_flip(&reference, &out.image).unwrap();
    let err = rel_mse(&reference, &out.image);
    eprintln!(
        "light map ({} texels, {} spp) shown by raster, MSAA 4: mean ratio {ratio}, relMSE {err:.5}, FLIP {flip:.4} (Mitsuba 64 spp: relMSE 0.00419, FLIP 0.084)",
        bake.stats.valid, s.samples
    );
    assert!((ratio - Vec3::ONE).abs().max_element() < 0.01, "{ratio}");
    assert!(err < 0.005, "relMSE {err}");
}

/// Per pixel centre: (instance, chart, normal) of the first hit, or None.
fn first_hits(scene: &Scene, bake: &LoadedBake, size: u32) -> Vec<Option<(usize, u32, Vec3)>> {
    let geometry = SceneGeometry::build(scene, BuildQuality::default()).unwrap();
    let camera = scene_camera(scene);
    (0..size * size)
        .map(|i| {
            let (x, y) = (i % size, i / size);
            let (o, d) = camera.generate_ray(x as f32 + 0.5, y as f32 + 0.5, size, size);
            let hit = geometry.intersect(scene, &Ray::new(o, d))?;
            if hit.light.is_some() || scene.materials[hit.material].is_emissive() {
                return None;
            }
            let (inst, local) = geometry.triangle_source(hit.triangle);
            let layout = bake.atlas.meshes[scene.instances[inst].mesh].as_ref()?;
            Some((inst, layout.charts[local], hit.ng))
        })
        .collect()
}

#[test]
fn a_baked_ao_shown_by_raster_agrees_with_the_ao_integrator() {
    let Some(ctx) = common::gpu("baked AO vs ao integrator") else {
        return;
    };
    let scene = builtin::cornell_box();
    let d = 100.0;
    let bake = bake_ao(
        &scene,
        &AoSettings {
            samples: 512,
            distance: d,
            seed: 0,
        },
        &AtlasSettings::default(),
        None,
    )
    .expect("bake");
    let dir = tempfile::tempdir().unwrap();
    let ao = round_trip(&bake, &scene, &dir, "ao");
    let size = 256;
    let out = raster(
        &ctx,
        &scene,
        size,
        4,
        ShadowMode::None,
        std::slice::from_ref(&ao),
        true,
    );
    let shown = aov(&out, "ao");
    let cpu = common::ao_reference::ao_reference("cornell-r100-256", &scene, size, d);
    let hits = first_hits(&scene, &ao, size);
    let at = |x: i64, y: i64| hits[(y * size as i64 + x) as usize];
    // Interior: the 3×3 neighbourhood sees one chart of one surface;
    // boundary: it sees two charts of the scene's surfaces (and nothing else).
    let (mut interior, mut boundary) = ((0.0, 0), (0.0, 0));
    for y in 1..size as i64 - 1 {
        for x in 1..size as i64 - 1 {
            let Some(centre) = at(x, y) else { continue };
            let mut same = true;
            let mut all_hit = true;
            for dy in -1..=1 {
                for dx in -1..=1 {
                    match at(x + dx, y + dy) {
                        Some(h) => same &= (h.0, h.1) == (centre.0, centre.1),
                        None => all_hit = false,
                    }
                }
            }
            let e = (shown.get(x as u32, y as u32).x - cpu.get(x as u32, y as u32).x).abs() as f64;
            if same && all_hit {
                interior.0 += e;
                interior.1 += 1;
            } else if all_hit {
                boundary.0 += e;
                boundary.1 += 1;
            }
        }
    }
    let mae = interior.0 / interior.1 as f64;
    let seam = boundary.0 / boundary.1 as f64;
    eprintln!(
        "baked AO (D = {d}, {} texels, 512 rays) vs ao integrator (1024 spp), {size}²: interior MAE {mae:.4} over {} px, chart-boundary MAE {seam:.4} over {} px",
        bake.stats.valid, interior.1, boundary.1
    );
    assert!(interior.1 > 20_000 && boundary.1 > 500);
    assert!(mae <= 0.02, "interior MAE {mae}");
    assert!(seam <= 0.03, "chart-boundary MAE {seam}");
}

#[test]
fn the_gpu_lookup_equals_the_cpu_lookup_at_every_pixel_centre() {
    let Some(ctx) = common::gpu("GPU vs CPU bake lookup") else {
        return;
    };
    let scene = builtin::cornell_box();
    let bake = bake_lightmap(
        &scene,
        &LightmapSettings {
            samples: 2,
            bounces: 1,
            ..Default::default()
        },
        &AtlasSettings {
            density: penumbra_bake::Density::MaxSize(128),
            ..Default::default()
        },
        None,
    )
    .expect("bake");
    let dir = tempfile::tempdir().unwrap();
    let lm = round_trip(&bake, &scene, &dir, "lm");
    let size = 128;
    let out = raster(
        &ctx,
        &scene,
        size,
        1,
        ShadowMode::None,
        std::slice::from_ref(&lm),
        true,
    );
    let shown = aov(&out, "irradiance");
    let geometry = SceneGeometry::build(&scene, BuildQuality::default()).unwrap();
    let camera = scene_camera(&scene);
    // Pixels on an edge may rasterise the neighbouring triangle: a few
    // differ; everywhere else the two lookups agree to float rounding.
    let (mut n, mut matched) = (0, 0);
    for y in 0..size {
        for x in 0..size {
            let (o, d) = camera.generate_ray(x as f32 + 0.5, y as f32 + 0.5, size, size);
            let Some(hit) = geometry.intersect(&scene, &Ray::new(o, d)) else {
                continue;
            };
            let Some(cpu) = lm.atlas.sample(&lm.pages, &scene, &geometry, &hit) else {
                continue;
            };
            n += 1;
            let e = (shown.get(x, y) - cpu).abs().max_element();
            if e <= 1e-3 * cpu.max_element().max(1e-3) {
                matched += 1;
            }
        }
    }
    eprintln!("{matched} of {n} pixels match the CPU lookup to 1e-3");
    assert!(matched as f64 >= 0.98 * n as f64, "{matched} of {n}");
}

#[test]
fn indirect_only_plus_real_time_shadows_matches_the_full_light_map() {
    let Some(ctx) = common::gpu("indirect-only + shadow volumes") else {
        return;
    };
    // The Cornell box lit by a point light under the ceiling instead of its
    // emissive panel (emitters give no real-time light).
    let mut scene = builtin::cornell_box();
    for m in &mut scene.materials {
        m.emission = Vec3::ZERO;
    }
    scene.lights.push(penumbra_scene::SceneLight {
        name: "bulb".into(),
        light: penumbra_shading::light::Light::Point(penumbra_shading::light::PointLight::new(
            Vec3::new(278.0, 500.0, 280.0),
            Vec3::splat(4.0e4),
        )),
    });
    let dir = tempfile::tempdir().unwrap();
    let bake = |indirect_only, name| {
        let b = bake_lightmap(
            &scene,
            &LightmapSettings {
                samples: 32,
                indirect_only,
                ..Default::default()
            },
            &AtlasSettings::default(),
            None,
        )
        .expect("bake");
        round_trip(&b, &scene, &dir, name)
    };
    let (full, indirect) = (bake(false, "full"), bake(true, "indirect"));
    let a = raster(&ctx, &scene, 256, 4, ShadowMode::None, &[full], false);
    let b = raster(&ctx, &scene, 256, 4, ShadowMode::Volume, &[indirect], false);
    let ratio = channel_means(&b.image) / channel_means(&a.image);
    eprintln!("indirect-only map + shadow volumes over the full map: mean ratio {ratio}");
    assert!((ratio - Vec3::ONE).abs().max_element() < 0.02, "{ratio}");
}

#[test]
fn bad_bake_combinations_are_refused() {
    let Some(ctx) = common::gpu("bake combinations") else {
        return;
    };
    let scene = builtin::cornell_box();
    let small = AtlasSettings {
        density: penumbra_bake::Density::MaxSize(32),
        ..Default::default()
    };
    let dir = tempfile::tempdir().unwrap();
    let ao = bake_ao(
        &scene,
        &AoSettings {
            samples: 1,
            ..Default::default()
        },
        &small,
        None,
    )
    .unwrap();
    let lm = bake_lightmap(
        &scene,
        &LightmapSettings {
            samples: 1,
            ..Default::default()
        },
        &small,
        None,
    )
    .unwrap();
    let (ao1, ao2) = (
        round_trip(&ao, &scene, &dir, "a"),
        round_trip(&ao, &scene, &dir, "b"),
    );
    let lm = round_trip(&lm, &scene, &dir, "l");
    let two_ao = [ao1.clone(), ao2];
    let e = BakedMaps::from_bakes(&two_ao).unwrap_err().to_string();
    assert!(e.contains("two ambient-occlusion bakes"), "{e}");
    let r = ForwardRenderer::new(
        &ctx,
        RasterOptions {
            shadows: ShadowMode::Map,
            ..Default::default()
        },
    )
    .unwrap();
    let both = [ao1, lm];
    let maps = BakedMaps::from_bakes(&both).unwrap();
    let e = r
        .render_baked(&ctx, &scene, &scene_camera(&scene), 32, 32, &maps, false)
        .unwrap_err()
        .to_string();
    assert!(e.contains("--indirect-only"), "{e}");
    let plain = ForwardRenderer::new(&ctx, RasterOptions::default()).unwrap();
    let e = plain
        .render_baked(
            &ctx,
            &scene,
            &scene_camera(&scene),
            32,
            32,
            &BakedMaps::default(),
            true,
        )
        .unwrap_err()
        .to_string();
    assert!(e.contains("--bake"), "{e}");
}
