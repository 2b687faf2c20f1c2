//! Named conductors: complex index n + iκ per RGB band, for
//! `Conductor`/`RoughConductor` (`preset = "gold"` in scene files).
//!
//! The three bands are sampled at single wavelengths, the tabulated points of
//! Johnson & Christy closest to 650/550/450 nm: **R = 659.5 nm (1.88 eV),
//! G = 548.6 nm (2.26 eV), B = 450.9 nm (2.75 eV)**. Values relative to
//! vacuum (air, to the precision given).
//!
//! Sources:
//! - gold, silver, copper: P. B. Johnson and R. W. Christy, "Optical
//!   constants of the noble metals", Phys. Rev. B 6, 4370 (1972), Table 1
//!   (as tabulated on refractiveindex.info, `main/{Au,Ag,Cu}/Johnson`);
//! - aluminium: the Lorentz–Drude fit of A. D. Rakić, A. B. Djurišić,
//!   J. M. Elazar and M. L. Majewski, "Optical properties of metallic films
//!   for vertical-cavity optoelectronic devices", Appl. Opt. 37, 5271 (1998),
//!   Table 2 (ωp = 14.98 eV, f0 = 0.523, Γ0 = 0.047 eV and four
//!   oscillators), evaluated at the same three photon energies (at 620 nm
//!   it agrees with Hagemann et al. 1974 to about 1.5 %; not checked
//!   against a tabulation at these exact wavelengths).
//!
//! Normal-incidence reflectances `((n−1)² + κ²)/((n+1)² + κ²)` (R, G, B):
//! gold 0.963/0.787/0.408, silver 0.991/0.983/0.980, copper 0.943/0.619/0.539,
//! aluminium 0.907/0.915/0.923.

use crate::Rgb;

/// Names accepted by [`conductor_preset`].
pub const CONDUCTOR_PRESETS: &[&str] = &["gold", "silver", "copper", "aluminium"];

/// (η, κ) per band (R, G, B at 659.5, 548.6, 450.9 nm) of a named conductor;
/// `aluminum` is accepted for `aluminium`. `None` for an unknown name.
pub fn conductor_preset(name: &str) -> Option<(Rgb, Rgb)> {
    let (n, k) = match name {
        // Johnson & Christy 1972.
        "gold" => ([0.14, 0.43, 1.38], [3.697, 2.455, 1.914]),
        "silver" => ([0.05, 0.06, 0.04], [4.483, 3.586, 2.657]),
        "copper" => ([0.22, 1.02, 1.24], [3.747, 2.577, 2.397]),
        // Rakić et al. 1998 Lorentz–Drude model.
        "aluminium" | "aluminum" => ([1.467, 0.960, 0.593], [7.560, 6.443, 5.322]),
        _ => return None,
    };
    Some((Rgb::from(n), Rgb::from(k)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::optics::f0_from_ior;

    fn f0(name: &str) -> Rgb {
        let (n, k) = conductor_preset(name).unwrap();
        f0_from_ior(n, k)
    }

    #[test]
    fn conductor_presets_every_name_resolves() {
        for name in CONDUCTOR_PRESETS {
            let (n, k) = conductor_preset(name).unwrap();
            assert!(n.min_element() > 0.0 && k.min_element() > 1.0, "{name}");
        }
        assert_eq!(conductor_preset("aluminum"), conductor_preset("aluminium"));
        assert!(conductor_preset("brass").is_none());
        assert!(conductor_preset("Gold").is_none());
    }

    #[test]
    fn conductor_presets_have_their_colours() {
        // Gold: yellow (red > green > blue, blue well below).
        let au = f0("gold");
        assert!(au.x > au.y && au.y > au.z && au.z < 0.5, "{au}");
        assert!(au.x > 0.95, "{au}");
        // Copper: reddish, red clearly above green and blue.
        let cu = f0("copper");
        assert!(cu.x > 0.9 && cu.x - cu.y > 0.25 && cu.y > cu.z, "{cu}");
        // Silver: nearly white and the most reflective.
        let ag = f0("silver");
        assert!(ag.min_element() > 0.97, "{ag}");
        assert!(ag.max_element() - ag.min_element() < 0.02, "{ag}");
        // Aluminium: ≈ 0.9, nearly neutral, a little bluish.
        let al = f0("aluminium");
        assert!((al - Rgb::splat(0.915)).abs().max_element() < 0.015, "{al}");
        assert!(al.z > al.x, "{al}");
        assert!(ag.min_element() > al.max_element());
    }
}
