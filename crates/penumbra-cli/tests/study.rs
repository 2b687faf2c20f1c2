//! `penumbra study`: the rankings that must hold on the example scene, the
//! report's numbers against `penumbra compare`, and bad input refused with
//! no report left behind.

mod common;

use common::{expect_failures, files_in, penumbra, stderr};
use std::path::PathBuf;

fn scene(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name)
        .display()
        .to_string()
}

fn skip_gpu(test: &str) -> bool {
    let skip = std::env::var("PENUMBRA_SKIP_GPU").is_ok_and(|v| v == "1");
    if skip {
        eprintln!(
            "note: {test}: skipped because PENUMBRA_SKIP_GPU=1 (the study's raster rows need a GPU)"
        );
    }
    skip
}

/// The row of `id` in study.json.
fn row<'a>(study: &'a serde_json::Value, id: &str) -> &'a serde_json::Value {
    study["rows"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["id"] == id)
        .unwrap_or_else(|| panic!("no row {id}; skipped: {}", study["skipped"]))
}

fn num(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// On scenes/study/shadows.toml (hard shadows of a sun and a spot, thin
/// posts, a planar floor): shadow-map error against `direct` falls with
/// the map size (hard PCF), shadow volumes beat every shadow map, and
/// `path` at local's time beats `local` against full GI. The report's
/// numbers are those of `penumbra compare` on its own images.
#[test]
fn rankings_on_the_example_scene_and_numbers_equal_compare() {
    if skip_gpu("rankings_on_the_example_scene") {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let o = penumbra(
        &[
            "study",
            &scene("study/shadows.toml"),
            "-o",
            "report",
            "--resolution",
            "160x120",
            "--spp",
            "256",
            "--techniques",
            "trace-local,maps,raster-volume",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let report = d.join("report");
    let study: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(report.join("study.json")).unwrap()).unwrap();
    assert_eq!(
        study["rows"].as_array().unwrap().len(),
        10,
        "{}",
        study["skipped"]
    );
    assert!(study["skipped"].as_array().unwrap().is_empty());
    let q = |id: &str| num(&row(&study, id)["quantity"]["rel_mse"]);
    for id in ["raster-volume", "raster-map-512-pcf1"] {
        assert_eq!(row(&study, id)["approximates"], "direct");
    }

    // Hard shadow maps: error falls with the map size.
    let sizes = [512, 1024, 2048, 4096];
    let hard: Vec<f64> = sizes
        .iter()
        .map(|s| q(&format!("raster-map-{s}-pcf1")))
        .collect();
    for (i, pair) in hard.windows(2).enumerate() {
        assert!(
            pair[1] < pair[0],
            "map {} PCF 1: relMSE {} is not below map {}: {}",
            sizes[i + 1],
            pair[1],
            sizes[i],
            pair[0]
        );
    }
    // Shadow volumes: closer to `direct` than every shadow map.
    let volume = q("raster-volume");
    for s in sizes {
        for pcf in [1, 3] {
            let id = format!("raster-map-{s}-pcf{pcf}");
            assert!(volume < q(&id), "volume {volume} vs {id} {}", q(&id));
        }
    }
    // Path at local's time beats local against full GI.
    let local = row(&study, "trace-local");
    let path_same_time = num(&local["equal_time_path"]["full"]["rel_mse"]);
    let local_full = num(&local["full"]["rel_mse"]);
    assert!(
        path_same_time < local_full,
        "path at equal time {path_same_time} vs local {local_full}"
    );

    // The numbers equal `penumbra compare` on the report's own images.
    for (truth, id, field) in [
        ("truths/path.exr", "raster-volume", "full"),
        ("truths/direct.exr", "raster-volume", "quantity"),
        ("truths/path.exr", "trace-local", "full"),
    ] {
        let r = row(&study, id);
        let o = penumbra(
            &["compare", truth, r["image_exr"].as_str().unwrap(), "--json"],
            &report,
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let c: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        for (a, b) in [("rel_mse", "rel_mse"), ("flip", "flip_mean")] {
            let (x, y) = (num(&c[a]), num(&r[field][b]));
            assert!(
                (x - y).abs() <= 1e-12 * x.abs().max(1e-30),
                "{id} {field} {b}: compare says {x}, the report {y}"
            );
        }
    }
    // The report's files are there; nothing else is left beside it.
    for f in ["index.html", "study.json", "study.csv", "truths/path.png"] {
        assert!(report.join(f).is_file(), "{f} missing");
    }
    assert_eq!(files_in(d), vec!["report".to_string()]);
}

/// Bad input: a clear error, and no report (nor a staging folder) left.
#[test]
fn bad_input_leaves_no_report() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    // A reference image of another resolution.
    let o = penumbra(
        &[
            "render",
            "--resolution",
            "24x16",
            "--spp",
            "1",
            "-o",
            "ref.exr",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::write(d.join("file"), "not a directory").unwrap();
    let cases: [(&[&str], &str); 5] = [
        (
            &["study", "-o", "r", "--techniques", "trace-path,raster-mapp"],
            "unknown technique 'raster-mapp'",
        ),
        (
            &[
                "study",
                "-o",
                "r",
                "--reference",
                "ref.exr",
                "--resolution",
                "32x32",
            ],
            "the reference is 24x16 but the study renders 32x32",
        ),
        (&["study", "-o", "file"], "exists and is not a directory"),
        (
            &["study", "-o", "r", "--reference", "missing.exr"],
            "missing.exr: no such file",
        ),
        (
            &["study", "-o", "r", "--spp", "4", "--target-relmse", "0.01"],
            "cannot be used with",
        ),
    ];
    expect_failures(&cases, d, &["file", "ref.exr"]);
    assert_eq!(
        std::fs::read_to_string(d.join("file")).unwrap(),
        "not a directory"
    );
}
