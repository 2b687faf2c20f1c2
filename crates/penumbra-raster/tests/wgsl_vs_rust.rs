//! The WGSL twins against the Rust models: a compute shader evaluates the
//! WGSL Lambert, every Phong–Blinn variant, the point, directional and spot
//! lights (with and without a range) and the far fields of area lights on
//! random inputs (≥ 10⁴ each, 5000 per light kind); every component must be
//! within relative 1e-4 or absolute 1e-6 of `Bsdf::eval` /
//! `Light::sample_li` / `FarField::sample_li`.

mod common;

use common::{BrdfCase, LightCase, LightIncidence, close};
use glam::Vec3;
use penumbra_raster::gpu::{GpuLight, MODEL_LAMBERT, MODEL_PHONG_BLINN, phong_variant_index};
use penumbra_raster::shaders::with_library;
use penumbra_raster::{GpuContext, map_read};
use penumbra_shading::bsdf::{Bsdf, Lambert, PhongBlinn, PhongVariant};
use penumbra_shading::light::{
    AreaLight, DirectionalLight, FarField, Light, PointLight, Shape, SpotLight,
};
use penumbra_shading::stats::TestRng;
use wgpu::util::DeviceExt;

const CASES: usize = 20_000;

fn unit(rng: &mut TestRng) -> Vec3 {
    loop {
        let v = Vec3::new(
            2.0 * rng.next_f32() - 1.0,
            2.0 * rng.next_f32() - 1.0,
            2.0 * rng.next_f32() - 1.0,
        );
        let l2 = v.length_squared();
        if l2 > 1e-4 && l2 <= 1.0 {
            return v / l2.sqrt();
        }
    }
}

fn colour(rng: &mut TestRng, scale: f32) -> Vec3 {
    Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * scale
}

/// Runs `entry` over `input` (binding 0 or 2) and returns `count` outputs.
fn dispatch<T: bytemuck::Pod>(
    ctx: &GpuContext,
    entry: &str,
    input: &[u8],
    count: usize,
    input_binding: u32,
) -> Vec<T> {
    let device = &ctx.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("twins"),
        source: wgpu::ShaderSource::Wgsl(with_library(common::KERNELS_WGSL).into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: None,
        module: &module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    });
    let out_size = (count * size_of::<T>()) as u64;
    let input_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("input"),
        contents: input,
        usage: wgpu::BufferUsages::STORAGE,
    });
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("output"),
        size: out_size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let read = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read"),
        size: out_size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: input_binding,
                resource: input_buf.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: input_binding + 1,
                resource: output.as_entire_binding(),
            },
        ],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(count.div_ceil(64) as u32, 1, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &read, 0, out_size);
    ctx.queue.submit([encoder.finish()]);
    let bytes = map_read(ctx, &read).expect("readback");
    bytemuck::cast_slice(&bytes).to_vec()
}

