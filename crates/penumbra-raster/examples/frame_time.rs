//! Frame times of the forward pass: renders a scene N times with one
//! context and pipeline and prints the cold (first) and warm (median) times.
//!
//! `cargo run -p penumbra-raster --example frame_time -- SCENE [WxH] [MSAA] [N]`

use penumbra_raster::{ForwardRenderer, GpuContext, RasterOptions};
use penumbra_scene::{LoadOptions, load_scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args
        .first()
        .ok_or("usage: frame_time SCENE [WxH] [MSAA] [N]")?;
    let (w, h) = match args.get(1) {
        Some(r) => {
            let (w, h) = r.split_once('x').ok_or("resolution is WxH")?;
            (w.parse()?, h.parse()?)
        }
        None => (1920, 1080),
    };
    let msaa = args.get(2).map_or(Ok(1), |s| s.parse())?;
    let n: usize = args.get(3).map_or(Ok(10), |s| s.parse())?;
    let scene = load_scene(std::path::Path::new(path), &LoadOptions::default())?;
    let camera = penumbra_trace::scene_camera(&scene);
    let ctx = GpuContext::new()?;
    let renderer = ForwardRenderer::new(
        &ctx,
        RasterOptions {
            msaa,
            ..Default::default()
        },
    )?;
    let mut frame = Vec::new();
    let mut gpu = Vec::new();
    for _ in 0..n.max(1) {
        let out = renderer.render(&ctx, &scene, &camera, w, h)?;
        frame.push(out.frame_ms);
        gpu.extend(penumbra_raster::total_ms(&out.passes, "forward"));
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied()
    };
    let cold = frame[0];
    let mut warm: Vec<f64> = frame[1..].to_vec();
    println!(
        "{} | {w}x{h} MSAA {msaa} | {} triangles, {} lights | cold frame {cold:.1} ms | warm median frame {:.1} ms | forward pass (GPU timestamps, median) {:.1} ms",
        ctx.summary,
        scene.triangle_count(),
        scene.lights.len(),
        median(&mut warm).unwrap_or(cold),
        median(&mut gpu).unwrap_or(f64::NAN)
    );
    Ok(())
}
