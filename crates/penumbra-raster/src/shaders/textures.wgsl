// Textures and vertex attributes of the forward passes (host: textures.rs,
// scene_gpu.rs). Twins of the CPU's lookups: Texture::sample (wrap modes,
// KHR_texture_transform, bilinear at level 0) and TraceContext::shading
// (base colour × texture × COLOR_0, roughness × G, metallic × B, emission ×
// its texture). Minified textures are read trilinearly from box-filtered
// levels. Appended to the forward module.

// Per vertex of every mesh (GpuInstance::first_uv, first_uv1 /
// first_color): UV sets 0 and 1 in one array.
@group(0) @binding(25) var<storage, read> vertex_uvs: array<vec2<f32>>;
@group(0) @binding(26) var<storage, read> vertex_colors: array<vec4<f32>>;
@group(0) @binding(27) var<storage, read> textures: array<GpuTexture>;
// Every level of every texture, in its format (TEXEL_*): 8-bit r, g, b in
// one word, or IEEE halves (r | g << 16, b) in two.
@group(0) @binding(28) var<storage, read> texels: array<u32>;
@group(0) @binding(29) var<storage, read> material_textures: array<GpuMaterialTextures>;
// Per vertex: tangent of UV set 0 (xyz) and handedness (w = ±1).
@group(0) @binding(30) var<storage, read> vertex_tangents: array<vec4<f32>>;

// One texture's mip chain in `texels`, level 0 first, each level
// row-major from the top row.
struct GpuTexture {
    // KHR_texture_transform: u' = u_row · (u, v, 1), v' = v_row · (u, v, 1).
    u_row: vec4<f32>,
    v_row: vec4<f32>,
    width: u32,
    height: u32,
    levels: u32,
    first: u32,
    wrap_u: u32,
    wrap_v: u32,
    format: u32,
    // The UV set the texture reads (0 or 1).
    uv_set: u32,
}

struct GpuMaterialTextures {
    albedo: u32,
    metallic_roughness: u32,
    emission: u32,
    normal: u32,
    normal_scale: f32,
    occlusion: u32,
    occlusion_strength: f32,
    alpha_mode: u32,
    alpha_texture: u32,
    alpha_factor: f32,
    alpha_cutoff: f32,
    _pad0: u32,
}

// SLOT_* bits (gpu.rs) of the texture slots some material of the scene
// fills: the lookups of the others are left out of the pipeline, since a
// software rasteriser (lavapipe) runs every branch a lane of the SIMD
// batch could take, untextured fragments included.
override TEXTURE_SLOTS: u32 = 0xffffffffu;
const SLOT_ALBEDO: u32 = 1u;
const SLOT_METALLIC_ROUGHNESS: u32 = 2u;
const SLOT_EMISSION: u32 = 4u;
const SLOT_NORMAL: u32 = 8u;
const SLOT_OCCLUSION: u32 = 16u;
const SLOT_ALPHA: u32 = 32u;

// Whether texture `index` of the slot `slot` (a SLOT_* bit) is read: the
// pipeline has the slot and the material fills it.
fn has_texture(slot: u32, index: u32) -> bool {
    return (TEXTURE_SLOTS & slot) != 0u && index != NO_TEXTURE;
}

const ALPHA_OPAQUE: u32 = 0u;
const ALPHA_MASK: u32 = 1u;
const ALPHA_BLEND: u32 = 2u;

const NO_TEXTURE: u32 = 0xffffffffu;
const NO_VERTEX_DATA: u32 = 0xffffffffu;
const WRAP_REPEAT: u32 = 0u;
const WRAP_CLAMP: u32 = 1u;
const WRAP_MIRROR: u32 = 2u;
const TEXEL_HALF: u32 = 0u;
const TEXEL_SRGB8: u32 = 1u;
const TEXEL_UNORM8: u32 = 2u;

// Bits 1 << WRAP_* of the wrap modes and 1 << TEXEL_* of the formats the
// scene's textures use (TEXTURE_SLOTS says why).
override WRAP_MODES: u32 = 0xffffffffu;
override TEXEL_FORMATS: u32 = 0xffffffffu;

// Whether a texture of the value `value` takes the branch of `choice`, one
// of the values the pipeline's mask `mask` allows: always where it is the
// only one, never where the mask lacks it.
fn takes(mask: u32, choice: u32, value: u32) -> bool {
    let bit = 1u << choice;
    return (mask & bit) != 0u && (value == choice || mask == bit);
}

