//! Discrete 1-D distribution sampled by inverting its CDF.

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
}
