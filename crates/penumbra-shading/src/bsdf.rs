//! BSDFs. A closed set, so an enum over one struct per model (pbrt-v4 style):
//! no allocation and no dynamic dispatch per lobe.
//!
//! ## The contract every model follows
//! Every function works in the **local shading frame**: z = shading normal,
//! unit directions pointing **away** from the surface. The integrator always
//! orients the frame so that `wo.z > 0`; when it had to flip the frame (the
//! surface is seen from its back) it calls [`Bsdf::seen_from_back`], which
//! inverts the relative index η of transmissive models. So for every model
//! "outside" is the side of `wo`, and `eta` = n_inside / n_outside.
//!
//! - `eval(wo, wi) -> Rgb`: f(wo, wi) in 1/sr **without** the cosine, of the
//!   non-delta lobes only (0 for a purely specular model);
//! - `pdf(wo, wi) -> f32`: solid-angle density with which `sample` returns
//!   `wi` through a non-delta lobe (lobe selection probability included);
//! - `sample(wo, u_lobe, u) -> Option<BsdfSample>`: `u_lobe` ∈ [0,1) picks a
//!   lobe (diffuse/specular, reflect/transmit), `u` ∈ [0,1)² the direction;
//!   `weight` = f·|cos θi|/pdf (for a delta lobe: the lobe's throughput
//!   divided by its selection probability);
//! - `specular(wo) -> SpecularSet`: the delta lobes as (direction, throughput)
//!   pairs, for Whitted-style branching (empty if none);
//! - `flags() -> BsdfFlags`, `albedo() -> Rgb` (a colour summary for the
//!   albedo AOV and lobe selection), `tinted(t) -> Self` (base colour × t, for
//!   textures).
//!
//! Radiance crossing a refractive boundary is scaled by (n_t/n_i)², with n_i
//! and n_t the indices before and after the boundary in the direction the
//! light travels: light leaving glass (η = 1.5) towards `wo` outside is
//! divided by η². Radiance, not importance, is transported.

mod conductor;
mod conductor_presets;
mod dielectric;
mod lambert;
mod metallic_roughness;
mod microfacet;
mod mirror;
pub mod optics;
mod phong;
mod rough_conductor;
mod rough_dielectric;

pub use conductor::Conductor;
pub use conductor_presets::{CONDUCTOR_PRESETS, conductor_preset};
pub use dielectric::Dielectric;
pub use lambert::Lambert;
pub use metallic_roughness::{DELTA_ALPHA, MetallicRoughness, ggx_split_sum};
pub use microfacet::{Ggx, MIN_ALPHA};
pub use mirror::Mirror;
pub use optics::FresnelModel;
pub use phong::{PhongBlinn, PhongVariant};
pub use rough_conductor::RoughConductor;
pub use rough_dielectric::RoughDielectric;

use crate::Rgb;
use glam::Vec3;

/// One sampled direction of a BSDF.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// Sampled incident direction (local frame).
    pub wi: Vec3,
    /// f(wo, wi) · |cos θi| / pdf (delta lobes: throughput / selection probability).
    pub weight: Rgb,
    /// Solid-angle density of `wi`; for a delta lobe its selection probability.
    pub pdf: f32,
    /// The direction came from a delta (ideally specular) lobe.
    pub delta: bool,
    /// Relative index of refraction η crossed when `wi` is transmitted
    /// (1 for reflection). Transmitted radiance is scaled by 1/η² (Veach
    /// 1997, §5.2), which `weight` includes; a path tracer multiplies
    /// the η² back before Russian roulette so that paths inside glass are
    /// not ended for a factor that leaving the glass undoes.
    pub eta: f32,
}

/// What kinds of lobes a BSDF has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BsdfFlags {
    /// Has a lobe with a density (can be evaluated for light samples).
    pub non_delta: bool,
    /// Has an ideally specular (delta) lobe.
    pub delta: bool,
    /// Can send light to the far side of the surface.
    pub transmission: bool,
}

impl BsdfFlags {
    pub const DIFFUSE: Self = Self {
        non_delta: true,
        delta: false,
        transmission: false,
    };
    pub const SPECULAR_REFLECTION: Self = Self {
        non_delta: false,
        delta: true,
        transmission: false,
    };
}

/// Up to two delta lobes: direction (local frame) and throughput
/// (f·|cos|/"pdf" of the lobe, e.g. F for mirror reflection).
#[derive(Clone, Copy, Debug, Default)]
pub struct SpecularSet {
    len: usize,
    items: [(Vec3, Rgb); 2],
}

