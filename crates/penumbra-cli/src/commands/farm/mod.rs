//! `penumbra farm`: a render split by sample range into tasks that an
//! existing scheduler runs (a Slurm job array, a Kubernetes Indexed Job),
//! each writing a partial film to a shared farm directory, then merged
//! exactly. See docs/farm.md.

pub mod job;
pub mod k8s;
pub mod slurm;
pub mod task;

use anyhow::Result;
use clap::{Args, Subcommand};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct FarmArgs {
    #[command(subcommand)]
    pub command: FarmCommand,
}

#[derive(Subcommand, Debug)]
pub enum FarmCommand {
    /// Write (and with --submit, sbatch) a job array of N tasks and a merge job that runs after them.
    Slurm(slurm::SlurmArgs),
    /// Write an Indexed Job of N tasks and a merge Job for Kubernetes, over a shared volume.
    K8s(k8s::K8sArgs),
    /// Render one task's part (run by the scheduler; INDEX defaults to
    /// $SLURM_ARRAY_TASK_ID or $JOB_COMPLETION_INDEX).
    Task {
        /// The farm directory.
        dir: PathBuf,
        index: Option<u32>,
    },
    /// Merge the parts into the farm's output (run by the merge job).
    Merge {
        /// The farm directory.
        dir: PathBuf,
    },
    /// Show which parts exist, which are checkpointed, which are missing.
    Status {
        /// The farm directory.
        dir: PathBuf,
    },
}

pub fn run(args: FarmArgs) -> Result<()> {
    match args.command {
        FarmCommand::Slurm(a) => slurm::run(a),
        FarmCommand::K8s(a) => k8s::run(a),
        FarmCommand::Task { dir, index } => task::run_task(&dir, index),
        FarmCommand::Merge { dir } => task::run_merge(&dir),
        FarmCommand::Status { dir } => task::run_status(&dir),
    }
}
