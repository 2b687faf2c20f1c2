//! Tables the WGSL material twins read: the Kulla–Conty specular albedo
//! tables of the metallic–roughness model, the same numbers the Rust model
//! interpolates ([`MetallicRoughness::albedo_tables`]).
//!
//! # What a pass that calls `material_eval` must bind
//!
//! The shading library calls `kulla_conty_entry(i)` and reads the sizes
//! `KC_MU`, `KC_R`; [`kulla_conty_binding_wgsl`], appended to every module
//! after the library ([`crate::shaders::library`]), declares them with the
//! table as a storage buffer:
//!
//! ```text
//! @group(0) @binding(8) var<storage, read> kulla_conty_table: array<vec4<f32>>;
//! ```
//!
//! A pass that evaluates materials binds, at [`KULLA_CONTY_BINDING`] = 8 of
//! group 0, a read-only storage buffer with the contents
//! `bytemuck::cast_slice(&kulla_conty_table())` ([`KULLA_CONTY_BYTES`]
//! bytes). The table is a constant of the build: the forward renderer
//! uploads it once, when its pipelines are created. (The whole table as a
//! constant array in the shader would need no binding, but lavapipe takes
//! minutes to compile dynamic indexing into it.)
//!
//! Entry `ir · KC_MU + im` is `(A, B, A_avg, B_avg)` at x = √μ =
//! im / (KC_MU − 1), y = √roughness = ir / (KC_R − 1): A and B of node
//! (im, ir), the cosine averages of row ir in z and w.

use penumbra_shading::bsdf::MetallicRoughness;

/// Group-0 binding of the Kulla–Conty table in passes that bind it.
pub const KULLA_CONTY_BINDING: u32 = 8;

/// Nodes per axis: (μ, roughness).
pub const KULLA_CONTY_SIZE: [usize; 2] = MetallicRoughness::ALBEDO_TABLE_SIZE;

/// Size of the buffer [`kulla_conty_table`] fills.
pub const KULLA_CONTY_BYTES: usize = KULLA_CONTY_SIZE[0] * KULLA_CONTY_SIZE[1] * 16;

/// The table as the shaders read it: `(A, B, A_avg, B_avg)` per node, rows
/// of constant roughness (see the module doc).
pub fn kulla_conty_table() -> Vec<[f32; 4]> {
    let [n_mu, n_r] = KULLA_CONTY_SIZE;
    let [a, b, a_avg, b_avg] = MetallicRoughness::albedo_tables();
    assert_eq!((a.len(), b.len()), (n_mu * n_r, n_mu * n_r));
    assert_eq!((a_avg.len(), b_avg.len()), (n_r, n_r));
    (0..n_r)
        .flat_map(|ir| (0..n_mu).map(move |im| (ir, im)))
        .map(|(ir, im)| {
            let i = ir * n_mu + im;
            [a[i], b[i], a_avg[ir], b_avg[ir]]
        })
        .collect()
}

fn sizes_wgsl() -> String {
    let [n_mu, n_r] = KULLA_CONTY_SIZE;
    format!("const KC_MU: u32 = {n_mu}u;\nconst KC_R: u32 = {n_r}u;\n")
}

/// Table source: the storage buffer at `@group(0) @binding(8)`.
pub fn kulla_conty_binding_wgsl() -> String {
    format!(
        "// Kulla–Conty table (crates/penumbra-raster/src/material_tables.rs).\n\
         {}\
         @group(0) @binding({KULLA_CONTY_BINDING}) var<storage, read> kulla_conty_table: array<vec4<f32>>;\n\
         fn kulla_conty_entry(i: u32) -> vec4<f32> {{\n    return kulla_conty_table[i];\n}}\n",
        sizes_wgsl()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_holds_the_rust_numbers() {
        let t = kulla_conty_table();
        let [n_mu, n_r] = KULLA_CONTY_SIZE;
        assert_eq!(t.len() * 16, KULLA_CONTY_BYTES);
        let [a, b, a_avg, b_avg] = MetallicRoughness::albedo_tables();
        // The smooth row: A = 1, B = (1 − μ)⁵; the roughest row loses energy.
        assert_eq!(t[n_mu / 2][0], 1.0);
        assert_eq!(t[(n_r - 1) * n_mu + n_mu - 1][0], a[n_r * n_mu - 1]);
        assert!(a[n_r * n_mu - 1] < 0.6);
        let (ir, im) = (17, 5);
        assert_eq!(
            t[ir * n_mu + im],
            [a[ir * n_mu + im], b[ir * n_mu + im], a_avg[ir], b_avg[ir]]
        );
        // The smooth row.
        for (im, e) in t[..n_mu].iter().enumerate() {
            let x = im as f32 / (n_mu - 1) as f32;
            assert_eq!(e[..2], [1.0, (1.0 - x * x).powi(5)]);
        }
        assert!(kulla_conty_binding_wgsl().contains("@binding(8)"));
    }
}
