//! `penumbra merge`: adds the partial films of a split render into its image.

use crate::commands::partial::read_parts;
use crate::commands::render::ToneArg;
use anyhow::{Context, Result};
use clap::Args;
use penumbra_image::{Exposure, ToneMapping, merge_parts, write_image};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct MergeArgs {
    /// Partial films (.exr) written by `penumbra render --samples/--crop`,
    /// in any order.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// Output image: .exr (linear float RGB) or .png (tone-mapped sRGB).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Exposure before tone mapping (PNG only): auto or a number of stops,
    /// as for `render`.
    #[arg(long, default_value = "auto", allow_negative_numbers = true)]
    pub exposure: Exposure,
    /// Tone-mapping operator for PNG output.
    #[arg(long, value_enum, default_value_t = ToneArg::Filmic)]
    pub tonemap: ToneArg,
}

pub fn run(args: MergeArgs) -> Result<()> {
    penumbra_image::check_output_path(&args.output)?;
    let parts = read_parts(&args.parts)?;
    let merged = merge_parts(&parts)?;
    let image = merged.film.mean();
    let tm = ToneMapping {
        exposure_ev: args.exposure.resolve(&image, None),
        operator: args.tonemap.operator(),
    };
    write_image(&args.output, &image, &[], &tm)
        .with_context(|| format!("writing {}", args.output.display()))?;
    let rejected = merged.film.rejected_samples();
    eprintln!(
        "penumbra: merged {} parts: {}x{} at {} spp{} -> {}",
        parts.len(),
        merged.image_width,
        merged.image_height,
        merged.spp,
        if rejected > 0 {
            format!(" ({rejected} non-finite or huge samples left out)")
        } else {
            String::new()
        },
        args.output.display()
    );
    Ok(())
}
