//! Light from infinitely far away in every direction: a constant radiance,
//! or an equirectangular (latitude–longitude) HDR map.
//!
//! Lat-long convention (+y up, right-handed): texel row 0 is the zenith
//! (+y), the last row the nadir; `v = θ/π` with `θ = acos(y)`. Columns run
//! with the azimuth `φ = atan2(x, −z)`, `u = φ/2π + ½`: the image centre
//! (u = ½) looks along −z, u = ¾ along +x, u = ¼ along −x, and the left/right
//! edges along +z. So `d(u, v) = (sin θ sin φ, cos θ, −sin θ cos φ)` with
//! `φ = 2π(u − ½)`, `θ = πv`. A rotation α turns the whole map about +y
//! (counter-clockwise seen from above, the right-hand rule): the map texel
//! for world direction d is looked up at `R_y(−α) d`.
//!
//! Importance sampling: a 2-D piecewise-constant distribution over the
//! texels with weights luminance × sin θ (of the texel centre); since
//! `dω = sin θ dθ dφ = 2π² sin θ du dv`, the solid-angle pdf is
//! `p(u, v) / (2π² sin θ)`. Radiance is looked up by nearest texel, so it is
//! piecewise constant like the pdf.

use super::LightSample;
use crate::Rgb;
use crate::color::luminance;
use crate::sampling::{Distribution2D, UNIFORM_SPHERE_PDF, square_to_uniform_sphere};
use glam::{Quat, Vec2, Vec3};
use std::f32::consts::PI;
use std::sync::Arc;

/// An equirectangular environment map.
#[derive(Clone)]
pub struct EnvironmentMap {
    width: usize,
    height: usize,
    /// Row-major texels, already multiplied by the scale.
    texels: Vec<Rgb>,
    /// World → map rotation (R_y(−α)) and its inverse.
    to_map: Quat,
    to_world: Quat,
    distribution: Distribution2D,
    /// Mean radiance over the sphere (solid-angle weighted).
    mean: Rgb,
}

impl std::fmt::Debug for EnvironmentMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EnvironmentMap")
            .field("width", &self.width)
            .field("height", &self.height)
            .field("mean", &self.mean)
            .finish_non_exhaustive()
    }
}

impl PartialEq for EnvironmentMap {
    fn eq(&self, o: &Self) -> bool {
        (self.width, self.height) == (o.width, o.height)
            && self.to_map == o.to_map
            && self.texels == o.texels
    }
}

impl EnvironmentMap {
    /// `texels` row-major, `width × height` (both ≥ 1), radiance
    /// [W/(sr·m²)] before `scale`; `rotation` [rad] about +y.
    pub fn new(width: usize, height: usize, texels: Vec<Rgb>, scale: Rgb, rotation: f32) -> Self {
        assert!(width > 0 && height > 0 && texels.len() == width * height);
        let texels: Vec<Rgb> = texels
            .into_iter()
            .map(|t| (t * scale).max(Rgb::ZERO))
            .map(|t| if t.is_finite() { t } else { Rgb::ZERO })
            .collect();
        let mut weights = Vec::with_capacity(texels.len());
        let mut sum = glam::DVec3::ZERO;
        let mut sin_sum = 0.0f64;
        for row in 0..height {
            let sin = (PI * (row as f32 + 0.5) / height as f32).sin();
            for t in &texels[row * width..(row + 1) * width] {
                weights.push(luminance(*t) * sin);
                sum += t.as_dvec3() * sin as f64;
                sin_sum += sin as f64;
            }
        }
        let to_world = Quat::from_rotation_y(rotation);
        Self {
            width,
            height,
            distribution: Distribution2D::new(width, height, &weights),
            mean: (sum / sin_sum.max(1e-300)).as_vec3(),
            texels,
            to_map: to_world.inverse(),
            to_world,
        }
    }

    pub fn width(&self) -> usize {
        self.width
    }

    pub fn height(&self) -> usize {
        self.height
    }

    /// Mean radiance over the sphere of directions.
    pub fn mean_radiance(&self) -> Rgb {
        self.mean
    }

    /// The texels, row-major (row 0 the zenith), scale applied: the
    /// piecewise-constant radiance [`EnvironmentMap::eval`] returns.
    pub fn texels(&self) -> &[Rgb] {
        &self.texels
    }

    /// Map → world rotation (R_y(α)): the world direction of map direction
    /// `m` is `rotation() * m`.
    pub fn rotation(&self) -> Quat {
        self.to_world
    }

