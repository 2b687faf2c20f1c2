//! Triangles whose padded boxes are bitwise identical (one triangle
//! repeated, a mesh instanced many times at the same place) are grouped
//! before PLOC and put back after it.
//!
//! PLOC merges only nodes that are each other's nearest neighbour, and
//! among equal costs obvhs 0.4's search keeps the farthest candidate
//! ahead, so in a run of k identical boxes only the last pair agree: the
//! run loses about one node an iteration, while every iteration scans all
//! the nodes left. Building over 30,000 copies of one triangle took 40 s
//! (10,000: 4.3 s). A group goes to PLOC as one box instead, and comes
//! back as a balanced subtree of its members.

use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::bvh2::node::Bvh2Node;
use std::collections::HashMap;

/// Groups smaller than this go to PLOC as they are: k identical boxes
/// cost it about k iterations, cheap for a few.
const MIN_GROUP: usize = 16;

/// log2 of the buckets that count `n` boxes by hash, to find out cheaply
/// whether any box can be repeated [`MIN_GROUP`] times: about two buckets
/// a box, so that distinct boxes rarely crowd one (the table stays small
/// enough for the caches).
fn bucket_bits(n: usize) -> u32 {
    (n.next_power_of_two().trailing_zeros() + 1).clamp(10, 26)
}

/// The boxes PLOC is given, each standing for one or more primitives.
#[derive(Debug)]
pub(super) struct Grouped {
    /// One box per group (in the order of their first members), then
    /// every other primitive's.
    pub boxes: Vec<Aabb>,
    /// The primitives of `boxes[i]`: `members[starts[i]..starts[i + 1]]`.
    starts: Vec<u32>,
    members: Vec<u32>,
}

/// The box's bits: equal keys, identical boxes.
fn key(b: &Aabb) -> [u32; 6] {
    [
        b.min.x.to_bits(),
        b.min.y.to_bits(),
        b.min.z.to_bits(),
        b.max.x.to_bits(),
        b.max.y.to_bits(),
        b.max.z.to_bits(),
    ]
}

/// The counting table's bucket of `b`: the top `bits` of a hash of its
/// six words (three 64-bit products, then a multiply to mix them).
fn bucket(b: &Aabb, bits: u32) -> usize {
    let [a, c, d, e, f, g] = key(b).map(u64::from);
    let h = (a | c << 32).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (d | e << 32).wrapping_mul(0xBF58_476D_1CE4_E5B9)
        ^ (f | g << 32).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((h ^ h >> 29).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - bits)) as usize
}

/// The primitives of `boxes` grouped where at least [`MIN_GROUP`] share
/// one box; `None` when no box is repeated that often (one pass of
/// counting, the usual case).
pub(super) fn group_identical(boxes: &[Aabb]) -> Option<Grouped> {
    let bits = bucket_bits(boxes.len());
    let mut counts = vec![0u8; 1 << bits];
    let mut crowded = false;
    for b in boxes {
        let c = &mut counts[bucket(b, bits)];
        *c = c.saturating_add(1);
        crowded |= usize::from(*c) >= MIN_GROUP;
    }
    if !crowded {
        return None;
    }
    // The buckets are hashed again rather than kept from the count: a
    // bucket per box would cost every build memory and time for this rare
    // case.
    let mut by_box: HashMap<[u32; 6], Vec<u32>> = HashMap::new();
    for (i, b) in boxes.iter().enumerate() {
        if usize::from(counts[bucket(b, bits)]) >= MIN_GROUP {
            by_box.entry(key(b)).or_default().push(i as u32);
        }
    }
    let mut groups: Vec<Vec<u32>> = by_box
        .into_values()
        .filter(|m| m.len() >= MIN_GROUP)
        .collect();
    if groups.is_empty() {
        return None;
    }
    groups.sort_unstable_by_key(|m| m[0]);
    let mut grouped = vec![false; boxes.len()];
    let mut out = Grouped {
        boxes: Vec::with_capacity(boxes.len()),
        starts: vec![0],
        members: Vec::with_capacity(boxes.len()),
    };
    for g in &groups {
        out.boxes.push(boxes[g[0] as usize]);
        out.members.extend_from_slice(g);
        out.starts.push(out.members.len() as u32);
        for &i in g {
            grouped[i as usize] = true;
        }
    }
    for (i, b) in boxes.iter().enumerate() {
        if !grouped[i] {
            out.boxes.push(*b);
            out.members.push(i as u32);
            out.starts.push(out.members.len() as u32);
        }
    }
    Some(out)
}

