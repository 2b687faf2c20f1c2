//! Stencil shadows against the CPU ray tracer's hard shadows (`direct`):
//! shadow volumes everywhere, planar projected shadows on the planar
//! receiver. A pixel is shadowed on the CPU where `direct` < ½ · `local`, on
//! the GPU where the shadowed raster image < ½ · the unshadowed one (see
//! shadow_maps.rs). Differences must be rare (≤ 0.5 % of the pixels) and lie
//! on shadow edges (within two pixels of a CPU shadow boundary: the CPU's 4
//! random samples and the 4× MSAA pattern disagree about partly covered
//! pixels).

mod common;
mod shadow_scene;

use glam::{Mat4, Vec3};
use penumbra_image::Image;
use penumbra_raster::{GpuContext, RasterOptions, ShadowMode};
use penumbra_scene::camera::{Camera, Projection};
use penumbra_scene::{IntegratorKind, Material, Scene, SceneLight, primitives};
use penumbra_shading::light::{Light, PointLight};
use shadow_scene::{
    RES, classify, cpu_with, differences, lum, raster_with, save, scene, scene_with,
};

const MAX_DIFF: f64 = 0.005;

fn options(shadows: ShadowMode, msaa: u32) -> RasterOptions {
    RasterOptions {
        shadows,
        msaa,
        ..Default::default()
    }
}

/// Pixels within two pixels of a change of the CPU's shadow state.
fn near_edge(cpu: &[bool]) -> Vec<bool> {
    let n = RES as i32;
    (0..cpu.len())
        .map(|i| {
            let (x, y) = (i as i32 % n, i as i32 / n);
            let me = cpu[i];
            (-2..=2).any(|dy| {
                (-2..=2).any(|dx| {
                    let (u, v) = (x + dx, y + dy);
                    u >= 0 && v >= 0 && u < n && v < n && cpu[(v * n + u) as usize] != me
                })
            })
        })
        .collect()
}

struct Comparison {
    diff: f64,
    leak: f64,
    /// Differing pixels away from every CPU shadow edge.
    off_edge: usize,
    shadowed: f64,
    pixels: usize,
}

/// Compares `mode` with CPU direct for `scene` seen by `camera`, over the
/// pixels of `mask`.
fn compare(
    ctx: &GpuContext,
    name: &str,
    s: &Scene,
    camera: &Camera,
    mode: ShadowMode,
    msaa: u32,
    mask: Option<&[bool]>,
) -> Comparison {
    let cpu_shadowed = classify(
        &cpu_with(s, *camera, IntegratorKind::Direct),
        &cpu_with(s, *camera, IntegratorKind::Local),
    );
    let (plain, _) = raster_with(ctx, s, camera, options(ShadowMode::None, msaa), "");
    let (img, _) = raster_with(ctx, s, camera, options(mode, msaa), "");
    save(name, &img);
    let gpu_shadowed = classify(&img, &plain);
    let (diff, leak, pixels) = differences(&gpu_shadowed, &cpu_shadowed, mask);
    let edge = near_edge(&cpu_shadowed);
    let off_edge = (0..gpu_shadowed.len())
        .filter(|&i| mask.is_none_or(|m| m[i]) && gpu_shadowed[i] != cpu_shadowed[i] && !edge[i])
        .count();
    let shadowed = (0..cpu_shadowed.len())
        .filter(|&i| mask.is_none_or(|m| m[i]) && cpu_shadowed[i])
        .count() as f64
        / pixels as f64;
    eprintln!(
        "{name}: {mode:?} MSAA {msaa}: {:.3} % of {pixels} pixels differ from CPU direct ({:.3} % lit on the GPU but shadowed on the CPU, {off_edge} away from a shadow edge; {:.2} % shadowed on the CPU)",
        100.0 * diff,
        100.0 * leak,
        100.0 * shadowed
    );
    Comparison {
        diff,
        leak,
        off_edge,
        shadowed,
        pixels,
    }
}

