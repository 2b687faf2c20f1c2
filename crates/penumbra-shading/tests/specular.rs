//! Ideally smooth BSDFs (mirror, conductor, dielectric) through the public
//! API: laws of reflection and refraction, Fresnel energy balance, total
//! internal reflection, lobe-selection statistics, and the notes' quiz numbers.

use glam::Vec3;
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::optics::{
    f0_from_ior, fresnel_conductor, fresnel_dielectric, schlick, schlick_dielectric,
};
use penumbra_shading::bsdf::{BsdfFlags, Conductor, Dielectric, FresnelModel, Mirror};
use penumbra_shading::stats::TestRng;

const MODELS: [FresnelModel; 2] = [FresnelModel::Exact, FresnelModel::Schlick];

/// Uniform direction on the open upper hemisphere (z ∈ (0, 1]).
fn upper(rng: &mut TestRng) -> Vec3 {
    let z = 1.0 - rng.next_f32();
    let phi = 2.0 * std::f32::consts::PI * rng.next_f32();
    let r = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Uniform direction on the whole sphere.
fn sphere(rng: &mut TestRng) -> Vec3 {
    let d = upper(rng);
    if rng.next_f32() < 0.5 { d } else { -d }
}

/// Outgoing direction at polar angle `deg` in the xz plane.
fn at_angle(deg: f32) -> Vec3 {
    let t = deg.to_radians();
    Vec3::new(t.sin(), 0.0, t.cos())
}

fn sin_theta(d: Vec3) -> f32 {
    (d.x * d.x + d.y * d.y).sqrt()
}

fn close(a: Rgb, b: Rgb, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

/// Law of reflection: same polar angle, opposite azimuth, unit length.
fn assert_mirror_direction(wo: Vec3, wi: Vec3) {
    assert!((wi.length() - 1.0).abs() < 1e-5, "{wi}");
    assert!((wi.z - wo.z).abs() < 1e-6, "θi = θo: {wo} {wi}");
    assert!(
        (wi.x + wo.x).abs() < 1e-6 && (wi.y + wo.y).abs() < 1e-6,
        "{wo} {wi}"
    );
}

/// Snell–Descartes with wo outside: wi below, sin θo = η sin θi, and wi in the
/// plane of incidence on the opposite side of the normal.
fn assert_snell(wo: Vec3, wi: Vec3, eta: f32) {
    assert!((wi.length() - 1.0).abs() < 1e-5, "{wi}");
    assert!(
        wi.z < 0.0 || wo.z < 1e-3,
        "transmitted to the far side: {wo} {wi}"
    );
    let (so, si) = (sin_theta(wo), sin_theta(wi));
    assert!(
        (so - eta * si).abs() < 2e-5,
        "sin θo = η sin θi: {so} vs {eta}·{si}"
    );
    // Coplanar with z and wo, azimuth opposite: wi.xy = −wo.xy · si/so.
    let cross = wo.x * wi.y - wo.y * wi.x;
    assert!(cross.abs() < 1e-5, "plane of incidence: {wo} {wi}");
    assert!(
        wo.x * wi.x + wo.y * wi.y <= 1e-7,
        "opposite azimuth: {wo} {wi}"
    );
}

fn dielectrics() -> Vec<Dielectric> {
    let mut v = Vec::new();
    for fresnel in MODELS {
        for eta in [1.5f32, 1.33, 1.4, 2.42, 10.0] {
            let d = Dielectric::new(eta, Rgb::ONE, fresnel);
            v.push(d);
            v.push(d.inverted());
        }
    }
    v
}

/// (reflection, transmission) throughputs and directions of the specular set.
fn lobes(d: &Dielectric, wo: Vec3) -> (Vec3, Rgb, Option<(Vec3, Rgb)>) {
    let set = d.specular(wo);
    let mut it = set.iter();
    let (wr, fr) = it.next().expect("a reflection lobe");
    assert!(wr.z > 0.0, "first lobe reflects");
    let t = it.next();
    assert!(it.next().is_none());
    (wr, fr, t)
}

#[test]
fn mirror_obeys_law_of_reflection() {
    let m = Mirror::new(Rgb::new(0.9, 0.5, 0.2));
    assert_eq!(m.flags(), BsdfFlags::SPECULAR_REFLECTION);
    assert_eq!(m.albedo(), m.reflectance);
    let mut rng = TestRng::new(11);
    for _ in 0..10_000 {
        let wo = upper(&mut rng);
        let s = m.sample(wo, rng.next_f32(), rng.next_2d()).unwrap();
        assert!(s.delta && s.pdf == 1.0);
        assert_mirror_direction(wo, s.wi);
        assert_eq!(s.weight, m.reflectance);
        let set = m.specular(wo);
        assert_eq!(set.len(), 1);
        let (wi, tp) = set.iter().next().unwrap();
        assert_eq!((wi, tp), (s.wi, s.weight));
    }
    assert!(m.sample(-Vec3::Z, 0.5, [0.5; 2]).is_none());
    assert!(m.specular(-Vec3::Z).is_empty());
    let t = Rgb::new(0.5, 1.0, 0.0);
    assert_eq!(m.tinted(t).reflectance, m.reflectance * t);
}

#[test]
fn dielectric_reflection_and_snell_refraction() {
    let mut rng = TestRng::new(12);
    for d in dielectrics() {
        assert_eq!(
            d.flags(),
            BsdfFlags {
                non_delta: false,
                delta: true,
                transmission: true
            }
        );
        let mut transmitted = 0;
        for _ in 0..4_000 {
            let wo = upper(&mut rng);
            let (wr, _, t) = lobes(&d, wo);
            assert_mirror_direction(wo, wr);
            if let Some((wt, _)) = t {
                assert_snell(wo, wt, d.eta);
                transmitted += 1;
            } else {
                // Only possible leaving the denser side beyond the critical angle.
                assert!(
                    d.eta < 1.0 && sin_theta(wo) >= d.eta * (1.0 - 1e-5),
                    "{d:?} {wo}"
                );
            }
        }
        assert!(transmitted > 0, "{d:?}");
    }
}

#[test]
fn dielectric_fresnel_energy_balance() {
    // With tint 1: F + η'² T = 1 (η' = η for light crossing from inside to wo).
    let mut rng = TestRng::new(13);
    for d in dielectrics() {
        for _ in 0..4_000 {
            let wo = upper(&mut rng);
            let (_, fr, t) = lobes(&d, wo);
            let expect_f = match d.fresnel {
                FresnelModel::Exact => fresnel_dielectric(wo.z, d.eta),
                FresnelModel::Schlick => schlick_dielectric(wo.z, d.eta),
            };
            let tt = t.map_or(Rgb::ZERO, |(_, tt)| tt);
            if t.is_some() {
                assert!(close(fr, Rgb::splat(expect_f), 1e-6), "{d:?} {wo}: {fr}");
            }
            let total = fr + tt * d.eta * d.eta;
            assert!(close(total, Rgb::ONE, 2e-6), "{d:?} {wo}: {total}");
            assert!(fr.min_element() >= 0.0 && fr.max_element() <= 1.0);
        }
    }
    // The tint colours transmission only.
    let tint = Rgb::new(0.8, 0.4, 0.1);
    let clear = Dielectric::glass();
    let coloured = clear.tinted(tint);
    assert_eq!(coloured.albedo(), tint);
    let wo = at_angle(40.0);
    let (_, f0, t0) = lobes(&clear, wo);
    let (_, f1, t1) = lobes(&coloured, wo);
    assert_eq!(f0, f1);
    assert!(close(t1.unwrap().1, t0.unwrap().1 * tint, 1e-7));
}

#[test]
fn dielectric_normal_incidence_quiz() {
    // Notes 003 quiz: F0 = 4 % for glass, 2.78 % for n = 1.4, from either side.
    for fresnel in MODELS {
        for (eta, f0, tol) in [(1.5f32, 0.04f32, 1e-6f32), (1.4, 0.02778, 5e-5)] {
            for d in [
                Dielectric::new(eta, Rgb::ONE, fresnel),
                Dielectric::new(eta, Rgb::ONE, fresnel).inverted(),
            ] {
                let (wr, fr, t) = lobes(&d, Vec3::Z);
                assert!((wr - Vec3::Z).length() < 1e-6);
                assert!((fr.x - f0).abs() < tol, "{d:?}: F = {}", fr.x);
                let (wt, tt) = t.unwrap();
                assert!((wt + Vec3::Z).length() < 1e-6, "straight through");
                assert!((tt.x * d.eta * d.eta - (1.0 - f0)).abs() < tol);
            }
        }
    }
    assert_eq!(Dielectric::glass().eta, 1.5);
    assert_eq!(Dielectric::glass().tint, Rgb::ONE);
}

#[test]
fn dielectric_total_internal_reflection_from_inside() {
    // Quiz 3: light leaving n = 10 into air: TIR beyond asin(1/10) = 5.739°.
    let crit = (0.1f32).asin().to_degrees();
    for fresnel in MODELS {
        let inside = Dielectric::new(10.0, Rgb::ONE, fresnel).inverted();
        assert!((inside.eta - 0.1).abs() < 1e-7);
        for deg in [0.0f32, 2.0, 5.0, 5.7] {
            let wo = at_angle(deg);
            let (_, fr, t) = lobes(&inside, wo);
            let (wt, tt) = t.unwrap_or_else(|| panic!("{deg}° transmits"));
            assert_snell(wo, wt, inside.eta);
            assert!(fr.x < 1.0 && tt.x > 0.0);
        }
        for deg in [5.78f32, 6.0, 30.0, 60.0, 89.0] {
            let wo = at_angle(deg);
            let (wr, fr, t) = lobes(&inside, wo);
            assert!(t.is_none(), "{deg}° is beyond the critical angle");
            assert_eq!(fr, Rgb::ONE);
            for u in [0.0f32, 0.5, 0.999_999] {
                let s = inside.sample(wo, u, [0.3, 0.7]).unwrap();
                assert_eq!((s.wi, s.weight, s.pdf, s.delta), (wr, Rgb::ONE, 1.0, true));
            }
        }
        // Bisection for the onset of TIR.
        let (mut lo, mut hi) = (0.0f32, 30.0f32);
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            if lobes(&inside, at_angle(mid)).2.is_some() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        assert!(
            (lo - crit).abs() < 2e-3,
            "TIR from {lo}° (expected {crit}°)"
        );
    }
}

#[test]
fn dielectric_lobe_frequencies_match_fresnel() {
    // Transmission is chosen with probability 1 − F: binomial, 5 sigma.
    let mut rng = TestRng::new(14);
    let n = 100_000u32;
    for fresnel in MODELS {
        for d in [
            Dielectric::glass(),
            Dielectric::new(1.33, Rgb::ONE, fresnel),
            Dielectric::new(1.5, Rgb::ONE, fresnel).inverted(),
        ] {
            let d = Dielectric { fresnel, ..d };
            for deg in [0.0f32, 30.0, 40.0, 60.0, 80.0, 88.0] {
                let wo = at_angle(deg);
                let (_, fr, t) = lobes(&d, wo);
                let p_t = if t.is_some() { 1.0 - fr.x as f64 } else { 0.0 };
                let mut count = 0u32;
                for _ in 0..n {
                    let s = d.sample(wo, rng.next_f32(), rng.next_2d()).unwrap();
                    if s.wi.z < 0.0 {
                        count += 1;
                    }
                }
                let mean = n as f64 * p_t;
                let sigma = (n as f64 * p_t * (1.0 - p_t)).sqrt();
                assert!(
                    (count as f64 - mean).abs() <= 5.0 * sigma + 1e-9,
                    "{d:?} at {deg}°: {count} transmissions, expected {mean} ± {sigma}"
                );
            }
        }
    }
}

#[test]
fn sample_weights_match_specular_throughputs() {
    // Every sample is one of the specular() lobes, pdf = its selection
    // probability and weight · pdf = its throughput; so E[weight] = Σ throughputs.
    let mut rng = TestRng::new(15);
    let tint = Rgb::new(0.9, 0.6, 0.3);
    for d in dielectrics() {
        let d = d.tinted(tint);
        for _ in 0..200 {
            let wo = upper(&mut rng);
            let set = d.specular(wo);
            let total: Rgb = set.iter().map(|(_, tp)| tp).sum();
            let mut prob = 0.0f32;
            for (wi, tp) in set.iter() {
                let s = if wi.z > 0.0 {
                    d.sample(wo, 0.0, [0.5; 2])
                } else {
                    d.sample(wo, 1.0 - f32::EPSILON, [0.5; 2])
                }
                .unwrap();
                assert!(s.delta);
                assert!((s.wi - wi).length() < 1e-6);
                let tol = 1e-6 * tp.max_element().max(1.0);
                assert!(close(s.weight * s.pdf, tp, tol), "{d:?} {wo}");
                prob += s.pdf;
            }
            assert!(
                (prob - 1.0).abs() < 1e-6,
                "selection probabilities sum to 1"
            );
            let m = 64;
            let mut est = Rgb::ZERO;
            for i in 0..m {
                let u = (i as f32 + 0.5) / m as f32;
                est += d.sample(wo, u, rng.next_2d()).unwrap().weight;
            }
            // Stratified over u_lobe: exact up to the lobe boundary stratum.
            let bound = (Rgb::ONE + tint / (d.eta * d.eta)) / m as f32;
            assert!(
                ((est / m as f32) - total).abs().cmple(bound).all(),
                "{d:?} {wo}"
            );
        }
    }
    let mut rng = TestRng::new(16);
    let c = Conductor::new(
        Rgb::new(0.2, 0.9, 1.1),
        Rgb::new(3.9, 2.4, 2.2),
        FresnelModel::Exact,
    );
    for _ in 0..1_000 {
        let wo = upper(&mut rng);
        let s = c.sample(wo, rng.next_f32(), rng.next_2d()).unwrap();
        let (wi, tp) = c.specular(wo).iter().next().unwrap();
        assert_mirror_direction(wo, s.wi);
        assert_eq!((s.wi, s.weight * s.pdf, s.delta), (wi, tp, true));
    }
}

/// Gold, copper, aluminium, and a plain dielectric-like index (n, κ).
fn metals() -> [(Rgb, Rgb); 4] {
    [
        (Rgb::new(0.143, 0.374, 1.442), Rgb::new(3.983, 2.385, 1.603)),
        (Rgb::new(0.200, 0.924, 1.102), Rgb::new(3.912, 2.452, 2.142)),
        (Rgb::new(1.657, 0.880, 0.521), Rgb::new(9.224, 6.270, 4.837)),
        (Rgb::new(1.5, 1.4, 2.4), Rgb::ZERO),
    ]
}

#[test]
fn conductor_exact_and_schlick_agree_at_normal_incidence() {
    let mut rng = TestRng::new(17);
    for (eta, k) in metals() {
        let exact = Conductor::new(eta, k, FresnelModel::Exact);
        let approx = Conductor::new(eta, k, FresnelModel::Schlick);
        let f0 = f0_from_ior(eta, k);
        let (_, fe) = exact.specular(Vec3::Z).iter().next().unwrap();
        let (_, fs) = approx.specular(Vec3::Z).iter().next().unwrap();
        assert!(close(fe, f0, 1e-5) && close(fs, f0, 1e-6), "{fe} {fs} {f0}");
        assert!(close(exact.albedo(), f0, 0.0) && close(approx.albedo(), f0, 0.0));
        assert_eq!(exact.flags(), BsdfFlags::SPECULAR_REFLECTION);
        for _ in 0..5_000 {
            let wo = upper(&mut rng);
            for (c, reference) in [
                (exact, fresnel_conductor(wo.z, eta, k)),
                (approx, schlick(f0, wo.z)),
            ] {
                let (wi, f) = c.specular(wo).iter().next().unwrap();
                assert_mirror_direction(wo, wi);
                assert!(close(f, reference, 1e-6));
                assert!(f.min_element() >= 0.0 && f.max_element() <= 1.0, "{f}");
            }
        }
        // Both tend to 1 at grazing incidence.
        let graze = at_angle(89.99);
        for c in [exact, approx] {
            assert!(close(c.reflectance(graze.z), Rgb::ONE, 2e-3));
        }
    }
}

#[test]
fn conductor_without_extinction_is_a_dielectric() {
    let mut rng = TestRng::new(18);
    for eta in [1.33f32, 1.5, 2.42] {
        for fresnel in MODELS {
            let c = Conductor::new(Rgb::splat(eta), Rgb::ZERO, fresnel);
            let d = Dielectric::new(eta, Rgb::ONE, fresnel);
            for _ in 0..5_000 {
                let wo = upper(&mut rng);
                let (wc, fc) = c.specular(wo).iter().next().unwrap();
                let (wd, fd, _) = lobes(&d, wo);
                assert_eq!(wc, wd);
                assert!(
                    close(fc, fd, 2e-6),
                    "{fresnel:?} η={eta} {wo}: {fc} vs {fd}"
                );
            }
        }
    }
}

#[test]
fn conductor_tint_scales_normal_reflectance() {
    let mut rng = TestRng::new(19);
    for (eta, k) in metals() {
        for fresnel in MODELS {
            let c = Conductor::new(eta, k, fresnel);
            // Tint 1 is the identity.
            let same = c.tinted(Rgb::ONE);
            assert!(close(same.eta, eta, 2e-4 * eta.max_element()), "{same:?}");
            assert!(
                close(same.k, k, 2e-4 * k.max_element().max(1.0)),
                "{same:?}"
            );
            for t in [Rgb::new(0.5, 0.8, 0.2), Rgb::splat(0.9), Rgb::ZERO] {
                let tc = c.tinted(t);
                assert!(close(tc.albedo(), c.albedo() * t, 2e-5), "{t}: {tc:?}");
                assert!(tc.k.min_element() >= 0.0 && tc.eta.min_element() > 0.0);
                for _ in 0..200 {
                    let wo = upper(&mut rng);
                    let f = tc.reflectance(wo.z);
                    assert!(f.min_element() >= 0.0 && f.max_element() <= 1.0, "{f}");
                }
            }
            // A black tint: F0 = 0; the exact model then reflects nothing at
            // any angle (n = 1, κ = 0), Schlick keeps its (1 − cos θ)^5 rise.
            let black = c.tinted(Rgb::ZERO);
            for cos in [1.0f32, 0.7, 0.3, 0.01] {
                let f = black.reflectance(cos);
                let expect = match fresnel {
                    FresnelModel::Exact => 0.0,
                    FresnelModel::Schlick => (1.0 - cos).powi(5),
                };
                assert!(close(f, Rgb::splat(expect), 1e-6), "{fresnel:?} {cos}: {f}");
            }
        }
    }
}

/// A tint keeps n's relative position g in its admissible range (module
/// doc of `conductor.rs`): for F0 = r, κ² ≥ 0 allows
/// n ∈ [(1 − √r)/(1 + √r), (1 + √r)/(1 − √r)]; g and the range are
/// computed here from those closed forms.
#[test]
fn conductor_tint_keeps_the_relative_position_of_n() {
    let f0 = |n: f64, k: f64| ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
    let g = |n: f64, k: f64| {
        let s = f0(n, k).sqrt();
        let (lo, hi) = ((1.0 - s) / (1.0 + s), (1.0 + s) / (1.0 - s));
        (n - lo) / (hi - lo)
    };
    for (eta, k) in metals() {
        let c = Conductor::new(eta, k, FresnelModel::Exact);
        for t in [0.5f32, 0.8, 0.2] {
            let tc = c.tinted(Rgb::splat(t));
            for i in 0..3 {
                let (n0, k0) = (eta[i] as f64, k[i] as f64);
                let (n1, k1) = (tc.eta[i] as f64, tc.k[i] as f64);
                assert!(
                    (f0(n1, k1) - f0(n0, k0) * t as f64).abs() < 1e-5,
                    "F0 scaled by {t}"
                );
                assert!(
                    (g(n1, k1) - g(n0, k0)).abs() < 1e-4,
                    "band {i}, tint {t}: g {} -> {}",
                    g(n0, k0),
                    g(n1, k1)
                );
            }
        }
    }
}

/// F0 = 0 (n = 1, κ = 0) leaves n no range to move in: any tint keeps
/// (n, κ) = (1, 0), with finite values.
#[test]
fn conductor_tint_of_zero_reflectance_stays_index_matched() {
    for fresnel in MODELS {
        let c = Conductor::new(Rgb::ONE, Rgb::ZERO, fresnel);
        for t in [0.5f32, 1.0, 2.0] {
            let tc = c.tinted(Rgb::splat(t));
            assert_eq!((tc.eta, tc.k), (Rgb::ONE, Rgb::ZERO), "{fresnel:?} {t}");
        }
    }
}

#[test]
fn inverted_interface_is_reciprocal() {
    // F(θo, η) = F(θt, 1/η): light crossing either way splits alike, and
    // the transmission throughputs differ by exactly the radiance factor η².
    let mut rng = TestRng::new(20);
    for d in dielectrics() {
        let back = d.inverted();
        assert!((back.inverted().eta - d.eta).abs() <= 1e-6 * d.eta);
        for _ in 0..2_000 {
            let wo = upper(&mut rng);
            // Near grazing the reverse path sits at the critical angle, where
            // F has an infinite slope and 1 − sin²θt/η² cancels: f32
            // round-off, not physics, dominates there.
            if wo.z < 0.2 {
                continue;
            }
            let Some((wt, tt)) = lobes(&d, wo).2 else {
                continue;
            };
            // The reverse path: leave along −wt on the other side.
            let wo_back = -wt;
            let (wt_back, tt_back) = lobes(&back, wo_back).2.expect("reverse path transmits");
            assert!((wt_back + wo).length() < 5e-4, "{d:?} {wo}: {wt_back}");
            let lhs = tt * d.eta * d.eta;
            let rhs = tt_back * back.eta * back.eta;
            // (Schlick too: it uses the angle on the lighter side both ways.)
            assert!(close(lhs, rhs, 1e-4), "{d:?} {wo}: {lhs} vs {rhs}");
        }
    }
}

#[test]
fn smooth_models_have_no_density() {
    let mut rng = TestRng::new(21);
    let mirror = Mirror::new(Rgb::ONE);
    let cond = Conductor::new(Rgb::splat(0.2), Rgb::splat(3.0), FresnelModel::Exact);
    let glass = Dielectric::glass();
    for _ in 0..2_000 {
        let wo = upper(&mut rng);
        let mut wis = vec![sphere(&mut rng), Vec3::Z, -Vec3::Z];
        wis.extend(glass.specular(wo).iter().map(|(w, _)| w));
        for wi in wis {
            assert_eq!(mirror.eval(wo, wi), Rgb::ZERO);
            assert_eq!(cond.eval(wo, wi), Rgb::ZERO);
            assert_eq!(glass.eval(wo, wi), Rgb::ZERO);
            assert_eq!(mirror.pdf(wo, wi), 0.0);
            assert_eq!(cond.pdf(wo, wi), 0.0);
            assert_eq!(glass.pdf(wo, wi), 0.0);
        }
        assert!(
            glass
                .sample(wo, rng.next_f32(), rng.next_2d())
                .unwrap()
                .delta
        );
    }
}

/// A direction in the surface plane (cos θo = 0) or below it sees no
/// lobe of a one-sided smooth reflector, in `specular` as in `sample`:
/// at grazing incidence Fresnel gives F = 1, so a lobe there would send
/// the path along the surface with full weight.
#[test]
fn one_sided_reflectors_have_no_lobe_at_or_below_the_horizon() {
    let mirror = Mirror::new(Rgb::ONE);
    let cond = Conductor::new(Rgb::splat(0.2), Rgb::splat(3.0), FresnelModel::Exact);
    for wo in [
        Vec3::X,
        Vec3::new(0.6, -0.8, 0.0),
        Vec3::new(0.6, 0.0, -0.8),
    ] {
        assert_eq!(mirror.specular(wo).iter().count(), 0, "{wo}");
        assert_eq!(cond.specular(wo).iter().count(), 0, "{wo}");
        assert!(mirror.sample(wo, 0.5, [0.5; 2]).is_none(), "{wo}");
        assert!(cond.sample(wo, 0.5, [0.5; 2]).is_none(), "{wo}");
    }
}
