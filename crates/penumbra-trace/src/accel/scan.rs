//! Every triangle of a tiny scene tested against one ray, sixteen
//! triangles per AVX-512 instruction, without a tree: for scenes of at
//! most [`MAX_TRIANGLES`] triangles (a Cornell box has 32), where a tree
//! walk costs more in branches and setup than the tests it saves.
//!
//! Inside a scalar path loop such a scan is no faster than the tree walk,
//! which the next step waits for (measured on 2026-12-06); it pays where
//! many independent rays are in flight, as in the wavefront path tracer
//! (`integrator/wavefront.rs`), whose lanes' scans overlap.
//!
//! The test is the watertight one of `watertight.rs` (Woop et al. 2013)
//! with the same operations per triangle; lanes whose edge functions are
//! 0 take that module's scalar test with its f64 fallback. Of equal
//! distances the lowest triangle index wins.
//!
//! One of the crate's modules with `unsafe` code: its AVX-512 intrinsics.
#![allow(unsafe_code)]
// Lane loops index several structure-of-arrays fields by lane: the form
// that vectorises plainly.
#![allow(clippy::needless_range_loop)]

use super::watertight::{TriangleHit, WatertightRay};
use glam::{Vec3, Vec3A};

/// Triangles per chunk: one 16-lane register.
const LANES: usize = 16;

/// The largest scene the scan takes.
pub const MAX_TRIANGLES: usize = 64;

type Lanes = [f32; LANES];

/// [`LANES`] triangles in structure-of-arrays form: corners
/// (`[corner][axis][lane]`), unit front normals, whether rays that cull
/// back faces pass through their back, and which lanes hold a triangle.
#[derive(Clone, Copy, Debug)]
struct Chunk {
    corners: [[Lanes; 3]; 3],
    normal: [Lanes; 3],
    culls: [bool; LANES],
    used: [bool; LANES],
}

/// The scene's triangles in chunks.
#[derive(Clone, Debug)]
pub struct TriangleScan {
    chunks: Vec<Chunk>,
}

/// The watertight test's quantities of a chunk's triangles for one ray.
struct Edges {
    u: Lanes,
    v: Lanes,
    w: Lanes,
    t_scaled: Lanes,
    det: Lanes,
    /// Lanes holding a triangle whose edge functions include a 0.
    zero: [bool; LANES],
}

impl TriangleScan {
    /// The scan of `triangles` (world-space corners), with their unit front
    /// normals and whether each culls back faces; `None` beyond
    /// [`MAX_TRIANGLES`].
    pub fn new(triangles: &[[Vec3; 3]], normals: &[Vec3], culls: &[bool]) -> Option<Self> {
        if triangles.len() > MAX_TRIANGLES {
            return None;
        }
        let mut chunks = Vec::new();
        for (k, corners) in triangles.iter().enumerate() {
            if k % LANES == 0 {
                chunks.push(Chunk {
                    corners: [[[0.0; LANES]; 3]; 3],
                    normal: [[0.0; LANES]; 3],
                    culls: [false; LANES],
                    used: [false; LANES],
                });
            }
            let chunk = chunks.last_mut().expect("pushed above");
            let lane = k % LANES;
            for (c, p) in corners.iter().enumerate() {
                for a in 0..3 {
                    chunk.corners[c][a][lane] = p[a];
                }
            }
            for a in 0..3 {
                chunk.normal[a][lane] = normals[k][a];
            }
            chunk.culls[lane] = culls[k];
            chunk.used[lane] = true;
        }
        Some(TriangleScan { chunks })
    }

    /// Triangle `lane` of `chunk`.
    fn triangle(chunk: &Chunk, lane: usize) -> [Vec3A; 3] {
        [0, 1, 2].map(|c| {
            Vec3A::new(
                chunk.corners[c][0][lane],
                chunk.corners[c][1][lane],
                chunk.corners[c][2][lane],
            )
        })
    }

