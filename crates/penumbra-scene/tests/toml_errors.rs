//! Bad TOML scenes (tests/corpus/toml/*.toml): every error names the file,
//! the key path or line, the offending value and what is allowed.

use penumbra_scene::load::{LoadOptions, load_toml, load_toml_str};
use penumbra_scene::{Location, SceneError};
use std::path::{Path, PathBuf};

fn corpus(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/corpus/toml")
        .join(name)
}

/// Loads a corpus file that must fail; checks the file is named, the
/// location is `location`, and every `needle` appears in the message.
fn check(name: &str, location: Location, needles: &[&str]) -> String {
    let err = match load_toml(&corpus(name), &LoadOptions::default()) {
        Ok(_) => panic!("{name} loaded but must fail"),
        Err(e) => e,
    };
    let text = err.to_string();
    let SceneError::Invalid {
        file,
        location: loc,
        ..
    } = &err
    else {
        panic!("{name}: expected SceneError::Invalid, got {err:?}");
    };
    assert_eq!(file, &corpus(name), "{text}");
    assert!(text.contains(name), "file not named: {text}");
    assert_eq!(loc, &location, "{text}");
    for n in needles {
        assert!(text.contains(n), "{name}: message lacks {n:?}: {text}");
    }
    text
}

fn path(p: &str) -> Location {
    Location::Path(p.to_string())
}

fn line(line: usize, column: usize) -> Location {
    Location::Line {
        line,
        column: Some(column),
    }
}

#[test]
fn empty_file_has_no_objects() {
    check("empty.toml", Location::File, &["no objects", "[[objects]]"]);
    check("no-objects.toml", Location::File, &["no objects"]);
}

#[test]
fn syntax_error_gives_line_and_column() {
    let t = check(
        "syntax-error.toml",
        line(7, 1),
        &["syntax-error.toml:7:1:", "comma", "near `[[objects]]`"],
    );
    assert!(!t.contains('\n'), "one line: {t}");
}

#[test]
fn unknown_key_gives_line_and_key_path() {
    check(
        "unknown-key.toml",
        line(14, 1),
        &["objects[1].radiuss", "unknown field `radiuss`", "`radius`"],
    );
}

#[test]
fn wrong_value_type_gives_line_and_key_path() {
    check(
        "wrong-type.toml",
        line(4, 13),
        &["camera.fov_y_deg", "\"wide\"", "expected f64"],
    );
}

#[test]
fn albedo_out_of_range() {
    for (file, mat, value, l) in [
        ("negative-albedo.toml", 1, "[0.5, -0.1, 0.2]", 9),
        ("albedo-above-one.toml", 0, "[1.2, 0.5, 0.5]", 4),
        ("nan-albedo.toml", 0, "[0.5, NaN, 0.5]", 4),
    ] {
        check(
            file,
            path(&format!("materials[{mat}].albedo")),
            &[
                "reflectance must be in [0, 1]",
                &format!("got {value}"),
                &format!("(line {l})"),
            ],
        );
    }
    check(
        "kd-too-large.toml",
        path("materials[0].kd"),
        &["kd must be in [0, 1/π", "got 0.5", "(line 4)"],
    );
}

#[test]
fn zero_radius() {
    check(
        "zero-radius.toml",
        path("objects[2].radius"),
        &[
            "at objects[2].radius",
            "radius must be finite and > 0",
            "got 0",
            "(line 20)",
        ],
    );
}

#[test]
fn render_settings_out_of_range() {
    check(
        "zero-spp.toml",
        path("render.spp"),
        &["spp must be an integer in [1, ", "got 0", "(line 3)"],
    );
    check(
        "zero-resolution.toml",
        path("render.resolution"),
        &["[width, height]", "[1, 65536]", "got [0, 10]", "(line 2)"],
    );
    check(
        "unknown-integrator.toml",
        path("render.integrator"),
        &[
            "unknown integrator 'photon'",
            "local, direct, path, ao",
            "(line 2)",
        ],
    );
}

#[test]
fn material_references_and_names() {
    check(
        "unknown-material.toml",
        path("objects[1].material"),
        &[
            "unknown material 'blue'",
            "defined: red, white",
            "(line 17)",
        ],
    );
    check(
        "duplicate-material.toml",
        path("materials[1].name"),
        &[
            "duplicate material name 'white'",
            "materials[0]",
            "(line 7)",
        ],
    );
}

#[test]
fn mesh_paths() {
    check(
        "mesh-escape.toml",
        path("objects[0].mesh"),
        &[
            "'../../../../secret/model.obj'",
            "leaves the scene's folder",
            "(line 2)",
        ],
    );
    check(
        "mesh-absolute.toml",
        path("objects[0].mesh"),
        &["absolute path '/etc/model.obj' is not allowed"],
    );
    check(
        "missing-mesh.toml",
        path("objects[1].mesh"),
        &[
            "mesh file 'meshes/does-not-exist.obj' not found",
            "does-not-exist.obj)",
            "(line 6)",
        ],
    );
}

