//! The WGSL twins against the Rust models: a compute shader evaluates the
//! WGSL BSDFs (Lambert, every Phong–Blinn variant, the GGX rough conductor
//! and dielectric, metallic–roughness with its Kulla–Conty tables, the delta
//! models) and lights (point, directional and spot, with and without a
//! range, and the far fields of area lights) on random inputs (2·10⁴ per
//! test, 5000 per light kind); every component must be within relative 1e-4
//! or absolute 1e-6 of `Bsdf::eval` / `Light::sample_li` /
//! `FarField::sample_li`, and the delta models exactly 0.

mod common;

use common::{BrdfCase, LightCase, LightIncidence, close};
use glam::Vec3;
use penumbra_raster::GpuContext;
use penumbra_raster::gpu::{GpuEnvMaterial, GpuLight, GpuMaterial, MODEL_DELTA, MODEL_LAMBERT};
use penumbra_raster::material_tables::{KULLA_CONTY_BINDING, kulla_conty_table};
use penumbra_raster::passes::environment::env_material;
use penumbra_raster::shaders::with_library;
use penumbra_shading::bsdf::{
    Bsdf, CONDUCTOR_PRESETS, Conductor, DELTA_ALPHA, Dielectric, FresnelModel, Lambert, MIN_ALPHA,
    MetallicRoughness, Mirror, PhongBlinn, PhongVariant, RoughConductor, RoughDielectric,
    conductor_preset,
};
use penumbra_shading::light::{
    AreaLight, DirectionalLight, FarField, Light, PointLight, Shape, SpotLight,
};
use penumbra_shading::stats::TestRng;

const CASES: usize = 20_000;

fn unit(rng: &mut TestRng) -> Vec3 {
    loop {
        let v = Vec3::new(
            2.0 * rng.next_f32() - 1.0,
            2.0 * rng.next_f32() - 1.0,
            2.0 * rng.next_f32() - 1.0,
        );
        let l2 = v.length_squared();
        if l2 > 1e-4 && l2 <= 1.0 {
            return v / l2.sqrt();
        }
    }
}

fn colour(rng: &mut TestRng, scale: f32) -> Vec3 {
    Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * scale
}

/// Runs `entry` of the test kernels over `input` (binding `input_binding`,
/// output at the next binding; with `bind_table`, the Kulla–Conty table at
/// binding 8) and returns `count` outputs.
fn dispatch<T: bytemuck::Pod>(
    ctx: &GpuContext,
    bind_table: bool,
    entry: &str,
    input: &[u8],
    count: usize,
    input_binding: u32,
) -> Vec<T> {
    let table = kulla_conty_table();
    let extra: &[(u32, &[u8])] = if bind_table {
        &[(KULLA_CONTY_BINDING, bytemuck::cast_slice(&table))]
    } else {
        &[]
    };
    common::dispatch(
        ctx,
        &with_library(common::KERNELS_WGSL),
        entry,
        (input_binding, input),
        count,
        extra,
    )
}

/// How a case presents the material's back side to the GPU.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Side {
    Front,
    /// Rust `seen_from_back`, WGSL `material_seen_from_back` of the front.
    BackOnGpu,
    /// Rust `seen_from_back`, uploaded already inverted.
    BackOnHost,
}

impl Side {
    /// The BSDF as Rust evaluates it from this side.
    fn apply(self, bsdf: Bsdf) -> Bsdf {
        if self == Side::Front {
            bsdf
        } else {
            bsdf.seen_from_back()
        }
    }
}

/// One BRDF case: the model Rust evaluates (its back already applied) and
/// what the GPU gets.
struct Case {
    bsdf: Bsdf,
    gpu: BrdfCase,
}

