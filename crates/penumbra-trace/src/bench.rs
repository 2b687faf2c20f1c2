//! Ray-tracing throughput measurements for `penumbra bench`: BVH build rate,
//! closest-hit rate for coherent (camera) and incoherent (random directions
//! from surface points) rays, and rays read from a file so that another
//! engine can trace exactly the same set.

use crate::accel::{Accel, Hit};
use crate::ray::{Ray, offset_ray_origin};
use glam::Vec3;
use penumbra_scene::Camera;
use penumbra_shading::sampling::{Sampler, square_to_uniform_sphere};
use rayon::prelude::*;
use std::time::Instant;

/// One measurement.
#[derive(Clone, Debug)]
pub struct Measure {
    pub name: &'static str,
    pub seconds: f64,
    /// Rays (or triangles, for the build) processed.
    pub count: u64,
    /// Rays that hit something (0 for the build).
    pub hits: u64,
}

impl Measure {
    /// Millions of items per second.
    pub fn millions_per_second(&self) -> f64 {
        self.count as f64 / self.seconds.max(1e-12) / 1e6
    }
}

/// Camera rays through every pixel centre of a `width`×`height` image, in
/// scanline order (the coherent set).
pub fn camera_rays(camera: &Camera, width: u32, height: u32) -> Vec<Ray> {
    let mut rays = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let (o, d) = camera.generate_ray(x as f32 + 0.5, y as f32 + 0.5, width, height);
            rays.push(Ray::new(o, d));
        }
    }
    rays
}

/// Incoherent rays: from the first hits of `primary` rays, `per_hit` rays
/// each in uniformly random directions over the full sphere (fixed seed),
/// offset off the surface to the side they leave from.
pub fn incoherent_rays(
    accel: &Accel,
    triangles: &[[Vec3; 3]],
    primary: &[Ray],
    per_hit: u32,
    seed: u32,
) -> Vec<Ray> {
    primary
        .par_iter()
        .enumerate()
        .flat_map_iter(|(i, r)| {
            let hit = accel.intersect(r).map(|h| {
                let [a, b, c] = triangles[h.triangle as usize];
                let p = a * (1.0 - h.b1 - h.b2) + b * h.b1 + c * h.b2;
                (p, (b - a).cross(c - a).normalize_or_zero())
            });
            hit.into_iter().flat_map(move |(p, n)| {
                (0..per_hit).map(move |k| {
                    let mut s = Sampler::new(i as u32, k, 0, seed);
                    let d = square_to_uniform_sphere(s.next_2d());
                    let side = if d.dot(n) >= 0.0 { n } else { -n };
                    Ray::new(offset_ray_origin(p, side), d)
                })
            })
        })
        .collect()
}

/// How a measurement traces its rays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tracing {
    /// [`Accel::intersect`], one ray after another.
    OneAtATime,
    /// [`Accel::intersect_many`]: a few rays' walks interleaved per thread.
    Interleaved,
    /// [`Accel::intersect_packets`]: consecutive rays in packets.
    Packets,
}

/// Traces every ray for its closest hit, in parallel chunks; returns the
/// timing and the number of hits.
pub fn measure_closest_hit(
    accel: &Accel,
    rays: &[Ray],
    name: &'static str,
    tracing: Tracing,
) -> Measure {
    let t = Instant::now();
    let hits: u64 = rays
        .par_chunks(4096)
        .map(|chunk| {
            let hits = match tracing {
                Tracing::OneAtATime => chunk
                    .iter()
                    .filter(|r| accel.intersect(r).is_some())
                    .count() as u64,
                Tracing::Interleaved => count_hits(chunk, |r, h| accel.intersect_many(r, h)),
                Tracing::Packets => count_hits(chunk, |r, h| accel.intersect_packets(r, h)),
            };
            // The walk's visit counts, in a `stage-timing` build.
            crate::stages::flush();
            hits
        })
        .sum();
    Measure {
        name,
        seconds: t.elapsed().as_secs_f64(),
        count: rays.len() as u64,
        hits,
    }
}

/// The rays of `rays` that `trace` (a batch call) finds a hit for.
fn count_hits(rays: &[Ray], trace: impl Fn(&[Ray], &mut [Option<Hit>])) -> u64 {
    let mut hits = vec![None; rays.len()];
    trace(rays, &mut hits);
    hits.iter().filter(|h| h.is_some()).count() as u64
}

