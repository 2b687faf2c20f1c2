//! `[[materials]]` of every type: the parsed BSDF values, and errors for bad
//! parameters that name the file, the key path and the allowed range.

use glam::Vec3;
use penumbra_scene::load::{LoadOptions, load_toml_str};
use penumbra_scene::{Location, Material, Scene, SceneError};
use penumbra_shading::bsdf::optics::f0_from_ior;
use penumbra_shading::bsdf::{
    Bsdf, Conductor, Dielectric, FresnelModel, Lambert, MetallicRoughness, Mirror, PhongBlinn,
    PhongVariant, RoughConductor, RoughDielectric, conductor_preset,
};
use std::f32::consts::PI;
use std::path::Path;

const FILE: &str = "inline/materials.toml";
const SPHERE: &str = "\n[[objects]]\nshape = \"sphere\"\nradius = 1\n";

fn load(text: &str) -> Scene {
    load_toml_str(
        &format!("{text}{SPHERE}"),
        Path::new(FILE),
        &LoadOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e}\n---\n{text}"))
}

fn material<'a>(s: &'a Scene, name: &str) -> &'a Material {
    s.materials
        .iter()
        .find(|m| m.name == name)
        .unwrap_or_else(|| panic!("no material {name}"))
}

fn one(text: &str) -> Material {
    let s = load(&format!("[[materials]]\nname = \"m\"\n{text}"));
    material(&s, "m").clone()
}

#[test]
fn lambert_and_phong() {
    assert_eq!(
        one("type = \"lambert\"\nalbedo = [0.5, 0.25, 1]").bsdf,
        Bsdf::Lambert(Lambert::new(Vec3::new(0.5, 0.25, 1.0)))
    );
    let Bsdf::Lambert(l) = one("type = \"lambert\"\nkd = 0.1").bsdf else {
        panic!()
    };
    assert!((l.albedo - Vec3::splat(0.1 * PI)).length() < 1e-6);

    // The notes' quiz material: kd given directly, every variant by name.
    for (name, variant) in [
        ("notes", PhongVariant::Notes),
        ("max-blinn", PhongVariant::MaxBlinn),
        ("halfway-squared", PhongVariant::HalfwaySquared),
    ] {
        let m = one(&format!(
            "type = \"phong\"\nvariant = \"{name}\"\nkd = 0.2\nks = [1.25, 2, 0]\nshininess = 3"
        ));
        assert_eq!(
            m.bsdf,
            Bsdf::PhongBlinn(PhongBlinn {
                kd: Vec3::splat(0.2),
                ks: Vec3::new(1.25, 2.0, 0.0),
                shininess: 3.0,
                variant,
            }),
            "{name}"
        );
    }
    // Default variant: normalized, with albedo → kd = ρ/π and ks ≤ 1.
    let Bsdf::PhongBlinn(p) = one("type = \"phong\"\nalbedo = 0.6\nks = 0.3\nshininess = 40").bsdf
    else {
        panic!()
    };
    assert_eq!(p.variant, PhongVariant::Normalized);
    assert!((p.kd - Vec3::splat(0.6 / PI)).length() < 1e-7);
    assert_eq!((p.ks, p.shininess), (Vec3::splat(0.3), 40.0));
    // Diffuse and ks default to 0.
    let Bsdf::PhongBlinn(p) = one("type = \"phong\"\nshininess = 0").bsdf else {
        panic!()
    };
    assert_eq!((p.kd, p.ks), (Vec3::ZERO, Vec3::ZERO));
}

