//! The WGSL sources: the shading library (BRDF and light twins of the Rust
//! models), the structs every pass shares with the host, and the passes
//! built on them. Each pass module is the library (with the Kulla–Conty
//! table source, [`crate::material_tables`]) followed by the pass.

use crate::material_tables::kulla_conty_binding_wgsl;

/// BRDFs and lights shared by every pass and by the tests (shading.wgsl
/// followed by the GGX models of microfacet.wgsl). Needs a table source
/// after it: see [`library`].
pub const SHADING_WGSL: &str = concat!(
    include_str!("shaders/shading.wgsl"),
    "\n",
    include_str!("shaders/microfacet.wgsl")
);

/// The shading library with its Kulla–Conty table source: the storage
/// buffer at `@group(0) @binding(8)`, which a pipeline binds only if its
/// entry points evaluate a metallic–roughness material.
/// It ends with the environment light's structs and functions without
/// bindings ([`ENVIRONMENT_COMMON_WGSL`]).
pub fn library() -> String {
    format!(
        "{SHADING_WGSL}\n{}\n{ENVIRONMENT_COMMON_WGSL}",
        kulla_conty_binding_wgsl()
    )
}

/// Host-shared structs of the raster passes (camera, instances, shadows,
/// culling, per-pass parameters).
pub const SCENE_WGSL: &str = include_str!("shaders/scene.wgsl");

/// The geometry passes (depth prepass, forward, base, one-light, shadow
/// map), without the library.
pub const FORWARD_WGSL: &str = include_str!("shaders/forward.wgsl");

/// Textures and vertex attributes of the geometry passes (bindings 25–29).
pub const TEXTURES_WGSL: &str = include_str!("shaders/textures.wgsl");

/// Baked maps looked up by the geometry passes (group 2), and the pass that
/// writes the looked-up values as AOVs.
pub const LIGHTMAP_WGSL: &str = include_str!("passes/lightmap/lightmap.wgsl");

/// Environment light: the functions without bindings (SH9 irradiance,
/// lat-long lookups, split sum, GGX samples, specular occlusion).
pub const ENVIRONMENT_COMMON_WGSL: &str = crate::passes::environment::COMMON_WGSL;

/// Environment light of the forward passes: bindings 20–23 and
/// `environment_light(s, k_a)`.
pub const ENVIRONMENT_WGSL: &str = crate::passes::environment::ENVIRONMENT_WGSL;

/// Tiled light culling (compute).
pub const LIGHT_CULLING_WGSL: &str = include_str!("shaders/light_culling.wgsl");

/// Stencil shadow volumes: bindings and geometry shared by both passes.
pub const SHADOW_VOLUME_WGSL: &str = include_str!("shaders/shadow_volume.wgsl");
/// Shadow volumes: the facing compute pass.
pub const SHADOW_VOLUME_FACING_WGSL: &str = include_str!("shaders/shadow_volume_facing.wgsl");
/// Shadow volumes: the cap and edge extrusion draws.
pub const SHADOW_VOLUME_DRAW_WGSL: &str = include_str!("shaders/shadow_volume_draw.wgsl");

/// Planar projected shadows (receiver marking, projected occluders).
pub const PLANAR_SHADOW_WGSL: &str = include_str!("shaders/planar_shadow.wgsl");

/// The complete forward shader module: library + structs + pass + textures
/// + baked maps + environment light.
pub fn forward_source() -> String {
    format!(
        "{}\n{SCENE_WGSL}\n{FORWARD_WGSL}\n{TEXTURES_WGSL}\n{LIGHTMAP_WGSL}\n{ENVIRONMENT_WGSL}",
        library()
    )
}

/// The light-culling module for a single- or multisampled depth buffer.
pub fn light_culling_source(multisampled: bool) -> String {
    let (texture, load) = if multisampled {
        (
            "texture_depth_multisampled_2d",
            "textureLoad(depth, vec2<i32>(px), i32(s))",
        )
    } else {
        ("texture_depth_2d", "textureLoad(depth, vec2<i32>(px), 0)")
    };
    let pass = LIGHT_CULLING_WGSL
        .replace("DEPTH_TEXTURE", texture)
        .replace("LOAD_DEPTH", load);
    format!("{}\n{SCENE_WGSL}\n{pass}", library())
}

