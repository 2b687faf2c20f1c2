//! The 8-wide BVH: uncompressed fp32 nodes in structure-of-arrays form, so
//! that one ray tests all eight child boxes with one 8-lane instruction per
//! plane (Fuetterling et al. 2017, "Accelerated single ray tracing for wide
//! vector units"; the layout of tinybvh's `BVH8_CPU`). It is made by
//! collapsing a binary BVH (obvhs: PLOC + reinsertion + SAH leaf collapse)
//! with the least SAH cost (`collapse.rs`).

use super::block::{LANES, LEAF_LANES};
use obvhs::aabb::Aabb;

/// Children per node.
pub(super) const WIDTH: usize = 8;

/// Largest leaf, in triangles: two blocks, one 8-lane test.
pub(super) const LEAF_MAX: u32 = LEAF_LANES as u32;

/// A slot's code: an inner node's index, or a leaf: this bit, its triangle
/// count in [`COUNT_SHIFT`].., and its triangles' block (`block.rs`) below.
/// As `collapse.rs` makes them, the low bits are the leaf's first index
/// into the collapse's primitive list instead.
pub(super) const LEAF_BIT: u32 = 1 << 31;
pub(super) const COUNT_SHIFT: u32 = 27;
const START_MASK: u32 = (1 << COUNT_SHIFT) - 1;

/// Most triangles a BVH can index (the leaf code's start field).
pub(super) const MAX_TRIANGLES: usize = START_MASK as usize;

/// One node: the boxes of up to eight children and what each one is.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(super) struct Node8 {
    /// Planes in the order min x, max x, min y, max y, min z, max z; a slot
    /// without a child has min = +∞ and max = −∞, which no ray enters.
    pub bounds: [[f32; WIDTH]; 6],
    /// Per slot: an inner node's index or a leaf code (`LEAF_BIT`).
    pub child: [u32; WIDTH],
}

/// Seven boxes (min, max corners) of several sizes and places around the
/// origin, one of them flat (z = 0), for the box tests' tests: with
/// [`Node8::with_boxes`], a node whose eighth slot is empty.
#[cfg(test)]
pub(super) const TEST_BOXES: [([f32; 3], [f32; 3]); 7] = [
    ([1.0; 3], [2.0; 3]),
    ([-3.0, -0.5, -0.5], [-2.0, 0.5, 0.5]),
    ([-1.0; 3], [1.0; 3]),
    ([1.0, 5.0, 1.0], [2.0, 6.0, 2.0]),
    ([4.0; 3], [5.0; 3]),
    ([-6.0, -6.0, 0.0], [6.0, 6.0, 0.0]),
    ([-2.0, 1.0, -4.0], [-1.0, 3.0, -3.0]),
];

impl Node8 {
    pub const EMPTY: Node8 = Node8 {
        bounds: [
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
        ],
        child: [0; WIDTH],
    };

    /// The box of slot `i`.
    pub fn slot_box(&self, i: usize) -> ([f32; 3], [f32; 3]) {
        let b = &self.bounds;
        ([b[0][i], b[2][i], b[4][i]], [b[1][i], b[3][i], b[5][i]])
    }

    pub fn set_slot(&mut self, i: usize, b: &Aabb, child: u32) {
        for a in 0..3 {
            self.bounds[2 * a][i] = b.min[a];
            self.bounds[2 * a + 1][i] = b.max[a];
        }
        self.child[i] = child;
    }

    /// Slots that hold a child.
    pub fn used(&self, i: usize) -> bool {
        self.bounds[0][i] <= self.bounds[1][i]
    }

    /// A node whose first slots hold `boxes` (min, max corners) and whose
    /// other slots are empty (for the box tests' tests).
    #[cfg(test)]
    pub fn with_boxes(boxes: &[([f32; 3], [f32; 3])]) -> Node8 {
        let mut n = Node8::EMPTY;
        for (slot, (lo, hi)) in boxes.iter().enumerate() {
            for a in 0..3 {
                n.bounds[2 * a][slot] = lo[a];
                n.bounds[2 * a + 1][slot] = hi[a];
            }
        }
        n
    }
}

/// A leaf code for `count` triangles at `start` (a block, or while
/// collapsing a first primitive index).
pub(super) fn leaf_code(start: u32, count: u32) -> u32 {
    debug_assert!((1..=LEAF_MAX).contains(&count) && start <= START_MASK);
    LEAF_BIT | (count << COUNT_SHIFT) | start
}

/// The start field (block) and triangle count of a leaf code.
#[inline(always)]
pub(super) fn leaf_parts(code: u32) -> (usize, usize) {
    (
        (code & START_MASK) as usize,
        ((code & !LEAF_BIT) >> COUNT_SHIFT) as usize,
    )
}

/// The triangle slots of a leaf code: lanes 0..count of its block, slot
/// `LANES · block + lane` in leaf order.
#[inline(always)]
pub(super) fn leaf_range(code: u32) -> std::ops::Range<usize> {
    let (block, count) = leaf_parts(code);
    let start = block * LANES;
    start..start + count
}

/// The 8-wide tree: `nodes[0]` is the root.
#[derive(Debug, Default)]
pub(super) struct Wide {
    pub nodes: Vec<Node8>,
    /// Most nodes on a root-to-leaf path (the traversal stack's bound).
    pub depth: usize,
}

impl Wide {
    /// The triangle count of each leaf, in the order
    /// [`Wide::renumber_leaves`] visits them.
    pub fn leaf_counts(&self) -> impl Iterator<Item = usize> + '_ {
        self.nodes
            .iter()
            .flat_map(|node| node.child)
            .filter(|code| code & LEAF_BIT != 0)
            .map(|code| leaf_parts(code).1)
    }

    /// Gives each leaf, in node order, the start field `start(first,
    /// count)` in place of its first primitive index.
    pub fn renumber_leaves(&mut self, mut start: impl FnMut(usize, usize) -> u32) {
        for node in &mut self.nodes {
            for slot in 0..WIDTH {
                let code = node.child[slot];
                if code & LEAF_BIT != 0 {
                    let (first, count) = leaf_parts(code);
                    node.child[slot] = leaf_code(start(first, count), count as u32);
                }
            }
        }
    }
}
