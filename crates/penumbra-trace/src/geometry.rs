//! The scene flattened for tracing: world-space triangles in one BVH, and the
//! surface data (normals, UVs, material) looked up at a hit. The scene's few
//! analytic area lights are intersected by a linear loop beside the BVH.

use crate::accel::{Accel, BuildQuality, Hit};
use crate::ray::Ray;
use crate::texture_lod::TextureLevels;

/// Culled back faces a camera ray passes through before it gives up.
pub const MAX_CULLED_LAYERS: usize = 64;
use glam::{Mat3, Vec2, Vec3, Vec4};
use penumbra_scene::{AlphaCoverage, MaterialId, Scene, Texture};
use penumbra_shading::light::AreaLight;
use penumbra_shading::sampling::{hash_combine, hash_u32};

/// Where a triangle came from.
#[derive(Clone, Copy, Debug)]
struct TriangleSource {
    instance: u32,
    /// Triangle index inside the instance's mesh.
    local: u32,
}

/// Per-instance data cached for shading.
#[derive(Clone, Debug)]
struct InstanceData {
    normal_matrix: Mat3,
    material: MaterialId,
    /// +1, or −1 when the transform mirrors (front = CW in world space).
    winding: f32,
    /// The material's coverage test (glTF alphaMode MASK or BLEND).
    alpha: Option<AlphaTest>,
}

/// What the any-hit filter needs of an alpha-tested instance: its coverage
/// (texture ids into [`SceneGeometry::alpha_textures`]) and where its
/// triangles' corner UVs start in [`SceneGeometry::alpha_uvs`].
#[derive(Clone, Copy, Debug)]
struct AlphaTest {
    coverage: AlphaCoverage,
    first_uv: usize,
}

/// Geometric and shading data at a ray hit.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit {
    pub p: Vec3,
    pub t: f32,
    /// Unit geometric normal of the *front* face (CCW winding, glTF rules).
    pub ng: Vec3,
    /// Unit shading normal (interpolated vertex normal, or `ng`), on the
    /// same side as `ng`.
    pub ns: Vec3,
    /// Texture coordinates in UV sets 0 and 1 ([`SceneGeometry::uvs_at`]).
    pub uvs: [Vec2; 2],
    /// Interpolated vertex colour (glTF COLOR_0), 1 without one: it
    /// multiplies the material's base colour.
    pub color: Vec3,
    /// Barycentrics of the hit for the triangle's vertices 1 and 2 (mesh
    /// order); 0 on a light.
    pub b1: f32,
    pub b2: f32,
    /// Meaningless when `light` is set (check it first).
    pub material: MaterialId,
    /// Triangle index in [`SceneGeometry`] order (u32::MAX for a light).
    pub triangle: u32,
    /// Index into `Scene::area_lights` when the hit is on an analytic area
    /// light (a pure emitter: `ng` = `ns` = its front normal, no material).
    pub light: Option<u32>,
}

/// A scene with more triangles, every instance counted, than the BVH
/// holds ([`Accel::MAX_TRIANGLES`]): bad input, refused before any work.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "{triangles} triangles with every instance counted; penumbra's BVH holds at most {}",
    Accel::MAX_TRIANGLES
)]
pub struct SceneTooLarge {
    pub triangles: usize,
}

/// Scene triangles in world space with a BVH over them.
#[derive(Debug)]
pub struct SceneGeometry {
    pub accel: Accel,
    /// Wall time of the BVH build alone [s] (what `bench` reports).
    pub accel_seconds: f64,
    /// World-space vertices of each triangle.
    pub triangles: Vec<[Vec3; 3]>,
    sources: Vec<TriangleSource>,
    instances: Vec<InstanceData>,
    /// The scene's analytic area lights, in `Scene::area_lights` order.
    pub area_lights: Vec<AreaLight>,
    /// Corner UVs (set 0; barycentric corners without UVs) of the triangles
    /// of alpha-tested instances, in mesh order per instance.
    alpha_uvs: Vec<[Vec2; 3]>,
    /// The coverage textures of alpha-tested instances.
    alpha_textures: Vec<Texture>,
    /// The mip chains of the textures that shape BSDFs.
    pub texture_levels: TextureLevels,
}

