//! Analytic shapes tessellated to triangle meshes.
//!
//! Every function returns a [`Mesh`] whose positions are in the coordinate
//! system of its arguments: the *object space* of the instance that places
//! it (the TOML loader puts an object's `translate`/`rotate`/`scale` in
//! [`crate::Instance::transform`], not in the vertices). With an identity
//! instance transform the arguments are world coordinates.
//!
//! Conventions shared by all shapes:
//! - triangles are counter-clockwise seen from the front, so the geometric
//!   normal `(v1 − v0) × (v2 − v0)` is the front side; closed shapes (sphere,
//!   box) face outwards;
//! - UVs follow glTF: `v = 0` is the top row of a texture;
//! - the sphere has smooth per-vertex normals; the flat shapes (quad, box,
//!   disk) have `normals = None`, i.e. they are shaded with face normals;
//! - `material` is 0: the caller sets it;
//! - no triangle is degenerate for valid (finite, non-zero) arguments.

use crate::mesh::Mesh;
use glam::{Vec2, Vec3};
use penumbra_shading::Frame;
use std::f32::consts::{PI, TAU};

/// Default number of latitude bands of [`sphere`] used by the scene format.
pub const DEFAULT_SPHERE_RINGS: u32 = 32;
/// Default number of rim segments of [`disk`] used by the scene format.
pub const DEFAULT_DISK_SEGMENTS: u32 = 64;

/// UV sphere of `radius` around `center` with `rings` latitude bands (≥ 2)
/// and `2·rings` longitude segments.
///
/// Vertex `(θ, φ)` (polar angle from +y, azimuth from +z towards +x) is at
/// `center + r (sin θ sin φ, cos θ, sin θ cos φ)` with normal
/// `(p − center)/r` and UV `(φ / 2π, θ / π)`. The seam (φ = 0 = 2π) has
/// duplicated vertices so UVs do not wrap; each pole is a fan of triangles
/// whose pole vertices carry the UV of their segment's middle, so no
/// triangle is degenerate. `2·rings·(2·rings − 2)` triangles in all.
pub fn sphere(center: Vec3, radius: f32, rings: u32) -> Mesh {
    let rings = rings.max(2);
    let segments = 2 * rings;
    let dir = |theta: f32, phi: f32| {
        let (st, ct) = theta.sin_cos();
        let (sp, cp) = phi.sin_cos();
        Vec3::new(st * sp, ct, st * cp)
    };
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    let mut push = |n: Vec3, uv: Vec2| {
        positions.push(center + radius * n);
        normals.push(n);
        uvs.push(uv);
        (positions.len() - 1) as u32
    };
    // Pole vertices, one per segment: north (θ = 0) then south (θ = π).
    let north: Vec<u32> = (0..segments)
        .map(|j| push(Vec3::Y, Vec2::new((j as f32 + 0.5) / segments as f32, 0.0)))
        .collect();
    let south: Vec<u32> = (0..segments)
        .map(|j| push(-Vec3::Y, Vec2::new((j as f32 + 0.5) / segments as f32, 1.0)))
        .collect();
    // Interior rings i = 1 ..= rings−1, each with segments+1 vertices (seam).
    let mut ring_index = Vec::with_capacity((rings - 1) as usize);
    for i in 1..rings {
        let v = i as f32 / rings as f32;
        let theta = PI * v;
        let first = push(dir(theta, 0.0), Vec2::new(0.0, v));
        for j in 1..=segments {
            let u = j as f32 / segments as f32;
            let phi = if j == segments { 0.0 } else { TAU * u };
            push(dir(theta, phi), Vec2::new(u, v));
        }
        ring_index.push(first);
    }
    let at = |i: u32, j: u32| ring_index[(i - 1) as usize] + j;
    let mut indices = Vec::new();
    // Increasing φ turns from +z towards +x, counter-clockwise seen from
    // above (+y): on the upper cap, seen from outside, pole → (ring, j) →
    // (ring, j+1) is counter-clockwise; the south cap and the bands follow
    // (θ grows downwards, φ to the viewer's right on the near side).
    for j in 0..segments {
        indices.push([north[j as usize], at(1, j), at(1, j + 1)]);
        indices.push([south[j as usize], at(rings - 1, j + 1), at(rings - 1, j)]);
    }
    for i in 1..rings - 1 {
        for j in 0..segments {
            let (a, b) = (at(i, j), at(i, j + 1));
            let (c, d) = (at(i + 1, j), at(i + 1, j + 1));
            indices.push([a, c, d]);
            indices.push([a, d, b]);
        }
    }
    Mesh {
        name: "sphere".into(),
        positions,
        normals: Some(normals),
        uv0: Some(uvs),
        uv1: None,
        tangents: None,
        colors: None,
        indices,
        material: 0,
    }
}

