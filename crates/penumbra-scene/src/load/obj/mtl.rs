//! MTL files: a checking pass before `tobj` parses them (it reports no line
//! numbers and panics on a colour with fewer than three numbers), and the
//! conversion of `tobj` materials to penumbra's.
//!
//! `Kd` (× `map_Kd`, sRGB-decoded) is the diffuse colour (clamped to [0, 1]),
//! `Ke` the emitted radiance. The `illum` mode picks the nearest model:
//!
//! | `illum` | model | parameters |
//! |---|---|---|
//! | 0, 1 | `Lambert` | albedo `Kd` (`Ks` switched off) |
//! | 2 (also: no `illum` but `Ks` > 0) | `PhongBlinn`, variant `Normalized` | kd = `Kd`/π, ks = `Ks` (the lobe's reflectance, clamped to [0, 1]), shininess γ = `Ns`; `Ks` = 0 gives `Lambert` |
//! | 3, 8 | `Mirror` | reflectance `Ks`; `Kd` ignored (warned); 8 warned as read as 3 |
//! | 5 | `Conductor` (Schlick Fresnel, κ = 0) | η per band with ((η−1)/(η+1))² = `Ks`: a Fresnel mirror whose normal reflectance is `Ks`; `Kd` ignored (warned) |
//! | 4, 6, 7, 9 | `Dielectric` (exact Fresnel), two-sided | η = `Ni` (1.5 if absent, warned), tint = `Tf` (default 1); `Kd` ignored (warned) |
//! | 10 and others | `Lambert` | `Kd`, warned (`Ks` dropped) |
//! | any, with `Pr` or `Pm` | `MetallicRoughness` | base colour `Kd`, roughness `Pr` (default 1), metallic `Pm` (default 0), ior `Ni` (default 1.5) |
//!
//! Recorded as warnings, one per material, when they would change the
//! appearance: `d` < 1 / `Tr` > 0 (dissolve is not modelled), the maps
//! `map_Ks`/`map_Ns`/`map_d`/`bump`/`norm`/`disp`/`map_Ke`, the other PBR
//! extension parameters (`Ps`, `Pc`, ...), `map_Kd` options, clamped values.

use super::ObjLoader;
use crate::error::{Location, SceneError};
use crate::load::gltf::texture::decode_texture;
use crate::material::{Material, MaterialId};
use crate::paths::resolve_uri;
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{
    Bsdf, Conductor, Dielectric, FresnelModel, Lambert, MetallicRoughness, Mirror, PhongBlinn,
    PhongVariant,
};
use std::collections::HashMap;
use std::f32::consts::FRAC_1_PI;
use std::path::{Path, PathBuf};

/// An MTL file after the checking pass.
#[derive(Debug, Default)]
pub(super) struct MtlPrepared {
    /// Text for `tobj` (same lines).
    pub text: String,
    /// (material name, keyword) → line of the statement.
    pub lines: HashMap<(String, String), usize>,
    /// Per material: statements dropped by the pass (as notes).
    pub notes: HashMap<String, Vec<String>>,
}

/// Keywords with a colour argument (`r [g b]`).
const COLOUR_KEYS: &[&str] = &["Ka", "Kd", "Ks", "Ke", "Tf"];
/// Keywords with one number.
const SCALAR_KEYS: &[&str] = &["Ns", "Ni", "d", "Tr", "sharpness"];

