//! Shadow-map views of the abstract lights: an orthographic view fitted to
//! the scene bounds for directional lights, a perspective view around the
//! outer cone for spot lights, and six 90° cube faces for point lights.

use crate::gpu::{GpuLight, GpuShadow, GpuShadowView, LIGHT_DIRECTIONAL, LIGHT_SPOT};
use glam::{Mat4, Vec3, Vec4};

/// Constant part of the shadow passes' depth bias, in units of the depth
/// format's precision at the triangle's depth.
pub(crate) const SHADOW_CONSTANT_BIAS: i32 = 16;

/// Default edge of a shadow map in texels.
pub const DEFAULT_SHADOW_MAP_SIZE: u32 = 2048;
/// Default slope-scaled depth bias of the shadow passes, in units of the
/// depth slope of the occluder's triangle per texel (rasteriser state).
pub const DEFAULT_SLOPE_BIAS: f32 = 1.5;
/// Default normal offset of the shadow lookup, in shadow-map texels.
pub const DEFAULT_NORMAL_OFFSET: f32 = 1.0;

/// Right-handed world-to-view transform of an eye at `eye` looking along
/// `dir` (view −z) with `up` roughly view +y.
fn look_to(eye: Vec3, dir: Vec3, up: Vec3) -> Mat4 {
    let f = dir.normalize();
    let s = f.cross(up).normalize();
    let u = s.cross(f);
    Mat4::from_cols(
        Vec4::new(s.x, u.x, -f.x, 0.0),
        Vec4::new(s.y, u.y, -f.y, 0.0),
        Vec4::new(s.z, u.z, -f.z, 0.0),
        Vec4::new(-s.dot(eye), -u.dot(eye), f.dot(eye), 1.0),
    )
}

/// The shadow-map views of the frame's lights: one [`GpuShadow`] per light
/// and one [`GpuShadowView`] per layer of the shadow-map array.
///
/// Every view stores reversed depth (1 near the light). Directional lights:
/// an orthographic view along the light fitted to the eight corners of the
/// scene bounds. Spot lights: an infinite reversed perspective along the
/// spot axis whose square frustum contains the outer cone (a cone wider than
/// 170° is clamped to 170°). Point lights: six 90° faces looking along ±x,
/// ±y, ±z (a depth "cube" stored as six array layers with their own
/// view-projections; the shader picks the face of the major axis); the far
/// fields of area lights like point lights. The
/// perspective frusta are widened by the PCF kernel's half-width plus a
/// texel so that taps near a face edge stay inside the face.
pub fn shadow_views(
    lights: &[GpuLight],
    bounds: (Vec3, Vec3),
    size: u32,
    pcf: u32,
    normal_offset: f32,
) -> (Vec<GpuShadow>, Vec<GpuShadowView>) {
    let (lo, hi) = bounds;
    let centre = 0.5 * (lo + hi);
    let radius = (0.5 * (hi - lo).length()).max(1e-4);
    let size_f = size as f32;
    let margin = (pcf / 2 + 1) as f32;
    let widen = size_f / (size_f - 2.0 * margin).max(1.0);
    let mut shadows = Vec::with_capacity(lights.len());
    let mut views = Vec::new();
    let up_for = |axis: Vec3| {
        if axis.y.abs() > 0.99 {
            Vec3::Z
        } else {
            Vec3::Y
        }
    };
    // Reversed infinite perspective (depth = near / distance along the axis).
    let perspective = |pos: Vec3, axis: Vec3, tan_half: f32| {
        let near = radius * 1e-4;
        let f = 1.0 / tan_half;
        let proj = Mat4::from_cols(
            Vec4::new(f, 0.0, 0.0, 0.0),
            Vec4::new(0.0, f, 0.0, 0.0),
            Vec4::new(0.0, 0.0, 0.0, -1.0),
            Vec4::new(0.0, 0.0, near, 0.0),
        );
        GpuShadowView {
            view_proj: (proj * look_to(pos, axis, up_for(axis))).to_cols_array_2d(),
            axis: axis.extend(0.0).to_array(),
        }
    };
    for l in lights {
        let first_layer = views.len() as u32;
        let mut sh = GpuShadow {
            first_layer,
            pcf,
            normal_offset,
            map_size: size_f,
            ..GpuShadow::default()
        };
        let position = l.xyz();
        match l.kind {
            LIGHT_DIRECTIONAL => {
                // The homogeneous position points towards the light.
                let axis = -position.normalize();
                let eye = centre - axis * (2.0 * radius);
                let view = look_to(eye, axis, up_for(axis));
                let mut vlo = Vec3::splat(f32::INFINITY);
                let mut vhi = Vec3::splat(f32::NEG_INFINITY);
                for i in 0..8 {
                    let c = Vec3::new(
                        if i & 1 == 0 { lo.x } else { hi.x },
                        if i & 2 == 0 { lo.y } else { hi.y },
                        if i & 4 == 0 { lo.z } else { hi.z },
                    );
                    let v = view.transform_point3(c);
                    vlo = vlo.min(v);
                    vhi = vhi.max(v);
                }
                // A square texel grid over the fitted rectangle, a margin of
                // the PCF half-width around it.
                let extent = (vhi.x - vlo.x).max(vhi.y - vlo.y).max(1e-4) * widen;
                let mid = 0.5 * (vlo + vhi);
                let pad = 1e-3 * radius;
                let (zn, zf) = (vhi.z + pad, vlo.z - pad);
                let s = 2.0 / extent;
                let proj = Mat4::from_cols(
                    Vec4::new(s, 0.0, 0.0, 0.0),
                    Vec4::new(0.0, s, 0.0, 0.0),
                    Vec4::new(0.0, 0.0, 1.0 / (zn - zf), 0.0),
                    Vec4::new(-s * mid.x, -s * mid.y, -zf / (zn - zf), 1.0),
                );
                views.push(GpuShadowView {
                    view_proj: (proj * view).to_cols_array_2d(),
                    axis: axis.extend(0.0).to_array(),
                });
                sh.layer_count = 1;
                sh.texel = extent / size_f;
            }
            LIGHT_SPOT => {
                let c = l.cos_outer.clamp(85f32.to_radians().cos(), 1.0 - 1e-6);
                let tan_half = (1.0 - c * c).sqrt() / c * widen;
                let axis = Vec3::from(l.spot_direction).normalize();
                views.push(perspective(position, axis, tan_half));
                sh.layer_count = 1;
                sh.perspective = 1;
                sh.texel = 2.0 * tan_half / size_f;
            }
            // Point lights and the far fields of area lights.
            _ => {
                for axis in [
                    Vec3::X,
                    Vec3::NEG_X,
                    Vec3::Y,
                    Vec3::NEG_Y,
                    Vec3::Z,
                    Vec3::NEG_Z,
                ] {
                    views.push(perspective(position, axis, widen));
                }
                sh.layer_count = 6;
                sh.perspective = 1;
                sh.texel = 2.0 * widen / size_f;
            }
        }
        shadows.push(sh);
    }
    (shadows, views)
}