fn case(front: Bsdf, side: Side, wo: Vec3, wi: Vec3) -> Case {
    let back = front.seen_from_back();
    let (uploaded, flag) = match side {
        Side::Front => (front, 0),
        Side::BackOnGpu => (front, 1),
        Side::BackOnHost => (back, 0),
    };
    let mat = GpuMaterial::from_bsdf(&uploaded, Vec3::ZERO, true);
    // Every model maps to a twin `material_eval` knows.
    assert!(mat.model <= MODEL_DELTA, "{uploaded:?}");
    Case {
        bsdf: if side == Side::Front { front } else { back },
        gpu: BrdfCase {
            mat,
            wo: wo.to_array(),
            back: flag,
            wi: wi.to_array(),
            _pad0: 0.0,
        },
    }
}

/// Directions for a case: a third both anywhere on the sphere, a third wo
/// above and wi anywhere, a third wi sampled from `bsdf` itself (its
/// reflection and transmission peaks, where narrow lobes are non-zero).
fn directions(rng: &mut TestRng, bsdf: &Bsdf, i: usize) -> (Vec3, Vec3) {
    let mut wo = unit(rng);
    let wi = unit(rng);
    if i.is_multiple_of(3) {
        return (wo, wi);
    }
    wo.z = wo.z.abs();
    if i % 3 == 2 {
        let u_lobe = rng.next_f32();
        let u = rng.next_2d();
        if let Some(s) = bsdf.sample(wo, u_lobe, u) {
            return (wo, s.wi);
        }
    }
    (wo, wi)
}

/// What a comparison saw.
#[derive(Debug, Default)]
struct Stats {
    /// Cases with a non-zero Rust value, wi above / below the surface.
    reflected: usize,
    transmitted: usize,
    /// Worst |GPU − Rust| / |Rust| over components with |Rust| > 1e-6.
    worst: f32,
}

/// Every component of every case within `close` of `Bsdf::eval`.
fn compare(name: &str, cases: &[Case], gpu: &[[f32; 4]]) -> Stats {
    let mut stats = Stats::default();
    for (i, (c, out)) in cases.iter().zip(gpu).enumerate() {
        let (wo, wi) = (Vec3::from(c.gpu.wo), Vec3::from(c.gpu.wi));
        let cpu = c.bsdf.eval(wo, wi);
        let g = Vec3::new(out[0], out[1], out[2]);
        assert!(cpu.is_finite(), "{name} case {i}: Rust {cpu:?}");
        for k in 0..3 {
            assert!(
                close(g[k], cpu[k]),
                "{name} case {i} ({:?}, back {}, wo {wo:?}, wi {wi:?}): GPU {g:?} vs Rust {cpu:?}",
                c.bsdf,
                c.gpu.back
            );
            if cpu[k].abs() > 1e-6 {
                stats.worst = stats.worst.max((g[k] - cpu[k]).abs() / cpu[k].abs());
            }
        }
        if cpu.max_element() > 0.0 {
            if wi.z > 0.0 {
                stats.reflected += 1;
            } else {
                stats.transmitted += 1;
            }
        }
    }
    eprintln!(
        "{name}: {} cases, non-zero with wi above {} / below {}, worst relative error {:.3e}",
        cases.len(),
        stats.reflected,
        stats.transmitted,
        stats.worst
    );
    stats
}

/// Evaluates `cases` on the GPU with the table source `tables`.
fn eval_cases(ctx: &GpuContext, cases: &[Case]) -> Vec<[f32; 4]> {
    let input: Vec<BrdfCase> = cases.iter().map(|c| c.gpu).collect();
    dispatch(
        ctx,
        true,
        "eval_brdf",
        bytemuck::cast_slice(&input),
        input.len(),
        0,
    )
}

