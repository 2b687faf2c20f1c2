//! Dilation: every texel that was not baked (padding around charts, and
//! texels found inside geometry) takes the mean of its already-filled
//! neighbours, ring by ring outwards from the baked texels (a multi-source
//! breadth-first fill over the 8-neighbourhood), so a bilinear lookup at a
//! chart's border reads the chart's own values and never an unbaked texel.
//! Charts lie at least two paddings apart, so a texel within one padding of
//! a chart is filled from that chart alone.

use penumbra_image::Image;

/// How a texel of a page got its value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TexelState {
    /// Baked: covered by a triangle and valid.
    Baked,
    /// Covered, but inside geometry: filled by dilation.
    Invalid,
    /// Not covered (padding, free space): filled by dilation.
    Empty,
}

impl TexelState {
    /// The value of the `coverage` layer of the EXR pages.
    pub fn coverage(self) -> f32 {
        match self {
            TexelState::Baked => 1.0,
            TexelState::Invalid => 0.5,
            TexelState::Empty => 0.0,
        }
    }
}

/// Fills every non-[`TexelState::Baked`] texel of `image` reachable from a
/// baked one (see the module docs); returns how many were filled.
pub fn dilate(image: &mut Image, states: &[TexelState]) -> usize {
    let (w, h) = (image.width as i64, image.height as i64);
    let mut filled: Vec<bool> = states.iter().map(|&s| s == TexelState::Baked).collect();
    let mut frontier: Vec<usize> = (0..filled.len()).filter(|&i| filled[i]).collect();
    let mut count = 0;
    let neighbours = |i: usize| {
        let (x, y) = ((i as i64) % w, (i as i64) / w);
        (-1..=1i64)
            .flat_map(move |dy| (-1..=1i64).map(move |dx| (x + dx, y + dy)))
            .filter(move |&(nx, ny)| (nx, ny) != (x, y) && nx >= 0 && ny >= 0 && nx < w && ny < h)
            .map(move |(nx, ny)| (ny * w + nx) as usize)
    };
    while !frontier.is_empty() {
        // The next ring: unfilled texels next to the current one.
        let mut ring: Vec<usize> = frontier
            .iter()
            .flat_map(|&i| neighbours(i))
            .filter(|&j| !filled[j])
            .collect();
        ring.sort_unstable();
        ring.dedup();
        // Each takes the mean of its neighbours filled before this ring.
        let values: Vec<_> = ring
            .iter()
            .map(|&j| {
                let (sum, n) = neighbours(j)
                    .filter(|&k| filled[k])
                    .fold((glam::Vec3::ZERO, 0u32), |(s, n), k| {
                        (s + image.pixels[k], n + 1)
                    });
                sum / n.max(1) as f32
            })
            .collect();
        for (&j, v) in ring.iter().zip(values) {
            image.pixels[j] = v;
            filled[j] = true;
        }
        count += ring.len();
        frontier = ring;
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn fills_rings_from_the_nearest_baked_texels() {
        // Two baked texels, 5 apart on a 7×1 row: each half takes its side.
        let mut img = Image::new(7, 1);
        img.pixels[1] = Vec3::splat(1.0);
        img.pixels[5] = Vec3::splat(3.0);
        let mut states = vec![TexelState::Empty; 7];
        states[1] = TexelState::Baked;
        states[5] = TexelState::Baked;
        states[6] = TexelState::Invalid;
        img.pixels[6] = Vec3::splat(-9.0); // an invalid value is replaced
        assert_eq!(dilate(&mut img, &states), 5);
        let xs: Vec<f32> = img.pixels.iter().map(|p| p.x).collect();
        // Texel 3 is equally far from both: the mean of its two neighbours.
        assert_eq!(xs, vec![1.0, 1.0, 1.0, 2.0, 3.0, 3.0, 3.0]);
    }

    #[test]
    fn diagonal_neighbours_count() {
        let mut img = Image::new(3, 3);
        img.pixels[0] = Vec3::ONE;
        let mut states = vec![TexelState::Empty; 9];
        states[0] = TexelState::Baked;
        dilate(&mut img, &states);
        assert!(img.pixels.iter().all(|&p| p == Vec3::ONE));
    }
}
