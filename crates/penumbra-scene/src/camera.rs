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
        self.film(width, height).ray(sx, sy)
    }

    /// The primary rays of a `width`×`height` image, with what they share
    /// computed once (a render asks for millions).
    pub fn film(&self, width: u32, height: u32) -> FilmRays {
        let (w, h) = (width as f32, height as f32);
        let shared = match self.projection {
            Projection::Perspective { fov_y } => Shared::Perspective {
                tan_half_fov: (0.5 * fov_y).tan(),
                origin: self.camera_to_world.transform_point3(Vec3::ZERO),
            },
            Projection::Orthographic { height } => Shared::Orthographic {
                height,
                direction: self.camera_to_world.transform_vector3(-Vec3::Z).normalize(),
            },
        };
        FilmRays {
            camera_to_world: self.camera_to_world,
            width: w,
            height: h,
            aspect: w / h,
            shared,
        }
    }
}

/// [`Camera::generate_ray`] for one image size: the field of view's
/// tangent, the aspect ratio and the perspective origin (or the
/// orthographic direction) computed once.
#[derive(Clone, Copy, Debug)]
pub struct FilmRays {
    camera_to_world: Mat4,
    width: f32,
    height: f32,
    aspect: f32,
    shared: Shared,
}

#[derive(Clone, Copy, Debug)]
enum Shared {
    Perspective { tan_half_fov: f32, origin: Vec3 },
    Orthographic { height: f32, direction: Vec3 },
}

impl FilmRays {
    /// Primary ray for film position (`sx`, `sy`) in pixels: (origin,
    /// unit direction), as [`Camera::generate_ray`].
    pub fn ray(&self, sx: f32, sy: f32) -> (Vec3, Vec3) {
        let aspect = self.aspect;
        // Normalised device coordinates in [-1, 1], y up.
        let nx = 2.0 * sx / self.width - 1.0;
        let ny = 1.0 - 2.0 * sy / self.height;
        match self.shared {
            Shared::Perspective {
                tan_half_fov: t,
                origin,
            } => {
                let d = Vec3::new(nx * t * aspect, ny * t, -1.0);
                (
                    origin,
                    self.camera_to_world.transform_vector3(d).normalize(),
                )
            }
            Shared::Orthographic { height, direction } => {
                let p = Vec3::new(nx * 0.5 * height * aspect, ny * 0.5 * height, 0.0);
                (self.camera_to_world.transform_point3(p), direction)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An orthographic view 4 high of a 100×50 image (so 8 wide) from
    /// (1, 2, 3) along −z: the corners' rays start 4 and 2 from the centre,
    /// all rays point along −z, and a second image size changes the
    /// spacing, not the view.
    #[test]
    fn orthographic_rays_start_on_the_view_rectangle() {
        let c = Camera::look_at(
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(1.0, 2.0, 0.0),
            Vec3::Y,
            Projection::Orthographic { height: 4.0 },
        );
        for (sx, sy, expected) in [
            (50.0, 25.0, Vec3::new(1.0, 2.0, 3.0)),
            (0.0, 0.0, Vec3::new(-3.0, 4.0, 3.0)),
            (100.0, 50.0, Vec3::new(5.0, 0.0, 3.0)),
            (75.0, 0.0, Vec3::new(3.0, 4.0, 3.0)),
        ] {
            let (o, d) = c.generate_ray(sx, sy, 100, 50);
            assert!((o - expected).length() < 1e-5, "({sx}, {sy}): {o}");
            assert!((d - Vec3::NEG_Z).length() < 1e-6, "{d}");
        }
        let (o, _) = c.film(200, 100).ray(0.0, 0.0);
        assert!((o - Vec3::new(-3.0, 4.0, 3.0)).length() < 1e-5, "{o}");
    }

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
        // A 2:1 image: the right edge is at tan θ = 2 tan(½ fov_y).
        let (_, right) = c.generate_ray(200.0, 50.0, 200, 100);
        let expected = (2.0 * (fov / 2.0).tan()).atan();
        assert!((right.angle_between(d) - expected).abs() < 1e-5, "{right}");
        assert!(right.x > 0.0 && right.y.abs() < 1e-6);
    }
}
