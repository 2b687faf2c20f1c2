//! Path tracing with sixteen paths advanced together ("SIMD across
//! paths", as Mitsuba 3's vectorised variants and wavefront GPU tracers
//! do; Laine, Karras & Aila 2013, "Megakernels considered harmful"): each
//! stage of a path segment (closest hit, emission, light sample, shadow
//! ray, BSDF sample, Russian roulette) runs for all sixteen lanes before
//! the next, its arithmetic written over 16-lane arrays so that the
//! compiler turns it into AVX-512 instructions (or AVX2 ones, two
//! registers per array, on CPUs without AVX-512), and a lane whose path
//! ends starts its pixel's next sample at once (its lanes stay busy).
//!
//! The estimator is [`super::path`]'s, operation for operation: next-event
//! estimation and BSDF sampling weighted by the power heuristic, Russian
//! roulette after [`RR_START_DEPTH`] segments, and every lane draws its
//! numbers from its pixel's sampler in `path::li`'s order. So the image is
//! the scalar integrator's up to rounding (relMSE between the two about
//! 1e-5 at 64 spp on the Cornell box: a few paths part where a hit's
//! rounding differs).
//!
//! Scope, checked by [`WavefrontScene::new`] (other scenes take the scalar
//! integrator): the `path` integrator without AOVs; surfaces of any BSDF,
//! shaded flat or with interpolated vertex normals, without textures or
//! vertex colours (Lambert and smooth dielectric surfaces with exact
//! Fresnel are written out in lane form; the other models, mirrors,
//! conductors, Phong, rough dielectrics and metallic–roughness, are
//! sampled and evaluated lane by lane with the shared [`Bsdf`] code, in
//! loops apart that run only where a group's lanes hit them); light from emissive
//! triangles only (no environment, abstract or analytic area lights); an
//! x86-64 CPU with AVX2 (the lanes run in one AVX-512 register where the
//! CPU has AVX-512, else in two AVX2 ones: [`LaneKind`],
//! `accel/lanes16.rs`). [`crate::RenderOptions::scalar_paths`] (on the
//! command line `PENUMBRA_SCALAR_PATHS=1`) keeps the scalar integrator
//! for comparisons.
//!
//! Rays meet the scene in two parts ([`Tracer`]): the smallest objects, up
//! to [`scan::MAX_TRIANGLES`] triangles in all, are tested triangle by
//! triangle ([`TriangleScan`], sixteen at once: a room's walls, which
//! most rays hit), and the rest, up to [`MAX_BVH_TRIANGLES`], object by
//! object where there are at most [`MAX_SHAPES`] objects of at most
//! [`cluster_scan::MAX_TRIANGLES`] each ([`ClusterScan`]: a glass
//! sphere's thousands of triangles, whose box most rays miss), else
//! through a BVH of their own.
//!
//! One of the crate's modules with `unsafe` code: the entry points
//! compiled for AVX-512 and AVX2, the attribute reads (register permutes,
//! gathers, 8 × 8 transposes) and table reads without bounds checks (a checked read's
//! branch would keep a lane loop from vectorising).
#![allow(unsafe_code)]
// Lane loops index several structure-of-arrays fields by lane: the form
// that vectorises plainly.
#![allow(clippy::needless_range_loop)]

use crate::accel::cluster_scan::{self, ClusterScan};
use crate::accel::lanes16::{Avx2, Avx512, Simd16};
use crate::accel::scan::{self, TriangleScan, padded, reciprocals, slabs};
use crate::accel::{Accel, BuildQuality, WatertightRay};
use crate::geometry::SceneGeometry;
use crate::lights::LightSampler;
use crate::ray::{Ray, offset_coordinate};
use glam::{Vec2, Vec3};
use penumbra_image::film::FilmTile;
use penumbra_scene::{FilmRays, IntegratorKind, RenderSettings, Scene};
use penumbra_shading::bsdf::{Bsdf, FresnelModel};
use penumbra_shading::sampling::{
    Sampler, power_heuristic, square_to_cosine_hemisphere, square_to_triangle,
};
use std::f32::consts::FRAC_1_PI;

/// Paths in flight per group: one AVX-512 register of f32, or two AVX2
/// ones.
pub(crate) const LANES: usize = 16;

// Segments after which Russian roulette may end a path, and its survival
// probability: `path.rs`'s.
use super::path::{RR_START_DEPTH, rr_survival};

type F = [f32; LANES];
type B = [bool; LANES];

/// 64 entries of one attribute component, four aligned registers.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Block([f32; 64]);

/// The attribute components of every triangle. Up to 64 triangles, one
/// [`Block`] per component, read by sixteen lanes with two-register
/// permutes; beyond, one row of [`ROW`] components per triangle (two
/// cache lines), read with gathers.
#[derive(Debug)]
struct Tables {
    /// Rows instead of one block per component.
    rows: bool,
    /// Component `a` of triangle `t` at `a × 64 + t` (blocks) or `t × ROW
    /// + a` (rows).
    data: Vec<Block>,
}

/// Components per row: [`ATTRIBUTES`] rounded up to half a block.
const ROW: usize = 32;
const _: () = assert!(ATTRIBUTES <= ROW);

// The gathers' indices t × ROW + a are 32-bit signed.
const _: () = assert!((scan::MAX_TRIANGLES + MAX_BVH_TRIANGLES) * ROW < i32::MAX as usize);

/// The tables' components: corner c's axis a at `CORNERS + 3c + a`; the
/// unit front normal; the vertex normals at the corners (`SHADING + 3c +
/// a`, all 0 for a flat triangle, whose shading normal is the face's);
/// the Lambert albedo or the dielectric's tint; the emission; the
/// probability of being chosen as a light over the triangle's area (0 for
/// a non-emitter: a light sample's pdf is this × d² / |cos θ_light|); 1 for
/// a two-sided surface, else 0; the dielectric's relative index η, 0 for a
/// Lambert surface; for a surface of another model (see [`SHARED`]), the
/// index of its material + 1, else 0.
const CORNERS: usize = 0;
const NORMAL: usize = 9;
const SHADING: usize = 12;
const ALBEDO: usize = 21;
const EMISSION: usize = 24;
const PMF_PER_AREA: usize = 27;
const TWO_SIDED: usize = 28;
const ETA: usize = 29;
/// Surfaces whose model the lanes do not write out (mirrors, conductors,
/// Phong, rough dielectrics, metallic–roughness) are shaded lane by lane
/// with the shared [`Bsdf`] code: this component names their material.
const SHARED: usize = 30;
/// For a triangle of a convex object with a shape of its own in the BVH
/// part ([`BvhPart::convex`]), that shape's index + 1, else 0.
const CONVEX: usize = 31;
const ATTRIBUTES: usize = 32;
// Material indices are exact in f32.
const MAX_MATERIALS: usize = 1 << 24;

/// The components a surface hit reads: all but [`SHARED`] and
/// [`CONVEX`], each read apart where the scene has such surfaces.
const HIT_READS: [usize; SHARED] = {
    let mut r = [0; SHARED];
    let mut k = 0;
    while k < SHARED {
        r[k] = k;
        k += 1;
    }
    r
};

/// The components a hit on a scene of flat Lambert surfaces reads: all
/// but the vertex normals and η.
const FLAT_LAMBERT_READS: [usize; 20] = {
    let mut r = [0; 20];
    let mut k = 0;
    while k < SHADING {
        r[k] = k;
        k += 1;
    }
    while k < 20 {
        r[k] = k + (ALBEDO - SHADING);
        k += 1;
    }
    r
};

/// The components a light sample reads: corners, normal, emission, pmf,
/// two-sidedness, in this order.
const LIGHT_READS: [usize; 17] = [
    CORNERS,
    CORNERS + 1,
    CORNERS + 2,
    CORNERS + 3,
    CORNERS + 4,
    CORNERS + 5,
    CORNERS + 6,
    CORNERS + 7,
    CORNERS + 8,
    NORMAL,
    NORMAL + 1,
    NORMAL + 2,
    EMISSION,
    EMISSION + 1,
    EMISSION + 2,
    PMF_PER_AREA,
    TWO_SIDED,
];

// The permutes read 32 entries of two registers; two of them, a block.
const _: () = assert!(
    scan::MAX_TRIANGLES == 64,
    "the scan's triangles fit one block"
);

impl Tables {
    fn new(triangles: usize) -> Self {
        let rows = triangles > 64;
        let blocks = if rows {
            (triangles * ROW).div_ceil(64)
        } else {
            ATTRIBUTES
        };
        Tables {
            rows,
            data: vec![Block([0.0; 64]); blocks],
        }
    }

    fn set(&mut self, attribute: usize, triangle: usize, value: f32) {
        let k = if self.rows {
            triangle * ROW + attribute
        } else {
            attribute * 64 + triangle
        };
        self.data[k / 64].0[k % 64] = value;
    }

