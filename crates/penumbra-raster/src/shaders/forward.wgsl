// The geometry passes over the scene's instances, one draw per instance:
//  - vs_depth: the depth prepass (reversed depth, no colour);
//  - vs_main + fs_forward: per-pixel sum over the lights of the pixel's
//    tile (tiled light culling) of f · E⊥ · cos θ plus emission and the
//    environment light, each light optionally weighted by its shadow-map
//    visibility;
//  - vs_main + fs_base: emission and environment light only (the base of the
//    per-light passes);
//  - vs_main + fs_light: one light (params.light), added where the stencil
//    says the light is not shadowed (shadow volumes, planar shadows);
//  - vs_shadow: the depth-only shadow-map passes.
// Baked maps (ambient occlusion, irradiance) come from lightmap.wgsl.
// Appended to shading.wgsl + scene.wgsl, followed by lightmap.wgsl.

@group(0) @binding(0) var<uniform> camera: GpuCamera;
@group(0) @binding(1) var<storage, read> instances: array<GpuInstance>;
@group(0) @binding(2) var<storage, read> materials: array<GpuMaterial>;
@group(0) @binding(3) var<storage, read> lights: array<GpuLight>;
@group(0) @binding(4) var<storage, read> shadows: array<GpuShadow>;
@group(0) @binding(5) var<storage, read> shadow_views: array<GpuShadowView>;
@group(0) @binding(6) var shadow_maps: texture_depth_2d_array;
@group(0) @binding(7) var shadow_sampler: sampler_comparison;
@group(0) @binding(10) var<storage, read> tile_lights: array<u32>;
@group(0) @binding(11) var<uniform> culling: GpuCulling;
// The environment light (bindings 20–23) comes from
// passes/environment/environment.wgsl, appended after this file.
// Screen-space kA per pixel (passes/ao), with SCREEN_AO.
@group(0) @binding(24) var screen_ao: texture_2d<f32>;
@group(1) @binding(0) var<uniform> params: GpuPassParams;

// Shadow passes: instance_index = view * instance count + instance, so that
// one draw call per (view, instance) needs no per-view uniform.
@vertex
fn vs_shadow(
    @location(0) position: vec3<f32>,
    @builtin(instance_index) index: u32,
) -> @builtin(position) vec4<f32> {
    let n = arrayLength(&instances);
    let inst = instances[index % n];
    let world = world_point(inst.model, position);
    return shadow_views[index / n].view_proj * vec4<f32>(world, 1.0);
}

// Shadow passes of scenes with alpha masks: vs_shadow's position, and the
// texture coordinates for fs_shadow_masked to discard masked-out fragments
// (the same outputs as the discarding depth prepass).
@vertex
fn vs_shadow_masked(
    @location(0) position: vec3<f32>,
    @builtin(instance_index) index: u32,
    @builtin(vertex_index) corner: u32,
) -> DiscardingDepthOut {
    let n = arrayLength(&instances);
    let inst = instances[index % n];
    let world = world_point(inst.model, position);
    let clip = shadow_views[index / n].view_proj * vec4<f32>(world, 1.0);
    return DiscardingDepthOut(clip, index % n, vertex_uv(inst, corner));
}

@fragment
fn fs_shadow_masked(in: DiscardingDepthOut) {
    if masked_out(instances[in.instance].material, tex_coords(in.uv)) {
        discard;
    }
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
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) instance: u32,
    // Atlas coordinates of the AO and irradiance bakes (lightmap.wgsl).
    @location(3) ao_uv: vec2<f32>,
    @location(4) irradiance_uv: vec2<f32>,
    // Texture coordinates (UV sets 0 and 1) and vertex colour (textures.wgsl).
    @location(5) uv: vec4<f32>,
    @location(6) color: vec3<f32>,
    // World tangent of UV set 0 (w = handedness; 0 without tangents).
    @location(7) tangent: vec4<f32>,
}

// Whether a fragment of `instance` on the side `facing` is a culled back
// face (glTF doubleSided: false): the front side as the CPU defines it,
// the object-space winding kept through mirroring transforms.
fn culled_back_face(instance: u32, facing: bool) -> bool {
    let inst = instances[instance];
    let front = facing != (inst.flip_winding != 0u);
    return !front && materials[inst.material].cull_back_faces != 0u;
}

// Whether a fragment is discarded: a culled back face, or cut away by its
// material's alpha mask (glTF MASK: α < alphaCutoff).
fn discarded(instance: u32, facing: bool, tc: TexCoords) -> bool {
    return culled_back_face(instance, facing) || masked_out(instances[instance].material, tc);
}

