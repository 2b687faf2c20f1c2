//! `penumbra farm slurm`: a split render as a Slurm job array and a merge
//! job that runs after every task succeeded (`--dependency=afterok`).

use super::job::{FarmJob, NewFarmArgs, farm_dir, write_file};
use super::task::missing_tasks;
use anyhow::{Context, Result, bail};
use clap::Args;
use std::path::{Path, PathBuf};
use std::process::Command;

#[derive(Args, Debug)]
pub struct SlurmArgs {
    #[command(flatten)]
    pub new: NewFarmArgs,
    /// Resubmit only the tasks of the farm in DIR whose part is missing,
    /// and a new merge job after them (the old merge job is cancelled).
    #[arg(long, value_name = "DIR", conflicts_with_all = ["scene", "tasks", "output", "dir"])]
    pub retry: Option<PathBuf>,
    /// Slurm partition (sbatch --partition).
    #[arg(long)]
    pub partition: Option<String>,
    /// Time limit of each task (sbatch --time, e.g. 2:00:00).
    #[arg(long)]
    pub time: Option<String>,
    /// CPUs per task (sbatch --cpus-per-task); each task renders with that many threads.
    #[arg(long)]
    pub cpus_per_task: Option<u32>,
    /// The penumbra binary as the nodes see it [default: this one].
    #[arg(long)]
    pub penumbra: Option<PathBuf>,
    /// Submit the jobs with sbatch (otherwise only write the scripts and
    /// print the commands).
    #[arg(long)]
    pub submit: bool,
}

/// The job array's script.
pub const RENDER_SCRIPT: &str = "render.sbatch";
/// The merge job's script.
pub const MERGE_SCRIPT: &str = "merge.sbatch";
/// Where submitted job ids are recorded.
const JOBS_FILE: &str = "slurm-jobs.txt";

pub fn run(args: SlurmArgs) -> Result<()> {
    if let Some(dir) = &args.retry {
        return retry(dir, args.submit);
    }
    let dir = farm_dir(&args.new)?;
    let job = FarmJob::new(&args.new, &dir)?;
    let abs = std::path::absolute(&dir)?;
    let dir_text = abs
        .to_str()
        .filter(|s| !s.chars().any(char::is_whitespace))
        .with_context(|| {
            format!(
                "{}: the farm directory's path must be UTF-8 without spaces (it appears in #SBATCH lines)",
                abs.display()
            )
        })?;
    let penumbra = match &args.penumbra {
        Some(p) => p.clone(),
        None => std::env::current_exe().context("finding the penumbra binary")?,
    };
    job.write(&dir)?;
    let mut options = Vec::new();
    for (name, value) in [
        ("partition", args.partition.clone()),
        ("time", args.time.clone()),
        ("cpus-per-task", args.cpus_per_task.map(|c| c.to_string())),
    ] {
        if let Some(v) = value {
            options.push(format!("#SBATCH --{name}={v}\n"));
        }
    }
    let options = options.concat();
    let bin = shell_quote(&penumbra.to_string_lossy());
    let render = format!(
        "#!/bin/bash\n\
         # penumbra farm: task i of this array renders samples floor(i*{spp}/{n})..floor((i+1)*{spp}/{n})\n\
         # of every pixel into parts/part-i.exr, resuming its checkpoint after a failure.\n\
         #SBATCH --job-name=penumbra-render\n\
         #SBATCH --array=0-{last}\n\
         #SBATCH --chdir={dir_text}\n\
         #SBATCH --output=logs/render-%a.log\n\
         {options}\
         exec {bin} farm task {dir}\n",
        spp = job.spp,
        n = job.tasks,
        last = job.tasks - 1,
        dir = shell_quote(dir_text),
    );
    let merge = format!(
        "#!/bin/bash\n\
         # penumbra farm: adds the parts into {output} once every task succeeded.\n\
         #SBATCH --job-name=penumbra-merge\n\
         #SBATCH --chdir={dir_text}\n\
         #SBATCH --output=logs/merge.log\n\
         {partition}\
         exec {bin} farm merge {dir}\n",
        output = job.output,
        partition = args
            .partition
            .as_ref()
            .map_or(String::new(), |p| format!("#SBATCH --partition={p}\n")),
        dir = shell_quote(dir_text),
    );
    write_file(&dir.join(RENDER_SCRIPT), &render)?;
    write_file(&dir.join(MERGE_SCRIPT), &merge)?;
    eprintln!(
        "penumbra: farm of {} tasks ({} spp) in {}",
        job.tasks,
        job.spp,
        dir.display()
    );
    submit(&abs, None, args.submit)
}