/// Parallelogram with vertices `corner`, `corner + edge1`,
/// `corner + edge1 + edge2`, `corner + edge2`; two triangles (0,1,2), (0,2,3).
/// Front (geometric normal) = `edge1 × edge2`. UV (0,0) at `corner`, u along
/// `edge1`, v along `edge2`.
pub fn quad(corner: Vec3, edge1: Vec3, edge2: Vec3) -> Mesh {
    let mut m = quad_from_vertices([
        corner,
        corner + edge1,
        corner + edge1 + edge2,
        corner + edge2,
    ]);
    m.name = "quad".into();
    m
}

/// Quadrilateral through four vertices in order (as an OBJ `f 1 2 3 4`),
/// triangulated (0,1,2), (0,2,3); front = `(v1 − v0) × (v2 − v0)`. UVs
/// (0,0), (1,0), (1,1), (0,1). Planarity is the caller's business: a
/// non-planar quad is rendered as its two triangles.
pub fn quad_from_vertices(v: [Vec3; 4]) -> Mesh {
    Mesh {
        name: "quad".into(),
        positions: v.to_vec(),
        normals: None,
        uv0: Some(vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ]),
        uv1: None,
        tangents: None,
        colors: None,
        indices: vec![[0, 1, 2], [0, 2, 3]],
        material: 0,
    }
}

/// Rectangle of `size` = (extent along x, extent along z) centred on
/// `center` in the plane y = center.y, facing +y (a floor). Built with
/// [`quad`]: corner `center + (−sx/2, 0, +sz/2)`, `edge1 = (sx, 0, 0)`,
/// `edge2 = (0, 0, −sz)`, so `edge1 × edge2 = +y` and, seen from above with
/// −z up, u points right and v up.
pub fn rectangle(center: Vec3, size: Vec2) -> Mesh {
    let corner = center + Vec3::new(-0.5 * size.x, 0.0, 0.5 * size.y);
    quad(
        corner,
        Vec3::new(size.x, 0.0, 0.0),
        Vec3::new(0.0, 0.0, -size.y),
    )
}

