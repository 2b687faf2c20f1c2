//! The shooter choice of progressive refinement: a tournament tree over the
//! unshot powers, so "the patch with the most unshot power" costs O(1) to
//! read and O(log n) to update after a patch's unshot power changes (a
//! linear scan per shot would make the solve quadratic in the patches).
//! Ties go to the lower index, so the order of shots is reproducible.

/// A complete binary tree whose node k holds the index of the largest
/// value among its leaves.
pub(crate) struct MaxTree {
    values: Vec<f64>,
    size: usize,
    nodes: Vec<u32>,
}

const EMPTY: u32 = u32::MAX;

impl MaxTree {
    pub fn new(values: Vec<f64>) -> Self {
        let size = values.len().next_power_of_two().max(1);
        let mut nodes = vec![EMPTY; 2 * size];
        for i in 0..values.len() {
            nodes[size + i] = i as u32;
        }
        let mut tree = Self {
            values,
            size,
            nodes,
        };
        for k in (1..size).rev() {
            tree.nodes[k] = tree.better(tree.nodes[2 * k], tree.nodes[2 * k + 1]);
        }
        tree
    }

    fn better(&self, a: u32, b: u32) -> u32 {
        match (a, b) {
            (EMPTY, _) => b,
            (_, EMPTY) => a,
            // `>=` keeps the left (lower) index on ties.
            _ if self.values[a as usize] >= self.values[b as usize] => a,
            _ => b,
        }
    }

    /// The index of the largest value, and the value.
    pub fn max(&self) -> Option<(usize, f64)> {
        let i = self.nodes[1];
        (i != EMPTY).then(|| (i as usize, self.values[i as usize]))
    }

    pub fn set(&mut self, i: usize, value: f64) {
        self.values[i] = value;
        let mut k = (self.size + i) / 2;
        while k >= 1 {
            self.nodes[k] = self.better(self.nodes[2 * k], self.nodes[2 * k + 1]);
            k /= 2;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tracks_the_maximum_through_updates() {
        let mut t = MaxTree::new(vec![3.0, 1.0, 4.0, 1.0, 5.0]);
        assert_eq!(t.max(), Some((4, 5.0)));
        t.set(4, 0.0);
        assert_eq!(t.max(), Some((2, 4.0)));
        t.set(1, 4.0); // a tie: the lower index wins
        assert_eq!(t.max(), Some((1, 4.0)));
        t.set(1, 0.0);
        t.set(2, 0.0);
        t.set(0, 0.0);
        assert_eq!(t.max(), Some((3, 1.0)));
        let one = MaxTree::new(vec![2.0]);
        assert_eq!(one.max(), Some((0, 2.0)));
        assert_eq!(MaxTree::new(Vec::new()).max(), None);
    }
}