    /// The components `which` of the triangles `index` (one a lane, each
    /// below the triangle count), each into its own place of `out` (the
    /// others left as they were: a buffer kept across reads, not zeroed
    /// per read).
    ///
    /// # Safety
    /// The CPU must support `S`.
    #[inline(always)]
    unsafe fn read<S: Simd16, const K: usize>(
        &self,
        which: &[usize; K],
        index: &[u32; LANES],
        out: &mut [F; ATTRIBUTES],
    ) {
        use std::arch::x86_64::*;
        if S::AVX512 {
            // SAFETY: `S`'s features (the caller's contract); in blocks, each
            // component is 64 aligned f32 read as four aligned registers;
            // in rows, the gather reads entry `index × ROW + a` with
            // `index < triangles` and `a < ROW`, inside `data`; 16 values
            // written.
            unsafe {
                let vindex = _mm512_loadu_si512(index.as_ptr().cast());
                if !self.rows {
                    let upper = _mm512_test_epi32_mask(vindex, _mm512_set1_epi32(32));
                    for &a in which {
                        let t = self.data.as_ptr().add(a).cast::<f32>();
                        let low = _mm512_permutex2var_ps(
                            _mm512_load_ps(t),
                            vindex,
                            _mm512_load_ps(t.add(16)),
                        );
                        let high = _mm512_permutex2var_ps(
                            _mm512_load_ps(t.add(32)),
                            vindex,
                            _mm512_load_ps(t.add(48)),
                        );
                        _mm512_storeu_ps(
                            out[a].as_mut_ptr(),
                            _mm512_mask_blend_ps(upper, low, high),
                        );
                    }
                } else {
                    let rows = _mm512_slli_epi32::<5>(vindex);
                    const _: () = assert!(ROW == 1 << 5);
                    for &a in which {
                        let t = self.data.as_ptr().cast::<f32>().add(a);
                        _mm512_storeu_ps(out[a].as_mut_ptr(), _mm512_i32gather_ps::<4>(rows, t));
                    }
                }
            }
        } else if self.rows {
            // Each lane's row, eight components at a time, turned into
            // eight components' lanes by 8 × 8 transposes. (AVX2's
            // gathers fetch one element at a time: the reads' share of the
            // metal render fell from about 12 % to 9 % in `perf` profiles
            // on an AMD EPYC, Zen 3.)
            let blocks = which.iter().fold(0u8, |m, &a| m | (1 << (a / 8)));
            for half in 0..2 {
                for block in (0..ROW / 8).filter(|b| blocks & (1 << b) != 0) {
                    // SAFETY: AVX2 (the caller's contract).
                    let mut r = [unsafe { _mm256_setzero_ps() }; 8];
                    for (j, r) in r.iter_mut().enumerate() {
                        // SAFETY: AVX2 (the caller's contract); `index <
                        // triangles`, so the row's eight components from
                        // `8 block` lie inside `data`, 32-byte aligned.
                        unsafe {
                            let t = at(index, 8 * half + j) as usize;
                            *r = _mm256_load_ps(
                                self.data.as_ptr().cast::<f32>().add(t * ROW + 8 * block),
                            );
                        }
                    }
                    // SAFETY: AVX2 (the caller's contract).
                    let c = unsafe { transpose8(r) };
                    for &a in which {
                        if a / 8 == block {
                            // SAFETY: AVX2; eight f32 written inside `out[a]`.
                            unsafe {
                                _mm256_storeu_ps(out[a].as_mut_ptr().add(8 * half), c[a % 8])
                            };
                        }
                    }
                }
            }
        } else {
            // SAFETY: AVX2 (the caller's contract); the gathers read entry
            // `a × 64 + index` with `index < triangles` and `a <
            // ATTRIBUTES`, inside `data`; 16 values written.
            unsafe {
                let low = _mm256_loadu_si256(index.as_ptr().cast());
                let high = _mm256_loadu_si256(index.as_ptr().add(8).cast());
                for &a in which {
                    let t = self.data.as_ptr().add(a).cast::<f32>();
                    let o = out[a].as_mut_ptr();
                    _mm256_storeu_ps(o, _mm256_i32gather_ps::<4>(t, low));
                    _mm256_storeu_ps(o.add(8), _mm256_i32gather_ps::<4>(t, high));
                }
            }
        }
    }
}

/// The columns of the 8 × 8 matrix whose rows are `r`.
///
/// # Safety
/// The CPU must support AVX.
#[inline(always)]
unsafe fn transpose8(r: [std::arch::x86_64::__m256; 8]) -> [std::arch::x86_64::__m256; 8] {
    use std::arch::x86_64::*;
    // SAFETY: the caller's contract.
    unsafe {
        // Pairs of rows interleaved, then quads, then the 128-bit halves.
        let t0 = _mm256_unpacklo_ps(r[0], r[1]);
        let t1 = _mm256_unpackhi_ps(r[0], r[1]);
        let t2 = _mm256_unpacklo_ps(r[2], r[3]);
        let t3 = _mm256_unpackhi_ps(r[2], r[3]);
        let t4 = _mm256_unpacklo_ps(r[4], r[5]);
        let t5 = _mm256_unpackhi_ps(r[4], r[5]);
        let t6 = _mm256_unpacklo_ps(r[6], r[7]);
        let t7 = _mm256_unpackhi_ps(r[6], r[7]);
        let s0 = _mm256_shuffle_ps::<0x44>(t0, t2);
        let s1 = _mm256_shuffle_ps::<0xee>(t0, t2);
        let s2 = _mm256_shuffle_ps::<0x44>(t1, t3);
        let s3 = _mm256_shuffle_ps::<0xee>(t1, t3);
        let s4 = _mm256_shuffle_ps::<0x44>(t4, t6);
        let s5 = _mm256_shuffle_ps::<0xee>(t4, t6);
        let s6 = _mm256_shuffle_ps::<0x44>(t5, t7);
        let s7 = _mm256_shuffle_ps::<0xee>(t5, t7);
        [
            _mm256_permute2f128_ps::<0x20>(s0, s4),
            _mm256_permute2f128_ps::<0x20>(s1, s5),
            _mm256_permute2f128_ps::<0x20>(s2, s6),
            _mm256_permute2f128_ps::<0x20>(s3, s7),
            _mm256_permute2f128_ps::<0x31>(s0, s4),
            _mm256_permute2f128_ps::<0x31>(s1, s5),
            _mm256_permute2f128_ps::<0x31>(s2, s6),
            _mm256_permute2f128_ps::<0x31>(s3, s7),
        ]
    }
}

/// Where rays meet the scene: the scan of the smallest objects, with the
/// scene indices of its triangles (none for a scan of every triangle, in
/// scene order), and the rest ([`BvhPart`]).
#[derive(Debug)]
struct Tracer {
    scan: Option<(TriangleScan, Vec<u32>)>,
    bvh: Option<BvhPart>,
}

/// The triangles beyond the scan: their search ([`PartSearch`]), and for
/// each of their objects (one shape around them all where there are more
/// than [`MAX_SHAPES`]) its padded bounds and a padded ball around it
/// (`[cx, cy, cz, r]`). A ray searches an object (or the BVH) only where
/// it passes both its tests, sixteen lanes at a time: the ball keeps out the rays
/// that pass a round object's box but miss the object, about half of a
/// sphere's box's, and objects apart keep out those that pass between
/// them (spheres side by side over a floor). A ray that leaves a convex
/// object from its outer side skips that object's tests: it cannot meet
/// it again (rays reflected off a metal sphere or refracted out of a glass
/// one; [`convex`]).
#[derive(Debug)]
struct BvhPart {
    search: PartSearch,
    shapes: Vec<([[f32; 3]; 2], [f32; 4])>,
    /// The scene triangles of the convex objects among those with a shape
    /// of their own, each object's with its shape's index + 1 (the
    /// [`CONVEX`] component).
    convex: Vec<(std::ops::Range<u32>, u32)>,
}

/// The most objects of the BVH part tested (and searched) one by one.
const MAX_SHAPES: usize = 8;

/// How the BVH part's triangles are searched for a ray that passes an
/// object's tests.
#[derive(Debug)]
enum PartSearch {
    /// A BVH over them all, and the scene index of each of its triangles.
    Tree(Accel, Vec<u32>),
    /// A cluster scan per object, in the order of the shapes (objects of
    /// at most [`cluster_scan::MAX_TRIANGLES`] each, which its fixed
    /// tree of 16-wide tests searches faster than the BVH walks).
    Objects(Vec<ClusterScan>),
}

impl BvhPart {
    /// For each lane's ray `o + t d` (t in (0, `tmax`), 1/d = `inv`), the
    /// objects whose box and ball it passes (bit k for shape k), other
    /// than the object `leaves` names (its shape's index + 1; 0 for none):
    /// a convex object the ray leaves from its outer side, which it cannot
    /// meet again.
    #[inline(always)]
    fn passed(
        &self,
        o: &[F; 3],
        d: &[F; 3],
        inv: &[F; 3],
        tmax: &F,
        leaves: &[u32; LANES],
    ) -> [u8; LANES] {
        let mut shapes = [0u8; LANES];
        for (k, (bounds, b)) in self.shapes.iter().enumerate() {
            let maybe = slabs(o, inv, tmax, bounds);
            let near = ball(o, d, b);
            for i in 0..LANES {
                let pass = maybe[i] & near[i] & (leaves[i] != k as u32 + 1);
                shapes[i] |= u8::from(pass) << k;
            }
        }
        shapes
    }
}

/// The most face-corner pairs of an object checked for convexity (each
/// face against each corner, faces in parallel: about 10 ms on two cores
/// for a sphere of 5,120 triangles and 2,562 corners, 13M pairs).
const MAX_CONVEX_CHECK: usize = 1 << 25;