#[test]
fn lights_and_shapes() {
    check(
        "inner-cone-exceeds-outer.toml",
        path("lights[0].inner_cone_deg"),
        &[
            "inner_cone_deg (40)",
            "outer_cone_deg (30)",
            "0 <= inner <= outer <= 90",
        ],
    );
    check(
        "key-for-other-light-type.toml",
        path("lights[0].irradiance"),
        &["`irradiance` does not apply to a point light", "intensity"],
    );
    check(
        "unknown-shape.toml",
        path("objects[0].shape"),
        &["unknown shape 'torus'", "sphere, quad, box, disk"],
    );
    check(
        "parallel-quad-edges.toml",
        path("objects[0].edge2"),
        &["parallel", "no area"],
    );
    check(
        "matrix-and-translate.toml",
        path("objects[0].translate"),
        &["cannot be combined with `matrix`"],
    );
}

/// Smaller cases written inline; `f` names the virtual file.
fn inline_err(text: &str) -> String {
    let f = Path::new("inline/scene.toml");
    match load_toml_str(text, f, &LoadOptions::default()) {
        Ok(_) => panic!("must fail:\n{text}"),
        Err(e) => {
            let t = e.to_string();
            assert!(t.starts_with("inline/scene.toml"), "{t}");
            t
        }
    }
}

const SPHERE: &str = "\n[[objects]]\nshape = \"sphere\"\nradius = 1\n";

