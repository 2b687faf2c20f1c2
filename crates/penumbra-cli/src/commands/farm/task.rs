//! What runs inside a farm: one task's render, the merge, and the status
//! of the parts.

use super::job::{FarmJob, checkpoint_file, part_file};
use crate::commands::merge::merge_files;
use crate::commands::render;
use anyhow::{Context, Result, bail};
use penumbra_image::{Exposure, ToneOperator, read_partial_film};
use std::path::{Path, PathBuf};

/// Environment variables that carry a task's index: Slurm job arrays and
/// Kubernetes Indexed Jobs.
const INDEX_VARIABLES: [&str; 2] = ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"];

/// Seconds between a task's checkpoints.
const TASK_CHECKPOINT_SECONDS: &str = "60";

/// The index given, else the scheduler's.
fn task_index(given: Option<u32>) -> Result<u32> {
    if let Some(i) = given {
        return Ok(i);
    }
    for var in INDEX_VARIABLES {
        if let Ok(v) = std::env::var(var) {
            return v
                .trim()
                .parse()
                .with_context(|| format!("{var}={v:?} is not a task index"));
        }
    }
    bail!("no task index: give INDEX, or run inside a Slurm array job or an Indexed Job")
}

/// The `penumbra render` arguments of task `i`.
pub fn task_render_args(dir: &Path, job: &FarmJob, i: u32, resume: bool) -> Vec<String> {
    let path = |p: &Path| p.to_string_lossy().into_owned();
    let samples = job.samples(i);
    let mut args = vec!["render".to_string()];
    if let Some(scene) = &job.scene {
        args.push(path(&dir.join(scene)));
    }
    args.extend(job.render_args.iter().cloned());
    let checkpoint = path(&checkpoint_file(dir, i));
    args.extend([
        "--samples".to_string(),
        format!("{}..{}", samples.start, samples.end),
        "-o".to_string(),
        path(&part_file(dir, i)),
        "--checkpoint".to_string(),
        checkpoint.clone(),
        "--checkpoint-every".to_string(),
        TASK_CHECKPOINT_SECONDS.to_string(),
    ]);
    if resume {
        args.extend(["--resume".to_string(), checkpoint]);
    }
    if let Ok(cpus) = std::env::var("SLURM_CPUS_PER_TASK") {
        args.extend(["--threads".to_string(), cpus]);
    }
    args
}

/// `penumbra farm task DIR [INDEX]`: renders task INDEX's samples into its
/// part, resuming its checkpoint if an earlier attempt left one; a task
/// whose part exists has nothing to do.
pub fn run_task(dir: &Path, index: Option<u32>) -> Result<()> {
    let job = FarmJob::read(dir)?;
    let i = task_index(index)?;
    if i >= job.tasks {
        bail!(
            "task {i} does not exist: the farm has tasks 0..{}",
            job.tasks
        );
    }
    let part = part_file(dir, i);
    if part.exists() {
        eprintln!(
            "penumbra: task {i}: {} exists, nothing to do",
            part.display()
        );
        return Ok(());
    }
    let checkpoint = checkpoint_file(dir, i);
    // Checkpoints are replaced atomically, so one that exists is whole;
    // `render --resume` checks that it belongs to this task.
    let resume = checkpoint.exists();
    let args = task_render_args(dir, &job, i, resume);
    eprintln!("penumbra: task {i}: penumbra {}", args.join(" "));
    render::run_argv(&args).with_context(|| format!("task {i}"))?;
    // The part is complete; the checkpoint only repeats it.
    let _ = std::fs::remove_file(&checkpoint);
    Ok(())
}

/// `penumbra farm merge DIR`: adds the parts into the farm's output.
pub fn run_merge(dir: &Path) -> Result<()> {
    let job = FarmJob::read(dir)?;
    let missing = missing_tasks(dir, &job);
    if !missing.is_empty() {
        let list: Vec<String> = missing
            .iter()
            .map(|&i| {
                let s = job.samples(i);
                format!("{i} (samples {}..{})", s.start, s.end)
            })
            .collect();
        bail!(
            "{}: parts of tasks {} are missing; run them again (penumbra farm slurm --retry {} --submit, or penumbra farm task {} INDEX)",
            dir.display(),
            list.join(", "),
            dir.display(),
            dir.display()
        );
    }
    let files: Vec<PathBuf> = (0..job.tasks).map(|i| part_file(dir, i)).collect();
    merge_files(
        &files,
        &dir.join(&job.output),
        (Exposure::Auto, ToneOperator::Filmic),
    )
}

/// Tasks whose part file does not exist.
pub fn missing_tasks(dir: &Path, job: &FarmJob) -> Vec<u32> {
    (0..job.tasks)
        .filter(|&i| !part_file(dir, i).exists())
        .collect()
}

/// `penumbra farm status DIR`: one line per task, then a summary.
pub fn run_status(dir: &Path) -> Result<()> {
    let job = FarmJob::read(dir)?;
    let mut done = 0;
    for i in 0..job.tasks {
        let s = job.samples(i);
        let state = if part_file(dir, i).exists() {
            done += 1;
            "done".to_string()
        } else if let Ok(c) = read_partial_film(&checkpoint_file(dir, i)) {
            format!(
                "running or stopped: the checkpoint holds samples {}..{}",
                c.samples.start, c.samples.end
            )
        } else {
            "not started, or failed before its first checkpoint".to_string()
        };
        println!("task {i:>4}  samples {:>6}..{:<6} {state}", s.start, s.end);
    }
    let output = dir.join(&job.output);
    println!(
        "{done} of {} parts done; {} {}",
        job.tasks,
        output.display(),
        if output.exists() {
            "written"
        } else {
            "not written yet"
        }
    );
    let jobs = dir.join("slurm-jobs.txt");
    if let Ok(text) = std::fs::read_to_string(&jobs) {
        println!("Slurm jobs submitted ({}):", jobs.display());
        print!("{text}");
    }
    Ok(())
}
