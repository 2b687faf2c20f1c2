// penumbra shading library, GGX part: WGSL twins of `eval` of the microfacet
// models (crates/penumbra-shading/src/bsdf/{microfacet, optics,
// rough_conductor, rough_dielectric, metallic_roughness}.rs).
//
// Every function repeats the Rust operation order (a * b * c is (a * b) * c,
// dot is (x x' + y y') + z z', powi(5) is x · (x² · x²)), so that IEEE f32
// arithmetic gives the Rust results to rounding. Where Rust relies on ∞ or
// NaN (Λ = ∞ at grazing angles, a non-finite conductor Fresnel taken as 1)
// the twin tests the condition that produces them, since shader compilers
// may assume neither occurs.
//
// The metallic–roughness model reads the Kulla–Conty albedo tables through
// `kulla_conty_entry(i)` and the sizes KC_MU, KC_R, which a table source
// declares (crates/penumbra-raster/src/material_tables.rs: a storage buffer
// at @group(0) @binding(8), or the same numbers as a constant array).

// metallic_roughness.rs DELTA_ALPHA: below it the GGX lobes are delta lobes.
const DELTA_ALPHA: f32 = 1e-3;
// std::f32::consts::FRAC_1_PI.
const FRAC_1_PI: f32 = 0.318309886183790671537767526745028724;

// x⁵ as Rust's powi(5) evaluates it.
fn pow5(x: f32) -> f32 {
    let x2 = x * x;
    let x4 = x2 * x2;
    return x * x4;
}