fn assert_close(name: &str, c: &Comparison) {
    // The view must contain a real shadow, or the comparison proves nothing.
    assert!(c.shadowed > 0.02, "{name}: only {:.4} shadowed", c.shadowed);
    assert!(c.diff <= MAX_DIFF, "{name}: {:.3} % differ", 100.0 * c.diff);
    // No light leaks into the CPU's shadows (beyond partly covered pixels).
    assert!(
        c.leak <= 0.6 * MAX_DIFF,
        "{name}: {:.3} % leak",
        100.0 * c.leak
    );
    assert_eq!(c.off_edge, 0, "{name}: differences away from shadow edges");
}

#[test]
fn shadow_volumes_match_cpu_direct() {
    let Some(ctx) = common::gpu("shadow_volumes_match_cpu_direct") else {
        return;
    };
    for which in ["point", "directional", "spot"] {
        for msaa in [1, 4] {
            let name = format!("volume-{which}-msaa{msaa}");
            let c = compare(
                &ctx,
                &name,
                &scene(which, true),
                &shadow_scene::camera(),
                ShadowMode::Volume,
                msaa,
                None,
            );
            assert_close(&name, &c);
        }
    }
}

/// Pixels where the receiver (instance 0, the ground) is the visible
/// surface: the raster image of the scene with every material black except
/// the ground, which emits.
fn receiver_mask(ctx: &GpuContext, s: &Scene, camera: &Camera) -> Vec<bool> {
    let mut m = s.clone();
    m.lights.clear();
    m.materials = vec![
        Material::emitter("ground", Vec3::ONE),
        Material::lambert("black", Vec3::ZERO),
    ];
    for (i, mesh) in m.meshes.iter_mut().enumerate() {
        mesh.material = usize::from(i != 0);
    }
    let (img, _) = raster_with(ctx, &m, camera, options(ShadowMode::None, 1), "");
    img.pixels.iter().map(|p| lum(*p) > 0.5).collect()
}

#[test]
fn planar_shadows_match_cpu_direct_on_the_receiver() {
    let Some(ctx) = common::gpu("planar_shadows_match_cpu_direct_on_the_receiver") else {
        return;
    };
    let camera = shadow_scene::camera();
    for which in ["point", "directional", "spot"] {
        let s = scene(which, true);
        let mask = receiver_mask(&ctx, &s, &camera);
        let covered = mask.iter().filter(|b| **b).count();
        assert!(covered > (RES * RES / 3) as usize, "{covered}");
        for msaa in [1, 4] {
            let name = format!("planar-{which}-msaa{msaa}");
            let c = compare(
                &ctx,
                &name,
                &s,
                &camera,
                ShadowMode::Planar,
                msaa,
                Some(&mask),
            );
            assert_eq!(c.pixels, covered);
            assert_close(&name, &c);
        }
    }
}