/// The WGSL twins (and the Rust models) at a few fixed inputs against
/// values worked out by hand from the formulas, so that one bug made on
/// both sides still fails (the random comparisons above would pass it).
/// GGX with α = 0.5: D(θh) = α² / (π cos⁴θh (α² + tan²θh)²), height-
/// correlated G2 = 1 / (1 + Λo + Λi), Λ = (√(1 + α² tan²θ) − 1) / 2,
/// f = F D G2 / (4 cos θo cos θi).
#[test]
fn wgsl_models_give_hand_computed_values() {
    let Some(ctx) = common::gpu("wgsl_models_give_hand_computed_values") else {
        return;
    };
    let schlick = |eta: f32| {
        let mut rc = RoughConductor::new(Vec3::splat(eta), Vec3::ZERO, 0.5);
        rc.fresnel = FresnelModel::Schlick;
        Bsdf::RoughConductor(rc)
    };
    let (s60, c60) = (3f32.sqrt() / 2.0, 0.5);
    let fixed = [
        // Lambert: ρ / π.
        (
            "Lambert",
            Bsdf::Lambert(Lambert::new(Vec3::new(0.5, 0.25, 1.0))),
            Vec3::Z,
            Vec3::new(0.6, 0.0, 0.8),
            Vec3::new(0.5, 0.25, 1.0) * std::f32::consts::FRAC_1_PI,
        ),
        // Schlick, n = 1.5: F0 = 0.04. Head-on: h = n, D = 1/(π α²),
        // G2 = 1: f = 0.04 / π.
        (
            "Schlick head-on",
            schlick(1.5),
            Vec3::Z,
            Vec3::Z,
            Vec3::splat(0.012_732_395),
        ),
        // At 60° (a mirror pair, h = n): F = 0.04 + 0.96 · 0.5⁵ = 0.07;
        // tan²θ = 3, Λ = (√1.75 − 1)/2 = 0.161438, G2 = 0.755929;
        // f = 0.07 · 1.273240 · 0.755929 / (4 · 0.25) = 0.0673735.
        (
            "Schlick at 60°",
            schlick(1.5),
            Vec3::new(s60, 0.0, c60),
            Vec3::new(-s60, 0.0, c60),
            Vec3::splat(0.067_373_5),
        ),
        // wo = n, wi = (0.6, 0, 0.8): h = (1, 0, 3)/√10, tan²θh = 1/9,
        // D = 0.25 / (π · 0.81 · (0.25 + 1/9)²) = 0.753396; Λi at
        // tan²θ = 0.5625: 0.0340 (G2 = 0.967118); F = 0.04 + 0.96 ·
        // (1 − 3/√10)⁵ = 0.0400003; f = F D G2 / (4 · 0.8) = 0.00910786.
        (
            "GGX off the normal",
            schlick(1.5),
            Vec3::Z,
            Vec3::new(0.6, 0.0, 0.8),
            Vec3::splat(0.009_107_863),
        ),
        // Exact conductor Fresnel head-on: F = ((n−1)² + κ²) / ((n+1)² +
        // κ²) per band = 9.64/10.44, 6.5/8.5, 3.77/9.37; f = F / π.
        (
            "exact conductor head-on",
            Bsdf::RoughConductor(RoughConductor::new(
                Vec3::new(0.2, 0.5, 1.4),
                Vec3::new(3.0, 2.5, 1.9),
                0.5,
            )),
            Vec3::Z,
            Vec3::Z,
            Vec3::new(0.293_918_3, 0.243_413_4, 0.128_071_3),
        ),
    ];
    let cases: Vec<Case> = fixed
        .iter()
        .map(|&(_, bsdf, wo, wi, _)| case(bsdf, Side::Front, wo, wi))
        .collect();
    let out = eval_cases(&ctx, &cases);
    for ((name, bsdf, wo, wi, expected), gpu) in fixed.iter().zip(&out) {
        let gpu = Vec3::new(gpu[0], gpu[1], gpu[2]);
        let rust = bsdf.eval(*wo, *wi);
        for (side, got) in [("WGSL", gpu), ("Rust", rust)] {
            let err = ((got - *expected) / *expected).abs().max_element();
            assert!(
                err < 1e-4,
                "{name}, {side}: {got} vs {expected} (relative {err:.2e})"
            );
        }
    }
}

