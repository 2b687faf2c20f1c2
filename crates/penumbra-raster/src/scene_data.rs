//! The scene as the forward pass sees it: GPU lights, materials and
//! instances, and warnings for what the raster path approximates.
//!
//! Analytic area lights become two things: a point light with the shape's
//! far-field intensity ([`penumbra_shading::light::FarField`], appended after the abstract lights),
//! and a tessellated emitter (appended after the scene's instances, drawn
//! with its radiance, casting no shadow: it would hide its own point light).

use crate::gpu::{GpuEnvMaterial, GpuInstance, GpuLight, GpuMaterial};
use crate::passes::environment::env_material;
use glam::{Mat3, Mat4};
use penumbra_scene::{Material, Mesh, Scene, primitives};
use penumbra_shading::light::{AreaLight, Shape};

/// The scene as the forward pass sees it, and what it approximates.
#[derive(Clone, Debug, Default)]
pub struct SceneData {
    /// The abstract lights, then the area lights' far fields.
    pub lights: Vec<GpuLight>,
    pub materials: Vec<GpuMaterial>,
    /// The scene's instances, then one per emitter.
    pub instances: Vec<GpuInstance>,
    /// World-space meshes of the area lights (instances
    /// `scene.instances.len()..`), which cast no shadows.
    pub emitters: Vec<Mesh>,
    /// Per material (emitters of area lights included, which reflect
    /// nothing): what the environment light needs of it
    /// ([`crate::passes::environment`]).
    pub env_materials: Vec<GpuEnvMaterial>,
    /// What the raster path renders differently from the CPU `local`
    /// integrator for this scene.
    pub warnings: Vec<String>,
}

impl SceneData {
    /// The material models present, as the `1 << MODEL_*` mask the shaders'
    /// `MATERIAL_MODELS` constant takes.
    pub fn model_mask(&self) -> u32 {
        self.materials.iter().fold(0, |m, g| m | (1 << g.model))
    }

    pub fn from_scene(scene: &Scene) -> Self {
        let mut warnings = Vec::new();
        let mut materials = Vec::with_capacity(scene.materials.len());
        for m in &scene.materials {
            materials.push(GpuMaterial {
                cull_back_faces: m.cull_back_faces as u32,
                ..GpuMaterial::from_bsdf(&m.bsdf, m.emission, m.double_sided)
            });
        }
        warnings.extend(texture_warnings(scene));
        if materials.is_empty() {
            // Storage bindings cannot be empty.
            materials.push(GpuMaterial::default());
        }
        let mut instances: Vec<GpuInstance> = scene
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
        let mut lights: Vec<GpuLight> = scene
            .lights
            .iter()
            .map(|l| GpuLight::from_light(&l.light))
            .collect();
        let mut emitters = Vec::new();
        for l in &scene.area_lights {
            lights.push(GpuLight::from_far_field(&l.light.far_field()));
            let mut mesh = emitter_mesh(&l.light);
            // Spheres emit outwards only; disks and quads on both sides if
            // two-sided.
            let emitter = Material {
                double_sided: l.light.two_sided && !matches!(l.light.shape, Shape::Sphere { .. }),
                ..Material::emitter(&l.name, l.light.radiance)
            };
            let m = GpuMaterial::from_bsdf(&emitter.bsdf, emitter.emission, emitter.double_sided);
            mesh.material = materials.len();
            materials.push(m);
            instances.push(GpuInstance {
                light_shape: 1,
                ..GpuInstance::new(
                    Mat4::IDENTITY,
                    Mat3::IDENTITY,
                    mesh.material as u32,
                    mesh.normals.is_some(),
                )
            });
            emitters.push(mesh);
        }
        if !scene.area_lights.is_empty() {
            warnings.push(format!(
                "raster: {} analytic area light(s) shade as point lights with their far-field intensity (exact for a sphere seen whole by a Lambertian surface; disks and quads as Lambertian emitters, accurate far from them; shadows hard, from the centre)",
                scene.area_lights.len()
            ));
        }
        if scene.materials.iter().any(|m| m.is_emissive()) {
            warnings.push(
                "raster: emissive surfaces are drawn with their emission but do not light other surfaces"
                    .to_string(),
            );
        }
        let mut env_materials: Vec<GpuEnvMaterial> = scene
            .materials
            .iter()
            .map(|m| env_material(&m.bsdf))
            .collect();
        env_materials.resize(materials.len(), GpuEnvMaterial::default());
        warnings.extend(environment_warnings(scene));
        Self {
            lights,
            materials,
            instances,
            emitters,
            env_materials,
            warnings,
        }
    }
}

