//! The binary BVH collapsed into the 8-wide tree with the least SAH cost
//! (Ylitie et al. 2017, "Efficient incoherent ray traversal on GPUs
//! through compressed wide BVHs", §3.1): dynamic programming over the
//! binary nodes decides which become wide nodes, which become leaves of at
//! most [`LEAF_MAX`] triangles, and which are opened so that their
//! children take slots of the node above.
//!
//! The cost of a tree is the surface area heuristic: a ray through the
//! root visits a node or leaf with the probability area(box)/area(root),
//! and each visit costs [`NODE_COST`] or [`leaf_cost`]. For binary node
//! n, cost(n, j) is the least cost of its subtree made into at most j
//! slots:
//!
//!   cost(n, 1) = min(leaf(n), A(n)·NODE_COST + spread(n, 8)),
//!   cost(n, j) = min(cost(n, 1), spread(n, j)),
//!   spread(n, j) = min over k in 1..j of cost(left, k) + cost(right, j − k),
//!
//! with leaf(n) = A(n)·leaf_cost(triangles) where n holds at most
//! [`LEAF_MAX`] triangles, else ∞. On the 1M-triangle bench mesh's
//! random rays it visits 7 % fewer nodes than opening the largest child
//! until a node is full (Wald et al. 2008), the collapse it replaces.

use super::block::LANES;
use super::wide::{LEAF_MAX, Node8, WIDTH, Wide, leaf_code};
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use std::cmp::Ordering;

/// Cost of visiting a wide node: one 8-lane box test.
const NODE_COST: f32 = 1.0;

/// Cost of visiting a leaf of `triangles` triangles: one 8-lane triangle
/// test either way, but a leaf of two blocks reads five cache lines where
/// one block reads three.
fn leaf_cost(triangles: u32) -> f32 {
    if triangles as usize <= LANES {
        1.0
    } else {
        1.3
    }
}

/// The dynamic program's table, indexed by binary node.
struct Plan {
    /// `cost[n][j − 1]`: cost(n, j) above.
    cost: Vec<[f32; WIDTH]>,
    /// `choice[n][j − 1]`: 0 where n takes one slot, else the k of
    /// spread(n, j): k slots for the left child, j − k for the right.
    choice: Vec<[u8; WIDTH]>,
    /// The k of spread(n, 8), for n made a wide node.
    node_split: Vec<u8>,
    /// Whether n, taking one slot, is a leaf (else a wide node).
    leaf: Vec<bool>,
    /// Triangles under n.
    triangles: Vec<u32>,
    /// 1 / the root's area: areas enter the table relative to the root's,
    /// so that no cost overflows however large the scene.
    root_scale: f64,
}

impl Plan {
    /// Fills the table, children before parents (no recursion: a binary
    /// tree can be deep).
    fn new(bvh2: &Bvh2) -> Self {
        let count = bvh2.nodes.len();
        let mut plan = Plan {
            cost: vec![[0.0; WIDTH]; count],
            choice: vec![[0; WIDTH]; count],
            node_split: vec![0; count],
            leaf: vec![false; count],
            triangles: vec![0; count],
            root_scale: 1.0,
        };
        let root = area(&bvh2.nodes[0].aabb);
        if root > 0.0 && root.is_finite() {
            plan.root_scale = 1.0 / root;
        }
        // Preorder; reversed, each node comes after its children.
        let mut order = Vec::with_capacity(count);
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            order.push(n);
            let node = &bvh2.nodes[n];
            if !node.is_leaf() {
                let first = node.first_index as usize;
                stack.extend([first, first + 1]);
            }
        }
        for &n in order.iter().rev() {
            plan.solve(bvh2, n);
        }
        plan
    }

    /// Row `n` of the table, from its children's rows.
    fn solve(&mut self, bvh2: &Bvh2, n: usize) {
        let node = &bvh2.nodes[n];
        let area = (area(&node.aabb) * self.root_scale) as f32;
        if node.is_leaf() {
            self.triangles[n] = node.prim_count;
            self.cost[n] = [area * leaf_cost(node.prim_count); WIDTH];
            self.leaf[n] = true;
            return;
        }
        let (l, r) = (node.first_index as usize, node.first_index as usize + 1);
        let triangles = self.triangles[l] + self.triangles[r];
        self.triangles[n] = triangles;
        // spread[j] and its k, for j = 2..=8 slots.
        let mut spread = [f32::INFINITY; WIDTH + 1];
        // (k = 1 is a valid split even where every cost is ∞ or NaN.)
        let mut split = [1u8; WIDTH + 1];
        for j in 2..=WIDTH {
            for k in 1..j {
                let c = self.cost[l][k - 1] + self.cost[r][j - k - 1];
                if c < spread[j] {
                    spread[j] = c;
                    split[j] = k as u8;
                }
            }
        }
        let inner = area * NODE_COST + spread[WIDTH];
        let fits = triangles <= LEAF_MAX;
        let leaf = if fits {
            area * leaf_cost(triangles)
        } else {
            f32::INFINITY
        };
        let one = inner.min(leaf);
        // A leaf only where it fits, whatever the costs (∞ or NaN from
        // degenerate boxes would otherwise make one of any size).
        self.leaf[n] = fits && inner.partial_cmp(&leaf) != Some(Ordering::Less);
        self.node_split[n] = split[WIDTH];
        for j in 1..=WIDTH {
            let (c, k) = if spread[j] < one {
                (spread[j], split[j])
            } else {
                (one, 0)
            };
            self.cost[n][j - 1] = c;
            self.choice[n][j - 1] = k;
        }
    }

    /// Appends to `out[..*len]` the binary nodes that subtree `n` becomes
    /// as at most `j` slots (the recursion is at most [`WIDTH`] deep: j
    /// shrinks).
    fn slots(&self, bvh2: &Bvh2, n: usize, j: usize, out: &mut [usize; WIDTH], len: &mut usize) {
        match self.choice[n][j - 1] as usize {
            0 => {
                out[*len] = n;
                *len += 1;
            }
            k => {
                let first = bvh2.nodes[n].first_index as usize;
                self.slots(bvh2, first, k, out, len);
                self.slots(bvh2, first + 1, j - k, out, len);
            }
        }
    }
}