// Wrap::index: the texel for index i of an axis of n texels.
fn wrap_texel(mode: u32, i: i32, n: i32) -> i32 {
    if takes(WRAP_MODES, WRAP_CLAMP, mode) {
        return clamp(i, 0, n - 1);
    }
    if takes(WRAP_MODES, WRAP_MIRROR, mode) {
        let m = ((i % (2 * n)) + 2 * n) % (2 * n);
        return select(2 * n - 1 - m, m, m < n);
    }
    return ((i % n) + n) % n;
}

struct TextureLevel {
    first: u32,
    width: i32,
    height: i32,
}

// Words per texel of a format.
fn texel_words(format: u32) -> u32 {
    return select(1u, 2u, format == TEXEL_HALF);
}

// Level l of t: max(1, size >> l), after the levels above it.
fn texture_level(t: GpuTexture, level: u32) -> TextureLevel {
    var first = t.first;
    var w = t.width;
    var h = t.height;
    for (var l = 0u; l < level; l++) {
        first += w * h * texel_words(t.format);
        w = max(w / 2u, 1u);
        h = max(h / 2u, 1u);
    }
    return TextureLevel(first, i32(w), i32(h));
}

// An IEEE half float (the low 16 bits of h) as f32, exactly; decoded by
// hand because unpack2x16float needs a capability not every adapter has.
// The host writes no infinities or NaNs.
fn half_to_f32(h: u32) -> f32 {
    let e = (h >> 10u) & 0x1fu;
    let m = h & 0x3ffu;
    var v = f32(m) * exp2(-24.0);
    if e != 0u {
        v = bitcast<f32>(((e + 112u) << 23u) | (m << 13u));
    }
    return select(v, -v, (h & 0x8000u) != 0u);
}

// srgb_to_linear of penumbra_shading::color, per channel.
fn srgb_to_linear3(c: vec3<f32>) -> vec3<f32> {
    return select(pow((c + 0.055) / 1.055, vec3<f32>(2.4)), c / 12.92, c <= vec3<f32>(0.04045));
}

fn texel_at(t: GpuTexture, lv: TextureLevel, x: i32, y: i32) -> vec3<f32> {
    let xi = wrap_texel(t.wrap_u, x, lv.width);
    let yi = wrap_texel(t.wrap_v, y, lv.height);
    let i = lv.first + u32(yi * lv.width + xi) * texel_words(t.format);
    let w = texels[i];
    if takes(TEXEL_FORMATS, TEXEL_SRGB8, t.format) {
        return srgb_to_linear3(unpack4x8unorm(w).xyz);
    }
    if takes(TEXEL_FORMATS, TEXEL_UNORM8, t.format) || (TEXEL_FORMATS & (1u << TEXEL_HALF)) == 0u {
        return unpack4x8unorm(w).xyz;
    }
    return vec3<f32>(half_to_f32(w), half_to_f32(w >> 16u), half_to_f32(texels[i + 1u]));
}

// Bilinear lookup of one level at transformed coordinates st (texel
// centres at (i + ½) / size), as Texture::sample.
fn sample_level(t: GpuTexture, level: u32, st: vec2<f32>) -> vec3<f32> {
    let lv = texture_level(t, level);
    let x = st.x * f32(lv.width) - 0.5;
    let y = st.y * f32(lv.height) - 0.5;
    let x0 = floor(x);
    let y0 = floor(y);
    let fx = x - x0;
    let fy = y - y0;
    let xi = i32(x0);
    let yi = i32(y0);
    let top = mix(texel_at(t, lv, xi, yi), texel_at(t, lv, xi + 1, yi), fx);
    let bottom = mix(texel_at(t, lv, xi, yi + 1), texel_at(t, lv, xi + 1, yi + 1), fx);
    return mix(top, bottom, fy);
}