/// Submits the array (all tasks, or `only` these) and the merge job after it.
fn submit(dir: &Path, only: Option<&[u32]>, really: bool) -> Result<()> {
    let render = dir.join(RENDER_SCRIPT);
    let merge = dir.join(MERGE_SCRIPT);
    let mut array_args: Vec<String> = vec!["--parsable".into()];
    if let Some(tasks) = only {
        let list: Vec<String> = tasks.iter().map(u32::to_string).collect();
        array_args.push(format!("--array={}", list.join(",")));
    }
    array_args.push(render.to_string_lossy().into_owned());
    if !really {
        println!("sbatch {}", array_args.join(" "));
        println!(
            "sbatch --parsable --kill-on-invalid-dep=yes --dependency=afterok:<the array's job id> {}",
            merge.display()
        );
        println!(
            "(add --submit to run these; penumbra farm status {} shows the parts)",
            dir.display()
        );
        return Ok(());
    }
    let array = sbatch(&array_args)?;
    // A merge whose tasks failed can never run: let Slurm cancel it.
    let merge_id = sbatch(&[
        "--parsable".into(),
        "--kill-on-invalid-dep=yes".into(),
        format!("--dependency=afterok:{array}"),
        merge.to_string_lossy().into_owned(),
    ])?;
    let tasks = only.map_or("all".to_string(), |t| {
        t.iter().map(u32::to_string).collect::<Vec<_>>().join(",")
    });
    let record = format!("render {array} tasks {tasks}\nmerge {merge_id} after {array}\n");
    let jobs = dir.join(JOBS_FILE);
    let old = std::fs::read_to_string(&jobs).unwrap_or_default();
    write_file(&jobs, &(old + &record))?;
    println!("submitted render array {array} (tasks {tasks}) and merge job {merge_id}");
    Ok(())
}

/// Runs sbatch and returns the job id it prints (`--parsable`: `id[;cluster]`).
fn sbatch(args: &[String]) -> Result<String> {
    let out = Command::new("sbatch")
        .args(args)
        .output()
        .context("running sbatch (is Slurm's client installed and on PATH?)")?;
    if !out.status.success() {
        bail!(
            "sbatch {} failed: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let id = text
        .trim()
        .split(';')
        .next()
        .unwrap_or_default()
        .to_string();
    if id.is_empty() || !id.chars().all(|c| c.is_ascii_digit()) {
        bail!("sbatch printed {text:?}, not a job id");
    }
    Ok(id)
}

/// `--retry DIR`: the missing tasks again, and a new merge job.
fn retry(dir: &Path, really: bool) -> Result<()> {
    let job = FarmJob::read(dir)?;
    let missing = missing_tasks(dir, &job);
    if missing.is_empty() {
        println!(
            "every part exists; nothing to retry (penumbra farm merge {} merges them)",
            dir.display()
        );
        return Ok(());
    }
    let abs = std::path::absolute(dir)?;
    if really {
        // The old merge job waits on a failed array and can never run.
        if let Some(old) = std::fs::read_to_string(abs.join(JOBS_FILE))
            .unwrap_or_default()
            .lines()
            .rev()
            .find_map(|l| {
                l.strip_prefix("merge ")?
                    .split(' ')
                    .next()
                    .map(str::to_string)
            })
        {
            let _ = Command::new("scancel").arg(&old).output();
        }
    }
    submit(&abs, Some(&missing), really)
}

/// `s` in single quotes for bash.
pub fn shell_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', r"'\''"))
}
