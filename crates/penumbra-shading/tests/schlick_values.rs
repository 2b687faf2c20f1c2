//! Schlick's Fresnel approximation F = F0 + (1 − F0)(1 − cos θ)⁵ against
//! values computed by hand (not by the functions under test), at several
//! angles and from both sides of a dielectric.

use penumbra_shading::Rgb;
use penumbra_shading::bsdf::optics::{schlick, schlick_dielectric, schlick_scalar};

fn close(a: f32, b: f64, what: &str) {
    assert!((f64::from(a) - b).abs() < 1e-6, "{what}: {a} vs {b}");
}

#[test]
fn schlick_at_several_angles() {
    // F0 = 0.04 (glass in air).
    close(schlick_scalar(0.04, 1.0), 0.04, "normal incidence");
    // 60°: 0.04 + 0.96 · 0.5⁵ = 0.07.
    close(schlick_scalar(0.04, 0.5), 0.07, "60°");
    // cos θ = 0.8: 0.04 + 0.96 · 0.2⁵ = 0.0403072.
    close(schlick_scalar(0.04, 0.8), 0.040_307_2, "cos 0.8");
    // Grazing: 1.
    close(schlick_scalar(0.04, 0.0), 1.0, "grazing");
    // Per band, a gold-like F0 at 60°: F0 + (1 − F0)/32.
    let f = schlick(Rgb::new(1.0, 0.71, 0.29), 0.5);
    close(f.x, 1.0, "red");
    close(f.y, 0.71 + 0.29 / 32.0, "green");
    close(f.z, 0.29 + 0.71 / 32.0, "blue");
}

#[test]
fn schlick_for_a_dielectric_from_both_sides() {
    // Entering glass (η = 1.5, F0 = 0.04) at 60°.
    close(schlick_dielectric(0.5, 1.5), 0.07, "entering at 60°");
    // Leaving glass at cos θi = 0.9: the transmitted angle is used,
    // sin²θt = 2.25 · (1 − 0.81) = 0.4275, cos θt = 0.756637…,
    // F = 0.04 + 0.96 (1 − cos θt)⁵ = 0.0408195.
    close(
        schlick_dielectric(-0.9, 1.5),
        0.040_819_486,
        "leaving at cos 0.9",
    );
    // Past the critical angle (sin²θt = 2.25 · 0.75 > 1): total reflection.
    close(
        schlick_dielectric(-0.5, 1.5),
        1.0,
        "total internal reflection",
    );
    // An interface whose inside is the rarer medium (η = 1/1.5), light
    // from inside at cos 0.9: it enters the denser medium, so the incident
    // angle is used: 0.04 + 0.96 · 0.1⁵ = 0.0400096.
    close(
        schlick_dielectric(-0.9, 1.0 / 1.5),
        0.040_009_6,
        "inside the rarer medium",
    );
}
