//! GGX microfacet models: normalisation of D and of the visible-normal
//! density, white furnace, reciprocity, chi-square goodness of fit of every
//! sampler against its pdf, and the glTF metallic–roughness limits.

use glam::Vec3;
use penumbra_shading::bsdf::optics::{f0_from_ior, fresnel_dielectric, reflect, schlick};
use penumbra_shading::bsdf::{
    BsdfSample, FresnelModel, Ggx, MetallicRoughness, RoughConductor, RoughDielectric,
};
use penumbra_shading::stats::{ChiSquare, SphereBins, TestRng, chi_square_sphere};
use penumbra_shading::{Frame, Rgb};
use std::cell::Cell;
use std::f64::consts::PI;

/// Overall significance of the chi-square family.
const ALPHA_SIG: f64 = 0.01;
/// Chi-square tests in the family (Šidák): 3 visible-normal + 12 conductor
/// + 18 dielectric + 8 metallic–roughness.
const FAMILY: usize = 3 + 12 + 18 + 8;
/// Non-delta samples per chi-square test.
const CHI2_SAMPLES: usize = 100_000;

fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

/// The same direction seen from the other side of the surface (frame flipped).
fn flip(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

/// Chi-square of `sample` (non-delta directions only; delta and failed
/// attempts are retried and counted) against `pdf`. The sphere bins are
/// rotated so that their pole lies in a direction no lobe points to: the
/// peaked lobes of small α then fall where the bins are well resolved.
fn chi2(
    name: &str,
    seed: u64,
    mut sample: impl FnMut(&mut TestRng) -> Option<BsdfSample>,
    pdf: impl Fn(Vec3) -> f32,
) -> ChiSquare {
    let bins_frame = Frame::from_normal(Vec3::new(0.1, 1.0, 0.05).normalize());
    let mut rng = TestRng::new(seed);
    let attempts = Cell::new(0usize);
    let res = chi_square_sphere(
        CHI2_SAMPLES,
        SphereBins {
            cos_theta: 40,
            phi: 80,
            resolution: 24,
        },
        || {
            // A sampler that (almost) never yields a non-delta direction
            // fails here, not after hours of retries.
            assert!(
                attempts.get() < 100 * CHI2_SAMPLES,
                "{name}: under 1 % of the samples are non-delta"
            );
            for _ in 0..10_000 {
                attempts.set(attempts.get() + 1);
                if let Some(s) = sample(&mut rng)
                    && !s.delta
                {
                    return Some(bins_frame.to_local(s.wi));
                }
            }
            None
        },
        |d| pdf(bins_frame.to_world(d)),
    );
    let fraction = CHI2_SAMPLES as f64 / attempts.get() as f64;
    println!(
        "{name}: chi2 {:.1} dof {} p {:.4}, ∫pdf {:.4}, non-delta fraction {:.4}",
        res.statistic, res.dof, res.p_value, res.pdf_integral, fraction
    );
    assert!(res.defect.is_none(), "{name}: {:?}", res.defect);
    // The pdf integrates to the probability of producing a non-delta direction.
    assert!(
        (res.pdf_integral - fraction).abs() < 0.01,
        "{name}: ∫pdf {} vs sampled fraction {}",
        res.pdf_integral,
        fraction
    );
    assert!(res.passes(ALPHA_SIG, FAMILY), "{name}: {res:?}");
    res
}

/// Checks `weight == eval·|cos θi|/pdf` for a non-delta sample.
fn check_weight(name: &str, s: &BsdfSample, f: Rgb, pdf: f32) {
    if s.delta {
        return;
    }
    assert!(
        (pdf - s.pdf).abs() <= 1e-3 * pdf.max(s.pdf),
        "{name}: sample pdf {} vs pdf() {pdf}",
        s.pdf
    );
    let expect = f * s.wi.z.abs() / pdf;
    let err = (expect - s.weight).abs().max_element();
    assert!(
        err <= 1e-3 * expect.max_element().max(1e-3),
        "{name}: weight {} vs f|cos|/pdf {expect} at wi {}",
        s.weight,
        s.wi
    );
}

#[test]
fn ggx_d_projected_area_is_one() {
    for alpha in [0.01f32, 0.05, 0.3, 0.7, 1.0] {
        let ggx = Ggx::new(alpha);
        // ∫ D cos θ dω = 2π ∫ D(θ) cos θ sin θ dθ, midpoint rule.
        let n = 400_000;
        let h = PI / 2.0 / n as f64;
        let mut sum = 0.0;
        for i in 0..n {
            let t = (i as f64 + 0.5) * h;
            let m = Vec3::new(t.sin() as f32, 0.0, t.cos() as f32);
            sum += ggx.d(m) as f64 * t.cos() * t.sin();
        }
        let integral = 2.0 * PI * sum * h;
        assert!((integral - 1.0).abs() < 2e-3, "α {alpha}: {integral}");
    }
}

#[test]
fn visible_normal_density_is_normalised() {
    for alpha in [0.05f32, 0.3, 1.0] {
        let ggx = Ggx::new(alpha);
        for theta_o in [0.0f32, 45.0, 80.0, 89.0] {
            let wo = dir(theta_o, 30.0);
            // ∫ D_wo(m) dω_m over the hemisphere, midpoint in (θ, φ).
            let (nt, np) = (3000, 600);
            let (ht, hp) = (PI / 2.0 / nt as f64, 2.0 * PI / np as f64);
            let mut sum = 0.0;
            for i in 0..nt {
                let t = (i as f64 + 0.5) * ht;
                let mut ring = 0.0;
                for j in 0..np {
                    let p = (j as f64 + 0.5) * hp;
                    let m = Vec3::new(
                        (t.sin() * p.cos()) as f32,
                        (t.sin() * p.sin()) as f32,
                        t.cos() as f32,
                    );
                    ring += ggx.pdf_visible(wo, m) as f64;
                }
                sum += ring * t.sin();
            }
            let integral = sum * ht * hp;
            assert!(
                (integral - 1.0).abs() < 3e-3,
                "α {alpha}, θo {theta_o}: ∫D_wo = {integral}"
            );
        }
    }
}

#[test]
fn chi_square_visible_normals() {
    for (k, alpha) in [0.05f32, 0.3, 1.0].into_iter().enumerate() {
        let ggx = Ggx::new(alpha);
        let wo = dir(70.0, 0.0);
        chi2(
            &format!("VNDF α {alpha}"),
            100 + k as u64,
            |rng| {
                Some(BsdfSample {
                    wi: ggx.sample_visible(wo, rng.next_2d()),
                    weight: Rgb::ONE,
                    pdf: 1.0,
                    delta: false,
                    eta: 1.0,
                })
            },
            |m| ggx.pdf_visible(wo, m),
        );
    }
}

/// Directional albedo ∫ f |cos θi| dωi of a model, estimated from its own
/// samples as the mean of eval·|cos|/pdf, split by the side of ωi.
/// Returns (reflected, transmitted, standard error of their sum).
fn albedo(
    seed: u64,
    n: usize,
    sample: impl Fn(f32, [f32; 2]) -> Option<BsdfSample>,
    eval: impl Fn(Vec3) -> Rgb,
    pdf: impl Fn(Vec3) -> f32,
    t_scale: f32,
) -> (Rgb, Rgb, f32) {
    let mut rng = TestRng::new(seed);
    let (mut r, mut t) = (Rgb::ZERO, Rgb::ZERO);
    let mut sq = 0.0f64;
    for _ in 0..n {
        let u_lobe = rng.next_f32();
        let Some(s) = sample(u_lobe, rng.next_2d()) else {
            continue;
        };
        let w = if s.delta {
            s.weight
        } else {
            eval(s.wi) * s.wi.z.abs() / pdf(s.wi)
        };
        let w = if s.wi.z < 0.0 { w * t_scale } else { w };
        if s.wi.z > 0.0 {
            r += w;
        } else {
            t += w;
        }
        sq += (w.max_element() as f64).powi(2);
    }
    let (r, t) = (r / n as f32, t / n as f32);
    let mean = (r + t).max_element() as f64;
    let se = ((sq / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
    (r, t, se as f32)
}

#[test]
fn rough_conductor_white_furnace() {
    // Schlick with F0 = 1 (κ → ∞): F ≡ 1.
    let white = |alpha| RoughConductor {
        eta: Rgb::ONE,
        k: Rgb::splat(1e4),
        alpha,
        fresnel: FresnelModel::Schlick,
    };
    assert!((white(0.1).fresnel_at(0.3) - Rgb::ONE).abs().max_element() < 1e-6);
    let thetas = [0.0f32, 30.0, 60.0, 80.0, 89.0];
    let mut table = Vec::new();
    for alpha in [0.05f32, 0.3, 0.6, 1.0] {
        let m = white(alpha);
        let mut row = Vec::new();
        for (k, &theta) in thetas.iter().enumerate() {
            let wo = dir(theta, 0.0);
            let (r, t, se) = albedo(
                k as u64,
                100_000,
                |ul, u| m.sample(wo, ul, u),
                |wi| m.eval(wo, wi),
                |wi| m.pdf(wo, wi),
                1.0,
            );
            assert_eq!(t, Rgb::ZERO);
            assert!(r.x <= 1.0 + 4.0 * se + 1e-4, "α {alpha} θ {theta}: {r}");
            row.push(r.x);
        }
        println!("conductor F≡1 α {alpha}: albedo at θo {thetas:?} = {row:.4?}");
        table.push(row);
    }
    // Near 1 at low α and normal incidence.
    assert!(table[0][0] > 0.995, "{}", table[0][0]);
    // More roughness, more masking: up to 60°, albedo decreases with α.
    for j in 0..3 {
        for i in 1..table.len() {
            assert!(table[i][j] < table[i - 1][j] + 2e-3, "θ {}", thetas[j]);
        }
    }
    // At α = 1 and normal incidence the visible normals are cosine
    // distributed (D cos θm = cos θm / π), and those beyond 45° reflect below
    // the horizon: E < ∫_{θm<45°} cos θm/π dω = 1/2, less the G2 shadowing.
    let loss_normal = 1.0 - table[3][0];
    let loss_grazing = 1.0 - table[3][3];
    println!("α = 1 single-scattering loss: {loss_normal:.3} at θo 0°, {loss_grazing:.3} at 80°");
    assert!(table[3][0] < 0.5 && table[3][0] > 0.25, "{}", table[3][0]);
}

#[test]
fn rough_dielectric_energy() {
    for eta in [1.5f32, 1.0 / 1.5] {
        for alpha in [0.05f32, 0.3, 1.0] {
            let m = RoughDielectric::new(eta, alpha);
            let mut row = Vec::new();
            for (k, theta) in [0.0f32, 45.0, 80.0].into_iter().enumerate() {
                let wo = dir(theta, 10.0);
                // Transmitted radiance carries 1/η²: η² T is the energy fraction.
                let (r, t, se) = albedo(
                    k as u64 + 7,
                    100_000,
                    |ul, u| m.sample(wo, ul, u),
                    |wi| m.eval(wo, wi),
                    |wi| m.pdf(wo, wi),
                    eta * eta,
                );
                let sum = r.x + t.x;
                assert!(sum <= 1.0 + 4.0 * se + 1e-4, "η {eta} α {alpha} θ {theta}");
                if alpha == 0.05 && theta == 0.0 {
                    // Nearly smooth: R + T ≈ F + (1 − F) = 1, R ≈ F(0°).
                    assert!(sum > 0.99, "η {eta}: {sum}");
                    assert!((r.x - fresnel_dielectric(1.0, eta)).abs() < 0.005, "{r}");
                }
                row.push((r.x, t.x));
            }
            println!("dielectric η {eta:.3} α {alpha}: (R, η²T) at 0/45/80° = {row:.4?}");
        }
    }
    // Total internal reflection: from inside glass at 80° (beyond 41.8°),
    // a nearly smooth surface transmits only through its rare steep facets.
    let m = RoughDielectric::new(1.0 / 1.5, 0.05);
    let wo = dir(80.0, 0.0);
    let (r, t, _) = albedo(
        3,
        50_000,
        |ul, u| m.sample(wo, ul, u),
        |wi| m.eval(wo, wi),
        |wi| m.pdf(wo, wi),
        1.0,
    );
    assert!(t.x < 0.01 && r.x > 0.9, "R {r} T {t}");
}

#[test]
fn reciprocity() {
    let mut rng = TestRng::new(42);
    let conductor = RoughConductor::new(Rgb::new(0.2, 0.9, 1.1), Rgb::new(3.9, 2.4, 1.8), 0.3);
    let glass = RoughDielectric {
        eta: 1.5,
        alpha: 0.4,
        tint: Rgb::new(1.0, 0.8, 0.6),
    };
    let inside = glass.inverted();
    assert_eq!(inside.eta, 1.0 / 1.5);
    let close = |a: Rgb, b: Rgb| (a - b).abs().max_element() <= 2e-4 * a.max_element().max(1e-3);
    let mut transmitted = 0;
    let mut f_max = 0.0f32;
    for _ in 0..20_000 {
        let u = rng.next_2d();
        let v = rng.next_2d();
        let wo = dir(u[0] * 89.0, u[1] * 360.0);
        let wi = dir(v[0] * 89.0, v[1] * 360.0);
        let (a, b) = (conductor.eval(wo, wi), conductor.eval(wi, wo));
        assert!(close(a, b), "conductor {a} vs {b}");
        let (a, b) = (glass.eval(wo, wi), glass.eval(wi, wo));
        assert!(close(a, b), "dielectric reflection {a} vs {b}");
        // Transmission, ωo outside (n = 1), ωi inside (n = η):
        // f(ωo, ωi) / n_o² = f(ωi, ωo) / n_i², f(ωi, ωo) evaluated from inside.
        let wt = flip(wi);
        let f_out = glass.eval(wo, wt);
        let f_in = inside.eval(wi, flip(wo)) / (1.5 * 1.5);
        // At grazing microfacet incidence (ωo·m → 0) f vanishes and f32 loses
        // its relative precision in ωo·m and 1 − F: pairs with |ωo·m| or
        // |ωi·m| below 0.05 are skipped.
        let h = (wo.as_dvec3() + 1.5 * wt.as_dvec3()).normalize();
        if h.dot(wo.as_dvec3()).abs() < 0.05 || h.dot(wt.as_dvec3()).abs() < 0.05 {
            continue;
        }
        let err = (f_out - f_in).abs().max_element();
        assert!(
            err <= 2e-4 * f_out.max_element() + 1e-9,
            "transmission {f_out} vs {f_in} at wo {wo} wi {wt}"
        );
        f_max = f_max.max(f_out.max_element());
        if f_out.max_element() > 0.0 {
            transmitted += 1;
        }
    }
    assert!(transmitted > 3_000, "{transmitted}");
    println!("largest transmission f: {f_max}");
    assert!(f_max > 0.1, "{f_max}");
}

#[test]
fn chi_square_rough_conductor() {
    let mut seed = 1000;
    for alpha in [0.05f32, 0.3, 1.0] {
        for theta in [0.0f32, 40.0, 75.0, 88.0] {
            let m = RoughConductor {
                fresnel: FresnelModel::Schlick,
                ..RoughConductor::new(Rgb::new(0.2, 0.9, 1.1), Rgb::new(3.9, 2.4, 1.8), alpha)
            };
            let wo = dir(theta, 20.0);
            let name = format!("conductor α {alpha} θo {theta}");
            seed += 1;
            chi2(
                &name,
                seed,
                |rng| {
                    let s = m.sample(wo, rng.next_f32(), rng.next_2d())?;
                    check_weight(&name, &s, m.eval(wo, s.wi), m.pdf(wo, s.wi));
                    Some(s)
                },
                |wi| m.pdf(wo, wi),
            );
        }
    }
}

#[test]
fn chi_square_rough_dielectric() {
    let mut seed = 2000;
    for eta in [1.5f32, 1.0 / 1.5] {
        for alpha in [0.05f32, 0.3, 1.0] {
            for theta in [0.0f32, 50.0, 85.0] {
                let m = RoughDielectric {
                    eta,
                    alpha,
                    tint: Rgb::new(0.9, 0.7, 0.5),
                };
                let wo = dir(theta, -30.0);
                let name = format!("dielectric η {eta:.3} α {alpha} θo {theta}");
                seed += 1;
                chi2(
                    &name,
                    seed,
                    |rng| {
                        let s = m.sample(wo, rng.next_f32(), rng.next_2d())?;
                        check_weight(&name, &s, m.eval(wo, s.wi), m.pdf(wo, s.wi));
                        Some(s)
                    },
                    |wi| m.pdf(wo, wi),
                );
            }
        }
    }
}

/// Parameter sets of the metallic–roughness tests.
fn mr_sets() -> Vec<(&'static str, MetallicRoughness)> {
    let base = Rgb::new(0.8, 0.5, 0.2);
    vec![
        ("plastic r0.5", MetallicRoughness::new(base, 0.0, 0.5)),
        ("half-metal r0.3", MetallicRoughness::new(base, 0.5, 0.3)),
        ("metal r1", MetallicRoughness::new(base, 1.0, 1.0)),
        (
            "specular-tinted r0.25",
            MetallicRoughness {
                specular: 0.6,
                specular_color: Rgb::new(1.0, 0.5, 2.0),
                ior: 1.8,
                ..MetallicRoughness::new(base, 0.2, 0.25)
            },
        ),
        (
            "transmission r0.3",
            MetallicRoughness {
                transmission: 1.0,
                ..MetallicRoughness::new(Rgb::new(0.9, 0.95, 1.0), 0.0, 0.3)
            },
        ),
        (
            "half-transmission r0.6 inside",
            MetallicRoughness {
                transmission: 0.5,
                ..MetallicRoughness::new(base, 0.1, 0.6)
            }
            .inverted(),
        ),
        (
            "smooth plastic (delta)",
            MetallicRoughness::new(base, 0.0, 0.0),
        ),
        (
            "smooth transmission r0.01 (delta)",
            MetallicRoughness {
                transmission: 0.7,
                ..MetallicRoughness::new(base, 0.0, 0.01)
            },
        ),
    ]
}

#[test]
fn chi_square_metallic_roughness() {
    let sets = mr_sets();
    let mut seed = 3000;
    for (name, m) in &sets {
        // Delta sets still have a diffuse base to test.
        let theta = if seed % 2 == 0 { 30.0 } else { 80.0 };
        let wo = dir(theta, 45.0);
        let name = format!("MR {name} θo {theta}");
        seed += 1;
        chi2(
            &name,
            seed,
            |rng| {
                let s = m.sample(wo, rng.next_f32(), rng.next_2d())?;
                check_weight(&name, &s, m.eval(wo, s.wi), m.pdf(wo, s.wi));
                Some(s)
            },
            |wi| m.pdf(wo, wi),
        );
    }
    assert_eq!(sets.len(), 8);
}

#[test]
fn metallic_roughness_energy() {
    let white = Rgb::ONE;
    let mut sets = mr_sets();
    for roughness in [0.0f32, 0.05, 0.3, 0.7, 1.0] {
        for metallic in [0.0f32, 1.0] {
            sets.push(("white", MetallicRoughness::new(white, metallic, roughness)));
        }
        let glass = MetallicRoughness {
            transmission: 1.0,
            ..MetallicRoughness::new(white, 0.0, roughness)
        };
        sets.push(("white glass", glass));
        sets.push(("white glass inside", glass.inverted()));
        sets.push((
            "white half-glass inside",
            MetallicRoughness {
                transmission: 0.5,
                ..glass
            }
            .inverted(),
        ));
    }
    for (k, (name, m)) in sets.iter().enumerate() {
        for theta in [0.0f32, 45.0, 75.0, 89.0] {
            let wo = dir(theta, 0.0);
            // Energy: transmitted radiance × η² (η = ior relative to ωo's side).
            let (r, t, se) = albedo(
                k as u64 * 10 + theta as u64,
                40_000,
                |ul, u| m.sample(wo, ul, u),
                |wi| m.eval(wo, wi),
                |wi| m.pdf(wo, wi),
                m.ior * m.ior,
            );
            let e = (r + t).max_element();
            assert!(
                e <= 1.0 + 4.0 * se + 2e-3,
                "{name} {m:?} θ {theta}: R {r} T {t} ± {se}"
            );
        }
    }
    // The base catches what the specular layer does not reflect: a white,
    // nearly smooth plastic reflects everything.
    for theta in [0.0f32, 45.0, 75.0] {
        let m = MetallicRoughness::new(white, 0.0, 0.1);
        let wo = dir(theta, 0.0);
        let (r, _, se) = albedo(
            5,
            100_000,
            |ul, u| m.sample(wo, ul, u),
            |wi| m.eval(wo, wi),
            |wi| m.pdf(wo, wi),
            1.0,
        );
        println!("white plastic r 0.1 θ {theta}: albedo {r} ± {se}");
        assert!((r.x - 1.0).abs() < 0.01 + 4.0 * se, "θ {theta}: {r}");
    }
}

#[test]
fn metallic_roughness_smooth_metal_is_schlick_mirror() {
    let base = Rgb::new(0.95, 0.64, 0.54);
    // Roughness 0: one delta lobe, the mirror direction with Schlick(base).
    let m = MetallicRoughness::new(base, 1.0, 0.0);
    assert!(m.is_delta() && m.flags().delta && !m.flags().non_delta);
    let mut rng = TestRng::new(9);
    for theta in [0.0f32, 40.0, 80.0] {
        let wo = dir(theta, 60.0);
        let set = m.specular(wo);
        assert_eq!(set.len(), 1);
        let (wi, thr) = set.iter().next().unwrap();
        assert!((wi - reflect(wo, Vec3::Z)).length() < 1e-6);
        assert!((thr - schlick(base, wo.z)).abs().max_element() < 1e-6);
        let s = m.sample(wo, rng.next_f32(), rng.next_2d()).unwrap();
        assert!(s.delta && (s.weight - thr).abs().max_element() < 1e-6);
        assert_eq!(m.eval(wo, wi), Rgb::ZERO);
    }
    // Small roughness: the albedo approaches Schlick(base) and the lobe
    // concentrates around the mirror direction.
    for theta in [0.0f32, 45.0, 70.0] {
        let wo = dir(theta, 0.0);
        let target = schlick(base, wo.z);
        let mut prev_err = f32::INFINITY;
        for roughness in [0.3f32, 0.15, 0.05] {
            let m = MetallicRoughness::new(base, 1.0, roughness);
            let (r, _, _) = albedo(
                11,
                50_000,
                |ul, u| m.sample(wo, ul, u),
                |wi| m.eval(wo, wi),
                |wi| m.pdf(wo, wi),
                1.0,
            );
            let err = (r - target).abs().max_element();
            println!("metal r {roughness} θ {theta}: albedo {r} vs Schlick {target}");
            assert!(err < prev_err + 1e-3, "r {roughness} θ {theta}");
            prev_err = err;
        }
        assert!(prev_err < 0.01, "θ {theta}: {prev_err}");
        let m = MetallicRoughness::new(base, 1.0, 0.05);
        let mirror = reflect(wo, Vec3::Z);
        let mut near = 0;
        for _ in 0..10_000 {
            let s = m.sample(wo, rng.next_f32(), rng.next_2d()).unwrap();
            if s.wi.dot(mirror) > 3f32.to_radians().cos() {
                near += 1;
            }
        }
        assert!(near > 9_000, "θ {theta}: {near}");
    }
}

#[test]
fn metallic_roughness_limits() {
    let base = Rgb::new(0.7, 0.4, 0.1);
    let mut rng = TestRng::new(5);
    // No specular layer: pure Lambert.
    let lambert = MetallicRoughness {
        specular: 0.0,
        ..MetallicRoughness::new(base, 0.0, 0.5)
    };
    for _ in 0..100 {
        let (u, v) = (rng.next_2d(), rng.next_2d());
        let (wo, wi) = (
            dir(u[0] * 89.0, u[1] * 360.0),
            dir(v[0] * 89.0, v[1] * 360.0),
        );
        let f = lambert.eval(wo, wi);
        assert!((f - base / std::f32::consts::PI).abs().max_element() < 1e-6);
    }
    // Reciprocal diffuse + specular reflection.
    let m = MetallicRoughness::new(base, 0.3, 0.4);
    for _ in 0..1000 {
        let (u, v) = (rng.next_2d(), rng.next_2d());
        let (wo, wi) = (
            dir(u[0] * 89.0, u[1] * 360.0),
            dir(v[0] * 89.0, v[1] * 360.0),
        );
        let (a, b) = (m.eval(wo, wi), m.eval(wi, wo));
        assert!(
            (a - b).abs().max_element() <= 1e-4 * a.max_element(),
            "{a} {b}"
        );
    }
    // Dielectric F0 from KHR_materials_ior/_specular at normal incidence of
    // a smooth surface: min(((ior−1)/(ior+1))² · specular_color, 1) · specular.
    let s = MetallicRoughness {
        ior: 2.0,
        specular: 0.5,
        specular_color: Rgb::new(1.0, 2.0, 20.0),
        ..MetallicRoughness::new(base, 0.0, 0.0)
    };
    let f0 = (f0_from_ior(Rgb::splat(2.0), Rgb::ZERO) * s.specular_color).min(Rgb::ONE) * 0.5;
    let (_, thr) = s.specular(Vec3::Z).iter().next().unwrap();
    assert!((thr - f0).abs().max_element() < 1e-6, "{thr} vs {f0}");
    // Smooth transmission: Snell refraction carrying (1 − F) base / η².
    let g = MetallicRoughness {
        transmission: 1.0,
        ..MetallicRoughness::new(base, 0.0, 0.0)
    };
    let wo = dir(30.0, 0.0);
    let set = g.specular(wo);
    assert_eq!(set.len(), 2);
    let (wt, tt) = set.iter().nth(1).unwrap();
    assert!((wo.x - 1.5 * -wt.x).abs() < 1e-5 && wt.z < 0.0, "Snell");
    let f = 0.04 + 0.96 * (1.0 - wo.z).powi(5);
    assert!((tt - base * (1.0 - f) / 2.25).abs().max_element() < 1e-5);
    // Tinting multiplies the base colour.
    assert_eq!(g.tinted(Rgb::splat(0.5)).base_color, base * 0.5);
    assert_eq!(g.inverted().ior, 1.0 / 1.5);
}

/// α as given, α = r² from perceptual roughness (glTF), and the clamp to
/// 10⁻⁴ (NaN and 0 alike).
#[test]
fn ggx_alpha_values() {
    assert_eq!(Ggx::new(0.3).alpha(), 0.3);
    assert_eq!(Ggx::from_roughness(0.5).alpha(), 0.25);
    assert_eq!(Ggx::from_roughness(1.0).alpha(), 1.0);
    assert_eq!(Ggx::new(0.0).alpha(), 1e-4);
    assert_eq!(Ggx::new(f32::NAN).alpha(), 1e-4);
}