impl SceneGeometry {
    /// Whether `scene` fits the BVH: counts its triangles (every instance
    /// counted), allocates nothing.
    pub fn check_size(scene: &Scene) -> Result<(), SceneTooLarge> {
        let triangles = scene.triangle_count();
        if triangles > Accel::MAX_TRIANGLES {
            return Err(SceneTooLarge { triangles });
        }
        Ok(())
    }

    /// Flattens `scene` and builds its BVH; an error, before anything is
    /// allocated, for a scene the BVH cannot hold.
    pub fn build(scene: &Scene, quality: BuildQuality) -> Result<Self, SceneTooLarge> {
        Self::check_size(scene)?;
        let mut triangles = Vec::with_capacity(scene.triangle_count());
        let mut sources = Vec::with_capacity(scene.triangle_count());
        let mut instances = Vec::with_capacity(scene.instances.len());
        let mut alpha_uvs = Vec::new();
        let mut alpha_textures = Vec::new();
        let mut alpha_texture_ids = std::collections::HashMap::new();
        for (ii, inst) in scene.instances.iter().enumerate() {
            let mesh = &scene.meshes[inst.mesh];
            let world: Vec<Vec3> = mesh
                .positions
                .iter()
                .map(|&p| inst.transform.transform_point3(p))
                .collect();
            for (ti, tri) in mesh.indices.iter().enumerate() {
                triangles.push([
                    world[tri[0] as usize],
                    world[tri[1] as usize],
                    world[tri[2] as usize],
                ]);
                sources.push(TriangleSource {
                    instance: ii as u32,
                    local: ti as u32,
                });
            }
            let material = inst.material.unwrap_or(mesh.material);
            let alpha = scene.materials[material].alpha.map(|mut coverage| {
                coverage.texture = coverage.texture.map(|t| {
                    *alpha_texture_ids.entry(t).or_insert_with(|| {
                        alpha_textures.push(scene.textures[t].clone());
                        alpha_textures.len() - 1
                    })
                });
                let first_uv = alpha_uvs.len();
                let set = coverage.texture.map_or(0, |t| alpha_textures[t].uv_set);
                alpha_uvs.extend(mesh.indices.iter().map(|tri| match mesh.uv_set(set) {
                    Some(uv) => tri.map(|i| uv[i as usize]),
                    None => [Vec2::ZERO, Vec2::X, Vec2::Y],
                }));
                AlphaTest { coverage, first_uv }
            });
            instances.push(InstanceData {
                normal_matrix: inst.normal_matrix(),
                material,
                winding: if inst.flips_winding() { -1.0 } else { 1.0 },
                alpha,
            });
        }
        // The mip chains build beside the BVH (each is parallel inside).
        let ((accel, accel_seconds), texture_levels) = rayon::join(
            || {
                let start = std::time::Instant::now();
                let accel = Accel::build(&triangles, quality);
                (accel, start.elapsed().as_secs_f64())
            },
            || TextureLevels::new(scene),
        );
        Ok(Self {
            accel,
            accel_seconds,
            texture_levels,
            triangles,
            sources,
            instances,
            area_lights: scene.area_lights.iter().map(|l| l.light).collect(),
            alpha_uvs,
            alpha_textures,
        })
    }

    /// Whether some triangles have a coverage test (the BVH queries then
    /// filter their hits).
    fn alpha_tested(&self) -> bool {
        !self.alpha_uvs.is_empty()
    }

