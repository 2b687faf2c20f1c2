//! The flags of `render` that split, checkpoint and resume a render, and
//! what they share with `merge` and `farm`: the identity of a render that
//! every partial film records.

use anyhow::{Context, Result, bail};
use clap::Args;
use penumbra_image::{
    Film, PartialFilm, key_differences, parse_range, read_partial_film, render_key,
    write_partial_film,
};
use penumbra_scene::{RenderSettings, Scene, fingerprint};
use penumbra_trace::{Crop, Resume};
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Seconds between checkpoints when `--checkpoint-every` is not given.
pub const DEFAULT_CHECKPOINT_SECONDS: f64 = 60.0;

#[derive(Args, Clone, Debug, Default)]
pub struct PartArgs {
    /// Take only sample indices A..B−1 of every pixel (the same numbers a
    /// whole render draws for them) and write a partial film (.exr) for
    /// `penumbra merge`. B may not exceed --spp.
    #[arg(long, value_name = "A..B", value_parser = parse_samples)]
    pub samples: Option<Range<u32>>,
    /// Render only columns X0..X1−1 and rows Y0..Y1−1 and write a partial
    /// film (.exr) for `penumbra merge`.
    #[arg(long, value_name = "X0,Y0,X1,Y1", value_parser = parse_crop)]
    pub crop: Option<Crop>,
    /// Keep the film's state in FILE (a partial film, replaced atomically)
    /// while rendering, so that --resume FILE can continue after a crash.
    #[arg(long, value_name = "FILE")]
    pub checkpoint: Option<PathBuf>,
    /// Seconds between checkpoints; 0 writes one after every pass (at most
    /// 64 samples per pixel) [default: 60].
    #[arg(long, value_name = "S", value_parser = parse_seconds_or_zero)]
    pub checkpoint_every: Option<f64>,
    /// Continue the render held in this checkpoint (written by --checkpoint
    /// with the same scene and flags); new checkpoints go to the same file
    /// unless --checkpoint names another.
    #[arg(long, value_name = "FILE")]
    pub resume: Option<PathBuf>,
    /// Stop when the film's estimate of its own relMSE, mean over pixels of
    /// Var[mean] / (mean² + 0.01), falls to E (tested after each pass once
    /// every pixel has 16 samples); --spp stays the most it takes.
    #[arg(long, value_name = "E", value_parser = parse_relmse)]
    pub target_relmse: Option<f64>,
}

fn parse_samples(s: &str) -> Result<Range<u32>, String> {
    match parse_range(s) {
        Some(r) if !r.is_empty() => Ok(r),
        _ => Err(format!(
            "'{s}' is not a sample range A..B with A < B (e.g. 0..64)"
        )),
    }
}

fn parse_crop(s: &str) -> Result<Crop, String> {
    let v: Vec<u32> = s
        .split(',')
        .map(|p| p.trim().parse::<u32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{s}' is not a window X0,Y0,X1,Y1 of pixel numbers"))?;
    match v.as_slice() {
        &[x0, y0, x1, y1] if x0 < x1 && y0 < y1 => Ok(Crop {
            x: x0..x1,
            y: y0..y1,
        }),
        _ => Err(format!(
            "'{s}' is not a window X0,Y0,X1,Y1 with X0 < X1 and Y0 < Y1"
        )),
    }
}

fn parse_seconds_or_zero(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("'{s}' is not a number of seconds (0 or more)")),
    }
}

fn parse_relmse(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("'{s}' is not a relMSE (a number above 0)")),
    }
}

impl PartArgs {
    /// Whether the output is a partial film rather than an image.
    pub fn writes_partial(&self) -> bool {
        self.samples.is_some() || self.crop.is_some()
    }

    /// Checks the flags against the settings and the output, before any
    /// time is spent rendering.
    pub fn check(&self, settings: &RenderSettings, output: &Path, aovs: bool) -> Result<()> {
        if let Some(r) = &self.samples
            && r.end > settings.spp
        {
            bail!(
                "--samples {}..{} reaches past --spp {} (the whole render's samples per pixel)",
                r.start,
                r.end,
                settings.spp
            );
        }
        if let Some(c) = &self.crop
            && (c.x.end > settings.width || c.y.end > settings.height)
        {
            bail!(
                "--crop {},{},{},{} reaches outside the {}x{} image",
                c.x.start,
                c.y.start,
                c.x.end,
                c.y.end,
                settings.width,
                settings.height
            );
        }
        let splits = self.writes_partial() || self.checkpoint.is_some() || self.resume.is_some();
        if splits && aovs {
            bail!(
                "--aovs cannot be split, checkpointed or resumed: partial films hold the radiance only"
            );
        }
        if self.writes_partial() && !is_exr(output) {
            bail!(
                "{}: --samples and --crop write a partial film, which is an .exr file (merge the parts with `penumbra merge`)",
                output.display()
            );
        }
        for file in [&self.checkpoint, &self.resume].into_iter().flatten() {
            if !is_exr(file) {
                bail!("{}: a checkpoint is an .exr file", file.display());
            }
        }
        if self.checkpoint_every.is_some() && self.checkpoint.is_none() && self.resume.is_none() {
            bail!("--checkpoint-every needs --checkpoint FILE");
        }
        Ok(())
    }

    /// The sample range to take: `--samples`, else all of `--spp`.
    pub fn sample_range(&self, settings: &RenderSettings) -> Range<u32> {
        self.samples.clone().unwrap_or(0..settings.spp)
    }

    /// The window to render: `--crop`, else the whole image.
    pub fn window(&self, settings: &RenderSettings) -> Crop {
        self.crop.clone().unwrap_or(Crop {
            x: 0..settings.width,
            y: 0..settings.height,
        })
    }