    /// The edge functions and scaled distances of a chunk's triangles for
    /// `ray`, with the f64 fallback's lanes done by the scalar test.
    #[inline(always)]
    fn edges(chunk: &Chunk, ray: &WatertightRay, tmax: f32) -> Edges {
        let [kx, ky, kz] = ray.permutation();
        let [ox, oy, oz] = ray.origin_permuted();
        let [sx, sy, sz] = ray.shear();
        let mut e = Edges {
            u: [0.0; LANES],
            v: [0.0; LANES],
            w: [0.0; LANES],
            t_scaled: [0.0; LANES],
            det: [0.0; LANES],
            zero: [false; LANES],
        };
        let [p0, p1, p2] = &chunk.corners;
        for l in 0..LANES {
            // The sheared corners, as `WatertightRay::intersect_a`.
            let (az, bz, cz) = (p0[kz][l] - oz, p1[kz][l] - oz, p2[kz][l] - oz);
            let ax = (p0[kx][l] - ox) - sx * az;
            let ay = (p0[ky][l] - oy) - sy * az;
            let bx = (p1[kx][l] - ox) - sx * bz;
            let by = (p1[ky][l] - oy) - sy * bz;
            let cx = (p2[kx][l] - ox) - sx * cz;
            let cy = (p2[ky][l] - oy) - sy * cz;
            let (az, bz, cz) = (sz * az, sz * bz, sz * cz);
            let u = cx * by - cy * bx;
            let v = ax * cy - ay * cx;
            let w = bx * ay - by * ax;
            e.zero[l] = ((u == 0.0) | (v == 0.0) | (w == 0.0)) & chunk.used[l];
            e.u[l] = u;
            e.v[l] = v;
            e.w[l] = w;
            e.t_scaled[l] = u * az + v * bz + w * cz;
            e.det[l] = u + v + w;
        }
        if !e.zero.iter().any(|&z| z) {
            return e;
        }
        for l in (0..LANES).filter(|&l| e.zero[l]) {
            let [a, b, c] = Self::triangle(chunk, l);
            // The scalar test decides the lane: a hit as edge functions
            // (1, b1, b2) with det 1 (so t_scaled = t), a miss as det 0.
            (e.u[l], e.v[l], e.w[l], e.t_scaled[l], e.det[l]) = match ray.intersect_a(a, b, c, tmax)
            {
                Some(h) => (1.0, h.b1, h.b2, h.t, 1.0),
                None => (0.0, 0.0, 0.0, 0.0, 0.0),
            };
        }
        e
    }

    /// The closest hit of `ray` (direction `d`) in (0, `tmax`): triangle
    /// index and hit. With `camera`, the back faces of triangles that cull
    /// them are passed through (glTF single-sided materials seen by a
    /// camera ray).
    ///
    /// # Safety
    /// The CPU must support AVX-512F.
    #[inline(always)]
    pub unsafe fn closest_avx512(
        &self,
        ray: &WatertightRay,
        d: Vec3,
        tmax: f32,
        camera: bool,
    ) -> Option<(u32, TriangleHit)> {
        use std::arch::x86_64::*;
        // Per lane, the nearest hit among that lane's triangles of all
        // chunks: no distance is carried from chunk to chunk, so their
        // tests overlap; one reduction at the end.
        let mut near = [f32::INFINITY; LANES];
        let mut near_chunk = [0u32; LANES];
        let mut near_v = [0.0f32; LANES];
        let mut near_w = [0.0f32; LANES];
        let mut near_det = [1.0f32; LANES];
        for (c, chunk) in self.chunks.iter().enumerate() {
            let e = Self::edges(chunk, ray, tmax);
            // 1/det from the 14-bit estimate and one Newton step: within
            // about an ulp, it only ranks the hits (the chosen one's
            // barycentrics are divided exactly below).
            // SAFETY: AVX-512F (the caller's contract); 16 f32 in and out.
            let inv: Lanes = unsafe {
                let det = _mm512_loadu_ps(e.det.as_ptr());
                let r = _mm512_rcp14_ps(det);
                let r = _mm512_mul_ps(r, _mm512_fnmadd_ps(det, r, _mm512_set1_ps(2.0)));
                std::mem::transmute::<__m512, Lanes>(r)
            };
            for l in 0..LANES {
                let facing =
                    chunk.normal[0][l] * d.x + chunk.normal[1][l] * d.y + chunk.normal[2][l] * d.z;
                let culled = camera & chunk.culls[l] & (facing > 0.0);
                let ok = chunk.used[l]
                    & !culled
                    & accepts(e.u[l], e.v[l], e.w[l], e.t_scaled[l], e.det[l], tmax);
                let t = e.t_scaled[l] * inv[l];
                let closer = ok & (t < near[l]);
                near[l] = if closer { t } else { near[l] };
                near_chunk[l] = if closer { c as u32 } else { near_chunk[l] };
                near_v[l] = if closer { e.v[l] } else { near_v[l] };
                near_w[l] = if closer { e.w[l] } else { near_w[l] };
                near_det[l] = if closer { e.det[l] } else { near_det[l] };
            }
        }
        // SAFETY: AVX-512F (the caller's contract); 16 f32 in.
        let (t, lanes) = unsafe {
            let v = _mm512_loadu_ps(near.as_ptr());
            let t = _mm512_reduce_min_ps(v);
            (
                t,
                _mm512_cmp_ps_mask::<_CMP_EQ_OQ>(v, _mm512_set1_ps(t)) as u32,
            )
        };
        if t.is_nan() || t >= tmax {
            return None;
        }
        // Of equal distances, the lowest triangle index.
        let l = (0..LANES)
            .filter(|&l| lanes & (1 << l) != 0)
            .min_by_key(|&l| near_chunk[l])
            .expect("the minimum is some lane's");
        let inv = 1.0 / near_det[l];
        Some((
            near_chunk[l] * LANES as u32 + l as u32,
            TriangleHit {
                t,
                b1: near_v[l] * inv,
                b2: near_w[l] * inv,
            },
        ))
    }

