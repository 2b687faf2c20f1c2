//! Triangles of a glTF primitive from its vertex sequence (its indices, or
//! 0..n without), per the glTF 2.0 topology types:
//! - TRIANGLES: `(v₃ᵢ, v₃ᵢ₊₁, v₃ᵢ₊₂)`;
//! - TRIANGLE_STRIP: `(vᵢ, vᵢ₊₁₊ᵢ﹪₂, vᵢ₊₂₋ᵢ﹪₂)` for i = 0..n−3, which keeps
//!   every triangle's winding the first one's;
//! - TRIANGLE_FAN: `(vᵢ₊₁, vᵢ₊₂, v₀)` for i = 0..n−3.

/// The triangle topologies glTF defines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Topology {
    Triangles,
    Strip,
    Fan,
}

/// The triangles of `seq` under `topology`; `Err` with what is wrong when
/// the count does not fit (TRIANGLES: a multiple of 3; strips and fans: at
/// least 3).
pub(super) fn triangles(topology: Topology, seq: &[u32]) -> Result<Vec<[u32; 3]>, String> {
    let n = seq.len();
    match topology {
        Topology::Triangles => {
            if !n.is_multiple_of(3) {
                return Err(format!(
                    "{n} vertices is not a multiple of 3 (mode TRIANGLES)"
                ));
            }
            Ok(seq.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect())
        }
        Topology::Strip | Topology::Fan if n < 3 => Err(format!(
            "{n} vertices: a {} needs at least 3",
            if topology == Topology::Strip {
                "TRIANGLE_STRIP"
            } else {
                "TRIANGLE_FAN"
            }
        )),
        Topology::Strip => Ok((0..n - 2)
            .map(|i| [seq[i], seq[i + 1 + i % 2], seq[i + 2 - i % 2]])
            .collect()),
        Topology::Fan => Ok((0..n - 2)
            .map(|i| [seq[i + 1], seq[i + 2], seq[0]])
            .collect()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_alternate_to_keep_the_winding_and_fans_share_the_first_vertex() {
        let seq = [10, 11, 12, 13, 14];
        assert_eq!(
            triangles(Topology::Strip, &seq).unwrap(),
            [[10, 11, 12], [11, 13, 12], [12, 13, 14]]
        );
        assert_eq!(
            triangles(Topology::Fan, &seq).unwrap(),
            [[11, 12, 10], [12, 13, 10], [13, 14, 10]]
        );
        assert_eq!(
            triangles(Topology::Triangles, &seq[..3]).unwrap(),
            [[10, 11, 12]]
        );
        assert!(triangles(Topology::Triangles, &seq).is_err());
        assert!(triangles(Topology::Strip, &seq[..2]).is_err());
        assert!(triangles(Topology::Fan, &[]).is_err());
    }
}
