//! The glTF 2.0 metallic–roughness material (with KHR_materials_ior,
//! _transmission and _specular), built from the Lambert and GGX lobes.
//!
//! Following glTF 2.0 Appendix B and the extension texts, with α = roughness²:
//! - **metal**: `GGX_brdf · F_m`, `F_m = Schlick(base_color)` at ωo·m;
//! - **dielectric specular**: `GGX_brdf · F_d`, `F_d = f0 + (f90 − f0)(1 − ωo·m)⁵`
//!   with `f0 = min(((ior−1)/(ior+1))² · specular_color, 1) · specular` and
//!   `f90 = specular` (KHR_materials_specular); when ωo is in the denser
//!   medium (ior < 1 after [`MetallicRoughness::inverted`]) the cosine of the
//!   transmitted angle is used and F_d = 1 under total internal reflection;
//! - **transmission** (KHR_materials_transmission): a rough-dielectric
//!   transmission lobe (Walter et al. 2007, the radiance form with 1/η²)
//!   weighted by `transmission · (1 − F_d) · base_color`;
//! - **diffuse base**: Lambert `base_color/π` weighted by `1 − transmission`.
//!
//! `material = mix(dielectric, metal, metallic)`.
//!
//! The spec's `fresnel_mix` weights the diffuse base by `1 − F_d(V·H)`, H the
//! half vector of (ωo, ωi). That is not energy conserving: for white light at
//! θo = 85° and roughness 0.1 the specular lobe reflects 63 % while the
//! (1 − F)-weighted base still reflects 94 % (sum 1.57; 1.29 at roughness
//! 0.3, 1.03 at θo = 60°). Here the base receives what the
//! specular layer's single scattering does not reflect, reciprocally
//! (Kulla & Conty 2017, "Revisiting Physically Based Shading at Imageworks"):
//! `base_color/π · (1 − E(μo)) (1 − E(μi)) / (1 − E_avg)`, per band, with
//! `E(μ) = ∫ F_d D_ωo G2/G1 dm` the specular directional albedo and
//! `E_avg = 2∫E(μ) μ dμ`. E is linear in (f0, f90): `E = f0 A + (f90 − f0) B`,
//! A and B tabulated once over (μ, roughness) by quadrature. The base then
//! reflects exactly `(1 − E(μo)) · base_color`, so the material conserves
//! energy; as roughness → 0, E(μ) → F_d(μ), the spec's `1 − F` weighting.
//! Seen from the denser side (ior < 1) F_d reaches 1 under total internal
//! reflection, which the Schlick tables do not capture; there E is bounded
//! by the white (F ≡ 1) albedo A, which keeps the sum ≤ 1.
//!
//! Below [`DELTA_ALPHA`] the GGX lobes become delta lobes (mirror and Snell
//! refraction), reported by `specular()` and `sample(..).delta`.

use super::microfacet::{
    Ggx, reflection_core, reflection_half_vector, transmission_core, transmission_half_vector,
    transmission_jacobian,
};
use super::optics::{reflect, refract, schlick};
use super::{BsdfFlags, BsdfSample, SpecularSet};
use crate::Rgb;
use crate::sampling::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use glam::Vec3;
use std::f32::consts::FRAC_1_PI;
use std::sync::OnceLock;

/// α = roughness² below which the specular lobes are delta lobes
/// (roughness < 0.0316: the GGX lobe is then under 0.1° wide).
pub const DELTA_ALPHA: f32 = 1e-3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetallicRoughness {
    pub base_color: Rgb,
    pub metallic: f32,
    /// Perceptual roughness; GGX α = roughness².
    pub roughness: f32,
    /// KHR_materials_ior (default 1.5).
    pub ior: f32,
    /// KHR_materials_transmission factor (default 0).
    pub transmission: f32,
    /// KHR_materials_specular `specularFactor` (default 1).
    pub specular: f32,
    /// KHR_materials_specular `specularColorFactor` (default 1).
    pub specular_color: Rgb,
}

