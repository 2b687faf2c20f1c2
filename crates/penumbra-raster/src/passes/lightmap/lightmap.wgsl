// Baked maps (penumbra-bake directories) looked up per fragment: group 2
// of the geometry passes. An ambient-occlusion bake multiplies the ambient
// light (the notes' Lo = c_diff · LA · kA); an irradiance bake (light map
// or radiosity) gives the diffuse light L = c_diff · E / π. Pages are
// float texture arrays read with textureLoad and interpolated bilinearly
// between texel centres here, exactly as penumbra_bake::lookup::bilinear
// does on the CPU. Appended after the forward pass (it uses VsOut).

@group(2) @binding(0) var ao_pages: texture_2d_array<f32>;
@group(2) @binding(1) var<storage, read> ao_corners: array<vec2<f32>>;
@group(2) @binding(2) var<storage, read> ao_instances: array<GpuBakeInstance>;
@group(2) @binding(3) var irradiance_pages: texture_2d_array<f32>;
@group(2) @binding(4) var<storage, read> irradiance_corners: array<vec2<f32>>;
@group(2) @binding(5) var<storage, read> irradiance_instances: array<GpuBakeInstance>;
@group(2) @binding(6) var<uniform> bake: GpuBakeParams;

// Whether the pipeline reads bakes (false: their code is dropped).
override BAKED_MAPS: bool = true;

// Atlas coordinate of corner `corner` of an instance's mesh in one bake.
fn bake_rect(b: GpuBakeInstance, layout_uv: vec2<f32>) -> vec2<f32> {
    return b.uv_min + layout_uv * (b.uv_max - b.uv_min);
}

fn ao_corner_uv(instance: u32, corner: u32) -> vec2<f32> {
    if !BAKED_MAPS || bake.ao == 0u {
        return vec2<f32>(0.0);
    }
    let b = ao_instances[instance];
    if b.valid == 0u {
        return vec2<f32>(0.0);
    }
    return bake_rect(b, ao_corners[b.first_corner + corner]);
}

fn irradiance_corner_uv(instance: u32, corner: u32) -> vec2<f32> {
    if !BAKED_MAPS || bake.irradiance == 0u {
        return vec2<f32>(0.0);
    }
    let b = irradiance_instances[instance];
    if b.valid == 0u {
        return vec2<f32>(0.0);
    }
    return bake_rect(b, irradiance_corners[b.first_corner + corner]);
}

// Bilinear lookup of layer `layer` at page coordinate uv: texel (x, y) has
// its centre at ((x + 0.5) / W, (y + 0.5) / H); edges clamp.
fn bake_bilinear(pages: texture_2d_array<f32>, layer: u32, uv: vec2<f32>) -> vec3<f32> {
    let dims = vec2<i32>(textureDimensions(pages));
    let p = uv * vec2<f32>(dims) - 0.5;
    let fl = floor(p);
    let f = p - fl;
    let i0 = vec2<i32>(fl);
    let hi = dims - vec2<i32>(1);
    let t00 = textureLoad(pages, clamp(i0, vec2<i32>(0), hi), layer, 0).xyz;
    let t10 = textureLoad(pages, clamp(i0 + vec2<i32>(1, 0), vec2<i32>(0), hi), layer, 0).xyz;
    let t01 = textureLoad(pages, clamp(i0 + vec2<i32>(0, 1), vec2<i32>(0), hi), layer, 0).xyz;
    let t11 = textureLoad(pages, clamp(i0 + vec2<i32>(1, 1), vec2<i32>(0), hi), layer, 0).xyz;
    let top = t00 * (1.0 - f.x) + t10 * f.x;
    let bottom = t01 * (1.0 - f.x) + t11 * f.x;
    return top * (1.0 - f.y) + bottom * f.y;
}

// kA at a fragment; `missing` where the frame has no AO bake or the
// instance has no texels.
fn baked_ao(in: VsOut, missing: f32) -> f32 {
    if !BAKED_MAPS || bake.ao == 0u {
        return missing;
    }
    let b = ao_instances[in.instance];
    if b.valid == 0u {
        return missing;
    }
    return bake_bilinear(ao_pages, b.page, in.ao_uv).x;
}

// Irradiance E [W/m²] at a fragment (0 without an irradiance bake).
fn baked_irradiance(in: VsOut) -> vec3<f32> {
    if !BAKED_MAPS || bake.irradiance == 0u {
        return vec3<f32>(0.0);
    }
    let b = irradiance_instances[in.instance];
    if b.valid == 0u {
        return vec3<f32>(0.0);
    }
    return bake_bilinear(irradiance_pages, b.page, in.irradiance_uv);
}

// The baked part of a lit fragment's radiance, and whether the real-time
// ambient light and lights still add to it (no irradiance bake, or one of
// indirect light only).
struct Baked {
    radiance: vec3<f32>,
    realtime: bool,
}

fn baked_light(s: Surface, in: VsOut) -> Baked {
    var out: Baked;
    out.radiance = vec3<f32>(0.0);
    out.realtime = true;
    if BAKED_MAPS && bake.irradiance != 0u {
        // L = c_diff · E / π (notes 004: B = c_diff · E, L = B / π), c_diff
        // the fragment's (textures applied).
        out.radiance = s.env.diffuse * baked_irradiance(in) * (1.0 / PI);
        out.realtime = bake.indirect_only != 0u;
    }
    return out;
}

// The looked-up values alone (--aovs): kA and E, 0 on the back of one-sided
// surfaces and on surfaces without texels (as the CPU `ao` integrator
// gives 0 on emitters and back faces).
struct BakeAovs {
    @location(0) ao: vec4<f32>,
    @location(1) irradiance: vec4<f32>,
}

@fragment
fn fs_bake_aovs(in: VsOut, @builtin(front_facing) facing: bool) -> BakeAovs {
    let s = surface_at(in, facing);
    if s.culled {
        discard;
    }
    var out: BakeAovs;
    out.ao = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    out.irradiance = vec4<f32>(0.0, 0.0, 0.0, 1.0);
    if s.lit != 0u {
        out.ao = vec4<f32>(vec3<f32>(baked_ao(in, 0.0)), 1.0);
        out.irradiance = vec4<f32>(baked_irradiance(in), 1.0);
    }
    return out;
}