#[test]
fn mirror_conductor_dielectric() {
    assert_eq!(
        one("type = \"mirror\"").bsdf,
        Bsdf::Mirror(Mirror {
            reflectance: Vec3::ONE
        })
    );
    assert_eq!(
        one("type = \"mirror\"\nreflectance = [0.9, 0.8, 0.7]").bsdf,
        Bsdf::Mirror(Mirror {
            reflectance: Vec3::new(0.9, 0.8, 0.7)
        })
    );

    // Smooth conductor from a preset; exact Fresnel by default.
    let (eta, k) = conductor_preset("gold").unwrap();
    assert_eq!(
        one("type = \"conductor\"\npreset = \"gold\"").bsdf,
        Bsdf::Conductor(Conductor {
            eta,
            k,
            fresnel: FresnelModel::Exact
        })
    );
    let f0 = f0_from_ior(eta, k);
    assert!(f0.x > f0.z, "gold is yellow: {f0}");
    // Rough conductor: α = roughness², explicit index, Schlick.
    assert_eq!(
        one("type = \"conductor\"\neta = [0.2, 0.9, 1.1]\nk = [3.9, 2.4, 2.2]\nroughness = 0.5\nfresnel = \"schlick\"").bsdf,
        Bsdf::RoughConductor(RoughConductor {
            eta: Vec3::new(0.2, 0.9, 1.1),
            k: Vec3::new(3.9, 2.4, 2.2),
            alpha: 0.25,
            fresnel: FresnelModel::Schlick
        })
    );
    assert_eq!(
        one("type = \"conductor\"\npreset = \"aluminum\"\nroughness = 0").bsdf,
        one("type = \"conductor\"\npreset = \"aluminium\"").bsdf
    );

    // Dielectric: defaults ior 1.5, clear, exact; always two-sided.
    let glass = one("type = \"dielectric\"");
    assert_eq!(
        glass.bsdf,
        Bsdf::Dielectric(Dielectric {
            eta: 1.5,
            tint: Vec3::ONE,
            fresnel: FresnelModel::Exact
        })
    );
    assert!(glass.double_sided);
    assert_eq!(
        one("type = \"dielectric\"\nior = 1.33\ntint = [0.9, 1, 1]\nfresnel = \"schlick\"").bsdf,
        Bsdf::Dielectric(Dielectric {
            eta: 1.33,
            tint: Vec3::new(0.9, 1.0, 1.0),
            fresnel: FresnelModel::Schlick
        })
    );
    // An emissive dielectric is still two-sided.
    let frosted = one("type = \"dielectric\"\nior = 1.5\nroughness = 0.3\nemission = 1");
    assert_eq!(
        frosted.bsdf,
        Bsdf::RoughDielectric(RoughDielectric {
            eta: 1.5,
            alpha: 0.3 * 0.3,
            tint: Vec3::ONE
        })
    );
    assert!(frosted.double_sided);
}

#[test]
fn metallic_roughness() {
    // glTF's defaults.
    assert_eq!(
        one("type = \"metallic-roughness\"").bsdf,
        Bsdf::MetallicRoughness(MetallicRoughness {
            base_color: Vec3::ONE,
            metallic: 1.0,
            roughness: 1.0,
            ior: 1.5,
            transmission: 0.0,
            specular: 1.0,
            specular_color: Vec3::ONE,
        })
    );
    let m = one(
        "type = \"metallic-roughness\"\nbase_color = [0.8, 0.1, 0.1]\nmetallic = 0\nroughness = 0.2\nior = 1.45\ntransmission = 0.5\nspecular = 0.7\nspecular_color = [1, 0.9, 0.8]",
    );
    assert_eq!(
        m.bsdf,
        Bsdf::MetallicRoughness(MetallicRoughness {
            base_color: Vec3::new(0.8, 0.1, 0.1),
            metallic: 0.0,
            roughness: 0.2,
            ior: 1.45,
            transmission: 0.5,
            specular: 0.7,
            specular_color: Vec3::new(1.0, 0.9, 0.8),
        })
    );
    assert!(m.double_sided, "transmissive");
    assert!(m.metallic_roughness_texture.is_none());
    // Opaque emitters stay front-side only.
    assert!(!one("type = \"metallic-roughness\"\nemission = 2").double_sided);
}

/// `text` (one material) must fail at key path `path` (with the line when
/// the key is written), naming the file and saying every `needle`.
fn bad(text: &str, path: &str, needles: &[&str]) {
    let full = format!("[[materials]]\nname = \"m\"\n{text}{SPHERE}");
    let err = match load_toml_str(&full, Path::new(FILE), &LoadOptions::default()) {
        Ok(_) => panic!("must fail:\n{text}"),
        Err(e) => e,
    };
    let msg = err.to_string();
    let SceneError::Invalid { file, location, .. } = &err else {
        panic!("{err:?}")
    };
    assert_eq!(file, Path::new(FILE), "{msg}");
    assert_eq!(location, &Location::Path(path.to_string()), "{msg}");
    assert!(msg.starts_with(&format!("{FILE} at {path}: ")), "{msg}");
    for n in needles {
        assert!(msg.contains(n), "{msg:?} lacks {n:?} for:\n{text}");
    }
}