// Texture `index` at coordinates uv (before its transform); duv = (∂uv/∂x,
// ∂uv/∂y) per pixel. The level is log2 of the footprint's longer side in
// level-0 texels (ρ of OpenGL's isotropic LOD), level 0 when magnified,
// blended linearly between the two nearest levels.
fn sample_texture(index: u32, uv: vec2<f32>, duv: vec4<f32>) -> vec3<f32> {
    let t = textures[index];
    if t.width == 0u || t.height == 0u {
        return vec3<f32>(1.0);
    }
    let st = vec2<f32>(dot(t.u_row.xyz, vec3<f32>(uv, 1.0)), dot(t.v_row.xyz, vec3<f32>(uv, 1.0)));
    let j = mat2x2<f32>(vec2<f32>(t.u_row.x, t.v_row.x), vec2<f32>(t.u_row.y, t.v_row.y));
    let size = vec2<f32>(f32(t.width), f32(t.height));
    let dx = (j * duv.xy) * size;
    let dy = (j * duv.zw) * size;
    let rho2 = max(dot(dx, dx), dot(dy, dy));
    var lod = 0.0;
    // NaN and infinite footprints read level 0.
    if rho2 > 1.0 && rho2 < 3.0e38 {
        lod = min(0.5 * log2(rho2), f32(t.levels - 1u));
    }
    let l0 = u32(lod);
    let f = lod - f32(l0);
    let a = sample_level(t, l0, st);
    if f <= 0.0 {
        return a;
    }
    return mix(a, sample_level(t, min(l0 + 1u, t.levels - 1u), st), f);
}

// A fragment's texture coordinates in UV sets 0 (xy) and 1 (zw), and
// their screen derivatives (∂/∂x, ∂/∂y).
struct TexCoords {
    uv: vec4<f32>,
    dx: vec4<f32>,
    dy: vec4<f32>,
}

// The fragment's TexCoords from the interpolated `uv`; call in uniform
// control flow (derivatives).
fn tex_coords(uv: vec4<f32>) -> TexCoords {
    return TexCoords(uv, dpdx(uv), dpdy(uv));
}

// Texture `index` on its own UV set (Texture::lookup on the CPU). One
// sample_texture call, on selected coordinates: a call per set would
// double the inlined lookups, and software drivers' shader compilers
// (lavapipe's LLVM) then take minutes.
fn lookup_texture(index: u32, tc: TexCoords) -> vec3<f32> {
    let set1 = textures[index].uv_set == 1u;
    let uv = select(tc.uv.xy, tc.uv.zw, set1);
    let duv = select(vec4<f32>(tc.dx.xy, tc.dy.xy), vec4<f32>(tc.dx.zw, tc.dy.zw), set1);
    return sample_texture(index, uv, duv);
}

// Texture coordinates in UV sets 0 (xy) and 1 (zw; 0 where the mesh lacks
// a set) and colour (COLOR_0, else white) of vertex `vertex` of an instance.
fn vertex_uv(inst: GpuInstance, vertex: u32) -> vec4<f32> {
    var uv = vec4<f32>(0.0);
    if inst.first_uv != NO_VERTEX_DATA {
        uv = vec4<f32>(vertex_uvs[inst.first_uv + vertex], uv.zw);
    }
    if inst.first_uv1 != NO_VERTEX_DATA {
        uv = vec4<f32>(uv.xy, vertex_uvs[inst.first_uv1 + vertex]);
    }
    return uv;
}

fn vertex_color(inst: GpuInstance, vertex: u32) -> vec3<f32> {
    if inst.first_color == NO_VERTEX_DATA {
        return vec3<f32>(1.0);
    }
    return vertex_colors[inst.first_color + vertex].xyz;
}

// The world tangent of vertex `vertex` (w = handedness, flipped by
// mirroring transforms); w = 0 without tangents.
fn vertex_tangent(inst: GpuInstance, vertex: u32) -> vec4<f32> {
    if inst.first_tangent == NO_VERTEX_DATA {
        return vec4<f32>(0.0);
    }
    let t = vertex_tangents[inst.first_tangent + vertex];
    let w = select(1.0, -1.0, t.w < 0.0) * select(1.0, -1.0, inst.flip_winding != 0u);
    return vec4<f32>((inst.model * vec4<f32>(t.xyz, 0.0)).xyz, w);
}

// NormalMap::perturb: normalize(T x + B y + N z), (x, y, z) = (2 texel − 1)
// · (scale, scale, 1), T the tangent made orthogonal to the unit normal n,
// B = w · n × T; n when the frame is degenerate.
fn perturb_normal(texel: vec3<f32>, scale: f32, n: vec3<f32>, t: vec4<f32>) -> vec3<f32> {
    let m = (2.0 * texel - 1.0) * vec3<f32>(scale, scale, 1.0);
    var tangent = t.xyz - n * dot(n, t.xyz);
    let l2 = dot(tangent, tangent);
    if !(l2 > 0.0) || l2 > 3.0e38 {
        return n;
    }
    tangent = tangent * inverseSqrt(l2);
    let b = cross(n, tangent) * select(1.0, -1.0, t.w < 0.0);
    let mapped = tangent * m.x + b * m.y + n * m.z;
    let ml2 = dot(mapped, mapped);
    if !(ml2 > 0.0) || ml2 > 3.0e38 {
        return n;
    }
    return mapped * inverseSqrt(ml2);
}

