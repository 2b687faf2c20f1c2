//! The ambient-occlusion bake against closed forms: an open plane, a
//! right-angled inner edge and a three-plane corner.
//!
//! For a point on a floor with walls standing on it, AO rays of length D
//! that leave in direction d are occluded when they reach a wall within D.
//! By Nusselt's analogue the cosine-weighted measure of a set of directions
//! is the area of its projection onto the unit disk, so with u the
//! direction's component towards a wall at distance x, the occluded set is
//! the part of the disk with u > x/D and
//! `kA = 1 − area / π`; the segment beyond c has area
//! `acos c − c √(1 − c²)`.

mod common;

use common::*;
use glam::Vec3;
use penumbra_bake::{AoSettings, AtlasSettings, Density, bake_ao};
use penumbra_scene::{Material, Scene};

const D: f32 = 1.0;

fn settings(samples: u32) -> AoSettings {
    AoSettings {
        samples,
        distance: D,
        seed: 7,
    }
}

fn atlas(n: u32) -> AtlasSettings {
    AtlasSettings {
        density: Density::MaxSize(n),
        ..Default::default()
    }
}

/// Area of the unit disk beyond the chord u = c (0 for c ≥ 1).
fn segment(c: f64) -> f64 {
    if c >= 1.0 {
        return 0.0;
    }
    c.acos() - c * (1.0 - c * c).sqrt()
}

/// Area of {u > a, v > b} inside the unit disk: ∫_a^{√(1−b²)} (√(1−u²) − b) du
/// with the antiderivative F(u) = (u √(1−u²) + asin u) / 2.
fn quadrant(a: f64, b: f64) -> f64 {
    if a * a + b * b >= 1.0 {
        return 0.0;
    }
    let f = |u: f64| 0.5 * (u * (1.0 - u * u).sqrt() + u.asin());
    let u1 = (1.0 - b * b).sqrt();
    f(u1) - f(a) - b * (u1 - a)
}

/// Checks the bake against `expected(p)` at every baked texel that
/// `selected(p)` keeps: the mean error and the worst error in units of the
/// binomial standard deviation √(k(1−k)/N).
fn check(
    scene: &Scene,
    samples: u32,
    selected: impl Fn(Vec3) -> bool,
    expected: impl Fn(Vec3) -> f64,
) {
    let bake = bake_ao(scene, &settings(samples), &atlas(128), None).expect("bake");
    assert_eq!(bake.stats.invalid, 0, "no texel lies inside geometry here");
    let mut n = 0;
    let mut sum_err = 0.0;
    let mut worst: f64 = 0.0;
    for (t, p, _) in baked_points(scene, &bake) {
        if !selected(p) {
            continue;
        }
        let k = expected(p);
        let got = value(&bake, 0, &t).x as f64;
        let sigma = (k * (1.0 - k) / samples as f64).sqrt().max(1e-3);
        sum_err += got - k;
        worst = worst.max((got - k).abs() / sigma);
        n += 1;
    }
    assert!(n > 200, "only {n} texels tested");
    let mean = sum_err / n as f64;
    eprintln!("{n} texels: mean error {mean:+.5}, worst {worst:.2} σ");
    assert!(mean.abs() < 2e-3, "mean error {mean}");
    assert!(worst < 5.0, "worst error {worst} σ");
}