impl MetallicRoughness {
    /// glTF core material: ior 1.5, no transmission, specular 1 and white.
    pub fn new(base_color: Rgb, metallic: f32, roughness: f32) -> Self {
        Self {
            base_color,
            metallic,
            roughness,
            ior: 1.5,
            transmission: 0.0,
            specular: 1.0,
            specular_color: Rgb::ONE,
        }
    }

    /// The same surface seen from the inside: ior → 1/ior when it transmits
    /// (f0 is invariant under it); an opaque surface is returned unchanged.
    pub fn inverted(self) -> Self {
        if self.has_transmission() {
            Self {
                ior: 1.0 / self.ior,
                ..self
            }
        } else {
            self
        }
    }

    /// GGX α = roughness², roughness clamped to [0, 1].
    pub fn alpha(&self) -> f32 {
        let r = self.roughness.clamp(0.0, 1.0);
        r * r
    }

    /// The specular lobes are delta lobes (α < [`DELTA_ALPHA`]).
    pub fn is_delta(&self) -> bool {
        self.alpha() < DELTA_ALPHA
    }

    fn metallic(&self) -> f32 {
        self.metallic.clamp(0.0, 1.0)
    }

    fn transmission(&self) -> f32 {
        self.transmission.clamp(0.0, 1.0)
    }

    fn has_transmission(&self) -> bool {
        self.transmission() > 0.0 && self.metallic() < 1.0
    }

    fn ggx(&self) -> Ggx {
        Ggx::new(self.alpha())
    }

    /// (f0, f90) of the dielectric Fresnel (KHR_materials_specular).
    fn dielectric_f0_f90(&self) -> (Rgb, f32) {
        let r = ((self.ior - 1.0) / (self.ior + 1.0)).powi(2);
        let s = self.specular.clamp(0.0, 1.0);
        (
            (r * self.specular_color).min(Rgb::ONE).max(Rgb::ZERO) * s,
            s,
        )
    }

    /// F_d at the microfacet, `cos` = ωo·m.
    fn fresnel_dielectric(&self, cos: f32) -> Rgb {
        let (f0, f90) = self.dielectric_f0_f90();
        let mut c = cos.clamp(0.0, 1.0);
        if self.ior < 1.0 {
            let sin2_t = (1.0 - c * c) / (self.ior * self.ior);
            if sin2_t >= 1.0 {
                return Rgb::ONE;
            }
            c = (1.0 - sin2_t).sqrt();
        }
        f0 + (Rgb::splat(f90) - f0) * (1.0 - c).powi(5)
    }

    /// Reflectance of the specular microfacets: mix(F_d, F_m, metallic).
    fn f_reflect(&self, cos: f32) -> Rgb {
        let m = self.metallic();
        self.fresnel_dielectric(cos) * (1.0 - m) + schlick(self.base_color, cos) * m
    }

    /// Transmittance of the specular microfacets (before the 1/η² factor).
    fn f_transmit(&self, cos: f32) -> Rgb {
        if !self.has_transmission() {
            return Rgb::ZERO;
        }
        let w = (1.0 - self.metallic()) * self.transmission();
        (Rgb::ONE - self.fresnel_dielectric(cos)) * self.base_color * w
    }

    /// Specular directional albedo E(μ) per band and its cosine average E_avg.
    fn specular_albedo(&self, mu: f32) -> (Rgb, Rgb) {
        let (f0, f90) = self.dielectric_f0_f90();
        let table = albedo_table();
        // Delta lobes reflect exactly F_d(μ): the r = 0 row.
        let r = if self.is_delta() {
            0.0
        } else {
            self.roughness.clamp(0.0, 1.0)
        };
        let (a, b) = table.lookup(mu, r);
        let (a_avg, b_avg) = table.average(r);
        if self.ior < 1.0 {
            // From the denser side F_d reaches 1 (TIR): bound E by F ≡ 1.
            return (Rgb::splat(a), Rgb::splat(a_avg));
        }
        let df = Rgb::splat(f90) - f0;
        (f0 * a + df * b, f0 * a_avg + df * b_avg)
    }

