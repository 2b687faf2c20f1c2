//! Integrators: estimators of the radiance arriving at the camera along a ray.

mod ao;
mod local;
mod path;
mod surface;
pub(crate) mod wavefront;
mod whitted;

pub use path::RadianceSink;

use crate::geometry::{SceneGeometry, SurfaceHit};
use crate::lights::LightSampler;
use crate::ray::{Ray, offset_ray_origin};
use crate::texture_lod::{Footprint, RayCone, filtered_maps};
use glam::Vec3;
use penumbra_scene::{IntegratorKind, RenderSettings, Scene};
use penumbra_shading::bsdf::Bsdf;
use penumbra_shading::sampling::Sampler;
use penumbra_shading::{Frame, Rgb};

/// What one camera sample returns: radiance and the first-hit AOVs.
#[derive(Clone, Copy, Debug, Default)]
pub struct PathSample {
    pub radiance: Rgb,
    /// Albedo of the first surface hit (0 on a miss).
    pub albedo: Rgb,
    /// World-space shading normal of the first hit, facing the camera.
    pub normal: Vec3,
    /// Distance along the camera ray to the first hit (0 on a miss).
    pub depth: f32,
}

/// Everything an integrator reads; built once per render.
#[derive(Debug)]
pub struct TraceContext<'a> {
    pub scene: &'a Scene,
    pub geometry: &'a SceneGeometry,
    pub lights: &'a LightSampler,
    pub settings: &'a RenderSettings,
    /// The footprint of a camera ray ([`RayCone::POINT`] where no camera
    /// shoots the rays: textures are then read at level 0 first).
    pub camera_cone: RayCone,
}

/// Local shading state at a surface hit, oriented towards the outgoing
/// direction for two-sided materials.
pub(crate) struct Shading<'h> {
    pub hit: &'h SurfaceHit,
    pub frame: Frame,
    /// Geometric normal on the side of `wo`.
    pub ng: Vec3,
    pub bsdf: Bsdf,
    pub wo_local: Vec3,
}

