//! File I/O: EXR/PNG writing and reading, atomicity, error handling on bad files.

mod common;

use std::fs;
use std::path::Path;

use penumbra_image::{
    Image, ImageError, Rgb, ToneMapping, ToneOperator, check_output_path, read_exr_layers,
    read_image, srgb_eotf, write_image,
};

fn dir_entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .expect("read_dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Awkward float values: negative, denormal, huge, tiny, non-finite.
fn special_image(w: u32, h: u32, salt: f32) -> Image {
    let specials = [
        0.0,
        -0.0,
        1.0,
        -3.5,
        f32::MIN_POSITIVE / 4.0,
        1.0e-30,
        3.0e38,
        0.1 + salt,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        std::f32::consts::PI * salt,
    ];
    Image::from_fn(w, h, |x, y| {
        let i = (y * w + x) as usize;
        Rgb::new(
            specials[i % specials.len()],
            specials[(i * 5 + 1) % specials.len()] * 0.5,
            (x as f32 + 0.123_456_79 * y as f32) * salt,
        )
    })
}

fn assert_bit_exact(a: &Image, b: &Image) {
    assert_eq!((a.width, a.height), (b.width, b.height));
    assert_eq!(a.pixels.len(), b.pixels.len());
    for (i, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        for c in 0..3 {
            assert_eq!(
                p[c].to_bits(),
                q[c].to_bits(),
                "pixel {i} channel {c}: {} vs {}",
                p[c],
                q[c]
            );
        }
    }
}

#[test]
fn exr_round_trip_is_bit_exact_with_aovs() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("render.exr");
    let beauty = special_image(37, 23, 1.0);
    let albedo = special_image(37, 23, 0.25);
    let normal = Image::from_fn(37, 23, |x, y| {
        Rgb::new(x as f32 / 37.0, -(y as f32) / 23.0, 1.0)
    });
    write_image(
        &path,
        &beauty,
        &[("albedo", &albedo), ("normal", &normal)],
        &ToneMapping::default(),
    )
    .expect("write");
    assert_eq!(dir_entries(dir.path()), vec!["render.exr"]);

    assert_bit_exact(&read_image(&path).expect("read"), &beauty);
    let layers = read_exr_layers(&path).expect("layers");
    assert_bit_exact(&layers.rgb, &beauty);
    let names: Vec<&str> = layers.aovs.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, vec!["albedo", "normal"]);
    assert_bit_exact(&layers.aovs[0].1, &albedo);
    assert_bit_exact(&layers.aovs[1].1, &normal);

    // Channel layout: B,G,R + albedo.{B,G,R} + normal.{B,G,R}, all float32.
    let meta = exr::meta::MetaData::read_from_file(&path, true).expect("meta");
    assert_eq!(meta.headers.len(), 1);
    let channels: Vec<String> = meta.headers[0]
        .channels
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    assert_eq!(
        channels,
        [
            "B", "G", "R", "albedo.B", "albedo.G", "albedo.R", "normal.B", "normal.G", "normal.R"
        ]
    );
    assert!(
        meta.headers[0]
            .channels
            .list
            .iter()
            .all(|c| c.sample_type == exr::meta::attribute::SampleType::F32)
    );
}

#[test]
fn exr_without_aovs_has_only_rgb() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("plain.EXR");
    let img = special_image(5, 4, 2.0);
    write_image(&path, &img, &[], &ToneMapping::default()).expect("write");
    let meta = exr::meta::MetaData::read_from_file(&path, true).expect("meta");
    let channels: Vec<String> = meta.headers[0]
        .channels
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    assert_eq!(channels, ["B", "G", "R"]);
    let layers = read_exr_layers(&path).expect("layers");
    assert!(layers.aovs.is_empty());
    assert_bit_exact(&layers.rgb, &img);
}

#[test]
fn exr_written_by_exr_crate_with_half_floats_is_read() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("half.exr");
    exr::prelude::write_rgb_file(&path, 3, 2, |x, y| {
        (
            exr::prelude::f16::from_f32(x as f32),
            exr::prelude::f16::from_f32(y as f32),
            exr::prelude::f16::from_f32(0.5),
        )
    })
    .expect("write");
    let img = read_image(&path).expect("read");
    assert_eq!(img.get(2, 1), Rgb::new(2.0, 1.0, 0.5));
}

