//! The scene as the forward pass sees it: GPU lights, materials and
//! instances, and warnings for what the raster path approximates.

use crate::gpu::{GpuInstance, GpuLight, GpuMaterial, MODEL_METALLIC_ROUGHNESS};
use crate::shaders::{FORWARD_BINDS_MATERIAL_TABLES, FORWARD_WGSL};
use penumbra_scene::Scene;
use penumbra_shading::bsdf::DELTA_ALPHA;

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
            warnings.extend(pass_warnings(&m.name, &g, m.bsdf.flags().transmission));
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

/// Where the forward pass does not give a material's exact WGSL twin what
/// it needs: the Kulla–Conty table (binding 8, see
/// [`crate::shaders::FORWARD_BINDS_MATERIAL_TABLES`]) and, for transmissive
/// materials seen from their back, `material_seen_from_back` (η → 1/η, as the
/// CPU's `seen_from_back`), detected in the pass's source.
fn pass_warnings(name: &str, g: &GpuMaterial, transmissive: bool) -> Vec<String> {
    let mut out = Vec::new();
    let diffuse = (1.0 - g.metallic) * (1.0 - g.transmission) > 0.0;
    if !FORWARD_BINDS_MATERIAL_TABLES
        && g.model == MODEL_METALLIC_ROUGHNESS
        && g.alpha >= DELTA_ALPHA
        && diffuse
    {
        out.push(format!(
            "raster: material '{name}' (metallic-roughness): the diffuse base is weighted by the smooth-surface specular albedo (the forward pass does not bind the Kulla-Conty table yet)"
        ));
    }
    if transmissive && !FORWARD_WGSL.contains("material_seen_from_back(") {
        out.push(format!(
            "raster: material '{name}': seen from its back it is shaded with its front-side index of refraction (the forward pass does not call material_seen_from_back yet)"
        ));
    }
    out
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
    use penumbra_shading::bsdf::{Bsdf, MetallicRoughness, Mirror, RoughDielectric};
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
        // What the forward pass does not wire up yet is reported.
        scene.add_material(Material {
            bsdf: Bsdf::MetallicRoughness(MetallicRoughness::new(Vec3::ONE, 0.0, 0.5)),
            ..Material::lambert("plastic", Vec3::ONE)
        });
        scene.add_material(Material {
            bsdf: Bsdf::RoughDielectric(RoughDielectric::new(1.5, 0.1)),
            ..Material::lambert("frosted", Vec3::ONE)
        });
        let w = SceneData::from_scene(&scene).warnings.join("\n");
        assert_eq!(
            w.contains("'plastic' (metallic-roughness)"),
            !FORWARD_BINDS_MATERIAL_TABLES,
            "{w}"
        );
        assert_eq!(
            w.contains("'frosted': seen from its back"),
            !FORWARD_WGSL.contains("material_seen_from_back("),
            "{w}"
        );
        assert!(w.contains("area light"), "{w}");
        assert!(w.contains("emissive"), "{w}");
    }
}
