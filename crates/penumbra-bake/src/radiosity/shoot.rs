//! Progressive refinement (Cohen, Chen, Wallace, Greenberg 1988, "A
//! Progressive Refinement Approach to Fast Radiosity Image Generation")
//! with form factors by ray casting.
//!
//! Each patch j keeps its irradiance `E_j` and its *unshot* radiosity
//! `ΔB_j` [W/m²]; its unshot power is `Φ_j = Y(ΔB_j) A_j` (Y: Rec.709
//! luminance, the scalar that ranks and measures colours). Initially
//! `ΔB_j = π Le_j + ρ_j E0_j` (emission and the reflected light of the
//! lights that shot first), `E_j = E0_j`. Each iteration:
//!
//! 1. the patch i with the largest unshot power shoots: its power
//!    `Φ_i = ΔB_i A_i` (RGB) leaves along K_i rays from points uniform over
//!    its footprint, in cosine-distributed directions about the footprint's
//!    front normal, so ray r reaches patch j with probability
//!    `F_ij` (the form factor) and `hits_ij / K_i` estimates it;
//! 2. a ray that hits patch j from the front delivers `Φ_i / K_i`:
//!    `E_j += Φ_i / (K_i A_j)` and `ΔB_j += ρ_j Φ_i / (K_i A_j)` — the
//!    shooting form of `B_j = E_j^emit + ρ_j Σ_i B_i F_ij` with reciprocity
//!    `A_i F_ij = A_j F_ji`;
//! 3. `ΔB_i = 0`.
//!
//! Rays that escape, hit an analytic area light (a black emitter), hit a
//! surface from its back, or land on an instance without patches deliver
//! nothing. The map holds one side of each surface (the front); light
//! reaching the back of a two-sided surface is lost to the solve (exact
//! for closed rooms seen from inside; in open scenes the backs of thin
//! two-sided surfaces receive nothing). A double-sided emitter also shoots
//! its back emission `π Le A` once, into its back hemisphere.
//!
//! Since ρ ≤ 1 and a shot delivers at most what it carries, the total
//! unshot power falls at every iteration (strictly if some ρ < 1 or some
//! ray is lost). The solve stops when it is below `tolerance` times the
//! emitted power (patch emission plus the power the first lights
//! delivered), or after a safety cap of shots.
//!
//! **Ray budget.** The solve casts about `rays_per_patch × patches` rays.
//! Shot i gets `K_i = Φ_i / φ` rays (at least [`MIN_RAYS_PER_SHOT`]), where
//! `φ` is the power per ray that spends the budget left on the power still
//! to shoot, estimated as a geometric series of the unshot power above the
//! stopping level: `(U − T P) / (1 − r)`, with r the fraction of shot power
//! that came back as unshot power so far (blended with the scenes' mean
//! reflectance as a prior). Every ray then carries about the same power,
//! so the noise in each E_j depends on the rays it received, not on which
//! shot they came from.
//!
//! **Reproducibility.** Shots are sequential; the rays of a shot are traced
//! in parallel, ray r of shot s from patch i with the sampler of "pixel"
//! (i, s), sample r, and the hits are counted per patch after sorting, so
//! the result does not depend on the thread count.

use super::max_tree::MaxTree;
use super::patches::{NONE, Patches, sample_footprint};
use crate::baker::{BakeProgress, Prepared};
use crate::convergence::ConvergenceStep;
use glam::DVec3;
use penumbra_image::Rgb;
use penumbra_shading::Frame;
use penumbra_shading::sampling::{Sampler, square_to_cosine_hemisphere};
use penumbra_trace::ray::{Ray, offset_ray_origin};
use rayon::prelude::*;
use std::time::Instant;

/// Fewest rays a shot casts (a weak shooter still spreads its power).
pub const MIN_RAYS_PER_SHOT: u64 = 32;

/// Most rays one shot casts (bounds the memory of its hit list).
pub const MAX_RAYS_PER_SHOT: u64 = 1 << 22;

/// Rays a parallel task traces together.
const RAYS_PER_TASK: usize = 256;

