//! Statistical tests of samplers: Pearson's chi-square goodness-of-fit of a
//! direction sampler against the density it claims, on the unit sphere
//! (the test pbrt and Mitsuba use for BSDFs and lights), with the p-value from
//! the regularised incomplete gamma function and Šidák-corrected significance.
//!
//! Used by the tests of every BSDF and light; public so that tests in other
//! crates share one implementation.

use glam::Vec3;
use std::f64::consts::PI;

/// A small, fast, seedable generator (SplitMix64) of independent uniforms:
/// goodness-of-fit tests need independent samples, not low-discrepancy ones.
#[derive(Clone, Debug)]
pub struct TestRng(u64);

impl TestRng {
    pub fn new(seed: u64) -> Self {
        Self(seed ^ 0x9e37_79b9_7f4a_7c15)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    pub fn next_2d(&mut self) -> [f32; 2] {
        [self.next_f32(), self.next_f32()]
    }
}

/// Monte Carlo directional albedo in the first band: the mean of
/// `weight.x` over `n` draws of `sample(u_lobe, u)` with uniforms from
/// `rng` (a draw that returns no sample counts 0). For a BSDF sampled
/// from direction ωo, `∫ f(ωo, ωi) |cos θi| dωi`.
pub fn sampled_albedo(
    n: usize,
    rng: &mut TestRng,
    mut sample: impl FnMut(f32, [f32; 2]) -> Option<crate::bsdf::BsdfSample>,
) -> f64 {
    let mut sum = 0.0f64;
    for _ in 0..n {
        if let Some(s) = sample(rng.next_f32(), rng.next_2d()) {
            sum += s.weight.x as f64;
        }
    }
    sum / n as f64
}

/// Outcome of a chi-square test.
#[derive(Clone, Debug)]
pub struct ChiSquare {
    /// Pearson's statistic Σ (observed − expected)² / expected over pooled bins.
    pub statistic: f64,
    /// Degrees of freedom (pooled bins − 1).
    pub dof: usize,
    /// P(χ² ≥ statistic) under the hypothesis that samples follow the pdf.
    pub p_value: f64,
    /// ∫ pdf over the sphere (numerically); 1 for a sampler that always
    /// returns a direction through its density.
    pub pdf_integral: f64,
    /// Fraction of sampling attempts that produced a direction.
    pub sampled_fraction: f64,
    /// Why the test failed outright, e.g. a sample where the pdf is 0.
    pub defect: Option<String>,
}

impl ChiSquare {
    /// Šidák-corrected acceptance: with `tests` tests in the family and an
    /// overall significance `alpha`, each needs p ≥ 1 − (1 − α)^(1/tests).
    pub fn passes(&self, alpha: f64, tests: usize) -> bool {
        let per_test = 1.0 - (1.0 - alpha).powf(1.0 / tests.max(1) as f64);
        self.defect.is_none() && self.p_value >= per_test
    }
}

/// Configuration of [`chi_square_sphere`].
#[derive(Clone, Copy, Debug)]
pub struct SphereBins {
    /// Bins in cos θ over [−1, 1] (equal solid angle).
    pub cos_theta: usize,
    /// Bins in φ over [0, 2π).
    pub phi: usize,
    /// Simpson sub-intervals per bin side when integrating the pdf (even).
    pub resolution: usize,
}

impl Default for SphereBins {
    fn default() -> Self {
        Self {
            cos_theta: 20,
            phi: 40,
            resolution: 8,
        }
    }
}

/// Chi-square test of `sample` (called `n` times, `None` = no direction, e.g.
/// absorbed or a delta lobe the caller excludes) against `pdf` [1/sr] on the
/// sphere. Bins with fewer than 5 expected samples are pooled.
pub fn chi_square_sphere(
    n: usize,
    bins: SphereBins,
    mut sample: impl FnMut() -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f32,
) -> ChiSquare {
    let (nt, np) = (bins.cos_theta, bins.phi);
    let bin_of = |d: Vec3| -> usize {
        let z = d.z.clamp(-1.0, 1.0) as f64;
        let t = (((z + 1.0) * 0.5 * nt as f64) as usize).min(nt - 1);
        let mut phi = (d.y as f64).atan2(d.x as f64);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let p = ((phi / (2.0 * PI) * np as f64) as usize).min(np - 1);
        t * np + p
    };
    let mut observed = vec![0f64; nt * np];
    let mut produced = 0usize;
    let mut defect = None;
    for _ in 0..n {
        if let Some(d) = sample() {
            if !d.is_finite() || (d.length() - 1.0).abs() > 1e-3 {
                defect.get_or_insert_with(|| format!("sampled a non-unit direction {d}"));
                continue;
            }
            if pdf(d) <= 0.0 {
                defect.get_or_insert_with(|| format!("sampled {d} where the pdf is 0"));
            }
            observed[bin_of(d)] += 1.0;
            produced += 1;
        }
    }
    // Expected counts: composite Simpson over (cos θ, φ) in each bin; the
    // measure dω = d(cos θ) dφ, so no Jacobian is needed.
    let m = bins.resolution.max(2) & !1;
    let simpson = |i: usize| -> f64 {
        if i == 0 || i == m {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        }
    };
    let inside = |i: usize| (i as f64 / m as f64).clamp(1e-6, 1.0 - 1e-6);
    let mut expected = vec![0f64; nt * np];
    let (dz, dphi) = (2.0 / nt as f64, 2.0 * PI / np as f64);
    for t in 0..nt {
        for p in 0..np {
            let mut sum = 0.0;
            for i in 0..=m {
                // Edge points sit a hair inside the bin: densities that are
                // discontinuous at a bin edge (e.g. zero below the horizon)
                // must be evaluated on this bin's side. The poles stay exact:
                // lat-long densities carry 1/sin θ there.
                let pole = (t == 0 && i == 0) || (t == nt - 1 && i == m);
                let z = -1.0 + dz * (t as f64 + if pole { i as f64 / m as f64 } else { inside(i) });
                let r = (1.0 - z * z).max(0.0).sqrt();
                for j in 0..=m {
                    let phi = dphi * (p as f64 + inside(j));
                    let d = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
                    sum += simpson(i) * simpson(j) * pdf(d) as f64;
                }
            }
            expected[t * np + p] = sum * (dz / (3.0 * m as f64)) * (dphi / (3.0 * m as f64));
        }
    }
    let pdf_integral: f64 = expected.iter().sum();
    let sampled_fraction = produced as f64 / n.max(1) as f64;
    // Scale the density to counts: the pdf integrates to 1 over the directions
    // actually produced.
    for e in &mut expected {
        *e *= produced as f64 / pdf_integral.max(1e-300);
    }
    let (statistic, dof) = pearson_pooled(&observed, &expected, &mut defect);
    let p_value = if dof == 0 {
        1.0
    } else {
        1.0 - regularized_gamma_p(dof as f64 / 2.0, statistic / 2.0)
    };
    ChiSquare {
        statistic,
        dof,
        p_value,
        pdf_integral,
        sampled_fraction,
        defect,
    }
}

/// Pearson's statistic with bins of expected count < 5 pooled into one.
fn pearson_pooled(observed: &[f64], expected: &[f64], defect: &mut Option<String>) -> (f64, usize) {
    let mut order: Vec<usize> = (0..observed.len()).collect();
    order.sort_by(|&a, &b| expected[a].total_cmp(&expected[b]));
    let (mut pool_obs, mut pool_exp) = (0.0, 0.0);
    let (mut stat, mut cells) = (0.0, 0usize);
    for &i in &order {
        let (o, e) = (observed[i], expected[i]);
        if e <= 0.0 {
            if o > 0.0 {
                defect.get_or_insert_with(|| {
                    format!("bin {i} has {o} samples but an expected count of {e}")
                });
            }
            continue;
        }
        if e < 5.0 || pool_exp > 0.0 && pool_exp < 5.0 {
            pool_obs += o;
            pool_exp += e;
            continue;
        }
        stat += (o - e) * (o - e) / e;
        cells += 1;
    }
    if pool_exp > 0.0 {
        stat += (pool_obs - pool_exp) * (pool_obs - pool_exp) / pool_exp;
        cells += 1;
    }
    (stat, cells.saturating_sub(1))
}

/// Regularised lower incomplete gamma P(a, x) (series for x < a + 1, else
/// Lentz's continued fraction for Q).
pub fn regularized_gamma_p(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    let ln_prefix = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        (sum * ln_prefix.exp()).min(1.0)
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        (1.0 - ln_prefix.exp() * h).max(0.0)
    }
}