    /// The energy-conserving Lambert base (see the module doc).
    fn diffuse(&self, mu_o: f32, mu_i: f32) -> Rgb {
        let w = (1.0 - self.metallic()) * (1.0 - self.transmission());
        if w <= 0.0 {
            return Rgb::ZERO;
        }
        let (e_o, e_avg) = self.specular_albedo(mu_o);
        let (e_i, _) = self.specular_albedo(mu_i);
        let mut scale = Rgb::ZERO;
        for band in 0..3 {
            let rest = 1.0 - e_avg[band];
            if rest > 1e-6 {
                scale[band] = (1.0 - e_o[band]).max(0.0) * (1.0 - e_i[band]).max(0.0) / rest;
            }
        }
        self.base_color * scale * (w * FRAC_1_PI)
    }

    /// Probability of choosing the diffuse base in `sample`.
    fn diffuse_probability(&self, mu_o: f32) -> f32 {
        let w = (1.0 - self.metallic()) * (1.0 - self.transmission());
        let (e_o, _) = self.specular_albedo(mu_o);
        let w_d = w * mean(self.base_color * (Rgb::ONE - e_o).max(Rgb::ZERO));
        let w_g = mean(self.f_reflect(mu_o)) + mean(self.f_transmit(mu_o));
        if w_d <= 0.0 {
            0.0
        } else if w_g <= 0.0 {
            1.0
        } else {
            (w_d / (w_d + w_g)).clamp(0.05, 0.95)
        }
    }

    /// Probability of reflecting (not refracting) at a microfacet, ωo·m = `cos`.
    fn reflect_probability(&self, cos: f32) -> f32 {
        let r = mean(self.f_reflect(cos));
        let t = mean(self.f_transmit(cos));
        if t <= 0.0 { 1.0 } else { r / (r + t) }
    }

