// Forward pass: one draw per instance, per-pixel sum over every abstract
// light of f · E⊥ · cos θ plus the material's emission, without shadows (the
// CPU `local` integrator's model). Appended to shading.wgsl.

struct GpuCamera {
    view_proj: mat4x4<f32>,
    // World position of the pinhole (perspective).
    eye: vec4<f32>,
    // World +z axis of the camera (towards the viewer); w = 1 orthographic.
    back: vec4<f32>,
    light_count: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

struct GpuInstance {
    model: mat4x4<f32>,
    // Inverse transpose of the linear part (columns 0..2).
    normal: mat4x4<f32>,
    material: u32,
    has_normals: u32,
    flip_winding: u32,
    _pad0: u32,
}

@group(0) @binding(0) var<uniform> camera: GpuCamera;
@group(0) @binding(1) var<storage, read> instances: array<GpuInstance>;
@group(0) @binding(2) var<storage, read> materials: array<GpuMaterial>;
@group(0) @binding(3) var<storage, read> lights: array<GpuLight>;

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) instance: u32,
}

@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @builtin(instance_index) instance: u32,
) -> VsOut {
    let inst = instances[instance];
    let world = inst.model * vec4<f32>(position, 1.0);
    var out: VsOut;
    out.clip = camera.view_proj * vec4<f32>(world.xyz, 1.0);
    out.world = world.xyz;
    out.normal = (inst.normal * vec4<f32>(normal, 0.0)).xyz;
    out.instance = instance;
    return out;
}

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) facing: bool) -> @location(0) vec4<f32> {
    let p = in.world;
    // Geometric normal of the triangle (derivatives in uniform control flow).
    let ng_raw = cross(dpdx(p), dpdy(p));
    let inst = instances[in.instance];
    let mat = materials[inst.material];

    var wo: vec3<f32>;
    if camera.back.w > 0.5 {
        wo = camera.back.xyz;
    } else {
        wo = normalize(camera.eye.xyz - p);
    }
    // Front side as the CPU defines it: the object-space winding, kept
    // through mirroring transforms.
    let front = facing != (inst.flip_winding != 0u);

    var radiance = vec3<f32>(0.0);
    if front || mat.double_sided != 0u {
        radiance = mat.emission;
    }
    if !front && mat.double_sided == 0u {
        return vec4<f32>(radiance, 1.0);
    }

    // Normals on the visible side, the shading normal on the side of ng.
    var ng = ng_raw;
    let ng_len2 = dot(ng, ng);
    if ng_len2 > 0.0 {
        ng = ng * inverseSqrt(ng_len2);
    } else {
        ng = wo;
    }
    if dot(ng, wo) < 0.0 {
        ng = -ng;
    }
    var ns = ng;
    if inst.has_normals != 0u {
        let n2 = dot(in.normal, in.normal);
        if n2 > 0.0 {
            ns = in.normal * inverseSqrt(n2);
            if dot(ns, ng) < 0.0 {
                ns = -ns;
            }
        }
    }
    let frame = frame_from_normal(ns);
    var wo_local = to_local(frame, wo);
    if wo_local.z <= 0.0 {
        wo_local.z = 1e-4;
        wo_local = normalize(wo_local);
    }
    for (var i = 0u; i < camera.light_count; i++) {
        let s = light_li(lights[i], p);
        if s.valid == 0u {
            continue;
        }
        let wl = to_local(frame, s.wi);
        let g = dot(s.wi, ng);
        if g != 0.0 && wl.z != 0.0 && (g > 0.0) == (wl.z > 0.0) {
            radiance += material_eval(mat, wo_local, wl) * s.value * abs(wl.z);
        }
    }
    return vec4<f32>(radiance, 1.0);
}