    /// Map coordinates (u, v) ∈ [0,1]² of a world direction.
    pub fn direction_to_uv(&self, d: Vec3) -> Vec2 {
        let m = self.to_map * d;
        // atan2 keeps θ accurate near the poles, where acos(y) is not.
        let theta = (m.x * m.x + m.z * m.z).sqrt().atan2(m.y);
        let phi = m.x.atan2(-m.z);
        Vec2::new(phi / (2.0 * PI) + 0.5, theta / PI)
    }

    /// World direction of map coordinates (u, v).
    pub fn uv_to_direction(&self, uv: Vec2) -> Vec3 {
        let phi = 2.0 * PI * (uv.x - 0.5);
        let theta = PI * uv.y;
        let (st, ct) = theta.sin_cos();
        self.to_world * Vec3::new(st * phi.sin(), ct, -st * phi.cos())
    }

    fn texel(&self, uv: Vec2) -> Rgb {
        let x = ((uv.x * self.width as f32) as usize).min(self.width - 1);
        let y = ((uv.y * self.height as f32) as usize).min(self.height - 1);
        self.texels[y * self.width + x]
    }

    /// Radiance arriving from world direction `d` (unit).
    pub fn eval(&self, d: Vec3) -> Rgb {
        self.texel(self.direction_to_uv(d))
    }

    /// Importance-sampled direction; `value` = L / pdf.
    pub fn sample_li(&self, u: [f32; 2]) -> Option<LightSample> {
        let (uv, p) = self.distribution.sample(u)?;
        let sin = (PI * uv.y).sin();
        if sin <= 0.0 || p <= 0.0 {
            return None;
        }
        let pdf = p / (2.0 * PI * PI * sin);
        Some(LightSample {
            wi: self.uv_to_direction(uv),
            distance: f32::INFINITY,
            value: self.texel(uv) / pdf,
            pdf,
            is_delta: false,
        })
    }

    /// Solid-angle density of [`EnvironmentMap::sample_li`] at `d`.
    pub fn pdf(&self, d: Vec3) -> f32 {
        let uv = self.direction_to_uv(d);
        let m = self.to_map * d;
        let sin = (m.x * m.x + m.z * m.z).sqrt();
        if sin <= 0.0 {
            return 0.0;
        }
        self.distribution.pdf(uv) / (2.0 * PI * PI * sin)
    }
}

/// The scene's environment as a light.
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    /// The same radiance from every direction (sampled uniformly over the
    /// sphere, pdf 1/4π).
    Constant(Rgb),
    Map(Arc<EnvironmentMap>),
}

impl Default for Environment {
    fn default() -> Self {
        Environment::Constant(Rgb::ZERO)
    }
}

impl Environment {
    /// Radiance arriving from direction `d` (what a ray that escapes sees).
    pub fn eval(&self, d: Vec3) -> Rgb {
        match self {
            Environment::Constant(l) => *l,
            Environment::Map(m) => m.eval(d),
        }
    }

    pub fn is_black(&self) -> bool {
        match self {
            Environment::Constant(l) => *l == Rgb::ZERO,
            Environment::Map(m) => m.mean_radiance() == Rgb::ZERO,
        }
    }

    pub fn sample_li(&self, u: [f32; 2]) -> Option<LightSample> {
        match self {
            Environment::Constant(l) => Some(LightSample {
                wi: square_to_uniform_sphere(u),
                distance: f32::INFINITY,
                value: *l / UNIFORM_SPHERE_PDF,
                pdf: UNIFORM_SPHERE_PDF,
                is_delta: false,
            }),
            Environment::Map(m) => m.sample_li(u),
        }
    }

    /// Solid-angle density of [`Environment::sample_li`] at `d`.
    pub fn pdf(&self, d: Vec3) -> f32 {
        match self {
            Environment::Constant(_) => UNIFORM_SPHERE_PDF,
            Environment::Map(m) => m.pdf(d),
        }
    }

    /// Power through a disk of the scene's radius r facing the light — the
    /// irradiance π L̄ over π r²: `Φ = π² r² L̄` (L̄ = mean radiance); used
    /// only to choose among lights.
    pub fn power(&self, scene_radius: f32) -> Rgb {
        let mean = match self {
            Environment::Constant(l) => *l,
            Environment::Map(m) => m.mean_radiance(),
        };
        mean * (PI * PI * scene_radius * scene_radius)
    }
}
