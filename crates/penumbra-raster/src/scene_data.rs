//! The scene as the forward pass sees it: GPU lights, materials and
//! instances, and warnings for what the raster path approximates.

use crate::gpu::{GpuInstance, GpuLight, GpuMaterial};
use penumbra_scene::Scene;

/// The scene as the forward pass sees it, and what it approximates.
#[derive(Clone, Debug, Default)]
pub struct SceneData {
    pub lights: Vec<GpuLight>,
    pub materials: Vec<GpuMaterial>,
    pub instances: Vec<GpuInstance>,
    /// What the raster path renders differently from the CPU `local`
    /// integrator for this scene.
    pub warnings: Vec<String>,
}

impl SceneData {
    pub fn from_scene(scene: &Scene) -> Self {
        let mut warnings = Vec::new();
        let mut materials = Vec::with_capacity(scene.materials.len());
        for m in &scene.materials {
            let (g, exact) = GpuMaterial::from_bsdf(&m.bsdf, m.emission, m.double_sided);
            if !exact {
                warnings.push(format!(
                    "raster: material '{}' ({}) has no exact WGSL twin yet",
                    m.name,
                    bsdf_name(&m.bsdf)
                ));
            }
            if m.albedo_texture.is_some() || m.metallic_roughness_texture.is_some() {
                warnings.push(format!(
                    "raster: material '{}': textures are ignored (untextured factors used)",
                    m.name
                ));
            }
            materials.push(g);
        }
        if materials.is_empty() {
            // Storage bindings cannot be empty.
            materials.push(GpuMaterial::default());
        }
        let instances = scene
            .instances
            .iter()
            .map(|inst| {
                let material = inst.material.unwrap_or(scene.meshes[inst.mesh].material);
                GpuInstance::new(
                    inst.transform,
                    inst.normal_matrix(),
                    material as u32,
                    scene.meshes[inst.mesh].normals.is_some(),
                )
            })
            .collect();
        let lights: Vec<GpuLight> = scene
            .lights
            .iter()
            .map(|l| GpuLight::from_light(&l.light))
            .collect();
        if !scene.area_lights.is_empty() {
            warnings.push(format!(
                "raster: {} analytic area light(s) are neither drawn nor lit from (abstract lights only)",
                scene.area_lights.len()
            ));
        }
        if scene.materials.iter().any(|m| m.is_emissive()) {
            warnings.push(
                "raster: emissive surfaces are drawn with their emission but do not light other surfaces"
                    .to_string(),
            );
        }
        if scene.environment_map.is_some() {
            warnings.push(
                "raster: the environment map is not drawn or lit from; the background colour is used"
                    .to_string(),
            );
        }
        Self {
            lights,
            materials,
            instances,
            warnings,
        }
    }
}

fn bsdf_name(b: &penumbra_shading::bsdf::Bsdf) -> &'static str {
    use penumbra_shading::bsdf::Bsdf;
    match b {
        Bsdf::Lambert(_) => "Lambert",
        Bsdf::PhongBlinn(_) => "Phong-Blinn",
        Bsdf::Mirror(_) => "mirror",
        Bsdf::Conductor(_) => "conductor",
        Bsdf::Dielectric(_) => "dielectric",
        Bsdf::RoughConductor(_) => "rough conductor",
        Bsdf::RoughDielectric(_) => "rough dielectric",
        Bsdf::MetallicRoughness(_) => "metallic-roughness",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Mat4, Vec3};
    use penumbra_scene::{Material, SceneAreaLight, primitives};
    use penumbra_shading::bsdf::{Bsdf, Mirror};
    use penumbra_shading::light::{AreaLight, Shape};

    #[test]
    fn scene_data_warns_about_what_it_approximates() {
        let mut scene = Scene::default();
        let lambert = scene.add_material(Material::lambert("white", Vec3::ONE));
        let mut mesh = primitives::sphere(Vec3::ZERO, 1.0, 4);
        mesh.material = lambert;
        scene.add_mesh(mesh, Mat4::IDENTITY);
        let data = SceneData::from_scene(&scene);
        assert!(data.warnings.is_empty(), "{:?}", data.warnings);
        assert_eq!((data.instances.len(), data.materials.len()), (1, 1));

        scene.add_material(Material {
            bsdf: Bsdf::Mirror(Mirror::new(Vec3::ONE)),
            ..Material::lambert("chrome", Vec3::ONE)
        });
        scene.add_material(Material::emitter("lamp", Vec3::splat(5.0)));
        scene.area_lights.push(SceneAreaLight {
            name: "ball".into(),
            light: AreaLight {
                shape: Shape::Sphere {
                    center: Vec3::Y,
                    radius: 0.1,
                },
                radiance: Vec3::ONE,
                two_sided: false,
            },
        });
        let w = SceneData::from_scene(&scene).warnings.join("\n");
        // Every model has an exact twin (a mirror reflects no abstract light,
        // as in the CPU `local` integrator): no material warning.
        assert!(!w.contains("chrome"), "{w}");
        assert!(w.contains("area light"), "{w}");
        assert!(w.contains("emissive"), "{w}");
    }
}