    /// f(ωo, ωi) of the non-delta lobes (radiance form).
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z <= 0.0 {
            return Rgb::ZERO;
        }
        let delta = self.is_delta();
        if wi.z > 0.0 {
            let mut f = self.diffuse(wo.z, wi.z);
            if !delta && let Some(m) = reflection_half_vector(wo, wi) {
                f += self.f_reflect(wo.dot(m)) * reflection_core(&self.ggx(), wo, wi, m);
            }
            f
        } else if wi.z < 0.0 && !delta && self.has_transmission() {
            match transmission_half_vector(wo, wi, self.ior) {
                Some(m) => {
                    self.f_transmit(wo.dot(m)) * transmission_core(&self.ggx(), wo, wi, m, self.ior)
                }
                None => Rgb::ZERO,
            }
        } else {
            Rgb::ZERO
        }
    }

    /// Density of `sample` through its non-delta lobes.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 {
            return 0.0;
        }
        let delta = self.is_delta();
        let p_d = self.diffuse_probability(wo.z);
        if wi.z > 0.0 {
            let mut p = p_d * cosine_hemisphere_pdf(wi.z);
            if !delta && let Some(m) = reflection_half_vector(wo, wi) {
                let c = wo.dot(m);
                if c > 0.0 {
                    p += (1.0 - p_d) * self.ggx().pdf_visible(wo, m) / (4.0 * c)
                        * self.reflect_probability(c);
                }
            }
            p
        } else if wi.z < 0.0 && !delta && self.has_transmission() {
            match transmission_half_vector(wo, wi, self.ior) {
                Some(m) => {
                    let c = wo.dot(m);
                    (1.0 - p_d)
                        * self.ggx().pdf_visible(wo, m)
                        * transmission_jacobian(wo, wi, m, self.ior)
                        * (1.0 - self.reflect_probability(c))
                }
                None => 0.0,
            }
        } else {
            0.0
        }
    }

    /// `u_lobe` picks the diffuse base or the specular microfacets; within
    /// the latter, m is drawn from the visible normals (m = z when delta) and
    /// reflection or refraction chosen in proportion to their reflectance
    /// and transmittance at m.
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: [f32; 2]) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let p_d = self.diffuse_probability(wo.z);
        if u_lobe < p_d {
            return self.non_delta_sample(wo, square_to_cosine_hemisphere(u));
        }
        let u2 = ((u_lobe - p_d) / (1.0 - p_d)).min(1.0 - f32::EPSILON);
        let delta = self.is_delta();
        let m = if delta {
            Vec3::Z
        } else {
            self.ggx().sample_visible(wo, u)
        };
        let c = wo.dot(m);
        if c <= 0.0 {
            return None;
        }
        let q = self.reflect_probability(c);
        if u2 < q {
            let wi = reflect(wo, m);
            if wi.z <= 0.0 {
                return None;
            }
            if delta {
                let p = (1.0 - p_d) * q;
                Some(BsdfSample {
                    wi,
                    weight: self.f_reflect(c) / p,
                    pdf: p,
                    delta: true,
                    eta: 1.0,
                })
            } else {
                self.non_delta_sample(wo, wi)
            }
        } else {
            let wi = refract(wo, m, self.ior)?.normalize();
            if wi.z >= 0.0 {
                return None;
            }
            if delta {
                let p = (1.0 - p_d) * (1.0 - q);
                Some(BsdfSample {
                    wi,
                    weight: self.f_transmit(c) / (self.ior * self.ior * p),
                    pdf: p,
                    delta: true,
                    eta: self.ior,
                })
            } else {
                self.non_delta_sample(wo, wi)
            }
        }
    }

    /// A non-delta direction with weight f·|cos θi|/pdf over all lobes.
    fn non_delta_sample(&self, wo: Vec3, wi: Vec3) -> Option<BsdfSample> {
        let pdf = self.pdf(wo, wi);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.eval(wo, wi) * (wi.z.abs() / pdf),
            pdf,
            delta: false,
            eta: if wi.z < 0.0 { self.ior } else { 1.0 },
        })
    }

    pub fn flags(&self) -> BsdfFlags {
        let delta = self.is_delta();
        let diffuse = (1.0 - self.metallic()) * (1.0 - self.transmission()) > 0.0;
        BsdfFlags {
            non_delta: !delta || diffuse,
            delta,
            transmission: self.has_transmission(),
        }
    }

    /// Mirror reflection with F = mix(F_d, F_m, metallic) and, with
    /// transmission, Snell refraction with `(1 − F_d) base_color / η²`.
    pub fn specular(&self, wo: Vec3) -> SpecularSet {
        let mut set = SpecularSet::default();
        if !self.is_delta() || wo.z <= 0.0 {
            return set;
        }
        set.push(reflect(wo, Vec3::Z), self.f_reflect(wo.z));
        if self.has_transmission()
            && let Some(wi) = refract(wo, Vec3::Z, self.ior)
        {
            set.push(
                wi.normalize(),
                self.f_transmit(wo.z) / (self.ior * self.ior),
            );
        }
        set
    }

    /// The base colour.
    pub fn albedo(&self) -> Rgb {
        self.base_color
    }

    /// Base colour multiplied by `t` (baseColorTexture).
    pub fn tinted(self, t: Rgb) -> Self {
        Self {
            base_color: self.base_color * t,
            ..self
        }
    }
}

impl MetallicRoughness {
    /// Nodes (μ, roughness) per axis of the Kulla–Conty tables `eval` uses.
    pub const ALBEDO_TABLE_SIZE: [usize; 2] = [TABLE_MU, TABLE_R];

    /// The Kulla–Conty tables exactly as `eval` reads them, for GPU twins:
    /// `[a, b, a_avg, b_avg]`. `a` and `b` hold `TABLE_R` rows of `TABLE_MU`
    /// nodes (index `ir · TABLE_MU + im`) at x = √μ = im/(TABLE_MU − 1) and
    /// y = √roughness = ir/(TABLE_R − 1), interpolated bilinearly in (x, y);
    /// `a_avg` and `b_avg` hold one cosine average per row, interpolated
    /// linearly in y.
    pub fn albedo_tables() -> [&'static [f32]; 4] {
        let t = albedo_table();
        [&t.a, &t.b, &t.a_avg, &t.b_avg]
    }
}

