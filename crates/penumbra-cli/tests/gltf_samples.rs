//! Khronos glTF sample models (../shared/gltf-samples) rendered as a new
//! user would: a file without lights is lit by the default environment, a
//! file without a camera is framed from an oblique direction that keeps the
//! whole model in view at any aspect ratio, PNGs are exposed
//! automatically, and unlit materials show their base colour in both
//! engines.

mod common;

use common::{penumbra, stderr};
use penumbra_image::{Image, read_exr_layers};
use std::path::{Path, PathBuf};

fn sample(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/gltf-samples")
        .join(name);
    let gltf = dir.join("glTF").join(format!("{name}.gltf"));
    if gltf.exists() {
        gltf
    } else {
        dir.join("glTF-Binary").join(format!("{name}.glb"))
    }
}

/// Renders `model` to `out` (EXR with AOVs) and returns (beauty, normal, depth).
fn render(dir: &Path, model: &str, extra: &[&str], out: &str) -> (Image, Image, Image, String) {
    let path = sample(model);
    let mut args = vec!["render", path.to_str().unwrap(), "--spp", "4", "--aovs"];
    args.extend(extra);
    args.extend(["-o", out]);
    let o = penumbra(&args, dir);
    assert!(o.status.success(), "{model}: {}", stderr(&o));
    let mut layers = read_exr_layers(&dir.join(out)).unwrap();
    let mut take = |name: &str| {
        let i = layers.aovs.iter().position(|(n, _)| n == name).unwrap();
        layers.aovs.remove(i).1
    };
    let (normal, depth) = (take("normal"), take("depth"));
    (layers.rgb, normal, depth, stderr(&o))
}

/// The pixels of `image` whose camera rays hit the model (depth > 0).
fn on_model<'a>(image: &'a Image, depth: &'a Image) -> impl Iterator<Item = glam::Vec3> + 'a {
    image
        .pixels
        .iter()
        .zip(&depth.pixels)
        .filter(|(_, d)| d.x > 0.0)
        .map(|(p, _)| *p)
}

/// Fraction of pixels whose camera rays hit the model.
fn coverage(depth: &Image) -> f64 {
    depth.pixels.iter().filter(|d| d.x > 0.0).count() as f64 / depth.pixels.len() as f64
}