#[test]
fn wgsl_brdfs_match_rust() {
    let Some(ctx) = common::gpu("wgsl_brdfs_match_rust") else {
        return;
    };
    let mut rng = TestRng::new(7);
    let mut cases = Vec::with_capacity(CASES);
    for i in 0..CASES {
        // Mostly both directions above the surface; some below.
        let mut wo = unit(&mut rng);
        let mut wi = unit(&mut rng);
        if rng.next_f32() < 0.85 {
            wo.z = wo.z.abs();
            wi.z = wi.z.abs();
        }
        let kd = colour(&mut rng, std::f32::consts::FRAC_1_PI);
        let ks = colour(&mut rng, 1.0);
        let shininess = match i % 5 {
            0 => 0.0,
            1 => (rng.next_f32() * 8.0).floor(),
            _ => rng.next_f32() * 200.0,
        };
        let bsdf = if i % 5 == 4 {
            Bsdf::Lambert(Lambert::from_kd(kd))
        } else {
            Bsdf::PhongBlinn(PhongBlinn::new(kd, ks, shininess, PhongVariant::ALL[i % 4]))
        };
        cases.push(case(bsdf, Side::Front, wo, wi));
    }
    let out = eval_cases(&ctx, &cases);
    compare("Lambert and Phong-Blinn", &cases, &out);
    let mut counts = [0usize; 5];
    for (c, o) in cases.iter().zip(&out) {
        if o[..3].iter().any(|&v| v > 0.0) {
            counts[if c.gpu.mat.model == MODEL_LAMBERT {
                4
            } else {
                c.gpu.mat.variant as usize
            }] += 1;
        }
    }
    eprintln!("non-zero per Phong variant/Lambert {counts:?}");
    // Every model was exercised with non-zero values.
    assert!(counts.iter().all(|&n| n > 1000), "{counts:?}");
}

/// A light the raster path evaluates: an abstract light or the far field of
/// an area light.
#[derive(Debug)]
enum TestLight {
    Abstract(Light),
    Area(FarField),
}

impl TestLight {
    fn gpu(&self) -> GpuLight {
        match self {
            TestLight::Abstract(l) => GpuLight::from_light(l),
            TestLight::Area(f) => GpuLight::from_far_field(f),
        }
    }

    fn sample_li(&self, p: Vec3) -> Option<penumbra_shading::light::LightSample> {
        match self {
            TestLight::Abstract(l) => l.sample_li(p),
            TestLight::Area(f) => f.sample_li(p),
        }
    }

    fn range(&self) -> f32 {
        match self {
            TestLight::Abstract(l) => l.range(),
            TestLight::Area(_) => f32::INFINITY,
        }
    }
}

/// GGX α for the rough models: half log-uniform over [MIN_ALPHA, 1], half
/// roughness² with roughness uniform (α = 0 included: clamped to MIN_ALPHA).
fn ggx_alpha(rng: &mut TestRng) -> f32 {
    if rng.next_f32() < 0.5 {
        MIN_ALPHA * (1.0 / MIN_ALPHA).powf(rng.next_f32())
    } else {
        let r = rng.next_f32();
        r * r
    }
}

/// ior 1.0–2.5, a few exactly 1.
fn ior(rng: &mut TestRng) -> f32 {
    if rng.next_f32() < 0.05 {
        1.0
    } else {
        1.0 + 1.5 * rng.next_f32()
    }
}

fn side(rng: &mut TestRng) -> Side {
    match (rng.next_f32() * 4.0) as u32 {
        0 | 1 => Side::Front,
        2 => Side::BackOnGpu,
        _ => Side::BackOnHost,
    }
}