#[test]
fn wgsl_brdfs_match_rust() {
    let Some(ctx) = common::gpu("wgsl_brdfs_match_rust") else {
        return;
    };
    let mut rng = TestRng::new(7);
    let mut cases = Vec::with_capacity(CASES);
    let mut models = Vec::with_capacity(CASES);
    for i in 0..CASES {
        // Mostly both directions above the surface; some below.
        let mut wo = unit(&mut rng);
        let mut wi = unit(&mut rng);
        if rng.next_f32() < 0.85 {
            wo.z = wo.z.abs();
            wi.z = wi.z.abs();
        }
        let kd = colour(&mut rng, std::f32::consts::FRAC_1_PI);
        let ks = colour(&mut rng, 1.0);
        let shininess = match i % 5 {
            0 => 0.0,
            1 => (rng.next_f32() * 8.0).floor(),
            _ => rng.next_f32() * 200.0,
        };
        let (bsdf, model, variant) = if i % 5 == 4 {
            (Bsdf::Lambert(Lambert::from_kd(kd)), MODEL_LAMBERT, 0)
        } else {
            let v = PhongVariant::ALL[i % 4];
            (
                Bsdf::PhongBlinn(PhongBlinn::new(kd, ks, shininess, v)),
                MODEL_PHONG_BLINN,
                phong_variant_index(v),
            )
        };
        let gpu_kd = match bsdf {
            Bsdf::Lambert(l) => l.kd(),
            _ => kd,
        };
        cases.push(BrdfCase {
            wo: wo.to_array(),
            shininess,
            wi: wi.to_array(),
            model,
            kd: gpu_kd.to_array(),
            variant,
            ks: ks.to_array(),
            _pad0: 0.0,
        });
        models.push(bsdf);
    }
    let out: Vec<[f32; 4]> = dispatch(&ctx, "eval_brdf", bytemuck::cast_slice(&cases), CASES, 0);
    let mut worst = 0f32;
    let mut counts = [0usize; 5];
    for (i, (c, bsdf)) in cases.iter().zip(&models).enumerate() {
        let cpu = bsdf.eval(Vec3::from(c.wo), Vec3::from(c.wi));
        let g = Vec3::new(out[i][0], out[i][1], out[i][2]);
        for k in 0..3 {
            assert!(
                close(g[k], cpu[k]),
                "case {i} ({bsdf:?}, wo {:?}, wi {:?}): GPU {g:?} vs Rust {cpu:?}",
                c.wo,
                c.wi
            );
            if cpu[k].abs() > 1e-6 {
                worst = worst.max((g[k] - cpu[k]).abs() / cpu[k].abs());
            }
        }
        if cpu.max_element() > 0.0 {
            counts[if c.model == MODEL_LAMBERT {
                4
            } else {
                c.variant as usize
            }] += 1;
        }
    }
    eprintln!(
        "BRDF cases: {CASES}, non-zero per variant/Lambert {counts:?}, worst relative error {worst:.3e}"
    );
    // Every model was exercised with non-zero values.
    assert!(counts.iter().all(|&n| n > 1000), "{counts:?}");
}

/// A light the raster path evaluates: an abstract light or the far field of
/// an area light.
#[derive(Debug)]
enum TestLight {
    Abstract(Light),
    Area(FarField),
}

impl TestLight {
    fn gpu(&self) -> GpuLight {
        match self {
            TestLight::Abstract(l) => GpuLight::from_light(l),
            TestLight::Area(f) => GpuLight::from_far_field(f),
        }
    }

    fn sample_li(&self, p: Vec3) -> Option<penumbra_shading::light::LightSample> {
        match self {
            TestLight::Abstract(l) => l.sample_li(p),
            TestLight::Area(f) => f.sample_li(p),
        }
    }

    fn range(&self) -> f32 {
        match self {
            TestLight::Abstract(l) => l.range(),
            TestLight::Area(_) => f32::INFINITY,
        }
    }
}