impl TraceContext<'_> {
    /// Radiance along a camera ray with the configured integrator.
    pub fn li(&self, ray: &Ray, sampler: &mut Sampler) -> PathSample {
        match self.settings.integrator {
            IntegratorKind::Local => local::li(self, ray, sampler),
            // Direct lighting is path tracing cut at two segments (camera →
            // surface → light), Mitsuba's `max_depth = 2`.
            IntegratorKind::Direct => path::li(self, ray, sampler, 2),
            IntegratorKind::Path => path::li(self, ray, sampler, self.settings.max_depth),
            IntegratorKind::Ao => ao::li(self, ray, sampler),
            IntegratorKind::Whitted => whitted::li(self, ray, sampler),
        }
    }

    /// The BSDF at `hit` (texture applied) in a frame facing `wo`; `None`
    /// when a one-sided material is seen from its back (black, absorbing).
    /// Transmissive materials are always two-sided: seen from the back their
    /// relative index is inverted (the ray is inside the medium).
    ///
    /// `cone_width` is the width of the arriving ray's cone at the hit: the
    /// textures are filtered over it ([`crate::texture_lod`]; 0 reads
    /// level 0).
    pub(crate) fn shading<'h>(
        &self,
        hit: &'h SurfaceHit,
        wo: Vec3,
        cone_width: f32,
    ) -> Option<Shading<'h>> {
        let material = &self.scene.materials[hit.material];
        let (mut ng, mut ns) = (hit.ng, hit.ns);
        let mut bsdf = material.bsdf;
        // (A cone of width 0, as bakes start with, gives no footprint.)
        let maps = filtered_maps(material);
        let footprint = if maps.iter().any(Option::is_some) {
            Footprint::new(
                cone_width,
                wo.dot(ng),
                self.geometry.uv_area_ratio(self.scene, hit.triangle),
            )
        } else {
            Footprint(None)
        };
        // The three maps at once: where they share a layout, they share
        // the level choice and the texel positions.
        let [albedo, metallic_roughness, normal] = self
            .geometry
            .texture_levels
            .lookup_maps(self.scene, maps, hit.uvs, footprint);
        if let Some(texel) = albedo {
            bsdf = bsdf.tinted(texel);
        }
        // glTF COLOR_0 multiplies the base colour (as the texture does).
        if hit.color != Vec3::ONE {
            bsdf = bsdf.tinted(hit.color);
        }
        // glTF metallicRoughnessTexture: roughness × G, metallic × B.
        if let (Some(texel), Bsdf::MetallicRoughness(mut m)) = (metallic_roughness, bsdf) {
            m.roughness *= texel.y;
            m.metallic *= texel.z;
            bsdf = Bsdf::MetallicRoughness(m);
        }
        // glTF normalTexture: the shading normal from the map in the mesh's
        // tangent frame (kept only on the geometric normal's side).
        if let (Some(map), Some(texel)) = (material.normal_map, normal)
            && let Some(t) = self
                .geometry
                .tangent_at(self.scene, hit.triangle, hit.b1, hit.b2)
        {
            let mapped = map.perturb(texel, ns, t);
            if mapped.dot(ng) > 0.0 {
                ns = mapped;
            }
        }
        if ng.dot(wo) < 0.0 {
            if !material.double_sided && !bsdf.flags().transmission {
                return None;
            }
            ng = -ng;
            ns = -ns;
            bsdf = bsdf.seen_from_back();
        }
        let frame = Frame::from_normal(ns);
        let mut wo_local = frame.to_local(wo);
        // Shading normals can put wo below the shading hemisphere at grazing
        // angles; nudge it onto the surface's side so the BSDF stays defined.
        if wo_local.z <= 0.0 {
            wo_local.z = 1e-4;
            wo_local = wo_local.normalize();
        }
        Some(Shading {
            hit,
            frame,
            ng,
            bsdf,
            wo_local,
        })
    }

    /// Ray leaving `s` in world direction `wi` (offset to the side of `wi`).
    pub(crate) fn spawn(&self, s: &Shading, wi: Vec3, tmax: f32) -> Ray {
        let n = if wi.dot(s.ng) >= 0.0 { s.ng } else { -s.ng };
        Ray::segment(offset_ray_origin(s.hit.p, n), wi, tmax)
    }

    /// World direction `wi` is on the same side of the geometric and the
    /// shading surface (no light leaks through shading normals).
    #[inline]
    pub(crate) fn consistent_side(s: &Shading, wi: Vec3, wi_local: Vec3) -> bool {
        let g = wi.dot(s.ng);
        g != 0.0 && wi_local.z != 0.0 && (g > 0.0) == (wi_local.z > 0.0)
    }

    /// Shadow ray from `s` towards a light at `distance` along `wi`: unblocked?
    /// Triangles and analytic area lights occlude.
    pub(crate) fn visible(&self, s: &Shading, wi: Vec3, distance: f32) -> bool {
        // Stop just short of the light so the emitter itself does not occlude.
        let tmax = if distance.is_finite() {
            distance * (1.0 - 1e-4)
        } else {
            f32::INFINITY
        };
        !self.geometry.occluded(&self.spawn(s, wi, tmax))
    }

    /// Direct light at `s` from the non-delta lobes: every abstract light
    /// exactly, plus one sample of the lights with extent (emissive
    /// triangles, analytic area lights, environment). With `shadow_rays` each
    /// contribution is tested for visibility (`whitted`); without, it is the
    /// notes' local illumination (`local`).
    pub(crate) fn direct_light(
        &self,
        s: &Shading,
        sampler: &mut Sampler,
        shadow_rays: bool,
    ) -> Rgb {
        let mut sum = Rgb::ZERO;
        let mut add = |wi: Vec3, distance: f32, value: Rgb| {
            let wl = s.frame.to_local(wi);
            if !Self::consistent_side(s, wi, wl) {
                return;
            }
            let f = s.bsdf.eval(s.wo_local, wl);
            if f != Rgb::ZERO && (!shadow_rays || self.visible(s, wi, distance)) {
                sum += f * value * wl.z.abs();
            }
        };
        for l in &self.scene.lights {
            if let Some(ls) = l.light.sample_li(s.hit.p) {
                add(ls.wi, ls.distance, ls.value);
            }
        }
        let u_sel = sampler.next_1d();
        let u = sampler.next_2d();
        if let Some(c) = self
            .lights
            .sample_area(self.scene, self.geometry, s.hit.p, u_sel, u)
        {
            add(
                c.sample.wi,
                c.sample.distance,
                c.sample.value / c.select_pdf,
            );
        }
        sum
    }

    /// Radiance a mesh surface emits at `hit` towards `wo`: the material's
    /// emission times its emission texture at the hit's UV (front side
    /// only unless double-sided).
    pub(crate) fn emitted(&self, hit: &SurfaceHit, wo: Vec3) -> Rgb {
        let material = &self.scene.materials[hit.material];
        if !material.is_emissive() {
            return Rgb::ZERO;
        }
        let le = material.emission_at(&self.scene.textures, hit.uvs);
        crate::lights::emitted(le, material.double_sided, hit.ng, wo)
    }

    /// AOVs of a first hit.
    pub(crate) fn first_hit_aovs(&self, s: Option<&Shading>, hit: &SurfaceHit) -> PathSample {
        PathSample {
            radiance: Rgb::ZERO,
            albedo: s.map_or(Rgb::ZERO, |s| s.bsdf.albedo()),
            normal: s.map_or(hit.ns, |s| s.frame.n),
            depth: hit.t,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::BuildQuality;
    use glam::{Affine2, Mat4};
    use penumbra_scene::texture::Wrap;
    use penumbra_scene::{Material, Texture, primitives};
    use penumbra_shading::bsdf::MetallicRoughness;

    /// A one-texel texture of linear `rgb`.
    fn texel(rgb: Rgb) -> Texture {
        Texture {
            name: "texel".into(),
            width: 1,
            height: 1,
            texels: vec![rgb].into(),
            wrap: [Wrap::Repeat; 2],
            uv_transform: Affine2::IDENTITY,
            uv_set: 0,
        }
    }

    /// glTF's rules at a hit, by hand: base colour 0.8 × texture 0.5 =
    /// 0.4; roughness 0.8 × G 0.25 = 0.2; metallic 0.5 × B 0.5 = 0.25
    /// (R unused), whatever the cone.
    #[test]
    fn shading_applies_the_maps_by_the_gltf_rules() {
        let mut scene = Scene {
            textures: vec![texel(Rgb::splat(0.5)), texel(Rgb::new(0.9, 0.25, 0.5))],
            ..Scene::default()
        };
        let m = scene.add_material(Material {
            bsdf: Bsdf::MetallicRoughness(MetallicRoughness::new(Rgb::splat(0.8), 0.5, 0.8)),
            albedo_texture: Some(0),
            metallic_roughness_texture: Some(1),
            ..Material::lambert("textured", Rgb::ONE)
        });
        add_floor(&mut scene, m);
        with_context(&scene, |ctx| {
            let hit = floor_hit(ctx, 1.0);
            for cone in [0.0, 0.01, 5.0] {
                let s = ctx.shading(&hit, Vec3::Y, cone).expect("front side");
                let Bsdf::MetallicRoughness(mr) = s.bsdf else {
                    panic!("{:?}", s.bsdf)
                };
                assert!((mr.base_color - Rgb::splat(0.4)).abs().max_element() < 1e-6);
                assert!((mr.roughness - 0.2).abs() < 1e-6, "{}", mr.roughness);
                assert!((mr.metallic - 0.25).abs() < 1e-6, "{}", mr.metallic);
            }
        });
    }

    /// A 2 × 2 quad in the plane y = 0, front (+y) up, of material `m`.
    fn add_floor(scene: &mut Scene, m: usize) {
        let mut quad = primitives::quad(Vec3::new(-1.0, 0.0, -1.0), Vec3::Z * 2.0, Vec3::X * 2.0);
        quad.material = m;
        scene.add_mesh(quad, Mat4::IDENTITY);
    }

    /// The floor's hit by a vertical ray from y = `from_y`.
    fn floor_hit(ctx: &TraceContext, from_y: f32) -> SurfaceHit {
        let ray = Ray::segment(
            Vec3::new(0.2, from_y, 0.3),
            Vec3::new(0.0, -from_y.signum(), 0.0),
            f32::INFINITY,
        );
        ctx.geometry.intersect(ctx.scene, &ray).expect("the floor")
    }

    fn with_context(scene: &Scene, test: impl FnOnce(&TraceContext)) {
        let geometry = SceneGeometry::build(scene, BuildQuality::Fast).unwrap();
        let lights = LightSampler::new(scene, &geometry);
        let settings = RenderSettings::default();
        test(&TraceContext {
            scene,
            geometry: &geometry,
            lights: &lights,
            settings: &settings,
            camera_cone: RayCone::POINT,
        });
    }

    /// A one-sided opaque material seen from behind is black (`None`); a
    /// one-sided transmissive one is seen from behind with its normals
    /// turned towards the viewer; a two-sided one likewise.
    #[test]
    fn one_sided_materials_are_black_from_behind() {
        let scene = Scene::default();
        let one_sided = Material {
            double_sided: false,
            ..Material::lambert("one-sided", Rgb::splat(0.5))
        };
        let glass = Material {
            bsdf: Bsdf::MetallicRoughness(MetallicRoughness {
                transmission: 1.0,
                ..MetallicRoughness::new(Rgb::ONE, 0.0, 0.0)
            }),
            ..one_sided.clone()
        };
        let two_sided = Material::lambert("two-sided", Rgb::splat(0.5));
        for (material, seen_from_behind) in [(one_sided, false), (glass, true), (two_sided, true)] {
            let mut scene = scene.clone();
            let m = scene.add_material(material);
            add_floor(&mut scene, m);
            with_context(&scene, |ctx| {
                let (hit_above, hit_below) = (floor_hit(ctx, 1.0), floor_hit(ctx, -1.0));
                let above = ctx.shading(&hit_above, Vec3::Y, 0.0).unwrap();
                assert_eq!(above.ng, Vec3::Y);
                let below = ctx.shading(&hit_below, -Vec3::Y, 0.0);
                assert_eq!(below.is_some(), seen_from_behind);
                if let Some(s) = below {
                    assert_eq!(s.ng, -Vec3::Y);
                    assert!(s.wo_local.z > 0.99, "{}", s.wo_local);
                }
            });
        }
    }

    /// A direction counts only where the geometric and the shading
    /// surface agree on its side, and never along either surface.
    #[test]
    fn consistent_side_needs_both_surfaces_to_agree() {
        let mut scene = Scene::default();
        let m = scene.add_material(Material::lambert("m", Rgb::ONE));
        add_floor(&mut scene, m);
        with_context(&scene, |ctx| {
            let hit = floor_hit(ctx, 1.0);
            let s = ctx.shading(&hit, Vec3::Y, 0.0).unwrap();
            // World directions (the floor's normal is +y) and local ones
            // (the shading normal is +z).
            let (up, down, along) = (
                Vec3::new(0.3, 0.8, 0.1),
                Vec3::new(0.3, -0.8, 0.1),
                Vec3::new(0.6, 0.0, 0.8),
            );
            let (l_up, l_down, l_along) = (
                Vec3::new(0.3, 0.1, 0.8),
                Vec3::new(0.3, 0.1, -0.8),
                Vec3::new(0.6, 0.8, 0.0),
            );
            for (wi, local, expected) in [
                (up, l_up, true),
                (down, l_down, true),
                (up, l_down, false),
                (down, l_up, false),
                (along, l_up, false),
                (along, l_down, false),
                (up, l_along, false),
                (down, l_along, false),
            ] {
                assert_eq!(
                    TraceContext::consistent_side(&s, wi, local.normalize()),
                    expected,
                    "world {wi}, local {local}"
                );
            }
        });
    }

    /// Russian roulette keeps a path with probability max(β) · Πη², at
    /// most 0.95 (by hand): β 0.3 inside glass (η² = 2.25) → 0.675.
    #[test]
    fn roulette_undoes_the_refraction_scaling() {
        use super::path::rr_survival;
        assert!((rr_survival(Rgb::new(0.1, 0.3, 0.2), 2.25) - 0.675).abs() < 1e-6);
        assert!((rr_survival(Rgb::new(0.1, 0.3, 0.2), 1.0) - 0.3).abs() < 1e-6);
        assert_eq!(rr_survival(Rgb::splat(0.5), 2.25), 0.95);
    }

    /// `scatter` through glass multiplies the η² product by η² = 2.25 on
    /// the way in; roulette spares the first four segments and then keeps
    /// a path of throughput 10⁻³ about once in a thousand, dividing its
    /// throughput by that probability.
    #[test]
    fn scatter_tracks_refraction_and_plays_roulette_late() {
        use super::path::scatter;
        use penumbra_shading::bsdf::Dielectric;
        use penumbra_shading::sampling::Sampler;
        for (material, glass) in [
            (
                Material {
                    bsdf: Bsdf::Dielectric(Dielectric::glass()),
                    ..Material::lambert("glass", Rgb::ONE)
                },
                true,
            ),
            (Material::lambert("white", Rgb::ONE), false),
        ] {
            let mut scene = Scene::default();
            let m = scene.add_material(material);
            add_floor(&mut scene, m);
            with_context(&scene, |ctx| {
                let hit = floor_hit(ctx, 1.0);
                let s = ctx.shading(&hit, Vec3::Y, 0.0).unwrap();
                let (mut refracted, mut late) = (0, 0);
                let n = 4000;
                for i in 0..n {
                    let mut sampler = Sampler::new(1, 2, i, 7);
                    // Segments up to the fourth are spared, however dim.
                    let dim = Rgb::splat(1e-3);
                    let u_lobe = sampler.next_1d();
                    let next = scatter(ctx, &s, &mut sampler, u_lobe, dim, 1.0, 3, RayCone::POINT)
                        .expect("no roulette on the fourth segment");
                    if next.ray.direction.y < 0.0 {
                        assert!((next.eta_scale - 2.25).abs() < 1e-5, "{}", next.eta_scale);
                        refracted += 1;
                    } else {
                        assert_eq!(next.eta_scale, 1.0);
                    }
                    let mut sampler = Sampler::new(1, 2, i, 7);
                    let beta = Rgb::splat(1e-3);
                    let u_lobe = sampler.next_1d();
                    if let Some(next) =
                        scatter(ctx, &s, &mut sampler, u_lobe, beta, 1.0, 9, RayCone::POINT)
                    {
                        late += 1;
                        if !glass {
                            // White Lambert: weight 1, then / q = 10⁻³.
                            assert!((next.beta.x - 1.0).abs() < 1e-4, "{}", next.beta);
                        }
                    }
                }
                assert_eq!(refracted > n / 2, glass, "{refracted} of {n} refracted");
                // q = 10⁻³ (up to 2.25 · 10⁻³ inside glass): a handful of
                // 4000 survive.
                assert!(late <= 30, "{late} of {n} survived roulette at depth 10");
            });
        }
    }
}