// glam's Vec3::dot order.
fn dot3(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

// ---------------------------------------------------------------- GGX ----

// Ggx::d: 1 / (π α² (cos²θm + sin²θm / α²)²), 0 below the surface.
fn ggx_d(alpha: f32, m: vec3<f32>) -> f32 {
    if m.z <= 0.0 {
        return 0.0;
    }
    let a2 = alpha * alpha;
    let sin2 = m.x * m.x + m.y * m.y;
    let t = m.z * m.z + sin2 / a2;
    return 1.0 / (PI * a2 * t * t);
}

// Ggx::lambda for cos θ ≠ 0: x / (2 (√(1 + x) + 1)), x = α² tan²θ.
fn ggx_lambda(alpha: f32, w: vec3<f32>) -> f32 {
    let cos2 = w.z * w.z;
    let a2_tan2 = alpha * alpha * (w.x * w.x + w.y * w.y) / cos2;
    return a2_tan2 / (2.0 * (sqrt(1.0 + a2_tan2) + 1.0));
}

// Ggx::g2, height-correlated: 1 / (1 + Λ(ωo) + Λ(ωi)); 0 when either
// direction is grazing (Rust: Λ = ∞).
fn ggx_g2(alpha: f32, wo: vec3<f32>, wi: vec3<f32>) -> f32 {
    if wo.z * wo.z == 0.0 || wi.z * wi.z == 0.0 {
        return 0.0;
    }
    return 1.0 / (1.0 + ggx_lambda(alpha, wo) + ggx_lambda(alpha, wi));
}

// A microfacet normal, or none (Rust: Option<Vec3>).
struct HalfVector {
    m: vec3<f32>,
    valid: bool,
}

// reflection_half_vector: normalize(ωo + ωi) unless |ωo + ωi| ≤ 1e-6.
fn reflection_half_vector(wo: vec3<f32>, wi: vec3<f32>) -> HalfVector {
    var out: HalfVector;
    let h = wo + wi;
    let len = sqrt(dot3(h, h));
    out.valid = len > 1e-6;
    out.m = h / select(1.0, len, out.valid);
    return out;
}

// transmission_half_vector: m ∝ ωo + η ωi oriented to +z, valid when it is
// not degenerate and sees ωo from above and ωi from below.
fn transmission_half_vector(wo: vec3<f32>, wi: vec3<f32>, eta: f32) -> HalfVector {
    var out: HalfVector;
    let h = wo + eta * wi;
    let len = sqrt(dot3(h, h));
    if !(len > 1e-6) {
        out.valid = false;
        return out;
    }
    if h.z < 0.0 {
        out.m = -h / len;
    } else {
        out.m = h / len;
    }
    out.valid = out.m.z > 0.0 && dot3(wo, out.m) > 0.0 && dot3(wi, out.m) < 0.0;
    return out;
}

// reflection_core: D(m) G2 / (4 cos θo cos θi).
fn reflection_core(alpha: f32, wo: vec3<f32>, wi: vec3<f32>, m: vec3<f32>) -> f32 {
    return ggx_d(alpha, m) * ggx_g2(alpha, wo, wi) / (4.0 * wo.z * wi.z);
}

// transmission_core: D(m) G2 |ωo·m| |ωi·m| / (|cos θo cos θi| (ωo·m + η ωi·m)²).
fn transmission_core(alpha: f32, wo: vec3<f32>, wi: vec3<f32>, m: vec3<f32>, eta: f32) -> f32 {
    let om = dot3(wo, m);
    let im = dot3(wi, m);
    let denom = om + eta * im;
    return ggx_d(alpha, m) * ggx_g2(alpha, wo, wi) * abs(om * im)
        / (abs(wo.z * wi.z) * denom * denom);
}

// ------------------------------------------------------------ Fresnel ----

// optics::f0_from_ior: ((n − 1)² + κ²) / ((n + 1)² + κ²) per band.
fn f0_from_ior(n: vec3<f32>, k: vec3<f32>) -> vec3<f32> {
    let k2 = k * k;
    return ((n - 1.0) * (n - 1.0) + k2) / ((n + 1.0) * (n + 1.0) + k2);
}

// optics::schlick: F0 + (1 − F0)(1 − cos θ)⁵ per band.
fn schlick(f0: vec3<f32>, cos_theta: f32) -> vec3<f32> {
    let m = pow5(1.0 - clamp(cos_theta, 0.0, 1.0));
    return f0 + (vec3<f32>(1.0) - f0) * m;
}

// optics::fresnel_dielectric: exact unpolarised reflectance, η = n_inside /
// n_outside, cos θi < 0 from inside, 1 under total internal reflection.
fn fresnel_dielectric(cos_theta_i: f32, eta_in: f32) -> f32 {
    var cos_i = min(cos_theta_i, 1.0);
    var eta = eta_in;
    if cos_theta_i < 0.0 {
        cos_i = min(-cos_theta_i, 1.0);
        eta = 1.0 / eta_in;
    }
    let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = sqrt(max(1.0 - sin2_t, 0.0));
    let r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (r_s * r_s + r_p * r_p);
}

// optics::fresnel_conductor_scalar: exact reflectance of n + iκ, one band;
// 1 where Rust's value is not finite (a vanishing denominator).
fn fresnel_conductor_scalar(cos_theta_i: f32, n: f32, k: f32) -> f32 {
    let c = clamp(cos_theta_i, 0.0, 1.0);
    let cos2 = c * c;
    let sin2 = 1.0 - cos2;
    let t0 = n * n - k * k - sin2;
    let a2b2 = sqrt(t0 * t0 + 4.0 * n * n * k * k);
    let a = sqrt(max(0.5 * (a2b2 + t0), 0.0));
    let t1 = a2b2 + cos2;
    let t2 = 2.0 * a * c;
    let t3 = cos2 * a2b2 + sin2 * sin2;
    let t4 = t2 * sin2;
    if t1 + t2 == 0.0 || t3 + t4 == 0.0 {
        return 1.0;
    }
    let rs = (t1 - t2) / (t1 + t2);
    let rp = rs * (t3 - t4) / (t3 + t4);
    return 0.5 * (rp + rs);
}

fn fresnel_conductor(cos_theta_i: f32, n: vec3<f32>, k: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        fresnel_conductor_scalar(cos_theta_i, n.x, k.x),
        fresnel_conductor_scalar(cos_theta_i, n.y, k.y),
        fresnel_conductor_scalar(cos_theta_i, n.z, k.z),
    );
}

// ---------------------------------------------------- rough conductor ----

// RoughConductor::fresnel_at.
fn rough_conductor_fresnel(mat: GpuMaterial, cos_theta: f32) -> vec3<f32> {
    if mat.variant == FRESNEL_SCHLICK {
        return schlick(f0_from_ior(mat.conductor_eta, mat.conductor_k), cos_theta);
    }
    return fresnel_conductor(cos_theta, mat.conductor_eta, mat.conductor_k);
}

