//! Tables the WGSL material twins read: the Kulla–Conty specular albedo
//! tables of the metallic–roughness model, the same numbers the Rust model
//! interpolates ([`MetallicRoughness::albedo_tables`]).
//!
//! # What a pass that calls `material_eval` must bind
//!
//! The shading library calls `kulla_conty_entry(i)` and reads the sizes
//! `KC_MU`, `KC_R`; a *table source* appended to the module declares them.
//! There are two:
//!
//! - [`kulla_conty_binding_wgsl`] (what [`crate::shaders::with_library`]
//!   uses): the table is a storage buffer
//!
//!   ```text
//!   @group(0) @binding(8) var<storage, read> kulla_conty_table: array<vec4<f32>>;
//!   ```
//!
//!   The pass binds, at [`KULLA_CONTY_BINDING`] = 8 of group 0, a read-only
//!   storage buffer (`wgpu::BufferBindingType::Storage { read_only: true }`,
//!   visible to the stages that shade: FRAGMENT for the forward pass) whose
//!   contents are `bytemuck::cast_slice(&kulla_conty_table())`
//!   ([`KULLA_CONTY_BYTES`] bytes). The table is a constant of the build (it
//!   depends on no scene or setting): upload it once, when the pipeline is
//!   created, and keep it for every frame.
//! - [`kulla_conty_fallback_wgsl`]: no binding; every roughness row is
//!   replaced by the smooth row (computed in the shader, bit-equal to the
//!   table's). Exact only for metallic–roughness materials with delta lobes
//!   or without a diffuse base. The forward pass uses it until its renderer
//!   binds the buffer (see [`crate::shaders::FORWARD_BINDS_MATERIAL_TABLES`]);
//!   `SceneData` warns about the materials it approximates. (The whole table
//!   as a constant array in the shader would need no binding either, but
//!   lavapipe takes minutes to compile dynamic indexing into it.)
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

/// Table source without a binding, for a pass that does not bind the
/// table yet: every roughness row is replaced by the smooth row (A = 1,
/// B = (1 − μ)⁵ at the nodes, the same numbers as the Rust table's first
/// row, and that row's averages). Exact for metallic–roughness materials
/// with delta lobes (which read that row) or no diffuse base; otherwise the
/// diffuse base is weighted by 1 − F_d-like smooth-surface albedos instead
/// of the rough ones (too bright at high roughness).
pub fn kulla_conty_fallback_wgsl() -> String {
    let [_, _, a_avg, b_avg] = MetallicRoughness::albedo_tables();
    format!(
        "// Kulla–Conty table fallback (crates/penumbra-raster/src/material_tables.rs):\n\
         // the smooth row for every roughness.\n\
         {}\
         fn kulla_conty_entry(i: u32) -> vec4<f32> {{\n\
         \x20   let x = f32(i % KC_MU) / f32(KC_MU - 1u);\n\
         \x20   let mu = x * x;\n\
         \x20   return vec4<f32>(1.0, pow5(1.0 - mu), bitcast<f32>({:#010x}u), bitcast<f32>({:#010x}u));\n\
         }}\n",
        sizes_wgsl(),
        a_avg[0].to_bits(),
        b_avg[0].to_bits()
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
        // The smooth row the fallback reproduces.
        for (im, e) in t[..n_mu].iter().enumerate() {
            let x = im as f32 / (n_mu - 1) as f32;
            assert_eq!(e[..2], [1.0, (1.0 - x * x).powi(5)]);
        }
        let fallback = kulla_conty_fallback_wgsl();
        assert!(fallback.contains(&format!("{:#010x}u", b_avg[0].to_bits())));
        assert!(!fallback.contains("@binding"));
        assert!(kulla_conty_binding_wgsl().contains("@binding(8)"));
    }
}
