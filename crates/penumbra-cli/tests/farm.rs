//! `penumbra farm`: the job files a scheduler runs, the tasks, the merge,
//! the status and the retry of failed tasks. The Slurm test submits to a
//! real cluster (`scripts/slurm-local.sh start` brings one up on this
//! machine); the Kubernetes manifests are checked against the batch/v1
//! schema of the official Python client.

mod common;

use common::{penumbra, stderr};
use penumbra_image::{Image, read_image};
use std::path::Path;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

const RENDER: [&str; 4] = ["--resolution", "40x30", "--spp", "20"];

fn ok(o: Output, what: &str) -> String {
    assert!(o.status.success(), "{what}: {}", stderr(&o));
    String::from_utf8_lossy(&o.stdout).into_owned() + &stderr(&o)
}

/// The farm's render done in one process.
fn whole(dir: &Path) -> Image {
    let mut args = vec!["render"];
    args.extend(RENDER);
    args.extend(["-o", "whole.exr"]);
    ok(penumbra(&args, dir), "whole render");
    read_image(&dir.join("whole.exr")).unwrap()
}

fn task(dir: &Path, env: Option<(&str, &str)>, index: Option<&str>) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_penumbra"));
    c.args(["farm", "task", "out.farm"])
        .args(index)
        .current_dir(dir);
    for var in [
        "SLURM_ARRAY_TASK_ID",
        "JOB_COMPLETION_INDEX",
        "SLURM_CPUS_PER_TASK",
    ] {
        c.env_remove(var);
    }
    if let Some((k, v)) = env {
        c.env(k, v);
    }
    c.output().unwrap()
}

#[test]
fn tasks_run_anywhere_merge_exactly_and_missing_ones_are_retried_alone() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut args = vec!["farm", "slurm", "--tasks", "3", "-o", "out.exr"];
    args.extend(RENDER);
    args.extend([
        "--partition",
        "debug",
        "--time",
        "10:00",
        "--cpus-per-task",
        "1",
    ]);
    let printed = ok(penumbra(&args, dir), "farm slurm");
    assert!(printed.contains("sbatch --parsable"), "{printed}");
    let script = std::fs::read_to_string(dir.join("out.farm/render.sbatch")).unwrap();
    for line in [
        "#SBATCH --array=0-2",
        "#SBATCH --partition=debug",
        "#SBATCH --time=10:00",
        "#SBATCH --cpus-per-task=1",
        "farm task '",
    ] {
        assert!(script.contains(line), "{line} not in\n{script}");
    }
    // Tasks 0 and 2, as a scheduler starts them; task 1 is lost.
    ok(task(dir, None, Some("0")), "task 0");
    ok(
        task(dir, Some(("SLURM_ARRAY_TASK_ID", "2")), None),
        "task 2",
    );
    let status = ok(penumbra(&["farm", "status", "out.farm"], dir), "status");
    assert!(
        status.contains("samples      6..13     not started"),
        "{status}"
    );
    assert!(status.contains("2 of 3 parts done"), "{status}");
    let o = penumbra(&["farm", "merge", "out.farm"], dir);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("parts of tasks 1 (samples 6..13) are missing"),
        "{}",
        stderr(&o)
    );
    let retry = ok(
        penumbra(&["farm", "slurm", "--retry", "out.farm"], dir),
        "retry",
    );
    assert!(retry.contains("sbatch --parsable --array=1 "), "{retry}");
    // The retried task, then the merge, give the single render's bits.
    ok(
        task(dir, Some(("JOB_COMPLETION_INDEX", "1")), None),
        "task 1",
    );
    let again = ok(task(dir, None, Some("1")), "task 1 again");
    assert!(again.contains("exists, nothing to do"), "{again}");
    ok(penumbra(&["farm", "merge", "out.farm"], dir), "merge");
    let merged = read_image(&dir.join("out.exr")).unwrap();
    assert!(merged.pixels == whole(dir).pixels);
    let o = task(dir, None, Some("3"));
    assert!(stderr(&o).contains("task 3 does not exist: the farm has tasks 0..3"));
    let o = task(dir, None, None);
    assert!(stderr(&o).contains("no task index"), "{}", stderr(&o));
    let o = penumbra(
        &[
            "farm", "slurm", "--tasks", "30", "--spp", "20", "-o", "x.exr",
        ],
        dir,
    );
    assert!(stderr(&o).contains("--tasks 30 is more than the 20 samples per pixel"));
}