/// Whether the triangles `t` (world space) with unit front normals `n`
/// bound a convex object with their fronts outside: every corner of the
/// object lies behind each face's plane by more than 1e-6 of its distance
/// from the face (in f64), the face's own corners aside. Then a ray that
/// leaves one of its faces on the front side (from a point in front of
/// that face's plane, in a direction that does not turn back towards it)
/// stays in front of that plane and cannot meet the object. (Coplanar
/// faces, as a box's, fail the margin: such objects count as not convex.)
fn convex(t: &[[Vec3; 3]], n: &[Vec3]) -> bool {
    if t.len() < 4 {
        return false;
    }
    let mut bits: Vec<[u32; 3]> = t
        .iter()
        .flatten()
        .map(|v| v.to_array().map(f32::to_bits))
        .collect();
    bits.sort_unstable();
    bits.dedup();
    let corners: Vec<glam::DVec3> = bits
        .iter()
        .map(|b| glam::DVec3::from_array(b.map(|x| f64::from(f32::from_bits(x)))))
        .collect();
    if t.len() * corners.len() > MAX_CONVEX_CHECK {
        return false;
    }
    use rayon::prelude::*;
    t.par_iter().zip(n).all(|(f, front)| {
        let [a, b, c] = f.map(|v| v.as_dvec3());
        let m = (b - a).cross(c - a);
        // Oriented as the front (a mirrored instance turns its winding).
        let m = if m.dot(front.as_dvec3()) < 0.0 { -m } else { m };
        let len = m.length();
        len > 0.0
            && corners.iter().all(|&v| {
                v == a || v == b || v == c || m.dot(v - a) < -1e-6 * len * (v - a).length()
            })
    })
}

/// The most triangles the BVH part holds. Beyond, its tree outgrows the
/// caches and the traversal dominates, one ray at a time as in the scalar
/// integrator, which then does as well: a Lambert scene of 1M triangles
/// (the `bench` mesh under an emissive square) took 11.12 s here against
/// 10.21 s scalar (512 spp, two threads), where the glass-sphere box's
/// 5,120 run 1.3-1.4x faster than scalar.
const MAX_BVH_TRIANGLES: usize = 1 << 16;

/// A ball around the points `p` padded by `pad`: the centre of `[lo,
/// hi]`, the radius the farthest point's distance (in f64) plus `pad`, as
/// `[cx, cy, cz, r]`.
fn bounding_ball(p: impl Iterator<Item = Vec3>, [lo, hi]: [Vec3; 2], pad: f32) -> [f32; 4] {
    let centre = ((lo + hi) * 0.5).as_dvec3();
    let r2 = p.fold(0.0f64, |r2, p| {
        r2.max((p.as_dvec3() - centre).length_squared())
    });
    let c = centre.as_vec3();
    [c.x, c.y, c.z, r2.sqrt() as f32 + pad]
}

/// The lanes whose ray `o + t d` (t > 0) may meet the ball `[cx, cy, cz,
/// r]`: it starts inside, or its line passes within r of the centre ahead
/// of it. Conservative: the line's distance comes from a cross product
/// (no cancellation), its rounding (a few ulps of |c - o|) is covered by
/// adding 1e-6 |c - o| to r, and the ball is padded beyond the rest.
#[inline(always)]
fn ball(o: &[F; 3], d: &[F; 3], [cx, cy, cz, r]: &[f32; 4]) -> B {
    let mut maybe = [false; LANES];
    for i in 0..LANES {
        let oc = [cx - o[0][i], cy - o[1][i], cz - o[2][i]];
        let dv = [d[0][i], d[1][i], d[2][i]];
        let cross = [
            oc[1] * dv[2] - oc[2] * dv[1],
            oc[2] * dv[0] - oc[0] * dv[2],
            oc[0] * dv[1] - oc[1] * dv[0],
        ];
        let dd = dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2];
        let cc = cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2];
        let oo = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2];
        let ahead = oc[0] * dv[0] + oc[1] * dv[1] + oc[2] * dv[2] > 0.0;
        let reach = *r + 1e-6 * oo.sqrt();
        maybe[i] = (oo <= r * r) | (ahead & (cc <= reach * reach * dd));
    }
    maybe
}

impl Tracer {
    /// The BVH part has convex objects ([`CONVEX`]).
    fn has_convex(&self) -> bool {
        self.bvh.as_ref().is_some_and(|b| !b.convex.is_empty())
    }

    /// The scene's triangles split by object: objects in increasing order
    /// of size to the scan while they fit, the rest to a BVH. `None` where
    /// a triangle the BVH would hold culls its back faces for camera rays
    /// (only the scan does that), or the BVH would hold more than
    /// [`MAX_BVH_TRIANGLES`].
    fn new(
        geometry: &SceneGeometry,
        scene: &Scene,
        normals: &[Vec3],
        culls: &[bool],
    ) -> Option<Self> {
        let mut objects: Vec<_> = (0..scene.instances.len())
            .map(|i| geometry.instance_triangles(i))
            .collect();
        objects.sort_by_key(|r| r.len());
        let (mut scanned, mut rest, mut rest_objects) = (Vec::new(), Vec::new(), Vec::new());
        for r in objects {
            if scanned.len() + r.len() <= scan::MAX_TRIANGLES {
                scanned.extend(r);
            } else {
                rest.extend(r.clone());
                rest_objects.push(r);
            }
        }
        // In scene order: of equal distances the scan keeps the lowest index.
        scanned.sort_unstable();
        rest.sort_unstable();
        if rest.len() > MAX_BVH_TRIANGLES || rest.iter().any(|&t| culls[t as usize]) {
            return None;
        }
        let pick = |ids: &[u32]| -> Vec<[Vec3; 3]> {
            ids.iter()
                .map(|&t| geometry.triangles[t as usize])
                .collect()
        };
        let scan = if scanned.is_empty() {
            None
        } else {
            let n: Vec<Vec3> = scanned.iter().map(|&t| normals[t as usize]).collect();
            let c: Vec<bool> = scanned.iter().map(|&t| culls[t as usize]).collect();
            let g: Vec<u32> = scanned
                .iter()
                .map(|&t| geometry.triangle_source(t).0 as u32)
                .collect();
            let scan = TriangleScan::new(&pick(&scanned), &n, &c, &g)?;
            let ids = if rest.is_empty() { Vec::new() } else { scanned };
            Some((scan, ids))
        };
        let bvh = if rest.is_empty() {
            None
        } else {
            let corners = |ts: &mut dyn Iterator<Item = u32>| -> Vec<Vec3> {
                ts.flat_map(|t| geometry.triangles[t as usize]).collect()
            };
            let shape = |p: Vec<Vec3>| {
                let ([lo, hi], pad) = padded(p.iter().copied());
                let ball = bounding_ball(p.into_iter(), [lo, hi], pad);
                ([lo.to_array(), hi.to_array()], ball)
            };
            // One shape an object, or one around them all; only objects
            // with a shape of their own can be named as the one a ray
            // leaves.
            let by_object = rest_objects.len() <= MAX_SHAPES;
            // Each object's scene triangles, their corners and normals
            // (where the objects are taken one by one).
            let objects: Vec<_> = if by_object {
                rest_objects
                    .iter()
                    .map(|r| {
                        let ids: Vec<u32> = r.clone().collect();
                        let (t, n) = (
                            pick(&ids),
                            ids.iter().map(|&t| normals[t as usize]).collect::<Vec<_>>(),
                        );
                        (ids, t, n)
                    })
                    .collect()
            } else {
                Vec::new()
            };
            let (shapes, convex) = if by_object {
                let shapes = objects
                    .iter()
                    .map(|(_, t, _)| shape(t.iter().flatten().copied().collect()))
                    .collect();
                let convex = rest_objects
                    .iter()
                    .zip(&objects)
                    .enumerate()
                    .filter(|(_, (_, (_, t, n)))| convex(t, n))
                    .map(|(k, (r, _))| (r.clone(), k as u32 + 1))
                    .collect();
                (shapes, convex)
            } else {
                (vec![shape(corners(&mut rest.iter().copied()))], Vec::new())
            };
            let search = if by_object
                && objects
                    .iter()
                    .all(|(ids, _, _)| ids.len() <= cluster_scan::MAX_TRIANGLES)
            {
                PartSearch::Objects(
                    objects
                        .iter()
                        .map(|(ids, t, _)| ClusterScan::new(t, ids))
                        .collect(),
                )
            } else {
                PartSearch::Tree(Accel::build(&pick(&rest), BuildQuality::Medium), rest)
            };
            Some(BvhPart {
                search,
                shapes,
                convex,
            })
        };
        Some(Tracer { scan, bvh })
    }