#[test]
fn png_writes_expected_8bit_values() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("out.png");
    let img = Image::from_pixels(
        4,
        1,
        vec![
            Rgb::ZERO,
            Rgb::splat(0.5),
            Rgb::new(1.0, 0.18, 5.0),
            Rgb::new(0.001, -1.0, f32::NAN),
        ],
    )
    .expect("valid");
    let albedo = Image::new(4, 1);
    write_image(&path, &img, &[("albedo", &albedo)], &ToneMapping::CLAMP).expect("write");
    // AOVs are ignored for PNG output: only the one file exists.
    assert_eq!(dir_entries(dir.path()), vec!["out.png"]);
    let decoded = image::open(&path).expect("open").to_rgb8();
    assert_eq!(decoded.dimensions(), (4, 1));
    assert_eq!(
        decoded.as_raw(),
        &vec![0, 0, 0, 188, 188, 188, 255, 118, 255, 3, 0, 0]
    );

    // Exposure +1 and the filmic default.
    write_image(
        &path,
        &img,
        &[],
        &ToneMapping::new(1.0, ToneOperator::Clamp),
    )
    .expect("write");
    let decoded = image::open(&path).expect("open").to_rgb8();
    assert_eq!(&decoded.as_raw()[3..6], &[255, 255, 255]);
    write_image(&path, &img, &[], &ToneMapping::default()).expect("write");
    let decoded = image::open(&path).expect("open").to_rgb8();
    assert_eq!(
        &decoded.as_raw()[..9],
        &[0, 0, 0, 206, 206, 206, 232, 141, 253]
    );

    // Reading decodes sRGB to linear.
    write_image(&path, &img, &[], &ToneMapping::CLAMP).expect("write");
    let back = read_image(&path).expect("read");
    assert_eq!(back.get(1, 0), Rgb::splat(srgb_eotf(188.0 / 255.0)));
    assert!((back.get(1, 0).x - 0.5).abs() < 0.0033); // half an 8-bit step
    assert_eq!(back.get(0, 0), Rgb::ZERO);
}

#[test]
fn overwrite_replaces_file_atomically() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("a.exr");
    write_image(
        &path,
        &Image::filled(2, 2, Rgb::ONE),
        &[],
        &ToneMapping::default(),
    )
    .expect("write");
    write_image(
        &path,
        &Image::filled(3, 1, Rgb::ZERO),
        &[],
        &ToneMapping::default(),
    )
    .expect("write");
    assert_eq!(dir_entries(dir.path()), vec!["a.exr"]);
    assert_eq!(read_image(&path).expect("read"), Image::new(3, 1));
}

#[test]
fn failed_writes_leave_nothing_behind() {
    let dir = tempfile::tempdir().expect("tempdir");
    let img = Image::filled(4, 4, Rgb::splat(0.5));
    let tm = ToneMapping::default();

    // Missing directory: the error names it, nothing is created.
    let missing = dir.path().join("missing");
    let e = write_image(&missing.join("x.exr"), &img, &[], &tm).expect_err("missing dir");
    assert!(matches!(e, ImageError::MissingDirectory { .. }), "{e:?}");
    assert!(
        e.to_string().contains(&missing.display().to_string()),
        "{e}"
    );
    assert!(!missing.exists());

    // Unknown extension: the error names the path and the supported extensions.
    let bad = dir.path().join("x.tiff");
    let e = write_image(&bad, &img, &[], &tm).expect_err("bad extension");
    let msg = e.to_string();
    assert!(
        msg.contains("x.tiff") && msg.contains(".png") && msg.contains(".exr"),
        "{msg}"
    );
    let e = write_image(&dir.path().join("noext"), &img, &[], &tm).expect_err("no extension");
    assert!(matches!(e, ImageError::UnsupportedExtension { .. }));

    // Encoding errors (AOV size mismatch, zero size, inconsistent image) leave no file either.
    let small = Image::new(2, 2);
    assert!(write_image(&dir.path().join("y.exr"), &img, &[("albedo", &small)], &tm).is_err());
    assert!(write_image(&dir.path().join("z.png"), &Image::new(0, 3), &[], &tm).is_err());
    let broken = Image {
        width: 4,
        height: 4,
        pixels: vec![Rgb::ZERO; 3],
    };
    assert!(write_image(&dir.path().join("w.exr"), &broken, &[], &tm).is_err());
    assert!(write_image(&dir.path().join("w.png"), &broken, &[], &tm).is_err());

    assert!(
        dir_entries(dir.path()).is_empty(),
        "{:?}",
        dir_entries(dir.path())
    );
    assert!(check_output_path(&dir.path().join("ok.png")).is_ok());
}