#[test]
fn wgsl_rough_conductor_matches_rust() {
    let Some(ctx) = common::gpu("wgsl_rough_conductor_matches_rust") else {
        return;
    };
    let mut rng = TestRng::new(21);
    let mut cases = Vec::with_capacity(CASES);
    let mut schlick = 0;
    for i in 0..CASES {
        // Random indices (n 0.05–3, κ 0–5 per band) and the named metals.
        let (eta, k) = if i % 8 == 0 {
            let name = CONDUCTOR_PRESETS[(i / 8) % CONDUCTOR_PRESETS.len()];
            conductor_preset(name).unwrap()
        } else {
            (
                colour(&mut rng, 2.95) + Vec3::splat(0.05),
                colour(&mut rng, 5.0),
            )
        };
        let mut rc = RoughConductor::new(eta, k, ggx_alpha(&mut rng));
        if rng.next_f32() < 0.5 {
            rc.fresnel = FresnelModel::Schlick;
            schlick += 1;
        }
        let bsdf = Bsdf::RoughConductor(rc);
        let (wo, wi) = directions(&mut rng, &bsdf, i);
        cases.push(case(bsdf, Side::Front, wo, wi));
    }
    let out = eval_cases(&ctx, &cases);
    let s = compare("rough conductor", &cases, &out);
    assert!(
        s.reflected > 8000 && schlick > 8000,
        "{s:?}, Schlick {schlick}"
    );
    // The non-zero values include the narrow lobes' large peaks.
    let peaks = cases
        .iter()
        .filter(|c| {
            c.bsdf
                .eval(Vec3::from(c.gpu.wo), Vec3::from(c.gpu.wi))
                .max_element()
                > 100.0
        })
        .count();
    assert!(peaks > 1000, "{peaks}");
}

#[test]
fn wgsl_rough_dielectric_matches_rust() {
    let Some(ctx) = common::gpu("wgsl_rough_dielectric_matches_rust") else {
        return;
    };
    let mut rng = TestRng::new(33);
    let mut cases = Vec::with_capacity(CASES);
    let mut backs = 0;
    for i in 0..CASES {
        let rd = RoughDielectric {
            tint: colour(&mut rng, 1.0),
            ..RoughDielectric::new(ior(&mut rng), ggx_alpha(&mut rng))
        };
        let sd = side(&mut rng);
        backs += (sd != Side::Front) as usize;
        let bsdf = Bsdf::RoughDielectric(rd);
        let seen = sd.apply(bsdf);
        let (wo, wi) = directions(&mut rng, &seen, i);
        cases.push(case(bsdf, sd, wo, wi));
    }
    let out = eval_cases(&ctx, &cases);
    let s = compare("rough dielectric", &cases, &out);
    assert!(
        s.reflected > 4000 && s.transmitted > 4000 && backs > 8000,
        "{s:?}, back {backs}"
    );
}

/// A random glTF metallic–roughness material over the whole parameter range.
fn metallic_roughness(rng: &mut TestRng) -> MetallicRoughness {
    let u = rng.next_f32();
    let roughness = if u < 0.05 {
        // Delta lobes (α < DELTA_ALPHA): only the diffuse base is evaluated.
        DELTA_ALPHA.sqrt() * rng.next_f32()
    } else if u < 0.15 {
        // Just above DELTA_ALPHA.
        (DELTA_ALPHA * (1.0 + rng.next_f32())).sqrt()
    } else {
        DELTA_ALPHA.sqrt() + (1.0 - DELTA_ALPHA.sqrt()) * rng.next_f32()
    };
    let pick = |rng: &mut TestRng, p0: f32, p1: f32| {
        let u = rng.next_f32();
        if u < p0 {
            0.0
        } else if u < p0 + p1 {
            1.0
        } else {
            rng.next_f32()
        }
    };
    let mut m = MetallicRoughness::new(colour(rng, 1.0), pick(rng, 0.3, 0.15), roughness);
    m.ior = ior(rng);
    m.transmission = pick(rng, 0.3, 0.2);
    m.specular = if rng.next_f32() < 0.3 {
        1.0
    } else {
        rng.next_f32()
    };
    m.specular_color = match (rng.next_f32() * 3.0) as u32 {
        0 => Vec3::ONE,
        // Up to 8: f0 reaches its clamp at 1.
        1 => colour(rng, 8.0),
        _ => colour(rng, 1.0),
    };
    m
}