    /// The closest hits of the `live` lanes' rays `o + t d`: scene
    /// triangle and barycentrics, in `tri` and `bary`; lanes whose ray
    /// meets nothing leave `live`. `camera` passes through the back faces
    /// of triangles that cull them; `leaves` names the convex object of
    /// the BVH part each ray leaves (see [`BvhPart::passed`]).
    ///
    /// # Safety
    /// The CPU must support `S`.
    #[inline(always)]
    unsafe fn closest<S: Simd16>(
        &self,
        (o, d): (&[F; 3], &[F; 3]),
        camera: &B,
        leaves: &[u32; LANES],
        live: &mut B,
        tri: &mut [u32; LANES],
        bary: &mut [F; 2],
    ) {
        let mut tmax = [f32::INFINITY; LANES];
        let mut found = [false; LANES];
        let inv = reciprocals(d);
        let mut rays = [None; LANES];
        if let Some((scan, ids)) = &self.scan {
            let chunks = scan.chunks_passed(o, &inv, &tmax);
            for i in 0..LANES {
                if !live[i] || chunks[i] == 0 {
                    continue;
                }
                let ray = lane_ray(&mut rays, (o, d), i);
                // SAFETY: `S`'s features (the caller's contract); the scan's
                // indices are below `ids.len()`.
                unsafe {
                    if let Some((k, h)) =
                        scan.closest::<S>(ray, lane3(d, i), tmax[i], camera[i], chunks[i])
                    {
                        tmax[i] = h.t;
                        // (No map where the scan holds every triangle.)
                        tri[i] = if ids.is_empty() {
                            k
                        } else {
                            at(ids, k as usize)
                        };
                        [bary[0][i], bary[1][i]] = [h.b1, h.b2];
                        found[i] = true;
                    }
                }
            }
        }
        if let Some(part) = &self.bvh {
            let passed = part.passed(o, d, &inv, &tmax, leaves);
            for i in 0..LANES {
                if !live[i] || passed[i] == 0 {
                    continue;
                }
                let hit = match &part.search {
                    PartSearch::Tree(accel, ids) => accel
                        .intersect(&Ray::segment(lane3(o, i), lane3(d, i), tmax[i]))
                        // SAFETY: the BVH's indices are below `ids.len()`.
                        .map(|h| (unsafe { at(ids, h.triangle as usize) }, h.b1, h.b2)),
                    PartSearch::Objects(scans) => {
                        let ray = lane_ray(&mut rays, (o, d), i);
                        let (oi, inv_i) = (lane3(o, i), lane3(&inv, i));
                        let (mut hit, mut todo) = (None, passed[i]);
                        while todo != 0 {
                            let scan = &scans[todo.trailing_zeros() as usize];
                            todo &= todo - 1;
                            // SAFETY: `S`'s features (the caller's contract).
                            let h = unsafe { scan.closest::<S>(ray, oi, inv_i, tmax[i]) };
                            if let Some((id, h)) = h {
                                tmax[i] = h.t;
                                hit = Some((id, h.b1, h.b2));
                            }
                        }
                        hit
                    }
                };
                if let Some((id, b1, b2)) = hit {
                    tri[i] = id;
                    [bary[0][i], bary[1][i]] = [b1, b2];
                    found[i] = true;
                }
            }
        }
        for i in 0..LANES {
            live[i] &= found[i];
        }
    }

    /// Which of the `shadow` lanes' rays `o + t d` meet nothing in (0,
    /// `tmax`): the others leave `shadow`. `leaves` as for
    /// [`Self::closest`].
    ///
    /// # Safety
    /// The CPU must support `S`.
    #[inline(always)]
    unsafe fn unoccluded<S: Simd16>(
        &self,
        (o, d): (&[F; 3], &[F; 3]),
        tmax: &F,
        leaves: &[u32; LANES],
        shadow: &mut B,
    ) {
        let inv = reciprocals(d);
        let mut rays = [None; LANES];
        if let Some((scan, _)) = &self.scan {
            let chunks = scan.chunks_passed(o, &inv, tmax);
            for i in 0..LANES {
                if !shadow[i] || chunks[i] == 0 {
                    continue;
                }
                let ray = lane_ray(&mut rays, (o, d), i);
                // SAFETY: `S`'s features (the caller's contract).
                shadow[i] = !unsafe { scan.occluded::<S>(ray, tmax[i], chunks[i]) };
            }
        }
        if let Some(part) = &self.bvh {
            let passed = part.passed(o, d, &inv, tmax, leaves);
            for i in 0..LANES {
                if !shadow[i] || passed[i] == 0 {
                    continue;
                }
                shadow[i] = !match &part.search {
                    PartSearch::Tree(accel, _) => {
                        accel.occluded(&Ray::segment(lane3(o, i), lane3(d, i), tmax[i]))
                    }
                    PartSearch::Objects(scans) => {
                        let ray = lane_ray(&mut rays, (o, d), i);
                        let (oi, inv_i) = (lane3(o, i), lane3(&inv, i));
                        // (A loop, not a closure: the intrinsics would
                        // not be inlined into one.)
                        let (mut blocked, mut todo) = (false, passed[i]);
                        while todo != 0 && !blocked {
                            let scan = &scans[todo.trailing_zeros() as usize];
                            todo &= todo - 1;
                            // SAFETY: `S`'s features (the caller's contract).
                            blocked = unsafe { scan.occluded::<S>(ray, oi, inv_i, tmax[i]) };
                        }
                        blocked
                    }
                };
            }
        }
    }
}

/// What the lanes read of the scene: the triangles' attributes as tables;
/// the light sampler's emissive triangles with the running sums of their
/// weights; the tracer.
#[derive(Debug)]
pub(crate) struct WavefrontScene {
    tables: Tables,
    /// The light sampler's choices (triangles), the running sums of their
    /// weights and the total, as `Distribution1D::sample` reads them.
    lights: Vec<u32>,
    running_sums: Vec<f64>,
    total_weight: f64,
    tracer: Tracer,
    /// The registers the lanes run in.
    kind: LaneKind,
    /// Every surface is Lambertian and shaded flat.
    flat_lambert: bool,
    /// The materials' BSDFs, for the surfaces shaded with the shared code
    /// ([`SHARED`]); empty where there are none.
    shared_bsdfs: Vec<Bsdf>,
    max_depth: u32,
}

/// The registers the sixteen lanes run in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum LaneKind {
    /// One AVX-512 register.
    Avx512,
    /// Two AVX2 registers.
    Avx2,
}

impl WavefrontScene {
    /// The scene as the lanes read it, or `None` where the scene, the
    /// settings or the CPU are outside this integrator's scope (see the
    /// module's documentation). The lanes run in one AVX-512 register
    /// where the CPU has AVX-512 and not `avx2_only`, else in two AVX2
    /// ones.
    pub(crate) fn new(
        scene: &Scene,
        geometry: &SceneGeometry,
        light_sampler: &LightSampler,
        settings: &RenderSettings,
        avx2_only: bool,
    ) -> Option<Self> {
        // Every feature a `trace_group_*` is compiled for.
        #[cfg(target_arch = "x86_64")]
        let kind = if Avx512::supported() && !avx2_only {
            Some(LaneKind::Avx512)
        } else {
            Avx2::supported().then_some(LaneKind::Avx2)
        };
        #[cfg(not(target_arch = "x86_64"))]
        let kind: Option<LaneKind> = None;
        let n = geometry.triangles.len();
        let kind = kind?;
        if settings.integrator != IntegratorKind::Path
            || n == 0
            // (Checked again by object in `Tracer::new`; here before the
            // tables are filled.)
            || n > scan::MAX_TRIANGLES + MAX_BVH_TRIANGLES
            || !scene.lights.is_empty()
            || !scene.area_lights.is_empty()
            || scene.environment_map.is_some()
            || scene.background != Vec3::ZERO
        {
            return None;
        }
        let mut tables = Tables::new(n);
        let mut flat_lambert = true;
        let mut any_shared = false;
        if scene.materials.len() >= MAX_MATERIALS {
            return None;
        }
        let mut normal = Vec::with_capacity(n);
        let mut culls = Vec::with_capacity(n);
        for t in 0..n as u32 {
            let material = geometry.material_of(t);
            let m = &scene.materials[material];
            // The lanes' own models, else the shared code's.
            let (albedo, eta, shared) = match m.bsdf {
                Bsdf::Lambert(l) => (l.albedo, 0.0, 0.0),
                Bsdf::Dielectric(d) if d.fresnel == FresnelModel::Exact && d.eta > 0.0 => {
                    (d.tint, d.eta, 0.0)
                }
                _ => (Vec3::ZERO, 0.0, (material + 1) as f32),
            };
            any_shared |= shared != 0.0;
            if m.albedo_texture.is_some()
                || m.emission_texture.is_some()
                || m.normal_map.is_some()
                || m.alpha.is_some()
            {
                return None;
            }
            // No vertex colour tints it, at any corner (so anywhere).
            for (b1, b2) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)] {
                if geometry.surface_point(scene, t, b1, b2).color != Vec3::ONE {
                    return None;
                }
            }
            let ng = geometry.front_normal_scaled(t).normalize_or_zero();
            let k = t as usize;
            let shading = geometry.corner_normals(scene, t);
            flat_lambert &= shading.is_none() && eta == 0.0 && shared == 0.0;
            let shading = shading.unwrap_or([Vec3::ZERO; 3]);
            for a in 0..3 {
                for c in 0..3 {
                    tables.set(CORNERS + 3 * c + a, k, geometry.triangles[k][c][a]);
                    tables.set(SHADING + 3 * c + a, k, shading[c][a]);
                }
                tables.set(NORMAL + a, k, ng[a]);
                tables.set(ALBEDO + a, k, albedo[a]);
                tables.set(EMISSION + a, k, m.emission[a]);
            }
            tables.set(TWO_SIDED, k, if m.double_sided { 1.0 } else { 0.0 });
            tables.set(ETA, k, eta);
            tables.set(SHARED, k, shared);
            normal.push(ng);
            culls.push(m.cull_back_faces);
        }
        // The lights as the scalar integrator chooses them.
        let (lights, distribution) = light_sampler.triangle_lights()?;
        let (running_sums, total_weight) = distribution.running_sums();
        if lights.is_empty() || !(total_weight > 0.0 && total_weight.is_finite()) {
            return None;
        }
        for (entry, &t) in lights.iter().enumerate() {
            let pmf = distribution.pmf(entry) / geometry.area(t);
            tables.set(PMF_PER_AREA, t as usize, pmf);
        }
        let tracer = Tracer::new(geometry, scene, &normal, &culls)?;
        let convex = tracer.bvh.as_ref().map_or(&[][..], |b| &b.convex[..]);
        for (triangles, shape) in convex {
            for t in triangles.clone() {
                tables.set(CONVEX, t as usize, *shape as f32);
            }
        }
        Some(WavefrontScene {
            tracer,
            tables,
            kind,
            flat_lambert,
            shared_bsdfs: if any_shared {
                scene.materials.iter().map(|m| m.bsdf).collect()
            } else {
                Vec::new()
            },
            lights,
            running_sums: running_sums.to_vec(),
            total_weight,
            max_depth: settings.max_depth,
        })
    }
}

