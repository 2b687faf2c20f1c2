//! Ideal mirror: all light leaves in `R = v − 2n(n·v)`, scaled by a constant
//! reflectance (no Fresnel variation; see `Conductor` for that).

use crate::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mirror {
    /// Fraction reflected per band, in [0,1].
    pub reflectance: Rgb,
}