/// Axis-aligned box from `min` to `max`: 6 faces × 2 triangles with
/// outward normals, 24 vertices (4 per face, so UVs cover each face).
/// Shaded flat (`normals = None`).
pub fn cuboid(min: Vec3, max: Vec3) -> Mesh {
    let c = 0.5 * (min + max);
    let h = 0.5 * (max - min);
    // (outward axis, u axis, v axis) with u × v = outward.
    let faces = [
        (Vec3::X, -Vec3::Z, Vec3::Y),
        (-Vec3::X, Vec3::Z, Vec3::Y),
        (Vec3::Y, Vec3::X, -Vec3::Z),
        (-Vec3::Y, Vec3::X, Vec3::Z),
        (Vec3::Z, Vec3::X, Vec3::Y),
        (-Vec3::Z, -Vec3::X, Vec3::Y),
    ];
    let mut mesh = Mesh {
        name: "box".into(),
        uv0: Some(Vec::with_capacity(24)),
        material: 0,
        ..Default::default()
    };
    for (n, u, v) in faces {
        let (hu, hv) = ((u * h).abs().dot(Vec3::ONE), (v * h).abs().dot(Vec3::ONE));
        let corner = c + n * h - u * hu - v * hv;
        let face = quad(corner, 2.0 * hu * u, 2.0 * hv * v);
        let base = mesh.positions.len() as u32;
        mesh.positions.extend(face.positions);
        if let (Some(dst), Some(src)) = (mesh.uv0.as_mut(), face.uv0) {
            dst.extend(src);
        }
        mesh.indices.extend(
            face.indices
                .iter()
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
    }
    mesh
}

/// Disk of `radius` around `center`, facing the unit `normal`: a fan of
/// `segments` (≥ 3) triangles (centre, rim j, rim j+1), counter-clockwise
/// around `normal`, so the geometric normal is `normal`. The rim is a
/// regular polygon inscribed in the circle (its area is
/// `½ n r² sin(2π/n)`, slightly less than π r²). UVs map the disk onto the
/// unit square's inscribed circle. Shaded flat.
pub fn disk(center: Vec3, normal: Vec3, radius: f32, segments: u32) -> Mesh {
    let segments = segments.max(3);
    let n = normal.normalize();
    let frame = Frame::from_normal(n);
    // s × t = n for Frame (right-handed), so increasing φ is CCW around n.
    let (s, t) = (frame.s, frame.t);
    let mut positions = vec![center];
    let mut uvs = vec![Vec2::splat(0.5)];
    for j in 0..segments {
        let phi = TAU * j as f32 / segments as f32;
        let (sp, cp) = phi.sin_cos();
        positions.push(center + radius * (cp * s + sp * t));
        uvs.push(Vec2::new(0.5 + 0.5 * cp, 0.5 - 0.5 * sp));
    }
    let indices = (0..segments)
        .map(|j| [0, 1 + j, 1 + (j + 1) % segments])
        .collect();
    Mesh {
        name: "disk".into(),
        positions,
        normals: None,
        uv0: Some(uvs),
        uv1: None,
        tangents: None,
        colors: None,
        indices,
        material: 0,
    }
}

/// Total area of the mesh's triangles (object space).
pub fn surface_area(mesh: &Mesh) -> f32 {
    let p = &mesh.positions;
    mesh.indices
        .iter()
        .map(|t| {
            let (a, b, c) = (p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum()
}

/// Signed volume enclosed by the mesh (divergence theorem:
/// `V = Σ (a · (b × c)) / 6` over its triangles). Positive for a closed mesh
/// whose triangles face outwards, negative if they face inwards.
pub fn signed_volume(mesh: &Mesh) -> f32 {
    let p = &mesh.positions;
    mesh.indices
        .iter()
        .map(|t| {
            let (a, b, c) = (p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]);
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every edge of a closed, consistently oriented mesh is used once in
    /// each direction (seam duplicates compared by position).
    fn assert_closed_and_oriented(m: &Mesh) {
        use std::collections::HashMap;
        let key = |i: u32| {
            let p = m.positions[i as usize];
            [
                (p.x * 1e4).round() as i64,
                (p.y * 1e4).round() as i64,
                (p.z * 1e4).round() as i64,
            ]
        };
        let mut edges: HashMap<([i64; 3], [i64; 3]), i32> = HashMap::new();
        for t in &m.indices {
            for k in 0..3 {
                *edges.entry((key(t[k]), key(t[(k + 1) % 3]))).or_default() += 1;
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(count, 1, "edge used {count} times in the same direction");
            assert_eq!(edges.get(&(b, a)), Some(&1), "edge without its twin");
        }
    }

    fn face_normals_point_away_from(m: &Mesh, center: Vec3) {
        let p = &m.positions;
        for t in &m.indices {
            let (a, b, c) = (p[t[0] as usize], p[t[1] as usize], p[t[2] as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.length() > 0.0, "degenerate triangle");
            assert!(n.dot((a + b + c) / 3.0 - center) > 0.0, "inward face");
        }
    }

    #[test]
    fn sphere_is_closed_outward_and_has_the_right_area() {
        let c = Vec3::new(1.0, -2.0, 0.5);
        let r = 2.5;
        for rings in [2, 3, 8, 32] {
            let m = sphere(c, r, rings);
            m.validate().unwrap();
            assert_eq!(m.indices.len() as u32, 2 * rings * (2 * rings - 2));
            assert_closed_and_oriented(&m);
            face_normals_point_away_from(&m, c);
            // Divergence check: outward faces enclose a positive volume.
            let v = signed_volume(&m);
            assert!(v > 0.0 && v < 4.0 / 3.0 * PI * r * r * r);
        }
        let m = sphere(c, r, 32);
        let exact = 4.0 * PI * r * r;
        let area = surface_area(&m);
        // Inscribed polygons: relative error ≈ (π/rings)²/6·… < 0.5 %.
        assert!(
            area < exact && (exact - area) / exact < 5e-3,
            "{area} vs {exact}"
        );
        let vol = signed_volume(&m);
        let exact_v = 4.0 / 3.0 * PI * r * r * r;
        assert!((exact_v - vol) / exact_v < 1e-2);
        // Smooth normals: unit, radial, agreeing with the geometry.
        let normals = m.normals.as_ref().unwrap();
        for (p, n) in m.positions.iter().zip(normals) {
            assert!((n.length() - 1.0).abs() < 1e-5);
            assert!(((*p - c) / r - *n).length() < 1e-4);
        }
        for uv in m.uv0.as_ref().unwrap() {
            assert!((0.0..=1.0).contains(&uv.x) && (0.0..=1.0).contains(&uv.y));
        }
    }

    #[test]
    fn sphere_area_converges() {
        let exact = 4.0 * PI;
        let e8 = exact - surface_area(&sphere(Vec3::ZERO, 1.0, 8));
        let e16 = exact - surface_area(&sphere(Vec3::ZERO, 1.0, 16));
        assert!(e8 > 0.0 && e16 > 0.0);
        let ratio = e8 / e16;
        assert!((3.5..4.5).contains(&ratio), "second order: {ratio}");
    }

    #[test]
    fn quad_area_normal_and_uvs_are_exact() {
        let e1 = Vec3::new(3.0, 0.0, 0.0);
        let e2 = Vec3::new(1.0, 2.0, 0.0);
        let m = quad(Vec3::new(1.0, 1.0, 1.0), e1, e2);
        m.validate().unwrap();
        assert_eq!(m.indices.len(), 2);
        assert_eq!(surface_area(&m), e1.cross(e2).length());
        let p = &m.positions;
        for t in &m.indices {
            let n = (p[t[1] as usize] - p[t[0] as usize])
                .cross(p[t[2] as usize] - p[t[0] as usize])
                .normalize();
            assert!((n - e1.cross(e2).normalize()).length() < 1e-6);
        }
        assert_eq!(m.uv0.as_ref().unwrap()[2], Vec2::ONE);

        let r = rectangle(Vec3::new(0.0, 2.0, 0.0), Vec2::new(4.0, 6.0));
        assert_eq!(surface_area(&r), 24.0);
        let (lo, hi) = r.bounds();
        assert_eq!(
            (lo, hi),
            (Vec3::new(-2.0, 2.0, -3.0), Vec3::new(2.0, 2.0, 3.0))
        );
        let p = &r.positions;
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        assert!(n.normalize().abs_diff_eq(Vec3::Y, 1e-6));
    }

    #[test]
    fn box_is_closed_with_outward_flat_faces() {
        let (lo, hi) = (Vec3::new(-1.0, 0.0, 2.0), Vec3::new(3.0, 1.0, 2.5));
        let m = cuboid(lo, hi);
        m.validate().unwrap();
        assert_eq!(m.indices.len(), 12);
        assert_eq!(m.positions.len(), 24);
        assert!(m.normals.is_none());
        assert_closed_and_oriented(&m);
        face_normals_point_away_from(&m, 0.5 * (lo + hi));
        let d = hi - lo;
        assert!((signed_volume(&m) - d.x * d.y * d.z).abs() < 1e-5);
        let area = 2.0 * (d.x * d.y + d.y * d.z + d.z * d.x);
        assert!((surface_area(&m) - area).abs() < 1e-5);
        assert_eq!(m.bounds(), (lo, hi));
    }

    #[test]
    fn disk_faces_its_normal() {
        let n = Vec3::new(0.3, -0.9, 0.2).normalize();
        let c = Vec3::new(5.0, 1.0, -1.0);
        let m = disk(c, n, 2.0, 64);
        m.validate().unwrap();
        assert_eq!(m.indices.len(), 64);
        let p = &m.positions;
        for t in &m.indices {
            let g = (p[t[1] as usize] - p[t[0] as usize])
                .cross(p[t[2] as usize] - p[t[0] as usize])
                .normalize();
            assert!((g - n).length() < 1e-4, "{g} vs {n}");
        }
        for q in &p[1..] {
            assert!(((*q - c).length() - 2.0).abs() < 1e-5);
            assert!((*q - c).dot(n).abs() < 1e-5);
        }
        let polygon = 0.5 * 64.0 * 4.0 * (TAU / 64.0).sin();
        assert!((surface_area(&m) - polygon).abs() < 1e-3);
        assert!((surface_area(&m) - PI * 4.0).abs() / (PI * 4.0) < 2e-3);
    }
}