// RoughConductor::eval: D G2 F(ωo·m) / (4 cos θo cos θi), both above.
fn rough_conductor_eval(mat: GpuMaterial, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let h = reflection_half_vector(wo, wi);
    if !h.valid {
        return vec3<f32>(0.0);
    }
    return rough_conductor_fresnel(mat, dot3(wo, h.m)) * reflection_core(mat.alpha, wo, wi, h.m);
}

// --------------------------------------------------- rough dielectric ----

// RoughDielectric::eval: reflection above, transmission below (radiance form,
// tint = base_color).
fn rough_dielectric_eval(mat: GpuMaterial, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    if wi.z > 0.0 {
        let h = reflection_half_vector(wo, wi);
        if !h.valid {
            return vec3<f32>(0.0);
        }
        return vec3<f32>(fresnel_dielectric(dot3(wo, h.m), mat.ior) * reflection_core(mat.alpha, wo, wi, h.m));
    }
    if wi.z < 0.0 {
        let h = transmission_half_vector(wo, wi, mat.ior);
        if !h.valid {
            return vec3<f32>(0.0);
        }
        let t = 1.0 - fresnel_dielectric(dot3(wo, h.m), mat.ior);
        return mat.base_color * (t * transmission_core(mat.alpha, wo, wi, h.m, mat.ior));
    }
    return vec3<f32>(0.0);
}

// ------------------------------------------------ metallic–roughness ----

fn mr_has_transmission(mat: GpuMaterial) -> bool {
    return mat.transmission > 0.0 && mat.metallic < 1.0;
}

// (f0, f90) of the dielectric Fresnel (KHR_materials_specular): f0 in xyz,
// f90 in w.
fn mr_f0_f90(mat: GpuMaterial) -> vec4<f32> {
    let q = (mat.ior - 1.0) / (mat.ior + 1.0);
    let r = q * q;
    let s = mat.specular;
    let f0 = max(min(r * mat.specular_color, vec3<f32>(1.0)), vec3<f32>(0.0)) * s;
    return vec4<f32>(f0, s);
}

// F_d at the microfacet, cos_m = ωo·m; from the denser side (ior < 1) with the
// transmitted angle, 1 under total internal reflection.
fn mr_fresnel_dielectric(mat: GpuMaterial, cos_m: f32) -> vec3<f32> {
    let ff = mr_f0_f90(mat);
    let f0 = ff.xyz;
    var c = clamp(cos_m, 0.0, 1.0);
    if mat.ior < 1.0 {
        let sin2_t = (1.0 - c * c) / (mat.ior * mat.ior);
        if sin2_t >= 1.0 {
            return vec3<f32>(1.0);
        }
        c = sqrt(1.0 - sin2_t);
    }
    return f0 + (vec3<f32>(ff.w) - f0) * pow5(1.0 - c);
}

// mix(F_d, F_m = Schlick(base_color), metallic).
fn mr_f_reflect(mat: GpuMaterial, cos_m: f32) -> vec3<f32> {
    let m = mat.metallic;
    return mr_fresnel_dielectric(mat, cos_m) * (1.0 - m) + schlick(mat.base_color, cos_m) * m;
}

// Transmittance of the microfacets (before 1/η²).
fn mr_f_transmit(mat: GpuMaterial, cos_m: f32) -> vec3<f32> {
    if !mr_has_transmission(mat) {
        return vec3<f32>(0.0);
    }
    let w = (1.0 - mat.metallic) * mat.transmission;
    return (vec3<f32>(1.0) - mr_fresnel_dielectric(mat, cos_m)) * mat.base_color * w;
}

// AlbedoTable::cell: node index and fraction of x on n nodes over [0, 1].
struct KcCell {
    i: u32,
    f: f32,
}

fn kc_cell(x: f32, n: u32) -> KcCell {
    let xs = clamp(x, 0.0, 1.0) * f32(n - 1u);
    var c: KcCell;
    c.i = min(u32(xs), n - 2u);
    c.f = xs - f32(c.i);
    return c;
}

