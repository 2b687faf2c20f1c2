//! Piecewise-constant distributions sampled by inverting their CDFs: a
//! discrete / 1-D one (light selection, rows of an image) and a 2-D one over
//! [0,1)² (environment-map importance sampling).

/// Piecewise-constant discrete distribution over `n` items with weights w_i:
/// p(i) = w_i / Σw.
#[derive(Clone, Debug, Default)]
pub struct Distribution1D {
    cdf: Vec<f64>,
    total: f64,
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
        Self { cdf, total }
    }

    pub fn is_empty(&self) -> bool {
        self.total <= 0.0
    }

    pub fn len(&self) -> usize {
        self.cdf.len()
    }

    /// Probability of item `i`.
    pub fn pmf(&self, i: usize) -> f32 {
        if self.total <= 0.0 || i >= self.cdf.len() {
            return 0.0;
        }
        let prev = if i == 0 { 0.0 } else { self.cdf[i - 1] };
        ((self.cdf[i] - prev) / self.total) as f32
    }

    /// Item for `u` ∈ [0,1), with its probability. `None` if all weights are 0.
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        if self.total <= 0.0 {
            return None;
        }
        let target = u as f64 * self.total;
        // First index whose cdf exceeds the target (skips zero-weight items).
        let i = self
            .cdf
            .partition_point(|&c| c <= target)
            .min(self.cdf.len() - 1);
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
        Self { rows, marginal }
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
        let h = self.rows.len();
        if h == 0 || self.marginal.is_empty() {
            return 0.0;
        }
        let row = ((uv.y.clamp(0.0, 1.0) * h as f32) as usize).min(h - 1);
        self.marginal.pdf_continuous(uv.y) * self.rows[row].pdf_continuous(uv.x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