/// Safety cap on the shots: `SHOT_CAP_PER_SHOOTER` per shooter, plus
/// [`SHOT_CAP_BASE`].
pub const SHOT_CAP_PER_SHOOTER: u64 = 500;
pub const SHOT_CAP_BASE: u64 = 10_000;

/// Rec.709 luminance in f64.
fn lum(c: DVec3) -> f64 {
    0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
}

fn d(c: Rgb) -> DVec3 {
    c.as_dvec3()
}

/// The solution and its record.
pub(crate) struct Solution {
    /// Per patch, E on the front side [W/m²].
    pub irradiance: Vec<Rgb>,
    pub steps: Vec<ConvergenceStep>,
    /// Power emitted into the scene [W, luminance-weighted].
    pub emitted_power: f64,
    /// The shot cap stopped the solve before the tolerance.
    pub capped: bool,
}

/// Solves for E with the first lights' irradiance `first` (per patch).
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve(
    prep: &Prepared<'_>,
    patches: &Patches,
    first: &[Rgb],
    tolerance: f64,
    rays_per_patch: u32,
    seed: u32,
    start: Instant,
    progress: Option<BakeProgress<'_>>,
) -> Solution {
    let list = &patches.patches;
    let n = list.len();
    let area: Vec<f64> = list.iter().map(|p| p.area as f64).collect();
    let rho: Vec<DVec3> = list.iter().map(|p| d(p.reflectance)).collect();
    let mut e: Vec<DVec3> = first.iter().map(|&x| d(x)).collect();
    let mut unshot: Vec<DVec3> = (0..n)
        .map(|i| d(list[i].exitance) + rho[i] * e[i])
        .collect();
    // Back-emission shooters: slots n.. of the tree.
    let back: Vec<usize> = (0..n).filter(|&i| list[i].emits_back).collect();
    let mut back_power: Vec<DVec3> = back
        .iter()
        .map(|&i| d(list[i].exitance) * area[i])
        .collect();
    let mut slot_power: Vec<f64> = (0..n).map(|i| lum(unshot[i]) * area[i]).collect();
    slot_power.extend(back_power.iter().map(|&p| lum(p)));
    let emitted: f64 = (0..n)
        .map(|i| (lum(d(list[i].exitance)) + lum(e[i])) * area[i])
        .sum::<f64>()
        + back_power.iter().map(|&p| lum(p)).sum::<f64>();
    let mut total_unshot: f64 = slot_power.iter().sum();
    let mut tree = MaxTree::new(slot_power);
    let step = |iteration: u32, shooter: Option<u32>, u: f64| ConvergenceStep {
        iteration,
        shooter,
        unshot_power: u,
        unshot_fraction: if emitted > 0.0 { u / emitted } else { 0.0 },
        seconds: start.elapsed().as_secs_f64(),
    };
    let mut steps = vec![step(0, None, total_unshot)];
    let stop = tolerance * emitted;
    // Prior of the returned fraction: the area-weighted mean reflectance.
    let total_area: f64 = area.iter().sum();
    let prior = if total_area > 0.0 {
        ((0..n).map(|i| lum(rho[i]) * area[i]).sum::<f64>() / total_area).min(0.99)
    } else {
        0.0
    };
    let budget = rays_per_patch as u64 * n as u64;
    let (mut rays_used, mut shot_power, mut returned) = (0u64, 0.0f64, 0.0f64);
    let cap = SHOT_CAP_PER_SHOOTER * (n + back.len()) as u64 + SHOT_CAP_BASE;
    let u0 = total_unshot;
    let mut capped = false;
    let mut shots = 0u64;
    while emitted > 0.0 && total_unshot >= stop {
        if shots >= cap {
            capped = true;
            break;
        }
        let Some((slot, phi)) = tree.max() else { break };
        if phi.is_nan() || phi <= 0.0 {
            break;
        }
        // The shooter's power, leaving its front or (slots ≥ n) its back.
        let (i, side, power) = if slot < n {
            let p = unshot[slot] * area[slot];
            unshot[slot] = DVec3::ZERO;
            (slot, 1.0f32, p)
        } else {
            let k = slot - n;
            let p = back_power[k];
            back_power[k] = DVec3::ZERO;
            (back[k], -1.0f32, p)
        };
        // Rays: this shot's share of the budget left (see the module docs).
        let r = ((returned + prior * emitted) / (shot_power + emitted)).min(0.99);
        let future = ((total_unshot - stop).max(0.0) / (1.0 - r)).max(phi);
        let left = budget.saturating_sub(rays_used);
        let k_rays = ((phi / future * left as f64).round() as u64)
            .clamp(MIN_RAYS_PER_SHOT, MAX_RAYS_PER_SHOT);
        tree.set(slot, 0.0);
        total_unshot -= phi;
        shot_power += phi;
        rays_used += k_rays;
        let mut hits = trace_shot(prep, patches, i, side, k_rays, shots as u32, seed);
        hits.sort_unstable();
        let per_ray = power / k_rays as f64;
        let mut a = 0;
        while a < hits.len() {
            let j = hits[a];
            let b = hits[a..].partition_point(|&x| x == j) + a;
            let j = j as usize;
            let de = per_ray * (b - a) as f64 / area[j];
            e[j] += de;
            let before = lum(unshot[j]) * area[j];
            unshot[j] += rho[j] * de;
            let after = lum(unshot[j]) * area[j];
            tree.set(j, after);
            total_unshot += after - before;
            returned += after - before;
            a = b;
        }
        shots += 1;
        steps.push(step(shots as u32, Some(i as u32), total_unshot));
        if let Some(p) = progress
            && shots.is_multiple_of(256)
        {
            let span = (u0 / stop.max(f64::MIN_POSITIVE)).ln().max(1e-9);
            let done = ((u0 / total_unshot.max(f64::MIN_POSITIVE)).ln() / span).clamp(0.0, 1.0);
            p("radiosity: shooting", (done * 1000.0) as u64, 1000);
        }
    }
    Solution {
        irradiance: e.iter().map(|x| x.as_vec3()).collect(),
        steps,
        emitted_power: emitted,
        capped,
    }
}