// Depth prepass of scenes with culled back faces or alpha masks (vs_depth's
// clip position, and a fragment stage that discards what `discarded` says).
struct DiscardingDepthOut {
    @builtin(position) @invariant clip: vec4<f32>,
    @location(0) @interpolate(flat) instance: u32,
    @location(1) uv: vec4<f32>,
}

@vertex
fn vs_depth_discarding(
    @location(0) position: vec3<f32>,
    @builtin(instance_index) instance: u32,
    @builtin(vertex_index) corner: u32,
) -> DiscardingDepthOut {
    let inst = instances[instance];
    let world = world_point(inst.model, position);
    return DiscardingDepthOut(camera.view_proj * vec4<f32>(world, 1.0), instance, vertex_uv(inst, corner));
}

@fragment
fn fs_depth_discarding(in: DiscardingDepthOut, @builtin(front_facing) facing: bool) {
    if discarded(in.instance, facing, tex_coords(in.uv)) {
        discard;
    }
}

// Depth prepass: the same clip position as vs_main (both @invariant), so
// that the shading passes can test depth with GreaterEqual.
@vertex
fn vs_depth(
    @location(0) position: vec3<f32>,
    @builtin(instance_index) instance: u32,
) -> @invariant @builtin(position) vec4<f32> {
    let world = world_point(instances[instance].model, position);
    return camera.view_proj * vec4<f32>(world, 1.0);
}

// With bakes the meshes are drawn unwelded (vertex 3t + k is corner k of
// triangle t), so vertex_index is the corner the bakes' coordinates are
// stored for.
@vertex
fn vs_main(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @builtin(instance_index) instance: u32,
    @builtin(vertex_index) corner: u32,
) -> VsOut {
    let inst = instances[instance];
    let world = world_point(inst.model, position);
    var out: VsOut;
    out.clip = camera.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    out.normal = (inst.normal * vec4<f32>(normal, 0.0)).xyz;
    out.instance = instance;
    out.ao_uv = ao_corner_uv(instance, corner);
    out.irradiance_uv = irradiance_corner_uv(instance, corner);
    out.uv = vertex_uv(inst, corner);
    out.color = vertex_color(inst, corner);
    out.tangent = vertex_tangent(inst, corner);
    return out;
}

// What the lights need of a shaded fragment.
struct Surface {
    p: vec3<f32>,
    // Geometric normal on the viewer's side.
    ng: vec3<f32>,
    frame: Frame,
    wo_local: vec3<f32>,
    // The material as seen from the viewer's side (textures applied, and
    // Bsdf::seen_from_back on the back of a surface).
    mat: GpuMaterial,
    // What the environment light needs of the (textured) material.
    env: GpuEnvMaterial,
    material: u32,
    // Emission towards the viewer.
    emission: vec3<f32>,
    // A back face the camera does not see (glTF doubleSided: false): the
    // entry points discard it.
    culled: bool,
    // The material's baked occlusion (glTF occlusionTexture) on the
    // environment term.
    occlusion: f32,
    // 0: the back of a one-sided surface (emission only, no light).
    lit: u32,
    // Change across one pixel in x and in y of the mirror direction of the
    // view (world space) and of the direction seen straight through, −ωo:
    // the footprints of sharp environment reflections (surface_at).
    mirror_dx: vec3<f32>,
    mirror_dy: vec3<f32>,
    through_dx: vec3<f32>,
    through_dy: vec3<f32>,
}

// Unit vector from world point p towards the viewer.
fn view_direction(p: vec3<f32>) -> vec3<f32> {
    if camera.back.w > 0.5 {
        return camera.back.xyz;
    }
    return normalize(camera.eye.xyz - p);
}

struct VisibleNormals {
    // Geometric normal on the viewer's (wo's) side.
    ng: vec3<f32>,
    // Shading normal (the interpolated vertex normal, else ng) on ng's side.
    ns: vec3<f32>,
}

// The fragment's normals on the visible side. ng_raw = cross(dpdx(p),
// dpdy(p)), taken by the entry point.
fn visible_normals(in: VsOut, wo: vec3<f32>, ng_raw: vec3<f32>) -> VisibleNormals {
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
    if instances[in.instance].has_normals != 0u {
        let n2 = dot(in.normal, in.normal);
        if n2 > 0.0 {
            ns = in.normal * inverseSqrt(n2);
            if dot(ns, ng) < 0.0 {
                ns = -ns;
            }
        }
    }
    return VisibleNormals(ng, ns);
}

