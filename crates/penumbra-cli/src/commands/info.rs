//! `penumbra info`.

use crate::options::load_scene;
use anyhow::{Result, bail};
use clap::Args;
use penumbra_shading::light::Light;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Scene file (.gltf, .glb, .obj, .toml).
    pub scene: Option<PathBuf>,
    /// Print the GPU adapter the raster engine uses (name, backend, type, driver).
    #[arg(long)]
    pub gpu: bool,
    /// Describe a bake directory (`penumbra bake ...`): what it holds, its
    /// atlas, settings and figures; with SCENE, also whether it fits it.
    #[arg(long)]
    pub bake: Option<PathBuf>,
}

pub fn run(args: InfoArgs) -> Result<()> {
    if args.gpu {
        print_gpu()?;
    }
    if let Some(dir) = &args.bake {
        return print_bake(dir, args.scene.as_deref());
    }
    match &args.scene {
        Some(path) => print_scene(path),
        None if args.gpu => Ok(()),
        None => bail!("give a SCENE file, --bake DIR, or --gpu for the GPU adapter"),
    }
}

/// What a bake directory holds (its manifest), and with a scene, whether it
/// was made for it (reading every page as the raster engine would).
fn print_bake(dir: &std::path::Path, scene: Option<&std::path::Path>) -> Result<()> {
    let path = dir.join(penumbra_bake::manifest::MANIFEST_FILE);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        anyhow::anyhow!(
            "{}: cannot read the manifest ({e}); is this a bake directory?",
            path.display()
        )
    })?;
    let m = penumbra_bake::Manifest::parse(&path, &text)?;
    let s = &m.settings;
    println!(
        "bake:       {} ({} v{})",
        dir.display(),
        m.format,
        m.version
    );
    println!("kind:       {}: {}", m.kind, m.quantity);
    println!("units:      {}", m.units);
    println!(
        "scene:      {} ({} instances, {} triangles, geometry {})",
        m.scene.file.as_deref().unwrap_or("(not recorded)"),
        m.scene.instances,
        m.scene.triangles,
        m.scene.geometry_hash
    );
    let mut settings = vec![format!("{} samples", s.samples), format!("seed {}", s.seed)];
    match m.kind.as_str() {
        "ao" => settings.push(match s.ao_distance {
            Some(d) => format!("AO distance {d}"),
            None => "AO distance unlimited".into(),
        }),
        "lightmap" => {
            settings.push(format!("{} bounces", s.bounces.unwrap_or(0)));
            if s.indirect_only {
                settings.push("indirect light only".into());
            }
        }
        _ => {
            settings.push(format!("{} patches", s.patches.unwrap_or(0)));
            settings.push(format!("tolerance {}", s.tolerance.unwrap_or(0.0)));
        }
    }
    println!("settings:   {}", settings.join(", "));
    let a = &m.atlas;
    println!(
        "atlas:      {} page(s) of {}x{} texels, {:.4} texels per unit, padding {}, {} charts, {:.0} % of the texels covered",
        a.pages,
        a.width,
        a.height,
        a.texels_per_unit,
        a.padding,
        a.charts,
        100.0 * a.utilization
    );
    let generated = m
        .instances
        .iter()
        .filter(|i| i.uv_source == "generated")
        .count();
    println!(
        "instances:  {} with texels ({} generated layouts, {} from TEXCOORD_1)",
        m.instances.len(),
        generated,
        m.instances.len() - generated
    );
    println!(
        "texels:     {} covered, {} baked, {} inside geometry (filled by dilation)",
        m.texels.covered, m.texels.valid, m.texels.invalid
    );
    for map in &m.maps {
        println!(
            "map:        {} ({}): {}",
            map.name,
            map.light.as_deref().unwrap_or("all lights"),
            map.pages.join(", ")
        );
    }
    let t = &m.timing;
    println!(
        "timing:     {:.2} s baking ({:.2} Mrays/s, {} rays), {:.2} s atlas and BVH",
        t.bake_seconds,
        t.rays_per_second / 1e6,
        t.rays,
        t.prepare_seconds
    );
    if let Some(c) = &m.convergence {
        println!(
            "radiosity:  {} iterations, unshot power {:.2e} of the emitted power ({}, {})",
            c.iterations, c.final_unshot_fraction, c.csv, c.plot
        );
    }
    for w in &m.warnings {
        println!("warning:    {w}");
    }
    if let Some(scene_path) = scene {
        let scene = load_scene(scene_path)?;
        penumbra_bake::read_bake(dir, &scene)?;
        println!(
            "fits:       {} (geometry hash and every page checked)",
            scene_path.display()
        );
    }
    Ok(())
}