/// Checks and normalises MTL text (see the module docs).
pub(super) fn prepare_mtl(file: &Path, text: &str) -> Result<MtlPrepared, SceneError> {
    let mut out = MtlPrepared {
        text: String::with_capacity(text.len() + 64),
        ..Default::default()
    };
    let mut current = String::new();
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let err = |msg: String| SceneError::at_line(file, line_no, msg);
        let mut words = raw.split_whitespace();
        let Some(key) = words.next() else {
            out.text.push('\n');
            continue;
        };
        let args: Vec<&str> = words.take_while(|w| !w.starts_with('#')).collect();
        let mut line = raw.to_string();
        if key == "newmtl" {
            let name = raw.trim_start()["newmtl".len()..].trim();
            if name.is_empty() {
                return Err(err("newmtl names no material".into()));
            }
            current = name.to_string();
            line = format!("newmtl {name}");
        } else if COLOUR_KEYS.contains(&key) {
            if matches!(args.first(), Some(&"spectral") | Some(&"xyz")) {
                out.notes.entry(current.clone()).or_default().push(format!(
                    "{key} {} (line {line_no}) not supported, ignored",
                    args[0]
                ));
                line = format!("# {raw}");
            } else {
                let vals: Vec<f32> = args
                    .iter()
                    .map(|a| a.parse::<f32>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| {
                        err(format!(
                            "{key}: expected numbers, found '{}'",
                            args.join(" ")
                        ))
                    })?;
                let rgb = match vals.len() {
                    1 => [vals[0]; 3],
                    3 => [vals[0], vals[1], vals[2]],
                    n => {
                        return Err(err(format!(
                            "{key} has {n} numbers (expected r g b, or one value for all three)"
                        )));
                    }
                };
                if rgb.iter().any(|c| !c.is_finite() || *c < 0.0) {
                    return Err(err(format!(
                        "{key} ({} {} {}) must be finite and non-negative",
                        rgb[0], rgb[1], rgb[2]
                    )));
                }
                line = format!("{key} {} {} {}", rgb[0], rgb[1], rgb[2]);
            }
        } else if SCALAR_KEYS.contains(&key) || key == "illum" {
            // `d -halo 0.5`: the option is dropped (noted) and the value kept.
            let (opts, vals): (Vec<&str>, Vec<&str>) = args
                .iter()
                .partition(|a| a.starts_with('-') && a.parse::<f32>().is_err());
            if !opts.is_empty() {
                out.notes
                    .entry(current.clone())
                    .or_default()
                    .push(format!("{key} option {} ignored", opts.join(" ")));
            }
            let Some(v) = vals.first() else {
                return Err(err(format!("{key} needs a value")));
            };
            if key == "illum" {
                v.parse::<u8>()
                    .map_err(|_| err(format!("illum '{v}' is not an illumination model 0-10")))?;
            } else {
                let x: f32 = v
                    .parse()
                    .map_err(|_| err(format!("{key}: '{v}' is not a number")))?;
                if !x.is_finite() {
                    return Err(err(format!("{key} {x} is not finite")));
                }
            }
            line = format!("{key} {v}");
        }
        if !current.is_empty() {
            out.lines
                .entry((current.clone(), key.to_string()))
                .or_insert(line_no);
        }
        out.text.push_str(&line);
        out.text.push('\n');
    }
    Ok(out)
}

fn fmt_rgb(c: [f32; 3]) -> String {
    format!("({} {} {})", c[0], c[1], c[2])
}

fn parse_floats(s: &str) -> Option<Vec<f32>> {
    s.split_whitespace().map(|t| t.parse().ok()).collect()
}

/// The file name in a texture statement's argument: options (`-bm 1 -o 0 0`)
/// come first, the name last. Returns (name, had options).
fn texture_file_name(arg: &str) -> (&str, bool) {
    let arg = arg.trim();
    if arg.starts_with('-') {
        (arg.split_whitespace().last().unwrap_or(""), true)
    } else {
        (arg, false)
    }
}

/// Where a converted material came from.
#[derive(Debug, Clone)]
pub(super) struct MtlSource {
    pub file: PathBuf,
    pub lines: HashMap<(String, String), usize>,
    pub notes: HashMap<String, Vec<String>>,
}

