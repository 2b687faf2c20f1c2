//! Smooth dielectric (glass, water): Fresnel-weighted ideal reflection and
//! Snell refraction, total internal reflection.

use super::FresnelModel;
use crate::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    /// Relative index η = n_inside / n_outside.
    pub eta: f32,
    /// Colour multiplying transmitted light (1 = clear).
    pub tint: Rgb,
    pub fresnel: FresnelModel,
}