#[test]
fn an_open_plane_bakes_to_one_everywhere_and_dilation_covers_its_border() {
    let mut scene = Scene::default();
    add(
        &mut scene,
        floor(-2.0, 2.0, -2.0, 2.0),
        Material::lambert("f", Vec3::splat(0.5)),
    );
    let bake = bake_ao(&scene, &settings(16), &atlas(64), None).expect("bake");
    let page = &bake.maps[0].pages[0];
    let cov = &bake.coverage[0];
    let mut baked = 0;
    for y in 0..page.height {
        for x in 0..page.width {
            if cov.get(x, y).x != 1.0 {
                continue;
            }
            baked += 1;
            assert_eq!(page.get(x, y), Vec3::ONE, "texel ({x}, {y})");
            assert_eq!(bake.maps[0].variance[0].get(x, y), Vec3::ZERO);
            // Every texel a bilinear lookup here may read was filled.
            for (dx, dy) in [
                (-1i32, -1i32),
                (0, -1),
                (1, -1),
                (-1, 0),
                (1, 0),
                (-1, 1),
                (0, 1),
                (1, 1),
            ] {
                let (nx, ny) = (x as i32 + dx, y as i32 + dy);
                if nx >= 0 && ny >= 0 && (nx as u32) < page.width && (ny as u32) < page.height {
                    assert_eq!(
                        page.get(nx as u32, ny as u32),
                        Vec3::ONE,
                        "neighbour of ({x}, {y})"
                    );
                }
            }
        }
    }
    assert!(baked > 1000, "{baked} texels baked");
    assert_eq!(bake.stats.valid, baked);
}

#[test]
fn texels_at_a_right_angled_inner_edge_match_the_circular_segment() {
    // Floor x ∈ [0, 4], wall x = 0 of height 2: points with |z| < 1 see the
    // wall as an infinite one within D = 1.
    let mut scene = Scene::default();
    let m = Material::lambert("w", Vec3::splat(0.5));
    add(&mut scene, floor(0.0, 4.0, -2.0, 2.0), m.clone());
    add(&mut scene, wall_x(-2.0, 2.0, 2.0), m);
    check(
        &scene,
        1024,
        |p| p.y == 0.0 && p.z.abs() < 1.0 && p.x < 1.5,
        |p| 1.0 - segment(p.x as f64 / D as f64) / std::f64::consts::PI,
    );
}

#[test]
fn texels_in_a_three_plane_corner_match_the_union_of_two_segments() {
    let mut scene = Scene::default();
    let m = Material::lambert("w", Vec3::splat(0.5));
    add(&mut scene, floor(0.0, 4.0, 0.0, 4.0), m.clone());
    add(&mut scene, wall_x(0.0, 4.0, 2.0), m.clone());
    add(&mut scene, wall_z(0.0, 4.0, 2.0), m);
    check(
        &scene,
        1024,
        |p| p.y == 0.0 && p.x < 1.5 && p.z < 1.5,
        |p| {
            let (a, b) = (p.x as f64 / D as f64, p.z as f64 / D as f64);
            let occluded = segment(a) + segment(b) - quadrant(a, b);
            1.0 - occluded / std::f64::consts::PI
        },
    );
}

#[test]
fn the_closed_forms_themselves() {
    // Independent checks of the expected values: a wall at distance 0 hides
    // half the cosine-weighted hemisphere, a corner three quarters.
    assert!((segment(0.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    assert!((quadrant(0.0, 0.0) - std::f64::consts::FRAC_PI_4).abs() < 1e-12);
    // Monte Carlo of the quadrant area at (0.3, 0.5).
    let (a, b) = (0.3, 0.5);
    let n = 2000;
    let mut hits = 0;
    for i in 0..n {
        for j in 0..n {
            let (u, v) = (
                -1.0 + 2.0 * (i as f64 + 0.5) / n as f64,
                -1.0 + 2.0 * (j as f64 + 0.5) / n as f64,
            );
            if u * u + v * v < 1.0 && u > a && v > b {
                hits += 1;
            }
        }
    }
    let area = 4.0 * hits as f64 / (n * n) as f64;
    assert!(
        (area - quadrant(a, b)).abs() < 1e-3,
        "{area} vs {}",
        quadrant(a, b)
    );
}

#[test]
fn the_bake_is_the_same_for_any_thread_count() {
    let mut scene = Scene::default();
    let m = Material::lambert("w", Vec3::splat(0.5));
    add(&mut scene, floor(0.0, 4.0, 0.0, 4.0), m.clone());
    add(&mut scene, wall_x(0.0, 4.0, 2.0), m);
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| bake_ao(&scene, &settings(8), &atlas(64), None).unwrap())
    };
    let (a, b) = (run(1), run(2));
    assert_eq!(a.maps[0].pages[0].pixels, b.maps[0].pages[0].pixels);
    assert_eq!(a.atlas, b.atlas);
}