/// Lane `i`'s ray `o + t d` as the triangle tests see it, made when a
/// test first needs it: a lane may meet both parts, one or none.
#[inline(always)]
fn lane_ray<'r>(
    rays: &'r mut [Option<WatertightRay>; LANES],
    (o, d): (&[F; 3], &[F; 3]),
    i: usize,
) -> &'r WatertightRay {
    rays[i].get_or_insert_with(|| WatertightRay::new(lane3(o, i), lane3(d, i)))
}

/// Lane `i` of three lanes' arrays (x, y, z) as a vector.
#[inline(always)]
fn lane3(v: &[F; 3], i: usize) -> Vec3 {
    Vec3::new(v[0][i], v[1][i], v[2][i])
}

/// Reads `v[k]` without a bounds check.
///
/// # Safety
/// `k < v.len()`.
#[inline(always)]
unsafe fn at<T: Copy>(v: &[T], k: usize) -> T {
    debug_assert!(k < v.len());
    // SAFETY: the caller's contract.
    unsafe { *v.get_unchecked(k) }
}

/// The paths of a group of pixels in flight, one per lane, in
/// structure-of-arrays form (component, then lane).
struct Paths {
    /// The lane's path is alive (its ray is to be traced).
    live: B,
    /// The lane holds a path whose sample is not yet on the film.
    in_flight: B,
    next_sample: [u32; LANES],
    origin: [F; 3],
    dir: [F; 3],
    radiance: [F; 3],
    beta: [F; 3],
    /// Product of η² over the refractions so far (`path::PathState`'s).
    eta_scale: F,
    /// Solid-angle pdf of the BSDF sample that made the ray; 0 for a
    /// camera ray (emitters it hits get weight 1).
    prev_pdf: F,
    prev_point: [F; 3],
    /// The convex object of the BVH part the ray leaves from its outer
    /// side, as its shape's index + 1 (0: none), which it cannot meet.
    leaves: [u32; LANES],
    depth: [u32; LANES],
    camera_hit: B,
}

/// A group of at most [`LANES`] pixels of a tile and where their
/// samples go: sample indices `samples` of every pixel of `pixels`, each
/// with its sampler, onto `tile`; `hits` counts per pixel of the tile
/// (row length `tile_w`, origin `tile_origin`) the samples whose camera
/// ray met a surface.
struct Group<'a> {
    film: &'a FilmRays,
    pixels: &'a [(u32, u32)],
    samplers: &'a mut [Sampler],
    samples: (u32, u32),
    tile: &'a mut FilmTile,
    hits: &'a mut [u32],
    tile_origin: (u32, u32),
    tile_w: u32,
}

/// [`trace_group`] in one AVX-512 register per lane array.
///
/// # Safety
/// The CPU must support the features it is compiled for.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
unsafe fn trace_group_avx512<const GENERAL: bool>(s: &WavefrontScene, g: Group) {
    // SAFETY: the features, as `Avx512` needs.
    unsafe { trace_group::<Avx512, GENERAL>(s, g) }
}

/// [`trace_group`] in two AVX2 registers per lane array.
///
/// # Safety
/// The CPU must support the features it is compiled for.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
unsafe fn trace_group_avx2<const GENERAL: bool>(s: &WavefrontScene, g: Group) {
    // SAFETY: the features, as `Avx2` needs.
    unsafe { trace_group::<Avx2, GENERAL>(s, g) }
}

/// The samples of the group `g` ([`Group`]). With `GENERAL` for any
/// scene in scope, without for flat Lambert surfaces only (see
/// [`segment`]): two functions, one per kind of scene, so that neither
/// carries the other's code (a render runs one of them). Compiled once
/// per [`LaneKind`] ([`trace_group_avx512`], [`trace_group_avx2`]),
/// inlined into each.
///
/// # Safety
/// The CPU must support `S` and the features its entry point is compiled
/// for (checked by [`WavefrontScene::new`]).
#[inline(always)]
unsafe fn trace_group<S: Simd16, const GENERAL: bool>(s: &WavefrontScene, g: Group) {
    let Group {
        film,
        pixels,
        samplers,
        samples: (s0, s1),
        tile,
        hits,
        tile_origin,
        tile_w,
    } = g;
    let mut p = Paths {
        live: [false; LANES],
        in_flight: [false; LANES],
        next_sample: [s0; LANES],
        origin: [[0.0; LANES]; 3],
        dir: [[0.0; LANES]; 3],
        radiance: [[0.0; LANES]; 3],
        beta: [[1.0; LANES]; 3],
        eta_scale: [1.0; LANES],
        prev_pdf: [0.0; LANES],
        prev_point: [[0.0; LANES]; 3],
        leaves: [0; LANES],
        depth: [1; LANES],
        camera_hit: [false; LANES],
    };
    // The attributes of the hits and of the lights sampled, read anew
    // each segment (a component the scene's kind of surface does not use
    // is read never, and stays 0).
    let mut reads = [[[0.0f32; LANES]; ATTRIBUTES]; 2];
    loop {
        // Lanes whose path ended hand in their sample and start their
        // pixel's next one.
        let mut any_live = false;
        for i in 0..pixels.len() {
            let (x, y) = pixels[i];
            if p.in_flight[i] && !p.live[i] {
                let v = lane3(&p.radiance, i);
                // As `render_tile`: one bad sample must not ruin a pixel.
                tile.add_sample(x, y, if v.is_finite() { v } else { Vec3::ZERO });
                if p.camera_hit[i] {
                    let (x0, y0) = tile_origin;
                    hits[((y - y0) * tile_w + (x - x0)) as usize] += 1;
                }
                p.in_flight[i] = false;
            }
            if !p.in_flight[i] && p.next_sample[i] < s1 {
                let sampler = &mut samplers[i];
                sampler.start_sample(p.next_sample[i]);
                p.next_sample[i] += 1;
                let [jx, jy] = sampler.next_2d();
                let (o, d) = film.ray(x as f32 + jx, y as f32 + jy);
                for a in 0..3 {
                    p.origin[a][i] = o[a];
                    p.dir[a][i] = d[a];
                    p.prev_point[a][i] = o[a];
                    p.radiance[a][i] = 0.0;
                    p.beta[a][i] = 1.0;
                }
                p.eta_scale[i] = 1.0;
                p.prev_pdf[i] = 0.0;
                p.leaves[i] = 0;
                p.depth[i] = 1;
                p.camera_hit[i] = false;
                p.live[i] = true;
                p.in_flight[i] = true;
            }
            any_live |= p.live[i];
        }
        if !any_live {
            return;
        }
        segment::<S, GENERAL>(s, &mut p, samplers, &mut reads);
    }
}

