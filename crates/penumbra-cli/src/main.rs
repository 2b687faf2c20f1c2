//! `penumbra`: render scenes, inspect them, compare images and benchmark.

mod commands;
mod options;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Large allocations on transparent huge pages (fewer page faults: the
/// 1M-triangle BVH build's temporary arrays, images, the tree itself).
#[global_allocator]
static ALLOCATOR: penumbra_trace::accel::HugePageAllocator =
    penumbra_trace::accel::HugePageAllocator;

#[derive(Parser, Debug)]
#[command(
    name = "penumbra",
    version,
    about = "A physically based renderer: path tracing, direct and local illumination, ambient occlusion"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene (glTF, OBJ or TOML) to PNG or EXR. Without SCENE, renders the built-in Cornell box.
    Render(commands::render::RenderArgs),
    /// Print what a scene file contains: counts, bounds, lights and their power, warnings.
    Info(commands::info::InfoArgs),
    /// Add the partial films of a split render (`render --samples/--crop`) into its image, checking that they fit together.
    Merge(commands::merge::MergeArgs),
    /// Split a render into tasks for a scheduler (Slurm job array, Kubernetes Indexed Job), run a task, merge the parts, show their status.
    Farm(commands::farm::FarmArgs),
    /// Compare a test image with a reference: RMSE, relMSE, PSNR and HDR-FLIP.
    Compare(commands::compare::CompareArgs),
    /// Precompute ambient occlusion, irradiance light maps or radiosity into a light-map atlas.
    Bake(commands::bake::BakeArgs),
    /// Render a scene with every technique and report each one's error against the path-traced truth and its cost (HTML, JSON, CSV).
    Study(commands::study::StudyArgs),
    /// Measure BVH build and ray-tracing throughput, and path-tracing speed.
    Bench(commands::bench::BenchArgs),
}

/// Restores the default action of SIGPIPE, which Rust's runtime ignores:
/// `penumbra info scene.gltf | head` then ends quietly when `head` stops
/// reading, as other command-line tools do, instead of panicking in the
/// next `println!`.
#[cfg(unix)]
#[allow(unsafe_code)]
fn end_quietly_on_a_closed_pipe() {
    // SAFETY: called first in `main`, before any other thread exists;
    // setting a signal's action to SIG_DFL has no other precondition.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn main() -> ExitCode {
    #[cfg(unix)]
    end_quietly_on_a_closed_pipe();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(a) => commands::render::run(a),
        Command::Info(a) => commands::info::run(a),
        Command::Compare(a) => commands::compare::run(a),
        Command::Merge(a) => commands::merge::run(a),
        Command::Farm(a) => commands::farm::run(a),
        Command::Bench(a) => commands::bench::run(a),
        Command::Bake(a) => commands::bake::run(a),
        Command::Study(a) => commands::study::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("penumbra: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
