//! Smooth conductor: mirror reflection weighted by the Fresnel reflectance of
//! a complex index n + iκ per RGB band.

use super::FresnelModel;
use crate::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    /// Real part n of the index per band (relative to the outside medium).
    pub eta: Rgb,
    /// Extinction coefficient κ per band.
    pub k: Rgb,
    pub fresnel: FresnelModel,
}
