//! The raster projection maps the CPU's camera rays through pixel centres
//! back onto those pixel centres (perspective and orthographic, non-square
//! images), and depth is reversed (nearer = larger) inside [0, 1].

use glam::{Vec3, Vec4Swizzles};
use penumbra_raster::view_projection;
use penumbra_scene::camera::{Camera, Projection};

fn check(camera: Camera, width: u32, height: u32) {
    // The scene around the camera: every t below is inside the bounds, so
    // nothing may be clipped.
    let bounds = (Vec3::splat(-30.0), Vec3::splat(30.0));
    let vp = view_projection(&camera, width, height, bounds);
    let mut worst = 0f32;
    for (x, y) in [
        (0, 0),
        (width - 1, 0),
        (7, height / 2),
        (width / 3, height - 1),
        (width - 1, height - 1),
    ] {
        let (sx, sy) = (x as f32 + 0.5, y as f32 + 0.5);
        let (o, d) = camera.generate_ray(sx, sy, width, height);
        let mut last_depth = f32::INFINITY;
        for t in [0.5, 2.0, 5.0, 9.0, 25.0] {
            let clip = vp * (o + d * t).extend(1.0);
            let ndc = clip.xyz() / clip.w;
            // wgpu: framebuffer x = (ndc.x + 1)/2 · width, y = (1 − ndc.y)/2 · height.
            let px = (ndc.x + 1.0) * 0.5 * width as f32;
            let py = (1.0 - ndc.y) * 0.5 * height as f32;
            worst = worst.max((px - sx).abs()).max((py - sy).abs());
            assert!(
                ndc.z > 0.0 && ndc.z <= 1.0 && ndc.z < last_depth,
                "depth {} at t = {t} (previous {last_depth})",
                ndc.z
            );
            last_depth = ndc.z;
        }
    }
    assert!(
        worst < 2e-3,
        "{:?}: pixel offset {worst}",
        camera.projection
    );
}

#[test]
fn pixel_centres_line_up_with_cpu_rays() {
    let eye = Vec3::new(1.0, 2.0, 12.0);
    let persp = Camera::look_at(
        eye,
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::Y,
        Projection::Perspective {
            fov_y: 50f32.to_radians(),
        },
    );
    check(persp, 320, 200);
    check(persp, 64, 257);
    let ortho = Camera::look_at(
        eye,
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::Y,
        Projection::Orthographic { height: 6.0 },
    );
    check(ortho, 320, 200);
    check(ortho, 64, 257);
}