/// The adapter `penumbra render --engine raster` picks.
fn print_gpu() -> Result<()> {
    let ctx = penumbra_raster::GpuContext::new()?;
    let a = &ctx.summary;
    println!("gpu:        {}", a.name);
    println!("  backend:  {}", a.backend);
    println!("  type:     {}", a.device_type);
    println!("  driver:   {} ({})", a.driver, a.driver_info);
    println!("  vendor:   {:#06x}, device {:#06x}", a.vendor, a.device);
    let f = ctx.device.features();
    println!(
        "  features: timestamp queries {}, adapter-specific formats {}",
        if f.contains(penumbra_raster::wgpu::Features::TIMESTAMP_QUERY) {
            "yes"
        } else {
            "no"
        },
        if f.contains(penumbra_raster::wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES) {
            "yes"
        } else {
            "no"
        }
    );
    Ok(())
}

fn print_scene(path: &std::path::Path) -> Result<()> {
    let scene = load_scene(path)?;
    println!("scene:      {}", path.display());
    println!("meshes:     {}", scene.meshes.len());
    println!("instances:  {}", scene.instances.len());
    println!("triangles:  {}", scene.triangle_count());
    println!("materials:  {}", scene.materials.len());
    for m in &scene.materials {
        println!("  '{}': {}", m.name, material_summary(m, &scene.textures));
    }
    println!("textures:   {}", scene.textures.len());
    match scene.bounds() {
        Some((lo, hi)) => println!(
            "bounds:     [{:.4}, {:.4}, {:.4}] .. [{:.4}, {:.4}, {:.4}]",
            lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
        ),
        None => println!("bounds:     (empty)"),
    }
    match &scene.camera {
        Some(c) => println!(
            "camera:     at {}, {}",
            triple(c.position()),
            projection(&c.projection)
        ),
        None => println!(
            "camera:     none (a camera framing the bounds from 30° right of +z, 25° up is used)"
        ),
    }
    if scene.cameras.len() > 1 {
        for (i, c) in scene.cameras.iter().enumerate() {
            println!(
                "  camera {i}: '{}' at {} (render --camera {i})",
                c.name,
                triple(c.camera.position())
            );
        }
    }
    let s = &scene.settings;
    println!(
        "render:     {}x{}, {} spp, max depth {}, integrator {}, seed {}",
        s.width, s.height, s.spp, s.max_depth, s.integrator, s.seed
    );
    let radius = scene
        .bounds()
        .map_or(1.0, |(lo, hi)| 0.5 * (hi - lo).length());
    if penumbra_scene::LightCount::of(&scene).is_dark() {
        println!(
            "lights:     none: no lights, no emitters, a black background; `render` lights it with the built-in studio environment (--environment none keeps it black)"
        );
    }
    println!(
        "lights:     {} abstract, {} analytic area{}",
        scene.lights.len(),
        scene.area_lights.len(),
        if scene.environment().is_black() {
            ""
        } else {
            ", environment"
        }
    );
    for l in &scene.lights {
        let p = l.light.power(radius);
        let what = match &l.light {
            Light::Point(pl) => format!(
                "point at {}, intensity {} W/sr",
                triple(pl.position),
                triple(pl.intensity)
            ),
            Light::Directional(d) => format!(
                "directional, travelling {}, irradiance {} W/m²",
                triple(d.direction),
                triple(d.irradiance)
            ),
            Light::Spot(sp) => format!(
                "spot at {} towards {}, intensity {} W/sr",
                triple(sp.position),
                triple(sp.direction),
                triple(sp.intensity)
            ),
        };
        println!("  {}: {what}; power {} W", l.name, triple(p));
    }
    (scene.area_lights.iter()).for_each(|l| {
        println!(
            "  area light '{}': {}, radiance {} W/(sr·m²), {}, power {} W",
            l.name,
            shape(&l.light.shape),
            triple(l.light.radiance),
            if l.light.two_sided {
                "two-sided"
            } else {
                "one-sided"
            },
            triple(l.light.power())
        )
    });
    // Area lights: emissive instances, power Φ = π L A per emitting side.
    for inst in &scene.instances {
        let m = scene.instance_material(inst);
        if !m.is_emissive() {
            continue;
        }
        let mesh = &scene.meshes[inst.mesh];
        let area = scene.instance_area(inst);
        let phi = m.emitted_power(area);
        println!(
            "  emitting mesh '{}' (material '{}'): area {area:.4} m², radiance {} W/(sr·m²){}, power π·L·A = {} W (scene units taken as metres)",
            mesh.name,
            m.name,
            triple(m.emission),
            if m.emission_texture.is_some() {
                " × its emission texture"
            } else {
                ""
            },
            triple(phi)
        );
    }
    println!("warnings:   {}", scene.warnings.len());
    for w in &scene.warnings {
        println!("  {w}");
    }
    Ok(())
}