#[test]
fn wgsl_metallic_roughness_matches_rust() {
    let Some(ctx) = common::gpu("wgsl_metallic_roughness_matches_rust") else {
        return;
    };
    let mut rng = TestRng::new(45);
    let mut cases = Vec::with_capacity(CASES);
    let (mut backs, mut transmissive_backs) = (0, 0);
    for i in 0..CASES {
        let mr = metallic_roughness(&mut rng);
        let sd = side(&mut rng);
        let bsdf = Bsdf::MetallicRoughness(mr);
        if sd != Side::Front {
            backs += 1;
            transmissive_backs += bsdf.flags().transmission as usize;
        }
        let seen = sd.apply(bsdf);
        let (wo, wi) = directions(&mut rng, &seen, i);
        cases.push(case(bsdf, sd, wo, wi));
    }
    let out = eval_cases(&ctx, &cases);
    let s = compare("metallic-roughness", &cases, &out);
    assert!(
        s.reflected > 8000 && s.transmitted > 1000 && transmissive_backs > 2000,
        "{s:?}, back {backs}, transmissive back {transmissive_backs}"
    );
    // Among the reflected: diffuse-only (delta) and glossy-only (metal) ones.
    let delta_diffuse = cases
        .iter()
        .zip(&out)
        .filter(|(c, o)| {
            matches!(c.bsdf, Bsdf::MetallicRoughness(m) if m.is_delta()) && o[0] + o[1] + o[2] > 0.0
        })
        .count();
    assert!(delta_diffuse > 200, "{delta_diffuse}");
}

/// The environment light's view of a metallic–roughness material, which
/// the forward pass rebuilds per fragment once textures have changed the
/// material: WGSL `metallic_roughness_environment` against the host's
/// `env_material`.
#[test]
fn wgsl_metallic_roughness_environment_matches_rust() {
    let Some(ctx) = common::gpu("wgsl_metallic_roughness_environment_matches_rust") else {
        return;
    };
    let mut rng = TestRng::new(46);
    let materials: Vec<MetallicRoughness> =
        (0..2000).map(|_| metallic_roughness(&mut rng)).collect();
    let gpu_in: Vec<GpuMaterial> = materials
        .iter()
        .map(|m| GpuMaterial::from_bsdf(&Bsdf::MetallicRoughness(*m), Vec3::ZERO, true))
        .collect();
    let out: Vec<GpuEnvMaterial> = dispatch(
        &ctx,
        false,
        "eval_mr_environment",
        bytemuck::cast_slice(&gpu_in),
        gpu_in.len(),
        4,
    );
    let flat =
        |e: &GpuEnvMaterial| -> Vec<f32> { bytemuck::cast_slice(std::slice::from_ref(e)).to_vec() };
    for (m, g) in materials.iter().zip(&out) {
        let host = env_material(&Bsdf::MetallicRoughness(*m));
        for (k, (a, b)) in flat(&host).iter().zip(flat(g)).enumerate() {
            // Words 3 (kind), 15 (fresnel) and 19 (diffuse_kc) are
            // integers: compared as bits.
            if [3, 15, 19].contains(&k) {
                assert_eq!(a.to_bits(), b.to_bits(), "{m:?}: word {k}");
            } else {
                assert!(close(b, *a), "{m:?}: word {k}: GPU {b} vs host {a}");
            }
        }
    }
}

