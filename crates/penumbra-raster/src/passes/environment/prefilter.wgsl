// The environment prefilter (compute, once per environment; host:
// passes/environment/mod.rs): level i ≥ 1 of the prefiltered lat-long map
// holds, at each texel's map direction n, the environment convolved with a
// GGX lobe of α = r², r = i / (levels − 1), under Karis's (2013) n = v = r
// assumption:
//   L̃(n) = Σ_k L(l_k) (n·l_k) / Σ_k (n·l_k),
// l_k the mirror of n about half vectors h_k drawn from D(h) cos θh
// (Hammersley points). Each sample reads the source map's mip chain at the
// level whose texel solid angle matches the sample's, 1/(N pdf(l)) with
// pdf(l) = D(h) cos θh / (4 v·h) (filtered importance sampling, Křivánek &
// Colbert 2008), so few samples give a smooth result. Appended to the
// shading library (which ends with common.wgsl).

@group(0) @binding(0) var source_map: texture_2d<f32>;
@group(0) @binding(1) var source_sampler: sampler;
@group(0) @binding(2) var target_level: texture_storage_2d<rgba16float, write>;
@group(0) @binding(3) var<uniform> prefilter: GpuPrefilterParams;

// Added to the level whose texels match the sample's solid angle (Colbert
// and Křivánek suggest 1; less blurs less).
const LOD_BIAS: f32 = 0.5;

// Hammersley point i of n: ((i + ½)/n, radical inverse of i in base 2).
fn hammersley(i: u32, n: u32) -> vec2<f32> {
    return vec2<f32>((f32(i) + 0.5) / f32(n), f32(reverseBits(i)) * 2.3283064365386963e-10);
}

@compute @workgroup_size(8, 8)
fn prefilter_level(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= prefilter.width || id.y >= prefilter.height {
        return;
    }
    let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(f32(prefilter.width), f32(prefilter.height));
    let n = latlong_direction(uv);
    let f = frame_from_normal(n);
    let texel = (2.0 * PI / prefilter.source_width) * (PI / prefilter.source_height);
    var sum = vec3<f32>(0.0);
    var weight = 0.0;
    for (var i = 0u; i < prefilter.samples; i++) {
        let hs = ggx_sample_half(hammersley(i, prefilter.samples), prefilter.alpha);
        let h = f.s * hs.x + f.t * hs.y + f.n * hs.z;
        let l = 2.0 * dot(n, h) * h - n;
        let nl = dot(n, l);
        if nl <= 0.0 || hs.w <= 0.0 {
            continue;
        }
        // n = v: v·h = cos θh, so pdf(l) = D(h) cos θh / (4 cos θh).
        let pdf = hs.w / (4.0 * hs.z);
        let sin_l = max(sqrt(max(1.0 - l.y * l.y, 0.0)), 1e-3);
        let omega_s = 1.0 / (f32(prefilter.samples) * pdf);
        let lod = clamp(0.5 * log2(omega_s / (texel * sin_l)) + LOD_BIAS, 0.0, prefilter.source_levels - 1.0);
        // Karis's n·l weight (the exact n = v weight, G2(n, l), measured
        // brighter at grazing views against the CPU).
        sum += textureSampleLevel(source_map, source_sampler, latlong_uv(l), lod).xyz * nl;
        weight += nl;
    }
    textureStore(target_level, vec2<i32>(id.xy), vec4<f32>(sum / max(weight, 1e-8), 1.0));
}
