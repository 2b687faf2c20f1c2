// Environment light of the forward passes (host:
// crates/penumbra-raster/src/passes/environment/mod.rs): the radiance a
// surface reflects of the environment (constant or lat-long map), diffuse by
// its SH9 irradiance, specular by the prefiltered map and the split sum.
// Appended to the forward module after forward.wgsl (uses Surface).

@group(0) @binding(20) var<uniform> environment: GpuEnvironment;
@group(0) @binding(21) var environment_map: texture_2d<f32>;
@group(0) @binding(22) var environment_sampler: sampler;
@group(0) @binding(23) var<storage, read> environment_materials: array<GpuEnvMaterial>;

// The environment's radiance arriving from world direction d, prefiltered
// for a GGX lobe of perceptual roughness r (0: the map itself, bilinear).
fn environment_radiance(d: vec3<f32>, roughness: f32) -> vec3<f32> {
    let m = env_to_map(d, environment.rotation_cos, environment.rotation_sin);
    let lod = clamp(roughness, 0.0, 1.0) * (environment.mip_count - 1.0);
    return textureSampleLevel(environment_map, environment_sampler, latlong_uv(m), lod).xyz;
}

// Most taps per axis of a pixel's footprint (environment_footprint).
const FOOTPRINT_TAPS_MAX: u32 = 4u;

// The map's own radiance (level 0) box-filtered over a pixel's footprint:
// the mean over an n×n grid of directions d + u·d_dx + v·d_dy, u, v at the
// cell centres of (−½, ½)², where d_dx, d_dy are d's change across the pixel
// — the CPU's box pixel filter, for what the map shows sharply (delta
// lobes, the background). n is the footprint's extent in texels of the
// map's height (π radians), rounded up, from 1 to FOOTPRINT_TAPS_MAX.
fn environment_footprint(d: vec3<f32>, d_dx: vec3<f32>, d_dy: vec3<f32>) -> vec3<f32> {
    let texels_per_radian = f32(textureDimensions(environment_map, 0).y) / PI;
    let extent = max(length(d_dx), length(d_dy)) * texels_per_radian;
    // `extent` is NaN or ∞ only with non-finite derivatives: one lookup.
    var n = 1u;
    if extent > 1.0 {
        n = u32(min(ceil(extent), f32(FOOTPRINT_TAPS_MAX)));
    }
    var sum = vec3<f32>(0.0);
    for (var j = 0u; j < n; j++) {
        for (var i = 0u; i < n; i++) {
            let uv = (vec2<f32>(f32(i), f32(j)) + 0.5) / f32(n) - 0.5;
            sum += environment_radiance(normalize(d + uv.x * d_dx + uv.y * d_dy), 0.0);
        }
    }
    return sum / f32(n * n);
}

// Taps of the glossy lobe per pixel: ENV_LOBE_TAPS² visible-normal samples
// on a fixed grid (0: one lookup in the dominant direction; host:
// RasterOptions::environment_taps).
override ENV_LOBE_TAPS: u32 = 0u;

// The environment's radiance averaged over a glossy lobe of perceptual
// roughness r seen from s.wo_local: Σ L̃(l_k, r_tap) G2/G1 / Σ G2/G1 over
// visible-normal samples m_k (l_k their mirror of ωo; the G2/G1 weights of
// the estimator without F, which the split sum's E holds), each tap read
// from the map prefiltered at r_tap = r · TAP_ROUGHNESS so the taps blend;
// with ENV_LOBE_TAPS = 0 the prefiltered map at r along the dominant
// direction.
const TAP_ROUGHNESS: f32 = 0.1;

fn glossy_radiance(s: Surface, r: vec3<f32>, roughness: f32) -> vec3<f32> {
    let alpha = roughness * roughness;
    let n = s.frame.n;
    if ENV_LOBE_TAPS == 0u || alpha < 1e-3 {
        return environment_radiance(specular_dominant_direction(n, r, alpha), roughness);
    }
    let wo = s.wo_local;
    let g1 = 1.0 / (1.0 + ggx_lambda(alpha, wo));
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var j = 0u; j < ENV_LOBE_TAPS; j++) {
        for (var i = 0u; i < ENV_LOBE_TAPS; i++) {
            let u = (vec2<f32>(f32(i), f32(j)) + 0.5) / f32(ENV_LOBE_TAPS);
            let m = ggx_sample_visible(alpha, wo, u);
            let l = 2.0 * dot(wo, m) * m - wo;
            if l.z <= 0.0 {
                continue;
            }
            let w = ggx_g2(alpha, wo, l) / g1;
            let lw = s.frame.s * l.x + s.frame.t * l.y + n * l.z;
            sum += w * environment_radiance(lw, roughness * TAP_ROUGHNESS);
            weight += w;
        }
    }
    if weight <= 0.0 {
        return environment_radiance(specular_dominant_direction(n, r, alpha), roughness);
    }
    return sum / weight;
}