    /// The any-hit filter: whether `ray` meets `triangle` at (b1, b2), or
    /// passes through where its material's coverage says the surface is
    /// absent. BLEND's random number is a hash of the ray and the triangle,
    /// so a query is reproducible whatever thread asks it, and the shadow
    /// and closest-hit queries of one ray agree.
    fn meets(&self, ray: &Ray, triangle: u32, b1: f32, b2: f32) -> bool {
        let src = self.sources[triangle as usize];
        let Some(test) = &self.instances[src.instance as usize].alpha else {
            return true;
        };
        let [u0, u1, u2] = self.alpha_uvs[test.first_uv + src.local as usize];
        let uv = u0 * (1.0 - b1 - b2) + u1 * b1 + u2 * b2;
        let alpha = test.coverage.alpha_at(&self.alpha_textures, uv);
        test.coverage.covers(alpha, ray_uniform(ray, triangle))
    }

    /// The BVH's closest accepted hit.
    fn closest_triangle(&self, ray: &Ray) -> Option<Hit> {
        if self.alpha_tested() {
            self.accel
                .intersect_where(ray, |t, b1, b2| self.meets(ray, t, b1, b2))
        } else {
            self.accel.intersect(ray)
        }
    }

    /// The instance a triangle belongs to and its index in the instance's
    /// mesh.
    pub fn triangle_source(&self, triangle: u32) -> (usize, usize) {
        let s = self.sources[triangle as usize];
        (s.instance as usize, s.local as usize)
    }

    /// The triangles of instance `instance`: its mesh's triangles in mesh
    /// order, as the consecutive indices `first..first + count`.
    pub fn instance_triangles(&self, instance: usize) -> std::ops::Range<u32> {
        let start = self
            .sources
            .partition_point(|s| (s.instance as usize) < instance);
        let end = self
            .sources
            .partition_point(|s| (s.instance as usize) <= instance);
        start as u32..end as u32
    }

    /// The surface at barycentrics (b1, b2) of `triangle`, as a ray hit there
    /// would report it (t = 0): the starting point of queries that begin on
    /// a surface, such as a light-map texel.
    pub fn surface_point(&self, scene: &Scene, triangle: u32, b1: f32, b2: f32) -> SurfaceHit {
        self.surface_at(
            scene,
            &Hit {
                triangle,
                t: 0.0,
                b1,
                b2,
            },
        )
    }

    /// The vertex normals at `triangle`'s corners in world space (the
    /// mesh's normals under the instance's normal matrix, not normalised),
    /// or `None` for a mesh without normals (shaded flat): what
    /// [`Self::surface_point`] interpolates for the shading normal.
    pub fn corner_normals(&self, scene: &Scene, triangle: u32) -> Option<[Vec3; 3]> {
        let src = self.sources[triangle as usize];
        let mesh = &scene.meshes[scene.instances[src.instance as usize].mesh];
        let normals = mesh.normals.as_deref()?;
        let m = self.instances[src.instance as usize].normal_matrix;
        Some(mesh.indices[src.local as usize].map(|i| m * normals[i as usize]))
    }

    /// Material of a triangle.
    pub fn material_of(&self, triangle: u32) -> MaterialId {
        self.instances[self.sources[triangle as usize].instance as usize].material
    }

    /// Unnormalised front-face normal (length = 2 × area).
    pub fn front_normal_scaled(&self, triangle: u32) -> Vec3 {
        let [a, b, c] = self.triangles[triangle as usize];
        let inst = &self.instances[self.sources[triangle as usize].instance as usize];
        (b - a).cross(c - a) * inst.winding
    }

    pub fn area(&self, triangle: u32) -> f32 {
        0.5 * self.front_normal_scaled(triangle).length()
    }