// The fragment as a surface. ng_raw = cross(dpdx(p), dpdy(p)) and tc (the
// texture coordinates and their derivatives), taken by the entry point
// (derivatives need uniform control flow): see surface_at.
fn surface_of(in: VsOut, facing: bool, ng_raw: vec3<f32>, tc: TexCoords) -> Surface {
    let p = in.world;
    let inst = instances[in.instance];
    let textured = textured_material(inst.material, tc, in.color);
    let mat = textured.mat;
    var s: Surface;
    s.env = textured.env;
    s.culled = discarded(in.instance, facing, tc);
    s.occlusion = baked_occlusion(inst.material, tc);
    s.p = p;
    s.material = inst.material;

    let wo = view_direction(p);
    // Front side as the CPU defines it: the object-space winding, kept
    // through mirroring transforms.
    let front = facing != (inst.flip_winding != 0u);
    s.emission = vec3<f32>(0.0);
    if front || mat.double_sided != 0u {
        s.emission = mat.emission;
    }
    // The back of a surface is lit if the material is two-sided or
    // transmissive, and then seen from inside (η → 1/η), as on the CPU.
    s.lit = select(0u, 1u, front || mat.double_sided != 0u || material_transmissive(mat));
    s.mat = mat;
    if !front {
        s.mat = material_seen_from_back(mat);
    }

    let n = visible_normals(in, wo, ng_raw);
    s.ng = n.ng;
    // Normal maps act on the front side's normals (the CPU's order), then
    // the result turns to the viewer's side with them.
    let side = select(-1.0, 1.0, front);
    let ns = side * normal_mapped(inst.material, tc, in.tangent, side * n.ns, side * n.ng);
    s.frame = frame_from_normal(ns);
    var wo_local = to_local(s.frame, wo);
    if wo_local.z <= 0.0 {
        wo_local.z = 1e-4;
        wo_local = normalize(wo_local);
    }
    s.wo_local = wo_local;
    return s;
}

// The fragment as a surface; call at the top of an entry point (the
// derivatives it takes need uniform control flow).
fn surface_at(in: VsOut, facing: bool) -> Surface {
    var s = surface_of(in, facing, cross(dpdx(in.world), dpdy(in.world)), tex_coords(in.uv));
    let n = s.frame.n;
    let wo = s.frame.s * s.wo_local.x + s.frame.t * s.wo_local.y + n * s.wo_local.z;
    let mirror = 2.0 * dot(n, wo) * n - wo;
    s.mirror_dx = dpdx(mirror);
    s.mirror_dy = dpdy(mirror);
    s.through_dx = -dpdx(wo);
    s.through_dy = -dpdy(wo);
    return s;
}

// Radiance towards the viewer from light i without shadows: f · E⊥ ·
// |cos θ|, 0 where the light is below the geometric surface or the shading
// and geometric normals disagree about its side (the CPU `local` model).
fn unshadowed_contribution(s: Surface, i: u32) -> vec3<f32> {
    let l = light_li(lights[i], s.p);
    if l.valid == 0u {
        return vec3<f32>(0.0);
    }
    let wl = to_local(s.frame, l.wi);
    let g = dot(l.wi, s.ng);
    if g != 0.0 && wl.z != 0.0 && (g > 0.0) == (wl.z > 0.0) {
        return material_eval(s.mat, s.wo_local, wl) * l.value * abs(wl.z);
    }
    return vec3<f32>(0.0);
}

// Whether the pipeline looks up shadow maps (false: their code is dropped).
override SHADOW_MAPS: bool = true;

// Whether the frame has screen-space AO (false: kA = 1 from the screen).
override SCREEN_AO: bool = false;

// The screen-space kA of the pixel holding fragment position `frag` (every
// sample of a multisampled pixel gets its pixel's value).
fn screen_space_ao(frag: vec2<f32>) -> f32 {
    if !SCREEN_AO {
        return 1.0;
    }
    return textureLoad(screen_ao, vec2<i32>(frag), 0).x;
}

// kA of the ambient (environment) term: an AO bake's or the screen's.
fn ambient_occlusion(in: VsOut) -> f32 {
    return baked_ao(in, 1.0) * screen_space_ao(in.clip.xy);
}

