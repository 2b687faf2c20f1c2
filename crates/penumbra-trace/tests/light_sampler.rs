//! The light sampler on its own: which scene lights it can choose and
//! names, where it samples emissive triangles (their front side, points
//! on the triangle, the area-to-solid-angle density), and how it weights
//! textured emitters (by their mean emission over each triangle).

mod common;

use common::*;
use glam::{Affine2, Vec2, Vec3};
use penumbra_scene::texture::Wrap;
use penumbra_scene::{Material, Mesh, Scene, SceneLight, Texture};
use penumbra_shading::Rgb;
use penumbra_shading::light::{Light, PointLight, Shape};
use penumbra_trace::accel::BuildQuality;
use penumbra_trace::geometry::SceneGeometry;
use penumbra_trace::lights::{Emitter, LightSampler, LightSource};

/// A unit quad at height `y` whose front faces down (−y): corners x, z in
/// [x0, x0 + 1] × [0, 1].
fn ceiling_quad(x0: f32, y: f32, material: usize) -> Mesh {
    quad(Vec3::new(x0, y, 0.0), Vec3::X, Vec3::Z, material)
}

fn sampler(scene: &Scene) -> (SceneGeometry, LightSampler) {
    let geometry = SceneGeometry::build(scene, BuildQuality::Fast).unwrap();
    let lights = LightSampler::new(scene, &geometry);
    (geometry, lights)
}

#[test]
fn every_light_that_emits_is_a_source_once() {
    let mut scene = Scene::default();
    let floor = lambert(&mut scene, 0.5);
    let glow = scene.add_material(Material::emitter("glow", Rgb::splat(2.0)));
    add(&mut scene, quad(Vec3::ZERO, Vec3::Z, Vec3::X, floor));
    add(&mut scene, ceiling_quad(0.0, 2.0, glow));
    for (i, x) in [0.0f32, 1.0].into_iter().enumerate() {
        scene.lights.push(SceneLight {
            name: format!("point {i}"),
            light: Light::Point(PointLight::new(Vec3::new(x, 1.0, 0.0), Rgb::ONE)),
        });
    }
    for (name, le) in [("bright", 1.0), ("black", 0.0), ("sun", 3.0)] {
        let sphere = Shape::Sphere {
            center: Vec3::new(0.0, 5.0, 0.0),
            radius: 0.5,
        };
        scene.area_lights.push(area_light(name, sphere, le));
    }
    scene.background = Rgb::splat(0.1);
    let (geometry, lights) = sampler(&scene);
    assert!(!lights.is_empty());
    // The black sphere (area light 1) emits nothing: it is no source.
    assert_eq!(
        lights.sources(&geometry),
        [
            LightSource::Light(0),
            LightSource::Light(1),
            LightSource::AreaLight(0),
            LightSource::AreaLight(2),
            LightSource::EmissiveInstance(1),
            LightSource::Environment,
        ]
    );
    // Hits name their light; the floor's triangles are no light.
    for t in geometry.instance_triangles(0) {
        assert_eq!(lights.source(&geometry, Emitter::Triangle(t)), None);
    }
    let glowing = geometry.instance_triangles(1);
    assert_eq!(glowing.len(), 2);
    for t in glowing {
        assert_eq!(
            lights.source(&geometry, Emitter::Triangle(t)),
            Some(LightSource::EmissiveInstance(1))
        );
    }
    assert_eq!(
        lights.source(&geometry, Emitter::Shape(2)),
        Some(LightSource::AreaLight(2))
    );
    assert_eq!(
        lights.source(&geometry, Emitter::Environment),
        Some(LightSource::Environment)
    );
    // Entries: 2 points, 2 triangles, 2 spheres, the environment.
    assert_eq!(lights.source(&geometry, Emitter::Entry(7)), None);

    // Nothing that emits: nothing to sample.
    let mut dark = Scene::default();
    let m = lambert(&mut dark, 0.5);
    add(&mut dark, quad(Vec3::ZERO, Vec3::Z, Vec3::X, m));
    let (geometry, lights) = sampler(&dark);
    assert!(lights.is_empty());
    assert!(lights.sources(&geometry).is_empty());
    // One point light is enough.
    dark.lights.push(SceneLight {
        name: "p".into(),
        light: Light::Point(PointLight::new(Vec3::Y, Rgb::ONE)),
    });
    assert!(!sampler(&dark).1.is_empty());
}