    /// Closest surface along `ray`. Inlined with [`Self::surface_at`] into
    /// the integrators' loops, which then build the hit in place instead of
    /// copying it out of a returned `Option` (see `path::scatter`).
    #[inline(always)]
    pub fn intersect(&self, scene: &Scene, ray: &Ray) -> Option<SurfaceHit> {
        crate::stats::count_ray();
        let hit = crate::stages::timed(crate::stages::Stage::Traversal, || {
            self.closest_triangle(ray)
        });
        let mut tmax = hit.as_ref().map_or(ray.tmax, |h| h.t);
        let mut light_hit = None;
        for (i, l) in self.area_lights.iter().enumerate() {
            if let Some(h) = l.shape.intersect(ray.origin, ray.direction, tmax) {
                tmax = h.t;
                light_hit = Some((i as u32, h));
            }
        }
        if let Some((i, h)) = light_hit {
            return Some(SurfaceHit {
                p: h.p,
                t: h.t,
                ng: h.n,
                ns: h.n,
                uvs: [Vec2::ZERO; 2],
                color: Vec3::ONE,
                b1: 0.0,
                b2: 0.0,
                material: 0,
                triangle: u32::MAX,
                light: Some(i),
            });
        }
        Some(self.surface_at(scene, &hit?))
    }

    /// Closest surface a camera ray sees: as [`Self::intersect`], but the
    /// back faces of materials with `cull_back_faces` (glTF `doubleSided:
    /// false`) are passed through, as glTF's back-face culling hides them
    /// (at most [`MAX_CULLED_LAYERS`] of them; beyond, nothing is seen).
    /// The hit's `t` is measured from the camera ray's origin, through
    /// the faces passed.
    pub fn intersect_camera(&self, scene: &Scene, ray: &Ray) -> Option<SurfaceHit> {
        // The parameter t of `ray` at a point on it.
        let t_at = |q: Vec3| (q - ray.origin).dot(ray.direction) / ray.direction.length_squared();
        let mut r = *ray;
        let mut travelled = 0.0;
        for _ in 0..=MAX_CULLED_LAYERS {
            let hit = self.intersect(scene, &r)?;
            let culled = hit.light.is_none()
                && scene.materials[hit.material].cull_back_faces
                && hit.ng.dot(r.direction) > 0.0;
            if !culled {
                return Some(SurfaceHit {
                    t: travelled + hit.t,
                    ..hit
                });
            }
            // On through the face: leave from its back side, a little past
            // the hit (the offset counts in the distance travelled).
            let origin = crate::ray::offset_ray_origin(hit.p, hit.ng);
            travelled = t_at(origin);
            r = Ray::segment(origin, r.direction, ray.tmax - travelled);
        }
        None
    }

    /// Is anything (triangle or area light) along `ray` before `ray.tmax`?
    pub fn occluded(&self, ray: &Ray) -> bool {
        crate::stats::count_ray();
        self.area_lights.iter().any(|l| {
            l.shape
                .intersect(ray.origin, ray.direction, ray.tmax)
                .is_some()
        }) || if self.alpha_tested() {
            self.accel
                .occluded_where(ray, |t, b1, b2| self.meets(ray, t, b1, b2))
        } else {
            self.accel.occluded(ray)
        }
    }

    /// UV sets 0 and 1 at barycentrics (b1, b2) of `triangle` (the
    /// barycentrics themselves for a set the mesh lacks): all that texture
    /// lookups on a light sample need, without a whole [`SurfaceHit`].
    pub fn uvs_at(&self, scene: &Scene, triangle: u32, b1: f32, b2: f32) -> [Vec2; 2] {
        let src = self.sources[triangle as usize];
        let mesh = &scene.meshes[scene.instances[src.instance as usize].mesh];
        let idx = mesh.indices[src.local as usize];
        let at = |set| match mesh.uv_set(set) {
            Some(uv) => {
                uv[idx[0] as usize] * (1.0 - b1 - b2)
                    + uv[idx[1] as usize] * b1
                    + uv[idx[2] as usize] * b2
            }
            None => Vec2::new(b1, b2),
        };
        [at(0), at(1)]
    }

