// Forward pass: one draw per instance, per-pixel sum over every abstract
// light of f · E⊥ · cos θ plus the material's emission (the CPU `local`
// integrator's model), each light optionally weighted by its shadow-map
// visibility (the CPU `direct` integrator's hard shadows, approximated).
// Also the depth-only vertex stage of the shadow passes. Appended to
// shading.wgsl.

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

// How each light is shadowed (mirrors gpu.rs `GpuShadow`), indexed like
// `lights`; layer_count = 0: not shadowed.
struct GpuShadow {
    first_layer: u32,
    // 1: one view (directional, spot); 6: cube faces +x, -x, +y, -y, +z, -z.
    layer_count: u32,
    // PCF kernel edge N: N x N taps one texel apart.
    pcf: u32,
    perspective: u32,
    // World size of a texel (orthographic) or per unit distance (perspective).
    texel: f32,
    // Normal offset of the lookup point, in texels.
    normal_offset: f32,
    map_size: f32,
    _pad0: f32,
}

// One depth-only view of a light: world to clip with reversed depth.
struct GpuShadowView {
    view_proj: mat4x4<f32>,
    axis: vec4<f32>,
}

@group(0) @binding(4) var<storage, read> shadows: array<GpuShadow>;
@group(0) @binding(5) var<storage, read> shadow_views: array<GpuShadowView>;
@group(0) @binding(6) var shadow_maps: texture_depth_2d_array;
@group(0) @binding(7) var shadow_sampler: sampler_comparison;

// Shadow passes: instance_index = view * instance count + instance, so that
// one draw call per (view, instance) needs no per-view uniform.
@vertex
fn vs_shadow(
    @location(0) position: vec3<f32>,
    @builtin(instance_index) index: u32,
) -> @builtin(position) vec4<f32> {
    let n = arrayLength(&instances);
    let inst = instances[index % n];
    let world = inst.model * vec4<f32>(position, 1.0);
    return shadow_views[index / n].view_proj * vec4<f32>(world.xyz, 1.0);
}

// Fraction of light `li` reaching p (1 = lit): the lookup point is moved
// along the geometric normal ng by normal_offset texels (the texel's world
// size at p), projected into the light's view (the cube face of the major
// axis for point lights) and compared with the stored depth (reversed: lit
// where the point's depth >= the occluder's), averaged over N x N taps.
fn shadow_visibility(li: u32, p: vec3<f32>, ng: vec3<f32>) -> f32 {
    let sh = shadows[li];
    if sh.layer_count == 0u {
        return 1.0;
    }
    let light_pos = lights[li].position.xyz;
    var layer = sh.first_layer;
    if sh.layer_count == 6u {
        let d = p - light_pos;
        let a = abs(d);
        if a.x >= a.y && a.x >= a.z {
            layer += select(1u, 0u, d.x >= 0.0);
        } else if a.y >= a.z {
            layer += select(3u, 2u, d.y >= 0.0);
        } else {
            layer += select(5u, 4u, d.z >= 0.0);
        }
    }
    let view = shadow_views[layer];
    var texel = sh.texel;
    if sh.perspective != 0u {
        texel = texel * max(dot(p - light_pos, view.axis.xyz), 0.0);
    }
    let q = p + ng * (sh.normal_offset * texel);
    let clip = view.view_proj * vec4<f32>(q, 1.0);
    if clip.w <= 0.0 {
        return 1.0;
    }
    let ndc = clip.xyz / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    // Outside the light's view (beyond a spot's cone, outside the fitted
    // bounds): nothing there casts a shadow.
    if any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || ndc.z > 1.0 {
        return 1.0;
    }
    let n = max(sh.pcf, 1u);
    let h = f32(n - 1u) * 0.5;
    let step = 1.0 / sh.map_size;
    var sum = 0.0;
    for (var j = 0u; j < n; j++) {
        for (var i = 0u; i < n; i++) {
            let o = (vec2<f32>(f32(i), f32(j)) - h) * step;
            sum += textureSampleCompareLevel(shadow_maps, shadow_sampler, uv + o, i32(layer), ndc.z);
        }
    }
    return sum / f32(n * n);
}

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

// What the lights need of a shaded fragment.
struct Surface {
    p: vec3<f32>,
    // Geometric normal on the viewer's side.
    ng: vec3<f32>,
    frame: Frame,
    wo_local: vec3<f32>,
    material: u32,
    // Emission towards the viewer.
    emission: vec3<f32>,
    // 0: the back of a one-sided surface (emission only, no light).
    lit: u32,
}

// The fragment as a surface. ng_raw = cross(dpdx(p), dpdy(p)), taken by the
// entry point (derivatives need uniform control flow).
fn surface_of(in: VsOut, facing: bool, ng_raw: vec3<f32>) -> Surface {
    let p = in.world;
    let inst = instances[in.instance];
    let mat = materials[inst.material];
    var s: Surface;
    s.p = p;
    s.material = inst.material;

    var wo: vec3<f32>;
    if camera.back.w > 0.5 {
        wo = camera.back.xyz;
    } else {
        wo = normalize(camera.eye.xyz - p);
    }
    // Front side as the CPU defines it: the object-space winding, kept
    // through mirroring transforms.
    let front = facing != (inst.flip_winding != 0u);
    s.emission = vec3<f32>(0.0);
    if front || mat.double_sided != 0u {
        s.emission = mat.emission;
    }
    s.lit = select(0u, 1u, front || mat.double_sided != 0u);

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
    s.ng = ng;
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
    s.frame = frame_from_normal(ns);
    var wo_local = to_local(s.frame, wo);
    if wo_local.z <= 0.0 {
        wo_local.z = 1e-4;
        wo_local = normalize(wo_local);
    }
    s.wo_local = wo_local;
    return s;
}

// Radiance towards the viewer from light i: f · E⊥ · |cos θ| · shadow-map
// visibility, 0 where the light is below the geometric surface or the
// shading and geometric normals disagree about its side.
fn light_contribution(s: Surface, i: u32) -> vec3<f32> {
    let l = light_li(lights[i], s.p);
    if l.valid == 0u {
        return vec3<f32>(0.0);
    }
    let wl = to_local(s.frame, l.wi);
    let g = dot(l.wi, s.ng);
    if g != 0.0 && wl.z != 0.0 && (g > 0.0) == (wl.z > 0.0) {
        let v = shadow_visibility(i, s.p, s.ng);
        return material_eval(materials[s.material], s.wo_local, wl) * l.value * (abs(wl.z) * v);
    }
    return vec3<f32>(0.0);
}

@fragment
fn fs_main(in: VsOut, @builtin(front_facing) facing: bool) -> @location(0) vec4<f32> {
    let s = surface_of(in, facing, cross(dpdx(in.world), dpdy(in.world)));
    var radiance = s.emission;
    if s.lit == 0u {
        return vec4<f32>(radiance, 1.0);
    }
    for (var i = 0u; i < camera.light_count; i++) {
        radiance += light_contribution(s, i);
    }
    return vec4<f32>(radiance, 1.0);
}
