// Hemisphere SSAO (the notes' method, cosine-weighted): N kernel points on
// the hemisphere of radius R about the pixel's normal, turned about it by
// the pixel's entry of the 4×4 rotation tile. A point s is occluded when
// the surface q seen at its pixel lies in front of it (view distance), s
// lies below q's tangent plane and p above it — so the segment p → s,
// shorter than R, crosses that plane — and the surface is really there:
// q within R of p, or a surface seen at the crossing point. This is the
// range check: a far foreground object does not occlude (p is behind its
// plane too, or its plane's crossing point holds no surface). kA ≈ the fraction of points not occluded; the directions are
// cosine-distributed, so the fraction estimates the cosine-weighted kA
// rather than an unweighted one. Points that project off the screen count
// as open. Appended to common.wgsl + surface.wgsl.

// xyz: unit direction about +z (cosine-distributed); w unused.
@group(0) @binding(3) var<storage, read> kernel: array<vec4<f32>>;
@group(0) @binding(4) var raw_ao: texture_storage_2d<r32float, write>;

// Whether the point where the segment p → s crosses the plane (q, nq)
// lies on a surface the depth buffer sees (the surface at its pixel passes
// within 2 pixel footprints of it): true for a wall seen at a grazing
// angle, whose point q at the sample's pixel lies far from p; false where
// only the plane of a far surface reaches between p and s.
fn crossing_is_seen(p: vec3<f32>, s: vec3<f32>, q: vec3<f32>, nq: vec3<f32>) -> bool {
    let c = p + (s - p) * (dot(q - p, nq) / dot(s - p, nq));
    let cpx = ao_project(c);
    if !ao_on_screen(cpx) || -c.z <= 0.0 {
        return false;
    }
    let seen = ao_surface_at(vec2<i32>(cpx));
    return seen.valid && abs(dot(c - seen.p, seen.n)) <= 2.0 / ao_pixels_per_unit(seen.z);
}

@compute @workgroup_size(8, 8)
fn ssao_hemisphere(@builtin(global_invocation_id) id: vec3<u32>) {
    if any(id.xy >= vec2<u32>(ao.size)) {
        return;
    }
    let here = ao_target_at(vec2<i32>(id.xy));
    if !here.valid {
        textureStore(raw_ao, id.xy, vec4<f32>(1.0));
        return;
    }
    let p = here.p;
    let n = here.n;
    // A tangent frame about n (Duff et al. 2017), turned by the tile angle.
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let t0 = vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let b0 = vec3<f32>(b, sign + n.y * n.y * a, -n.y);
    let angle = 2.0 * AO_PI * ao_tile(id.xy).x;
    let t = cos(angle) * t0 + sin(angle) * b0;
    let bt = cross(n, t);
    // Below a surface by more than this counts as behind it.
    let eps = 1e-4 * ao.radius;
    var open = 0.0;
    for (var i = 0u; i < ao.samples; i++) {
        let k = kernel[i];
        let s = p + (t * k.x + bt * k.y + n * k.z) * ao.radius;
        let spx = ao_project(s);
        if !ao_on_screen(spx) || -s.z <= 0.0 {
            open += 1.0;
            continue;
        }
        let seen = ao_surface_at(vec2<i32>(spx));
        var occluded = false;
        if seen.valid && seen.z < -s.z {
            let q = seen.p;
            if dot(s - q, seen.n) < -eps && dot(p - q, seen.n) > eps {
                occluded = distance(q, p) <= ao.radius || crossing_is_seen(p, s, q, seen.n);
            }
        }
        open += select(1.0, 0.0, occluded);
    }
    textureStore(raw_ao, id.xy, vec4<f32>(open / f32(max(ao.samples, 1u)), 0.0, 0.0, 0.0));
}
