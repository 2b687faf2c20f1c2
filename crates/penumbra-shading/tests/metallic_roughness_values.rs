//! The glTF metallic–roughness model at its boundaries and against values
//! worked by hand (the statistical and energy tests are in
//! `microfacet.rs`): which surfaces transmit, and what seeing one from
//! its back changes.

use penumbra_shading::Rgb;
use penumbra_shading::bsdf::MetallicRoughness;

/// A surface transmits only with transmission > 0 and metallic < 1
/// (KHR_materials_transmission: metal is opaque); only then does seeing
/// it from the back invert its index, and flags say so.
#[test]
fn only_dielectrics_with_transmission_transmit() {
    let base = MetallicRoughness::new(Rgb::new(0.8, 0.5, 0.2), 0.0, 0.4);
    let with = |metallic: f32, transmission: f32| MetallicRoughness {
        metallic,
        transmission,
        ..base
    };
    for (m, transmits) in [
        (with(0.0, 0.0), false),
        (with(0.5, 0.0), false),
        (with(1.0, 1.0), false),
        (with(1.0, 0.0), false),
        (with(0.0, 1.0), true),
        (with(0.5, 0.25), true),
        // Out of range, clamped: transmission −1 is 0, metallic 2 is 1.
        (with(0.0, -1.0), false),
        (with(2.0, 1.0), false),
    ] {
        assert_eq!(
            m.flags().transmission,
            transmits,
            "metallic {} transmission {}",
            m.metallic,
            m.transmission
        );
        let back = m.inverted();
        if transmits {
            assert_eq!(back.ior, 1.0 / 1.5);
            assert_eq!(MetallicRoughness { ior: 1.5, ..back }, m);
        } else {
            assert_eq!(back, m, "an opaque surface looks the same from behind");
        }
    }
}

/// Smooth glass (roughness 0, transmission 1, white) seen from inside
/// (ior 1/1.5, f0 still 0.04): Fresnel takes the cosine of the
/// transmitted angle, `F = f0 + (1 − f0)(1 − cos θt)⁵`; at θo = 30°,
/// sin²θt = 0.25 · 2.25 = 0.5625, cos θt = 0.661438, F = 0.044270 and the
/// refracted throughput (1 − F)/η² = 2.150392. At 60° sin²θt = 1.6875 > 1:
/// total internal reflection, F = 1 and no refraction.
#[test]
fn from_the_denser_side_fresnel_uses_the_transmitted_angle() {
    let glass = MetallicRoughness {
        transmission: 1.0,
        ..MetallicRoughness::new(Rgb::ONE, 0.0, 0.0)
    }
    .inverted();
    let wo = |deg: f32| {
        let t = deg.to_radians();
        glam::Vec3::new(t.sin(), 0.0, t.cos())
    };
    let lobes: Vec<_> = glass.specular(wo(30.0)).iter().collect();
    assert_eq!(lobes.len(), 2);
    assert!((lobes[0].1 - Rgb::splat(0.044270)).abs().max_element() < 1e-5);
    assert!(lobes[0].0.z > 0.0);
    assert!((lobes[1].1 - Rgb::splat(2.150392)).abs().max_element() < 1e-4);
    assert!(lobes[1].0.z < 0.0);
    let lobes: Vec<_> = glass.specular(wo(60.0)).iter().collect();
    assert_eq!(lobes.len(), 1);
    assert!((lobes[0].1 - Rgb::ONE).abs().max_element() < 1e-6);
}

/// Half metal, half clear glass (metallic 0.5, transmission 1, base
/// colour (1, 0.5, 0.25), smooth) at normal incidence, by hand: the
/// mirror reflects mix(F_d, F_m, 0.5) = 0.5 · 0.04 + 0.5 · base (Schlick
/// at cos 1 is f0 = base) = (0.52, 0.27, 0.145); the refraction carries
/// (1 − F_d) · base · (1 − metallic) · transmission / η² =
/// 0.96 · base · 0.5 / 2.25 = (0.213333, 0.106667, 0.053333).
#[test]
fn half_metal_glass_splits_by_hand() {
    let m = MetallicRoughness {
        transmission: 1.0,
        ..MetallicRoughness::new(Rgb::new(1.0, 0.5, 0.25), 0.5, 0.0)
    };
    let lobes: Vec<_> = m.specular(glam::Vec3::Z).iter().collect();
    assert_eq!(lobes.len(), 2);
    let close = |a: Rgb, b: Rgb| (a - b).abs().max_element() < 1e-5;
    assert!(
        close(lobes[0].1, Rgb::new(0.52, 0.27, 0.145)),
        "{}",
        lobes[0].1
    );
    assert!(
        close(lobes[1].1, Rgb::new(0.213333, 0.106667, 0.053333)),
        "{}",
        lobes[1].1
    );
}