/// A material's model and what modulates it, in words.
fn material_summary(m: &penumbra_scene::Material, all: &[penumbra_scene::Texture]) -> String {
    use penumbra_scene::AlphaMode;
    use penumbra_shading::bsdf::Bsdf;
    let mut parts = vec![
        match &m.bsdf {
            Bsdf::Lambert(_) => "Lambert",
            Bsdf::PhongBlinn(_) => "Phong–Blinn",
            Bsdf::Mirror(_) => "mirror",
            Bsdf::Conductor(_) => "smooth conductor",
            Bsdf::Dielectric(_) => "smooth dielectric",
            Bsdf::RoughConductor(_) => "rough conductor (GGX)",
            Bsdf::RoughDielectric(_) => "rough dielectric (GGX)",
            Bsdf::MetallicRoughness(_) => "glTF metallic–roughness",
        }
        .to_string(),
    ];
    let textures = [
        (m.albedo_texture, "base colour"),
        (m.metallic_roughness_texture, "metallic–roughness"),
        (m.emission_texture, "emission"),
        (m.normal_map.map(|n| n.texture), "normal"),
        (
            m.occlusion_map.map(|o| o.texture),
            "occlusion (raster environment light only)",
        ),
    ];
    // The UV set where it is not the first.
    let named: Vec<String> = textures
        .iter()
        .filter_map(|&(t, name)| match all[t?].uv_set {
            0 => Some(name.to_string()),
            set => Some(format!("{name} on TEXCOORD_{set}")),
        })
        .collect();
    if !named.is_empty() {
        parts.push(format!("textures: {}", named.join(", ")));
    }
    if m.is_emissive() {
        parts.push(format!("emits {} W/(sr·m²)", triple(m.emission)));
    }
    if let Some(a) = m.alpha {
        let alpha = match a.texture {
            Some(_) => format!("{} × the base colour texture's alpha", a.factor),
            None => format!("{}", a.factor),
        };
        parts.push(match a.mode {
            AlphaMode::Mask { cutoff } => {
                format!("alpha MASK: cut away where α = {alpha} < {cutoff}")
            }
            AlphaMode::Blend => format!(
                "alpha BLEND, α = {alpha} (tracer: stochastic transparency; raster: sorted blending)"
            ),
        });
    }
    if m.cull_back_faces {
        parts.push("single-sided: back faces hidden from the camera".into());
    }
    parts.join("; ")
}

/// `(x, y, z)`, rounded to 4 decimals (scientific notation below 10⁻³ and from 10⁵).
fn triple(v: glam::Vec3) -> String {
    let f = |x: f32| {
        if x == 0.0 || (1e-3..1e5).contains(&x.abs()) {
            format!("{}", (x as f64 * 1e4).round() / 1e4)
        } else {
            format!("{x:.3e}")
        }
    };
    format!("({}, {}, {})", f(v.x), f(v.y), f(v.z))
}

fn projection(p: &penumbra_scene::Projection) -> String {
    match p {
        penumbra_scene::Projection::Perspective { fov_y } => {
            format!(
                "perspective, vertical field of view {:.2}°",
                fov_y.to_degrees()
            )
        }
        penumbra_scene::Projection::Orthographic { height } => {
            format!("orthographic, view {height:.4} m high")
        }
    }
}

fn shape(s: &penumbra_shading::light::Shape) -> String {
    use penumbra_shading::light::Shape;
    match *s {
        Shape::Sphere { center, radius } => {
            format!("sphere at {}, radius {radius} m", triple(center))
        }
        Shape::Disk {
            center,
            normal,
            radius,
        } => format!(
            "disk at {}, facing {}, radius {radius} m",
            triple(center),
            triple(normal)
        ),
        Shape::Quad {
            corner,
            edge1,
            edge2,
        } => format!(
            "quad from corner {} along {} and {}",
            triple(corner),
            triple(edge1),
            triple(edge2)
        ),
    }
}