/// Parses a ray file: little-endian f32 `ox oy oz dx dy dz` per ray, no
/// header. Directions are normalised; a zero or non-finite ray is an error.
pub fn parse_ray_file(bytes: &[u8]) -> Result<Vec<Ray>, String> {
    const RAY_BYTES: usize = 24;
    if !bytes.len().is_multiple_of(RAY_BYTES) {
        return Err(format!(
            "size {} is not a multiple of 24 bytes (6 little-endian f32 per ray)",
            bytes.len()
        ));
    }
    let mut rays = Vec::with_capacity(bytes.len() / RAY_BYTES);
    for (i, chunk) in bytes.chunks_exact(RAY_BYTES).enumerate() {
        let mut f = [0f32; 6];
        for (k, v) in f.iter_mut().enumerate() {
            let b = [
                chunk[4 * k],
                chunk[4 * k + 1],
                chunk[4 * k + 2],
                chunk[4 * k + 3],
            ];
            *v = f32::from_le_bytes(b);
        }
        let o = Vec3::new(f[0], f[1], f[2]);
        let d = Vec3::new(f[3], f[4], f[5]);
        if !o.is_finite() || !d.is_finite() || d.length_squared() == 0.0 {
            return Err(format!(
                "ray {i} (byte offset {}) has a non-finite origin or a zero/non-finite direction",
                i * RAY_BYTES
            ));
        }
        rays.push(Ray::new(o, d.normalize()));
    }
    Ok(rays)
}

/// Serialises rays in the format read by [`parse_ray_file`].
pub fn write_ray_file(rays: &[Ray]) -> Vec<u8> {
    let mut out = Vec::with_capacity(rays.len() * 24);
    for r in rays {
        for v in [
            r.origin.x,
            r.origin.y,
            r.origin.z,
            r.direction.x,
            r.direction.y,
            r.direction.z,
        ] {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out
}

/// The benchmark mesh: a sphere of radius 1 with a deterministic bumpy
/// displacement, tessellated into a `(n+1)`-ring latitude–longitude grid of
/// about `target_triangles` triangles. Closed, with many small triangles of
/// varying orientation (neither a flat plane nor a trivially regular grid).
pub fn bench_mesh(target_triangles: usize) -> penumbra_scene::Mesh {
    // A lat-long grid with `rings` × `2 rings` quads has ≈ 4 rings² triangles.
    let rings = ((target_triangles as f64 / 4.0).sqrt().ceil() as usize).max(4);
    let segments = 2 * rings;
    let mut positions = Vec::with_capacity((rings + 1) * segments);
    for i in 0..=rings {
        let theta = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..segments {
            let phi = 2.0 * std::f32::consts::PI * j as f32 / segments as f32;
            let dir = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            // The bump vanishes at the poles (sin θ = 0) so that all
            // vertices of a pole ring coincide and the surface stays closed.
            let bump = theta.sin()
                * (0.05 * (7.0 * theta).sin() * (9.0 * phi).cos()
                    + 0.02 * (23.0 * theta + 3.0).sin() * (31.0 * phi).sin());
            positions.push(dir * (1.0 + bump));
        }
    }
    let mut indices = Vec::with_capacity(2 * rings * segments);
    let at = |i: usize, j: usize| (i * segments + j % segments) as u32;
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1));
            if i != 0 {
                indices.push([a, b, c]);
            }
            if i != rings - 1 {
                indices.push([b, d, c]);
            }
        }
    }
    let mut mesh = penumbra_scene::Mesh {
        name: "bench-sphere".into(),
        positions,
        indices,
        ..Default::default()
    };
    mesh.remove_degenerate();
    mesh
}

/// Writes a mesh as Wavefront OBJ (positions and triangles), so other
/// renderers can load the benchmark mesh. Written to a temporary file and
/// renamed, so a failed write leaves nothing behind.
pub fn write_obj(path: &std::path::Path, mesh: &penumbra_scene::Mesh) -> std::io::Result<()> {
    use std::io::Write;
    let tmp = path.with_extension("obj.tmp");
    let result = (|| {
        let mut w = std::io::BufWriter::new(std::fs::File::create(&tmp)?);
        writeln!(w, "# penumbra bench mesh: {} triangles", mesh.indices.len())?;
        for p in &mesh.positions {
            writeln!(w, "v {} {} {}", p.x, p.y, p.z)?;
        }
        for t in &mesh.indices {
            writeln!(w, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
        }
        w.into_inner().map_err(|e| e.into_error())?.sync_all()
    })();
    match result {
        Ok(()) => std::fs::rename(&tmp, path),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_file_round_trip_and_errors() {
        let rays = vec![
            Ray::new(Vec3::new(1.0, 2.0, 3.0), Vec3::Z),
            Ray::new(Vec3::ZERO, Vec3::new(0.0, -1.0, 0.0)),
        ];
        let bytes = write_ray_file(&rays);
        let back = parse_ray_file(&bytes).unwrap();
        assert_eq!(back.len(), 2);
        assert_eq!(back[0].origin, rays[0].origin);
        assert!(
            parse_ray_file(&bytes[..30])
                .unwrap_err()
                .contains("multiple of 24")
        );
        let mut bad = bytes.clone();
        bad[12..24].copy_from_slice(&[0; 12]);
        assert!(parse_ray_file(&bad).unwrap_err().contains("ray 0"));
    }

    #[test]
    fn bench_mesh_size_and_validity() {
        let m = bench_mesh(100_000);
        assert!(m.validate().is_ok());
        assert!(
            (m.indices.len() as f64 / 100_000.0 - 1.0).abs() < 0.05,
            "{}",
            m.indices.len()
        );
    }
}
