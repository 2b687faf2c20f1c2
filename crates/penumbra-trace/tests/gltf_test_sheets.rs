//! Khronos' test sheets (../shared/gltf-samples), seen head-on through the
//! albedo layer (the colour a surface reflects, independent of the light):
//! the sampler wrap modes (TextureSettingsTest), KHR_texture_transform
//! (TextureTransformTest) and COLOR_0 (VertexColorTest). Each sheet shows a
//! mark of a known colour where a feature fails; the tests count them. And
//! normal maps through the normal layer (NormalTangentTest).

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
    aov_head_on(model, height, "albedo", 1)
}

/// An AOV (`albedo`, `normal`) of a glTF sample seen head-on.
fn aov_head_on(model: &str, height: u32, aov: &str, spp: u32) -> penumbra_image::Image {
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/gltf-samples")
        .join(model);
    let out = head_on(&file, height, spp);
    out.aovs.into_iter().find(|(n, _)| n == aov).unwrap().1
}

/// A glTF file seen head-on (orthographic, along −z, its bounds filling
/// the image), `height` pixels high, by the `local` integrator with AOVs.
fn head_on(file: &Path, height: u32, spp: u32) -> penumbra_trace::RenderOutput {
    let mut scene = load_scene(file, &LoadOptions::default()).unwrap();
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
    settings.spp = spp;
    settings.integrator = IntegratorKind::Local;
    render(
        &scene,
        &settings,
        &RenderOptions {
            aovs: true,
            ..Default::default()
        },
    )
    .unwrap()
}

/// TEXCOORD_1 (penumbra-scene's corpus file `ok_texcoord1.gltf`): four
/// quad rows whose every texture reads UV set 1, where set 0 is mirrored
/// in u; the texture is black and transparent on its left half, white and
/// opaque on its right. Each row is dark on the left and bright on the
/// right: base colour, emission (with no light, the image itself), the
/// alpha mask (the black background shows through on the left) and the
/// base colour whose set KHR_texture_transform overrides. Reading set 0
/// mirrors every row.
#[test]
fn textures_read_their_uv_set() {
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../penumbra-scene/tests/corpus/gltf/ok_texcoord1.gltf");
    // 20 pixels per unit: rows m = 0..4 centred on pixel row 10 + 25 m;
    // x = ∓0.75 (u = 0.125 and 0.875, one texel each) at columns 5 and 34.
    let out = head_on(&file, 95, 4);
    assert_eq!((out.image.width, out.image.height), (40, 95));
    let albedo = &out.aovs.iter().find(|(n, _)| n == "albedo").unwrap().1;
    for (row, what, image) in [
        (0, "base colour", albedo),
        (1, "emission", &out.image),
        (2, "alpha mask", albedo),
        (3, "texCoord override", albedo),
    ] {
        let y = 10 + 25 * row;
        let (left, right) = (image.get(5, y), image.get(34, y));
        eprintln!("{what}: left {left}, right {right}");
        assert!(left.max_element() < 0.02, "{what}: left {left}");
        assert!(
            (right - Vec3::ONE).abs().max_element() < 0.02,
            "{what}: right {right}"
        );
    }
}

