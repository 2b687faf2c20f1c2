// Environment light, the structs and functions without bindings (part of
// the shading library, so shared by every module and the tests): SH9
// irradiance, the lat-long convention, the split-sum factors, the GGX
// samples of the prefilter, specular occlusion.
// Host: crates/penumbra-raster/src/passes/environment/mod.rs and
// crates/penumbra-shading/src/light/{spherical_harmonics,environment}.rs.
// Needs the shading library (PI, the Kulla–Conty table) before it.

// GpuEnvMaterial::kind: how the environment's specular light is reflected.
// No specular lobe (Lambert).
const ENV_SPEC_NONE: u32 = 0u;
// A GGX-like lobe: split sum, f0·A + (f90 − f0)·B times the map prefiltered
// at `roughness`, plus `transmit` × the map straight through.
const ENV_SPEC_SPLIT_SUM: u32 = 1u;
// A mirror of constant reflectance f0.
const ENV_SPEC_DELTA_CONSTANT: u32 = 2u;
// A smooth conductor: F(n·v) of n + iκ (eta, k; `fresnel` = FRESNEL_*).
const ENV_SPEC_DELTA_CONDUCTOR: u32 = 3u;
// Smooth glass: F = fresnel_dielectric(n·v, ior) reflected, (1 − F)·transmit
// straight through.
const ENV_SPEC_DELTA_DIELECTRIC: u32 = 4u;

// The environment (host: gpu.rs GpuEnvironment).
struct GpuEnvironment {
    // L_lm (rgb) of the environment's radiance, order of sh9_basis.
    sh: array<vec4<f32>, 9>,
    // cos α, sin α of the map's rotation about +y.
    rotation_cos: f32,
    rotation_sin: f32,
    // Levels of the prefiltered map: perceptual roughness r reads level
    // r · (mip_count − 1).
    mip_count: f32,
    // 1: the map is drawn where no geometry is (fs_background).
    background: u32,
    // Clip → world of the frame's camera (the background's view rays).
    inv_view_proj: mat4x4<f32>,
}

// What the environment light needs of a material (host: gpu.rs
// GpuEnvMaterial, from the Rust Bsdf).
struct GpuEnvMaterial {
    // c_diff (Bsdf::diffuse_albedo).
    diffuse: vec3<f32>,
    kind: u32,
    f0: vec3<f32>,
    // Perceptual roughness √α of the specular lobe (0 for delta lobes).
    roughness: f32,
    f90: vec3<f32>,
    // Smooth dielectric: η = n_inside / n_outside.
    ior: f32,
    // Smooth conductor: n and κ per band.
    eta: vec3<f32>,
    fresnel: u32,
    k: vec3<f32>,
    // 1: the diffuse light is scaled by 1 − E_d(μo) (metallic–roughness's
    // energy-conserving base, E_d = d_f0·A + (d_f90 − d_f0)·B).
    diffuse_kc: u32,
    d_f0: vec3<f32>,
    d_f90: f32,
    // Weight of the environment seen straight through (transmission).
    transmit: vec3<f32>,
    _pad0: f32,
}

// One level of the prefilter (host: gpu.rs GpuPrefilterParams).
struct GpuPrefilterParams {
    alpha: f32,
    samples: u32,
    width: u32,
    height: u32,
    source_width: f32,
    source_height: f32,
    source_levels: f32,
    _pad0: f32,
}


// The nine real spherical harmonics of order ≤ 2 at unit d (Rust
// `sh9_basis`, Ramamoorthi & Hanrahan 2001): Y00, Y1-1 (y), Y10 (z),
// Y11 (x), Y2-2 (xy), Y2-1 (yz), Y20 (3z² − 1), Y21 (xz), Y22 (x² − y²).
fn sh9_basis(d: vec3<f32>) -> array<f32, 9> {
    return array<f32, 9>(
        0.2820948,
        0.4886025 * d.y,
        0.4886025 * d.z,
        0.4886025 * d.x,
        1.0925484 * d.x * d.y,
        1.0925484 * d.y * d.z,
        0.31539157 * (3.0 * d.z * d.z - 1.0),
        1.0925484 * d.x * d.z,
        0.5462742 * (d.x * d.x - d.y * d.y),
    );
}

