//! The rough (GGX) models at their boundaries and against hand-computed
//! values: no density across or along the surface (0, never NaN), no
//! sampled direction on the wrong side, the colour summaries, and the
//! tints (normal-incidence reflectance F0 = ((n−1)² + κ²)/((n+1)² + κ²)
//! worked by hand).

use glam::Vec3;
use penumbra_shading::Rgb;
use penumbra_shading::bsdf::{FresnelModel, RoughConductor, RoughDielectric};
use penumbra_shading::stats::TestRng;

fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

/// A conductor reflects only: a pair across the surface, or with a
/// direction along it, has f = 0 and pdf = 0 (the BRDF's 1/(cos θo cos θi)
/// would otherwise give ∞ or NaN there).
#[test]
fn rough_conductor_has_no_density_across_or_along_the_surface() {
    let up = dir(40.0, 0.0);
    let down = Vec3::new(-0.5, 0.1, -0.8).normalize();
    let flat = Vec3::new(0.6, -0.8, 0.0);
    for alpha in [0.05, 0.3, 1.0] {
        let m = RoughConductor::new(Rgb::new(0.2, 0.9, 1.1), Rgb::new(3.9, 2.4, 1.8), alpha);
        // Sanity: the same model has density for a reflection pair.
        assert!(m.eval(up, dir(40.0, 180.0)).min_element() > 0.0);
        for (wo, wi) in [
            (up, down),
            (down, up),
            (down, -down),
            (flat, up),
            (up, flat),
            (Vec3::X, Vec3::Z),
            (Vec3::Z, Vec3::X),
            (Vec3::Z, -Vec3::X),
        ] {
            assert_eq!(m.eval(wo, wi), Rgb::ZERO, "α {alpha}: f({wo}, {wi})");
            assert_eq!(m.pdf(wo, wi), 0.0, "α {alpha}: pdf({wo}, {wi})");
        }
    }
}

/// The dielectric's reflection and transmission lobes are split by the
/// sign of cos θi: a direction in the surface plane belongs to neither, and
/// ωo in the plane or below it (the caller flips the frame for light
/// arriving from inside) sees nothing: f = 0 and pdf = 0 there, not the ∞
/// or NaN of the BSDF's 1/(cos θo cos θi).
#[test]
fn rough_dielectric_has_no_density_along_the_surface() {
    let up = dir(30.0, 20.0);
    let below = Vec3::new(0.2, 0.1, -0.9).normalize();
    let flat = Vec3::new(0.6, -0.8, 0.0);
    for alpha in [0.05, 0.3, 1.0] {
        let m = RoughDielectric::new(1.5, alpha);
        // Sanity: both lobes have density away from the plane.
        assert!(m.eval(Vec3::Z, dir(10.0, 0.0)).min_element() > 0.0);
        assert!(m.eval(Vec3::Z, -dir(10.0, 0.0)).min_element() > 0.0);
        for (wo, wi) in [
            (flat, up),
            (flat, below),
            (Vec3::X, Vec3::Z),
            (up, flat),
            (Vec3::Z, Vec3::X),
            (Vec3::Z, -Vec3::X),
            (below, up),
            (below, Vec3::Z),
            (below, -below),
        ] {
            assert_eq!(m.eval(wo, wi), Rgb::ZERO, "α {alpha}: f({wo}, {wi})");
            assert_eq!(m.pdf(wo, wi), 0.0, "α {alpha}: pdf({wo}, {wi})");
        }
    }
}

/// Every sampled direction lies on the lobe's side: above the surface for
/// the conductor (even at grazing ωo and α = 1, where most visible
/// normals reflect ωo below the surface and the sample must be refused),
/// and for the dielectric above when it reflects (η = 1 in the sample),
/// below when it refracts. Every accepted sample's pdf matches `pdf`.
#[test]
fn sampled_directions_lie_on_their_lobe_side() {
    let mut rng = TestRng::new(11);
    let cond = RoughConductor::new(Rgb::splat(0.2), Rgb::splat(3.0), 1.0);
    let glass = RoughDielectric::new(1.5, 1.0);
    let (mut refused, mut reflected, mut refracted) = (0, 0, 0);
    for i in 0..20_000 {
        let wo = dir(if i % 2 == 0 { 85.0 } else { 60.0 }, 0.0);
        match cond.sample(wo, rng.next_f32(), rng.next_2d()) {
            None => refused += 1,
            Some(s) => {
                assert!(s.wi.z > 0.0, "conductor sent {} below", s.wi);
                let pdf = cond.pdf(wo, s.wi);
                assert!((s.pdf - pdf).abs() <= 1e-3 * pdf, "{} vs {pdf}", s.pdf);
            }
        }
        if let Some(s) = glass.sample(wo, rng.next_f32(), rng.next_2d()) {
            if s.eta == 1.0 {
                reflected += 1;
                assert!(s.wi.z > 0.0, "reflection sent {} below", s.wi);
            } else {
                refracted += 1;
                assert_eq!(s.eta, 1.5);
                assert!(s.wi.z < 0.0, "refraction sent {} above", s.wi);
            }
        }
    }
    // At 85° and α = 1 a good share of the visible normals reflect ωo
    // below the surface: the guard is exercised, not vacuous.
    assert!(refused > 1000, "only {refused} conductor samples refused");
    assert!(
        reflected > 1000 && refracted > 1000,
        "{reflected} / {refracted}"
    );
}