/// A one-sided emissive quad (radiance 2, front facing down, triangles of
/// area ½) seen from below: every sample is a point of the quad, with
/// density d² / (A |cos θ_light|) times the selection probability ½ and
/// value L / pdf. From above, a one-sided light gives nothing; a
/// two-sided one gives the same density.
#[test]
fn triangle_lights_are_sampled_on_their_front_side() {
    for double_sided in [false, true] {
        let mut scene = Scene::default();
        let glow = scene.add_material(Material {
            double_sided,
            ..Material::emitter("glow", Rgb::splat(2.0))
        });
        add(&mut scene, ceiling_quad(0.0, 2.0, glow));
        let (geometry, lights) = sampler(&scene);
        for p in [Vec3::new(0.3, 0.0, 0.6), Vec3::new(0.5, 3.5, -0.5)] {
            let above = p.y > 2.0;
            for k in 0..64 {
                let u = [(k % 8) as f32 / 8.0 + 0.06, (k / 8) as f32 / 8.0 + 0.03];
                let chosen = lights.sample(&scene, &geometry, p, (k as f32 + 0.5) / 64.0, u);
                if above && !double_sided {
                    assert!(chosen.is_none(), "behind a one-sided light: {chosen:?}");
                    continue;
                }
                let c = chosen.expect("a sample in front of the light");
                assert_eq!(c.select_pdf, 0.5);
                let q = p + c.sample.wi * c.sample.distance;
                assert!((q.y - 2.0).abs() < 1e-5, "{q}");
                assert!(
                    (-1e-5..=1.0 + 1e-5).contains(&q.x) && (-1e-5..=1.0 + 1e-5).contains(&q.z),
                    "{q} is not on the quad"
                );
                let d = q - p;
                let pdf = d.length_squared() / (0.5 * (d.y.abs() / d.length()));
                assert!((c.sample.pdf / pdf - 1.0).abs() < 1e-4, "{c:?}: pdf {pdf}");
                assert!((c.sample.value.x * pdf / 2.0 - 1.0).abs() < 1e-4);
                assert!(!c.sample.is_delta);
            }
        }
        // A point on the light itself, where the sample lands (the Heitz
        // map sends (0, 0) to the first vertex): no direction, no sample.
        assert!(
            lights
                .sample(&scene, &geometry, Vec3::new(0.0, 2.0, 0.0), 0.1, [0.0, 0.0])
                .is_none()
        );
    }
}

/// Emitters are chosen in proportion to their power: for a textured one,
/// its radiance times the texture's mean over each triangle. The texture
/// reads u (a 256-texel ramp, linear between texel centres); the quad's u
/// runs from 0.1 to 0.9, so its triangles' means are the u of their
/// centroids, (0.1 + 0.9 + 0.9)/3 and (0.1 + 0.9 + 0.1)/3 (within the 16
/// stratified points' 2 %); an untextured quad of radiance 1 beside it
/// weighs 1 a triangle.
#[test]
fn textured_emitters_are_chosen_by_their_mean_emission() {
    let mut scene = Scene::default();
    scene.textures.push(Texture {
        name: "ramp".into(),
        width: 256,
        height: 1,
        texels: (0..256)
            .map(|i| Rgb::splat((i as f32 + 0.5) / 256.0))
            .collect(),
        wrap: [Wrap::ClampToEdge; 2],
        uv_transform: Affine2::IDENTITY,
        uv_set: 0,
    });
    let textured = scene.add_material(Material {
        emission_texture: Some(0),
        ..Material::emitter("textured", Rgb::ONE)
    });
    let plain = scene.add_material(Material::emitter("plain", Rgb::ONE));
    let mut ramp = ceiling_quad(0.0, 2.0, textured);
    ramp.uv0 = Some(
        [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .map(|(u, v)| Vec2::new(0.1 + 0.8 * u, v))
            .to_vec(),
    );
    add(&mut scene, ramp);
    add(&mut scene, ceiling_quad(2.0, 2.0, plain));
    let (geometry, lights) = sampler(&scene);
    // Selection probability of triangle t from the density of the point
    // straight above p, one unit away: pmf · 1 / (½ · 1).
    let pmf = |t: u32| {
        let [a, b, c] = geometry.triangles[t as usize];
        let q = (a + b + c) / 3.0;
        0.5 * lights.pdf_triangle(t, q - Vec3::Y, q, -Vec3::Y)
    };
    // Quad triangles (0, 1, 2) and (0, 2, 3): u at their vertices.
    let means = [(0.1 + 0.9 + 0.9) / 3.0, (0.1 + 0.9 + 0.1) / 3.0, 1.0, 1.0];
    let total: f32 = means.iter().sum();
    let triangles: Vec<u32> = [0, 1]
        .iter()
        .flat_map(|&i| geometry.instance_triangles(i))
        .collect();
    assert_eq!(triangles.len(), 4);
    for (&t, mean) in triangles.iter().zip(means) {
        let expected = mean / total;
        assert!(
            (pmf(t) / expected - 1.0).abs() < 0.02,
            "triangle {t}: pmf {} expected {expected}",
            pmf(t)
        );
    }
}