// Irradiance on a surface of unit normal n (Rust Sh9::irradiance):
// E(n) = Σ Â_l L_lm Y_lm(n), Â0 = π, Â1 = 2π/3, Â2 = π/4 (R&H 2001, eq. 7),
// clamped at 0; sh[i].xyz = L_lm (rgb) in the order of sh9_basis.
fn sh9_irradiance(sh: array<vec4<f32>, 9>, n: vec3<f32>) -> vec3<f32> {
    let y = sh9_basis(n);
    let a0 = PI;
    let a1 = 2.0 * PI / 3.0;
    let a2 = PI / 4.0;
    var e = sh[0].xyz * (a0 * y[0]);
    e += (sh[1].xyz * y[1] + sh[2].xyz * y[2] + sh[3].xyz * y[3]) * a1;
    e += (sh[4].xyz * y[4] + sh[5].xyz * y[5] + sh[6].xyz * y[6] + sh[7].xyz * y[7] + sh[8].xyz * y[8]) * a2;
    return max(e, vec3<f32>(0.0));
}

// World → map direction: R_y(−α) d, (c, s) = (cos α, sin α) of the map's
// rotation about +y (EnvironmentMap::direction_to_uv).
fn env_to_map(d: vec3<f32>, c: f32, s: f32) -> vec3<f32> {
    return vec3<f32>(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
}

// Map → world: R_y(α) m.
fn env_to_world(m: vec3<f32>, c: f32, s: f32) -> vec3<f32> {
    return vec3<f32>(c * m.x + s * m.z, m.y, -s * m.x + c * m.z);
}

// Lat-long coordinates of a map direction: u = φ/2π + ½, φ = atan2(x, −z);
// v = θ/π, θ = atan2(√(x² + z²), y) (row 0 the zenith).
fn latlong_uv(m: vec3<f32>) -> vec2<f32> {
    let theta = atan2(sqrt(m.x * m.x + m.z * m.z), m.y);
    let phi = atan2(m.x, -m.z);
    return vec2<f32>(phi / (2.0 * PI) + 0.5, theta / PI);
}

// The map direction of lat-long coordinates (EnvironmentMap::uv_to_direction
// without the rotation): (sin θ sin φ, cos θ, −sin θ cos φ).
fn latlong_direction(uv: vec2<f32>) -> vec3<f32> {
    let phi = 2.0 * PI * (uv.x - 0.5);
    let theta = PI * uv.y;
    let st = sin(theta);
    return vec3<f32>(st * sin(phi), cos(theta), -st * cos(phi));
}

// The split-sum factors (A, B) of GGX at μ = cos θo and perceptual
// roughness r (Rust `ggx_split_sum`): the directional albedo of the lobe
// with Schlick Fresnel is f0·A + (f90 − f0)·B (Karis 2013: scale = A − B,
// bias = B for f90 = 1). The Kulla–Conty table, bilinear in (√μ, √r).
fn env_split_sum(mu: f32, roughness: f32) -> vec2<f32> {
    let cm = kc_cell(sqrt(clamp(mu, 0.0, 1.0)), KC_MU);
    let cr = kc_cell(sqrt(clamp(roughness, 0.0, 1.0)), KC_R);
    let row0 = cr.i * KC_MU + cm.i;
    let row1 = row0 + KC_MU;
    let lo = kulla_conty_entry(row0).xy * (1.0 - cm.f) + kulla_conty_entry(row0 + 1u).xy * cm.f;
    let hi = kulla_conty_entry(row1).xy * (1.0 - cm.f) + kulla_conty_entry(row1 + 1u).xy * cm.f;
    return lo * (1.0 - cr.f) + hi * cr.f;
}

// A GGX half vector about +z drawn from D(m) cos θm for u ∈ [0,1)²
// (Walter et al. 2007, eqs. 35–36: tan²θm = α² u1 / (1 − u1), φ = 2π u2),
// and its density D(m) cos θm in w. The prefilter draws its samples so.
fn ggx_sample_half(u: vec2<f32>, alpha: f32) -> vec4<f32> {
    let a2 = alpha * alpha;
    let cos2 = (1.0 - u.x) / (1.0 + (a2 - 1.0) * u.x);
    let cos_t = sqrt(clamp(cos2, 0.0, 1.0));
    let sin_t = sqrt(clamp(1.0 - cos2, 0.0, 1.0));
    let phi = 2.0 * PI * u.y;
    let m = vec3<f32>(sin_t * cos(phi), sin_t * sin(phi), cos_t);
    return vec4<f32>(m, ggx_d(alpha, m) * cos_t);
}

// Specular occlusion from the ambient occlusion kA (Lagarde & de Rousiers
// 2014, "Moving Frostbite to PBR", eq. in §4.10.2):
// so = saturate((n·v + kA)^(exp2(−16α − 1)) − 1 + kA); 1 where kA = 1.
fn specular_occlusion(n_dot_v: f32, k_a: f32, alpha: f32) -> f32 {
    let e = exp2(-16.0 * alpha - 1.0);
    return clamp(pow(max(n_dot_v + k_a, 0.0), e) - 1.0 + k_a, 0.0, 1.0);
}

// The direction a GGX lobe's reflected light mostly comes from, between the
// mirror direction r and the normal n (the off-specular peak; Lagarde & de
// Rousiers 2014, §4.9.3, GGX fit): normalize(mix(n, r, s)),
// s = (1 − α)(√(1 − α) + α). The prefiltered map is read there.
fn specular_dominant_direction(n: vec3<f32>, r: vec3<f32>, alpha: f32) -> vec3<f32> {
    let a = clamp(alpha, 0.0, 1.0);
    let s = (1.0 - a) * (sqrt(1.0 - a) + a);
    return normalize(mix(n, r, s));
}

// Ggx::sample_visible: a microfacet normal drawn from the visible normals
// D_ωo(m) = G1(ωo) (ωo·m)⁺ D(m) / cos θo (spherical caps, Dupuy & Benyoub
// 2023), local frame, u ∈ [0,1)².
fn ggx_sample_visible(alpha: f32, wo: vec3<f32>, u: vec2<f32>) -> vec3<f32> {
    let wh = normalize(vec3<f32>(alpha * wo.x, alpha * wo.y, wo.z));
    let phi = 2.0 * PI * u.x;
    let z = (1.0 - u.y) * (1.0 + wh.z) - wh.z;
    let s = sqrt(max(1.0 - z * z, 0.0));
    let h = vec3<f32>(s * cos(phi), s * sin(phi), z) + wh;
    return normalize(vec3<f32>(alpha * h.x, alpha * h.y, max(h.z, 1e-7)));
}

// What the environment light needs of a metallic–roughness material: the
// twin of env_material's MetallicRoughness branch (mod.rs), evaluated per
// fragment once textures have changed the material.
fn metallic_roughness_environment(mat: GpuMaterial) -> GpuEnvMaterial {
    var m: GpuEnvMaterial;
    let metallic = clamp(mat.metallic, 0.0, 1.0);
    let s = clamp(mat.specular, 0.0, 1.0);
    let r = (mat.ior - 1.0) / (mat.ior + 1.0);
    let d_f0 = clamp(r * r * mat.specular_color, vec3<f32>(0.0), vec3<f32>(1.0)) * s;
    m.diffuse = mat.base_color * ((1.0 - metallic) * (1.0 - mat.transmission));
    m.kind = ENV_SPEC_SPLIT_SUM;
    // F = mix(F_d, Schlick(base_color), metallic): linear in (f0, f90).
    m.f0 = d_f0 * (1.0 - metallic) + mat.base_color * metallic;
    m.f90 = vec3<f32>(s * (1.0 - metallic) + metallic);
    m.roughness = sqrt(clamp(mat.alpha, 0.0, 1.0));
    m.diffuse_kc = 1u;
    m.d_f0 = d_f0;
    m.d_f90 = s;
    m.transmit = mat.base_color * ((1.0 - metallic) * clamp(mat.transmission, 0.0, 1.0));
    return m;
}