    /// The film of `--resume`, after checking it belongs to this render.
    pub fn resume(&self, identity: &RenderIdentity) -> Result<Option<Resume>> {
        let Some(path) = &self.resume else {
            return Ok(None);
        };
        let part = read_partial_film(path)?;
        let window = &identity.window;
        let mismatch = |what: String| {
            anyhow::anyhow!(
                "{}: cannot resume: the checkpoint {what}; give the flags and scene it was written with",
                path.display()
            )
        };
        if let Some(odd) = identity.differences(&part).first() {
            return Err(mismatch(odd.clone()));
        }
        if part.window() != (window.x.clone(), window.y.clone()) {
            return Err(mismatch(format!("covers {}", part.extent())));
        }
        if part.samples.start != identity.samples.start || part.samples.end > identity.samples.end {
            return Err(mismatch(format!(
                "holds samples {}..{}, not a start of {}..{}",
                part.samples.start, part.samples.end, identity.samples.start, identity.samples.end
            )));
        }
        Ok(Some(Resume {
            film: part.film,
            next: part.samples.end,
        }))
    }

    /// The file checkpoints go to: `--checkpoint`, else the `--resume` file.
    pub fn checkpoint_file(&self) -> Option<&Path> {
        self.checkpoint.as_deref().or(self.resume.as_deref())
    }
}

fn is_exr(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

/// What makes two partial films parts of the same render.
#[derive(Clone, Debug)]
pub struct RenderIdentity {
    pub width: u32,
    pub height: u32,
    pub spp: u32,
    /// The settings that change pixels, and the scene's fingerprint when
    /// a partial film or checkpoint will record it.
    pub settings: BTreeMap<String, String>,
    /// The sample range this process renders.
    pub samples: Range<u32>,
    /// The window this process renders.
    pub window: Crop,
}

impl RenderIdentity {
    pub fn new(scene: &Scene, settings: &RenderSettings, parts: &PartArgs) -> Self {
        let mut settings_map = BTreeMap::from([
            ("integrator".to_string(), settings.integrator.to_string()),
            ("max_depth".to_string(), settings.max_depth.to_string()),
            ("seed".to_string(), settings.seed.to_string()),
            (
                "ao_distance".to_string(),
                format!("{:?}", settings.ao_distance),
            ),
        ]);
        // The fingerprint reads every vertex and texel: only the files that
        // record the identity (partial films, checkpoints) need it.
        if parts.writes_partial() || parts.checkpoint_file().is_some() {
            settings_map.insert("scene".to_string(), fingerprint(scene));
        }
        Self {
            width: settings.width,
            height: settings.height,
            spp: settings.spp,
            settings: settings_map,
            samples: parts.sample_range(settings),
            window: parts.window(settings),
        }
    }

    /// How `part` differs from this render (image size, spp, settings), in words.
    pub fn differences(&self, part: &PartialFilm) -> Vec<String> {
        let ours = render_key((self.width, self.height), self.spp, &self.settings);
        key_differences(&ours, &part.render_key())
            .into_iter()
            .map(|(k, v, theirs)| {
                if k == "scene" {
                    format!("was rendered from another scene ({theirs}, this one is {v})")
                } else {
                    format!("has {k} = {theirs}, not {v}")
                }
            })
            .collect()
    }

    /// The partial film of `film`, holding `samples`.
    pub fn part(&self, film: Film, samples: Range<u32>) -> PartialFilm {
        PartialFilm {
            image_width: self.width,
            image_height: self.height,
            samples,
            spp: self.spp,
            identity: self.settings.clone(),
            film,
        }
    }
}

/// Writes checkpoints at most every `every`, and at the end of the range;
/// remembers the first error so that the render can report it.
pub struct Checkpointer<'a> {
    pub path: &'a Path,
    pub every: Duration,
    pub identity: &'a RenderIdentity,
    last: Mutex<Instant>,
    error: Mutex<Option<anyhow::Error>>,
}

impl<'a> Checkpointer<'a> {
    pub fn new(path: &'a Path, every_seconds: Option<f64>, identity: &'a RenderIdentity) -> Self {
        Self {
            path,
            every: Duration::from_secs_f64(every_seconds.unwrap_or(DEFAULT_CHECKPOINT_SECONDS)),
            identity,
            last: Mutex::new(Instant::now()),
            error: Mutex::new(None),
        }
    }

    /// Called after every pass.
    pub fn pass_done(&self, film: &Film, samples: Range<u32>) {
        let Ok(mut last) = self.last.lock() else {
            return;
        };
        if last.elapsed() < self.every && samples.end < self.identity.samples.end {
            return;
        }
        let part = self.identity.part(film.clone(), samples);
        if let Err(e) = write_partial_film(self.path, &part)
            && let Ok(mut slot) = self.error.lock()
        {
            slot.get_or_insert(anyhow::Error::new(e).context("writing a checkpoint"));
        }
        *last = Instant::now();
    }

    /// The first error of a checkpoint write, if any.
    pub fn finish(self) -> Result<()> {
        match self.error.into_inner() {
            Ok(Some(e)) => Err(e),
            _ => Ok(()),
        }
    }
}

/// Reads every part, naming the file of any that is not a partial film.
pub fn read_parts(paths: &[PathBuf]) -> Result<Vec<(PathBuf, PartialFilm)>> {
    paths
        .iter()
        .map(|p| {
            read_partial_film(p)
                .map(|f| (p.clone(), f))
                .with_context(|| format!("reading part {}", p.display()))
        })
        .collect()
}