impl ObjLoader<'_> {
    /// Converts `tobj` material `k` (from `source`) to a scene material.
    pub(super) fn convert_material(
        &mut self,
        mat: &tobj::Material,
        source: &MtlSource,
    ) -> Result<MaterialId, SceneError> {
        let mut notes: Vec<String> = source.notes.get(&mat.name).cloned().unwrap_or_default();
        let line_of = |key: &str| {
            source
                .lines
                .get(&(mat.name.clone(), key.to_string()))
                .copied()
        };

        let kd = mat.diffuse.unwrap_or([0.8; 3]);
        let albedo = Rgb::from(kd);
        let clamped = albedo.clamp(Rgb::ZERO, Rgb::ONE);
        if clamped != albedo {
            notes.push(format!("Kd {} clamped to [0, 1]", fmt_rgb(kd)));
        }
        let emission = Rgb::from(mat.emissive.unwrap_or([0.0; 3]));

        let illum = mat.illumination_model;
        let ks_raw = mat.specular.unwrap_or([0.0; 3]);
        let ks = Rgb::from(ks_raw).min(Rgb::ONE);
        let param = |k: &str| mat.unknown_param.get(k).map(String::as_str);
        let scalar = |k: &str| param(k).and_then(|t| t.trim().parse::<f32>().ok());
        let dissolve = mat
            .dissolve
            .or_else(|| scalar("Tr").map(|t| 1.0 - t))
            .unwrap_or(1.0);
        let ni = mat.optical_density.filter(|n| *n > 0.0);
        let tf = param("Tf").and_then(parse_floats).filter(|v| v.len() == 3);
        let (pr, pm) = (scalar("Pr"), scalar("Pm"));
        let clamp_ks = |notes: &mut Vec<String>| {
            if ks != Rgb::from(ks_raw) {
                notes.push(format!("Ks {} clamped to [0, 1]", fmt_rgb(ks_raw)));
            }
        };
        let kd_unused = |notes: &mut Vec<String>, why: &str| {
            if mat.diffuse.is_some() && clamped.max_element() > 0.0 {
                notes.push(format!("Kd {} ignored ({why})", fmt_rgb(kd)));
            }
        };
        // See the module docs for the table.
        let mut refracting = false;
        let bsdf = if pr.is_some() || pm.is_some() {
            let unit = |k: &str, v: Option<f32>, d: f32, notes: &mut Vec<String>| {
                let x = v.unwrap_or(d);
                let c = x.clamp(0.0, 1.0);
                if c != x {
                    notes.push(format!("{k} {x} clamped to [0, 1]"));
                }
                c
            };
            let roughness = unit("Pr", pr, 1.0, &mut notes);
            let metallic = unit("Pm", pm, 0.0, &mut notes);
            Bsdf::MetallicRoughness(MetallicRoughness {
                base_color: clamped,
                metallic,
                roughness,
                ior: ni.unwrap_or(1.5),
                transmission: 0.0,
                specular: 1.0,
                specular_color: Rgb::ONE,
            })
        } else {
            match illum.unwrap_or(if ks.max_element() > 0.0 { 2 } else { 1 }) {
                0 | 1 => Bsdf::Lambert(Lambert::new(clamped)),
                2 if ks.max_element() <= 0.0 => Bsdf::Lambert(Lambert::new(clamped)),
                2 => {
                    clamp_ks(&mut notes);
                    Bsdf::PhongBlinn(PhongBlinn {
                        kd: clamped * FRAC_1_PI,
                        ks,
                        shininess: mat.shininess.unwrap_or(0.0).max(0.0),
                        variant: PhongVariant::Normalized,
                    })
                }
                n @ (3 | 8) => {
                    clamp_ks(&mut notes);
                    kd_unused(
                        &mut notes,
                        &format!("illum {n} is a mirror of reflectance Ks"),
                    );
                    if n == 8 {
                        notes.push(
                            "illum 8 (reflection without ray tracing) read as illum 3".into(),
                        );
                    }
                    Bsdf::Mirror(Mirror { reflectance: ks })
                }
                5 => {
                    clamp_ks(&mut notes);
                    kd_unused(&mut notes, "illum 5 is a Fresnel mirror");
                    // A real index per band whose normal reflectance is Ks:
                    // F0 = ((n−1)/(n+1))² ⇔ n = (1 + √F0)/(1 − √F0).
                    let s = Rgb::new(ks.x.sqrt(), ks.y.sqrt(), ks.z.sqrt()).min(Rgb::splat(0.9999));
                    Bsdf::Conductor(Conductor {
                        eta: (Rgb::ONE + s) / (Rgb::ONE - s),
                        k: Rgb::ZERO,
                        fresnel: FresnelModel::Schlick,
                    })
                }
                n @ (4 | 6 | 7 | 9) => {
                    refracting = true;
                    kd_unused(&mut notes, &format!("illum {n} is a clear dielectric"));
                    if ni.is_none() {
                        notes.push(format!("illum {n} without Ni: ior 1.5 assumed"));
                    }
                    let tint = tf.as_ref().map_or(Rgb::ONE, |v| Rgb::new(v[0], v[1], v[2]));
                    let tint_c = tint.clamp(Rgb::ZERO, Rgb::ONE);
                    if tint_c != tint {
                        notes.push(format!("Tf {} clamped to [0, 1]", fmt_rgb(tint.into())));
                    }
                    Bsdf::Dielectric(Dielectric {
                        eta: ni.unwrap_or(1.5),
                        tint: tint_c,
                        fresnel: FresnelModel::Exact,
                    })
                }
                n => {
                    notes.push(format!(
                        "illum {n} has no nearer model than Lambertian (Kd); Ks dropped"
                    ));
                    Bsdf::Lambert(Lambert::new(clamped))
                }
            }
        };
        if dissolve < 1.0 {
            notes.push(format!("transparency (d {dissolve}) ignored (opaque)"));
        }
        for (key, present) in [
            ("map_Ks", mat.specular_texture.is_some()),
            ("map_Ns", mat.shininess_texture.is_some()),
            ("map_d", mat.dissolve_texture.is_some()),
            ("bump/map_Bump", mat.normal_texture.is_some()),
        ] {
            if present {
                notes.push(format!("{key} ignored"));
            }
        }
        let mut extra: Vec<&String> = mat
            .unknown_param
            .keys()
            .filter(|k| {
                matches!(
                    k.as_str(),
                    "norm"
                        | "disp"
                        | "decal"
                        | "refl"
                        | "map_Ke"
                        | "Ps"
                        | "Pc"
                        | "Pcr"
                        | "aniso"
                        | "anisor"
                        | "map_Pr"
                        | "map_Pm"
                        | "map_Ps"
                )
            })
            .collect();
        extra.sort();
        for k in extra {
            notes.push(format!("{k} {} ignored", mat.unknown_param[k]));
        }

        let albedo_texture = match &mat.diffuse_texture {
            Some(arg) => {
                let (name, had_options) = texture_file_name(arg);
                if had_options {
                    notes.push(format!("map_Kd options in '{arg}' ignored"));
                }
                let location = match line_of("map_Kd") {
                    Some(line) => Location::Line { line, column: None },
                    None => Location::File,
                };
                let path = resolve_uri(
                    &source.file,
                    name,
                    &self.options.allowed_absolute_paths,
                    location,
                )?;
                if let Some(&id) = self.textures.get(&path) {
                    Some(id)
                } else {
                    match std::fs::read(&path)
                        .map_err(|e| format!("cannot be read ({e})"))
                        .and_then(|bytes| {
                            decode_texture(&bytes, name.to_string())
                                .map_err(|e| format!("cannot be decoded ({e})"))
                        }) {
                        Ok(tex) => {
                            self.scene.textures.push(tex);
                            let id = self.scene.textures.len() - 1;
                            self.textures.insert(path, id);
                            Some(id)
                        }
                        Err(e) => {
                            notes.push(format!("map_Kd '{name}' {e}; Kd used alone"));
                            None
                        }
                    }
                }
            }
            None => None,
        };

        if !notes.is_empty() {
            self.scene.warnings.push(format!(
                "{}: material '{}' ({}): {}",
                self.file.display(),
                mat.name,
                source.file.display(),
                notes.join("; ")
            ));
        }
        // Emitters emit from the front only, as in the reference scenes.
        let emissive = emission.max_element() > 0.0;
        Ok(self.scene.add_material(Material {
            name: mat.name.clone(),
            bsdf,
            albedo_texture,
            metallic_roughness_texture: None,
            emission,
            emission_texture: None,
            // Dielectrics are crossed both ways.
            double_sided: refracting || !emissive,
            cull_back_faces: false,
            normal_map: None,
            occlusion_map: None,
            alpha: None,
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prepare_normalises_and_reports_lines() {
        let f = Path::new("m.mtl");
        let p = prepare_mtl(
            f,
            "newmtl a\nKd 0.5\nKs 1 1 1 # shiny\nd -halo 0.5\nmap_Kd t.png\n",
        )
        .unwrap();
        assert!(p.text.contains("Kd 0.5 0.5 0.5\n"));
        assert!(p.text.contains("Ks 1 1 1\n"));
        assert!(p.text.contains("d 0.5\n"));
        assert_eq!(p.lines[&("a".to_string(), "map_Kd".to_string())], 5);
        assert_eq!(p.notes["a"].len(), 1);
        assert_eq!(
            prepare_mtl(f, "newmtl a\nKd\n").unwrap_err().to_string(),
            "m.mtl:2: Kd has 0 numbers (expected r g b, or one value for all three)"
        );
        assert!(prepare_mtl(f, "newmtl a\nKd 1 2\n").is_err());
        assert!(
            prepare_mtl(f, "newmtl a\nNs\n")
                .unwrap_err()
                .to_string()
                .starts_with("m.mtl:2:")
        );
        assert!(prepare_mtl(f, "newmtl\n").is_err());
        assert!(prepare_mtl(f, "newmtl a\nillum x\n").is_err());
        assert_eq!(texture_file_name("-bm 1 tex.png"), ("tex.png", true));
        assert_eq!(texture_file_name(" my tex.png "), ("my tex.png", false));
    }
}
