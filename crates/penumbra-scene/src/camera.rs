//! Cameras. Camera space follows glTF: the camera looks along −z, +y is up,
//! +x is right. Raster row 0 is the top of the image.

use glam::{Mat4, Vec3};

/// Projection of a camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Pinhole with vertical field of view `fov_y` [radians].
    Perspective { fov_y: f32 },
    /// Orthographic; `height` is the world-space height of the view.
    Orthographic { height: f32 },
}

/// A camera: camera-to-world transform (rigid) and a projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub camera_to_world: Mat4,
    pub projection: Projection,
}

impl Camera {
    /// Camera at `eye` looking at `target` with `up` (right-handed).
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3, projection: Projection) -> Self {
        let forward = (target - eye).normalize();
        let right = forward.cross(up).normalize();
        let true_up = right.cross(forward);
        let camera_to_world = Mat4::from_cols(
            right.extend(0.0),
            true_up.extend(0.0),
            (-forward).extend(0.0),
            eye.extend(1.0),
        );
        Self {
            camera_to_world,
            projection,
        }
    }

    /// The camera that frames a bounding box when a scene has none: it
    /// looks at the box's centre from 30° right of +z and 25° above the
    /// horizon (direction `(sin 30° cos 25°, sin 25°, cos 30° cos 25°)`, +y
    /// up), so that boxes show three faces and models lying in the xz-plane
    /// are seen from above. The vertical field of view is 40°, and the
    /// distance puts the bounding sphere of radius r inside the narrower of
    /// the two fields of view with a 5 % margin: `d = 1.05 r / sin(½ min(fov_y,
    /// fov_x))`, with `tan(½ fov_x) = aspect · tan(½ fov_y)`.
    pub fn framing(lo: Vec3, hi: Vec3, aspect: f32) -> Self {
        let centre = 0.5 * (lo + hi);
        let radius = (0.5 * (hi - lo).length()).max(1e-3);
        let fov_y = 40f32.to_radians();
        let half_x = ((0.5 * fov_y).tan() * aspect.max(1e-3)).atan();
        let half = (0.5 * fov_y).min(half_x);
        let distance = 1.05 * radius / half.sin();
        let (azimuth, elevation) = (30f32.to_radians(), 25f32.to_radians());
        let direction = Vec3::new(
            azimuth.sin() * elevation.cos(),
            elevation.sin(),
            azimuth.cos() * elevation.cos(),
        );
        Camera::look_at(
            centre + direction * distance,
            centre,
            Vec3::Y,
            Projection::Perspective { fov_y },
        )
    }

    /// Camera position in world space.
    pub fn position(&self) -> Vec3 {
        self.camera_to_world.w_axis.truncate()
    }

    /// Primary ray for film position (`sx`, `sy`) in pixels (continuous,
    /// (0,0) = top-left corner) of a `width`×`height` image: (origin, unit dir).
    pub fn generate_ray(&self, sx: f32, sy: f32, width: u32, height: u32) -> (Vec3, Vec3) {
        let aspect = width as f32 / height as f32;
        // Normalised device coordinates in [-1, 1], y up.
        let nx = 2.0 * sx / width as f32 - 1.0;
        let ny = 1.0 - 2.0 * sy / height as f32;
        match self.projection {
            Projection::Perspective { fov_y } => {
                let t = (0.5 * fov_y).tan();
                let d = Vec3::new(nx * t * aspect, ny * t, -1.0);
                let o = self.camera_to_world.transform_point3(Vec3::ZERO);
                (o, self.camera_to_world.transform_vector3(d).normalize())
            }
            Projection::Orthographic { height } => {
                let p = Vec3::new(nx * 0.5 * height * aspect, ny * 0.5 * height, 0.0);
                let o = self.camera_to_world.transform_point3(p);
                (
                    o,
                    self.camera_to_world.transform_vector3(-Vec3::Z).normalize(),
                )
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_ray_points_at_target_and_fov_edges() {
        let fov = 40f32.to_radians();
        let c = Camera::look_at(
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::Y,
            Projection::Perspective { fov_y: fov },
        );
        let (o, d) = c.generate_ray(50.0, 50.0, 100, 100);
        assert!((o - Vec3::new(1.0, 2.0, 3.0)).length() < 1e-5);
        assert!((d - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-5);
        let (_, top) = c.generate_ray(50.0, 0.0, 100, 100);
        assert!((top.angle_between(d) - fov / 2.0).abs() < 1e-5);
        assert!(top.y > 0.0, "row 0 is the top");
        let (_, right) = c.generate_ray(100.0, 50.0, 100, 100);
        assert!(right.x > 0.0);
    }
}