#[test]
fn wgsl_delta_models_are_zero() {
    let Some(ctx) = common::gpu("wgsl_delta_models_are_zero") else {
        return;
    };
    let mut rng = TestRng::new(57);
    let mut cases = Vec::with_capacity(CASES);
    for i in 0..CASES {
        let fresnel = if i % 2 == 0 {
            FresnelModel::Exact
        } else {
            FresnelModel::Schlick
        };
        let bsdf = match i % 5 {
            0 => Bsdf::Mirror(Mirror::new(colour(&mut rng, 1.0))),
            1 => Bsdf::Conductor(Conductor::new(
                colour(&mut rng, 3.0),
                colour(&mut rng, 5.0),
                fresnel,
            )),
            2 => Bsdf::Dielectric(Dielectric::new(
                ior(&mut rng),
                colour(&mut rng, 1.0),
                fresnel,
            )),
            // Metallic–roughness with delta lobes and no diffuse base
            // (metal, or fully transmissive).
            k => {
                let mut m = metallic_roughness(&mut rng);
                m.roughness = DELTA_ALPHA.sqrt() * 0.999 * rng.next_f32();
                if k == 3 {
                    m.metallic = 1.0;
                } else {
                    m.transmission = 1.0;
                }
                Bsdf::MetallicRoughness(m)
            }
        };
        let sd = side(&mut rng);
        let seen = sd.apply(bsdf);
        // Anywhere, and exactly along the delta lobes.
        let mut wo = unit(&mut rng);
        let mut wi = unit(&mut rng);
        if i % 3 != 0 {
            wo.z = wo.z.abs();
            let lobes = seen.specular(wo);
            if let Some((d, _)) = lobes.iter().nth(i % 2) {
                wi = d;
            } else if let Some((d, _)) = lobes.iter().next() {
                wi = d;
            }
        }
        cases.push(case(bsdf, sd, wo, wi));
    }
    let out = eval_cases(&ctx, &cases);
    for (i, (c, o)) in cases.iter().zip(&out).enumerate() {
        let cpu = c.bsdf.eval(Vec3::from(c.gpu.wo), Vec3::from(c.gpu.wi));
        assert_eq!(cpu, Vec3::ZERO, "case {i}: {:?}", c.bsdf);
        assert!(
            o[..3].iter().all(|v| v.to_bits() == 0),
            "case {i} ({:?}, wo {:?}, wi {:?}): GPU {o:?}, not exactly 0",
            c.bsdf,
            c.gpu.wo,
            c.gpu.wi
        );
    }
    let along_lobes = cases
        .iter()
        .filter(|c| !c.bsdf.specular(Vec3::from(c.gpu.wo)).is_empty())
        .count();
    eprintln!(
        "delta models: {} cases, {along_lobes} with delta lobes at wo",
        cases.len()
    );
    assert!(along_lobes > 10_000, "{along_lobes}");
}