/// What the raster path does not texture as the CPU does: tinted
/// conductors (the CPU solves for a new n + iκ per texel), and textured
/// meshes without texture coordinates (the CPU reads the texture at the
/// hit's barycentrics; the raster path at (0, 0)).
fn texture_warnings(scene: &Scene) -> Vec<String> {
    use penumbra_shading::bsdf::Bsdf;
    let mut out = Vec::new();
    let textured = |m: &Material| {
        m.albedo_texture.is_some()
            || m.metallic_roughness_texture.is_some()
            || m.emission_texture.is_some()
    };
    for (i, m) in scene.materials.iter().enumerate() {
        let coloured = scene
            .meshes
            .iter()
            .any(|mesh| mesh.material == i && mesh.colors.is_some());
        if matches!(m.bsdf, Bsdf::Conductor(_) | Bsdf::RoughConductor(_))
            && (m.albedo_texture.is_some() || coloured)
        {
            out.push(format!(
                "raster: conductor '{}': its texture and vertex colours are ignored (untinted n + iκ)",
                m.name
            ));
        }
    }
    let bare = scene
        .instances
        .iter()
        .filter(|inst| {
            let mesh = &scene.meshes[inst.mesh];
            mesh.uv0.is_none() && textured(&scene.materials[inst.material.unwrap_or(mesh.material)])
        })
        .count();
    if bare > 0 {
        out.push(format!(
            "raster: {bare} textured instance(s) without texture coordinates read texel (0, 0)"
        ));
    }
    out
}

/// What the environment light approximates for `scene` (see
/// [`crate::passes::environment`]).
fn environment_warnings(scene: &Scene) -> Vec<String> {
    use penumbra_shading::bsdf::Bsdf;
    let env = scene.environment();
    if env.is_black() {
        return Vec::new();
    }
    let mut out = Vec::new();
    if scene.environment_map.is_some() {
        out.push(
            "raster: the environment map lights diffuse surfaces by its 9-coefficient spherical-harmonic irradiance and glossy ones by a prefiltered map (split sum)"
                .to_string(),
        );
    }
    let has = |f: fn(&Bsdf) -> bool| scene.materials.iter().any(|m| f(&m.bsdf));
    if has(
        |b| matches!(b, Bsdf::RoughConductor(c) if c.fresnel == penumbra_shading::bsdf::FresnelModel::Exact),
    ) {
        out.push(
            "raster: environment reflections of rough conductors use a Schlick-shaped split sum with F0 = F(cos 0) of n + iκ".to_string(),
        );
    }
    if has(|b| matches!(b, Bsdf::PhongBlinn(_))) {
        out.push(
            "raster: Phong–Blinn materials reflect the environment through a GGX lobe of α = √(2/(n+2)) scaled to ks × the lobe's normal-incidence albedo".to_string(),
        );
    }
    if has(|b| b.flags().transmission) {
        out.push(
            "raster: transmissive materials show the environment straight through (no refraction, no interior, no objects behind)".to_string(),
        );
    }
    out.push(
        "raster: environment light is not shadowed by the scene's geometry (only ambient occlusion darkens it: an AO bake or --ssao)".to_string(),
    );
    out
}

/// The emitting surface of an area light as a mesh (front side emitting).
fn emitter_mesh(light: &AreaLight) -> Mesh {
    match light.shape {
        Shape::Sphere { center, radius } => {
            primitives::sphere(center, radius, primitives::DEFAULT_SPHERE_RINGS)
        }
        Shape::Disk {
            center,
            normal,
            radius,
        } => primitives::disk(center, normal, radius, primitives::DEFAULT_DISK_SEGMENTS),
        Shape::Quad {
            corner,
            edge1,
            edge2,
        } => primitives::quad(corner, edge1, edge2),
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
