//! Shared by the GPU tests: the adapter (a failure, not a skip, without one
//! unless PENUMBRA_SKIP_GPU=1), the test kernels' structs and WGSL, paths.
#![allow(dead_code)]

pub mod ao_reference;

use bytemuck::{Pod, Zeroable};
use penumbra_raster::GpuContext;
use penumbra_raster::gpu::{GpuLight, GpuMaterial, HostLayout};
use std::mem::{offset_of, size_of};
use std::path::PathBuf;

/// The GPU, or `None` (with a printed note) when PENUMBRA_SKIP_GPU=1. Without
/// an adapter and without that variable the test fails.
pub fn gpu(test: &str) -> Option<GpuContext> {
    if std::env::var("PENUMBRA_SKIP_GPU").is_ok_and(|v| v == "1") {
        eprintln!("note: {test}: skipped because PENUMBRA_SKIP_GPU=1 (no GPU check ran)");
        return None;
    }
    match GpuContext::new() {
        Ok(ctx) => {
            eprintln!("{test}: adapter {}", ctx.summary);
            Some(ctx)
        }
        Err(e) => panic!("{test}: {e} (set PENUMBRA_SKIP_GPU=1 to skip GPU tests)"),
    }
}

/// Runs compute `entry` of `source` over `count` items: the input at its
/// binding, the output (`count` values of `T`) at the next binding, and the
/// `extra` buffers at theirs; returns the output.
pub fn dispatch<T: bytemuck::Pod>(
    ctx: &GpuContext,
    source: &str,
    entry: &str,
    input: (u32, &[u8]),
    count: usize,
    extra: &[(u32, &[u8])],
) -> Vec<T> {
    dispatch_specialised(ctx, &[], source, entry, input, count, extra)
}

/// [`dispatch`] with values for the kernel's pipeline-overridable constants.
pub fn dispatch_specialised<T: bytemuck::Pod>(
    ctx: &GpuContext,
    constants: &[(&str, f64)],
    source: &str,
    entry: &str,
    (input_binding, input): (u32, &[u8]),
    count: usize,
    extra: &[(u32, &[u8])],
) -> Vec<T> {
    use wgpu::util::DeviceExt;
    let device = &ctx.device;
    let pipeline =
        penumbra_raster::shaders::specialised_compute_pipeline(device, source, entry, constants);
    let out_size = (count * size_of::<T>()) as u64;
    let storage = |label: &str, contents: &[u8]| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage: wgpu::BufferUsages::STORAGE,
        })
    };
    let input_buf = storage("input", input);
    let extra_bufs: Vec<(u32, wgpu::Buffer)> = extra
        .iter()
        .map(|(b, bytes)| (*b, storage("extra", bytes)))
        .collect();
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("output"),
        size: out_size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let read = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read"),
        size: out_size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut entries = vec![
        wgpu::BindGroupEntry {
            binding: input_binding,
            resource: input_buf.as_entire_binding(),
        },
        wgpu::BindGroupEntry {
            binding: input_binding + 1,
            resource: output.as_entire_binding(),
        },
    ];
    entries.extend(extra_bufs.iter().map(|(b, buf)| wgpu::BindGroupEntry {
        binding: *b,
        resource: buf.as_entire_binding(),
    }));
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &entries,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(count.div_ceil(64) as u32, 1, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &read, 0, out_size);
    ctx.queue.submit([encoder.finish()]);
    let bytes = penumbra_raster::map_read(ctx, &read).expect("readback");
    bytemuck::cast_slice(&bytes).to_vec()
}

/// ../shared/reference/<scene> next to the workspace.
pub fn reference_dir(scene: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/reference")
        .join(scene)
}

/// One BRDF evaluation (WGSL `BrdfCase`): `material_eval(mat, wo, wi)`, of
/// `material_seen_from_back(mat)` when `back` ≠ 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct BrdfCase {
    pub mat: GpuMaterial,
    pub wo: [f32; 3],
    pub back: u32,
    pub wi: [f32; 3],
    pub _pad0: f32,
}

/// One light evaluation (WGSL `LightCase`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct LightCase {
    pub light: GpuLight,
    pub p: [f32; 3],
    pub _pad0: f32,
}

/// The library's `LightIncidence`, as read back.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct LightIncidence {
    pub wi: [f32; 3],
    pub valid: u32,
    pub value: [f32; 3],
    pub distance: f32,
}

/// Compute kernels appended to the shading library.
pub const KERNELS_WGSL: &str = r#"
struct BrdfCase {
    mat: GpuMaterial,
    wo: vec3<f32>,
    back: u32,
    wi: vec3<f32>,
    _pad0: f32,
}

struct LightCase {
    light: GpuLight,
    p: vec3<f32>,
    _pad0: f32,
}

@group(0) @binding(0) var<storage, read> brdf_cases: array<BrdfCase>;
@group(0) @binding(1) var<storage, read_write> brdf_out: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> light_cases: array<LightCase>;
@group(0) @binding(3) var<storage, read_write> light_out: array<LightIncidence>;

@compute @workgroup_size(64)
fn eval_brdf(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&brdf_cases) {
        return;
    }
    let c = brdf_cases[i];
    var m = c.mat;
    if c.back != 0u {
        m = material_seen_from_back(m);
    }
    brdf_out[i] = vec4<f32>(material_eval(m, c.wo, c.wi), 0.0);
}

@compute @workgroup_size(64)
fn eval_light(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&light_cases) {
        return;
    }
    let c = light_cases[i];
    light_out[i] = light_li(c.light, c.p);
}

@group(0) @binding(4) var<storage, read> env_cases: array<GpuMaterial>;
@group(0) @binding(5) var<storage, read_write> env_out: array<GpuEnvMaterial>;

@compute @workgroup_size(64)
fn eval_mr_environment(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&env_cases) {
        return;
    }
    env_out[i] = metallic_roughness_environment(env_cases[i]);
}
"#;

/// Host layouts of the test structs.
pub fn test_structs() -> Vec<HostLayout> {
    vec![
        HostLayout {
            wgsl_name: "BrdfCase",
            size: size_of::<BrdfCase>(),
            fields: vec![
                ("mat", offset_of!(BrdfCase, mat)),
                ("wo", offset_of!(BrdfCase, wo)),
                ("back", offset_of!(BrdfCase, back)),
                ("wi", offset_of!(BrdfCase, wi)),
                ("_pad0", offset_of!(BrdfCase, _pad0)),
            ],
        },
        HostLayout {
            wgsl_name: "LightCase",
            size: size_of::<LightCase>(),
            fields: vec![
                ("light", offset_of!(LightCase, light)),
                ("p", offset_of!(LightCase, p)),
                ("_pad0", offset_of!(LightCase, _pad0)),
            ],
        },
        HostLayout {
            wgsl_name: "LightIncidence",
            size: size_of::<LightIncidence>(),
            fields: vec![
                ("wi", offset_of!(LightIncidence, wi)),
                ("valid", offset_of!(LightIncidence, valid)),
                ("value", offset_of!(LightIncidence, value)),
                ("distance", offset_of!(LightIncidence, distance)),
            ],
        },
    ]
}

/// Within relative 1e-4 or absolute 1e-6.
pub fn close(gpu: f32, cpu: f32) -> bool {
    if gpu == cpu {
        return true;
    }
    let d = (gpu - cpu).abs();
    d <= 1e-6 || d <= 1e-4 * cpu.abs()
}