/// At ior 1 the dielectric has f0 = 0 and is seen from outside: its
/// specular albedo is `f90 · B(μ)`, B(1) = 0 at normal incidence for a
/// smooth surface, and the white Lambert base under it reflects
/// `1/π · (1 − E(1))² / (1 − E_avg)` with E_avg = 2∫(1 − μ)⁵ μ dμ = 1/21
/// (the table's interpolant gives it within 1 %): f(z, z) = 0.3342. The
/// denser side's bound E = A ≡ 1 would leave the base nothing.
#[test]
fn index_one_is_seen_from_outside() {
    let m = MetallicRoughness {
        ior: 1.0,
        ..MetallicRoughness::new(Rgb::ONE, 0.0, 0.0)
    };
    let f = m.eval(glam::Vec3::Z, glam::Vec3::Z).x;
    let expected = 1.0 / (std::f32::consts::PI * (1.0 - 1.0 / 21.0));
    assert!((f - expected).abs() < 0.01 * expected, "{f} vs {expected}");
}

/// White furnace: a white, opaque dielectric reflects everything it
/// receives, specular and base together (the base takes exactly what the
/// specular layer's single scattering leaves, `1 − E(μo)`; the module
/// doc), so the directional albedo is 1, not just at most 1. Checked with
/// a strong specular layer (ior 3: f0 = 0.25), where the tabulated E must
/// match the lobe to within the table's accuracy (3·10⁻³), at 0°, 60° and
/// 80°; the estimator is the mean sampled weight over 10⁶ samples.
#[test]
fn a_white_dielectric_reflects_everything() {
    let m = MetallicRoughness {
        ior: 3.0,
        ..MetallicRoughness::new(Rgb::ONE, 0.0, 0.5)
    };
    let mut rng = penumbra_shading::stats::TestRng::new(7);
    for deg in [0.0f32, 60.0, 80.0] {
        let t = deg.to_radians();
        let wo = glam::Vec3::new(t.sin(), 0.0, t.cos());
        let albedo = penumbra_shading::stats::sampled_albedo(1_000_000, &mut rng, |u, u2| {
            m.sample(wo, u, u2)
        });
        assert!((albedo - 1.0).abs() < 5e-3, "θo {deg}°: albedo {albedo}");
    }
}

/// Lobe selection by hand, for smooth half-metal, half-transmissive
/// glass with base (0.2, 0.3, 0.7) (mean 0.4) at normal incidence, where
/// the specular albedo is F_d(1) = f0 = 0.04 exactly (the table's smooth
/// row at μ = 1):
/// - diffuse weight w_d = (1 − 0.5)(1 − 0.5) · mean(base · 0.96) = 0.096;
/// - specular weight w_g = mean(f_reflect) + mean(f_transmit) = (0.02 +
///   0.5 · 0.4) + 0.96 · 0.4 · 0.25 = 0.22 + 0.096 = 0.316;
/// - p_d = 0.096 / 0.412 = 0.2330097: the density at 60° is p_d cos/π =
///   0.0370846 (the delta lobes have none);
/// - reflect with q = 0.22 / 0.316 = 0.6962025: the mirror sample's pdf
///   (1 − p_d) q = 0.5339806 and weight f_reflect / pdf; the refraction's
///   pdf (1 − p_d)(1 − q) = 0.2330097, weight f_transmit / (η² pdf).
#[test]
fn lobe_selection_by_hand() {
    let m = MetallicRoughness {
        transmission: 0.5,
        ..MetallicRoughness::new(Rgb::new(0.2, 0.3, 0.7), 0.5, 0.0)
    };
    let z = glam::Vec3::Z;
    let at60 = glam::Vec3::new(60f32.to_radians().sin(), 0.0, 0.5);
    let pdf = m.pdf(z, at60);
    assert!((pdf - 0.0370846).abs() < 1e-6, "pdf {pdf}");
    let close = |a: Rgb, b: Rgb| (a - b).abs().max_element() < 1e-5;
    // u_lobe 0.5: past p_d, then u2 = 0.348 < q: the mirror.
    let s = m.sample(z, 0.5, [0.3, 0.7]).unwrap();
    assert!(s.delta && s.wi.z > 0.999);
    assert!((s.pdf - 0.5339806).abs() < 1e-6, "reflect pdf {}", s.pdf);
    assert!(
        close(s.weight, Rgb::new(0.2247273, 0.3183636, 0.6929091)),
        "{}",
        s.weight
    );
    // u_lobe 0.99: u2 = 0.987 ≥ q: the refraction, straight through.
    let s = m.sample(z, 0.99, [0.3, 0.7]).unwrap();
    assert!(s.delta && s.wi.z < -0.999);
    assert!((s.pdf - 0.2330097).abs() < 1e-6, "refract pdf {}", s.pdf);
    assert!(
        close(s.weight, Rgb::new(0.0915556, 0.1373333, 0.3204444)),
        "{}",
        s.weight
    );
    // u_lobe 0.85: u2 = 0.617/0.767 = 0.804 ≥ q, the refraction (not
    // rescaled, 0.617 < q would pick the mirror).
    assert!(m.sample(z, 0.85, [0.3, 0.7]).unwrap().wi.z < -0.999);
    // u_lobe 0.1 < p_d: the base, whose sample's pdf is p_d cos θi / π.
    let s = m.sample(z, 0.1, [0.3, 0.7]).unwrap();
    assert!(!s.delta);
    let expected = 0.2330097 * s.wi.z / std::f32::consts::PI;
    assert!((s.pdf - expected).abs() < 1e-6, "{} vs {expected}", s.pdf);
}