#[test]
fn truncated_and_garbage_files_are_errors() {
    let dir = tempfile::tempdir().expect("tempdir");
    let good = dir.path().join("good.exr");
    let img = common::synthetic_scene(64, 48);
    write_image(&good, &img, &[("albedo", &img)], &ToneMapping::default()).expect("write");
    let bytes = fs::read(&good).expect("read");

    let bad = dir.path().join("bad.exr");
    // Every truncation point in the header, then a stride through the pixel data.
    let cuts: Vec<usize> = (0..400.min(bytes.len()))
        .chain((400..bytes.len()).step_by(97))
        .collect();
    for cut in cuts {
        fs::write(&bad, &bytes[..cut]).expect("write");
        let e = read_image(&bad).expect_err(&format!("truncated at {cut} of {}", bytes.len()));
        assert!(e.to_string().contains("bad.exr"), "{e}");
    }
    // Corrupted pixel data (header intact) must not panic either.
    let mut corrupt = bytes.clone();
    for b in corrupt.iter_mut().skip(bytes.len() / 2).step_by(7) {
        *b ^= 0x5a;
    }
    fs::write(&bad, &corrupt).expect("write");
    let _ = read_image(&bad);

    for (name, content) in [
        ("garbage.exr", b"this is not an image at all".as_slice()),
        ("empty.exr", b"".as_slice()),
        ("garbage.png", b"\x89PNG\r\n\x1a\n garbage".as_slice()),
        ("garbage.hdr", b"#?RADIANCE\nnonsense".as_slice()),
        ("garbage.jpg", b"\xff\xd8\xff nonsense".as_slice()),
    ] {
        let path = dir.path().join(name);
        fs::write(&path, content).expect("write");
        let e = read_image(&path).expect_err(name);
        assert!(e.to_string().contains(name), "{e}");
    }

    // Truncated PNG.
    let png = dir.path().join("t.png");
    write_image(&png, &img, &[], &ToneMapping::default()).expect("write");
    let bytes = fs::read(&png).expect("read");
    fs::write(&png, &bytes[..bytes.len() / 2]).expect("write");
    assert!(
        read_image(&png)
            .expect_err("truncated png")
            .to_string()
            .contains("t.png")
    );
}

#[test]
fn missing_file_and_unknown_extension_on_read() {
    let dir = tempfile::tempdir().expect("tempdir");
    let missing = dir.path().join("nope.exr");
    let e = read_image(&missing).expect_err("missing");
    assert!(matches!(e, ImageError::Io { .. }));
    assert!(e.to_string().contains("nope.exr"), "{e}");
    let e = read_image(&dir.path().join("a.bmp")).expect_err("bmp");
    let msg = e.to_string();
    assert!(
        msg.contains("a.bmp") && msg.contains(".exr") && msg.contains(".hdr"),
        "{msg}"
    );
}

#[test]
fn hdr_is_read_as_linear() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("x.hdr");
    let data: Vec<image::Rgb<f32>> =
        vec![image::Rgb([0.5, 2.0, 0.25]), image::Rgb([0.0, 1.0, 8.0])];
    let file = fs::File::create(&path).expect("create");
    image::codecs::hdr::HdrEncoder::new(file)
        .encode(&data, 2, 1)
        .expect("encode");
    let img = read_image(&path).expect("read");
    assert_eq!((img.width, img.height), (2, 1));
    // RGBE keeps 8 mantissa bits: these values are exact.
    assert_eq!(img.get(0, 0), Rgb::new(0.5, 2.0, 0.25));
    assert_eq!(img.get(1, 0), Rgb::new(0.0, 1.0, 8.0));
}