/// One frame's shadow-map array and the per-light lookup data.
pub(crate) struct ShadowMapFrame {
    texture: wgpu::Texture,
    pub array_view: wgpu::TextureView,
    pub shadows: wgpu::Buffer,
    pub views: wgpu::Buffer,
    pub layers: u32,
}

impl ShadowMapFrame {
    /// The views of `lights` (none when `enabled` is false: a 1×1 dummy
    /// array and unshadowed lights).
    pub fn new(
        device: &wgpu::Device,
        enabled: bool,
        lights: &[GpuLight],
        bounds: (Vec3, Vec3),
        size: u32,
        pcf: u32,
        normal_offset: f32,
    ) -> Result<Self, crate::GpuError> {
        let (mut shadows, mut views) = if enabled {
            shadow_views(lights, bounds, size, pcf, normal_offset)
        } else {
            (Vec::new(), Vec::new())
        };
        let layers = views.len() as u32;
        let max_layers = device.limits().max_texture_array_layers;
        if layers > max_layers {
            return Err(crate::GpuError::Unsupported(format!(
                "{layers} shadow-map layers (the adapter allows {max_layers}; a point light takes 6)"
            )));
        }
        shadows.resize(lights.len().max(1), GpuShadow::default());
        if views.is_empty() {
            views.push(GpuShadowView::default());
        }
        let map_size = if layers > 0 { size } else { 1 };
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow maps"),
            size: wgpu::Extent3d {
                width: map_size,
                height: map_size,
                depth_or_array_layers: layers.max(1),
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: SHADOW_MAP_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let array_view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let storage = wgpu::BufferUsages::STORAGE;
        Ok(Self {
            array_view,
            shadows: crate::scene_gpu::buffer_init(
                device,
                "shadows",
                bytemuck::cast_slice(&shadows),
                storage,
            ),
            views: crate::scene_gpu::buffer_init(
                device,
                "shadow views",
                bytemuck::cast_slice(&views),
                storage,
            ),
            texture,
            layers,
        })
    }

    /// Records one depth pass per layer: every instance through the layer's
    /// view (instance index = layer · instance count + instance), with the
    /// pipeline `pipeline` gives (asked for only when there is a layer).
    pub fn record<'p>(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: impl FnOnce() -> &'p wgpu::RenderPipeline,
        bind_group: &wgpu::BindGroup,
        gpu: &crate::scene_gpu::SceneGpu,
        timer: &crate::timing::GpuTimer,
    ) {
        if self.layers == 0 {
            return;
        }
        let pipeline = pipeline();
        for layer in 0..self.layers {
            let view = self.texture.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2),
                base_array_layer: layer,
                array_layer_count: Some(1),
                ..Default::default()
            });
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow map"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(0.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.render_pass(&format!("shadow map {layer}")),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, bind_group, &[]);
            gpu.draw_casters(&mut pass, false, layer * gpu.instance_count);
        }
    }
}