// The shading normal of material `material` on the front side (ns_front,
// ng_front: the normals on the side the winding calls front), normal-mapped
// as the CPU does: kept only on the geometric normal's side.
fn normal_mapped(material: u32, tc: TexCoords, t: vec4<f32>, ns_front: vec3<f32>, ng_front: vec3<f32>) -> vec3<f32> {
    let tx = material_textures[material];
    if !has_texture(SLOT_NORMAL, tx.normal) || t.w == 0.0 {
        return ns_front;
    }
    let mapped = perturb_normal(lookup_texture(tx.normal, tc), tx.normal_scale, ns_front, t);
    return select(ns_front, mapped, dot(mapped, ng_front) > 0.0);
}

// glTF occlusionTexture: the factor 1 + strength · (R − 1) on the
// environment term of material `material` (1 without the texture).
fn baked_occlusion(material: u32, tc: TexCoords) -> f32 {
    let tx = material_textures[material];
    if !has_texture(SLOT_OCCLUSION, tx.occlusion) {
        return 1.0;
    }
    return 1.0 + tx.occlusion_strength * (lookup_texture(tx.occlusion, tc).x - 1.0);
}

// Coverage α of material `material` (glTF: baseColorFactor.a × the base
// colour texture's alpha; 1 for opaque materials).
fn coverage(material: u32, tc: TexCoords) -> f32 {
    let tx = material_textures[material];
    if tx.alpha_mode == ALPHA_OPAQUE {
        return 1.0;
    }
    if !has_texture(SLOT_ALPHA, tx.alpha_texture) {
        return tx.alpha_factor;
    }
    return tx.alpha_factor * lookup_texture(tx.alpha_texture, tc).x;
}

// Whether a MASK material cuts the fragment away (α < alphaCutoff).
fn masked_out(material: u32, tc: TexCoords) -> bool {
    let tx = material_textures[material];
    return tx.alpha_mode == ALPHA_MASK && coverage(material, tc) < tx.alpha_cutoff;
}

struct TexturedMaterial {
    mat: GpuMaterial,
    env: GpuEnvMaterial,
}

// Material `material` at a fragment with texture coordinates tc and
// vertex colour `color`, as the CPU's
// TraceContext::shading makes it: the base colour times the albedo texture
// and the vertex colour (Bsdf::tinted), roughness × G and metallic × B of
// the metallic–roughness texture, emission × the emission texture; and what
// the environment light needs of the result. Conductors keep their index
// (the host warns: tinting them solves for a new n + iκ).
fn textured_material(material: u32, tc: TexCoords, color: vec3<f32>) -> TexturedMaterial {
    var mat = materials[material];
    var env = environment_materials[material];
    let tx = material_textures[material];
    var tint = color;
    if has_texture(SLOT_ALBEDO, tx.albedo) {
        tint *= lookup_texture(tx.albedo, tc);
    }
    if has_texture(SLOT_EMISSION, tx.emission) {
        mat.emission *= lookup_texture(tx.emission, tc);
    }
    switch mat.model {
        case MODEL_LAMBERT, MODEL_PHONG_BLINN: {
            mat.kd *= tint;
            env.diffuse *= tint;
        }
        case MODEL_ROUGH_DIELECTRIC: {
            mat.base_color *= tint;
            env.transmit *= tint;
        }
        case MODEL_METALLIC_ROUGHNESS: {
            mat.base_color *= tint;
            if has_texture(SLOT_METALLIC_ROUGHNESS, tx.metallic_roughness) {
                let g_b = lookup_texture(tx.metallic_roughness, tc);
                mat.roughness = clamp(mat.roughness * g_b.y, 0.0, 1.0);
                mat.metallic = clamp(mat.metallic * g_b.z, 0.0, 1.0);
                mat.alpha = mat.roughness * mat.roughness;
            }
            env = metallic_roughness_environment(mat);
        }
        case MODEL_DELTA: {
            if env.kind == ENV_SPEC_DELTA_CONSTANT {
                env.f0 *= tint;
            }
            env.transmit *= tint;
        }
        default: {}
    }
    return TexturedMaterial(mat, env);
}