// Specular directional albedo E(μ) per band (xyz of `e`) and its cosine
// average E_avg (xyz of `avg`), MetallicRoughness::specular_albedo: table
// entries hold (A, B, A_avg, B_avg) of node (√μ, √roughness), bilinear.
struct SpecularAlbedo {
    e: vec3<f32>,
    avg: vec3<f32>,
}

fn mr_specular_albedo(mat: GpuMaterial, mu: f32) -> SpecularAlbedo {
    let ff = mr_f0_f90(mat);
    let f0 = ff.xyz;
    var r = mat.roughness;
    if mat.alpha < DELTA_ALPHA {
        r = 0.0;
    }
    let cm = kc_cell(sqrt(max(mu, 0.0)), KC_MU);
    let cr = kc_cell(sqrt(max(r, 0.0)), KC_R);
    let row0 = cr.i * KC_MU + cm.i;
    let row1 = row0 + KC_MU;
    let e00 = kulla_conty_entry(row0);
    let e01 = kulla_conty_entry(row0 + 1u);
    let e10 = kulla_conty_entry(row1);
    let e11 = kulla_conty_entry(row1 + 1u);
    let lo = e00.xy * (1.0 - cm.f) + e01.xy * cm.f;
    let hi = e10.xy * (1.0 - cm.f) + e11.xy * cm.f;
    let ab = lo * (1.0 - cr.f) + hi * cr.f;
    let ab_avg = e00.zw * (1.0 - cr.f) + e10.zw * cr.f;
    var out: SpecularAlbedo;
    if mat.ior < 1.0 {
        // From the denser side F_d reaches 1 (TIR): E bounded by F ≡ 1.
        out.e = vec3<f32>(ab.x);
        out.avg = vec3<f32>(ab_avg.x);
        return out;
    }
    let df = vec3<f32>(ff.w) - f0;
    out.e = f0 * ab.x + df * ab.y;
    out.avg = f0 * ab_avg.x + df * ab_avg.y;
    return out;
}

// The energy-conserving Lambert base: base_color/π · (1 − E(μo))(1 − E(μi)) /
// (1 − E_avg) per band, weighted by (1 − metallic)(1 − transmission).
fn mr_diffuse(mat: GpuMaterial, mu_o: f32, mu_i: f32) -> vec3<f32> {
    let w = (1.0 - mat.metallic) * (1.0 - mat.transmission);
    if w <= 0.0 {
        return vec3<f32>(0.0);
    }
    let so = mr_specular_albedo(mat, mu_o);
    let si = mr_specular_albedo(mat, mu_i);
    let rest = vec3<f32>(1.0) - so.avg;
    let ok = rest > vec3<f32>(1e-6);
    let scale = select(
        vec3<f32>(0.0),
        max(vec3<f32>(1.0) - so.e, vec3<f32>(0.0)) * max(vec3<f32>(1.0) - si.e, vec3<f32>(0.0))
            / select(vec3<f32>(1.0), rest, ok),
        ok,
    );
    return mat.base_color * scale * (w * FRAC_1_PI);
}

// MetallicRoughness::eval: with wi above, the diffuse base plus (unless
// delta) the GGX reflection with mix(F_d, F_m); with wi below and
// transmission, the GGX transmission lobe (radiance form).
fn metallic_roughness_eval(mat: GpuMaterial, wo: vec3<f32>, wi: vec3<f32>) -> vec3<f32> {
    if wo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    let delta = mat.alpha < DELTA_ALPHA;
    if wi.z > 0.0 {
        var f = mr_diffuse(mat, wo.z, wi.z);
        if !delta {
            let h = reflection_half_vector(wo, wi);
            if h.valid {
                f += mr_f_reflect(mat, dot3(wo, h.m)) * reflection_core(mat.alpha, wo, wi, h.m);
            }
        }
        return f;
    }
    if wi.z < 0.0 && !delta && mr_has_transmission(mat) {
        let h = transmission_half_vector(wo, wi, mat.ior);
        if h.valid {
            return mr_f_transmit(mat, dot3(wo, h.m)) * transmission_core(mat.alpha, wo, wi, h.m, mat.ior);
        }
    }
    return vec3<f32>(0.0);
}
