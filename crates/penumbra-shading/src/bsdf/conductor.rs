//! Smooth conductor: mirror reflection weighted by the Fresnel reflectance of
//! a complex index n + iκ per RGB band.
//!
//! | quantity            | value                                                      |
//! |---------------------|------------------------------------------------------------|
//! | `eval`, `pdf`       | 0 (a pure delta lobe)                                      |
//! | direction           | `wi = reflect(wo, z)`                                      |
//! | throughput, Exact   | `F = fresnel_conductor(cos θo, n, κ)` per band             |
//! | throughput, Schlick | `F = F0 + (1 − F0)(1 − cos θo)^5`                          |
//! | F0                  | `((n − 1)² + κ²) / ((n + 1)² + κ²)`                        |
//! | `sample` weight/pdf | `F` / 1, `delta = true`                                    |
//! | `albedo`            | `F0` (F at normal incidence, the same for both models)     |
//! | `tinted(t)`         | new (n, κ) with `F0' = F0·t`, same position `g` of n in its valid range |
//!
//! Tinting: for a given F0 = r, κ² ≥ 0 confines n to
//! `[(1 − √r)/(1 + √r), (1 + √r)/(1 − √r)]`, and
//! `κ² = (r (n + 1)² − (n − 1)²) / (1 − r)` gives back κ from (r, n). So
//! (r, g), g the relative position of n in that range, is a one-to-one
//! parameterisation (in the spirit of Gulbrandsen's 2014 "artist friendly"
//! reflectivity / edge-tint mapping); a tint scales r and keeps g.

use super::optics::{f0_from_ior, fresnel_conductor, reflect, schlick};
use super::{BsdfFlags, BsdfSample, FresnelModel, SpecularSet};
use crate::Rgb;
use glam::Vec3;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    /// Real part n of the index per band (relative to the outside medium).
    pub eta: Rgb,
    /// Extinction coefficient κ per band.
    pub k: Rgb,
    pub fresnel: FresnelModel,
}

/// Largest normal-incidence reflectance a tint can produce (F0 = 1 needs κ = ∞).
const MAX_F0: f64 = 0.9999;

impl Conductor {
    /// A conductor of complex index `eta + i·k` per band.
    pub fn new(eta: Rgb, k: Rgb, fresnel: FresnelModel) -> Self {
        Self { eta, k, fresnel }
    }

    /// Fresnel reflectance per band at `cos θ` ∈ `[0, 1]` (the lobe's throughput),
    /// clamped to `[0, 1]` against round-off (e.g. −3e-8 for n = 1, κ = 0).
    #[inline]
    pub fn reflectance(&self, cos_theta: f32) -> Rgb {
        let f = match self.fresnel {
            FresnelModel::Exact => fresnel_conductor(cos_theta, self.eta, self.k),
            FresnelModel::Schlick => schlick(f0_from_ior(self.eta, self.k), cos_theta),
        };
        f.clamp(Rgb::ZERO, Rgb::ONE)
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

    /// The mirror direction with weight F(cos θo) (selection probability 1).
    #[inline]
    pub fn sample(&self, wo: Vec3, _u_lobe: f32, _u: [f32; 2]) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi: reflect(wo, Vec3::Z),
            weight: self.reflectance(wo.z),
            pdf: 1.0,
            delta: true,
            eta: 1.0,
        })
    }

    /// One lobe: (reflect(wo), F(cos θo)).
    pub fn specular(&self, wo: Vec3) -> SpecularSet {
        let mut set = SpecularSet::default();
        if wo.z > 0.0 {
            set.push(reflect(wo, Vec3::Z), self.reflectance(wo.z));
        }
        set
    }

    /// Delta reflection only.
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::SPECULAR_REFLECTION
    }

    /// F0, the reflectance at normal incidence (the metal's colour).
    pub fn albedo(&self) -> Rgb {
        f0_from_ior(self.eta, self.k)
    }

    /// The conductor whose F0 is `F0 · t` (clamped below 1), with n kept at
    /// the same relative position in its admissible range (see module doc).
    pub fn tinted(self, t: Rgb) -> Self {
        let mut eta = self.eta;
        let mut k = self.k;
        for i in 0..3 {
            (eta[i], k[i]) = tint_band(self.eta[i], self.k[i], t[i]);
        }
        Self { eta, k, ..self }
    }
}

/// Admissible range of n for a normal-incidence reflectance `r`.
fn n_range(r: f64) -> (f64, f64) {
    let s = r.sqrt();
    ((1.0 - s) / (1.0 + s), (1.0 + s) / (1.0 - s))
}

/// (n, κ) of one band rescaled so that F0 becomes F0 · t.
fn tint_band(n: f32, k: f32, t: f32) -> (f32, f32) {
    let (n, k) = (n as f64, k as f64);
    let r = (((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k)).min(MAX_F0);
    let (lo, hi) = n_range(r);
    let g = if hi - lo > 1e-12 {
        ((n - lo) / (hi - lo)).clamp(0.0, 1.0)
    } else {
        0.5
    };
    let r2 = (r * t.max(0.0) as f64).min(MAX_F0);
    let (lo2, hi2) = n_range(r2);
    let n2 = lo2 + g * (hi2 - lo2);
    let k2 = ((r2 * (n2 + 1.0).powi(2) - (n2 - 1.0).powi(2)) / (1.0 - r2)).max(0.0);
    (n2 as f32, k2.sqrt() as f32)
}