/// The colour summaries: a rough conductor's albedo is its normal-incidence
/// reflectance, F0 = ((n−1)² + κ²)/((n+1)² + κ²), the same for the exact and
/// Schlick Fresnel models; a rough dielectric's is its transmission tint.
#[test]
fn albedo_is_normal_incidence_reflectance_or_tint() {
    // n = 2.5, κ = 0.5: (2.25 + 0.25)/(12.25 + 0.25) = 0.2.
    // n = 0.2, κ = 3.9: (0.64 + 15.21)/(1.44 + 15.21) = 15.85/16.65.
    // n = 1.0, κ = 0:   0.
    let expected = [0.2, 15.85 / 16.65, 0.0];
    let mut m = RoughConductor::new(Rgb::new(2.5, 0.2, 1.0), Rgb::new(0.5, 3.9, 0.0), 0.2);
    for model in [FresnelModel::Exact, FresnelModel::Schlick] {
        m.fresnel = model;
        let a = m.albedo();
        for b in 0..3 {
            assert!((a[b] - expected[b]).abs() < 1e-6, "{model:?} band {b}: {a}");
        }
    }
    let tint = Rgb::new(0.9, 0.5, 0.25);
    let glass = RoughDielectric {
        tint,
        ..RoughDielectric::new(1.5, 0.2)
    };
    assert_eq!(glass.albedo(), tint);
    // Tinting multiplies: transmitted light by t, reflected light not at all.
    let t = Rgb::new(0.5, 0.8, 2.0);
    let tinted = glass.tinted(t);
    assert_eq!(tinted.tint, tint * t);
    let (wo, wt, wr) = (dir(20.0, 0.0), -dir(12.0, 0.0), dir(20.0, 180.0));
    let (f, ft) = (glass.eval(wo, wt), tinted.eval(wo, wt));
    assert!((ft - f * t).abs().max_element() <= 1e-6 * ft.max_element());
    assert_eq!(tinted.eval(wo, wr), glass.eval(wo, wr));
}

/// Tinting a rough conductor solves for the index that gives F0·t, keeping
/// κ and the root nearest the old n. Worked by hand:
/// - n = 2.5, κ = 0.5: F0 = 0.2, c = (1 + F0)/(1 − F0) = 1.5, and
///   n² − 2cn + 1 + κ² = n² − 3n + 1.25 = 0 has the roots 0.5 and 2.5: a tint
///   of 1 keeps the upper root 2.5 (the lower gives the same F0);
/// - n = 0.2, κ = 3.9, tint 0.1: F0' = 0.1 · 15.85/16.65 = 0.0951952,
///   c = 1.0951952/0.9048048 = 1.2104215, and c² − 1 − κ² < 0 has no real
///   root: n' = c, κ' = √(c² − 1) = 0.6819972 (then F0(n', κ') = (c−1)/(c+1)
///   = F0' exactly).
#[test]
fn tinted_conductor_indices_by_hand() {
    let m = RoughConductor::new(Rgb::new(2.5, 0.2, 2.5), Rgb::new(0.5, 3.9, 0.5), 0.3);
    let same = m.tinted(Rgb::ONE);
    assert!(
        (same.eta[0] - 2.5).abs() < 1e-4,
        "upper root kept: {}",
        same.eta
    );
    assert!((same.k[0] - 0.5).abs() < 1e-6);
    // Tint 0.8 on n = 2.5, κ = 0.5: F0' = 0.16, c = 1.16/0.84 = 1.3809524,
    // disc = c² − 1.25 = 0.6570295, roots c ∓ 0.8105736 = 0.5703788 and
    // 2.1915260: the upper one is nearer 2.5.
    let t = m.tinted(Rgb::new(0.8, 0.1, 1.0));
    assert!((t.eta[0] - 2.191_526).abs() < 1e-4, "{}", t.eta);
    assert!((t.k[0] - 0.5).abs() < 1e-6);
    assert!((t.eta[1] - 1.210_421_5).abs() < 1e-4, "{}", t.eta);
    assert!((t.k[1] - 0.681_997_2).abs() < 1e-4, "{}", t.k);
    assert!((t.eta[2] - 2.5).abs() < 1e-4 && (t.k[2] - 0.5).abs() < 1e-6);
}