// Radiance towards the viewer reflected from the environment, kA the
// ambient occlusion at the surface (1 = open):
//  - diffuse: c_diff · kA · E_env(n) / π, E_env by SH9;
//  - specular: so(n·v, kA, α) × (split sum of the prefiltered map, or the
//    exact F of a delta lobe times the map along the mirror direction).
fn environment_light(s: Surface, k_a: f32) -> vec3<f32> {
    let em = s.env;
    let n = s.frame.n;
    let mu = clamp(s.wo_local.z, 0.0, 1.0);
    let wo = s.frame.s * s.wo_local.x + s.frame.t * s.wo_local.y + n * s.wo_local.z;
    var out = vec3<f32>(0.0);
    if any(em.diffuse > vec3<f32>(0.0)) {
        var c = em.diffuse;
        if em.diffuse_kc != 0u {
            let ab = env_split_sum(mu, em.roughness);
            c = c * max(vec3<f32>(1.0) - (em.d_f0 * ab.x + (vec3<f32>(em.d_f90) - em.d_f0) * ab.y), vec3<f32>(0.0));
        }
        out += c * (k_a / PI) * sh9_irradiance(environment.sh, n);
    }
    if em.kind == ENV_SPEC_NONE {
        return out;
    }
    let r = 2.0 * dot(n, wo) * n - wo;
    let alpha = em.roughness * em.roughness;
    var spec = vec3<f32>(0.0);
    switch em.kind {
        case ENV_SPEC_SPLIT_SUM: {
            let ab = env_split_sum(mu, em.roughness);
            let e = em.f0 * ab.x + (em.f90 - em.f0) * ab.y;
            spec = e * glossy_radiance(s, r, em.roughness);
            if any(em.transmit > vec3<f32>(0.0)) {
                let t = max(vec3<f32>(1.0) - e, vec3<f32>(0.0)) * em.transmit;
                spec += t * environment_radiance(-wo, em.roughness);
            }
        }
        case ENV_SPEC_DELTA_CONSTANT: {
            spec = em.f0 * environment_footprint(r, s.mirror_dx, s.mirror_dy);
        }
        case ENV_SPEC_DELTA_CONDUCTOR: {
            var f: vec3<f32>;
            if em.fresnel == FRESNEL_SCHLICK {
                f = schlick(f0_from_ior(em.eta, em.k), mu);
            } else {
                f = fresnel_conductor(mu, em.eta, em.k);
            }
            spec = clamp(f, vec3<f32>(0.0), vec3<f32>(1.0)) * environment_footprint(r, s.mirror_dx, s.mirror_dy);
        }
        case ENV_SPEC_DELTA_DIELECTRIC: {
            let f = fresnel_dielectric(mu, em.ior);
            let reflected = environment_footprint(r, s.mirror_dx, s.mirror_dy);
            let through = environment_footprint(-wo, s.through_dx, s.through_dy);
            spec = f * reflected + (1.0 - f) * em.transmit * through;
        }
        default: {}
    }
    return out + specular_occlusion(mu, k_a, alpha) * spec;
}

// The background pass: a full-screen triangle at depth 0 (reversed depth:
// the far plane, the prepass's clear value), depth-tested Equal, so it
// shades exactly the samples no geometry covers, with the map's radiance
// along the pixel's view rays (level 0, box-filtered over the pixel).
struct BackgroundOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
}

@vertex
fn vs_background(@builtin(vertex_index) i: u32) -> BackgroundOut {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    var out: BackgroundOut;
    out.ndc = uv * 2.0 - 1.0;
    out.clip = vec4<f32>(out.ndc, 0.0, 1.0);
    return out;
}

@fragment
fn fs_background(in: BackgroundOut) -> @location(0) vec4<f32> {
    var d: vec3<f32>;
    if camera.back.w > 0.5 {
        d = -camera.back.xyz;
    } else {
        let p = environment.inv_view_proj * vec4<f32>(in.ndc, 0.5, 1.0);
        d = normalize(p.xyz / p.w - camera.eye.xyz);
    }
    // Alpha 0: not a surface (the surfaces write 1), as the clear colour;
    // auto exposure meters the pixels of alpha > ½.
    return vec4<f32>(environment_footprint(d, dpdx(d), dpdy(d)), 0.0);
}