/// Depth format of the shadow maps.
pub(crate) const SHADOW_MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

#[cfg(test)]
mod tests {
    use super::*;

    fn project(v: &GpuShadowView, p: Vec3) -> Vec3 {
        let c = Mat4::from_cols_array_2d(&v.view_proj) * p.extend(1.0);
        c.truncate() / c.w
    }

    #[test]
    fn shadow_views_cover_the_scene_and_the_cones() {
        use penumbra_shading::light::{DirectionalLight, Light, PointLight, SpotLight};
        let bounds = (Vec3::new(-3.0, 0.0, -2.0), Vec3::new(4.0, 2.0, 5.0));
        let spot = SpotLight {
            position: Vec3::new(0.0, 5.0, 0.0),
            direction: Vec3::new(0.3, -1.0, 0.1).normalize(),
            intensity: Vec3::ONE,
            cos_inner: 0.95,
            cos_outer: 0.8,
            range: f32::INFINITY,
        };
        let lights = [
            Light::Directional(DirectionalLight {
                direction: Vec3::new(0.5, -1.0, 0.2).normalize(),
                irradiance: Vec3::ONE,
            }),
            Light::Spot(spot),
            Light::Point(PointLight {
                position: Vec3::new(1.0, 3.0, 1.0),
                intensity: Vec3::ONE,
                range: f32::INFINITY,
            }),
        ]
        .map(|light| GpuLight::from_light(&light));
        let (sh, views) = shadow_views(&lights, bounds, 1024, 3, 1.0);
        assert_eq!(views.len(), 8);
        let layers: Vec<_> = sh.iter().map(|s| (s.first_layer, s.layer_count)).collect();
        assert_eq!(layers, [(0, 1), (1, 1), (2, 6)]);
        // Directional: every corner of the bounds inside the map, depth in
        // [0, 1], nearer the light = larger (reversed) depth.
        let (lo, hi) = bounds;
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            let n = project(&views[0], c);
            assert!(n.x.abs() < 1.0 && n.y.abs() < 1.0, "{n}");
            assert!(n.z > 0.0 && n.z < 1.0, "{n}");
        }
        let d = Vec3::new(0.5, -1.0, 0.2).normalize();
        let centre = 0.5 * (lo + hi);
        assert!(project(&views[0], centre - d).z > project(&views[0], centre + d).z);
        // Spot: directions on the outer cone project inside the map.
        let frame = frame_of(spot.direction);
        let sin = (1.0 - spot.cos_outer * spot.cos_outer).sqrt();
        for k in 0..16 {
            let a = k as f32 * std::f32::consts::TAU / 16.0;
            let w = spot.cos_outer * spot.direction + sin * (a.cos() * frame.0 + a.sin() * frame.1);
            let n = project(&views[1], spot.position + 2.0 * w);
            assert!(n.x.abs() < 1.0 && n.y.abs() < 1.0, "{n}");
        }
        // Point: every direction lands inside the face of its major axis.
        let pos = Vec3::new(1.0, 3.0, 1.0);
        for w in [
            Vec3::new(0.9, 0.89, -0.5),
            Vec3::new(-1.0, 0.2, 0.99),
            Vec3::new(0.1, 1.0, 0.3),
            Vec3::new(0.5, -1.0, -0.9),
            Vec3::new(0.2, 0.3, 1.0),
            Vec3::new(-0.99, 0.1, -1.0),
        ] {
            let a = w.abs();
            let face = if a.x >= a.y && a.x >= a.z {
                if w.x >= 0.0 { 0 } else { 1 }
            } else if a.y >= a.z {
                if w.y >= 0.0 { 2 } else { 3 }
            } else if w.z >= 0.0 {
                4
            } else {
                5
            };
            let n = project(&views[2 + face], pos + w);
            assert!(n.x.abs() < 1.0 && n.y.abs() < 1.0, "{w}: {n}");
            assert!(n.z > 0.0 && n.z < 1.0, "{w}: {n}");
        }
    }

    fn frame_of(n: Vec3) -> (Vec3, Vec3) {
        let t = n
            .cross(if n.x.abs() < 0.9 { Vec3::X } else { Vec3::Y })
            .normalize();
        (t, n.cross(t))
    }
}
