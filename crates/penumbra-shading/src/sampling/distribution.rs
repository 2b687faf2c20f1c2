//! Piecewise-constant distributions sampled by inverting their CDFs: a
//! discrete / 1-D one (light selection, rows of an image) and a 2-D one over
//! [0,1)² (environment-map importance sampling).

/// Piecewise-constant discrete distribution over `n` items with weights w_i:
/// p(i) = w_i / Σw.
///
/// Sampling inverts the CDF with a guide table (the cutpoint method of
/// Chen & Asau 1974): `guide[k]` is the first item whose CDF exceeds
/// k/n · Σw, so the item for u lies between `guide[⌊u n⌋]` and
/// `guide[⌊u n⌋ + 1]` and the search covers those few entries, not all n.
#[derive(Clone, Debug, Default)]
pub struct Distribution1D {
    cdf: Vec<f64>,
    total: f64,
    /// `(cdf[i] − cdf[i−1]) / total` in f32, computed once (a sample's
    /// probability is then one load, not an f64 division); empty when all
    /// weights are 0.
    pmf: Vec<f32>,
    /// n + 1 cutpoints (empty when all weights are 0).
    guide: Vec<u32>,
}

impl Distribution1D {
    /// Negative or non-finite weights count as 0.
    pub fn new(weights: impl IntoIterator<Item = f32>) -> Self {
        let mut cdf = Vec::new();
        let mut total = 0.0f64;
        for w in weights {
            if w.is_finite() && w > 0.0 {
                total += w as f64;
            }
            cdf.push(total);
        }
        let n = cdf.len();
        let guide = if total > 0.0 {
            (0..=n)
                .map(|k| {
                    let start = (k as f64 / n as f64) * total;
                    cdf.partition_point(|&c| c <= start) as u32
                })
                .collect()
        } else {
            Vec::new()
        };
        let pmf = if total > 0.0 {
            let mut prev = 0.0;
            cdf.iter()
                .map(|&c| {
                    let p = ((c - prev) / total) as f32;
                    prev = c;
                    p
                })
                .collect()
        } else {
            Vec::new()
        };
        Self {
            cdf,
            total,
            pmf,
            guide,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.total <= 0.0
    }

    pub fn len(&self) -> usize {
        self.cdf.len()
    }

    /// The running sums of the weights (item i's is the sum of weights 0
    /// to i, invalid ones counted as 0) and their total: [`Self::sample`]
    /// picks the first item whose running sum exceeds u × total.
    pub fn running_sums(&self) -> (&[f64], f64) {
        (&self.cdf, self.total)
    }

    /// Probability of item `i`.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        self.pmf.get(i).copied().unwrap_or(0.0)
    }

    /// Item for `u` ∈ [0,1), with its probability. `None` if all weights are 0.
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        if self.total <= 0.0 {
            return None;
        }
        let target = u as f64 * self.total;
        // First index whose cdf exceeds the target (skips zero-weight
        // items), searched between the cutpoints of u's bucket: every
        // item before guide[k] has cdf ≤ k/n · Σw ≤ target, and item
        // guide[k + 1] has cdf > (k + 1)/n · Σw ≥ target, so the answer
        // is in [guide[k], guide[k + 1]] (the search returns the range's
        // end when all of it is ≤ target). For u ≥ 1, where no item
        // exceeds it, the last item of positive weight (the first whose
        // cdf reaches the total), as u → 1⁻ gives.
        // (A NaN u, which no sampler gives, lands in bucket 0: the first
        // item of positive weight.)
        let n = self.cdf.len();
        let k = ((u as f64 * n as f64) as usize).min(n - 1);
        let (lo, hi) = (self.guide[k] as usize, self.guide[k + 1] as usize);
        let found = lo + self.cdf[lo..hi].partition_point(|&c| c <= target);
        let i = match found {
            i if i < self.cdf.len() => i,
            _ => self.cdf.partition_point(|&c| c < self.total),
        };
        Some((i, self.pmf(i)))
    }

    /// Continuous sample of the piecewise-constant density on [0,1) whose
    /// n cells have probabilities pmf(i): returns (x, density p(x), cell).
    /// `p(x) = n · pmf(cell)`, so ∫₀¹ p = 1.
    pub fn sample_continuous(&self, u: f32) -> Option<(f32, f32, usize)> {
        let (i, pmf) = self.sample(u)?;
        let prev = if i == 0 { 0.0 } else { self.cdf[i - 1] };
        let width = self.cdf[i] - prev;
        let t = if width > 0.0 {
            ((u as f64 * self.total - prev) / width).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let n = self.cdf.len() as f64;
        let x = (((i as f64 + t) / n) as f32).min(1.0 - f32::EPSILON);
        Some((x, pmf * n as f32, i))
    }

    /// Density of [`Distribution1D::sample_continuous`] at x ∈ [0,1).
    pub fn pdf_continuous(&self, x: f32) -> f32 {
        let n = self.cdf.len();
        if n == 0 {
            return 0.0;
        }
        let i = ((x.clamp(0.0, 1.0) * n as f32) as usize).min(n - 1);
        self.pmf(i) * n as f32
    }
}