/// The split-sum ("DFG") factors of GGX with Schlick Fresnel (Karis 2013,
/// "Real Shading in Unreal Engine 4"): the directional albedo of a GGX lobe
/// of perceptual `roughness` (α = roughness²) at `mu` = cos θo is
/// `E(μ) = ∫ F(ωo·m) D_ωo(m) G2/G1 dm = f0·A + (f90 − f0)·B` for
/// `F = f0 + (f90 − f0)(1 − ωo·m)⁵`, so (A, B) = (Karis's scale + bias,
/// bias) for f90 = 1. The Kulla–Conty table `eval` uses, interpolated
/// bilinearly in (√μ, √roughness); roughness 0 gives (1, (1 − μ)⁵).
pub fn ggx_split_sum(mu: f32, roughness: f32) -> (f32, f32) {
    albedo_table().lookup(mu.clamp(0.0, 1.0), roughness.clamp(0.0, 1.0))
}

fn mean(c: Rgb) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

const TABLE_MU: usize = 33;
const TABLE_R: usize = 33;
/// Quadrature points per axis of the visible-normal square per table entry.
const TABLE_QUAD: usize = 64;

/// The specular directional albedo of GGX with Schlick Fresnel split into
/// its f0 and (f90 − f0) parts, `A = ∫ D_ωo G2/G1 dm` and
/// `B = ∫ D_ωo G2/G1 (1 − ωo·m)⁵ dm`, on a grid uniform in y = √roughness
/// and x = √μ (μ = cos θo): E changes fastest at grazing and small roughness.
#[derive(Debug)]
struct AlbedoTable {
    a: Vec<f32>,
    b: Vec<f32>,
    /// 2∫A μ dμ and 2∫B μ dμ per roughness row, exact for the piecewise
    /// linear interpolation `lookup` does in x = √μ.
    a_avg: Vec<f32>,
    b_avg: Vec<f32>,
}

fn albedo_table() -> &'static AlbedoTable {
    static TABLE: OnceLock<AlbedoTable> = OnceLock::new();
    TABLE.get_or_init(AlbedoTable::build)
}

impl AlbedoTable {
    fn build() -> Self {
        let mut a = vec![0.0; TABLE_MU * TABLE_R];
        let mut b = vec![0.0; TABLE_MU * TABLE_R];
        for ir in 0..TABLE_R {
            let y = ir as f32 / (TABLE_R - 1) as f32;
            let r = y * y;
            let ggx = Ggx::from_roughness(r);
            for im in 0..TABLE_MU {
                let x = im as f32 / (TABLE_MU - 1) as f32;
                let mu = x * x;
                let idx = ir * TABLE_MU + im;
                if ir == 0 {
                    // Smooth limit: E = F(μ).
                    a[idx] = 1.0;
                    b[idx] = (1.0 - mu).powi(5);
                    continue;
                }
                let mu = mu.max(1e-4);
                let wo = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
                let g1 = ggx.g1(wo);
                let (mut sa, mut sb) = (0.0f64, 0.0f64);
                for i in 0..TABLE_QUAD {
                    for j in 0..TABLE_QUAD {
                        let u = [
                            (i as f32 + 0.5) / TABLE_QUAD as f32,
                            (j as f32 + 0.5) / TABLE_QUAD as f32,
                        ];
                        let m = ggx.sample_visible(wo, u);
                        let wi = reflect(wo, m);
                        if wi.z <= 0.0 {
                            continue;
                        }
                        let g = (ggx.g2(wo, wi) / g1) as f64;
                        sa += g;
                        sb += g * (1.0 - wo.dot(m).clamp(0.0, 1.0) as f64).powi(5);
                    }
                }
                let n = (TABLE_QUAD * TABLE_QUAD) as f64;
                a[idx] = (sa / n) as f32;
                b[idx] = (sb / n) as f32;
            }
        }
        // 2∫E μ dμ = ∫E 4x³ dx; on a segment E = p + q x, whose integral
        // against 4x³ is [p x⁴ + (4/5) q x⁵].
        let row_avg = |t: &[f32], ir: usize| -> f32 {
            let h = 1.0 / (TABLE_MU - 1) as f64;
            let row = &t[ir * TABLE_MU..(ir + 1) * TABLE_MU];
            let mut s = 0.0;
            for j in 0..TABLE_MU - 1 {
                let (x0, x1) = (j as f64 * h, (j + 1) as f64 * h);
                let q = (row[j + 1] - row[j]) as f64 / h;
                let p = row[j] as f64 - q * x0;
                s += p * (x1.powi(4) - x0.powi(4)) + 0.8 * q * (x1.powi(5) - x0.powi(5));
            }
            s as f32
        };
        let a_avg = (0..TABLE_R).map(|ir| row_avg(&a, ir)).collect();
        let b_avg = (0..TABLE_R).map(|ir| row_avg(&b, ir)).collect();
        Self { a, b, a_avg, b_avg }
    }

