// penumbra shading library: WGSL twins of the Rust BRDFs and abstract lights
// (crates/penumbra-shading/src/bsdf/*.rs, light/*.rs); the GGX models are in
// microfacet.wgsl, which the host appends (crates/penumbra-raster/src/shaders.rs).
// Structs shared with the host mirror the `#[repr(C)]` structs of
// crates/penumbra-raster/src/gpu.rs; a test compares their layouts with naga.

const PI: f32 = 3.14159265358979323846;

const LIGHT_POINT: u32 = 0u;
const LIGHT_DIRECTIONAL: u32 = 1u;
const LIGHT_SPOT: u32 = 2u;
const LIGHT_AREA: u32 = 3u;
const LIGHT_TWO_SIDED: u32 = 1u;

const MODEL_LAMBERT: u32 = 0u;
const MODEL_PHONG_BLINN: u32 = 1u;
const MODEL_ROUGH_CONDUCTOR: u32 = 2u;
const MODEL_ROUGH_DIELECTRIC: u32 = 3u;
const MODEL_METALLIC_ROUGHNESS: u32 = 4u;
// Mirror, Conductor, Dielectric: delta lobes only, eval ≡ 0.
const MODEL_DELTA: u32 = 5u;

// Bit mask (1 << MODEL_*) of the models material_eval handles: a pipeline
// that shades a scene sets it to the models the scene uses, so the shader
// compiler drops the code of the others (on a CPU rasteriser such as
// lavapipe, unused GGX code slowed a Lambert-only forward pass by half).
override MATERIAL_MODELS: u32 = 0xffffffffu;

fn model_enabled(model: u32) -> bool {
    return (MATERIAL_MODELS & (1u << model)) != 0u;
}

// GpuMaterial::variant of a rough conductor.
const FRESNEL_EXACT: u32 = 0u;
const FRESNEL_SCHLICK: u32 = 1u;

const PHONG_NOTES: u32 = 0u;
const PHONG_MAX_BLINN: u32 = 1u;
const PHONG_HALFWAY_SQUARED: u32 = 2u;
const PHONG_NORMALIZED: u32 = 3u;

// An abstract light in the notes' homogeneous form: (y, w) with w = 1 for
// point and spot lights (y = position), w = 0 for directional lights (y =
// unit direction towards the light); m = intensity [W/sr] or irradiance
// [W/m²]. Spot lights add the glTF cone falloff around spot_direction.
// range > 0: point and spot lights are cut off by glTF's window (0 = none).
// LIGHT_AREA: an area light's far field (FarField), a point light whose
// intensity is m · lobe, lobe = 1 (spot_direction = 0, a sphere), (w·n)⁺ or
// |w·n| (flags & LIGHT_TWO_SIDED) around n = spot_direction.
struct GpuLight {
    position: vec4<f32>,
    m: vec3<f32>,
    kind: u32,
    spot_direction: vec3<f32>,
    cos_inner: f32,
    cos_outer: f32,
    range: f32,
    flags: u32,
    _pad2: f32,
}

// A material as the raster path shades it (host: gpu.rs `GpuMaterial`),
// plus emission. Per model:
// - Lambert: kd = ρ/π; Phong–Blinn: kd, ks, shininess, variant = PHONG_*;
// - rough conductor: conductor_eta, conductor_k (n + iκ per band), alpha (GGX
//   α, clamped like Ggx::new), variant = FRESNEL_*;
// - rough dielectric: ior (η = n_inside / n_outside), alpha, base_color (tint);
// - metallic–roughness: base_color, metallic, roughness (clamped to [0, 1]),
//   alpha = roughness², ior, transmission, specular (clamped), specular_color;
// - delta models: nothing (eval ≡ 0).
struct GpuMaterial {
    model: u32,
    variant: u32,
    shininess: f32,
    double_sided: u32,
    kd: vec3<f32>,
    alpha: f32,
    ks: vec3<f32>,
    ior: f32,
    emission: vec3<f32>,
    roughness: f32,
    base_color: vec3<f32>,
    metallic: f32,
    specular_color: vec3<f32>,
    transmission: f32,
    conductor_eta: vec3<f32>,
    specular: f32,
    conductor_k: vec3<f32>,
    // 1: the shading passes discard back faces (glTF doubleSided: false).
    cull_back_faces: u32,
}

