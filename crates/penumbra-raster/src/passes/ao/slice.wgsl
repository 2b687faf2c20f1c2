// The cosine-weighted visibility of one GTAO slice (Jimenez et al. 2016,
// "Practical Real-Time Strategies for Accurate Indirect Occlusion", eq. 10),
// twin of `gtao_slice_visibility` in gtao.rs. In the slice plane angles are
// measured from the view vector v; n is the angle of the projected normal,
// h0 ≤ 0 ≤ h1 the horizons on either side (already clamped to n ∓ π/2):
//   â = ¼(−cos(2h0 − n) + cos n + 2 h0 sin n) + ¼(−cos(2h1 − n) + cos n + 2 h1 sin n).
// The unoccluded slice of a normal facing the viewer (n = 0, h = ±π/2)
// gives 1; averaged over slice directions with the projected normal's
// length as weight, â gives kA.
fn gtao_slice_visibility(n: f32, h0: f32, h1: f32) -> f32 {
    let cn = cos(n);
    let sn = sin(n);
    let a0 = -cos(2.0 * h0 - n) + cn + 2.0 * h0 * sn;
    let a1 = -cos(2.0 * h1 - n) + cn + 2.0 * h1 * sn;
    return 0.25 * (a0 + a1);
}
