//! `penumbra merge`: adds the partial films of a split render into its image.

use crate::commands::partial::read_parts;
use crate::commands::render::ToneArg;
use anyhow::{Context, Result};
use clap::Args;
use penumbra_image::{Exposure, ToneMapping, ToneOperator, merge_parts, write_image};
use std::path::{Path, PathBuf};

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
    let tm = (args.exposure, args.tonemap.operator());
    merge_files(&args.parts, &args.output, tm)
}

/// Reads the partial films `parts`, checks that they make one render, adds
/// them, writes the image to `output` (exposure and operator for a PNG) and
/// says so. `penumbra merge` and `penumbra farm merge` both end here.
pub fn merge_files(
    parts: &[PathBuf],
    output: &Path,
    (exposure, operator): (Exposure, ToneOperator),
) -> Result<()> {
    let parts = read_parts(parts)?;
    let merged = merge_parts(&parts)?;
    let image = merged.film.mean();
    let tm = ToneMapping {
        exposure_ev: exposure.resolve(&image, None),
        operator,
    };
    write_image(output, &image, &[], &tm)
        .with_context(|| format!("writing {}", output.display()))?;
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
        output.display()
    );
    Ok(())
}