/// NormalTangentTest: each of its 15 pairs shows a bump made of geometry
/// (left) beside a flat quad whose normal map (and UVs turned a different
/// way in each row) reproduces it (right). Seen head-on, the shading
/// normals of each right bump vary across it as the left one's do: the
/// first moments of (n_x, n_y) against (x, y) about each bump's centre
/// agree within 25 % of their size. A flipped green channel, a tangent
/// frame built on glTF's downward v, or a missing normal map each turn
/// or zero a pair's moments.
#[test]
fn normal_maps_shade_like_the_geometry_they_replace() {
    let normals = aov_head_on(
        "NormalTangentTest/glTF-Binary/NormalTangentTest.glb",
        300,
        "normal",
        1,
    );
    let (w, h) = (normals.width as usize, normals.height as usize);
    // Bumps: surface pixels (the background has no normal) whose normal
    // leans more than ~8° from +z, grouped into
    // 4-connected blobs.
    let tilted: Vec<bool> = normals
        .pixels
        .iter()
        .map(|n| n.z < 0.99 && n.length() > 0.5)
        .collect();
    let mut blob = vec![usize::MAX; w * h];
    let mut blobs: Vec<Vec<usize>> = Vec::new();
    for start in 0..w * h {
        if !tilted[start] || blob[start] != usize::MAX {
            continue;
        }
        let id = blobs.len();
        let mut members = vec![start];
        blob[start] = id;
        let mut k = 0;
        while k < members.len() {
            let p = members[k];
            k += 1;
            let (x, y) = (p % w, p / w);
            let around = [
                (x > 0).then(|| p - 1),
                (x + 1 < w).then(|| p + 1),
                (y > 0).then(|| p - w),
                (y + 1 < h).then(|| p + w),
            ];
            for q in around.into_iter().flatten() {
                if tilted[q] && blob[q] == usize::MAX {
                    blob[q] = id;
                    members.push(q);
                }
            }
        }
        blobs.push(members);
    }
    blobs.retain(|b| b.len() > 50);
    assert_eq!(
        blobs.len(),
        30,
        "bumps found: {:?}",
        blobs.iter().map(Vec::len).collect::<Vec<_>>()
    );
    // Per bump: centroid and the moments [Σ n_x dx, Σ n_x dy, Σ n_y dx, Σ n_y dy] / Σ (dx² + dy²).
    let stats: Vec<(f32, f32, [f32; 4])> = blobs
        .iter()
        .map(|b| {
            let c = |f: fn(usize, usize) -> usize| {
                b.iter().map(|&p| f(p, w) as f32).sum::<f32>() / b.len() as f32
            };
            let (cx, cy) = (c(|p, w| p % w), c(|p, w| p / w));
            let mut m = [0.0f32; 4];
            let mut norm = 0.0;
            for &p in b {
                let (dx, dy) = ((p % w) as f32 - cx, (p / w) as f32 - cy);
                let n = normals.pixels[p];
                m[0] += n.x * dx;
                m[1] += n.x * dy;
                m[2] += n.y * dx;
                m[3] += n.y * dy;
                norm += dx * dx + dy * dy;
            }
            (cx, cy, m.map(|v| v / norm.sqrt()))
        })
        .collect();
    // Rows by centroid height, then left to right: (geometry, map) pairs.
    let mut order: Vec<usize> = (0..stats.len()).collect();
    order.sort_by(|&a, &b| stats[a].1.total_cmp(&stats[b].1));
    let mut worst = 0.0f32;
    for row in order.chunks(6) {
        let mut row = row.to_vec();
        row.sort_by(|&a, &b| stats[a].0.total_cmp(&stats[b].0));
        for pair in row.chunks(2) {
            let (geometry, mapped) = (stats[pair[0]].2, stats[pair[1]].2);
            let size = geometry.iter().map(|v| v * v).sum::<f32>().sqrt();
            let diff = geometry
                .iter()
                .zip(&mapped)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f32>()
                .sqrt();
            worst = worst.max(diff / size);
            assert!(
                size > 0.05 && diff < 0.25 * size,
                "bump at ({:.0}, {:.0}): geometry moments {geometry:?}, normal map {mapped:?}",
                stats[pair[1]].0,
                stats[pair[1]].1
            );
        }
    }
    eprintln!(
        "normal maps: worst moment difference {:.1} % of the geometry's",
        100.0 * worst
    );
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

/// AlphaBlendModeTest seen head-on: five quads over one texture, whose
/// alpha is a ramp inside an opaque border, under OPAQUE, BLEND and MASK
/// with cutoffs 0.25, 0.5 (the default) and 0.75. Each quad has a red "X"
/// that shows only where its mode is applied wrongly: on the opaque quad
/// one drawn with α = 0 on a green check (hidden if alpha is ignored, as
/// OPAQUE asks); on the others marks that α must remove. None may show.
/// And the ramp is cut where each cutoff says: the height of the green
/// fill of the three MASK quads falls with the cutoff.
#[test]
fn alpha_modes_show_no_red_marks() {
    let albedo = aov_head_on(
        "AlphaBlendModeTest/glTF-Binary/AlphaBlendModeTest.glb",
        240,
        "albedo",
        16,
    );
    let red = |p: Vec3| p.x > 0.3 && p.y < 0.1 && p.z < 0.1;
    let (w, h) = (albedo.width, albedo.height);
    let reds = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| red(albedo.get(x, y)))
        .count();
    assert_eq!(reds, 0, "{reds} red pixels");
    // The first row of the coloured (cyan and yellow) fill from the top, at
    // the middle of the cutoff-0.25, default and 0.75 quads: α rises
    // linearly down each quad, so the three rows are evenly spaced.
    let coloured = |p: Vec3| p.max_element() - p.min_element() > 0.3;
    let tops: Vec<u32> = [0.514, 0.68, 0.855]
        .iter()
        .map(|f| {
            let x = (f * w as f32) as u32;
            (0..h).find(|&y| coloured(albedo.get(x, y))).unwrap_or(h)
        })
        .collect();
    let (d1, d2) = (
        tops[1] as f32 - tops[0] as f32,
        tops[2] as f32 - tops[1] as f32,
    );
    assert!(
        d1 > 0.12 * h as f32 && (d1 - d2).abs() < 0.15 * d1,
        "fill tops at rows {tops:?}: cutoffs 0.25, 0.5 and 0.75 must cut evenly spaced rows"
    );
}