#[test]
fn a_file_without_lights_is_lit_by_the_default_environment() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let (lit, _, depth, said) = render(dir, "Duck", &["--resolution", "64x48"], "duck.exr");
    assert!(
        said.contains("lit by the built-in studio environment"),
        "{said}"
    );
    let model: Vec<f32> = on_model(&lit, &depth).map(|p| p.x + p.y + p.z).collect();
    assert!(model.len() > 50, "the duck covers {} pixels", model.len());
    let mean = model.iter().sum::<f32>() / model.len() as f32;
    // A yellow Lambertian model under an environment of mean radiance 1.
    assert!((0.2..3.0).contains(&mean), "mean R+G+B on the duck {mean}");

    let (dark, _, _, said) = render(
        dir,
        "Duck",
        &["--resolution", "64x48", "--environment", "none"],
        "dark.exr",
    );
    assert!(!said.contains("studio"), "{said}");
    assert!(dark.pixels.iter().all(|p| *p == glam::Vec3::ZERO));
    let info = penumbra(&["info", sample("Duck").to_str().unwrap()], dir);
    let text = String::from_utf8_lossy(&info.stdout).into_owned();
    assert!(text.contains("lights:     none"), "{text}");
    let o = penumbra(
        &["render", "--environment", "missing.hdr", "-o", "x.png"],
        dir,
    );
    assert!(
        stderr(&o).contains("--environment: missing.hdr"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn the_default_camera_sees_three_faces_of_a_box_and_a_plane_lying_flat() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // Box: the unit cube. Faces seen are told apart by their normals.
    let (_, normal, depth, _) = render(dir, "Box", &["--resolution", "64x64"], "box.exr");
    let n = normal.pixels.len() as f64;
    for axis in 0..3 {
        let share = normal.pixels.iter().filter(|v| v[axis].abs() > 0.9).count() as f64 / n;
        assert!(share > 0.04, "faces facing axis {axis} cover {share}");
    }
    // The whole box is in view at both aspect ratios: no border pixel hits it.
    for (size, name) in [
        ("64x64", "square.exr"),
        ("32x96", "tall.exr"),
        ("96x32", "wide.exr"),
    ] {
        let (_, _, depth, _) = render(dir, "Box", &["--resolution", size], name);
        let (w, h) = (depth.width, depth.height);
        let border = (0..w)
            .flat_map(|x| [(x, 0), (x, h - 1)])
            .chain((0..h).flat_map(|y| [(0, y), (w - 1, y)]));
        let hits = border.filter(|&(x, y)| depth.get(x, y).x > 0.0).count();
        assert_eq!(hits, 0, "{size}: the box touches the border");
        assert!(
            coverage(&depth) > 0.05,
            "{size}: the box covers {}",
            coverage(&depth)
        );
    }
    assert!(coverage(&depth) > 0.15, "{}", coverage(&depth));
    // TwoSidedPlane lies in the xz-plane: seen from above, it fills a good part of the view.
    let (_, _, depth, _) = render(
        dir,
        "TwoSidedPlane",
        &["--resolution", "64x48"],
        "plane.exr",
    );
    assert!(
        coverage(&depth) > 0.1,
        "the plane covers {}",
        coverage(&depth)
    );
}

#[test]
fn pngs_are_exposed_for_the_model() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let box_path = sample("Box");
    let scene = box_path.to_str().unwrap();
    let o = penumbra(
        &[
            "render",
            scene,
            "--resolution",
            "48x48",
            "--spp",
            "4",
            "-o",
            "auto.png",
        ],
        dir,
    );
    let auto_ev = |o: &std::process::Output| -> f32 {
        let said = stderr(o);
        said.split("exposure auto: ")
            .nth(1)
            .and_then(|s| s.split(' ').next())
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("no exposure in {said}"))
    };
    let ev = auto_ev(&o);
    // The box (albedo 0.8, 0, 0) under mean radiance 1: a log-average near
    // 0.18·2^−EV. Metering the background too would push EV up by stops.
    assert!((-2.0..1.5).contains(&ev), "{ev}");
    // The raster engine meters the same pixels (those its surfaces cover),
    // so it picks nearly the same exposure (it was +2.9 EV when it metered
    // the whole frame, the bright studio background included).
    let o = penumbra(
        &[
            "render",
            scene,
            "--engine",
            "raster",
            "--resolution",
            "48x48",
            "-o",
            "raster.png",
        ],
        dir,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let raster_ev = auto_ev(&o);
    assert!(
        (raster_ev - ev).abs() < 0.5,
        "raster {raster_ev:+.2} EV, tracer {ev:+.2} EV"
    );
    let o = penumbra(
        &[
            "render",
            scene,
            "--resolution",
            "48x48",
            "--spp",
            "4",
            "--exposure",
            "0",
            "-o",
            "fixed.png",
        ],
        dir,
    );
    assert!(o.status.success() && !stderr(&o).contains("exposure auto"));
    let o = penumbra(&["render", "--exposure", "bright", "-o", "x.png"], dir);
    assert!(stderr(&o).contains("is not an exposure"), "{}", stderr(&o));
}

/// DamagedHelmet's emissiveTexture lights only its small emissive details:
/// seen without any other light, the helmet's mean radiance is far below the
/// uniformly glowing silhouette that emissiveFactor (1, 1, 1) alone gives.
#[test]
fn an_emissive_texture_lights_only_what_it_paints() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let (dark, _, depth, said) = render(
        dir,
        "DamagedHelmet",
        &["--resolution", "48x48", "--environment", "none"],
        "helmet.exr",
    );
    assert!(!said.contains("emissiveTexture ignored"), "{said}");
    let surface: Vec<f32> = on_model(&dark, &depth).map(|p| p.max_element()).collect();
    assert!(surface.len() > 200, "{}", surface.len());
    let mean = surface.iter().sum::<f32>() / surface.len() as f32;
    let lit = surface.iter().filter(|v| **v > 0.2).count();
    assert!(mean < 0.15, "mean radiance of the helmet {mean}");
    assert!(lit > 5, "no emissive detail: {lit} pixels above 0.2");
    // The default environment is not added (the scene has an emitter), but a
    // note says how to add it.
    let (_, _, _, said) = render(dir, "DamagedHelmet", &["--resolution", "16x16"], "h.exr");
    assert!(said.contains("--environment studio adds"), "{said}");
}