// Incident light at a point: unit direction towards the light and the
// irradiance on a surface perpendicular to it; valid = 0 when the light does
// not reach the point (Rust: `sample_li` returns None).
struct LightIncidence {
    wi: vec3<f32>,
    valid: u32,
    value: vec3<f32>,
    distance: f32,
}

// HomogeneousLight::sample_li: wi = normalize(y − x·w), E⊥ = M / |y − x·w|².
fn homogeneous_li(position: vec4<f32>, m: vec3<f32>, x: vec3<f32>) -> LightIncidence {
    var out: LightIncidence;
    let w = position.w;
    let d = position.xyz - x * w;
    let r2 = dot(d, d);
    // r2 == 0 or not finite (the bit pattern test works whatever the
    // compiler assumes about IEEE special values).
    let bits = bitcast<u32>(r2) & 0x7fffffffu;
    if r2 == 0.0 || bits >= 0x7f800000u {
        out.valid = 0u;
        return out;
    }
    let len = sqrt(r2);
    out.wi = d / len;
    out.value = m / r2;
    if w == 0.0 {
        out.distance = bitcast<f32>(0x7f800000u);
    } else {
        out.distance = len / w;
    }
    out.valid = 1u;
    return out;
}

// SpotLight::falloff: t = clamp((cos θ − cos θo) / max(cos θi − cos θo, 1e-6), 0, 1), t².
fn spot_falloff(light: GpuLight, w: vec3<f32>) -> f32 {
    let c = dot(w, light.spot_direction);
    let span = max(light.cos_inner - light.cos_outer, 1e-6);
    let t = clamp((c - light.cos_outer) / span, 0.0, 1.0);
    return t * t;
}

// range_window: clamp(1 − (d / range)⁴, 0, 1)², 1 without a range (≤ 0).
fn range_window(distance: f32, range: f32) -> f32 {
    if range <= 0.0 {
        return 1.0;
    }
    let x = distance / range;
    let x2 = x * x;
    let t = clamp(1.0 - x2 * x2, 0.0, 1.0);
    return t * t;
}

// FarField::lobe for a direction w leaving the light.
fn area_lobe(light: GpuLight, w: vec3<f32>) -> f32 {
    let n = light.spot_direction;
    if all(n == vec3<f32>(0.0)) {
        return 1.0;
    }
    let c = dot(w, n);
    if (light.flags & LIGHT_TWO_SIDED) != 0u {
        return abs(c);
    }
    return max(c, 0.0);
}

// Light::sample_li for the abstract lights (the homogeneous form, times the
// spot cone falloff and the range window of point and spot lights), and
// FarField::sample_li for area lights.
fn light_li(light: GpuLight, x: vec3<f32>) -> LightIncidence {
    var s = homogeneous_li(light.position, light.m, x);
    if s.valid == 0u || light.kind == LIGHT_DIRECTIONAL {
        return s;
    }
    var f = range_window(s.distance, light.range);
    if light.kind == LIGHT_SPOT {
        f = f * spot_falloff(light, -s.wi);
    } else if light.kind == LIGHT_AREA {
        f = area_lobe(light, -s.wi);
    }
    if f <= 0.0 {
        s.valid = 0u;
        return s;
    }
    s.value = s.value * f;
    return s;
}

// Lambert::eval in the local frame (z = normal): kd when both are above.
fn lambert_eval(kd: vec3<f32>, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if wo.z > 0.0 && wi.z > 0.0 {
        return kd;
    }
    return vec3<f32>(0.0);
}