impl SpecularSet {
    /// Adds a lobe; at most two fit (reflection and transmission).
    pub fn push(&mut self, wi: Vec3, throughput: Rgb) {
        debug_assert!(self.len < 2);
        if self.len < 2 && throughput.max_element() > 0.0 {
            self.items[self.len] = (wi, throughput);
            self.len += 1;
        }
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn iter(&self) -> impl Iterator<Item = (Vec3, Rgb)> + '_ {
        self.items[..self.len].iter().copied()
    }
}

/// The BSDF models penumbra knows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bsdf {
    Lambert(Lambert),
    PhongBlinn(PhongBlinn),
    Mirror(Mirror),
    Conductor(Conductor),
    Dielectric(Dielectric),
    RoughConductor(RoughConductor),
    RoughDielectric(RoughDielectric),
    MetallicRoughness(MetallicRoughness),
}

/// `match` over every model, binding it to `$m` (static dispatch).
macro_rules! each_model {
    ($bsdf:expr, $m:ident => $body:expr) => {
        match $bsdf {
            Bsdf::Lambert($m) => $body,
            Bsdf::PhongBlinn($m) => $body,
            Bsdf::Mirror($m) => $body,
            Bsdf::Conductor($m) => $body,
            Bsdf::Dielectric($m) => $body,
            Bsdf::RoughConductor($m) => $body,
            Bsdf::RoughDielectric($m) => $body,
            Bsdf::MetallicRoughness($m) => $body,
        }
    };
}

impl Bsdf {
    /// f(wo, wi) [1/sr] of the non-delta lobes, cosine not included.
    #[inline]
    pub fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        each_model!(self, m => m.eval(wo, wi))
    }

    /// Solid-angle pdf of [`Bsdf::sample`] choosing `wi` by a non-delta lobe.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        each_model!(self, m => m.pdf(wo, wi))
    }

    /// Samples `wi`; `None` if no direction is possible.
    #[inline]
    pub fn sample(&self, wo: Vec3, u_lobe: f32, u: [f32; 2]) -> Option<BsdfSample> {
        each_model!(self, m => m.sample(wo, u_lobe, u))
    }

    /// The delta lobes at `wo` (Whitted recursion).
    #[inline]
    pub fn specular(&self, wo: Vec3) -> SpecularSet {
        each_model!(self, m => m.specular(wo))
    }

    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        each_model!(self, m => m.flags())
    }

    /// A colour summary of the reflectance, for the albedo AOV.
    pub fn albedo(&self) -> Rgb {
        each_model!(self, m => m.albedo())
    }

    /// c_diff: the albedo of the model's Lambertian lobe alone, what an
    /// irradiance map is multiplied by (`B = c_diff · E`, notes 004): ρ for
    /// Lambert, π kd for the Phong–Blinn family, the base colour ×
    /// (1 − metallic)(1 − transmission) for metallic–roughness (its diffuse
    /// base before the Kulla–Conty energy scaling, which depends on the
    /// directions); 0 for models without a diffuse lobe.
    pub fn diffuse_albedo(&self) -> Rgb {
        match self {
            Bsdf::Lambert(m) => m.albedo,
            Bsdf::PhongBlinn(m) => m.kd * std::f32::consts::PI,
            Bsdf::MetallicRoughness(m) => {
                m.base_color * ((1.0 - m.metallic) * (1.0 - m.transmission))
            }
            Bsdf::Mirror(_)
            | Bsdf::Conductor(_)
            | Bsdf::Dielectric(_)
            | Bsdf::RoughConductor(_)
            | Bsdf::RoughDielectric(_) => Rgb::ZERO,
        }
    }

    /// The base colour multiplied by `t` (textures).
    pub fn tinted(self, t: Rgb) -> Bsdf {
        match self {
            Bsdf::Lambert(m) => Bsdf::Lambert(m.tinted(t)),
            Bsdf::PhongBlinn(m) => Bsdf::PhongBlinn(m.tinted(t)),
            Bsdf::Mirror(m) => Bsdf::Mirror(m.tinted(t)),
            Bsdf::Conductor(m) => Bsdf::Conductor(m.tinted(t)),
            Bsdf::Dielectric(m) => Bsdf::Dielectric(m.tinted(t)),
            Bsdf::RoughConductor(m) => Bsdf::RoughConductor(m.tinted(t)),
            Bsdf::RoughDielectric(m) => Bsdf::RoughDielectric(m.tinted(t)),
            Bsdf::MetallicRoughness(m) => Bsdf::MetallicRoughness(m.tinted(t)),
        }
    }

    /// The same material seen from its back: transmissive models get η → 1/η.
    pub fn seen_from_back(self) -> Bsdf {
        match self {
            Bsdf::Dielectric(m) => Bsdf::Dielectric(m.inverted()),
            Bsdf::RoughDielectric(m) => Bsdf::RoughDielectric(m.inverted()),
            Bsdf::MetallicRoughness(m) => Bsdf::MetallicRoughness(m.inverted()),
            other => other,
        }
    }
}
