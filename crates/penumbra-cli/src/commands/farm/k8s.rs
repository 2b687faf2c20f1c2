//! `penumbra farm k8s`: a split render as a Kubernetes Indexed Job (the
//! completion index is the task) over a shared volume, and a merge Job.

use super::job::{FarmJob, NewFarmArgs, farm_dir, relative_to, write_file};
use anyhow::{Context, Result, bail};
use clap::Args;
use serde_json::{Value, json};
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct K8sArgs {
    #[command(flatten)]
    pub new: NewFarmArgs,
    /// Container image with `penumbra` on its PATH.
    #[arg(long)]
    pub image: String,
    /// PersistentVolumeClaim (ReadWriteMany) that holds the farm directory and the scene.
    #[arg(long)]
    pub claim: String,
    /// Where the pods mount the claim.
    #[arg(long, default_value = "/farm")]
    pub mount: String,
    /// The local folder the claim's root is (the farm directory and the
    /// scene must lie inside it) [default: the farm directory's parent].
    #[arg(long)]
    pub root: Option<PathBuf>,
    /// CPUs each pod requests (its render threads).
    #[arg(long, default_value_t = 2)]
    pub cpus: u32,
    /// Pods running at once [default: --tasks].
    #[arg(long)]
    pub parallelism: Option<u32>,
    /// Name prefix of the Jobs [default: from the output's name].
    #[arg(long)]
    pub name: Option<String>,
}

/// Retries of the whole Indexed Job before it fails (a retried pod resumes
/// its checkpoint).
const BACKOFF_LIMIT: u32 = 6;

pub fn run(args: K8sArgs) -> Result<()> {
    let dir = farm_dir(&args.new)?;
    let job = FarmJob::new(&args.new, &dir)?;
    let root = match &args.root {
        Some(r) => r.clone(),
        None => std::path::absolute(&dir)?
            .parent()
            .map(PathBuf::from)
            .context("the farm directory has no parent")?,
    };
    let dir_in_root = relative_to(&root, &dir)?;
    for (what, rel) in [
        ("the farm directory", Some(dir_in_root.clone())),
        (
            "the scene",
            args.new
                .scene
                .as_deref()
                .map(|s| relative_to(&root, s))
                .transpose()?,
        ),
        (
            "the output",
            args.new
                .output
                .as_deref()
                .map(|s| relative_to(&root, s))
                .transpose()?,
        ),
    ] {
        if rel.as_deref().is_some_and(|r| r.starts_with("..")) {
            bail!(
                "{what} lies outside --root {} (the volume the pods mount at {})",
                root.display(),
                args.mount
            );
        }
    }
    let name = dns_label(
        args.name
            .as_deref()
            .or_else(|| args.new.output.as_deref()?.file_stem()?.to_str())
            .unwrap_or("penumbra"),
    );
    let pod_dir = format!("{}/{}", args.mount.trim_end_matches('/'), dir_in_root);
    let parallelism = args.parallelism.unwrap_or(job.tasks).clamp(1, job.tasks);
    job.write(&dir)?;
    let k8s = dir.join("k8s");
    std::fs::create_dir_all(&k8s).with_context(|| format!("creating {}", k8s.display()))?;
    let render = manifest(
        &format!("{name}-render"),
        &args,
        &["farm", "task", &pod_dir],
        json!({
            "completionMode": "Indexed",
            "completions": job.tasks,
            "parallelism": parallelism,
            "backoffLimit": BACKOFF_LIMIT,
        }),
    );
    let merge = manifest(
        &format!("{name}-merge"),
        &args,
        &["farm", "merge", &pod_dir],
        json!({ "completions": 1, "backoffLimit": 2 }),
    );
    write_file(
        &k8s.join("render-job.json"),
        &serde_json::to_string_pretty(&render)?,
    )?;
    write_file(
        &k8s.join("merge-job.json"),
        &serde_json::to_string_pretty(&merge)?,
    )?;
    let script = format!(
        "#!/bin/sh\n\
         # penumbra farm: the Indexed Job renders {tasks} parts; the merge Job runs once it completed.\n\
         set -e\n\
         cd \"$(dirname \"$0\")\"\n\
         kubectl apply -f render-job.json\n\
         kubectl wait --for=condition=complete --timeout=-1s job/{name}-render\n\
         kubectl apply -f merge-job.json\n\
         kubectl wait --for=condition=complete --timeout=-1s job/{name}-merge\n",
        tasks = job.tasks,
    );
    write_file(&k8s.join("run.sh"), &script)?;
    eprintln!(
        "penumbra: farm of {} tasks ({} spp) in {}; {}/run.sh applies the Jobs",
        job.tasks,
        job.spp,
        dir.display(),
        k8s.display()
    );
    Ok(())
}

/// A batch/v1 Job running `penumbra ARGS` with the claim mounted.
fn manifest(name: &str, args: &K8sArgs, command: &[&str], spec: Value) -> Value {
    let mut spec = spec;
    spec["template"] = json!({
        "metadata": { "labels": { "app.kubernetes.io/name": "penumbra" } },
        "spec": {
            "restartPolicy": "OnFailure",
            "containers": [{
                "name": "penumbra",
                "image": args.image,
                "command": std::iter::once("penumbra").chain(command.iter().copied()).collect::<Vec<_>>(),
                "env": [{ "name": "RAYON_NUM_THREADS", "value": args.cpus.to_string() }],
                "resources": { "requests": { "cpu": args.cpus.to_string() } },
                "volumeMounts": [{ "name": "farm", "mountPath": args.mount }],
            }],
            "volumes": [{
                "name": "farm",
                "persistentVolumeClaim": { "claimName": args.claim },
            }],
        },
    });
    json!({
        "apiVersion": "batch/v1",
        "kind": "Job",
        "metadata": { "name": name, "labels": { "app.kubernetes.io/name": "penumbra" } },
        "spec": spec,
    })
}

/// `s` as a DNS-1123 label prefix: lower-case letters, digits and '-', at
/// most 50 characters (room for `-render`), starting with a letter.
fn dns_label(s: &str) -> String {
    let mut out: String = s
        .chars()
        .map(|c| c.to_ascii_lowercase())
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect();
    out = out.trim_matches('-').chars().take(50).collect();
    out = out.trim_end_matches('-').to_string();
    if out.is_empty() {
        return "penumbra".to_string();
    }
    if !out.starts_with(|c: char| c.is_ascii_lowercase()) {
        out.insert_str(0, "penumbra-");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn job_names_are_dns_labels() {
        assert_eq!(dns_label("My Render_01"), "my-render-01");
        assert_eq!(dns_label("4k"), "penumbra-4k");
        assert_eq!(dns_label("--"), "penumbra");
    }
}
