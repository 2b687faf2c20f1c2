//! Smooth dielectric (glass, water): Fresnel-weighted ideal reflection and
//! Snell refraction, total internal reflection.
//!
//! `wo` is outside (`wo.z > 0`), η = n_inside / n_outside; the material seen
//! from its back is [`Dielectric::inverted`] (η → 1/η).
//!
//! | quantity               | value                                                    |
//! |------------------------|----------------------------------------------------------|
//! | `eval`, `pdf`          | 0 (pure delta lobes)                                     |
//! | F, Exact               | `fresnel_dielectric(cos θo, η)`                          |
//! | F, Schlick             | `schlick_dielectric(cos θo, η)`, F0 = ((η − 1)/(η + 1))² |
//! | reflection             | `wi = reflect(wo, z)`, throughput `F`                    |
//! | transmission           | `wi = refract(wo, z, η)` (`sin θo = η sin θi`), throughput `(1 − F) · tint / η²` |
//! | total internal refl.   | `refract` fails ⇒ F = 1, reflection only                 |
//! | `sample` (u_lobe < F)  | reflection, pdf `F`, weight `1`                          |
//! | `sample` (u_lobe ≥ F)  | transmission, pdf `1 − F`, weight `tint / η²`            |
//! | `albedo`               | `tint`                                                   |
//!
//! The 1/η² is the radiance scaling: the transmitted light travels from inside
//! (index η relative to outside) to `wo` outside, and radiance / n² is
//! invariant across the boundary, so it leaves with `L / η²`. With tint 1,
//! `F + η² · T = 1` (energy conservation of the flux).

use super::optics::{fresnel_dielectric, reflect, refract, schlick_dielectric};
use super::{BsdfFlags, BsdfSample, FresnelModel, SpecularSet};
use crate::Rgb;
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    /// Relative index η = n_inside / n_outside.
    pub eta: f32,
    /// Colour multiplying transmitted light (1 = clear).
    pub tint: Rgb,
    pub fresnel: FresnelModel,
}

/// The two delta lobes at one `wo`.
struct Lobes {
    /// Probability (and throughput) of reflection; 1 under total internal reflection.
    f: f32,
    reflected: Vec3,
    /// `None` under total internal reflection.
    transmitted: Option<Vec3>,
}

impl Dielectric {
    /// A dielectric of relative index `eta` = n_inside / n_outside.
    pub fn new(eta: f32, tint: Rgb, fresnel: FresnelModel) -> Self {
        Self { eta, tint, fresnel }
    }

    /// Clear glass in air: η = 1.5, exact Fresnel.
    pub fn glass() -> Self {
        Self::new(1.5, Rgb::ONE, FresnelModel::Exact)
    }

    /// The same interface seen from the other side: η → 1/η.
    pub fn inverted(self) -> Self {
        Self {
            eta: 1.0 / self.eta,
            ..self
        }
    }

    /// Fresnel reflectance F for light leaving along `wo` with `cos θo` ∈ `[0, 1]`
    /// (1 under total internal reflection).
    #[inline]
    pub fn reflectance(&self, cos_theta_o: f32) -> f32 {
        match self.fresnel {
            FresnelModel::Exact => fresnel_dielectric(cos_theta_o, self.eta),
            FresnelModel::Schlick => schlick_dielectric(cos_theta_o, self.eta),
        }
    }

    fn lobes(&self, wo: Vec3) -> Lobes {
        let f = self.reflectance(wo.z);
        let transmitted = if f < 1.0 {
            refract(wo, Vec3::Z, self.eta).map(|t| t.normalize())
        } else {
            None
        };
        Lobes {
            f: if transmitted.is_some() { f } else { 1.0 },
            reflected: reflect(wo, Vec3::Z),
            transmitted,
        }
    }

    /// Throughput of the transmission lobe when a fraction `1 − f` crosses.
    #[inline]
    fn transmittance(&self, f: f32) -> Rgb {
        self.tint * ((1.0 - f) / (self.eta * self.eta))
    }

    /// Purely specular: no density anywhere.
    #[inline]
    pub fn eval(&self, _wo: Vec3, _wi: Vec3) -> Rgb {
        Rgb::ZERO
    }

    /// Purely specular: no density anywhere.
    #[inline]
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    /// Reflection if `u_lobe < F` (weight F/F = 1), else transmission
    /// (weight (1 − F)·tint/η² / (1 − F) = tint/η²).
    #[inline]
    pub fn sample(&self, wo: Vec3, u_lobe: f32, _u: [f32; 2]) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let l = self.lobes(wo);
        match l.transmitted {
            Some(wt) if u_lobe >= l.f => Some(BsdfSample {
                wi: wt,
                weight: self.tint / (self.eta * self.eta),
                pdf: 1.0 - l.f,
                delta: true,
                eta: self.eta,
            }),
            _ => Some(BsdfSample {
                wi: l.reflected,
                weight: Rgb::ONE,
                pdf: l.f,
                delta: true,
                eta: 1.0,
            }),
        }
    }

    /// Both lobes: (reflect(wo), F) and (refract(wo), (1 − F)·tint/η²);
    /// reflection only under total internal reflection.
    pub fn specular(&self, wo: Vec3) -> SpecularSet {
        let mut set = SpecularSet::default();
        if wo.z <= 0.0 {
            return set;
        }
        let l = self.lobes(wo);
        set.push(l.reflected, Rgb::splat(l.f));
        if let Some(wt) = l.transmitted {
            set.push(wt, self.transmittance(l.f));
        }
        set
    }

    /// Delta reflection and transmission.
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags {
            non_delta: false,
            delta: true,
            transmission: true,
        }
    }

    /// The transmission tint.
    pub fn albedo(&self) -> Rgb {
        self.tint
    }

    /// Tint multiplied by a texture colour.
    pub fn tinted(self, t: Rgb) -> Self {
        Self {
            tint: self.tint * t,
            ..self
        }
    }
}