    /// Whether `ray` meets a triangle in (0, `tmax`) (back faces included).
    #[inline(always)]
    pub fn occluded(&self, ray: &WatertightRay, tmax: f32) -> bool {
        let mut any = false;
        for chunk in &self.chunks {
            let e = Self::edges(chunk, ray, tmax);
            for l in 0..LANES {
                any |=
                    chunk.used[l] & accepts(e.u[l], e.v[l], e.w[l], e.t_scaled[l], e.det[l], tmax);
            }
        }
        any
    }
}

/// Whether edge functions (u, v, w), scaled distance and determinant make
/// a hit in (0, tmax): one sign for u, v, w, and t = t_scaled / det
/// compared without dividing, as `WatertightRay::intersect_a` does (it
/// then also checks t < tmax after its division); with
/// `&` and `|`, not `&&` and `||`, so that a loop over lanes has no
/// branches and vectorises.
#[inline(always)]
fn accepts(u: f32, v: f32, w: f32, t_scaled: f32, det: f32, tmax: f32) -> bool {
    let mixed = ((u < 0.0) | (v < 0.0) | (w < 0.0)) & ((u > 0.0) | (v > 0.0) | (w > 0.0));
    let bound = tmax * det;
    let ahead = (det > 0.0) & (t_scaled > 0.0) & (t_scaled < bound);
    let behind = (det < 0.0) & (t_scaled < 0.0) & (t_scaled > bound);
    !mixed & (ahead | behind)
}

#[cfg(test)]
mod tests {
    use super::*;
    use penumbra_shading::stats::TestRng;

    fn point(rng: &mut TestRng, scale: f32) -> Vec3 {
        Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 * scale - scale
    }

    /// A soup of 40 triangles (three chunks, the last partly used), some
    /// sharing an edge so that rays through it meet the f64 fallback's
    /// lanes, with their front normals and a culling flag on every third.
    fn soup(rng: &mut TestRng) -> (Vec<[Vec3; 3]>, Vec<Vec3>, Vec<bool>) {
        let mut tris = Vec::new();
        for k in 0..40 {
            let a = point(rng, 1.0);
            let t = if k % 5 == 4 {
                // Shares the previous triangle's edge (b, c).
                let [_, b, c] = tris[k - 1];
                [c, b, point(rng, 1.0)]
            } else {
                [a, a + point(rng, 0.6), a + point(rng, 0.6)]
            };
            tris.push(t);
        }
        let normals = tris
            .iter()
            .map(|[a, b, c]| (*b - *a).cross(*c - *a).normalize())
            .collect();
        let culls = (0..tris.len()).map(|k| k % 3 == 0).collect();
        (tris, normals, culls)
    }