/// ln Γ(x) for x > 0 (Lanczos, g = 7, n = 9).
pub fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = G[0];
    let t = x + 7.5;
    for (i, g) in G.iter().enumerate().skip(1) {
        a += g / (x + i as f64);
    }
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};

    #[test]
    fn gamma_function_values() {
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
        assert!((ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-12);
        // χ² with 2 dof: P = 1 − e^(−x/2).
        for x in [0.1, 1.0, 3.0, 10.0, 40.0] {
            let p = regularized_gamma_p(1.0, x / 2.0);
            assert!((p - (1.0 - (-x / 2.0f64).exp())).abs() < 1e-12, "{x}");
        }
        // Tabulated: χ²(10 dof) 0.95 quantile 18.307.
        let p = regularized_gamma_p(5.0, 18.307 / 2.0);
        assert!((p - 0.95).abs() < 1e-4, "{p}");
    }

    #[test]
    fn accepts_a_correct_sampler_and_rejects_a_wrong_one() {
        let mut rng = TestRng::new(1);
        let good = chi_square_sphere(
            200_000,
            SphereBins::default(),
            || Some(square_to_cosine_hemisphere(rng.next_2d())),
            |d| cosine_hemisphere_pdf(d.z),
        );
        assert!(good.passes(0.01, 1), "{good:?}");
        assert!((good.pdf_integral - 1.0).abs() < 1e-3);
        // Claiming a uniform hemisphere density for cosine samples must fail.
        let mut rng = TestRng::new(2);
        let bad = chi_square_sphere(
            200_000,
            SphereBins::default(),
            || Some(square_to_cosine_hemisphere(rng.next_2d())),
            |d| {
                if d.z > 0.0 {
                    0.5 / std::f32::consts::PI
                } else {
                    0.0
                }
            },
        );
        assert!(!bad.passes(0.01, 1), "{bad:?}");
    }
}