    fn cell(x: f32, n: usize) -> (usize, f32) {
        let x = x.clamp(0.0, 1.0) * (n - 1) as f32;
        let i = (x as usize).min(n - 2);
        (i, x - i as f32)
    }

    /// Bilinear (A, B) at (√μ, √roughness).
    fn lookup(&self, mu: f32, r: f32) -> (f32, f32) {
        let (im, fm) = Self::cell(mu.max(0.0).sqrt(), TABLE_MU);
        let (ir, fr) = Self::cell(r.max(0.0).sqrt(), TABLE_R);
        let at = |t: &[f32]| {
            let v = |i: usize, j: usize| t[i * TABLE_MU + j];
            let lo = v(ir, im) * (1.0 - fm) + v(ir, im + 1) * fm;
            let hi = v(ir + 1, im) * (1.0 - fm) + v(ir + 1, im + 1) * fm;
            lo * (1.0 - fr) + hi * fr
        };
        (at(&self.a), at(&self.b))
    }

    /// (2∫A μ dμ, 2∫B μ dμ) at roughness r, interpolated like `lookup`.
    fn average(&self, r: f32) -> (f32, f32) {
        let (ir, fr) = Self::cell(r.max(0.0).sqrt(), TABLE_R);
        let lerp = |t: &[f32]| t[ir] * (1.0 - fr) + t[ir + 1] * fr;
        (lerp(&self.a_avg), lerp(&self.b_avg))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::TestRng;

    /// The quadrature table against an independent Monte Carlo estimate with
    /// random visible normals, and its averages against dense quadrature.
    #[test]
    fn albedo_table_matches_monte_carlo() {
        let t = albedo_table();
        let node = |i: usize| (i as f32 / 32.0).powi(2);
        for (xi, yi) in [(32, 32), (16, 16), (4, 8), (24, 6), (2, 20)] {
            let (mu, r) = (node(xi), node(yi));
            let (a, b) = t.lookup(mu, r);
            let ggx = Ggx::from_roughness(r);
            let wo = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
            let mut rng = TestRng::new(xi as u64 * 100 + yi as u64);
            let n = 200_000;
            let (mut sa, mut sb) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let m = ggx.sample_visible(wo, rng.next_2d());
                let wi = reflect(wo, m);
                if wi.z > 0.0 {
                    let g = (ggx.g2(wo, wi) / ggx.g1(wo)) as f64;
                    sa += g;
                    sb += g * (1.0 - wo.dot(m) as f64).powi(5);
                }
            }
            let (ma, mb) = ((sa / n as f64) as f32, (sb / n as f64) as f32);
            assert!((a - ma).abs() < 3e-3, "A(μ {mu}, r {r}) = {a} vs MC {ma}");
            assert!((b - mb).abs() < 3e-3, "B(μ {mu}, r {r}) = {b} vs MC {mb}");
        }
        // Smooth limit: E = Schlick.
        let (a, b) = t.lookup(0.25, 0.0);
        assert!((a - 1.0).abs() < 1e-6 && (b - 0.75f32.powi(5)).abs() < 1e-6);
        // The averages are the cosine-weighted integrals of the interpolant.
        for r in [0.0f32, 0.1, 0.5, 0.93] {
            let n = 20_000;
            let (mut sa, mut sb) = (0.0f64, 0.0f64);
            for i in 0..n {
                let mu = (i as f32 + 0.5) / n as f32;
                let (a, b) = t.lookup(mu, r);
                sa += 2.0 * (a * mu) as f64 / n as f64;
                sb += 2.0 * (b * mu) as f64 / n as f64;
            }
            let (a_avg, b_avg) = t.average(r);
            assert!((a_avg as f64 - sa).abs() < 1e-4, "r {r}: {a_avg} vs {sa}");
            assert!((b_avg as f64 - sb).abs() < 1e-4, "r {r}: {b_avg} vs {sb}");
        }
    }