/// Two indices with the same F0 each keep their own root. n = 0.9, κ = 0.3:
/// F0 = (0.01 + 0.09)/(3.61 + 0.09) = 1/37, c = 38/36, and
/// n² − 2cn + 1.09 = 0 has the roots 0.9 and 2c − 0.9 = 1.2111111. A tint
/// of 1 leaves each where it is; a tint of 0.9 (F0' = 0.9/37, c = 1.0498615,
/// disc = c² − 1.09 = 0.0122092) moves 0.9 to the lower root 0.9393664 and
/// 1.2111111 to the upper root 1.1603566. (The nearest root is the one on
/// n's side of c, not the one farther than n from the other root.)
#[test]
fn tinted_conductor_keeps_the_nearer_of_two_roots() {
    let m = RoughConductor::new(
        Rgb::new(0.9, 1.211_111_1, 0.9),
        Rgb::new(0.3, 0.3, 0.3),
        0.3,
    );
    let same = m.tinted(Rgb::ONE);
    assert!(
        (same.eta[0] - 0.9).abs() < 1e-4,
        "lower root kept: {}",
        same.eta
    );
    assert!(
        (same.eta[1] - 1.211_111_1).abs() < 1e-4,
        "upper root kept: {}",
        same.eta
    );
    let t = m.tinted(Rgb::splat(0.9));
    assert!((t.eta[0] - 0.939_366_4).abs() < 1e-4, "{}", t.eta);
    assert!((t.eta[1] - 1.160_356_6).abs() < 1e-4, "{}", t.eta);
    assert_eq!(t.k, m.k);
}

/// At a direction so grazing that cos²θo underflows (an interpolated
/// shading normal can give one), Smith's G1(ωo) is 0, so the sample's pdf
/// and weight are 0 and 0/0: the models refuse such samples rather than
/// return a direction with pdf 0 and a NaN weight.
#[test]
fn samples_at_an_underflowing_cosine_are_refused_or_finite() {
    let wo = Vec3::new(1.0, 0.0, 1e-30);
    assert!(wo.z > 0.0 && wo.z * wo.z == 0.0);
    let cond = RoughConductor::new(Rgb::splat(0.2), Rgb::splat(3.0), 0.5);
    let glass = RoughDielectric::new(1.5, 0.5);
    let mut rng = TestRng::new(5);
    for _ in 0..2000 {
        let (ul, u) = (rng.next_f32(), rng.next_2d());
        for s in [cond.sample(wo, ul, u), glass.sample(wo, ul, u)]
            .into_iter()
            .flatten()
        {
            assert!(s.pdf > 0.0 && s.pdf.is_finite(), "pdf {}", s.pdf);
            assert!(s.weight.is_finite(), "weight {}", s.weight);
        }
    }
}

/// Seen from the denser side (relative index η = 1/1.5, as for light inside
/// glass) an in-plane ωi can have a valid generalised half vector:
/// ωo = (−0.8, 0, 0.6), ωi = (1, 0, 0) give m ∝ ωo + ωi/1.5 = (−0.1333, 0,
/// 0.6) with ωo·m > 0 > ωi·m. Still, a direction in the surface plane
/// belongs to neither lobe: f = 0 and pdf = 0, not the 0/0 of G2 = 0 over
/// cos θi = 0. (For η > 1 no in-plane ωi has one: ωi·(ωo + η ωi) =
/// ωo·ωi + η > 0.)
#[test]
fn rough_dielectric_from_inside_has_no_density_in_the_plane() {
    let m = RoughDielectric::new(1.0 / 1.5, 0.5);
    let wo = Vec3::new(-0.8, 0.0, 0.6);
    // Sanity: the same pair tilted just below the plane transmits.
    let below = Vec3::new(1.0, 0.0, -0.05).normalize();
    assert!(m.eval(wo, below).min_element() > 0.0 && m.pdf(wo, below) > 0.0);
    assert_eq!(m.eval(wo, Vec3::X), Rgb::ZERO);
    assert_eq!(m.pdf(wo, Vec3::X), 0.0);
}
