//! Phong–Blinn family through the public API: the notes' quiz, reciprocity,
//! energy (directional albedo by quadrature) and chi-square of `sample`
//! against `pdf`.

use glam::Vec3;
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{PhongBlinn, PhongVariant};
use penumbra_shading::sampling::square_to_uniform_sphere;
use penumbra_shading::stats::{SphereBins, TestRng, chi_square_sphere, sampled_albedo};
use std::f64::consts::{FRAC_PI_2, PI};

fn dir(theta_deg: f32, phi: f32) -> Vec3 {
    let t = theta_deg.to_radians();
    Vec3::new(t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos())
}

fn upper(rng: &mut TestRng) -> Vec3 {
    let d = square_to_uniform_sphere(rng.next_2d());
    Vec3::new(d.x, d.y, d.z.abs().max(1e-4)).normalize()
}

fn rel(a: f32, b: f32) -> f32 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-30)
}

#[test]
fn notes_quiz_diffuse_2_4_and_specular_2_5() {
    // SEEDS.md quiz 2: n = z, light from (0,3,4), Lin = 5, kd = 0.6 → 2.4 from any view.
    let lin = 5.0;
    let l = Vec3::new(0.0, 3.0, 4.0).normalize();
    for variant in PhongVariant::ALL {
        let m = PhongBlinn::new(Rgb::splat(0.6), Rgb::ZERO, 3.0, variant);
        for v in [
            Vec3::Z,
            dir(40.0, 1.0),
            dir(85.0, -2.0),
            Vec3::new(0.0, 4.0, 3.0) / 5.0,
        ] {
            let radiance = m.eval(v, l) * lin * l.z;
            assert!(
                (radiance - Rgb::splat(2.4)).abs().max_element() < 1e-5,
                "{radiance}"
            );
        }
    }
    // Quiz 4: ks = √2, γ = 3, camera (0,4,3), no diffuse, the notes' formula → 2.5.
    let v = Vec3::new(0.0, 4.0, 3.0) / 5.0;
    let h = (l + v).normalize();
    // cos δ = 0.7071 = 1/√2
    assert!((h.z - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6 && (l.z - 0.8).abs() < 1e-6);
    let m = PhongBlinn::new(Rgb::ZERO, Rgb::splat(2f32.sqrt()), 3.0, PhongVariant::Notes);
    let radiance = m.eval(v, l) * lin * l.z;
    assert!(
        (radiance - Rgb::splat(2.5)).abs().max_element() < 1e-5,
        "{radiance}"
    );
    // max(cos θ, cos θ') = cos θin here, so max-Blinn agrees; |l + v|² = 3.92 does not.
    let mb = PhongBlinn {
        variant: PhongVariant::MaxBlinn,
        ..m
    };
    assert!(
        (mb.eval(v, l) * lin * l.z - Rgb::splat(2.5))
            .abs()
            .max_element()
            < 1e-5
    );
    let hs = PhongBlinn {
        variant: PhongVariant::HalfwaySquared,
        ..m
    };
    assert!((hs.eval(v, l).x * lin * l.z - 2.5 * 0.8 / 3.92).abs() < 1e-5);
}

#[test]
fn constructors_tint_flags_and_hemisphere() {
    let rho = Rgb::new(0.6, 0.3, 0.9);
    let m = PhongBlinn::from_albedo(rho, Rgb::splat(0.2), 20.0, PhongVariant::MaxBlinn);
    assert!((m.kd * std::f32::consts::PI - rho).abs().max_element() < 1e-6);
    let t = m.tinted(Rgb::new(0.5, 1.0, 0.0));
    assert_eq!(t.kd, m.kd * Rgb::new(0.5, 1.0, 0.0));
    assert_eq!(
        (t.ks, t.shininess, t.variant),
        (m.ks, m.shininess, m.variant)
    );
    let f = m.flags();
    assert!(f.non_delta && !f.delta && !f.transmission);
    assert!(m.specular(Vec3::Z).is_empty());
    let wo = dir(30.0, 0.2);
    let below = Vec3::new(0.3, 0.1, -0.5).normalize();
    assert_eq!(m.eval(wo, below), Rgb::ZERO);
    assert_eq!(m.pdf(wo, below), 0.0);
    assert!(m.sample(-wo, 0.3, [0.4, 0.6]).is_none());
}

#[test]
fn reciprocal_variants_and_lambert_are_reciprocal() {
    let mut rng = TestRng::new(11);
    let lambert = penumbra_shading::bsdf::Lambert::new(Rgb::new(0.8, 0.5, 0.2));
    for variant in [
        PhongVariant::MaxBlinn,
        PhongVariant::HalfwaySquared,
        PhongVariant::Normalized,
    ] {
        assert!(variant.is_reciprocal());
        let mut worst = 0f32;
        for _ in 0..20_000 {
            let (a, b) = (upper(&mut rng), upper(&mut rng));
            let m = PhongBlinn::new(
                Rgb::splat(0.1 * rng.next_f32()),
                Rgb::new(1.0, 0.5, 0.25) * rng.next_f32(),
                200.0 * rng.next_f32(),
                variant,
            );
            let (fab, fba) = (m.eval(a, b), m.eval(b, a));
            worst = worst.max(rel(fab.x, fba.x)).max(rel(fab.z, fba.z));
            assert_eq!(lambert.eval(a, b), lambert.eval(b, a));
        }
        println!("{variant:?}: max relative |f(wo,wi) − f(wi,wo)| = {worst:e}");
        assert!(worst < 1e-6, "{variant:?} {worst}");
    }
}

#[test]
fn notes_variant_is_not_reciprocal() {
    assert!(!PhongVariant::Notes.is_reciprocal());
    let mut rng = TestRng::new(12);
    let (mut large, mut worst, n) = (0, 0f32, 10_000);
    for _ in 0..n {
        let (wo, wi) = (upper(&mut rng), upper(&mut rng));
        let m = PhongBlinn::new(
            Rgb::ZERO,
            Rgb::ONE,
            1.0 + 50.0 * rng.next_f32(),
            PhongVariant::Notes,
        );
        let (f, g) = (m.eval(wo, wi).x, m.eval(wi, wo).x);
        if !(f.is_normal() && g.is_normal()) {
            continue; // (cos δ)^γ underflowed for nearly opposite directions
        }
        // f ∝ 1/cos θin: swapping the roles of light and view scales by cos θo / cos θi.
        assert!(rel(f / g, wo.z / wi.z) < 1e-4, "{wo} {wi}");
        let r = rel(f, g);
        worst = worst.max(r);
        if r > 0.5 {
            large += 1;
        }
    }
    println!("Notes: {large}/{n} random pairs differ by > 50 %, max relative difference {worst}");
    assert!(large > n / 10 && worst > 0.99, "{large} {worst}");
}

/// Directional albedo ∫ f(wo, wi) cos θi dωi (red channel), by the midpoint
/// rule over the halfway vector: dωi = 4 (wo·h) dωh, θh ∈ [0, θmax] where
/// cos^γ θh ≥ 1e-9 (the lobes outside are below 1e-9 × a bounded factor);
/// so for the specular lobe only (kd = 0).
fn directional_albedo(m: &PhongBlinn, theta_o_deg: f32, nt: usize, np: usize) -> f64 {
    let wo = dir(theta_o_deg, 0.0);
    let g = m.shininess as f64;
    let tmax = if g > 0.0 {
        1e-9f64.powf(1.0 / g).acos().min(FRAC_PI_2)
    } else {
        FRAC_PI_2
    };
    let (dt, dp) = (tmax / nt as f64, 2.0 * PI / np as f64);
    let mut sum = 0.0;
    for i in 0..nt {
        let t = (i as f64 + 0.5) * dt;
        let mut ring = 0.0;
        for j in 0..np {
            let p = (j as f64 + 0.5) * dp;
            let h = Vec3::new(
                (t.sin() * p.cos()) as f32,
                (t.sin() * p.sin()) as f32,
                t.cos() as f32,
            );
            let wo_h = wo.dot(h);
            if wo_h <= 0.0 {
                continue;
            }
            let wi = (2.0 * wo_h * h - wo).normalize();
            if wi.z <= 0.0 {
                continue;
            }
            ring += (m.eval(wo, wi).x * wi.z * 4.0 * wo_h) as f64;
        }
        sum += ring * t.sin();
    }
    sum * dt * dp
}

const GAMMAS: [f32; 7] = [0.0, 1.0, 3.0, 10.0, 30.0, 100.0, 1000.0];

/// Max of the directional albedo over θo = 0..89° and the angle where it is
/// reached, with ks = 1 (Normalized) or ks = 1 / albedo at normal incidence.
fn albedo_sweep(variant: PhongVariant, gamma: f32) -> (f64, u32, f64) {
    let ks = match variant {
        PhongVariant::Normalized => 1.0,
        _ => 1.0 / variant.normal_incidence_albedo(gamma),
    };
    let m = PhongBlinn::new(Rgb::ZERO, Rgb::splat(ks), gamma, variant);
    let mut best = (0.0, 0, 0.0);
    for deg in 0..90 {
        let a = directional_albedo(&m, deg as f32, 256, 256);
        if a > best.0 {
            best = (a, deg, 0.0);
        }
        best.2 = a; // albedo at the last (most grazing) angle
    }
    println!(
        "{variant:?} γ = {gamma}: ks = {ks:.5}, max albedo {:.4} at θo = {}°, at 89°: {:.4}",
        best.0, best.1, best.2
    );
    best
}

#[test]
fn albedo_is_exact_at_normal_incidence() {
    for variant in PhongVariant::ALL {
        for g in GAMMAS {
            let m = PhongBlinn::new(Rgb::new(0.1, 0.0, 0.0), Rgb::splat(0.3), g, variant);
            // The quadrature covers the specular lobe only; kd adds π kd.
            let lobe = PhongBlinn { kd: Rgb::ZERO, ..m };
            let quad = directional_albedo(&lobe, 0.0, 1024, 256) + std::f64::consts::PI * 0.1;
            let closed = m.albedo().x as f64;
            assert!(
                (quad - closed).abs() < 1e-3 * closed,
                "{variant:?} γ={g}: {quad} vs {closed}"
            );
        }
    }
}

#[test]
fn energy_normalized_blinn_phong_exceeds_one_by_at_most_7_5_percent() {
    // Closed form at normal incidence over γ ∈ [0, 2000]: the (γ+8)/(8π)
    // factor is an approximation, and overshoots.
    let (mut peak, mut peak_g) = (0.0f32, 0.0f32);
    for i in 0..=20_000 {
        let g = i as f32 * 0.1;
        let a = PhongVariant::Normalized.normal_incidence_albedo(g);
        if a > peak {
            (peak, peak_g) = (a, g);
        }
    }
    println!("Normalized, ks = 1: normal-incidence albedo peaks at {peak:.5} for γ = {peak_g}");
    assert!(peak > 1.07 && peak < 1.08 && (5.0..20.0).contains(&peak_g));
    for g in GAMMAS {
        let (max, at, _) = albedo_sweep(PhongVariant::Normalized, g);
        assert!(max <= 1.0 + 0.0752, "γ={g}: {max}");
        if g == 0.0 {
            // γ = 0: f = 1/π, exactly Lambertian.
            assert!((max - 1.0).abs() < 2e-3);
        } else {
            // It is at normal incidence that the albedo is largest, and > 1.
            assert!(at == 0 && max > 1.001, "γ={g}: {max} at {at}");
        }
    }
}

#[test]
fn energy_notes_variant_never_exceeds_its_normal_incidence_albedo() {
    for g in GAMMAS {
        let (max, _, grazing) = albedo_sweep(PhongVariant::Notes, g);
        assert!(max < 1.002, "γ={g}: {max}");
        if g == 0.0 {
            // f cos θin = ks: the albedo 2π ks is the same at every angle.
            assert!((grazing - 1.0).abs() < 2e-3);
        } else {
            assert!(grazing < 0.6, "γ={g}: {grazing}");
        }
    }
}

#[test]
fn energy_max_blinn_exceeds_one_for_low_shininess() {
    for g in GAMMAS {
        let (max, at, _) = albedo_sweep(PhongVariant::MaxBlinn, g);
        match g {
            0.0 => assert!(max > 1.95 && max < 2.0 && at == 89, "{max} at {at}"),
            1.0 => assert!(
                max > 1.15 && max < 1.25 && (55..70).contains(&at),
                "{max} at {at}"
            ),
            3.0 => assert!(
                max > 1.004 && max < 1.02 && (15..35).contains(&at),
                "{max} at {at}"
            ),
            _ => assert!(max < 1.002, "γ={g}: {max}"),
        }
    }
}

#[test]
fn energy_halfway_squared_exceeds_one_at_grazing_for_low_shininess() {
    for g in GAMMAS {
        let (max, at, grazing) = albedo_sweep(PhongVariant::HalfwaySquared, g);
        let expected = match g {
            0.0 => Some(3.03),
            1.0 => Some(2.26),
            3.0 => Some(1.65),
            10.0 => Some(1.15),
            _ => None,
        };
        match expected {
            Some(e) => assert!(
                at == 89 && (grazing - e).abs() < 0.02,
                "γ={g}: {grazing} at {at}"
            ),
            None => assert!(max < 1.002, "γ={g}: {max}"),
        }
    }
}

#[test]
fn chi_square_sample_against_pdf_and_weights() {
    let gammas = [1.0, 10.0, 100.0];
    let angles = [0.0, 30.0, 60.0, 85.0];
    let tests = PhongVariant::ALL.len() * gammas.len() * angles.len();
    let bins = SphereBins {
        cos_theta: 40,
        phi: 80,
        resolution: 8,
    };
    let mut seed = 100;
    let mut worst_p = 1.0f64;
    for variant in PhongVariant::ALL {
        for g in gammas {
            let m = PhongBlinn::from_albedo(Rgb::new(0.3, 0.2, 0.1), Rgb::splat(0.5), g, variant);
            for theta in angles {
                let wo = dir(theta, 0.7);
                seed += 1;
                let mut rng = TestRng::new(seed);
                let mut bad_weight = None;
                let res = chi_square_sphere(
                    100_000,
                    bins,
                    || {
                        let s = m.sample(wo, rng.next_f32(), rng.next_2d())?;
                        let expect = m.eval(wo, s.wi) * s.wi.z / m.pdf(wo, s.wi);
                        let err = (s.weight - expect).abs().max_element() / expect.max_element();
                        if s.delta || err > 1e-4 || rel(s.pdf, m.pdf(wo, s.wi)) > 1e-4 {
                            bad_weight.get_or_insert((s, expect));
                        }
                        Some(s.wi)
                    },
                    |wi| m.pdf(wo, wi),
                );
                worst_p = worst_p.min(res.p_value);
                let tag = format!("{variant:?} γ={g} θo={theta}");
                assert!(bad_weight.is_none(), "{tag}: {bad_weight:?}");
                println!("{tag}: p = {:.4}", res.p_value);
                assert!(res.passes(0.01, tests), "{tag}: {res:?}");
                // ∫ pdf = the fraction of draws that returned a direction.
                assert!(
                    (res.pdf_integral - res.sampled_fraction).abs() < 5e-3,
                    "{tag}: {res:?}"
                );
            }
        }
    }
    println!("{tests} chi-square tests passed, smallest p-value {worst_p:.4}");
}

#[test]
fn specular_only_sampling_white_furnace_matches_quadrature() {
    // kd = 0 → the specular lobe alone (selection probability 1): the mean
    // weight is the directional albedo.
    let mut rng = TestRng::new(7);
    for variant in PhongVariant::ALL {
        for (g, theta) in [(10.0, 20.0), (100.0, 70.0)] {
            let m = PhongBlinn::new(Rgb::ZERO, Rgb::splat(0.05), g, variant);
            let wo = dir(theta, 0.0);
            let mc = sampled_albedo(200_000, &mut rng, |u, u2| m.sample(wo, u, u2));
            let quad = directional_albedo(&m, theta, 512, 256);
            assert!(
                (mc - quad).abs() < 0.01 * quad,
                "{variant:?} γ={g}: {mc} vs {quad}"
            );
        }
    }
}

/// The lobe-selection probability by hand (it changes the noise, not the
/// mean, so the statistical tests above cannot see it): p = a_s/(a_d + a_s)
/// with a_d = π mean(kd⁺), a_s = mean(ks⁺) × the lobe's albedo at normal
/// incidence. With s = 1/√2 and I(k) = (1 − s^(k+1))/(k+1):
/// - Notes, γ = 1, kd mean 0.2 (a negative band counts 0), ks = 0.5:
///   a_s = 0.5 · 8π I(2) = 2.7078292, a_d = 0.2π, p = 0.8116635;
/// - MaxBlinn, γ = 10, kd = 0.1, ks = (0.3, 0.6, 0) (mean 0.3):
///   A = 8π (2 I(13) − I(11)) = 1.5006715, p = 0.5889908;
/// - kd = 0 → 1, ks = 0 → 0, both 0 or an infinite ks → ½.
#[test]
fn specular_probability_by_hand() {
    let p = |kd: Rgb, ks: Rgb, g: f32, v: PhongVariant| {
        PhongBlinn::new(kd, ks, g, v).specular_probability()
    };
    let notes = p(
        Rgb::new(-1.0, 0.6, 0.0),
        Rgb::splat(0.5),
        1.0,
        PhongVariant::Notes,
    );
    assert!((notes - 0.811_663_5).abs() < 1e-5, "{notes}");
    let max = p(
        Rgb::splat(0.1),
        Rgb::new(0.3, 0.6, 0.0),
        10.0,
        PhongVariant::MaxBlinn,
    );
    assert!((max - 0.588_990_8).abs() < 1e-5, "{max}");
    assert_eq!(
        p(Rgb::ZERO, Rgb::splat(0.5), 5.0, PhongVariant::Normalized),
        1.0
    );
    assert_eq!(
        p(Rgb::splat(0.5), Rgb::ZERO, 5.0, PhongVariant::Normalized),
        0.0
    );
    assert_eq!(p(Rgb::ZERO, Rgb::ZERO, 5.0, PhongVariant::Notes), 0.5);
    assert_eq!(
        p(
            Rgb::splat(0.5),
            Rgb::splat(f32::INFINITY),
            5.0,
            PhongVariant::Notes
        ),
        0.5
    );
}

/// An infinite exponent makes the specular lobe's density infinite at the
/// mirror direction: such samples are refused, and every sample returned
/// has a finite positive pdf and a finite weight. (NaN is refused by the
/// constructor.)
#[test]
fn degenerate_exponents_give_no_infinite_samples() {
    let mut rng = TestRng::new(17);
    let m = PhongBlinn::new(
        Rgb::splat(0.2),
        Rgb::splat(0.5),
        f32::INFINITY,
        PhongVariant::Normalized,
    );
    for _ in 0..500 {
        let wo = upper(&mut rng);
        if let Some(s) = m.sample(wo, rng.next_f32(), rng.next_2d()) {
            assert!(s.pdf > 0.0 && s.pdf.is_finite(), "pdf {}", s.pdf);
            assert!(s.weight.is_finite(), "weight {}", s.weight);
        }
    }
}
