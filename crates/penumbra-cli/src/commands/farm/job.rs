//! The farm directory and its job description, `farm.toml`: what every task
//! of a split render needs, with every path relative to the directory, so a
//! task finds its work from the directory alone (a shared file system seen
//! at different paths on the submit host, the nodes or a pod).

use crate::options::{SettingsArgs, parse_positive, scene_or_builtin};
use anyhow::{Context, Result, bail};
use clap::Args;
use serde::{Deserialize, Serialize};
use std::ops::Range;
use std::path::{Component, Path, PathBuf};

/// The job file inside a farm directory.
pub const JOB_FILE: &str = "farm.toml";
/// Most tasks a farm may have (Slurm's default MaxArraySize is 1001).
pub const MAX_TASKS: u32 = 1000;

/// Where a new farm goes: the scene, the split, the output.
#[derive(Args, Clone, Debug)]
pub struct NewFarmArgs {
    /// Scene file (.gltf, .glb, .obj, .toml) on a file system every task
    /// sees. Default: the built-in Cornell box.
    pub scene: Option<PathBuf>,
    /// Number of tasks; task i renders samples ⌊i·S/N⌋..⌊(i+1)·S/N⌋ of every pixel.
    #[arg(long, value_parser = parse_positive)]
    pub tasks: Option<u32>,
    /// The merged image (.exr or .png), written by the merge job.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// The farm directory (job file, scripts, parts, logs) on a shared file
    /// system [default: OUTPUT's name with .farm].
    #[arg(long)]
    pub dir: Option<PathBuf>,
    #[command(flatten)]
    pub render: SettingsArgs,
}

/// `farm.toml`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FarmJob {
    /// The scene file relative to the farm directory; none: the built-in Cornell box.
    pub scene: Option<String>,
    /// The merged image, relative to the farm directory.
    pub output: String,
    pub tasks: u32,
    /// Samples per pixel of the whole render.
    pub spp: u32,
    /// The flags every task passes to `penumbra render`, besides the scene,
    /// `--samples`, the output and the checkpoint.
    pub render_args: Vec<String>,
}

impl FarmJob {
    /// Checks the scene (it must load) and the split, and describes the job
    /// relative to `dir`.
    pub fn new(args: &NewFarmArgs, dir: &Path) -> Result<FarmJob> {
        let (Some(tasks), Some(output)) = (args.tasks, &args.output) else {
            bail!("a new farm needs --tasks N and -o OUTPUT");
        };
        penumbra_image::check_output_path(output)?;
        let scene = scene_or_builtin(args.scene.as_deref())?;
        let r = &args.render;
        let spp = r.spp.unwrap_or(scene.settings.spp);
        if tasks > spp.min(MAX_TASKS) {
            bail!(
                "--tasks {tasks} is more than the {spp} samples per pixel to split (or than {MAX_TASKS})"
            );
        }
        // The spp is written out, so the split does not depend on the scene's default.
        let render_args = SettingsArgs {
            spp: Some(spp),
            ..r.clone()
        }
        .to_args();
        Ok(FarmJob {
            scene: args
                .scene
                .as_deref()
                .map(|s| relative_to(dir, s))
                .transpose()?,
            output: relative_to(dir, output)?,
            tasks,
            spp,
            render_args,
        })
    }

    /// Sample indices of task `i`: `⌊i·S/N⌋..⌊(i+1)·S/N⌋`.
    pub fn samples(&self, i: u32) -> Range<u32> {
        let at = |k: u32| (u64::from(k) * u64::from(self.spp) / u64::from(self.tasks)) as u32;
        at(i)..at(i + 1)
    }

