//! The camera of a raster frame: reversed-depth view-projection matching the
//! CPU camera's rays, and the per-frame camera constants.

use crate::gpu::GpuCamera;
use glam::{Mat4, Vec3, Vec4};
use penumbra_scene::camera::{Camera, Projection};

/// View-projection of `camera` for a `width`×`height` image with reversed
/// depth (1 at the near plane, 0 at the far plane or infinity). Pixel
/// centres map to the same points as `Camera::generate_ray(x + ½, y + ½)`:
/// both use NDC x = 2 sx / width − 1, y = 1 − 2 sy / height.
pub fn view_projection(camera: &Camera, width: u32, height: u32, bounds: (Vec3, Vec3)) -> Mat4 {
    let (view, proj) = view_and_projection(camera, width, height, bounds);
    proj * view
}

/// Depth beyond the scene's far side that an orthographic view keeps, in
/// scene radii: the finite shadow-volume extrusion
/// ([`ORTHO_EXTRUSION_RADII`]) must stay inside the far plane.
const ORTHO_FAR_RADII: f32 = ORTHO_EXTRUSION_RADII + 1.5;

/// Length, in scene radii, of the shadow-volume extrusion under an
/// orthographic camera (which has no points at infinity): any two points of
/// the bounding sphere are at most 2 radii apart, so the prisms reach past
/// every receiver.
pub const ORTHO_EXTRUSION_RADII: f32 = 2.5;

/// World-to-view transform and the reversed-depth projection of
/// [`view_projection`], separately (light culling works in view space).
pub fn view_and_projection(
    camera: &Camera,
    width: u32,
    height: u32,
    bounds: (Vec3, Vec3),
) -> (Mat4, Mat4) {
    let aspect = width as f32 / height as f32;
    let view = camera.camera_to_world.inverse();
    let (lo, hi) = bounds;
    let centre = 0.5 * (lo + hi);
    let radius = (0.5 * (hi - lo).length()).max(1e-6);
    let proj = match camera.projection {
        Projection::Perspective { fov_y } => {
            let dist = (camera.position() - centre).length();
            // Reversed float depth keeps precision far away, so the near
            // plane can sit well in front of the scene.
            let near = ((dist - radius) * 0.5).max(radius * 1e-5).max(1e-6);
            // Right-handed, infinite far plane, depth = near / −z_view.
            let f = 1.0 / (0.5 * fov_y).tan();
            Mat4::from_cols(
                Vec4::new(f / aspect, 0.0, 0.0, 0.0),
                Vec4::new(0.0, f, 0.0, 0.0),
                Vec4::new(0.0, 0.0, 0.0, -1.0),
                Vec4::new(0.0, 0.0, near, 0.0),
            )
        }
        Projection::Orthographic { height } => {
            // Rays start on the camera plane (z = 0), as the CPU's. The far
            // plane leaves room for shadow-volume extrusions.
            let z_centre = view.transform_point3(centre).z;
            let far = (-z_centre + ORTHO_FAR_RADII * radius) * 1.01 + 1e-4;
            let far = far.max(1e-4);
            Mat4::from_cols(
                Vec4::new(2.0 / (height * aspect), 0.0, 0.0, 0.0),
                Vec4::new(0.0, 2.0 / height, 0.0, 0.0),
                Vec4::new(0.0, 0.0, 1.0 / far, 0.0),
                Vec4::new(0.0, 0.0, 1.0, 1.0),
            )
        }
    };
    (view, proj)
}

/// The camera constants of a frame.
pub fn gpu_camera(
    camera: &Camera,
    width: u32,
    height: u32,
    bounds: (Vec3, Vec3),
    light_count: u32,
) -> GpuCamera {
    let back = camera
        .camera_to_world
        .transform_vector3(Vec3::Z)
        .normalize();
    let ortho = matches!(camera.projection, Projection::Orthographic { .. });
    GpuCamera {
        view_proj: view_projection(camera, width, height, bounds).to_cols_array_2d(),
        eye: camera.position().extend(1.0).to_array(),
        back: back.extend(if ortho { 1.0 } else { 0.0 }).to_array(),
        light_count,
        ..GpuCamera::default()
    }
}