/// No density along the surface (wi.z = 0), and none below it except
/// through a rough transmission lobe (smooth glass refracts by a delta
/// lobe; an opaque surface not at all).
#[test]
fn density_only_where_a_lobe_reaches() {
    let wo = glam::Vec3::new(0.3, 0.1, 0.9).normalize();
    let along = glam::Vec3::new(0.6, -0.8, 0.0);
    let below = glam::Vec3::new(-0.2, 0.1, -0.9).normalize();
    let glass = |roughness: f32| MetallicRoughness {
        transmission: 1.0,
        ..MetallicRoughness::new(Rgb::splat(0.9), 0.0, roughness)
    };
    let opaque = MetallicRoughness::new(Rgb::splat(0.9), 0.3, 0.5);
    // Sanity: rough glass has density below, the rough models above
    // (smooth clear glass has no non-delta lobe at all).
    assert!(glass(0.5).eval(wo, below).min_element() > 0.0);
    assert!(glass(0.5).pdf(wo, below) > 0.0);
    let above = glam::Vec3::new(-0.3, -0.1, 0.9).normalize();
    assert!(glass(0.5).pdf(wo, above) > 0.0 && opaque.pdf(wo, above) > 0.0);
    for m in [glass(0.5), glass(0.0), opaque] {
        assert_eq!(m.eval(wo, along), Rgb::ZERO, "{m:?}");
        assert_eq!(m.pdf(wo, along), 0.0, "{m:?}");
    }
    for m in [glass(0.0), opaque] {
        assert_eq!(m.eval(wo, below), Rgb::ZERO, "{m:?}");
        assert_eq!(m.pdf(wo, below), 0.0, "{m:?}");
    }
    // From inside (η = 1/1.5) a refraction half vector exists even for a
    // direction along the surface: ωo = (−0.95, 0, 0.312), ωi = x give
    // ωo + η ωi = (−0.283, 0, 0.312), with ωo·m > 0 > ωi·m. Still no
    // density there.
    let inside = glass(0.5).inverted();
    let grazing = glam::Vec3::new(-0.95, 0.0, 0.312).normalize();
    assert_eq!(inside.eval(grazing, glam::Vec3::X), Rgb::ZERO);
    assert_eq!(inside.pdf(grazing, glam::Vec3::X), 0.0);
}

/// A base sample drawn exactly along the surface (the concentric disk's
/// rim, u = (1, ½), gives cos θi = 0) has no density there: no sample,
/// rather than one of weight 0/0.
#[test]
fn no_sample_along_the_surface() {
    let m = MetallicRoughness::new(Rgb::splat(0.8), 0.0, 0.5);
    let wo = glam::Vec3::new(0.3, 0.1, 0.9).normalize();
    assert!(m.sample(wo, 0.0, [0.4, 0.3]).is_some(), "sanity");
    let s = m.sample(wo, 0.0, [1.0, 0.5]);
    assert!(s.is_none(), "{s:?}");
}

