//! Radiometric and photometric units (SEEDS.md, Radiometry).
//!
//! | radiometric | photometric |
//! |---|---|
//! | power Φ [W] | luminous flux [lm] |
//! | irradiance E [W/m²] | illuminance [lux] |
//! | intensity I [W/sr] | luminous intensity [cd] |
//! | radiance L [W/(sr·m²)] | luminance [cd/m²] |
//!
//! penumbra converts with the maximum luminous efficacy, 683 lm/W, as glTF's
//! `KHR_lights_punctual` and the reference scenes do.

use std::f32::consts::PI;

/// Luminous efficacy used for every photometric ↔ radiometric conversion [lm/W].
pub const LUMENS_PER_WATT: f32 = 683.0;

/// Luminous intensity [cd] → radiant intensity [W/sr]: `I = cd / 683`.
pub fn candela_to_watts_per_sr(cd: f32) -> f32 {
    cd / LUMENS_PER_WATT
}

/// Illuminance [lux] → irradiance [W/m²]: `E = lux / 683`.
pub fn lux_to_watts_per_m2(lux: f32) -> f32 {
    lux / LUMENS_PER_WATT
}

/// Luminous flux [lm] → radiant power [W]: `Φ = lm / 683`.
pub fn lumens_to_watts(lm: f32) -> f32 {
    lm / LUMENS_PER_WATT
}

/// Isotropic point light: intensity from power, `I = Φ / 4π` [W/sr].
pub fn point_intensity_from_power(power: f32) -> f32 {
    power / (4.0 * PI)
}

/// Isotropic point light: power from intensity, `Φ = 4π I` [W].
pub fn point_power_from_intensity(intensity: f32) -> f32 {
    4.0 * PI * intensity
}

/// Irradiance at distance `r` from an isotropic point light of power Φ on a
/// surface facing it: `M = Φ / (4π r²)` (SEEDS.md, Light sources).
pub fn point_irradiance(power: f32, r: f32) -> f32 {
    power / (4.0 * PI * r * r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_light_inverse_square() {
        let phi = 100.0;
        let e1 = point_irradiance(phi, 1.0);
        let e2 = point_irradiance(phi, 2.0);
        assert!((e1 / e2 - 4.0).abs() < 1e-5);
        // I = Φ/4π and E = I / r² agree.
        assert!((point_intensity_from_power(phi) / 9.0 - point_irradiance(phi, 3.0)).abs() < 1e-6);
        assert!((point_power_from_intensity(point_intensity_from_power(phi)) - phi).abs() < 1e-4);
    }

    #[test]
    fn photometric_conversions() {
        assert!((candela_to_watts_per_sr(683.0) - 1.0).abs() < 1e-6);
        assert!((lux_to_watts_per_m2(1366.0) - 2.0).abs() < 1e-6);
        assert!((lumens_to_watts(6830.0) - 10.0).abs() < 1e-4);
    }
}