// Depth prepass with screen-space AO: the normal target gets the shading
// normal on the viewer's side (world space) and the view distance at the
// pixel centre (the distance from the camera plane, −z_view), negated on
// the emitters of analytic area lights.
@fragment
fn fs_ao_prepass(in: VsOut, @builtin(front_facing) facing: bool) -> @location(0) vec4<f32> {
    // Only the normals of surface_of: no material work in the prepass.
    let n = visible_normals(in, view_direction(in.world), cross(dpdx(in.world), dpdy(in.world)));
    if discarded(in.instance, facing, tex_coords(in.uv)) {
        discard;
    }
    let z = max(dot(camera.eye.xyz - in.world, camera.back.xyz), 1e-30);
    // Analytic lights are not surfaces (kA = 0, as the `ao` integrator
    // gives): marked by a negative distance; they still occlude others.
    let light = instances[in.instance].light_shape != 0u;
    return vec4<f32>(n.ns, select(z, -z, light));
}

// The same times the light's shadow-map visibility (1 without a map).
fn light_contribution(s: Surface, i: u32) -> vec3<f32> {
    let c = unshadowed_contribution(s, i);
    if !SHADOW_MAPS || all(c == vec3<f32>(0.0)) {
        return c;
    }
    return c * shadow_visibility(i, s.p, s.ng);
}

// First word of the light list of the tile holding pixel `frag`.
fn tile_list(frag: vec2<f32>) -> u32 {
    let t = vec2<u32>(frag) / TILE;
    return (t.y * culling.tiles_x + t.x) * (culling.max_per_tile + 1u);
}

// Radiance towards the viewer of surface s: emission, the bakes, the
// environment light (times kA `ka`) and the lights, those of the pixel's
// tile when `tiled` and the tile lists are on, else every light.
fn forward_radiance(s: Surface, in: VsOut, ka: f32, tiled: bool) -> vec3<f32> {
    var radiance = s.emission;
    if s.lit == 0u {
        return radiance;
    }
    let baked = baked_light(s, in);
    radiance += baked.radiance;
    if !baked.realtime {
        return radiance;
    }
    radiance += environment_light(s, ka * s.occlusion);
    var count = TILE_OVERFLOW;
    var base = 0u;
    if tiled && culling.enabled != 0u {
        base = tile_list(in.clip.xy);
        count = tile_lights[base];
    }
    if count == TILE_OVERFLOW {
        for (var i = 0u; i < camera.light_count; i++) {
            radiance += light_contribution(s, i);
        }
    } else {
        // Increasing light order, as the loop above: the same sum.
        for (var k = 0u; k < count; k++) {
            radiance += light_contribution(s, tile_lights[base + 1u + k]);
        }
    }
    return radiance;
}

@fragment
fn fs_forward(in: VsOut, @builtin(front_facing) facing: bool) -> @location(0) vec4<f32> {
    let s = surface_at(in, facing);
    if s.culled {
        discard;
    }
    return vec4<f32>(forward_radiance(s, in, ambient_occlusion(in), true), 1.0);
}

// BLEND materials (glTF alphaMode), drawn after everything opaque and
// blended over it with weight α (source-over): every light (the tile lists
// cover only the opaque depths), and the AO of bakes only (screen-space AO
// describes the opaque surface behind).
@fragment
fn fs_blend(in: VsOut, @builtin(front_facing) facing: bool) -> @location(0) vec4<f32> {
    let s = surface_at(in, facing);
    let alpha = coverage(s.material, tex_coords(in.uv));
    if s.culled {
        discard;
    }
    return vec4<f32>(forward_radiance(s, in, baked_ao(in, 1.0), false), alpha);
}

@fragment
fn fs_base(in: VsOut, @builtin(front_facing) facing: bool) -> @location(0) vec4<f32> {
    let s = surface_at(in, facing);
    if s.culled {
        discard;
    }
    if s.lit == 0u {
        return vec4<f32>(s.emission, 1.0);
    }
    let baked = baked_light(s, in);
    var radiance = s.emission + baked.radiance;
    if baked.realtime {
        radiance += environment_light(s, ambient_occlusion(in) * s.occlusion);
    }
    return vec4<f32>(radiance, 1.0);
}

@fragment
fn fs_light(in: VsOut, @builtin(front_facing) facing: bool) -> @location(0) vec4<f32> {
    let s = surface_at(in, facing);
    if s.culled {
        discard;
    }
    if s.lit == 0u {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(unshadowed_contribution(s, params.light), 0.0);
}