/// Piecewise-constant density on [0,1)² over a `width × height` grid of
/// non-negative weights (row-major, row = v): the marginal picks a row, the
/// row's conditional picks the column. `p(u,v) = w(row,col) · W·H / Σw`.
#[derive(Clone, Debug, Default)]
pub struct Distribution2D {
    rows: Vec<Distribution1D>,
    marginal: Distribution1D,
    /// p(u, v) of every cell, row-major: the product [`Distribution2D::sample`]
    /// returns, kept so that [`Distribution2D::pdf`] is one load.
    density: Vec<f32>,
    width: usize,
}

impl Distribution2D {
    /// `weights.len()` must be `width * height`.
    pub fn new(width: usize, height: usize, weights: &[f32]) -> Self {
        assert_eq!(weights.len(), width * height, "Distribution2D size");
        let rows: Vec<Distribution1D> = weights
            .chunks(width.max(1))
            .map(|r| Distribution1D::new(r.iter().copied()))
            .collect();
        let marginal = Distribution1D::new(rows.iter().map(|r| r.total as f32));
        let (w, h) = (width as f32, height as f32);
        let density = rows
            .iter()
            .enumerate()
            .flat_map(|(r, row)| {
                let pv = marginal.pmf(r) * h;
                (0..width).map(move |c| row.pmf(c) * w * pv)
            })
            .collect();
        Self {
            rows,
            marginal,
            density,
            width,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.marginal.is_empty()
    }

    /// A point (u, v) ∈ [0,1)² and its density with respect to du dv.
    pub fn sample(&self, u: [f32; 2]) -> Option<(glam::Vec2, f32)> {
        let (v, pv, row) = self.marginal.sample_continuous(u[1])?;
        let (x, pu, _) = self.rows[row].sample_continuous(u[0])?;
        Some((glam::Vec2::new(x, v), pu * pv))
    }

    /// Density at (u, v) with respect to du dv.
    pub fn pdf(&self, uv: glam::Vec2) -> f32 {
        // An all-zero grid needs no test of its own: both factors are 0.
        let h = self.rows.len();
        if h == 0 {
            return 0.0;
        }
        // (Rows exist only for a width > 0.) The cells of
        // `pdf_continuous` along each axis.
        let w = self.width;
        let row = ((uv.y.clamp(0.0, 1.0) * h as f32) as usize).min(h - 1);
        let col = ((uv.x.clamp(0.0, 1.0) * w as f32) as usize).min(w - 1);
        self.density[row * w + col]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Weights (1, 0, 3): cdf (1, 1, 4), pmf (1/4, 0, 3/4). Items with no
    /// weight, negative or non-finite weights are never chosen; u = 1/4
    /// lands on the cdf step shared by items 0 and 1 and picks item 2; u ≥ 1
    /// picks the last item of positive weight, not a trailing zero one.
    #[test]
    fn discrete_values_by_hand() {
        let d = Distribution1D::new([1.0, 0.0, 3.0]);
        assert!(!d.is_empty());
        assert_eq!(d.len(), 3);
        assert_eq!([d.pmf(0), d.pmf(1), d.pmf(2)], [0.25, 0.0, 0.75]);
        assert_eq!(d.pmf(3), 0.0);
        for (u, i) in [(0.0, 0), (0.2499, 0), (0.25, 2), (0.999, 2), (1.0, 2)] {
            assert_eq!(d.sample(u), Some((i, d.pmf(i))), "u = {u}");
        }
        let leading = Distribution1D::new([0.0, 0.0, 2.0]);
        assert_eq!(leading.sample(f32::NAN), Some((2, 1.0)));
        let trailing = Distribution1D::new([1.0, 3.0, 0.0, -2.0, f32::NAN]);
        assert_eq!(trailing.len(), 5);
        assert_eq!(trailing.sample(1.0), Some((1, 0.75)));
        assert_eq!(trailing.sample(0.9), Some((1, 0.75)));
        for nothing in [
            Distribution1D::new([]),
            Distribution1D::new([0.0, -1.0, f32::INFINITY]),
        ] {
            assert!(nothing.is_empty());
            assert_eq!(nothing.sample(0.5), None);
            assert_eq!(nothing.pmf(0), 0.0, "no NaN from 0/0");
        }
        assert_eq!(Distribution1D::new([0.0, 0.0]).len(), 2);
    }

    /// The continuous forms of (1, 0, 3) on [0,1) in thirds: density
    /// 3 · pmf = (0.75, 0, 2.25). u = 0.5 → target 2 in the last cell
    /// (cdf 1 → 4), a third of the way: x = (2 + 1/3)/3.
    #[test]
    fn continuous_values_by_hand() {
        let d = Distribution1D::new([1.0, 0.0, 3.0]);
        let (x, p, cell) = d.sample_continuous(0.5).unwrap();
        assert!((x - 7.0 / 9.0).abs() < 1e-6, "{x}");
        assert_eq!((p, cell), (2.25, 2));
        let (x, p, cell) = d.sample_continuous(0.125).unwrap();
        assert!((x - 1.0 / 6.0).abs() < 1e-6, "{x}");
        assert_eq!((p, cell), (0.75, 0));
        for (x, p) in [
            (0.1, 0.75),
            (0.5, 0.0),
            (0.9, 2.25),
            (1.0, 2.25),
            (-0.5, 0.75),
        ] {
            assert_eq!(d.pdf_continuous(x), p, "x = {x}");
        }
        assert_eq!(Distribution1D::new([]).pdf_continuous(0.5), 0.0);
        // x stays inside [0, 1) where (i + t)/n rounds up to 1 in f32
        // (u = 1 − 2⁻²⁴: x = 0.99999997 in f64) and at u = 1.
        for u in [1.0 - f32::EPSILON / 2.0, 1.0] {
            let (x, _, cell) = d.sample_continuous(u).unwrap();
            assert!(x < 1.0 && cell == 2, "u = {u}: x = {x}");
        }
    }

    /// The grid (1, 3 / 0, 4) (rows v, columns u), Σw = 8: p = w · 4/8,
    /// (0.5, 1.5 / 0, 2). u = (0.5, 0.5) picks row 1 at its start (row
    /// totals 4, 4) and the middle of its non-zero cell: (0.75, 0.5), p = 2.
    #[test]
    fn grid_values_by_hand() {
        let g = Distribution2D::new(2, 2, &[1.0, 3.0, 0.0, 4.0]);
        assert!(!g.is_empty());
        for (u, v, p) in [
            (0.25, 0.25, 0.5),
            (0.75, 0.25, 1.5),
            (0.25, 0.75, 0.0),
            (0.75, 0.75, 2.0),
            (1.0, 1.0, 2.0),
        ] {
            assert_eq!(g.pdf(glam::Vec2::new(u, v)), p, "({u}, {v})");
        }
        let (uv, p) = g.sample([0.5, 0.5]).unwrap();
        assert!((uv - glam::Vec2::new(0.75, 0.5)).length() < 1e-6, "{uv}");
        assert_eq!(p, 2.0);
        for empty in [
            Distribution2D::new(2, 2, &[0.0; 4]),
            Distribution2D::new(0, 0, &[]),
        ] {
            assert!(empty.is_empty());
            assert_eq!(empty.sample([0.5, 0.5]), None);
            assert_eq!(empty.pdf(glam::Vec2::new(0.5, 0.5)), 0.0);
        }
    }

    /// The guide table finds the item a full search finds: the first
    /// whose running sum (in f64, summed here by hand) exceeds u · Σw, for
    /// weights with zeros, one spike of 10⁶ (a sun in an environment
    /// map) and a run of equal weights, at random u and at every bucket
    /// edge k/n and the floats either side of it.
    #[test]
    fn guided_search_finds_the_first_cdf_above_u() {
        let mut rng = crate::stats::TestRng::new(11);
        let mut spiky: Vec<f32> = (0..97).map(|i| (i % 5) as f32 * 0.1).collect();
        spiky[40] = 1e6;
        let sets = [
            spiky,
            vec![1.0; 64],
            vec![0.0, 0.0, 2.0, 0.0, 1e-7, 3.0, 0.0],
            vec![5.0],
        ];
        for weights in sets {
            let d = Distribution1D::new(weights.iter().copied());
            let total: f64 = weights.iter().map(|&w| w as f64).sum();
            let expected = |u: f32| {
                let target = u as f64 * total;
                let mut sum = 0.0f64;
                for (i, &w) in weights.iter().enumerate() {
                    sum += w as f64;
                    if sum > target {
                        return i;
                    }
                }
                // u ≥ 1: the last item of positive weight.
                weights.iter().rposition(|&w| w > 0.0).unwrap()
            };
            let n = weights.len();
            let mut us: Vec<f32> = (0..2000).map(|_| rng.next_f32()).collect();
            for k in 0..=n {
                let edge = k as f32 / n as f32;
                us.extend([edge, edge.next_down().max(0.0), edge.next_up().min(1.0)]);
            }
            us.extend([0.0, 1.0]);
            for u in us {
                let (i, p) = d.sample(u).unwrap();
                assert_eq!(i, expected(u), "u = {u} over {n} weights");
                assert_eq!(p, d.pmf(i));
            }
        }
    }

    /// The 2-D density is w · W·H / Σw in every cell (computed here from
    /// the weights), for a grid of random weights with empty rows.
    #[test]
    fn grid_density_is_the_normalised_weight() {
        let mut rng = crate::stats::TestRng::new(3);
        let (w, h) = (7, 5);
        let weights: Vec<f32> = (0..w * h)
            .map(|i| {
                if i / w == 2 {
                    0.0
                } else {
                    rng.next_f32() * 4.0
                }
            })
            .collect();
        let d = Distribution2D::new(w, h, &weights);
        let total: f64 = weights.iter().map(|&x| x as f64).sum();
        for r in 0..h {
            for c in 0..w {
                let uv = glam::Vec2::new((c as f32 + 0.5) / w as f32, (r as f32 + 0.5) / h as f32);
                let expected = weights[r * w + c] as f64 * (w * h) as f64 / total;
                let got = d.pdf(uv) as f64;
                assert!(
                    (got - expected).abs() <= 1e-6 * expected.max(1.0),
                    "cell ({c}, {r}): {got} vs {expected}"
                );
            }
        }
    }

    #[test]
    fn frequencies_match_weights() {
        let d = Distribution1D::new([1.0, 0.0, 3.0, 4.0]);
        let n = 80_000;
        let mut counts = [0usize; 4];
        for k in 0..n {
            let (i, p) = d.sample((k as f32 + 0.5) / n as f32).unwrap();
            assert!((p - d.pmf(i)).abs() < 1e-7);
            counts[i] += 1;
        }
        assert_eq!(counts[1], 0);
        for (i, w) in [1.0, 0.0, 3.0, 4.0].iter().enumerate() {
            assert!((counts[i] as f32 / n as f32 - w / 8.0).abs() < 1e-3);
        }
        assert!(Distribution1D::new([0.0, 0.0]).sample(0.5).is_none());
    }

    #[test]
    fn continuous_2d_density_matches_histogram() {
        let w = [1.0, 0.0, 2.0, 5.0, 0.5, 0.5];
        let d = Distribution2D::new(3, 2, &w);
        let total: f32 = w.iter().sum();
        let mut rng = crate::stats::TestRng::new(5);
        let n = 200_000;
        let mut counts = [0usize; 6];
        for _ in 0..n {
            let (uv, p) = d.sample(rng.next_2d()).unwrap();
            assert!(
                (p - d.pdf(uv)).abs() < 1e-4 * p.max(1.0),
                "{p} vs {}",
                d.pdf(uv)
            );
            let (c, r) = ((uv.x * 3.0) as usize, (uv.y * 2.0) as usize);
            counts[r * 3 + c] += 1;
        }
        for (i, wi) in w.iter().enumerate() {
            let expect = wi / total;
            assert!(
                (counts[i] as f32 / n as f32 - expect).abs() < 5e-3,
                "cell {i}"
            );
            let uv = glam::Vec2::new(((i % 3) as f32 + 0.5) / 3.0, ((i / 3) as f32 + 0.5) / 2.0);
            assert!((d.pdf(uv) - expect * 6.0).abs() < 1e-5);
        }
    }
}