/// Cameras.gltf has two cameras: `--camera` picks either by index, and
/// names the ones there are when asked for one that is not.
#[test]
fn a_file_camera_is_picked_by_index() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let (_, _, first, _) = render(dir, "Cameras", &["--resolution", "40x40"], "c0.exr");
    let (_, _, second, _) = render(
        dir,
        "Cameras",
        &["--resolution", "40x40", "--camera", "1"],
        "c1.exr",
    );
    assert!(coverage(&first) > 0.05 && coverage(&second) > 0.05);
    // Two different views: the depth layers differ.
    let differ = first
        .pixels
        .iter()
        .zip(&second.pixels)
        .filter(|(a, b)| (a.x - b.x).abs() > 1e-3)
        .count();
    assert!(differ > first.pixels.len() / 10, "{differ} pixels differ");
    let path = sample("Cameras");
    let o = penumbra(
        &[
            "render",
            path.to_str().unwrap(),
            "--camera",
            "7",
            "-o",
            "x.png",
        ],
        dir,
    );
    assert!(
        stderr(&o).contains("--camera: the scene has no camera '7'; its cameras are 0: 'cameras[0]', 1: 'cameras[1]'"),
        "{}",
        stderr(&o)
    );
}

/// UnlitTest (KHR_materials_unlit): with no light at all, both engines show
/// each object in exactly its base colour, flat: every pixel covered by an
/// object is orange (1, 0.2176, 0) or blue (0, 0.2176, 1), apart from the
/// antialiased outlines.
#[test]
fn unlit_materials_show_their_base_colour_in_both_engines() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let path = sample("UnlitTest");
    let colours = [
        glam::Vec3::new(1.0, 0.217_637_64, 0.0),
        glam::Vec3::new(0.0, 0.217_637_64, 1.0),
    ];
    for engine in ["trace", "raster"] {
        let out = format!("unlit-{engine}.exr");
        let o = penumbra(
            &[
                "render",
                path.to_str().unwrap(),
                "--engine",
                engine,
                "--environment",
                "none",
                "--resolution",
                "96x64",
                "-o",
                &out,
            ],
            dir,
        );
        assert!(o.status.success(), "{engine}: {}", stderr(&o));
        let image = penumbra_image::read_image(&dir.join(&out)).unwrap();
        let lit: Vec<glam::Vec3> = image
            .pixels
            .iter()
            .copied()
            .filter(|p| p.max_element() > 0.0)
            .collect();
        let exact = lit
            .iter()
            .filter(|p| {
                colours
                    .iter()
                    .any(|c| (**p - *c).abs().max_element() < 2e-3)
            })
            .count();
        let n = image.pixels.len();
        assert!(
            exact > n / 10 && exact as f64 > 0.8 * lit.len() as f64,
            "{engine}: {exact} pixels of a base colour, {} lit, of {n}",
            lit.len()
        );
    }
}

/// `bench --texture-breakdown` on a model with base colour,
/// metallic–roughness and normal maps prices the textures together and
/// each kind alone (their throughputs are measured, not checked: the
/// machines are shared).
#[test]
fn bench_prices_each_kind_of_map() {
    let tmp = tempfile::tempdir().unwrap();
    let path = sample("DamagedHelmet");
    let o = penumbra(
        &[
            "bench",
            path.to_str().unwrap(),
            "--ray-resolution",
            "32",
            "--spp",
            "1",
            "--texture-breakdown",
        ],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    for line in [
        "path-untextured",
        "textures cost",
        "path-mean-base-colour",
        "base colour alone costs",
        "path-mean-metallic-roughness",
        "metallic-roughness alone costs",
        "path-mean-normal",
        "normal map alone costs",
    ] {
        assert!(out.contains(line), "no '{line}' in {out}");
    }
}
