//! Environment maps from files, and the default light of a scene that has
//! none: glTF files usually carry no lights (viewers light them with an
//! environment), and an unlit scene would render black.

use crate::scene::Scene;
use penumbra_shading::Rgb;
use penumbra_shading::light::EnvironmentMap;
use std::path::Path;
use std::sync::Arc;

/// The built-in studio environment (`assets/studio.exr`, CC0; see
/// `assets/README.md`).
const STUDIO_EXR: &[u8] = include_bytes!("../assets/studio.exr");

/// Decodes a latitude–longitude image (`.hdr`, `.exr`, …) into an
/// environment map of radiance [W/(sr·m²)] times `scale`, turned by
/// `rotation` [rad] about +y. Negative values (lossy EXR compression such
/// as DWAB leaves tiny ones) become 0; a non-finite texel is an error.
pub fn environment_from_image(
    image: image::DynamicImage,
    scale: Rgb,
    rotation: f32,
) -> Result<EnvironmentMap, String> {
    let rgb = image.into_rgb32f();
    let (w, h) = (rgb.width() as usize, rgb.height() as usize);
    if w == 0 || h == 0 {
        return Err("the image is empty".into());
    }
    let texels: Vec<Rgb> = rgb
        .pixels()
        .map(|p| Rgb::new(p.0[0], p.0[1], p.0[2]).max(Rgb::ZERO))
        .collect();
    if let Some(i) = texels.iter().position(|t| !t.is_finite()) {
        return Err(format!(
            "texel ({}, {}) is {:?}: radiance must be finite",
            i % w,
            i / w,
            texels[i].to_array()
        ));
    }
    Ok(EnvironmentMap::new(w, h, texels, scale, rotation))
}

/// Reads an environment map file (`.hdr` or `.exr`, lat-long); errors
/// name the file.
pub fn environment_from_file(path: &Path) -> Result<EnvironmentMap, String> {
    let image = image::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    environment_from_image(image, Rgb::ONE, 0.0).map_err(|e| format!("{}: {e}", path.display()))
}

/// The built-in studio environment, white-balanced and normalised: each
/// channel is divided by its mean radiance over the sphere, so the mean is
/// 1 in every channel and a white Lambertian surface open to the whole
/// environment has radiance 1.
pub fn studio_environment() -> EnvironmentMap {
    // The asset is compiled in and checked by a test; it cannot fail to decode.
    let studio = image::load_from_memory_with_format(STUDIO_EXR, image::ImageFormat::OpenExr)
        .map_err(|e| e.to_string())
        .and_then(|image| environment_from_image(image, Rgb::ONE, 0.0))
        .unwrap_or_else(|e| panic!("the built-in studio.exr: {e}"));
    let scale = Rgb::ONE / studio.mean_radiance().max(Rgb::splat(1e-6));
    EnvironmentMap::new(
        studio.width(),
        studio.height(),
        studio.texels().to_vec(),
        scale,
        0.0,
    )
}

/// The light sources of a scene, counted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LightCount {
    /// Point, spot and directional lights.
    pub lights: usize,
    /// Analytic area lights.
    pub area_lights: usize,
    /// Instances whose material emits.
    pub emitters: usize,
    /// Whether rays that leave the scene see light (a non-black background
    /// or an environment map).
    pub environment: bool,
}

impl LightCount {
    /// Counts the light sources of `scene`.
    pub fn of(scene: &Scene) -> Self {
        LightCount {
            lights: scene.lights.len(),
            area_lights: scene.area_lights.len(),
            emitters: scene
                .instances
                .iter()
                .filter(|i| scene.instance_material(i).is_emissive())
                .count(),
            environment: scene.environment_map.is_some() || scene.background.max_element() > 0.0,
        }
    }

    /// Whether nothing lights the scene.
    pub fn is_dark(&self) -> bool {
        self.lights == 0 && self.area_lights == 0 && self.emitters == 0 && !self.environment
    }
}

/// What lights the environment of a render (`--environment`).
#[derive(Clone, Debug, Default, PartialEq)]
pub enum EnvironmentChoice {
    /// The scene's own; the built-in studio environment if nothing lights the scene.
    #[default]
    Default,
    /// The scene's own, even if nothing lights it.
    None,
    /// The built-in studio environment replaces the scene's.
    Studio,
    /// This map replaces the scene's environment.
    File(std::path::PathBuf),
}