#[test]
fn kubernetes_manifests_are_valid_indexed_jobs() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut args = vec![
        "farm",
        "k8s",
        "--tasks",
        "4",
        "-o",
        "out.exr",
        "--image",
        "registry.example/penumbra:1",
        "--claim",
        "renders",
        "--cpus",
        "3",
    ];
    args.extend(RENDER);
    ok(penumbra(&args, dir), "farm k8s");
    let k8s = dir.join("out.farm/k8s");
    let python = "/usr/bin/python3"; // Debian's, with python3-kubernetes
    let check = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/k8s/check_job.py");
    let o = Command::new(python)
        .arg(&check)
        .arg(k8s.join("render-job.json"))
        .arg(k8s.join("merge-job.json"))
        .output()
        .expect("run /usr/bin/python3 (scripts/test.sh installs python3-kubernetes)");
    let said = ok(o, "check_job.py");
    assert!(
        said.contains(
            "render-job.json: valid batch/v1 Job out-render (completions 4, mode Indexed)"
        ),
        "{said}"
    );
    assert!(
        said.contains("merge-job.json: valid batch/v1 Job out-merge"),
        "{said}"
    );
    let render: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(k8s.join("render-job.json")).unwrap())
            .unwrap();
    let container = &render["spec"]["template"]["spec"]["containers"][0];
    assert_eq!(
        container["command"],
        serde_json::json!(["penumbra", "farm", "task", "/farm/out.farm"])
    );
    assert_eq!(container["resources"]["requests"]["cpu"], "3");
    // The checker itself refuses a misspelt field.
    let bad = std::fs::read_to_string(k8s.join("render-job.json"))
        .unwrap()
        .replace("\"completions\"", "\"completion\"");
    std::fs::write(dir.join("bad.json"), bad).unwrap();
    let o = Command::new(python)
        .arg(&check)
        .arg(dir.join("bad.json"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    // Pods find their index in JOB_COMPLETION_INDEX.
    for i in 0..4 {
        let index = i.to_string();
        ok(
            task(dir, Some(("JOB_COMPLETION_INDEX", &index)), None),
            "pod",
        );
    }
    ok(penumbra(&["farm", "merge", "out.farm"], dir), "merge");
    assert!(read_image(&dir.join("out.exr")).unwrap().pixels == whole(dir).pixels);
    let o = penumbra(
        &[
            "farm",
            "k8s",
            "/etc/hostname",
            "--tasks",
            "2",
            "-o",
            "y.exr",
            "--image",
            "i",
            "--claim",
            "c",
        ],
        dir,
    );
    assert!(
        stderr(&o).contains("lies outside --root") || stderr(&o).contains("/etc/hostname"),
        "{}",
        stderr(&o)
    );
}

/// Waits until none of `jobs` is queued or running.
fn wait_for_jobs(jobs: &str) {
    let start = Instant::now();
    loop {
        let o = Command::new("squeue")
            .args(["-h", "-j", jobs])
            .output()
            .unwrap();
        if o.status.success() && o.stdout.iter().all(u8::is_ascii_whitespace) {
            return;
        }
        assert!(
            start.elapsed() < Duration::from_secs(300),
            "jobs {jobs} still queued"
        );
        std::thread::sleep(Duration::from_millis(300));
    }
}

/// The job ids of the last submission in `slurm-jobs.txt`: "array,merge".
fn last_jobs(dir: &Path) -> String {
    let text = std::fs::read_to_string(dir.join("out.farm/slurm-jobs.txt")).unwrap();
    let id = |kind: &str| {
        text.lines()
            .rev()
            .find_map(|l| l.strip_prefix(kind)?.split(' ').next().map(str::to_string))
            .unwrap()
    };
    format!("{},{}", id("render "), id("merge "))
}

/// A real Slurm cluster (scripts/slurm-local.sh start) runs the array; a
/// task that fails keeps the merge from running; `--retry` resubmits that
/// task alone and the merge then gives the single render's bits.
#[test]
fn slurm_runs_the_array_and_the_merge_and_retries_a_failed_task() {
    if std::env::var("PENUMBRA_SKIP_SLURM").as_deref() == Ok("1") {
        eprintln!("PENUMBRA_SKIP_SLURM=1: the Slurm test is skipped");
        return;
    }
    let sinfo = Command::new("sinfo").args(["-h", "-o", "%T"]).output();
    let up = sinfo.as_ref().is_ok_and(|o| {
        let s = String::from_utf8_lossy(&o.stdout);
        o.status.success() && ["idle", "mixed", "allocated"].iter().any(|t| s.contains(t))
    });
    assert!(
        up,
        "no Slurm cluster answers (start one with `scripts/slurm-local.sh start`, as scripts/test.sh does, or set PENUMBRA_SKIP_SLURM=1): {sinfo:?}"
    );
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // Task 2 cannot write its checkpoint (a directory stands in its way), so it fails.
    let blocker = dir.join("out.farm/parts/part-0002.checkpoint.exr");
    std::fs::create_dir_all(&blocker).unwrap();
    let mut args = vec!["farm", "slurm", "--tasks", "4", "-o", "out.exr", "--submit"];
    args.extend(RENDER);
    args.extend([
        "--cpus-per-task",
        "1",
        "--penumbra",
        env!("CARGO_BIN_EXE_penumbra"),
    ]);
    let said = ok(penumbra(&args, dir), "farm slurm --submit");
    assert!(said.contains("submitted render array"), "{said}");
    wait_for_jobs(&last_jobs(dir));
    let status = ok(penumbra(&["farm", "status", "out.farm"], dir), "status");
    assert!(status.contains("3 of 4 parts done"), "{status}");
    assert!(
        !dir.join("out.exr").exists(),
        "the merge ran after a failed task"
    );
    let log = std::fs::read_to_string(dir.join("out.farm/logs/render-2.log")).unwrap();
    assert!(log.contains("checkpoint"), "task 2's log: {log}");

    std::fs::remove_dir(&blocker).unwrap();
    let said = ok(
        penumbra(&["farm", "slurm", "--retry", "out.farm", "--submit"], dir),
        "retry",
    );
    assert!(said.contains("(tasks 2)"), "{said}");
    wait_for_jobs(&last_jobs(dir));
    let merge_log =
        std::fs::read_to_string(dir.join("out.farm/logs/merge.log")).unwrap_or_default();
    assert!(
        dir.join("out.exr").exists(),
        "no merged image; merge log: {merge_log}"
    );
    let merged = read_image(&dir.join("out.exr")).unwrap();
    assert!(merged.pixels == whole(dir).pixels);
}