    /// Reads `DIR/farm.toml`.
    pub fn read(dir: &Path) -> Result<FarmJob> {
        let path = dir.join(JOB_FILE);
        let text = std::fs::read_to_string(&path).with_context(|| {
            format!(
                "{}: cannot read the farm's job file (is {} a farm directory?)",
                path.display(),
                dir.display()
            )
        })?;
        let job: FarmJob =
            toml::from_str(&text).with_context(|| format!("{}: not a farm job", path.display()))?;
        if job.tasks == 0 || job.tasks > job.spp {
            bail!(
                "{}: tasks = {} does not split spp = {}",
                path.display(),
                job.tasks,
                job.spp
            );
        }
        Ok(job)
    }

    /// Writes `DIR/farm.toml` and creates `parts/` and `logs/`.
    pub fn write(&self, dir: &Path) -> Result<()> {
        for sub in ["parts", "logs"] {
            std::fs::create_dir_all(dir.join(sub))
                .with_context(|| format!("creating {}", dir.join(sub).display()))?;
        }
        let text = format!(
            "# penumbra farm: a render split into {} sample ranges (penumbra farm status DIR)\n{}",
            self.tasks,
            toml::to_string(self)?
        );
        write_file(&dir.join(JOB_FILE), &text)
    }
}

/// The partial film of task `i`.
pub fn part_file(dir: &Path, i: u32) -> PathBuf {
    dir.join("parts").join(format!("part-{i:04}.exr"))
}

/// The checkpoint of task `i` while it renders.
pub fn checkpoint_file(dir: &Path, i: u32) -> PathBuf {
    dir.join("parts")
        .join(format!("part-{i:04}.checkpoint.exr"))
}

/// The farm directory of a new farm: `--dir`, else OUTPUT with `.farm`.
pub fn farm_dir(args: &NewFarmArgs) -> Result<PathBuf> {
    match (&args.dir, &args.output) {
        (Some(d), _) => Ok(d.clone()),
        (None, Some(o)) => Ok(o.with_extension("farm")),
        (None, None) => bail!("a new farm needs -o OUTPUT"),
    }
}

/// `path` relative to `dir` (both made absolute first), with `..` where needed.
pub fn relative_to(dir: &Path, path: &Path) -> Result<String> {
    let abs = |p: &Path| {
        std::path::absolute(p)
            .map(|p| normalise(&p))
            .with_context(|| format!("{}: cannot make the path absolute", p.display()))
    };
    let (d, p) = (abs(dir)?, abs(path)?);
    let (dc, pc): (Vec<_>, Vec<_>) = (d.components().collect(), p.components().collect());
    let common = dc.iter().zip(&pc).take_while(|(a, b)| a == b).count();
    let mut out = PathBuf::new();
    for _ in common..dc.len() {
        out.push("..");
    }
    for c in &pc[common..] {
        out.push(c);
    }
    out.to_str()
        .map(str::to_string)
        .with_context(|| format!("{}: the path is not UTF-8", path.display()))
}

/// Removes `.` and resolves `..` lexically.
fn normalise(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// Writes a text file (scripts, manifests, the job file) atomically.
pub fn write_file(path: &Path, text: &str) -> Result<()> {
    Ok(penumbra_image::write_atomic(path, text.as_bytes())?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_split_the_samples_without_gaps() {
        let job = FarmJob {
            scene: None,
            output: "o.exr".into(),
            tasks: 7,
            spp: 100,
            render_args: vec![],
        };
        let ranges: Vec<Range<u32>> = (0..7).map(|i| job.samples(i)).collect();
        assert_eq!(ranges[0], 0..14);
        assert_eq!(ranges[6], 85..100);
        for w in ranges.windows(2) {
            assert_eq!(w[0].end, w[1].start);
            assert!((14..=15).contains(&w[0].len()));
        }
    }

    #[test]
    fn relative_paths() {
        let r = |d: &str, p: &str| relative_to(Path::new(d), Path::new(p)).unwrap();
        assert_eq!(r("/a/b/farm", "/a/scene.toml"), "../../scene.toml");
        assert_eq!(r("/a/farm", "/a/farm/../out.exr"), "../out.exr");
        assert_eq!(r("/a", "/a/x/y.png"), "x/y.png");
    }
}