/// Open meshes (single quads facing towards and away from the light, an
/// open box without a lid) cast correct volumes, also seen from a camera
/// that stands inside a shadow volume and through an orthographic camera.
#[test]
fn shadow_volumes_of_open_meshes_with_the_camera_inside_a_volume() {
    let Some(ctx) = common::gpu("shadow_volumes_of_open_meshes_with_the_camera_inside_a_volume")
    else {
        return;
    };
    let mut s = Scene::default();
    let white = s.add_material(Material {
        double_sided: true,
        ..Material::lambert("white", Vec3::splat(0.7))
    });
    let mut ground = primitives::quad(
        Vec3::new(-8.0, 0.0, 8.0),
        Vec3::new(16.0, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -16.0),
    );
    ground.material = white;
    s.add_mesh(ground, Mat4::IDENTITY);
    // Facing up (towards the light) and facing down.
    for (corner, e1, e2) in [
        (
            Vec3::new(-3.0, 2.0, 1.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, -2.0),
        ),
        (
            Vec3::new(0.5, 1.5, -1.0),
            Vec3::new(0.0, 0.0, -1.5),
            Vec3::new(2.0, 0.0, 0.0),
        ),
    ] {
        let mut q = primitives::quad(corner, e1, e2);
        q.material = white;
        s.add_mesh(q, Mat4::IDENTITY);
    }
    // A box without its top face: open.
    let mut b = primitives::cuboid(Vec3::new(1.5, 0.0, 1.5), Vec3::new(2.5, 1.0, 2.5));
    b.indices.retain(|t| {
        let y = |i: u32| b.positions[i as usize].y;
        !(y(t[0]) == 1.0 && y(t[1]) == 1.0 && y(t[2]) == 1.0)
    });
    b.material = white;
    s.add_mesh(b, Mat4::IDENTITY);
    s.lights = vec![SceneLight {
        name: "lamp".into(),
        light: Light::Point(PointLight::new(
            Vec3::new(-1.0, 6.0, 0.5),
            Vec3::splat(40.0),
        )),
    }];
    let outside = Camera::look_at(
        Vec3::new(0.0, 7.0, 9.0),
        Vec3::ZERO,
        Vec3::Y,
        Projection::Perspective {
            fov_y: 55f32.to_radians(),
        },
    );
    // Under the first quad, in its shadow, looking across the floor.
    let inside = Camera::look_at(
        Vec3::new(-2.0, 1.0, 0.0),
        Vec3::new(2.0, 0.0, -2.0),
        Vec3::Y,
        Projection::Perspective {
            fov_y: 70f32.to_radians(),
        },
    );
    let lamp = Vec3::new(-1.0, 6.0, 0.5);
    // The inside camera really is in the quad's shadow: the segment to the
    // lamp crosses the quad (y = 2, x in [-3, -1], z in [-1, 1]).
    let t = (2.0 - 1.0) / (lamp.y - 1.0);
    let cross = Vec3::new(-2.0, 1.0, 0.0).lerp(lamp, t);
    assert!(cross.x > -3.0 && cross.x < -1.0 && cross.z > -1.0 && cross.z < 1.0);
    // Orthographic views have no points at infinity: finite extrusion.
    let ortho = Camera::look_at(
        Vec3::new(2.0, 8.0, 6.0),
        Vec3::ZERO,
        Vec3::Y,
        Projection::Orthographic { height: 10.0 },
    );
    for (name, camera) in [
        ("open-outside", outside),
        ("open-inside", inside),
        ("open-orthographic", ortho),
    ] {
        for msaa in [1, 4] {
            let c = compare(
                &ctx,
                &format!("{name}-msaa{msaa}"),
                &s,
                &camera,
                ShadowMode::Volume,
                msaa,
                None,
            );
            assert_close(name, &c);
        }
    }
}

/// Each light's stencil pass starts from a cleared stencil: two lights
/// render as the sum of each alone.
#[test]
fn stencil_shadows_of_several_lights_add_up() {
    let Some(ctx) = common::gpu("stencil_shadows_of_several_lights_add_up") else {
        return;
    };
    let camera = shadow_scene::camera();
    for mode in [ShadowMode::Volume, ShadowMode::Planar] {
        let render = |lights: &[&str]| -> Image {
            raster_with(
                &ctx,
                &scene_with(lights, true),
                &camera,
                options(mode, 1),
                "",
            )
            .0
        };
        let both = render(&["point", "directional"]);
        let point = render(&["point"]);
        let sun = render(&["directional"]);
        let mut worst = 0.0f32;
        for i in 0..both.pixels.len() {
            let sum = point.pixels[i] + sun.pixels[i];
            let d = (both.pixels[i] - sum).abs().max_element();
            worst = worst.max(d / sum.max_element().max(1e-3));
        }
        eprintln!("{mode:?}: two lights vs the sum of each: worst relative difference {worst:.2e}");
        assert!(worst < 1e-5, "{mode:?}: {worst}");
        // And the shadows are there: the sum is darker than unshadowed.
        let (plain, _) = raster_with(
            &ctx,
            &scene_with(&["point", "directional"], true),
            &camera,
            options(ShadowMode::None, 1),
            "",
        );
        let shadowed = classify(&both, &plain).iter().filter(|b| **b).count();
        assert!(
            shadowed > (RES * RES / 100) as usize,
            "{mode:?}: {shadowed}"
        );
    }
}