/// Applies `choice` to `scene`; returns a sentence to tell the user when
/// penumbra added or replaced the light.
pub fn apply_environment(
    scene: &mut Scene,
    choice: &EnvironmentChoice,
) -> Result<Option<String>, String> {
    match choice {
        EnvironmentChoice::None => Ok(None),
        EnvironmentChoice::Studio => {
            scene.environment_map = Some(Arc::new(studio_environment()));
            Ok(Some(
                "the environment is the built-in studio (from --environment studio)".into(),
            ))
        }
        EnvironmentChoice::Default => {
            let count = LightCount::of(scene);
            if count.lights == 0
                && count.area_lights == 0
                && !count.environment
                && count.emitters > 0
            {
                return Ok(Some(format!(
                    "the scene is lit only by its {} emissive instance(s); --environment studio adds the built-in studio light",
                    count.emitters
                )));
            }
            if !count.is_dark() {
                return Ok(None);
            }
            scene.environment_map = Some(Arc::new(studio_environment()));
            Ok(Some(
                "the scene has no lights, no emitters and no environment; it is lit by the built-in studio environment (CC0; --environment none renders it black, --environment FILE.hdr uses another)".into(),
            ))
        }
        EnvironmentChoice::File(path) => {
            scene.environment_map = Some(Arc::new(environment_from_file(path)?));
            Ok(Some(format!(
                "the environment is {} (from --environment)",
                path.display()
            )))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Material, primitives};
    use glam::{Mat4, Vec3};

    #[test]
    fn the_studio_is_a_neutral_bright_environment() {
        let env = studio_environment();
        assert_eq!((env.width(), env.height()), (1024, 512));
        // White-balanced to mean radiance 1: the mean of the texels
        // weighted by their solid angle (sin θ per row), computed here.
        let (w, h) = (env.width(), env.height());
        let (mut sum, mut weight) = (glam::DVec3::ZERO, 0.0);
        for (i, t) in env.texels().iter().enumerate() {
            let theta = std::f64::consts::PI * ((i / w) as f64 + 0.5) / h as f64;
            sum += t.as_dvec3() * theta.sin();
            weight += theta.sin();
        }
        let mean = sum / weight;
        assert!(
            (mean - glam::DVec3::ONE).abs().max_element() < 1e-3,
            "{mean:?}"
        );
        // A studio: bright soft boxes against a darker room.
        let peak = env
            .texels()
            .iter()
            .map(|t| t.max_element())
            .fold(0.0, f32::max);
        assert!(peak > 50.0, "{peak}");
    }

    #[test]
    fn only_an_unlit_scene_gets_the_studio() {
        let mut scene = Scene::default();
        scene.add_material(Material::default_grey());
        scene.add_mesh(primitives::sphere(Vec3::ZERO, 1.0, 4), Mat4::IDENTITY);
        assert!(LightCount::of(&scene).is_dark());
        let said = apply_environment(&mut scene, &EnvironmentChoice::Default).unwrap();
        assert!(said.unwrap().contains("no lights"));
        assert!(scene.environment_map.is_some());

        let mut lit = Scene::default();
        let glow = lit.add_material(Material {
            emission: Rgb::splat(1.0),
            ..Material::lambert("glow", Vec3::ONE)
        });
        let mut mesh = primitives::sphere(Vec3::ZERO, 1.0, 4);
        mesh.material = glow;
        lit.add_mesh(mesh, Mat4::IDENTITY);
        assert_eq!(LightCount::of(&lit).emitters, 1);
        let said = apply_environment(&mut lit, &EnvironmentChoice::Default).unwrap();
        assert!(said.unwrap().contains("--environment studio"));
        assert!(lit.environment_map.is_none());
        apply_environment(&mut lit, &EnvironmentChoice::Studio).unwrap();
        assert!(lit.environment_map.is_some());

        let mut dark = Scene::default();
        assert_eq!(
            apply_environment(&mut dark, &EnvironmentChoice::None),
            Ok(None)
        );
        assert!(dark.environment_map.is_none());
        let e = apply_environment(&mut dark, &EnvironmentChoice::File("nope.hdr".into()));
        assert!(e.unwrap_err().contains("nope.hdr"));
    }
}