    /// The closest hit and occlusion of random rays (some aimed at shared
    /// edges and corners) against the scalar watertight test of every
    /// triangle, the reference: the same triangle (of equal distances the
    /// lowest index), the same distance within an ulp or two (the scan
    /// ranks by a reciprocal estimate), the same barycentrics; camera
    /// rays pass the back faces of culling triangles.
    #[test]
    fn scan_matches_scalar_test_of_every_triangle() {
        if !std::arch::is_x86_feature_detected!("avx512f") {
            assert!(
                std::env::var_os("PENUMBRA_SKIP_AVX512").is_some(),
                "no AVX-512 here: set PENUMBRA_SKIP_AVX512=1 to skip this test"
            );
            return;
        }
        let mut rng = TestRng::new(11);
        let (tris, normals, culls) = soup(&mut rng);
        let scan = TriangleScan::new(&tris, &normals, &culls).unwrap();
        let (mut hits, mut edge_rays) = (0, 0);
        for n in 0..20_000 {
            let o = point(&mut rng, 2.5);
            let target = if n % 4 == 0 {
                // A point of a shared edge or a corner.
                let [_, b, c] = tris[5 * (n / 4 % 8) + 4];
                edge_rays += 1;
                if n % 8 == 0 {
                    b
                } else {
                    b + (c - b) * rng.next_f32()
                }
            } else {
                point(&mut rng, 1.0)
            };
            let d = (target - o).normalize();
            let tmax = if n % 3 == 0 { 2.0 } else { f32::INFINITY };
            let camera = n % 2 == 0;
            let ray = WatertightRay::new(o, d);
            let mut expected: Option<(u32, TriangleHit)> = None;
            for (k, t) in tris.iter().enumerate() {
                let [a, b, c] = t.map(Vec3A::from);
                if camera && culls[k] && normals[k].dot(d) > 0.0 {
                    continue;
                }
                if let Some(h) = ray.intersect_a(a, b, c, tmax)
                    && expected.is_none_or(|(_, e)| h.t < e.t)
                {
                    expected = Some((k as u32, h));
                }
            }
            // SAFETY: AVX-512F checked above.
            let got = unsafe { scan.closest_avx512(&ray, d, tmax, camera) };
            match (expected, got) {
                (None, None) => {}
                (Some((k, e)), Some((j, g))) => {
                    hits += 1;
                    let close = |x: f32, y: f32| {
                        (x - y).abs() <= 4.0 * f32::EPSILON * x.abs().max(y.abs()).max(1e-3)
                    };
                    if j != k {
                        // Only a tie within the ranking's error may differ.
                        assert!(
                            close(e.t, g.t),
                            "ray {n}: triangle {j} at {} for {k} at {}",
                            g.t,
                            e.t
                        );
                        continue;
                    }
                    assert!(close(e.t, g.t), "ray {n}: t {} for {}", g.t, e.t);
                    assert!(
                        close(e.b1, g.b1) && close(e.b2, g.b2),
                        "ray {n}: {g:?} for {e:?}"
                    );
                }
                _ => panic!("ray {n}: {got:?} for {expected:?}"),
            }
            let blocked = tris.iter().any(|t| {
                let [a, b, c] = t.map(Vec3A::from);
                ray.intersect_a(a, b, c, tmax).is_some()
            });
            assert_eq!(scan.occluded(&ray, tmax), blocked, "ray {n}");
        }
        assert!(hits > 5_000 && edge_rays == 5_000, "{hits} hits");
    }

    /// Beyond [`MAX_TRIANGLES`] the scan is refused.
    #[test]
    fn refuses_large_scenes() {
        let t = [[Vec3::ZERO, Vec3::X, Vec3::Y]; MAX_TRIANGLES + 1];
        let n = [Vec3::Z; MAX_TRIANGLES + 1];
        let c = [false; MAX_TRIANGLES + 1];
        assert!(TriangleScan::new(&t, &n, &c).is_none());
        assert!(
            TriangleScan::new(
                &t[..MAX_TRIANGLES],
                &n[..MAX_TRIANGLES],
                &c[..MAX_TRIANGLES]
            )
            .is_some()
        );
    }
}
