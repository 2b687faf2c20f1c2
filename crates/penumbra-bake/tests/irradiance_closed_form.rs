//! The light-map bake against closed forms: a point light over a plane
//! (`E = I cos θ / r²`), a closed box of uniform emission and albedo
//! (`E = π Le / (1 − ρ)`: every surface has radiance L = Le + ρ L), and
//! per-light maps that add up to the total.

mod common;

use common::*;
use glam::Vec3;
use penumbra_bake::{AtlasSettings, Density, LightmapSettings, bake_lightmap};
use penumbra_scene::{Material, Scene, SceneLight, primitives};
use penumbra_shading::light::{Light, PointLight};

fn atlas(n: u32) -> AtlasSettings {
    AtlasSettings {
        density: Density::MaxSize(n),
        ..Default::default()
    }
}

#[test]
fn a_point_light_over_a_plane_gives_the_inverse_square_law() {
    let mut scene = Scene::default();
    add(
        &mut scene,
        floor(-2.0, 2.0, -2.0, 2.0),
        Material::lambert("f", Vec3::splat(0.7)),
    );
    let (light, i) = (Vec3::new(0.3, 1.0, -0.2), Vec3::new(10.0, 5.0, 2.0));
    scene.lights.push(SceneLight {
        name: "lamp".into(),
        light: Light::Point(PointLight::new(light, i)),
    });
    let s = LightmapSettings {
        samples: 4,
        ..Default::default()
    };
    let bake = bake_lightmap(&scene, &s, &atlas(64), None).expect("bake");
    let mut worst: f32 = 0.0;
    let points = baked_points(&scene, &bake);
    assert!(points.len() > 1000);
    for (t, p, n) in points {
        let d = light - p;
        let expected = i * (n.dot(d.normalize()) / d.length_squared());
        let got = value(&bake, 0, &t);
        worst = worst.max(((got - expected) / expected).abs().max_element());
    }
    eprintln!("worst relative error {worst:e}");
    assert!(worst < 0.01, "{worst}");
}

#[test]
fn a_closed_box_of_uniform_emission_converges_to_pi_le_over_one_minus_rho() {
    let (le, rho) = (Vec3::new(1.0, 2.0, 0.5), 0.5);
    let mut scene = Scene::default();
    // A cube seen from inside: the outward box with its faces turned in.
    let walls = flipped(primitives::cuboid(Vec3::splat(-1.0), Vec3::splat(1.0)));
    add(
        &mut scene,
        walls,
        Material {
            emission: le,
            double_sided: false,
            ..Material::lambert("glow", Vec3::splat(rho))
        },
    );
    let s = LightmapSettings {
        samples: 64,
        bounces: 64,
        ..Default::default()
    };
    let bake = bake_lightmap(&scene, &s, &atlas(48), None).expect("bake");
    assert_eq!(bake.stats.invalid, 0);
    let expected = le * (std::f32::consts::PI / (1.0 - rho));
    let points = baked_points(&scene, &bake);
    let mut sum = Vec3::ZERO;
    let mut outliers = 0;
    for (t, _, _) in &points {
        let got = value(&bake, 0, t);
        let sigma = variance(&bake, 0, t).max(Vec3::splat(1e-12)).powf(0.5);
        sum += got;
        if ((got - expected).abs() / sigma).max_element() > 4.0 {
            outliers += 1;
        }
    }
    let mean = sum / points.len() as f32;
    let ratio = mean / expected;
    eprintln!(
        "{} texels, mean / expected = {ratio}, {outliers} beyond 4σ",
        points.len()
    );
    assert!((ratio - Vec3::ONE).abs().max_element() < 0.01, "{ratio}");
    assert!(outliers * 200 < points.len(), "{outliers} texels beyond 4σ");
}