#[test]
fn bad_values_name_the_key_path_and_the_range() {
    let m = "materials[0]";
    let cases: &[(&str, &str, &[&str])] = &[
        (
            "type = \"lambert\"\nalbedo = [0.5, -0.1, 0.2]",
            "albedo",
            &[
                "reflectance must be in [0, 1] in every channel, got [0.5, -0.1, 0.2]",
                "(line 4)",
            ],
        ),
        (
            "type = \"phong\"\nalbedo = 1.2\nshininess = 1",
            "albedo",
            &["in [0, 1]", "got 1.2"],
        ),
        (
            "type = \"phong\"\nks = [0.5, -0.1, 0]\nshininess = 10",
            "ks",
            &["in [0, 1]", "got [0.5, -0.1, 0]"],
        ),
        (
            "type = \"phong\"\nvariant = \"max-blinn\"\nks = -1\nshininess = 10",
            "ks",
            &[">= 0", "got -1"],
        ),
        (
            "type = \"phong\"\nks = 0.5\nshininess = -2",
            "shininess",
            &["shininess must be finite and >= 0, got -2"],
        ),
        (
            "type = \"phong\"\nkd = 0.4\nshininess = 2",
            "kd",
            &["[0, 1/π", "got 0.4"],
        ),
        (
            "type = \"phong\"\nvariant = \"blinn\"\nshininess = 2",
            "variant",
            &[
                "unknown phong variant 'blinn'",
                "notes, max-blinn, halfway-squared, normalized",
            ],
        ),
        (
            "type = \"mirror\"\nreflectance = 1.5",
            "reflectance",
            &["in [0, 1]", "got 1.5"],
        ),
        (
            "type = \"conductor\"\npreset = \"gold\"\nroughness = 1.5",
            "roughness",
            &["roughness must be in [0, 1], got 1.5"],
        ),
        (
            "type = \"conductor\"\npreset = \"brass\"",
            "preset",
            &[
                "unknown conductor preset 'brass'",
                "gold, silver, copper, aluminium",
            ],
        ),
        (
            "type = \"conductor\"\neta = [0, 1, 1]\nk = 3",
            "eta",
            &["eta must be finite and > 0", "got [0, 1, 1]"],
        ),
        (
            "type = \"conductor\"\neta = 1\nk = -3",
            "k",
            &[">= 0", "got -3"],
        ),
        (
            "type = \"conductor\"\npreset = \"gold\"\nfresnel = \"fast\"",
            "fresnel",
            &["unknown fresnel 'fast'", "exact, schlick"],
        ),
        (
            "type = \"dielectric\"\nior = 0",
            "ior",
            &["ior must be finite and > 0, got 0"],
        ),
        (
            "type = \"dielectric\"\nior = -1.5",
            "ior",
            &["> 0", "got -1.5"],
        ),
        (
            "type = \"dielectric\"\nroughness = -0.1",
            "roughness",
            &["roughness must be in [0, 1], got -0.1"],
        ),
        (
            "type = \"dielectric\"\nroughness = 0.2\nfresnel = \"schlick\"",
            "fresnel",
            &["roughness = 0"],
        ),
        (
            "type = \"dielectric\"\ndouble_sided = false",
            "double_sided",
            &["always two-sided"],
        ),
        (
            "type = \"metallic-roughness\"\nmetallic = 1.2",
            "metallic",
            &["metallic must be in [0, 1], got 1.2"],
        ),
        (
            "type = \"metallic-roughness\"\ntransmission = -0.5",
            "transmission",
            &["transmission must be in [0, 1], got -0.5"],
        ),
        (
            "type = \"metallic-roughness\"\nspecular = 2",
            "specular",
            &["specular must be in [0, 1], got 2"],
        ),
        (
            "type = \"metallic-roughness\"\nroughness = nan",
            "roughness",
            &["roughness must be in [0, 1], got NaN"],
        ),
        (
            "type = \"metallic-roughness\"\nior = 0",
            "ior",
            &["> 0", "got 0"],
        ),
        (
            "type = \"metallic-roughness\"\nbase_color = [1, 2, 0]",
            "base_color",
            &["in [0, 1]", "got [1, 2, 0]"],
        ),
        // Keys of another type name the keys this type takes.
        (
            "type = \"mirror\"\nroughness = 0.2",
            "roughness",
            &["`roughness` does not apply to a mirror material (it takes: reflectance)"],
        ),
        (
            "type = \"lambert\"\nalbedo = 0.5\nks = 0.2",
            "ks",
            &["does not apply to a lambert material (it takes: albedo, kd)"],
        ),
        (
            "type = \"dielectric\"\nmetallic = 0",
            "metallic",
            &[
                "does not apply to a dielectric material",
                "ior, tint, roughness, fresnel",
            ],
        ),
        (
            "type = \"conductor\"\npreset = \"gold\"\neta = 1",
            "eta",
            &["either preset or eta and k"],
        ),
    ];
    for (text, key, needles) in cases {
        bad(text, &format!("{m}.{key}"), needles);
    }
    // Missing required parameters point at the table.
    bad("type = \"conductor\"", m, &["preset", "eta", "k"]);
    bad("type = \"conductor\"\neta = 1", m, &["both eta", "and k"]);
    bad(
        "type = \"phong\"\nks = 0.5",
        m,
        &["needs shininess", ">= 0"],
    );
}

#[test]
fn unknown_keys_name_line_and_key_path() {
    let text = format!("[[materials]]\nname = \"m\"\ntype = \"phong\"\nglossiness = 3\n{SPHERE}");
    let err = load_toml_str(&text, Path::new(FILE), &LoadOptions::default()).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.starts_with(&format!("{FILE}:4:1: materials[0].glossiness")),
        "{msg}"
    );
    assert!(msg.contains("unknown field `glossiness`"), "{msg}");
    assert!(msg.contains("`shininess`"), "{msg}");
}
