//! The `penumbra` binary: errors exit non-zero, name the problem and leave no
//! output file; good runs write the file.

mod common;

use common::{expect_failures, files_in, penumbra, penumbra_with_var, stderr};
use std::path::PathBuf;

fn reference(scene: &str, file: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/reference")
        .join(scene)
        .join(file)
        .display()
        .to_string()
}

/// A scene that cannot be read: the file and the system's reason, said
/// once (not again by the error chain).
#[test]
fn an_unreadable_scene_gives_its_reason_once() {
    let dir = tempfile::tempdir().unwrap();
    let o = penumbra(&["render", "no-such-scene.gltf", "-o", "a.png"], dir.path());
    assert!(!o.status.success());
    let err = stderr(&o);
    // What the system says, e.g. "No such file or directory (os error 2)".
    let reason = std::fs::read(dir.path().join("no-such-scene.gltf"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("no-such-scene.gltf: cannot read file"),
        "{err}"
    );
    assert_eq!(err.matches(&reason).count(), 1, "{err}");
    assert!(files_in(dir.path()).is_empty());
}

#[test]
fn bad_arguments_fail_without_output() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases: &[(&[&str], &str)] = &[
        (&["render", "--spp", "0", "-o", "a.png"], "--spp"),
        (&["render", "--spp", "-3", "-o", "a.png"], "--spp"),
        (
            &["render", "--resolution", "0x10", "-o", "a.png"],
            "width 0",
        ),
        (
            &["render", "--resolution", "64", "-o", "a.png"],
            "WIDTHxHEIGHT",
        ),
        (
            &["render", "--resolution", "60000x60000", "-o", "a.png"],
            "memory",
        ),
        (
            &["render", "--integrator", "whatever", "-o", "a.png"],
            "unknown integrator 'whatever'",
        ),
        (&["render", "-o", "missing-dir/a.png"], "missing-dir"),
        (&["render", "-o", "a.tiff"], "a.tiff"),
        (
            &["render", "no-such-scene.gltf", "-o", "a.png"],
            "no-such-scene.gltf",
        ),
        (
            &["render", "scene.blend", "-o", "a.png"],
            "unknown scene format",
        ),
        (&["info", "no-such-scene.obj"], "no-such-scene.obj"),
        (&["info"], "--gpu"),
        (
            &["render", "--engine", "raster", "--msaa", "2", "-o", "a.png"],
            "MSAA",
        ),
        (&["render", "--msaa", "4", "-o", "a.png"], "--engine raster"),
        (
            &["render", "--shadows", "map", "-o", "a.png"],
            "--shadows applies to --engine raster only",
        ),
        (
            &["render", "--pcf", "3", "-o", "a.png"],
            "--pcf applies to --engine raster only",
        ),
        (
            &["render", "--shadow-map-size", "512", "-o", "a.png"],
            "--shadow-map-size applies to --engine raster only",
        ),
        (
            &["render", "--engine", "raster", "--pcf", "0", "-o", "a.png"],
            "PCF kernel",
        ),
        (
            &["render", "--env-taps", "4", "-o", "a.png"],
            "--env-taps applies to --engine raster only",
        ),
        (
            &[
                "render",
                "--engine",
                "raster",
                "--env-taps",
                "99",
                "-o",
                "a.png",
            ],
            "environment taps",
        ),
        (
            &[
                "render",
                "--engine",
                "raster",
                "--shadows",
                "soft",
                "-o",
                "a.png",
            ],
            "soft",
        ),
        (
            &[
                "render",
                "--engine",
                "raster",
                "--shadows",
                "volume",
                "--pcf",
                "3",
                "-o",
                "a.png",
            ],
            "--shadows map",
        ),
        (
            &["render", "--engine", "raster", "--pcf", "3", "-o", "a.png"],
            "--shadows map",
        ),
        (
            &["render", "--engine", "raster", "--aovs", "-o", "a.exr"],
            "--aovs",
        ),
        (
            &["render", "--ssao", "gtao", "-o", "a.png"],
            "--ssao applies to --engine raster only",
        ),
        (
            &["render", "--ao-radius", "2", "-o", "a.png"],
            "the ray tracer's is --ao-distance",
        ),
        (
            &[
                "render",
                "--engine",
                "raster",
                "--ao-radius",
                "2",
                "-o",
                "a.png",
            ],
            "need --ssao",
        ),
        (
            &[
                "render",
                "--engine",
                "raster",
                "--ssao",
                "gtao",
                "--ao-radius",
                "0",
                "-o",
                "a.png",
            ],
            "--ao-radius",
        ),
        (
            &[
                "render",
                "--engine",
                "raster",
                "--ssao",
                "hemisphere",
                "--ao-thin",
                "1",
                "-o",
                "a.png",
            ],
            "--ao-thin needs --ssao gtao",
        ),
        (
            &[
                "render",
                "--engine",
                "raster",
                "--ssao",
                "gtao",
                "--ao-thin",
                "-1",
                "-o",
                "a.png",
            ],
            "thin-occluder compensation is a number >= 0",
        ),
        (
            &["render", "--ao-thin", "1", "-o", "a.png"],
            "--ao-thin applies to --engine raster only",
        ),
        (
            &[
                "render", "--engine", "raster", "--ssao", "sphere", "-o", "a.png",
            ],
            "sphere",
        ),
        (
            &["bench", "--ssao", "hemisphere"],
            "apply to --engine raster only",
        ),
        (&["compare", "no-ref.exr", "no-test.exr"], "no-ref.exr"),
    ];
    expect_failures(cases, d, &[]);
}