/// Rough glass, clear or over a base, from both sides: the density
/// integrates over the sphere to the fraction of samples that are
/// produced (the rest are refused where the chosen direction falls on the
/// wrong side). The integral is estimated
/// with 10⁶ uniform directions, the fraction with 10⁶ samples.
#[test]
fn rough_glass_density_integrates_to_its_sample_rate() {
    use penumbra_shading::stats::TestRng;
    let glass = MetallicRoughness {
        transmission: 1.0,
        ..MetallicRoughness::new(Rgb::ONE, 0.0, 0.6)
    };
    // Half of it with a Lambert base under the glass.
    let half = MetallicRoughness {
        transmission: 0.5,
        ..glass
    };
    for m in [glass, glass.inverted(), half, half.inverted()] {
        let wo = glam::Vec3::new(40f32.to_radians().sin(), 0.0, 40f32.to_radians().cos());
        let mut rng = TestRng::new(11);
        let n = 1_000_000;
        let mut integral = 0.0f64;
        for _ in 0..n {
            // Uniform on the sphere: z = 1 − 2u, φ = 2πv.
            let [u, v] = rng.next_2d();
            let z = 1.0 - 2.0 * u;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = 2.0 * std::f32::consts::PI * v;
            let wi = glam::Vec3::new(r * phi.cos(), r * phi.sin(), z);
            integral += m.pdf(wo, wi) as f64 * 4.0 * std::f64::consts::PI;
        }
        integral /= n as f64;
        let produced = (0..n)
            .filter(|_| m.sample(wo, rng.next_f32(), rng.next_2d()).is_some())
            .count() as f64
            / n as f64;
        assert!(
            (integral - produced).abs() < 0.02,
            "ior {}: ∫pdf {integral} vs sampled fraction {produced}",
            m.ior
        );
    }
}

/// Flags by hand: a smooth surface has delta lobes, and a non-delta one
/// only through its Lambert base, weighted (1 − metallic)(1 − transmission).
#[test]
fn flags_by_hand() {
    let smooth = |metallic: f32, transmission: f32| MetallicRoughness {
        transmission,
        ..MetallicRoughness::new(Rgb::splat(0.5), metallic, 0.0)
    };
    for (m, non_delta) in [
        (smooth(0.0, 0.0), true),
        (smooth(0.5, 0.5), true),
        (smooth(1.0, 0.0), false),
        (smooth(0.0, 1.0), false),
        (smooth(1.0, 1.0), false),
    ] {
        let f = m.flags();
        assert!(f.delta, "{m:?}");
        assert_eq!(f.non_delta, non_delta, "{m:?}");
    }
    let rough = MetallicRoughness::new(Rgb::splat(0.5), 1.0, 0.5).flags();
    assert!(rough.non_delta && !rough.delta && !rough.transmission);
}

/// The summaries: `albedo` is the base colour; a smooth surface seen
/// from below its own surface lists no delta lobe; the split-sum factors
/// and the tables for GPU twins follow their documented layout, with the
/// smooth limit (A, B) = (1, (1 − μ)⁵) by hand at the nodes μ = (i/32)².
#[test]
fn summaries_and_tables_by_hand() {
    let m = MetallicRoughness::new(Rgb::new(0.1, 0.2, 0.3), 0.0, 0.0);
    assert_eq!(m.albedo(), Rgb::new(0.1, 0.2, 0.3));
    let below = glam::Vec3::new(0.3, 0.0, -0.9).normalize();
    assert_eq!(m.specular(below).len(), 0);
    assert_eq!(m.specular(glam::Vec3::Z).len(), 1);
    // μ = 0.25 is node 16 of √μ: exactly (1, 0.75⁵).
    assert_eq!(
        penumbra_shading::bsdf::ggx_split_sum(0.25, 0.0),
        (1.0, 0.75f32.powi(5))
    );
    // Out-of-range arguments are clamped.
    assert_eq!(
        penumbra_shading::bsdf::ggx_split_sum(-1.0, 2.0),
        penumbra_shading::bsdf::ggx_split_sum(0.0, 1.0)
    );
    let [n_mu, n_r] = MetallicRoughness::ALBEDO_TABLE_SIZE;
    let [a, b, a_avg, b_avg] = MetallicRoughness::albedo_tables();
    assert_eq!(
        [a.len(), b.len(), a_avg.len(), b_avg.len()],
        [n_mu * n_r, n_mu * n_r, n_r, n_r]
    );
    for im in 0..n_mu {
        let mu = (im as f32 / (n_mu - 1) as f32).powi(2);
        assert_eq!(a[im], 1.0);
        assert!((b[im] - (1.0 - mu).powi(5)).abs() < 1e-6, "node {im}");
    }
    // Rough rows reflect less than the smooth limit, and every value is
    // an albedo.
    assert!(a[(n_r - 1) * n_mu + n_mu - 1] < 1.0);
    assert!(a.iter().chain(b).all(|v| (0.0..=1.0).contains(v)));
    // The smooth row's cosine average 2∫(1 − μ)⁵ μ dμ = 1/21, within the
    // interpolation in √μ.
    assert_eq!(a_avg[0], 1.0);
    assert!((b_avg[0] - 1.0 / 21.0).abs() < 1e-3, "{}", b_avg[0]);
}
