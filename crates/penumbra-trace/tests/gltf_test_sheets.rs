//! Khronos' test sheets (../shared/gltf-samples), seen head-on through the
//! albedo layer (the colour a surface reflects, independent of the light):
//! the sampler wrap modes (TextureSettingsTest), KHR_texture_transform
//! (TextureTransformTest) and COLOR_0 (VertexColorTest). Each sheet shows a
//! mark of a known colour where a feature fails; the tests count them.

use glam::Vec3;
use penumbra_scene::{Camera, IntegratorKind, LoadOptions, Projection, load_scene};
use penumbra_trace::{RenderOptions, render};
use std::path::Path;

/// Rows of the sheet, top to bottom, below the column titles.
const ROWS: [&str; 8] = [
    "single-sided",
    "double-sided",
    "texture clamp s",
    "texture clamp t",
    "texture repeat s",
    "texture repeat t",
    "texture mirror s",
    "texture mirror t",
];

#[test]
fn wrap_modes_show_no_red_marks() {
    let albedo = albedo_head_on(
        "TextureSettingsTest/glTF-Binary/TextureSettingsTest.glb",
        300,
    );
    let red = |p: Vec3| p.x > 0.3 && p.y < 0.1 && p.z < 0.1;
    let green = |p: Vec3| p.y > 0.1 && p.x < 0.1 && p.z < 0.1;
    // The sheet's rows: the 8 test rows share the image height below the
    // title row equally (as on the Khronos screenshot, 9 rows in all).
    let (w, h) = (albedo.width, albedo.height);
    let mut report = Vec::new();
    for (r, name) in ROWS.iter().enumerate() {
        let (y0, y1) = ((r + 1) * h as usize / 9, (r + 2) * h as usize / 9);
        let count = |f: &dyn Fn(Vec3) -> bool, x0: u32, x1: u32| {
            (y0..y1)
                .flat_map(|y| (x0..x1).map(move |x| (x, y as u32)))
                .filter(|&(x, y)| f(albedo.get(x, y)))
                .count()
        };
        // The "Test" column spans about 0.48–0.62 of the width.
        let test_column = (w * 48 / 100, w * 62 / 100);
        report.push((
            *name,
            count(&red, 0, w),
            count(&green, test_column.0, test_column.1),
        ));
    }
    eprintln!("{report:?}");
    // Every row passes, the single-sided one too: its quad shows the
    // camera its back face, which glTF culls, revealing the check behind.
    for (name, reds, greens) in &report {
        assert!(
            *greens > 50,
            "{name}: no green mark in the test column ({greens} pixels)"
        );
        assert_eq!(*reds, 0, "{name}: {reds} red pixels ({report:?})");
    }
}

/// The albedo of a glTF sample seen head-on (orthographic, along −z, the
/// sheet filling the image), `height` pixels high.
fn albedo_head_on(model: &str, height: u32) -> penumbra_image::Image {
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/gltf-samples")
        .join(model);
    let mut scene = load_scene(&file, &LoadOptions::default()).unwrap();
    let (lo, hi) = scene.bounds().unwrap();
    let (centre, size) = (0.5 * (lo + hi), hi - lo);
    scene.camera = Some(Camera::look_at(
        centre + Vec3::Z * (10.0 + size.z),
        centre,
        Vec3::Y,
        Projection::Orthographic { height: size.y },
    ));
    let mut settings = scene.settings.clone();
    settings.width = (height as f32 * size.x / size.y).round() as u32;
    settings.height = height;
    settings.spp = 1;
    settings.integrator = IntegratorKind::Local;
    let out = render(
        &scene,
        &settings,
        &RenderOptions {
            aovs: true,
            ..Default::default()
        },
    );
    out.aovs.into_iter().find(|(n, _)| n == "albedo").unwrap().1
}

/// Khronos' TextureTransformTest (KHR_texture_transform), top row: three
/// quads whose texture coordinates cover (0, 0)–(0.5, 0.5) with offsets
/// (0.5, 0), (0, 0.5) and (0.5, 0.5); without the offsets they show a yellow
/// image. (The bottom row's arrows, rotated and scaled, were checked by eye
/// to point at the green markers; the rotation's sign is tested on the
/// loader's transform itself.)
#[test]
fn texture_offsets_leave_no_yellow_image() {
    let albedo = albedo_head_on("TextureTransformTest/glTF/TextureTransformTest.gltf", 200);
    let (w, h) = (albedo.width, albedo.height);
    let yellow = |p: Vec3| p.x > 0.6 && p.y > 0.6 && p.z < 0.2;
    let count = |f: &dyn Fn(Vec3) -> bool| {
        (0..h / 2)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| f(albedo.get(x, y)))
            .count()
    };
    assert_eq!(count(&yellow), 0, "an offset was not applied");
    // The three check marks are there: white on green, blue and cyan.
    let white = |p: Vec3| p.min_element() > 0.8;
    assert!(
        count(&white) > (w * h / 2) as usize / 20,
        "{}",
        count(&white)
    );
}

/// VertexColorTest: the top row's check marks are multiplied by red, green
/// and blue vertex colours; without them each shows an "X" in the other
/// two channels (cyan, magenta, yellow), which must not appear.
#[test]
fn vertex_colours_multiply_the_base_colour() {
    let albedo = albedo_head_on("VertexColorTest/glTF-Binary/VertexColorTest.glb", 200);
    let (w, h) = (albedo.width, albedo.height);
    let two_channels = |p: Vec3| {
        let on = [p.x, p.y, p.z].iter().filter(|c| **c > 0.4).count();
        let off = [p.x, p.y, p.z].iter().filter(|c| **c < 0.1).count();
        on == 2 && off == 1
    };
    let pure = |p: Vec3| {
        let on = [p.x, p.y, p.z].iter().filter(|c| **c > 0.4).count();
        let off = [p.x, p.y, p.z].iter().filter(|c| **c < 0.1).count();
        on == 1 && off == 2
    };
    let count = |f: &dyn Fn(Vec3) -> bool| {
        (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| f(albedo.get(x, y)))
            .count()
    };
    let (x_marks, checks) = (count(&two_channels), count(&pure));
    assert!(checks > 500, "{checks} pixels of red, green or blue checks");
    assert!(
        x_marks < 20,
        "{x_marks} pixels of cyan, magenta or yellow X marks"
    );
}
