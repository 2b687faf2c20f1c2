//! `penumbra compare`.

use anyhow::{Context, Result};
use clap::Args;
use penumbra_image::{
    ToneMapping, ToneOperator, check_output_path, compare, flip_heatmap, hdr_flip, read_image,
    write_image,
};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct CompareArgs {
    /// Reference image (.exr, .hdr, .png).
    pub reference: PathBuf,
    /// Image to evaluate.
    pub test: PathBuf,
    /// Write the FLIP error map as a colour-mapped PNG.
    #[arg(long)]
    pub heatmap: Option<PathBuf>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: CompareArgs) -> Result<()> {
    if let Some(h) = &args.heatmap {
        check_output_path(h)?;
    }
    let reference = read_image(&args.reference)?;
    let test = read_image(&args.test)?;
    let m = compare(&reference, &test).with_context(|| {
        format!(
            "comparing {} with {}",
            args.test.display(),
            args.reference.display()
        )
    })?;
    if args.json {
        println!(
            "{{\"rmse\":{},\"rel_mse\":{},\"psnr\":{},\"flip\":{}}}",
            m.rmse, m.rel_mse, m.psnr, m.flip
        );
    } else {
        println!("RMSE    {:.6}", m.rmse);
        println!("relMSE  {:.6}", m.rel_mse);
        println!("PSNR    {:.3} dB", m.psnr);
        println!("FLIP    {:.6}", m.flip);
    }
    if let Some(h) = &args.heatmap {
        let (_, map) = hdr_flip(&reference, &test)?;
        let tm = ToneMapping {
            exposure_ev: 0.0,
            operator: ToneOperator::Clamp,
        };
        write_image(h, &flip_heatmap(&map), &[], &tm)?;
    }
    Ok(())
}