#[test]
fn corrupt_scene_names_file_and_place() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("broken.gltf");
    std::fs::write(&scene, r#"{"asset": {"version": "3.0"}}"#).unwrap();
    let o = penumbra(
        &["render", scene.to_str().unwrap(), "-o", "out.png"],
        dir.path(),
    );
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("broken.gltf") && e.contains("asset.version"),
        "{e}"
    );
    assert!(!dir.path().join("out.png").exists());
}

#[test]
fn render_info_compare_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = reference("spheres-direct", "spheres-direct.gltf");
    let o = penumbra(
        &[
            "render",
            &scene,
            "--integrator",
            "direct",
            "--spp",
            "4",
            "--resolution",
            "64x64",
            "-o",
            "a.exr",
            "--aovs",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = penumbra(
        &[
            "render",
            &scene,
            "--integrator",
            "direct",
            "--spp",
            "4",
            "--resolution",
            "64x64",
            "-o",
            "a.png",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(files_in(d), vec!["a.exr".to_string(), "a.png".to_string()]);
    let o = penumbra(
        &[
            "compare",
            "a.exr",
            "a.exr",
            "--json",
            "--heatmap",
            "heat.png",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("\"rmse\":0") && out.contains("\"flip\":0"),
        "{out}"
    );
    assert!(d.join("heat.png").exists());
    let o = penumbra(&["info", &scene], d);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success() && out.contains("triangles:  15362") && out.contains("lights:     2"),
        "{out}"
    );
    // Quantities as numbers with units, not Rust debug text.
    assert!(
        out.contains(" W/sr") && !out.contains("Vec3(") && out.contains("vertical field of view"),
        "{out}"
    );
}

/// `bench --kernel` runs the kernel asked for and names it; the portable
/// kernel runs on every CPU.
#[test]
fn bench_runs_the_kernel_asked_for() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "bench",
        "--triangles",
        "2000",
        "--ray-resolution",
        "16",
        "--spp",
        "0",
        "--kernel",
        "portable",
    ];
    let o = penumbra(&args, dir.path());
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.contains("Portable kernel"), "{out}");
    // The raster engine has no traversal kernel.
    let o = penumbra(
        &["bench", "--engine", "raster", "--kernel", "avx2"],
        dir.path(),
    );
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--engine trace only"), "{}", stderr(&o));
}