// x^y with Rust's powf conventions at the ends (0^0 = 1, x^0 = 1, 0^y = 0).
fn pow_rust(x: f32, y: f32) -> f32 {
    if y == 0.0 || x == 1.0 {
        return 1.0;
    }
    if x <= 0.0 {
        return 0.0;
    }
    return exp2(y * log2(x));
}

// PhongVariant::lobe: the specular lobe per unit ks.
fn phong_lobe(variant: u32, wo: vec3<f32>, wi: vec3<f32>, shininess: f32) -> f32 {
    let sum = wi + wo;
    let len2 = dot(sum, sum);
    if len2 <= 0.0 {
        return 0.0;
    }
    let cos_delta = clamp(sum.z / sqrt(len2), 0.0, 1.0);
    let d = pow_rust(cos_delta, shininess);
    switch variant {
        case PHONG_NOTES: {
            return d / wi.z;
        }
        case PHONG_MAX_BLINN: {
            return d / max(wo.z, wi.z);
        }
        case PHONG_HALFWAY_SQUARED: {
            return d / len2;
        }
        default: {
            return d * (shininess + 8.0) / (8.0 * PI);
        }
    }
}

// PhongBlinn::eval: kd + ks · lobe when both are above the surface.
fn phong_eval(kd: vec3<f32>, ks: vec3<f32>, shininess: f32, variant: u32, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    return kd + ks * phong_lobe(variant, wo, wi, shininess);
}

// The material's BSDF f(wo, wi) in the local frame, non-delta lobes only
// (Rust: Bsdf::eval; wi below the surface reaches the transmission lobes).
// A surface seen from its back must first go through material_seen_from_back.
fn material_eval(mat: GpuMaterial, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if model_enabled(MODEL_LAMBERT) && mat.model == MODEL_LAMBERT {
        return lambert_eval(mat.kd, wo, wi);
    }
    if model_enabled(MODEL_PHONG_BLINN) && mat.model == MODEL_PHONG_BLINN {
        return phong_eval(mat.kd, mat.ks, mat.shininess, mat.variant, wo, wi);
    }
    if model_enabled(MODEL_ROUGH_CONDUCTOR) && mat.model == MODEL_ROUGH_CONDUCTOR {
        return rough_conductor_eval(mat, wo, wi);
    }
    if model_enabled(MODEL_ROUGH_DIELECTRIC) && mat.model == MODEL_ROUGH_DIELECTRIC {
        return rough_dielectric_eval(mat, wo, wi);
    }
    if model_enabled(MODEL_METALLIC_ROUGHNESS) && mat.model == MODEL_METALLIC_ROUGHNESS {
        return metallic_roughness_eval(mat, wo, wi);
    }
    // The delta models (and models left out of MATERIAL_MODELS).
    return vec3<f32>(0.0);
}

// BsdfFlags::transmission of the models with a rough transmission lobe
// (such materials are two-sided, as on the CPU).
fn material_transmissive(mat: GpuMaterial) -> bool {
    return mat.model == MODEL_ROUGH_DIELECTRIC
        || (mat.model == MODEL_METALLIC_ROUGHNESS && mr_has_transmission(mat));
}

// Bsdf::seen_from_back: transmissive models get η → 1/η (the shading point
// is inside the medium); every other material is unchanged.
fn material_seen_from_back(mat: GpuMaterial) -> GpuMaterial {
    var m = mat;
    if material_transmissive(mat) {
        m.ior = 1.0 / mat.ior;
    }
    return m;
}

// Frame::from_normal (Duff et al.), so local vectors equal the CPU's.
struct Frame {
    s: vec3<f32>,
    t: vec3<f32>,
    n: vec3<f32>,
}

fn frame_from_normal(n: vec3<f32>) -> Frame {
    var sign = 1.0;
    if n.z < 0.0 || (n.z == 0.0 && (bitcast<u32>(n.z) & 0x80000000u) != 0u) {
        sign = -1.0;
    }
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    var f: Frame;
    f.s = vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.t = vec3<f32>(b, sign + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
}

fn to_local(f: Frame, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(v, f.s), dot(v, f.t), dot(v, f.n));
}