#[test]
fn more_value_errors_name_path_and_range() {
    let cases: &[(&str, &[&str])] = &[
        (
            "[camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, -1]\nfov_y_deg = 180\n",
            &["camera.fov_y_deg", "(0, 180)", "got 180"],
        ),
        (
            "[camera]\ntype = \"orthographic\"\nposition = [0, 0, 0]\nlook_at = [0, 0, -1]\n",
            &["at camera:", "needs height"],
        ),
        (
            "[camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, 0]\nfov_y_deg = 40\n",
            &["camera.look_at", "must differ from position"],
        ),
        (
            "[camera]\nposition = [0, 0, 0]\nlook_at = [0, 5, 0]\nfov_y_deg = 40\n",
            &["camera.up", "parallel"],
        ),
        (
            "background = [1, -1, 0]\n",
            &["at background", "got [1, -1, 0]"],
        ),
        ("[render]\nmax_depth = 0\n", &["render.max_depth", "got 0"]),
        (
            "[render]\nao_distance = -1\n",
            &["render.ao_distance", "> 0"],
        ),
        ("[render]\nseed = -3\n", &["render.seed", "got -3"]),
        (
            "[[materials]]\nname = \"m\"\ntype = \"ggx\"\nalbedo = 0.5\n",
            &[
                "materials[0].type",
                "unknown material type 'ggx'",
                "lambert, phong, mirror, conductor, dielectric, metallic-roughness",
            ],
        ),
        (
            "[[materials]]\nname = \"m\"\ntype = \"plastic\"\n",
            &["materials[0].type", "unknown material type 'plastic'"],
        ),
        (
            "[[materials]]\nname = \"m\"\ntype = \"lambert\"\n",
            &["at materials[0]:", "albedo", "kd"],
        ),
        (
            "[[materials]]\nname = \"m\"\ntype = \"lambert\"\nalbedo = 0.5\nkd = 0.1\n",
            &["materials[0].kd", "not both"],
        ),
        (
            "[[materials]]\nname = \"m\"\ntype = \"lambert\"\nalbedo = [0.5, 0.5]\n",
            &["materials[0].albedo", "[r, g, b]", "got 2 numbers"],
        ),
        (
            "[[materials]]\nname = \"m\"\ntype = \"lambert\"\nalbedo = 0.5\nemission = [-1, 0, 0]\n",
            &["materials[0].emission", ">= 0", "got [-1, 0, 0]"],
        ),
        (
            "[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\n",
            &[
                "at lights[0]:",
                "exactly one of: intensity, power, intensity_cd, power_lm",
            ],
        ),
        (
            "[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = 1\npower = 4\n",
            &["lights[0].power", "only one of"],
        ),
        (
            "[[lights]]\ntype = \"directional\"\ndirection = [0, 0, 0]\nirradiance = 1\n",
            &["lights[0].direction", "non-zero"],
        ),
        (
            "[[lights]]\ntype = \"spot\"\nposition = [0, 1, 0]\ndirection = [0, -1, 0]\nintensity = 1\nouter_cone_deg = 120\n",
            &["lights[0].outer_cone_deg", "[0, 90]", "got 120"],
        ),
        (
            "[[lights]]\ntype = \"area\"\n",
            &[
                "lights[0].type",
                "unknown light type 'area'",
                "point, directional, spot",
            ],
        ),
        (
            "[[objects]]\nshape = \"box\"\nmin = [0, 0, 0]\nmax = [1, 0, 1]\n",
            &["objects[0].max", "exceed min"],
        ),
        (
            "[[objects]]\nshape = \"box\"\nsize = [1, -1, 1]\n",
            &["objects[0].size", "> 0", "got [1, -1, 1]"],
        ),
        (
            "[[objects]]\nshape = \"sphere\"\nradius = 1\nsize = 2\n",
            &["objects[0].size", "does not apply to a sphere", "radius"],
        ),
        (
            "[[objects]]\nshape = \"sphere\"\nradius = 1\nsubdivisions = 1\n",
            &["objects[0].subdivisions", "[2, 1024]", "got 1"],
        ),
        (
            "[[objects]]\nshape = \"disk\"\nradius = -2\n",
            &["objects[0].radius", "got -2"],
        ),
        (
            "[[objects]]\nshape = \"quad\"\nsize = [1, 1]\ncorner = [0, 0, 0]\n",
            &["at objects[0]:", "corner + edge1 + edge2", "vertices"],
        ),
        (
            "[[objects]]\nshape = \"quad\"\nvertices = [[0, 0, 0], [1, 0, 0], [1, 1, 0]]\n",
            &["objects[0].vertices", "4 points", "got 3"],
        ),
        (
            "[[objects]]\nshape = \"quad\"\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]\n",
            &["objects[0].vertices", "convex"],
        ),
        (
            "[[objects]]\nshape = \"sphere\"\nradius = 1\nscale = 0\n",
            &["objects[0].scale", "non-zero", "got 0"],
        ),
        (
            "[[objects]]\nshape = \"sphere\"\nradius = 1\nrotate_deg = [0, 90, 0]\nrotate_axis_angle = { axis = [0, 1, 0], angle_deg = 90 }\n",
            &["objects[0].rotate_axis_angle", "not both"],
        ),
        (
            "[[objects]]\nshape = \"sphere\"\nradius = 1\nmatrix = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 1, 1]]\n",
            &["objects[0].matrix[3]", "[0, 0, 0, 1]"],
        ),
        (
            "[[objects]]\nshape = \"sphere\"\nradius = 1\nmatrix = [[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n",
            &["objects[0].matrix", "singular"],
        ),
        (
            "[[objects]]\nshape = \"sphere\"\nradius = 1\nmesh = \"a.obj\"\n",
            &["objects[0].mesh", "not both"],
        ),
        (
            "[[objects]]\nmesh = \"a.obj\"\nradius = 1\n",
            &["objects[0].radius", "shape parameter"],
        ),
        (
            "[[objects]]\nmesh = \"a.ply\"\n",
            &["objects[0].mesh", ".obj, .gltf or .glb"],
        ),
        (
            "[[objects]]\nname = \"nothing\"\n",
            &["at objects[0]:", "needs shape"],
        ),
        (
            "[[objects]]\nshape = \"sphere\"\nradius = 1\ncenter = [0, 1]\n",
            &["objects[0].center", "[x, y, z]", "got [0, 1]"],
        ),
        (
            "[[objects]]\nshape = \"sphere\"\nradius = 1\ncenter = [0, inf, 0]\n",
            &["objects[0].center", "finite"],
        ),
        (
            "[[objects]]\nshape = \"sphere\"\nradius = 1e39\n",
            &["objects[0].radius", "got 1e39"],
        ),
    ];
    for (text, needles) in cases {
        let msg = inline_err(text);
        for n in *needles {
            assert!(msg.contains(n), "{msg:?} lacks {n:?} for:\n{text}");
        }
    }
    // Where the objects are fine, the error is still the first bad value.
    let msg = inline_err(&format!("[render]\nspp = -5\n{SPHERE}"));
    assert!(
        msg.contains("render.spp") && msg.contains("got -5"),
        "{msg}"
    );
}

#[test]
fn serde_errors_in_nested_tables() {
    let msg = inline_err(&format!(
        "[[objects]]\nshape = \"sphere\"\nradius = 1\nrotate_axis_angle = {{ axis = [0, 1, 0], angle = 3 }}\n{SPHERE}"
    ));
    assert!(
        msg.contains("inline/scene.toml:4:")
            && msg.contains("objects[0].rotate_axis_angle.angle")
            && msg.contains("unknown field `angle`"),
        "{msg}"
    );
    let msg = inline_err(&format!("[render]\nresolution = [64, \"a\"]\n{SPHERE}"));
    assert!(
        msg.contains(":2:") && msg.contains("render.resolution[1]"),
        "{msg}"
    );
    let msg = inline_err(&format!("[camera]\nfov = 40\n{SPHERE}"));
    assert!(
        msg.contains("camera.fov") && msg.contains("unknown field `fov`"),
        "{msg}"
    );
    let msg = inline_err(&format!("colour = 1\n{SPHERE}"));
    assert!(
        msg.contains(":1:1:") && msg.contains("unknown field `colour`"),
        "{msg}"
    );
    let msg = inline_err(&format!("[[objects]]\nradius = 1\nradius = 2\n{SPHERE}"));
    assert!(
        msg.contains(":3:1:") && msg.contains("duplicate key"),
        "{msg}"
    );
}