impl Grouped {
    /// The primitives `boxes[i]` stands for.
    fn members_of(&self, i: u32) -> &[u32] {
        &self.members[self.starts[i as usize] as usize..self.starts[i as usize + 1] as usize]
    }

    /// `bvh`, built over [`Grouped::boxes`], with the primitives put back:
    /// each leaf lists the members of its boxes, and a leaf with more than
    /// `leaf_max` of them becomes a balanced subtree of leaves of at most
    /// `leaf_max` (`original` holds the primitives' boxes).
    pub fn expand(&self, bvh: &Bvh2, leaf_max: usize, original: &[Aabb]) -> Bvh2 {
        let mut nodes = vec![Bvh2Node::default()];
        let mut primitive_indices = Vec::with_capacity(self.members.len());
        // (node of `bvh`, its slot in `nodes`)
        let mut stack = vec![(0usize, 0usize)];
        let mut list = Vec::new();
        while let Some((old, slot)) = stack.pop() {
            let node = &bvh.nodes[old];
            if node.prim_count == 0 {
                let first = nodes.len();
                nodes.push(Bvh2Node::default());
                nodes.push(Bvh2Node::default());
                nodes[slot] = Bvh2Node::new(node.aabb, 0, first as u32);
                let child = node.first_index as usize;
                stack.push((child, first));
                stack.push((child + 1, first + 1));
                continue;
            }
            list.clear();
            let range = node.first_index as usize..(node.first_index + node.prim_count) as usize;
            for &p in &bvh.primitive_indices[range] {
                list.extend_from_slice(self.members_of(p));
            }
            balanced(
                &mut nodes,
                &mut primitive_indices,
                slot,
                &list,
                leaf_max,
                original,
            );
        }
        Bvh2 {
            nodes,
            primitive_indices,
            ..Default::default()
        }
    }
}