/// Half the surface area of `b`, in f64: f32 overflows for boxes
/// larger than about 10¹⁹ on a side.
pub(super) fn area(b: &Aabb) -> f64 {
    let d = (b.max - b.min).as_dvec3();
    (d.x + d.y) * d.z + d.x * d.y
}

/// Collapses `bvh2` (leaves of at most [`LEAF_MAX`] primitives) into the
/// 8-wide tree of least SAH cost. Its leaf codes' start fields index the
/// returned primitive list, in which each leaf's primitives are
/// consecutive.
pub(super) fn collapse(bvh2: &Bvh2) -> (Wide, Vec<u32>) {
    let plan = Plan::new(bvh2);
    let mut out = Collapse {
        bvh2,
        plan: &plan,
        wide: Wide {
            nodes: Vec::with_capacity(bvh2.nodes.len() / 4 + 1),
            depth: 0,
        },
        primitives: Vec::with_capacity(bvh2.primitive_indices.len()),
        stack: Vec::new(),
    };
    if plan.leaf[0] {
        let mut node = Node8::EMPTY;
        let code = out.leaf(0);
        node.set_slot(0, &bvh2.nodes[0].aabb, code);
        out.wide.nodes.push(node);
        out.wide.depth = 1;
    } else {
        out.wide.depth = out.node(0);
    }
    (out.wide, out.primitives)
}

/// The collapse's output while the plan is carried out.
struct Collapse<'a> {
    bvh2: &'a Bvh2,
    plan: &'a Plan,
    wide: Wide,
    primitives: Vec<u32>,
    /// [`Collapse::leaf`]'s walk, kept between leaves.
    stack: Vec<usize>,
}