/// The shadow-volume module: the facing compute pass (`facing_pass`) or
/// the stencil draws.
pub fn shadow_volume_source(facing_pass: bool) -> String {
    let pass = if facing_pass {
        SHADOW_VOLUME_FACING_WGSL
    } else {
        SHADOW_VOLUME_DRAW_WGSL
    };
    format!("{}\n{SCENE_WGSL}\n{SHADOW_VOLUME_WGSL}\n{pass}", library())
}

/// The planar-shadow module.
pub fn planar_shadow_source() -> String {
    format!("{}\n{SCENE_WGSL}\n{PLANAR_SHADOW_WGSL}", library())
}

/// Screen-space AO: what every AO pass shares (`GpuAoParams`, position
/// reconstruction).
pub const AO_COMMON_WGSL: &str = include_str!("passes/ao/common.wgsl");
/// The AO inputs as the hemisphere, GTAO and denoise passes read them.
pub const AO_SURFACE_WGSL: &str = include_str!("passes/ao/surface.wgsl");
/// GTAO's slice integral (also used by the tests' twin kernel).
pub const GTAO_SLICE_WGSL: &str = include_str!("passes/ao/slice.wgsl");

/// The AO inputs and depth-MIP module for a single- or multisampled
/// prepass normal target.
pub fn ao_inputs_source(multisampled: bool) -> String {
    let texture = if multisampled {
        "texture_multisampled_2d<f32>"
    } else {
        "texture_2d<f32>"
    };
    let pass = include_str!("passes/ao/inputs.wgsl").replace("PREPASS_TEXTURE", texture);
    format!("{AO_COMMON_WGSL}\n{pass}")
}

/// The hemisphere SSAO module.
pub fn hemisphere_source() -> String {
    format!(
        "{AO_COMMON_WGSL}\n{AO_SURFACE_WGSL}\n{}",
        include_str!("passes/ao/hemisphere.wgsl")
    )
}

/// The GTAO module.
pub fn gtao_source() -> String {
    format!(
        "{AO_COMMON_WGSL}\n{AO_SURFACE_WGSL}\n{GTAO_SLICE_WGSL}\n{}",
        include_str!("passes/ao/gtao.wgsl")
    )
}

/// The AO denoise module.
pub fn ao_denoise_source() -> String {
    format!(
        "{AO_COMMON_WGSL}\n{AO_SURFACE_WGSL}\n{}",
        include_str!("passes/ao/denoise.wgsl")
    )
}

/// Every pass module the renderer builds, by name (for the layout tests).
pub fn all_modules() -> Vec<(&'static str, String)> {
    vec![
        ("forward", forward_source()),
        ("light culling (1 sample)", light_culling_source(false)),
        ("light culling (multisampled)", light_culling_source(true)),
        ("shadow volume (facing)", shadow_volume_source(true)),
        ("shadow volume (draw)", shadow_volume_source(false)),
        ("planar shadow", planar_shadow_source()),
        ("ao inputs (1 sample)", ao_inputs_source(false)),
        ("ao inputs (multisampled)", ao_inputs_source(true)),
        ("ssao hemisphere", hemisphere_source()),
        ("gtao", gtao_source()),
        ("ao denoise", ao_denoise_source()),
        (
            "environment prefilter",
            crate::passes::environment::prefilter_source(),
        ),
    ]
}

/// A shader module made of the library followed by `entry_points`
/// (compute kernels of the tests).
pub fn with_library(entry_points: &str) -> String {
    format!("{}\n{entry_points}", library())
}

/// A compute pipeline of `entry` in the WGSL `source`, with the layout
/// derived from the shader (`layout: None`): for passes and test kernels
/// whose bind groups come from `get_bind_group_layout`.
pub fn compute_pipeline(device: &wgpu::Device, source: &str, entry: &str) -> wgpu::ComputePipeline {
    specialised_compute_pipeline(device, source, entry, &[])
}

/// [`compute_pipeline`] with values for the source's pipeline-overridable
/// constants.
pub fn specialised_compute_pipeline(
    device: &wgpu::Device,
    source: &str,
    entry: &str,
    constants: &[(&str, f64)],
) -> wgpu::ComputePipeline {
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(entry),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: None,
        module: &module,
        entry_point: Some(entry),
        compilation_options: wgpu::PipelineCompilationOptions {
            constants,
            ..Default::default()
        },
        cache: None,
    })
}