#[test]
fn bench_json_lines() {
    let dir = tempfile::tempdir().unwrap();
    let o = penumbra(
        &[
            "bench",
            "--triangles",
            "20000",
            "--ray-resolution",
            "64",
            "--spp",
            "1",
            "--json",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    for measure in [
        "build",
        "coherent",
        "coherent-interleaved",
        "coherent-packets",
        "incoherent",
        "incoherent-interleaved",
        "incoherent-packets",
        "path",
    ] {
        let line = out
            .lines()
            .find(|l| l.contains(&format!("\"measure\":\"{measure}\"")))
            .unwrap_or_else(|| panic!("no {measure} in {out}"));
        assert!(
            line.starts_with('{') && line.ends_with('}') && line.contains("\"seconds\":"),
            "{line}"
        );
    }
    assert!(
        out.lines().filter(|l| l.contains("mrays_per_s")).count() == 6,
        "{out}"
    );
}

/// `--engine raster` (GPU; fails without an adapter unless PENUMBRA_SKIP_GPU=1):
/// `info --gpu` names the adapter, the raster image has the CPU film's size
/// and files, and `compare` against the CPU `local` integrator works.
#[test]
fn raster_engine_round_trip() {
    if std::env::var("PENUMBRA_SKIP_GPU").is_ok_and(|v| v == "1") {
        eprintln!("note: raster_engine_round_trip skipped because PENUMBRA_SKIP_GPU=1");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = penumbra(&["info", "--gpu"], d);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success() && out.contains("backend:") && out.contains("driver:"),
        "{out}{}",
        stderr(&o)
    );
    let scene = reference("spheres-direct", "spheres-direct.gltf");
    let res = ["--resolution", "96x96"];
    let o = penumbra(
        &[
            &[
                "render", &scene, "--engine", "raster", "--msaa", "4", "-o", "r.exr",
            ],
            &res[..],
        ]
        .concat(),
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("raster 96x96"), "{}", stderr(&o));
    let o = penumbra(
        &[
            &["render", &scene, "--engine", "raster", "-o", "r.png"],
            &res[..],
        ]
        .concat(),
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = penumbra(
        &[
            &[
                "render",
                &scene,
                "--integrator",
                "local",
                "--spp",
                "16",
                "-o",
                "c.exr",
            ],
            &res[..],
        ]
        .concat(),
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = penumbra(&["compare", "c.exr", "r.exr", "--json"], d);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    let v: serde_json::Value = serde_json::from_str(out.trim()).expect("json");
    let flip = v["flip"].as_f64().expect("flip");
    assert!(flip <= 0.02, "raster vs local: FLIP {flip}");
    assert!(d.join("r.png").exists());

    // Shadow maps: closer to the CPU `direct` integrator than no shadows.
    let o = penumbra(
        &[
            &[
                "render",
                &scene,
                "--engine",
                "raster",
                "--shadows",
                "map",
                "--shadow-map-size",
                "1024",
                "--pcf",
                "3",
                "-o",
                "s.exr",
            ],
            &res[..],
        ]
        .concat(),
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = penumbra(
        &[
            &[
                "render",
                &scene,
                "--integrator",
                "direct",
                "--spp",
                "16",
                "-o",
                "t.exr",
            ],
            &res[..],
        ]
        .concat(),
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let flip_of = |test: &str| {
        let o = penumbra(&["compare", "t.exr", test, "--json"], d);
        assert!(o.status.success(), "{}", stderr(&o));
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        let v: serde_json::Value = serde_json::from_str(out.trim()).expect("json");
        v["flip"].as_f64().expect("flip")
    };
    let (with_maps, without) = (flip_of("s.exr"), flip_of("r.exr"));
    eprintln!("raster vs direct: FLIP {with_maps:.4} with shadow maps, {without:.4} without");
    assert!(
        with_maps < without,
        "shadow maps do not approach direct: FLIP {with_maps} vs {without} without"
    );
    // Stencil shadow volumes: hard shadows everywhere, closer still.
    let o = penumbra(
        &[
            &[
                "render",
                &scene,
                "--engine",
                "raster",
                "--shadows",
                "volume",
                "--msaa",
                "4",
                "-o",
                "v.exr",
            ],
            &res[..],
        ]
        .concat(),
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("shadow volume stencil"),
        "{}",
        stderr(&o)
    );
    let volumes = flip_of("v.exr");
    eprintln!("raster vs direct: FLIP {volumes:.4} with shadow volumes");
    assert!(volumes < without, "volumes: FLIP {volumes} vs {without}");
}

/// `bench --engine raster` (GPU; fails without an adapter unless
/// PENUMBRA_SKIP_GPU=1): one JSON line per light count with the frame time
/// and the forward pass, the shadow-map passes counted per layer.
#[test]
fn raster_bench_reports_each_pass_per_light_count() {
    if std::env::var("PENUMBRA_SKIP_GPU").is_ok_and(|v| v == "1") {
        eprintln!("note: raster_bench skipped because PENUMBRA_SKIP_GPU=1");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let o = penumbra(
        &[
            "bench",
            "--engine",
            "raster",
            "--triangles",
            "2000",
            "--resolution",
            "64x48",
            "--lights",
            "1,3",
            "--frames",
            "1",
            "--shadows",
            "map",
            "--json",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 2, "{out}");
    for (line, lights) in lines.iter().zip([1, 3]) {
        assert!(
            line.starts_with(&format!("{{\"lights\":{lights},\"frame_ms\":")),
            "{line}"
        );
        // Timestamps on lavapipe and most GPUs: every point light has six
        // shadow-map faces.
        if line.contains("forward") {
            assert!(
                line.contains(&format!("\"shadow map\":{{\"passes\":{}", 6 * lights)),
                "{line}"
            );
        }
    }
    let o = penumbra(
        &["bench", "--engine", "raster", "--rays", "x.bin"],
        dir.path(),
    );
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--engine trace only"), "{}", stderr(&o));
}

/// `PENUMBRA_SCALAR_PATHS=1` (the benchmark scripts' baseline) keeps the
/// scalar path tracer where the 16-lane one applies, `0` or nothing does
/// not; the render line says which ran. (The library itself reads no
/// environment: its options alone decide.)
#[test]
fn scalar_paths_variable_picks_the_path_tracer() {
    let dir = tempfile::tempdir().unwrap();
    let scene = cornell_toml();
    for (value, lanes) in [(Some("1"), false), (Some("0"), true), (None, true)] {
        let args = [
            "render",
            &scene,
            "--spp",
            "1",
            "--resolution",
            "32x32",
            "-o",
            "a.exr",
        ];
        let o = penumbra_with_var(&args, dir.path(), "PENUMBRA_SCALAR_PATHS", value);
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(
            stderr(&o).contains("16 paths at a time"),
            lanes,
            "PENUMBRA_SCALAR_PATHS={value:?}: {}",
            stderr(&o)
        );
    }
}

fn cornell_toml() -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/cornell-box.toml")
        .display()
        .to_string()
}

/// `penumbra bake`: bad settings fail before baking and write nothing; a
/// good bake writes a directory that `info --bake` describes and the raster
/// engine shows (GPU part skipped with PENUMBRA_SKIP_GPU=1).
#[test]
fn bake_round_trip_and_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cases: &[(&[&str], &str)] = &[
        (&["bake", "ao", "-o", "b", "--samples", "0"], "--samples"),
        (
            &["bake", "lightmap", "-o", "b", "--texels-per-unit", "-1"],
            "texels per unit",
        ),
        (
            &["bake", "lightmap", "-o", "b", "--texels-per-unit", "1e6"],
            "8192x8192",
        ),
        (
            &["bake", "ao", "-o", "b", "--ao-distance", "0"],
            "positive distance",
        ),
        (
            &["bake", "ao", "-o", "b", "--max-size", "4"],
            "atlas size 4",
        ),
        (
            &["bake", "radiosity", "-o", "b", "--tolerance", "2"],
            "between 0 and 1",
        ),
        (&["bake", "ao", "-o", "missing/b"], "does not exist"),
        (&["bake", "ao", "-o", "b", "--gltf", "out.gltf"], ".glb"),
        (&["bake", "ao", "no-such.toml", "-o", "b"], "no-such.toml"),
        (
            &[
                "render", "--engine", "raster", "--bake", "nowhere", "-o", "a.png",
            ],
            "nowhere",
        ),
        (
            &["render", "--bake", "nowhere", "-o", "a.png"],
            "--engine raster",
        ),
        (&["info", "--bake", "nowhere"], "nowhere"),
    ];
    expect_failures(cases, d, &[]);
    let scene = cornell_toml();
    let o = penumbra(
        &[
            "bake",
            "ao",
            &scene,
            "-o",
            "ao",
            "--max-size",
            "48",
            "--samples",
            "8",
            "--ao-distance",
            "80",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(files_in(d), ["ao"]);
    let o = penumbra(
        &[
            "bake",
            "ao",
            &scene,
            "-o",
            "ao-gltf",
            "--max-size",
            "32",
            "--samples",
            "2",
            "--gltf",
            "cornell.glb",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let glb = std::fs::read(d.join("cornell.glb")).unwrap();
    assert_eq!(&glb[..4], b"glTF");
    std::fs::remove_dir_all(d.join("ao-gltf")).unwrap();
    std::fs::remove_file(d.join("cornell.glb")).unwrap();
    assert_eq!(
        files_in(&d.join("ao")),
        ["manifest.json", "total-0.exr", "uvs.bin"]
    );
    let o = penumbra(&["info", &scene, "--bake", "ao"], d);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", stderr(&o));
    for needle in ["kind:       ao", "AO distance 80", "fits:"] {
        assert!(out.contains(needle), "'{needle}' not in:\n{out}");
    }
    // The bake does not fit another scene.
    let other = reference("spheres-direct", "spheres-direct.gltf");
    let o = penumbra(&["info", &other, "--bake", "ao"], d);
    assert!(
        !o.status.success() && stderr(&o).contains("another scene"),
        "{}",
        stderr(&o)
    );
    if std::env::var("PENUMBRA_SKIP_GPU").is_ok_and(|v| v == "1") {
        eprintln!("note: bake display skipped because PENUMBRA_SKIP_GPU=1");
        return;
    }
    let o = penumbra(
        &[
            "render", &other, "--engine", "raster", "--bake", "ao", "-o", "x.png",
        ],
        d,
    );
    assert!(
        !o.status.success() && stderr(&o).contains("another scene"),
        "{}",
        stderr(&o)
    );
    assert!(!d.join("x.png").exists());
    let o = penumbra(
        &[
            "render",
            &scene,
            "--engine",
            "raster",
            "--bake",
            "ao",
            "--aovs",
            "--resolution",
            "64x64",
            "-o",
            "r.exr",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let layers = penumbra_image::read_exr_layers(&d.join("r.exr")).unwrap();
    let ao = &layers
        .aovs
        .iter()
        .find(|(n, _)| n == "ao")
        .expect("ao layer")
        .1;
    let mean = ao.mean().x;
    assert!(mean > 0.2 && mean < 1.0, "mean kA {mean}");
}

/// Output piped into a reader that stops early (`penumbra info | head -1`)
/// ends the program quietly, killed by SIGPIPE as other tools are, never
/// with a panic.
#[cfg(unix)]
#[test]
fn a_closed_output_pipe_ends_quietly() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::{Command, Stdio};
    let dir = tempfile::tempdir().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_penumbra"))
        .args([
            "bench",
            "--triangles",
            "2000",
            "--spp",
            "0",
            "--ray-resolution",
            "64",
        ])
        .current_dir(dir.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Close the reading end before the program writes its first line.
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(
        o.status.signal(),
        Some(libc::SIGPIPE),
        "{:?} {err}",
        o.status
    );
}

/// A scene with more triangles, instances counted, than the BVH holds is
/// refused at load with the count and the file's name, before any output
/// is written; one at the limit loads. One mesh of 2^20 triangles placed
/// by 128 nodes makes 2^27, one past the limit; with the last node's mesh
/// one triangle shorter, 2^27 - 1.
#[test]
fn a_scene_past_the_bvh_limit_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let triangles: u32 = 1 << 20;
    let mut bin = Vec::new();
    for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for c in p {
            bin.extend_from_slice(&c.to_le_bytes());
        }
    }
    for _ in 0..triangles {
        for i in 0u32..3 {
            bin.extend_from_slice(&i.to_le_bytes());
        }
    }
    std::fs::write(dir.path().join("big.bin"), &bin).unwrap();
    // Nodes 0–126 place mesh 0; node 127 places `last_mesh`.
    let write = |name: &str, last_mesh: u32| {
        let nodes: Vec<String> = (0..128)
            .map(|i| {
                let mesh = if i == 127 { last_mesh } else { 0 };
                format!(r#"{{"mesh": {mesh}, "translation": [{i}, 0, 0]}}"#)
            })
            .collect();
        let gltf = format!(
            r#"{{"asset": {{"version": "2.0"}},
  "buffers": [{{"uri": "big.bin", "byteLength": {len}}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 36}},
                  {{"buffer": 0, "byteOffset": 36, "byteLength": {ilen}}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                  "min": [0, 0, 0], "max": [1, 1, 0]}},
                {{"bufferView": 1, "componentType": 5125, "count": {icount}, "type": "SCALAR"}},
                {{"bufferView": 1, "componentType": 5125, "count": {shorter}, "type": "SCALAR"}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}]}},
             {{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 2}}]}}],
  "nodes": [{nodes}],
  "scenes": [{{"nodes": [{roots}]}}], "scene": 0}}"#,
            len = bin.len(),
            ilen = bin.len() - 36,
            icount = 3 * triangles,
            shorter = 3 * (triangles - 1),
            nodes = nodes.join(", "),
            roots = (0..128)
                .map(|i| i.to_string())
                .collect::<Vec<_>>()
                .join(", "),
        );
        std::fs::write(dir.path().join(name), gltf).unwrap();
    };
    write("big.gltf", 0);
    write("limit.gltf", 1);
    let cases: &[(&[&str], &str)] = &[
        (
            &["render", "big.gltf", "-o", "out.png"],
            "big.gltf: 134217728 triangles with every instance counted; penumbra's BVH holds at most 134217727",
        ),
        (
            &["bake", "ao", "big.gltf", "-o", "baked"],
            "134217728 triangles",
        ),
        (&["study", "big.gltf", "-o", "study"], "134217728 triangles"),
    ];
    expect_failures(cases, dir.path(), &["big.bin", "big.gltf", "limit.gltf"]);
    let o = penumbra(&["info", "limit.gltf"], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("triangles:  134217727"), "{out}");
}