    /// Table nodes against the reflectance integral written out in f64
    /// over incident directions, with a GGX of the test's own:
    /// A = ∫ D(h) G2(ωo, ωi) / (4 μo) dωi (F = 1), B the same with
    /// (1 − ωo·h)⁵, D = α² / (π (μh² (α² − 1) + 1)²), Λ(ω) = (√(1 + α² tan²θ)
    /// − 1)/2, G2 = 1/(1 + Λo + Λi); a midpoint grid in (θi, φi) of
    /// 2048 × 1024 over the half space φ ∈ [0, π] (the lobe is symmetric).
    #[test]
    fn albedo_table_nodes_match_the_integral() {
        let t = albedo_table();
        for (im, ir) in [(16, 24), (32, 24), (8, 32), (24, 32), (28, 28)] {
            let x = im as f64 / 32.0;
            let mu = x * x;
            let rough = (ir as f64 / 32.0).powi(2);
            let a2 = rough.powi(4);
            let lambda = |cos: f64| {
                let tan2 = (1.0 - cos * cos) / (cos * cos);
                ((1.0 + a2 * tan2).sqrt() - 1.0) / 2.0
            };
            let wo = [(1.0 - mu * mu).sqrt(), 0.0, mu];
            let (nt, np) = (2048, 1024);
            let (dt, dp) = (
                std::f64::consts::FRAC_PI_2 / nt as f64,
                std::f64::consts::PI / np as f64,
            );
            let (mut sa, mut sb) = (0.0, 0.0);
            for i in 0..nt {
                let theta = (i as f64 + 0.5) * dt;
                let (st, ct) = theta.sin_cos();
                for j in 0..np {
                    let phi = (j as f64 + 0.5) * dp;
                    let wi = [st * phi.cos(), st * phi.sin(), ct];
                    let h = [wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]];
                    let len = (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
                    let hz = h[2] / len;
                    let o_h = (wo[0] * h[0] + wo[2] * h[2]) / len;
                    let d = a2 / (std::f64::consts::PI * (hz * hz * (a2 - 1.0) + 1.0).powi(2));
                    let g2 = 1.0 / (1.0 + lambda(mu) + lambda(ct));
                    let f = d * g2 / (4.0 * mu) * st * dt * dp * 2.0;
                    sa += f;
                    sb += f * (1.0 - o_h).powi(5);
                }
            }
            let idx = ir * TABLE_MU + im;
            let (a, b) = (t.a[idx] as f64, t.b[idx] as f64);
            // The table's 64 × 64 points per entry are within 5·10⁻⁴ of
            // it (a grid twice as fine here moves it by under 10⁻⁶).
            assert!((a - sa).abs() < 6e-4, "A(μ {mu}, r {rough}) = {a} vs {sa}");
            assert!((b - sb).abs() < 6e-4, "B(μ {mu}, r {rough}) = {b} vs {sb}");
        }
    }

    /// A white specular (specular colour 25 · f0 0.04, clamped to 1, so
    /// F = 1 at every angle) outweighs the base: its weight mean(F) = 1,
    /// the base's mean(base · (1 − E)) < 1, so the base is sampled less
    /// than half the time.
    #[test]
    fn a_white_specular_outweighs_the_base() {
        let mut m = MetallicRoughness::new(Rgb::new(0.9, 0.8, 0.7), 0.0, 0.6);
        m.specular_color = Rgb::splat(25.0);
        for mu in [0.2, 0.5, 0.9] {
            assert_eq!(m.f_reflect(mu), Rgb::ONE);
            let p = m.diffuse_probability(mu);
            assert!((0.05..0.5).contains(&p), "μ {mu}: p_d = {p}");
        }
    }
}