impl Collapse<'_> {
    /// Adds the wide node made of binary node `n` and its subtree; returns
    /// the subtree's depth in wide nodes.
    fn node(&mut self, n: usize) -> usize {
        let index = self.wide.nodes.len();
        self.wide.nodes.push(Node8::EMPTY);
        let first = self.bvh2.nodes[n].first_index as usize;
        let k = self.plan.node_split[n] as usize;
        let (mut slots, mut len) = ([0; WIDTH], 0);
        self.plan.slots(self.bvh2, first, k, &mut slots, &mut len);
        self.plan
            .slots(self.bvh2, first + 1, WIDTH - k, &mut slots, &mut len);
        let mut depth = 1;
        for (slot, &s) in slots[..len].iter().enumerate() {
            let code = if self.plan.leaf[s] {
                self.leaf(s)
            } else {
                let child = self.wide.nodes.len() as u32;
                depth = depth.max(1 + self.node(s));
                child
            };
            self.wide.nodes[index].set_slot(slot, &self.bvh2.nodes[s].aabb, code);
        }
        depth
    }

    /// The leaf code of binary subtree `n` made one leaf: its primitives
    /// appended to the list.
    fn leaf(&mut self, n: usize) -> u32 {
        let start = self.primitives.len();
        self.stack.push(n);
        while let Some(m) = self.stack.pop() {
            let node = &self.bvh2.nodes[m];
            let first = node.first_index as usize;
            if node.is_leaf() {
                let range = first..first + node.prim_count as usize;
                self.primitives
                    .extend_from_slice(&self.bvh2.primitive_indices[range]);
            } else {
                self.stack.extend([first + 1, first]);
            }
        }
        leaf_code(start as u32, (self.primitives.len() - start) as u32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::wide::{LEAF_BIT, leaf_parts};
    use obvhs::BvhBuildParams;
    use std::time::Duration;

    /// Random boxes, some large and some small, clustered so that the
    /// binary tree has subtrees of different shapes.
    fn random_boxes(count: usize, seed: u32, scale: f32) -> Vec<Aabb> {
        let mut s = penumbra_shading::sampling::Sampler::new(0, 0, 0, seed);
        (0..count)
            .map(|i| {
                let [a, b] = s.next_2d();
                let [c, d] = s.next_2d();
                let cluster = (i % 3) as f32 * 4.0;
                let lo = glam::Vec3A::new(a + cluster, b, c) * 4.0;
                let size = 0.05 + d * d * 2.0;
                let hi = lo + glam::Vec3A::new(size, size * 0.5, size * 2.0);
                Aabb::new(lo * scale, hi * scale)
            })
            .collect()
    }

    fn binary(count: usize, seed: u32, leaf_max: u32, scale: f32) -> Bvh2 {
        let mut params = BvhBuildParams::medium_build();
        params.max_prims_per_leaf = leaf_max;
        obvhs::bvh2::builder::build_bvh2(
            &random_boxes(count, seed, scale),
            params,
            &mut Duration::default(),
        )
    }

    /// The SAH cost of a wide tree, from its own boxes: each node costs
    /// `NODE_COST` times the area of the union of its slots, each leaf its
    /// `leaf_cost` times its box's area.
    fn wide_cost(wide: &Wide) -> f64 {
        let area = box_area;
        let mut cost = 0.0;
        for (n, node) in wide.nodes.iter().enumerate() {
            let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
            for s in (0..WIDTH).filter(|&s| node.used(s)) {
                let (a, b) = node.slot_box(s);
                for k in 0..3 {
                    lo[k] = lo[k].min(a[k]);
                    hi[k] = hi[k].max(b[k]);
                }
                let code = node.child[s];
                if code & LEAF_BIT != 0 {
                    cost += area(a, b) * f64::from(leaf_cost(leaf_parts(code).1 as u32));
                }
            }
            // The root node of a one-leaf tree is only a holder.
            let holder = n == 0 && node.child[0] & LEAF_BIT != 0 && !node.used(1);
            if !holder {
                cost += area(lo, hi) * f64::from(NODE_COST);
            }
        }
        cost
    }

    /// Half the surface area of the box from `lo` to `hi`.
    fn box_area(lo: [f32; 3], hi: [f32; 3]) -> f64 {
        let d = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]].map(f64::from);
        (d[0] + d[1]) * d[2] + d[0] * d[1]
    }

    /// Every way of making binary subtree `n` into slots: (slot count,
    /// cost of those slots), by enumeration, with no table.
    fn all_cuts(bvh2: &Bvh2, n: usize) -> Vec<(usize, f64)> {
        let node = &bvh2.nodes[n];
        let area = box_area(node.aabb.min.into(), node.aabb.max.into());
        let mut one = f64::INFINITY;
        let triangles = count_under(bvh2, n);
        if triangles <= LEAF_MAX {
            one = area * f64::from(leaf_cost(triangles));
        }
        let mut cuts = vec![];
        if !node.is_leaf() {
            let first = node.first_index as usize;
            let (l, r) = (all_cuts(bvh2, first), all_cuts(bvh2, first + 1));
            for &(a, ca) in &l {
                for &(b, cb) in &r {
                    if a + b <= WIDTH {
                        cuts.push((a + b, ca + cb));
                    }
                }
            }
            // n as a wide node over any cut of at least two slots.
            let best = cuts.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
            one = one.min(area * f64::from(NODE_COST) + best);
        }
        cuts.push((1, one));
        cuts
    }

    fn count_under(bvh2: &Bvh2, n: usize) -> u32 {
        let node = &bvh2.nodes[n];
        if node.is_leaf() {
            node.prim_count
        } else {
            let first = node.first_index as usize;
            count_under(bvh2, first) + count_under(bvh2, first + 1)
        }
    }

    /// On small trees, the collapsed tree's SAH cost (measured on the wide
    /// nodes it made) equals the least over every way of collapsing the
    /// binary tree (enumerated), and each primitive is in one leaf.
    #[test]
    fn collapse_reaches_the_least_sah_cost_of_any_collapse() {
        // The last case's areas (about 10⁵⁰) overflow f32.
        let cases = [
            (12, 1, 1, 1.0),
            (20, 2, 1, 1.0),
            (30, 3, 2, 1.0),
            (40, 4, 3, 1.0),
            (5, 5, 1, 1.0),
            (20, 6, 1, 1e25),
        ];
        for (count, seed, leaf_max, scale) in cases {
            let bvh2 = binary(count, seed, leaf_max, scale);
            let (wide, primitives) = collapse(&bvh2);
            let least = all_cuts(&bvh2, 0)
                .iter()
                .filter(|c| c.0 == 1)
                .map(|c| c.1)
                .fold(f64::INFINITY, f64::min);
            let got = wide_cost(&wide);
            assert!(
                (got - least).abs() <= 1e-4 * least,
                "{count} boxes, seed {seed}: cost {got} against the least {least}"
            );
            let mut sorted = primitives.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..count as u32).collect::<Vec<_>>());
            assert!(
                wide.leaf_counts()
                    .all(|c| (1..=LEAF_MAX as usize).contains(&c))
            );
        }
    }
}