    /// A_uv / A_world of `triangle` for UV sets 0 and 1 (the barycentric
    /// corners (0, 0), (1, 0), (0, 1) for a set the mesh lacks): how many
    /// square UV units a square world unit spans there, for
    /// [`crate::texture_lod::Footprint`]. 0 where the UVs are degenerate.
    pub fn uv_area_ratio(&self, scene: &Scene, triangle: u32) -> [f32; 2] {
        let src = self.sources[triangle as usize];
        let mesh = &scene.meshes[scene.instances[src.instance as usize].mesh];
        let idx = mesh.indices[src.local as usize].map(|i| i as usize);
        let world = self.area(triangle);
        [0, 1].map(|set| {
            let uv_area = match mesh.uv_set(set) {
                Some(uv) => {
                    0.5 * (uv[idx[1]] - uv[idx[0]])
                        .perp_dot(uv[idx[2]] - uv[idx[0]])
                        .abs()
                }
                None => 0.5,
            };
            uv_area / world
        })
    }

    /// The mesh tangent of `triangle` at barycentrics (b1, b2) in world
    /// space (xyz, not normalised; w = ±1 the handedness, flipped by
    /// mirroring transforms), or `None` when the mesh has no tangents.
    pub fn tangent_at(&self, scene: &Scene, triangle: u32, b1: f32, b2: f32) -> Option<Vec4> {
        let src = self.sources[triangle as usize];
        let inst = &scene.instances[src.instance as usize];
        let mesh = &scene.meshes[inst.mesh];
        let t = mesh.tangents.as_ref()?;
        let [i0, i1, i2] = mesh.indices[src.local as usize].map(|i| i as usize);
        let along =
            t[i0].truncate() * (1.0 - b1 - b2) + t[i1].truncate() * b1 + t[i2].truncate() * b2;
        let w =
            if t[i0].w < 0.0 { -1.0 } else { 1.0 } * self.instances[src.instance as usize].winding;
        Some((Mat3::from_mat4(inst.transform) * along).extend(w))
    }

    #[inline(always)]
    fn surface_at(&self, scene: &Scene, hit: &Hit) -> SurfaceHit {
        let src = self.sources[hit.triangle as usize];
        let inst_data = &self.instances[src.instance as usize];
        let inst = &scene.instances[src.instance as usize];
        let mesh = &scene.meshes[inst.mesh];
        let idx = mesh.indices[src.local as usize];
        let (b1, b2) = (hit.b1, hit.b2);
        let b0 = 1.0 - b1 - b2;
        let ng = self.front_normal_scaled(hit.triangle).normalize_or_zero();
        let interp3 = |v: &[Vec3]| {
            v[idx[0] as usize] * b0 + v[idx[1] as usize] * b1 + v[idx[2] as usize] * b2
        };
        let mut ns = match &mesh.normals {
            Some(n) => (inst_data.normal_matrix * interp3(n)).normalize_or_zero(),
            None => ng,
        };
        if ns == Vec3::ZERO {
            ns = ng;
        } else if ns.dot(ng) < 0.0 {
            ns = -ns;
        }
        let uvs = self.uvs_at(scene, hit.triangle, b1, b2);
        let color = mesh.colors.as_deref().map_or(Vec3::ONE, interp3);
        // Interpolating the world vertices is more accurate than o + t d.
        let [a, b, c] = self.triangles[hit.triangle as usize];
        let p = a * b0 + b * b1 + c * b2;
        SurfaceHit {
            p,
            t: hit.t,
            ng,
            ns,
            uvs,
            color,
            b1,
            b2,
            material: inst_data.material,
            triangle: hit.triangle,
            light: None,
        }
    }
}

/// A uniform number in [0, 1) from the bits of `ray` and a triangle index
/// (Wellons' lowbias32 hash, chained): stochastic transparency's coin.
fn ray_uniform(ray: &Ray, triangle: u32) -> f32 {
    let words = [
        ray.origin.x,
        ray.origin.y,
        ray.origin.z,
        ray.direction.x,
        ray.direction.y,
        ray.direction.z,
    ];
    let h = words
        .iter()
        .fold(hash_u32(triangle), |h, w| hash_combine(h, w.to_bits()));
    (h >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}