#[test]
fn wgsl_lights_match_rust() {
    let Some(ctx) = common::gpu("wgsl_lights_match_rust") else {
        return;
    };
    let mut rng = TestRng::new(11);
    let mut cases = Vec::with_capacity(CASES);
    let mut lights = Vec::with_capacity(CASES);
    let pos = |rng: &mut TestRng| colour(rng, 10.0) - Vec3::splat(5.0);
    // Half the point and spot lights are cut off at a range of 2 to 14.
    let range = |rng: &mut TestRng| {
        if rng.next_f32() < 0.5 {
            f32::INFINITY
        } else {
            2.0 + 12.0 * rng.next_f32()
        }
    };
    for i in 0..CASES {
        let p = pos(&mut rng);
        let light = match i % 4 {
            0 => TestLight::Abstract(Light::Point(PointLight {
                position: pos(&mut rng),
                intensity: colour(&mut rng, 100.0),
                range: range(&mut rng),
            })),
            1 => TestLight::Abstract(Light::Directional(DirectionalLight {
                // Not necessarily unit: the light normalises it.
                direction: unit(&mut rng) * (0.5 + rng.next_f32()),
                irradiance: colour(&mut rng, 10.0),
            })),
            3 => {
                // An area light's far field: sphere, disk or quad, one- or
                // two-sided.
                let centre = pos(&mut rng);
                let n = unit(&mut rng);
                let shape = match rng.next_u64() % 3 {
                    0 => Shape::Sphere {
                        center: centre,
                        radius: 0.1 + rng.next_f32(),
                    },
                    1 => Shape::Disk {
                        center: centre,
                        normal: n,
                        radius: 0.1 + rng.next_f32(),
                    },
                    _ => {
                        let e1 = unit(&mut rng).cross(n) * (0.2 + rng.next_f32());
                        Shape::Quad {
                            corner: centre,
                            edge1: e1,
                            edge2: n.cross(e1).normalize() * (0.2 + rng.next_f32()),
                        }
                    }
                };
                TestLight::Area(
                    AreaLight {
                        shape,
                        radiance: colour(&mut rng, 20.0),
                        two_sided: rng.next_f32() < 0.5,
                    }
                    .far_field(),
                )
            }
            _ => {
                let position = pos(&mut rng);
                // Half the spots point roughly at p, so that the cone and
                // its falloff band are well covered.
                let direction = if rng.next_f32() < 0.5 {
                    ((p - position).normalize() + unit(&mut rng) * 0.4).normalize()
                } else {
                    unit(&mut rng)
                };
                let cos_outer = rng.next_f32() * 0.99;
                let cos_inner = cos_outer + (1.0 - cos_outer) * rng.next_f32();
                TestLight::Abstract(Light::Spot(SpotLight {
                    position,
                    direction,
                    intensity: colour(&mut rng, 100.0),
                    cos_inner,
                    cos_outer,
                    range: range(&mut rng),
                }))
            }
        };
        cases.push(LightCase {
            light: light.gpu(),
            p: p.to_array(),
            _pad0: 0.0,
        });
        lights.push(light);
    }
    let out: Vec<LightIncidence> = dispatch(
        &ctx,
        false,
        "eval_light",
        bytemuck::cast_slice(&cases),
        CASES,
        2,
    );
    let mut lit = [0usize; 4];
    let mut falloff_band = 0;
    let mut window_band = 0;
    for (i, (c, light)) in cases.iter().zip(&lights).enumerate() {
        let g = out[i];
        let cpu = light.sample_li(Vec3::from(c.p));
        // A light that does not reach p contributes zero: compare values
        // with None as zero, directions and distances where both reach.
        let cpu_value = cpu.map_or(Vec3::ZERO, |s| s.value);
        let gpu_value = if g.valid != 0 {
            Vec3::from(g.value)
        } else {
            Vec3::ZERO
        };
        for k in 0..3 {
            assert!(
                close(gpu_value[k], cpu_value[k]),
                "case {i} ({light:?} at {:?}): GPU value {gpu_value:?} vs Rust {cpu_value:?}",
                c.p
            );
        }
        if let (Some(s), true) = (cpu, g.valid != 0) {
            for k in 0..3 {
                assert!(
                    close(g.wi[k], s.wi[k]),
                    "case {i}: GPU wi {:?} vs Rust {:?}",
                    g.wi,
                    s.wi
                );
            }
            assert!(
                (g.distance.is_infinite() && s.distance.is_infinite())
                    || close(g.distance, s.distance),
                "case {i}: GPU distance {} vs Rust {}",
                g.distance,
                s.distance
            );
            lit[i % 4] += 1;
            let w = penumbra_shading::light::range_window(s.distance, light.range());
            if w > 0.0 && w < 1.0 {
                window_band += 1;
            }
            if let TestLight::Abstract(Light::Spot(sp)) = light {
                let f = sp.falloff(-s.wi);
                if f > 0.0 && f < 1.0 {
                    falloff_band += 1;
                }
            }
        }
    }
    eprintln!(
        "light cases: {CASES}, reaching p per kind {lit:?}, spot falloff band {falloff_band}, range window band {window_band}"
    );
    assert!(
        lit[0] > 3000 && lit[1] > 4500 && lit[2] > 500 && lit[3] > 2500,
        "{lit:?}"
    );
    assert!(window_band > 1500, "{window_band}");
    assert!(falloff_band > 300, "{falloff_band}");
}