/// The patches hit by the `k_rays` rays of shot `shot` from patch `i`
/// (front side when `side` is 1, back when −1), in ray order; rays that
/// deliver nothing are left out.
fn trace_shot(
    prep: &Prepared<'_>,
    patches: &Patches,
    i: usize,
    side: f32,
    k_rays: u64,
    shot: u32,
    seed: u32,
) -> Vec<u32> {
    let (scene, geometry) = (prep.scene, &prep.geometry);
    let pieces = patches.pieces_of(i);
    let area = patches.patches[i].area;
    (0..k_rays as u32)
        .into_par_iter()
        .with_min_len(RAYS_PER_TASK)
        // One sampler per task, moved from ray to ray (the same points as
        // a new one per ray, without its set-up).
        .map_init(
            || Sampler::for_pixel(i as u32, shot, seed),
            |sampler, r| {
                sampler.start_sample(r);
                let u_pick = sampler.next_1d();
                let (triangle, b) = sample_footprint(pieces, area, u_pick, sampler.next_2d());
                let [p0, p1, p2] = geometry.triangles[triangle as usize];
                let p = p0 * (1.0 - b.x - b.y) + p1 * b.x + p2 * b.y;
                let n = geometry.front_normal_scaled(triangle).normalize() * side;
                let dir =
                    Frame::from_normal(n).to_world(square_to_cosine_hemisphere(sampler.next_2d()));
                let ray = Ray::new(offset_ray_origin(p, n), dir);
                let Some(hit) = geometry.intersect(scene, &ray) else {
                    return NONE;
                };
                if hit.light.is_some() || hit.ng.dot(dir) >= 0.0 {
                    return NONE;
                }
                match prep.atlas.locate(scene, geometry, &hit) {
                    Some((page, uv)) => patches.patch_at(&prep.atlas, page, uv),
                    None => NONE,
                }
            },
        )
        .filter(|&j| j != NONE)
        .collect()
}