/// A floor, a wall (so light bounces), a point light and an emissive quad.
fn two_light_scene() -> Scene {
    let mut scene = Scene::default();
    let m = Material::lambert("w", Vec3::new(0.8, 0.6, 0.4));
    add(&mut scene, floor(0.0, 3.0, -1.5, 1.5), m.clone());
    add(&mut scene, wall_x(-1.5, 1.5, 2.0), m);
    // A small emitter above the floor, facing down.
    let lamp = primitives::quad(
        Vec3::new(1.5, 1.5, -0.25),
        Vec3::new(0.5, 0.0, 0.0),
        Vec3::new(0.0, 0.0, 0.5),
    );
    add(
        &mut scene,
        lamp,
        Material::emitter("panel", Vec3::new(4.0, 4.0, 3.0)),
    );
    scene.lights.push(SceneLight {
        name: "key".into(),
        light: Light::Point(PointLight::new(Vec3::new(2.5, 1.0, 1.0), Vec3::splat(2.0))),
    });
    scene
}

#[test]
fn per_light_maps_add_up_to_the_total_within_noise() {
    let scene = two_light_scene();
    let base = LightmapSettings {
        samples: 64,
        bounces: 3,
        ..Default::default()
    };
    let total = bake_lightmap(
        &scene,
        &LightmapSettings { seed: 1, ..base },
        &atlas(48),
        None,
    )
    .expect("total");
    let split = bake_lightmap(
        &scene,
        &LightmapSettings {
            seed: 2,
            per_light: true,
            ..base
        },
        &atlas(48),
        None,
    )
    .expect("per light");
    assert_eq!(split.maps.len(), 3, "total, the point light, the panel");
    let names: Vec<_> = split.maps.iter().filter_map(|m| m.light.clone()).collect();
    assert!(names.iter().any(|n| n.contains("key")), "{names:?}");
    assert!(names.iter().any(|n| n.contains("panel")), "{names:?}");
    let points = baked_points(&scene, &split);
    let (mut outliers, mut n) = (0, 0);
    for (t, _, _) in &points {
        let parts: Vec3 = (1..split.maps.len()).map(|m| value(&split, m, t)).sum();
        // The split run's own total is its parts, sample by sample.
        let own = value(&split, 0, t);
        assert!(
            (parts - own).abs().max_element() <= 1e-4 * own.max_element().max(1e-3),
            "{parts} vs {own}"
        );
        // Against an independent run: within 3σ of both estimates.
        let other = value(&total, 0, t);
        let sigma = (variance(&total, 0, t) + variance(&split, 0, t)).powf(0.5);
        n += 1;
        if ((parts - other).abs() - 3.0 * sigma).max_element() > 1e-6 {
            outliers += 1;
        }
    }
    eprintln!("{outliers} of {n} texels beyond 3σ");
    // 3σ in each of three channels: about 0.8 % of texels by chance.
    assert!(outliers * 100 < 3 * n, "{outliers} of {n}");
}

#[test]
fn indirect_only_leaves_out_exactly_the_direct_light() {
    let scene = two_light_scene();
    let s = LightmapSettings {
        samples: 32,
        bounces: 0,
        indirect_only: true,
        ..Default::default()
    };
    // With no bounces there is no indirect light at all.
    let bake = bake_lightmap(&scene, &s, &atlas(32), None).expect("bake");
    assert!(
        bake.maps[0].pages[0]
            .pixels
            .iter()
            .all(|&p| p == Vec3::ZERO)
    );
    // With bounces, indirect + direct-only = full, within noise.
    let run = |bounces, indirect_only, seed| {
        bake_lightmap(
            &scene,
            &LightmapSettings {
                samples: 64,
                bounces,
                indirect_only,
                seed,
                per_light: false,
            },
            &atlas(32),
            None,
        )
        .unwrap()
    };
    let (full, direct, indirect) = (run(2, false, 3), run(0, false, 4), run(2, true, 5));
    let mut sums = [Vec3::ZERO; 2];
    for (t, _, _) in baked_points(&scene, &full) {
        sums[0] += value(&full, 0, &t);
        sums[1] += value(&direct, 0, &t) + value(&indirect, 0, &t);
    }
    let ratio = sums[1] / sums[0];
    assert!((ratio - Vec3::ONE).abs().max_element() < 0.01, "{ratio}");
    assert!(sums[1].x > 1.05 * (sums[1].x - sums[0].x).abs());
}