/// One segment of every live path: its closest hit, the emission found
/// there, a light sample with its shadow ray, and the BSDF sample that
/// makes the next ray (or the path's end). Without `GENERAL` the scene's
/// surfaces are all flat and Lambertian (shading normal = face normal, no
/// dielectric), and the work for the others is left out.
#[inline(always)]
fn segment<S: Simd16, const GENERAL: bool>(
    s: &WavefrontScene,
    p: &mut Paths,
    samplers: &mut [Sampler],
    [g, l]: &mut [[F; ATTRIBUTES]; 2],
) {
    // Closest hits.
    let mut tri = [0u32; LANES];
    let mut bary = [[0.0f32; LANES]; 2];
    let camera: B = p.depth.map(|d| d == 1);
    crate::stats::count_rays(p.live.iter().filter(|&&l| l).count() as u64);
    // SAFETY: `S`'s features (`trace_group`'s contract).
    unsafe {
        s.tracer.closest::<S>(
            (&p.origin, &p.dir),
            &camera,
            &p.leaves,
            &mut p.live,
            &mut tri,
            &mut bary,
        );
    }
    for i in 0..LANES {
        p.camera_hit[i] |= p.live[i] & camera[i];
    }
    // The hits' surfaces (dead lanes read triangle 0, whose values no
    // live result uses).
    for i in 0..LANES {
        tri[i] = if p.live[i] { tri[i] } else { 0 };
    }
    // SAFETY: `S`'s features (`trace_group`'s contract); triangle indices.
    unsafe {
        if GENERAL {
            s.tables.read::<S, _>(&HIT_READS, &tri, g);
            if !s.shared_bsdfs.is_empty() {
                s.tables.read::<S, _>(&[SHARED], &tri, g);
            }
            if s.tracer.has_convex() {
                s.tables.read::<S, _>(&[CONVEX], &tri, g);
            }
        } else {
            s.tables.read::<S, _>(&FLAT_LAMBERT_READS, &tri, g);
        }
    }
    let mut point = [[0.0f32; LANES]; 3];
    let mut ng = [[0.0f32; LANES]; 3];
    let mut ns = [[0.0f32; LANES]; 3];
    for i in 0..LANES {
        let (b1, b2) = (bary[0][i], bary[1][i]);
        let b0 = 1.0 - b1 - b2;
        let mut raw = [0.0f32; 3];
        for a in 0..3 {
            // Interpolating the corners is more accurate than o + t d.
            let c = |v: usize| g[CORNERS + 3 * v + a][i];
            point[a][i] = c(0) * b0 + c(1) * b1 + c(2) * b2;
            ng[a][i] = g[NORMAL + a][i];
            let n = |v: usize| g[SHADING + 3 * v + a][i];
            raw[a] = n(0) * b0 + n(1) * b1 + n(2) * b2;
        }
        if !GENERAL {
            for a in 0..3 {
                ns[a][i] = ng[a][i];
            }
            continue;
        }
        // The shading normal as `SceneGeometry::surface_point`'s: the
        // vertex normals interpolated and normalised (the face's where
        // that fails: a flat triangle's are 0), on the face's side.
        let rcp = 1.0 / (raw[0] * raw[0] + raw[1] * raw[1] + raw[2] * raw[2]).sqrt();
        let smooth = rcp.is_finite() & (rcp > 0.0);
        let mut n = [0.0f32; 3];
        for a in 0..3 {
            n[a] = if smooth { raw[a] * rcp } else { ng[a][i] };
        }
        let flip = n[0] * ng[0][i] + n[1] * ng[1][i] + n[2] * ng[2][i] < 0.0;
        for a in 0..3 {
            ns[a][i] = if flip { -n[a] } else { n[a] };
        }
    }
    let albedo: [F; 3] = [g[ALBEDO], g[ALBEDO + 1], g[ALBEDO + 2]];
    let mut eta = g[ETA];
    let dielectric: B = if GENERAL {
        eta.map(|e| e != 0.0)
    } else {
        [false; LANES]
    };
    // Surfaces the shared code shades (the component stays 0 where the
    // scene has none: it is never read).
    let shared: B = std::array::from_fn(|i| GENERAL & p.live[i] & (g[SHARED][i] != 0.0));
    let any_shared = shared.iter().any(|&x| x);
    let mut back_side = [false; LANES];
    // Emission reached by this segment, weighted against next-event
    // estimation; then the surface seen from the ray's side, as
    // `TraceContext::shading` sees it, in its shading frame.
    let mut frame_s = [[0.0f32; LANES]; 3];
    let mut frame_t = [[0.0f32; LANES]; 3];
    let mut wo_local = [[0.0f32; LANES]; 3];
    for i in 0..LANES {
        let two_sided = g[TWO_SIDED][i] != 0.0;
        let dn = p.dir[0][i] * ng[0][i] + p.dir[1][i] * ng[1][i] + p.dir[2][i] * ng[2][i];
        let front = dn < 0.0;
        let emits = p.live[i] & (two_sided | front);
        let mut dist2 = 0.0;
        for a in 0..3 {
            let d = point[a][i] - p.prev_point[a][i];
            dist2 += d * d;
        }
        let cos = dn.abs();
        let light_pdf = if cos > 1e-7 {
            g[PMF_PER_AREA][i] * dist2 / cos
        } else {
            0.0
        };
        let weight = if p.prev_pdf[i] > 0.0 {
            power_heuristic(p.prev_pdf[i], light_pdf)
        } else {
            1.0
        };
        for a in 0..3 {
            let add = p.beta[a][i] * g[EMISSION + a][i] * weight;
            // A select, not a product with 0: a dead lane's values may be
            // NaN.
            p.radiance[a][i] += if emits { add } else { 0.0 };
        }
        // From behind: one-sided opaque surfaces are black there; the
        // others turn their normals, and a dielectric's index inverts.
        let back = dn > 0.0;
        back_side[i] = back;
        for a in 0..3 {
            ng[a][i] = if back { -ng[a][i] } else { ng[a][i] };
            ns[a][i] = if back { -ns[a][i] } else { ns[a][i] };
        }
        eta[i] = if back { 1.0 / eta[i] } else { eta[i] };
        // `Frame::from_normal`, written out: with the call (and with
        // `Dielectric::sample` called below) this loop ran scalar, the
        // Cornell box 20 % slower (32 spp, one thread, 3.3 -> 4.1 s).
        let n = [ns[0][i], ns[1][i], ns[2][i]];
        let sign = 1.0f32.copysign(n[2]);
        let fa = -1.0 / (sign + n[2]);
        let fb = n[0] * n[1] * fa;
        let fs = [1.0 + sign * n[0] * n[0] * fa, sign * fb, -sign * n[0]];
        let ft = [fb, sign + n[1] * n[1] * fa, -n[1]];
        for a in 0..3 {
            frame_s[a][i] = fs[a];
            frame_t[a][i] = ft[a];
        }
        // `wo` in the frame, for the dielectric (a Lambert BSDF needs only
        // that it is above the surface, which it is once nudged).
        if GENERAL {
            let wo = [-p.dir[0][i], -p.dir[1][i], -p.dir[2][i]];
            let mut w = [
                wo[0] * fs[0] + wo[1] * fs[1] + wo[2] * fs[2],
                wo[0] * ft[0] + wo[1] * ft[1] + wo[2] * ft[2],
                wo[0] * n[0] + wo[1] * n[1] + wo[2] * n[2],
            ];
            // Below the shading hemisphere at a grazing angle: onto it.
            if w[2] <= 0.0 {
                w[2] = 1e-4;
                let r = 1.0 / (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
                w = w.map(|c| c * r);
            }
            for a in 0..3 {
                wo_local[a][i] = w[a];
            }
        }
        // Black Lambert surfaces reflect nothing (a path ends there as
        // `path::li`'s would add nothing more).
        let black = !dielectric[i]
            & !shared[i]
            & (albedo[0][i] == 0.0)
            & (albedo[1][i] == 0.0)
            & (albedo[2][i] == 0.0);
        p.live[i] &=
            (!back | two_sided | dielectric[i] | shared[i]) & !black & (p.depth[i] < s.max_depth);
    }
    // The shared models as `TraceContext::shading` sees them: one-sided
    // opaque surfaces are black from behind.
    if any_shared {
        for i in 0..LANES {
            if shared[i] {
                let transmits = shared_material(s, g[SHARED][i]).flags().transmission;
                p.live[i] &= !back_side[i] | (g[TWO_SIDED][i] != 0.0) | transmits;
            }
        }
    }
    // Next-event estimation, its numbers drawn as `path::next_event` draws
    // them (also where a dielectric then skips it).
    let mut u_select = [0.0f32; LANES];
    let mut u_lobe = [0.0f32; LANES];
    let mut u_light = [[0.0f32; LANES]; 2];
    for i in 0..LANES {
        if p.live[i] {
            // The light's and the lobe's choice share a pair, as in
            // `path::walk`.
            [u_select[i], u_lobe[i]] = samplers[i].next_2d();
            [u_light[0][i], u_light[1][i]] = samplers[i].next_2d();
        }
    }
    let mut light = [0u32; LANES];
    let last = s.lights.len() - 1;
    for i in 0..LANES {
        // The light: the first whose running sum exceeds u × total, as
        // `Distribution1D::sample` (every weight is positive, so it is
        // the number of sums at or below it).
        let target = f64::from(u_select[i]) * s.total_weight;
        let sums = &s.running_sums[..last];
        let j = if last <= 64 {
            let mut j = 0;
            for &c in sums {
                j += (c <= target) as usize;
            }
            j
        } else {
            sums.partition_point(|&c| c <= target)
        };
        // SAFETY: j ≤ last < lights.len().
        light[i] = unsafe { at(&s.lights, j) };
    }
    // SAFETY: `S`'s features (`trace_group`'s contract); triangle indices.
    unsafe { s.tables.read::<S, _>(&LIGHT_READS, &light, l) };
    let mut shadow_origin = [[0.0f32; LANES]; 3];
    let mut wi = [[0.0f32; LANES]; 3];
    let mut shadow_tmax = [0.0f32; LANES];
    let mut shadow = [false; LANES];
    let mut contribution = [[0.0f32; LANES]; 3];
    // The light's direction in the shading frame and its density, for the
    // shared models.
    let mut wi_local = [[0.0f32; LANES]; 3];
    let mut light_pdf = [0.0f32; LANES];
    let mut shadow_leaves = [0u32; LANES];
    for i in 0..LANES {
        // A uniform point of the triangle.
        let Vec2 { x: b0, y: b1 } = square_to_triangle([u_light[0][i], u_light[1][i]]);
        let mut d = [0.0f32; 3];
        for a in 0..3 {
            let c = |v: usize| l[CORNERS + 3 * v + a][i];
            let q = c(0) * (1.0 - b0 - b1) + c(1) * b0 + c(2) * b1;
            d[a] = q - point[a][i];
        }
        let dist2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        let dist = dist2.sqrt();
        let w = d.map(|c| c / dist);
        let cos_light = -(w[0] * l[NORMAL][i] + w[1] * l[NORMAL + 1][i] + w[2] * l[NORMAL + 2][i]);
        let lit_side = (cos_light > 0.0) | (l[TWO_SIDED][i] != 0.0);
        let cos_light = cos_light.abs();
        // `TraceContext::consistent_side` and a Lambert BSDF's support.
        let wl = [
            w[0] * frame_s[0][i] + w[1] * frame_s[1][i] + w[2] * frame_s[2][i],
            w[0] * frame_t[0][i] + w[1] * frame_t[1][i] + w[2] * frame_t[2][i],
            w[0] * ns[0][i] + w[1] * ns[1][i] + w[2] * ns[2][i],
        ];
        let gn = w[0] * ng[0][i] + w[1] * ng[1][i] + w[2] * ng[2][i];
        let consistent = (gn != 0.0) & (wl[2] != 0.0) & ((gn > 0.0) == (wl[2] > 0.0));
        let reflects = wl[2] > 0.0;
        // (A shared model's BSDF, evaluated below, may transmit.)
        let ok = p.live[i]
            & !dielectric[i]
            & (dist2 > 0.0)
            & lit_side
            & (cos_light > 1e-7)
            & consistent
            & (reflects | shared[i]);
        // Area density → solid angle, with the selection: pdf = P(light)
        // d² / (A |cos θ_light|).
        let pdf = l[PMF_PER_AREA][i] * dist2 / cos_light;
        light_pdf[i] = pdf;
        for a in 0..3 {
            wi_local[a][i] = wl[a];
        }
        let cos = wl[2].abs();
        let weight = power_heuristic(pdf, wl[2].max(0.0) * FRAC_1_PI);
        // f cos / pdf with f = albedo / π.
        let scale = if ok {
            cos * FRAC_1_PI * weight / pdf
        } else {
            0.0
        };
        // `TraceContext::spawn`: off the surface on `wi`'s side (a live
        // lane's Lambert sample is on the normal's).
        let side = if GENERAL && gn < 0.0 { -1.0 } else { 1.0 };
        for a in 0..3 {
            contribution[a][i] = p.beta[a][i] * albedo[a][i] * l[EMISSION + a][i] * scale;
            shadow_origin[a][i] = offset_coordinate(point[a][i], side * ng[a][i]);
            wi[a][i] = w[a];
        }
        // Stop just short of the light, as `TraceContext::visible`.
        shadow_tmax[i] = dist * (1.0 - 1e-4);
        shadow[i] = ok;
        shadow_leaves[i] = leaving(GENERAL, gn, back_side[i], g[CONVEX][i]);
    }
    // The shared models' f and pdf, as `path::next_event` weighs them (a
    // BSDF of delta lobes only evaluates to 0 everywhere: no shadow ray,
    // as `next_event` skips it).
    if any_shared {
        for i in 0..LANES {
            if shadow[i] & shared[i] {
                let bsdf = seen_from(shared_material(s, g[SHARED][i]), back_side[i]);
                let wl = lane3(&wi_local, i);
                let wo = lane3(&wo_local, i);
                let f = bsdf.eval(wo, wl);
                shadow[i] = f != Vec3::ZERO;
                let pdf = light_pdf[i];
                let scale = wl.z.abs() * power_heuristic(pdf, bsdf.pdf(wo, wl)) / pdf;
                for a in 0..3 {
                    contribution[a][i] = p.beta[a][i] * f[a] * l[EMISSION + a][i] * scale;
                }
            }
        }
    }
    crate::stats::count_rays(shadow.iter().filter(|&&l| l).count() as u64);
    // SAFETY: `S`'s features (`trace_group`'s contract).
    unsafe {
        s.tracer.unoccluded::<S>(
            (&shadow_origin, &wi),
            &shadow_tmax,
            &shadow_leaves,
            &mut shadow,
        );
    }
    for i in 0..LANES {
        for a in 0..3 {
            p.radiance[a][i] += if shadow[i] { contribution[a][i] } else { 0.0 };
        }
    }
    // BSDF sampling, then Russian roulette.
    let mut u_bsdf = [[0.0f32; LANES]; 2];
    let mut u_rr = [0.0f32; LANES];
    for i in 0..LANES {
        p.depth[i] += 1;
        if p.live[i] {
            [u_bsdf[0][i], u_bsdf[1][i]] = samplers[i].next_2d();
            if p.depth[i] > RR_START_DEPTH {
                u_rr[i] = samplers[i].next_1d();
            }
        }
    }
    // The shared models' samples: direction (local), weight, pdf (0 for a
    // delta lobe, whose emitter hit gets weight 1) and η crossed.
    let mut shared_dir = [[0.0f32; LANES]; 3];
    let mut shared_weight = [[0.0f32; LANES]; 3];
    let mut shared_pdf = [0.0f32; LANES];
    let mut shared_eta = [1.0f32; LANES];
    let mut shared_ok = [false; LANES];
    if any_shared {
        for i in 0..LANES {
            if shared[i] & p.live[i] {
                let bsdf = seen_from(shared_material(s, g[SHARED][i]), back_side[i]);
                let wo = lane3(&wo_local, i);
                if let Some(bs) = bsdf.sample(wo, u_lobe[i], [u_bsdf[0][i], u_bsdf[1][i]]) {
                    for a in 0..3 {
                        shared_dir[a][i] = bs.wi[a];
                        shared_weight[a][i] = bs.weight[a];
                    }
                    shared_pdf[i] = if bs.delta { 0.0 } else { bs.pdf };
                    shared_eta[i] = bs.eta;
                    shared_ok[i] = true;
                }
            }
        }
    }
    for i in 0..LANES {
        let wo = [wo_local[0][i], wo_local[1][i], wo_local[2][i]];
        // Lambert: a cosine-weighted direction, weight ρ.
        let cosine = square_to_cosine_hemisphere([u_bsdf[0][i], u_bsdf[1][i]]);
        let lambert_pdf = cosine.z.max(0.0) * FRAC_1_PI;
        // Dielectric: `Dielectric::sample` with `fresnel_dielectric` and
        // `refract` written out in lane form, the same operations (called
        // per lane, its `Option` kept the loop scalar: glass 1.5 -> 1.75 s);
        // a change there must be mirrored here, and the glass test
        // compares the two. Reflection with probability F (exact
        // Fresnel), else refraction with weight tint / η²; F = 1 under
        // total internal reflection.
        let e = eta[i];
        let cos_i = wo[2].min(1.0);
        let sin2_t = (1.0 - cos_i * cos_i) / (e * e);
        let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
        let r_s = (cos_i - e * cos_t) / (cos_i + e * cos_t);
        let r_p = (e * cos_i - cos_t) / (e * cos_i + cos_t);
        let fresnel = if sin2_t >= 1.0 {
            1.0
        } else {
            0.5 * (r_s * r_s + r_p * r_p)
        };
        // `refract(wo, z, η)`, normalised.
        let disc = 1.0 - (1.0 - wo[2] * wo[2]) / (e * e);
        let k = wo[2] / e - disc.max(0.0).sqrt();
        let t = [-wo[0] / e, -wo[1] / e, -wo[2] / e + k];
        let rt = 1.0 / (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
        let transmits = (fresnel < 1.0) & (disc >= 0.0);
        let refracts = transmits & (u_lobe[i] >= fresnel);
        let local = if shared[i] {
            [shared_dir[0][i], shared_dir[1][i], shared_dir[2][i]]
        } else if !dielectric[i] {
            [cosine.x, cosine.y, cosine.z]
        } else if refracts {
            t.map(|c| c * rt)
        } else {
            [-wo[0], -wo[1], wo[2]]
        };
        let mut w = [0.0f32; 3];
        for a in 0..3 {
            w[a] = frame_s[a][i] * local[0] + frame_t[a][i] * local[1] + ns[a][i] * local[2];
        }
        let gn = w[0] * ng[0][i] + w[1] * ng[1][i] + w[2] * ng[2][i];
        let consistent = (gn != 0.0) & (local[2] != 0.0) & ((gn > 0.0) == (local[2] > 0.0));
        let sampled = if shared[i] {
            shared_ok[i]
        } else {
            dielectric[i] | (lambert_pdf > 0.0)
        };
        let mut alive = p.live[i] & consistent & sampled;
        for a in 0..3 {
            let weight = if shared[i] {
                shared_weight[a][i]
            } else if !dielectric[i] {
                albedo[a][i]
            } else if refracts {
                albedo[a][i] / (e * e)
            } else {
                1.0
            };
            p.beta[a][i] *= weight;
        }
        // (× 1 · 1 is exact: a reflection leaves it as it was.)
        let crossed = if shared[i] {
            shared_eta[i]
        } else if refracts {
            e
        } else {
            1.0
        };
        p.eta_scale[i] = p.eta_scale[i] * crossed * crossed;
        let q = if p.depth[i] > RR_START_DEPTH {
            let beta = lane3(&p.beta, i);
            rr_survival(beta, p.eta_scale[i])
        } else {
            1.0
        };
        alive &= u_rr[i] < q;
        // `TraceContext::spawn`: off the surface on `w`'s side (a live
        // lane's Lambert sample is on the normal's).
        let side = if GENERAL && gn < 0.0 { -1.0 } else { 1.0 };
        for a in 0..3 {
            p.beta[a][i] /= q;
            p.origin[a][i] = offset_coordinate(point[a][i], side * ng[a][i]);
            p.dir[a][i] = w[a];
            p.prev_point[a][i] = point[a][i];
        }
        p.leaves[i] = leaving(GENERAL, gn, back_side[i], g[CONVEX][i]);
        // After a delta lobe the emitter hit gets weight 1.
        p.prev_pdf[i] = if shared[i] {
            shared_pdf[i]
        } else if dielectric[i] {
            0.0
        } else {
            lambert_pdf
        };
        p.live[i] = alive;
    }
}

/// The convex object a ray leaves (its [`CONVEX`] component `convex`),
/// where it leaves on the object's outer side: `gn`, the ray's direction
/// against the geometric normal turned to the side the hit was seen
/// from, is positive on the front (outer) side of a hit from the front,
/// negative for a hit from behind (inside). 0 where not.
#[inline(always)]
fn leaving(general: bool, gn: f32, back: bool, convex: f32) -> u32 {
    if general && ((gn > 0.0) != back) {
        convex as u32
    } else {
        0
    }
}

/// The BSDF of a surface the shared code shades, from its [`SHARED`]
/// component (the material's index + 1).
#[inline]
fn shared_material(s: &WavefrontScene, shared: f32) -> Bsdf {
    s.shared_bsdfs[shared as usize - 1]
}

/// `bsdf` as `TraceContext::shading` sees it from the side the ray came
/// from.
#[inline]
fn seen_from(bsdf: Bsdf, back: bool) -> Bsdf {
    if back { bsdf.seen_from_back() } else { bsdf }
}

/// Sample indices `s0..s1` of the tile `(x0, y0, w, h)`'s pixels onto
/// `tile`, [`LANES`] pixels a group; `hits` counts per pixel the samples
/// whose camera ray met a surface.
#[allow(clippy::too_many_arguments)]
pub(crate) fn render_tile(
    s: &WavefrontScene,
    film: &FilmRays,
    seed: u32,
    tile: &mut FilmTile,
    (x0, y0, w, h): (u32, u32, u32, u32),
    s0: u32,
    s1: u32,
    hits: &mut [u32],
) {
    let pixels: Vec<(u32, u32)> = (y0..y0 + h)
        .flat_map(|y| (x0..x0 + w).map(move |x| (x, y)))
        .collect();
    let mut samplers = Vec::with_capacity(LANES);
    for group in pixels.chunks(LANES) {
        // One sampler per pixel, as `render_tile`'s scalar loop.
        samplers.clear();
        samplers.extend(group.iter().map(|&(x, y)| match s.kind {
            LaneKind::Avx512 => Sampler::for_pixel_avx512(x, y, seed),
            LaneKind::Avx2 => Sampler::for_pixel(x, y, seed),
        }));
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `WavefrontScene::new` checked the CPU's features.
        unsafe {
            let trace = match (s.kind, s.flat_lambert) {
                (LaneKind::Avx512, true) => trace_group_avx512::<false>,
                (LaneKind::Avx512, false) => trace_group_avx512::<true>,
                (LaneKind::Avx2, true) => trace_group_avx2::<false>,
                (LaneKind::Avx2, false) => trace_group_avx2::<true>,
            };
            trace(
                s,
                Group {
                    film,
                    pixels: group,
                    samplers: &mut samplers,
                    samples: (s0, s1),
                    tile: &mut *tile,
                    hits: &mut *hits,
                    tile_origin: (x0, y0),
                    tile_w: w,
                },
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::WatertightRay;
    use penumbra_shading::stats::TestRng;

    /// Every ray that the watertight test finds meeting one of a cloud of
    /// triangles passes the ball test, for origins near the cloud and up
    /// to 1e5 times its size away (where the ball test's rounding exceeds
    /// the padding and its |c - o| term must cover it), with rays aimed at
    /// the triangles' corners (on the ball's surface) and points; and rays
    /// aimed at the box's corners, outside the ball, or away from it are
    /// kept out.
    #[test]
    fn rays_that_meet_the_triangles_pass_the_ball_test() {
        let mut rng = TestRng::new(5);
        let unit = |rng: &mut TestRng| {
            Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0
        };
        let centre = Vec3::new(0.3, -0.2, 0.1);
        // Corners on a unit sphere around `centre`.
        let corner = |v: Vec3| centre + v.normalize();
        let triangles: Vec<[Vec3; 3]> = (0..200)
            .map(|_| {
                let a = unit(&mut rng);
                let (b, c) = (unit(&mut rng), unit(&mut rng));
                [corner(a), corner(a + b * 0.3), corner(a + c * 0.3)]
            })
            .collect();
        let points = || triangles.iter().flatten().copied();
        // As `Tracer::new` builds it.
        let ([lo, hi], pad) = padded(points());
        let b = bounding_ball(points(), [lo, hi], pad);
        let (mut hits, mut kept_out) = (0, 0);
        for n in 0..40_000 {
            let far = [3.0, 1e3, 1e5][n % 3];
            let k = n / 3 % triangles.len();
            let o = centre + unit(&mut rng).normalize() * far;
            let target = match n % 4 {
                0 => triangles[k][n % 3],
                1 => {
                    let [u, v] = [rng.next_f32(), rng.next_f32()];
                    let [p0, p1, p2] = triangles[k];
                    if u + v < 1.0 {
                        p0 + (p1 - p0) * u + (p2 - p0) * v
                    } else {
                        p0 + (p1 - p0) * (1.0 - u) + (p2 - p0) * (1.0 - v)
                    }
                }
                2 => Vec3::select(glam::BVec3::new(n % 5 < 2, n % 7 < 3, n % 11 < 5), lo, hi),
                _ => centre + unit(&mut rng) * 1.2,
            };
            let d = (target - o).normalize();
            let ray = WatertightRay::new(o, d);
            let meets = triangles
                .iter()
                .any(|&[p0, p1, p2]| ray.intersect(p0, p1, p2, f32::INFINITY).is_some());
            let lanes = |v: Vec3| [[v.x; LANES], [v.y; LANES], [v.z; LANES]];
            let pass = ball(&lanes(o), &lanes(d), &b)[0];
            if meets {
                hits += 1;
                assert!(pass, "ray {n} from {o} along {d} meets a triangle");
            }
            if n % 4 == 2 && far == 3.0 {
                kept_out += usize::from(!pass);
            }
            // Away from the ball: behind the ray.
            let away = (o - centre).normalize();
            assert!(!ball(&lanes(o), &lanes(away), &b)[0], "ray {n} away");
        }
        assert!(hits > 15_000, "{hits} hits");
        assert!(kept_out > 2_000, "{kept_out} rays kept out");
    }

    /// An icosahedron of circumradius `r` around `c`: its faces,
    /// counter-clockwise seen from outside, and their unit outward normals.
    fn icosahedron(c: Vec3, r: f32) -> (Vec<[Vec3; 3]>, Vec<Vec3>) {
        let g = (1.0 + 5f32.sqrt()) / 2.0;
        let v: Vec<Vec3> = [
            (-1.0, g, 0.0),
            (1.0, g, 0.0),
            (-1.0, -g, 0.0),
            (1.0, -g, 0.0),
            (0.0, -1.0, g),
            (0.0, 1.0, g),
            (0.0, -1.0, -g),
            (0.0, 1.0, -g),
            (g, 0.0, -1.0),
            (g, 0.0, 1.0),
            (-g, 0.0, -1.0),
            (-g, 0.0, 1.0),
        ]
        .iter()
        .map(|&(x, y, z)| c + Vec3::new(x, y, z).normalize() * r)
        .collect();
        let f = [
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ];
        let t: Vec<[Vec3; 3]> = f.iter().map(|k| k.map(|i| v[i])).collect();
        let n = t
            .iter()
            .map(|[a, b, c]| (*b - *a).cross(*c - *a).normalize())
            .collect();
        (t, n)
    }

    /// The convexity check that lets a ray leaving an object skip its
    /// tree: an icosahedron near the origin and far from it, also with its
    /// winding turned (a mirrored instance, its front normals kept
    /// outward), is convex; with a corner pushed in, turned inside out
    /// (fronts inward), or a box (coplanar faces, within the margin) not.
    #[test]
    fn convex_objects_are_told_from_the_others() {
        for (c, r) in [(Vec3::ZERO, 1.0), (Vec3::splat(1e3), 0.5)] {
            let (t, n) = icosahedron(c, r);
            assert!(convex(&t, &n), "{c} {r}");
            let turned: Vec<[Vec3; 3]> = t.iter().map(|&[a, b, c]| [a, c, b]).collect();
            assert!(convex(&turned, &n));
            let inward: Vec<Vec3> = n.iter().map(|&v| -v).collect();
            assert!(!convex(&t, &inward));
            // One corner pushed in to 0.3 of its radius, below the plane of
            // its five neighbours (at 0.45): a dent.
            let corner = t[0][0];
            let dented: Vec<[Vec3; 3]> = t
                .iter()
                .map(|f| f.map(|v| if v == corner { c + (v - c) * 0.3 } else { v }))
                .collect();
            let dented_n: Vec<Vec3> = dented
                .iter()
                .map(|[a, b, c]| (*b - *a).cross(*c - *a).normalize())
                .collect();
            assert!(!convex(&dented, &dented_n));
        }
        let cube = penumbra_scene::primitives::cuboid(Vec3::ZERO, Vec3::ONE);
        let t: Vec<[Vec3; 3]> = cube
            .indices
            .iter()
            .map(|k| k.map(|i| cube.positions[i as usize]))
            .collect();
        let n: Vec<Vec3> = t
            .iter()
            .map(|[a, b, c]| (*b - *a).cross(*c - *a).normalize())
            .collect();
        assert!(!convex(&t, &n));
    }
}