#[test]
fn wgsl_lights_match_rust() {
    let Some(ctx) = common::gpu("wgsl_lights_match_rust") else {
        return;
    };
    let mut rng = TestRng::new(11);
    let mut cases = Vec::with_capacity(CASES);
    let mut lights = Vec::with_capacity(CASES);
    let pos = |rng: &mut TestRng| colour(rng, 10.0) - Vec3::splat(5.0);
    // Half the point and spot lights are cut off at a range of 2 to 14.
    let range = |rng: &mut TestRng| {
        if rng.next_f32() < 0.5 {
            f32::INFINITY
        } else {
            2.0 + 12.0 * rng.next_f32()
        }
    };
    for i in 0..CASES {
        let p = pos(&mut rng);
        let light = match i % 4 {
            0 => TestLight::Abstract(Light::Point(PointLight {
                position: pos(&mut rng),
                intensity: colour(&mut rng, 100.0),
                range: range(&mut rng),
            })),
            1 => TestLight::Abstract(Light::Directional(DirectionalLight {
                // Not necessarily unit: the light normalises it.
                direction: unit(&mut rng) * (0.5 + rng.next_f32()),
                irradiance: colour(&mut rng, 10.0),
            })),
            3 => {
                // An area light's far field: sphere, disk or quad, one- or
                // two-sided.
                let centre = pos(&mut rng);
                let n = unit(&mut rng);
                let shape = match rng.next_u64() % 3 {
                    0 => Shape::Sphere {
                        center: centre,
                        radius: 0.1 + rng.next_f32(),
                    },
                    1 => Shape::Disk {
                        center: centre,
                        normal: n,
                        radius: 0.1 + rng.next_f32(),
                    },
                    _ => {
                        let e1 = unit(&mut rng).cross(n) * (0.2 + rng.next_f32());
                        Shape::Quad {
                            corner: centre,
                            edge1: e1,
                            edge2: n.cross(e1).normalize() * (0.2 + rng.next_f32()),
                        }
                    }
                };
                TestLight::Area(
                    AreaLight {
                        shape,
                        radiance: colour(&mut rng, 20.0),
                        two_sided: rng.next_f32() < 0.5,
                    }
                    .far_field(),
                )
            }
            _ => {
                let position = pos(&mut rng);
                // Half the spots point roughly at p, so that the cone and
                // its falloff band are well covered.
                let direction = if rng.next_f32() < 0.5 {
                    ((p - position).normalize() + unit(&mut rng) * 0.4).normalize()
                } else {
                    unit(&mut rng)
                };
                let cos_outer = rng.next_f32() * 0.99;
                let cos_inner = cos_outer + (1.0 - cos_outer) * rng.next_f32();
                TestLight::Abstract(Light::Spot(SpotLight {
                    position,
                    direction,
                    intensity: colour(&mut rng, 100.0),
                    cos_inner,
                    cos_outer,
                    range: range(&mut rng),
                }))
            }
        };
        cases.push(LightCase {
            light: light.gpu(),
            p: p.to_array(),
            _pad0: 0.0,
        });
        lights.push(light);
    }
    let out: Vec<LightIncidence> =
        dispatch(&ctx, "eval_light", bytemuck::cast_slice(&cases), CASES, 2);
    let mut lit = [0usize; 4];
    let mut falloff_band = 0;
    let mut window_band = 0;
    for (i, (c, light)) in cases.iter().zip(&lights).enumerate() {
        let g = out[i];
        let cpu = light.sample_li(Vec3::from(c.p));
        // A light that does not reach p contributes zero: compare values
        // with None as zero, directions and distances where both reach.
        let cpu_value = cpu.map_or(Vec3::ZERO, |s| s.value);
        let gpu_value = if g.valid != 0 {
            Vec3::from(g.value)
        } else {
            Vec3::ZERO
        };
        for k in 0..3 {
            assert!(
                close(gpu_value[k], cpu_value[k]),
                "case {i} ({light:?} at {:?}): GPU value {gpu_value:?} vs Rust {cpu_value:?}",
                c.p
            );
        }
        if let (Some(s), true) = (cpu, g.valid != 0) {
            for k in 0..3 {
                assert!(
                    close(g.wi[k], s.wi[k]),
                    "case {i}: GPU wi {:?} vs Rust {:?}",
                    g.wi,
                    s.wi
                );
            }
            assert!(
                (g.distance.is_infinite() && s.distance.is_infinite())
                    || close(g.distance, s.distance),
                "case {i}: GPU distance {} vs Rust {}",
                g.distance,
                s.distance
            );
            lit[i % 4] += 1;
            let w = penumbra_shading::light::range_window(s.distance, light.range());
            if w > 0.0 && w < 1.0 {
                window_band += 1;
            }
            if let TestLight::Abstract(Light::Spot(sp)) = light {
                let f = sp.falloff(-s.wi);
                if f > 0.0 && f < 1.0 {
                    falloff_band += 1;
                }
            }
        }
    }
    eprintln!(
        "light cases: {CASES}, reaching p per kind {lit:?}, spot falloff band {falloff_band}, range window band {window_band}"
    );
    assert!(
        lit[0] > 3000 && lit[1] > 4500 && lit[2] > 500 && lit[3] > 2500,
        "{lit:?}"
    );
    assert!(window_band > 1500, "{window_band}");
    assert!(falloff_band > 300, "{falloff_band}");
}