/// Writes at `slot` a balanced subtree over `prims` (halved until at most
/// `leaf_max` remain in a leaf), each node boxing its primitives.
fn balanced(
    nodes: &mut Vec<Bvh2Node>,
    primitive_indices: &mut Vec<u32>,
    slot: usize,
    prims: &[u32],
    leaf_max: usize,
    boxes: &[Aabb],
) {
    let mut stack = vec![(slot, prims)];
    while let Some((slot, prims)) = stack.pop() {
        let aabb = prims
            .iter()
            .map(|&p| boxes[p as usize])
            .reduce(|a, b| a.union(&b))
            .expect("a leaf has primitives");
        if prims.len() <= leaf_max {
            nodes[slot] = Bvh2Node::new(aabb, prims.len() as u32, primitive_indices.len() as u32);
            primitive_indices.extend_from_slice(prims);
            continue;
        }
        let first = nodes.len();
        nodes.push(Bvh2Node::default());
        nodes.push(Bvh2Node::default());
        nodes[slot] = Bvh2Node::new(aabb, 0, first as u32);
        let (left, right) = prims.split_at(prims.len() / 2);
        stack.push((first, left));
        stack.push((first + 1, right));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3A;

    fn unit_box(x: f32) -> Aabb {
        Aabb::new(Vec3A::new(x, 0.0, 0.0), Vec3A::new(x + 1.0, 1.0, 1.0))
    }

    /// Boxes 0..n at x = 0, 2, 4, …; then `copies` of the box at x = −5
    /// spread among them at every third index.
    fn boxes(n: usize, copies: usize) -> (Vec<Aabb>, Vec<u32>) {
        let mut out: Vec<Aabb> = (0..n).map(|i| unit_box(2.0 * i as f32)).collect();
        let mut at = Vec::new();
        for c in 0..copies {
            let i = 3 * c;
            out.insert(i, unit_box(-5.0));
            at.push(i as u32);
        }
        (out, at)
    }

    /// Two to four buckets a box (at least 2^10), so that distinct boxes
    /// crowd a bucket only by a very rare chance.
    #[test]
    fn counting_table_has_two_to_four_buckets_a_box() {
        for n in [1usize, 100, 1000, 1024, 1025, 998_000, 1 << 20] {
            let buckets = 1usize << bucket_bits(n);
            assert!(buckets >= (2 * n).max(1024), "{n}: {buckets}");
            assert!(buckets <= (4 * n).max(1024), "{n}: {buckets}");
        }
    }

    /// Distinct boxes on a regular 30³ grid (structured input, where a
    /// weak hash collides) spread over the buckets: none holds more than
    /// 6 (a uniform hash at 0.41 boxes a bucket puts 7 in some bucket of
    /// the table with a chance of about 2 %), so no bucket is crowded and
    /// the exact pass is skipped.
    #[test]
    fn distinct_boxes_spread_over_the_buckets() {
        let mut b = Vec::new();
        for x in 0..30 {
            for y in 0..30 {
                for z in 0..30 {
                    let lo = Vec3A::new(x as f32, y as f32, z as f32);
                    b.push(Aabb::new(lo, lo + Vec3A::ONE));
                }
            }
        }
        let bits = bucket_bits(b.len());
        let mut load = vec![0u32; 1 << bits];
        for x in &b {
            load[bucket(x, bits)] += 1;
        }
        let most = load.iter().max().copied().unwrap_or(0);
        assert!(most <= 6, "a bucket holds {most} distinct boxes");
        assert!(group_identical(&b).is_none());
    }

    #[test]
    fn no_group_below_the_threshold() {
        let (b, _) = boxes(100, MIN_GROUP - 1);
        assert!(group_identical(&b).is_none());
    }

    #[test]
    fn groups_exactly_the_repeated_box() {
        let (b, at) = boxes(100, 40);
        let g = group_identical(&b).expect("40 copies form a group");
        // One box for the group, then the 100 others in order.
        assert_eq!(g.boxes.len(), 101);
        assert_eq!(g.members_of(0), &at[..]);
        let others: Vec<u32> = (0..b.len() as u32).filter(|i| !at.contains(i)).collect();
        for (k, &i) in others.iter().enumerate() {
            assert_eq!(g.members_of(k as u32 + 1), &[i]);
            assert_eq!(key(&g.boxes[k + 1]), key(&b[i as usize]));
        }
        assert_eq!(key(&g.boxes[0]), key(&unit_box(-5.0)));
    }

    /// A leaf standing for a 40-member group becomes a subtree whose
    /// leaves hold at most `leaf_max`, every primitive once, each node
    /// boxing its subtree.
    #[test]
    fn expansion_keeps_every_primitive_once_in_small_leaves() {
        let (b, _) = boxes(100, 40);
        let g = group_identical(&b).unwrap();
        let bvh = obvhs::bvh2::builder::build_bvh2(
            &g.boxes,
            obvhs::BvhBuildParams::medium_build(),
            &mut std::time::Duration::default(),
        );
        let leaf_max = 8;
        let out = g.expand(&bvh, leaf_max, &b);
        let mut seen = vec![0; b.len()];
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = &out.nodes[n];
            if node.prim_count == 0 {
                let c = node.first_index as usize;
                for child in [c, c + 1] {
                    let inner = out.nodes[child].aabb;
                    assert_eq!(
                        node.aabb.union(&inner),
                        node.aabb,
                        "a child's box inside its parent's"
                    );
                    stack.push(child);
                }
            } else {
                assert!(node.prim_count as usize <= leaf_max);
                let f = node.first_index as usize;
                for &p in &out.primitive_indices[f..f + node.prim_count as usize] {
                    seen[p as usize] += 1;
                    assert_eq!(
                        node.aabb.union(&b[p as usize]),
                        node.aabb,
                        "a leaf boxes its primitives"
                    );
                }
            }
        }
        assert!(seen.iter().all(|&s| s == 1), "{seen:?}");
    }
}
