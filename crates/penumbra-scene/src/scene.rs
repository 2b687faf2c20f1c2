//! The scene: what every backend renders.

use crate::camera::Camera;
use crate::material::Material;
use crate::mesh::{Instance, Mesh};
use crate::settings::RenderSettings;
use crate::texture::Texture;
use glam::Vec3;
use penumbra_shading::Rgb;
use penumbra_shading::light::{AreaLight, Environment, EnvironmentMap, Light};
use std::sync::Arc;

/// A named abstract light.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneLight {
    pub name: String,
    pub light: Light,
}

/// A named analytic area light (sphere, disk or quad).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneAreaLight {
    pub name: String,
    pub light: AreaLight,
}

/// Everything a renderer needs. Emissive meshes are area lights too: the
/// instances whose material has non-zero emission.
/// A camera a scene file defines, with its name and the aspect ratio
/// (width / height) it asks for, if any.
#[derive(Clone, Debug, PartialEq)]
pub struct NamedCamera {
    pub name: String,
    pub camera: Camera,
    pub aspect: Option<f32>,
}

#[derive(Clone, Debug, Default)]
pub struct Scene {
    pub meshes: Vec<Mesh>,
    pub instances: Vec<Instance>,
    pub materials: Vec<Material>,
    pub textures: Vec<Texture>,
    pub lights: Vec<SceneLight>,
    /// Analytic emitting shapes, intersected beside the meshes.
    pub area_lights: Vec<SceneAreaLight>,
    /// `None` until a loader or the user sets one; renderers then need a default.
    pub camera: Option<Camera>,
    /// Every camera the file defines, in file order (`camera` is the first
    /// unless one is picked with [`Scene::use_camera`]).
    pub cameras: Vec<NamedCamera>,
    /// Constant radiance of the background / environment [W/(sr·m²)],
    /// used when there is no `environment_map`.
    pub background: Rgb,
    /// Equirectangular environment map; replaces `background` when set.
    pub environment_map: Option<Arc<EnvironmentMap>>,
    pub settings: RenderSettings,
    /// Non-fatal problems found while loading (approximations, skipped data).
    pub warnings: Vec<String>,
}

impl Scene {
    /// Makes the file camera named `which`, or with index `which`, the
    /// scene's camera; its aspect ratio, if it gives one, sets the image
    /// height for a width of 512 (as loading does for the first camera).
    /// The error lists the cameras there are.
    pub fn use_camera(&mut self, which: &str) -> Result<(), String> {
        let found = match which.trim().parse::<usize>() {
            Ok(i) => self.cameras.get(i),
            Err(_) => self.cameras.iter().find(|c| c.name == which),
        };
        let Some(c) = found.cloned() else {
            let names: Vec<String> = self
                .cameras
                .iter()
                .enumerate()
                .map(|(i, c)| format!("{i}: '{}'", c.name))
                .collect();
            return Err(if names.is_empty() {
                format!("the scene defines no camera, so there is no camera '{which}'")
            } else {
                format!(
                    "the scene has no camera '{which}'; its cameras are {}",
                    names.join(", ")
                )
            });
        };
        self.set_camera(&c);
        Ok(())
    }

    /// Makes `c` the scene's camera; its aspect ratio, if it gives one, sets
    /// the image height for a width of 512.
    pub fn set_camera(&mut self, c: &NamedCamera) {
        self.camera = Some(c.camera);
        if let Some(a) = c.aspect {
            self.settings.width = 512;
            self.settings.height = ((512.0 / a).round() as u32).clamp(1, 16384);
        }
    }

    /// World-space bounds (min, max) of all instances and analytic area
    /// lights; `None` if there are none.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for inst in &self.instances {
            for &p in &self.meshes[inst.mesh].positions {
                let w = inst.transform.transform_point3(p);
                lo = lo.min(w);
                hi = hi.max(w);
            }
        }
        for l in &self.area_lights {
            let (a, b) = l.light.shape.bounds();
            lo = lo.min(a);
            hi = hi.max(b);
        }
        (lo.x <= hi.x).then_some((lo, hi))
    }

    /// The environment seen by rays that escape: the map, else the
    /// constant background.
    pub fn environment(&self) -> Environment {
        match &self.environment_map {
            Some(m) => Environment::Map(m.clone()),
            None => Environment::Constant(self.background),
        }
    }

    /// Total number of triangles over all instances.
    pub fn triangle_count(&self) -> usize {
        self.instances
            .iter()
            .map(|i| self.meshes[i.mesh].indices.len())
            .sum()
    }

    /// World-space surface area of an instance [scene units²].
    pub fn instance_area(&self, inst: &Instance) -> f32 {
        let mesh = &self.meshes[inst.mesh];
        let world = |i: u32| inst.transform.transform_point3(mesh.positions[i as usize]);
        mesh.indices
            .iter()
            .map(|t| {
                0.5 * (world(t[1]) - world(t[0]))
                    .cross(world(t[2]) - world(t[0]))
                    .length()
            })
            .sum()
    }

    /// Material used by an instance (its override, else its mesh's).
    pub fn instance_material(&self, inst: &Instance) -> &Material {
        &self.materials[inst.material.unwrap_or(self.meshes[inst.mesh].material)]
    }

    /// Adds a mesh and one identity instance of it; returns the mesh index.
    pub fn add_mesh(&mut self, mesh: Mesh, transform: glam::Mat4) -> usize {
        self.meshes.push(mesh);
        let id = self.meshes.len() - 1;
        self.instances.push(Instance::new(id, transform));
        id
    }

    /// Adds a material, returning its id.
    pub fn add_material(&mut self, m: Material) -> usize {
        self.materials.push(m);
        self.materials.len() - 1
    }
}
