//! The report opened in a real browser: a synthetic study with generated
//! images is written with `write_report`, then headless Chromium loads
//! `index.html` in a harness page (rows, images, sorting, the truth flip)
//! and takes a screenshot of it.
//!
//! Chromium (Debian package `chromium`) is installed by `scripts/test.sh`;
//! without it these tests fail, unless `PENUMBRA_SKIP_BROWSER=1`.
//! `PENUMBRA_CHROMIUM=/path/to/browser` picks a browser explicitly.

use penumbra_study::{Cost, EqualTime, Errors, Row, Skipped, Study, Truth, write_report};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A hung browser is killed after this long.
const BROWSER_TIMEOUT: Duration = Duration::from_secs(60);

// --- the study ----------------------------------------------------------------

fn errors(rel_mse: f64, flip_mean: f64) -> Errors {
    Errors {
        rel_mse,
        flip_mean,
        flip_p99: (flip_mean * 3.0).min(1.0),
        mean_ratio: [0.97, 1.0, 1.04],
    }
}

/// A `path`-approximating row without a bake.
fn row(id: &str, label: &str, group: &str, full_rel_mse: f64, seconds: f64) -> Row {
    Row {
        id: id.into(),
        label: label.into(),
        group: group.into(),
        engine: if group == "ray tracing" {
            "trace"
        } else {
            "raster"
        }
        .into(),
        command: format!("penumbra render scenes/cornell.toml --technique {id}"),
        approximates: "path".into(),
        image: format!("rows/{id}.png"),
        image_exr: format!("rows/{id}.exr"),
        error_map: format!("rows/{id}-error.png"),
        quantity_image: None,
        quantity: errors(full_rel_mse, full_rel_mse.sqrt() / 4.0),
        full: errors(full_rel_mse, full_rel_mse.sqrt() / 4.0),
        equal_time_path: Some(EqualTime {
            spp: 3,
            seconds,
            full: errors(0.4, 0.2),
        }),
        cost: Cost {
            bake_seconds: None,
            seconds,
            peak_memory_mib: Some(300.0 + full_rel_mse * 100.0),
        },
        notes: vec![format!("note on {id} <i>not markup</i>")],
    }
}

/// Four rows whose errors, times and bakes all order them differently.
fn study() -> Study {
    let truth = |id: &str, label: &str, image: &str| Truth {
        id: id.into(),
        label: label.into(),
        source: format!("path, 1024 spp, seed 7 ({id})"),
        image: image.into(),
        image_exr: image.replace(".png", ".exr"),
        noise_rel_mse: Some(2e-4),
        spp: Some(1024),
        seconds: 12.5,
    };
    let mut path = row("path", "path tracing, 16 spp", "ray tracing", 0.08, 2.0);
    path.equal_time_path = None;
    let map = row(
        "map-pcf3",
        "shadow map 1024², PCF 3, \"soft\"",
        "shadows",
        0.31,
        0.004,
    );
    let mut gtao = row("gtao", "GTAO <b>&\"", "ambient occlusion", 0.55, 0.009);
    gtao.approximates = "ao".into();
    gtao.quantity = errors(0.2, 0.1);
    gtao.quantity_image = Some("rows/gtao-quantity.png".into());
    gtao.cost.bake_seconds = Some(0.5);
    let mut lightmap = row("lightmap", "light map, 64 texels/m", "bakes", 0.02, 0.001);
    lightmap.cost.bake_seconds = Some(30.0);
    Study {
        scene: "scenes/cornell.toml".into(),
        width: 64,
        height: 48,
        adapter: Some("llvmpipe (LLVM 15.0.6, 256 bits)".into()),
        version: "0.1.0".into(),
        truths: vec![
            truth("path", "full GI", "truth.png"),
            truth("ao", "ambient occlusion kA", "truths/ao.png"),
        ],
        rows: vec![path, map, gtao, lightmap],
        skipped: vec![Skipped {
            id: "rtx".into(),
            label: "hardware ray queries".into(),
            reason: "the adapter has no <ray query> support".into(),
        }],
        total_seconds: 61.0,
    }
}

/// Every image the study references, as small distinct gradient PNGs.
fn write_images(dir: &Path, study: &Study) {
    let mut paths: Vec<&str> = study.truths.iter().map(|t| t.image.as_str()).collect();
    for r in &study.rows {
        paths.extend([r.image.as_str(), r.error_map.as_str()]);
        paths.extend(r.quantity_image.as_deref());
    }
    for (k, rel) in paths.iter().enumerate() {
        let k = k as u32;
        let img = image::RgbImage::from_fn(study.width, study.height, |x, y| {
            image::Rgb([
                (x * 4 + k * 23) as u8,
                (y * 5 + k * 11) as u8,
                255u32.wrapping_sub(x * 2 + y * 2 + k * 7) as u8,
            ])
        });
        let path = dir.join(rel);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        img.save(&path).unwrap();
    }
}

/// A report directory with the images and the report files.
fn report() -> (tempfile::TempDir, Study) {
    let dir = tempfile::tempdir().unwrap();
    let study = study();
    write_images(dir.path(), &study);
    write_report(dir.path(), &study).unwrap();
    (dir, study)
}

// --- the browser --------------------------------------------------------------

/// The browser to run, or `None` when `PENUMBRA_SKIP_BROWSER=1`. Panics,
/// saying how to install one, when none is found.
fn chromium() -> Option<PathBuf> {
    if std::env::var("PENUMBRA_SKIP_BROWSER").as_deref() == Ok("1") {
        eprintln!("note: PENUMBRA_SKIP_BROWSER=1: the study report is not checked in a browser");
        return None;
    }
    if let Some(exe) = std::env::var_os("PENUMBRA_CHROMIUM") {
        return Some(PathBuf::from(exe));
    }
    let names = [
        "chromium",
        "chromium-browser",
        "google-chrome",
        "google-chrome-stable",
    ];
    let path = std::env::var_os("PATH").unwrap_or_default();
    let found = names.iter().find_map(|name| {
        std::env::split_paths(&path)
            .map(|d| d.join(name))
            .find(|p| p.is_file())
    });
    match found {
        Some(exe) => Some(exe),
        None => panic!(
            "no Chromium found (tried {names:?} on PATH): the study report test opens index.html in \
             headless Chromium. Install it (`sudo apt-get install chromium`, or run scripts/test.sh), \
             point PENUMBRA_CHROMIUM at a browser, or set PENUMBRA_SKIP_BROWSER=1 to skip this check"
        ),
    }
}

/// Runs headless `exe` on `url` with `args` in a fresh profile under
/// `work`, killing it after [`BROWSER_TIMEOUT`]; returns its stdout.
/// stderr (dbus and GPU noise) is only shown when it fails.
fn run_chromium(exe: &Path, work: &Path, args: &[String], url: &str) -> String {
    let profile = tempfile::tempdir_in(work).unwrap();
    let stdout_path = work.join("chromium.stdout");
    let stderr_path = work.join("chromium.stderr");
    let mut cmd = Command::new(exe);
    cmd.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        "--no-first-run",
        "--no-default-browser-check",
        "--allow-file-access-from-files",
        "--hide-scrollbars",
    ])
    .arg(format!("--user-data-dir={}", profile.path().display()))
    .args(args)
    .arg(url)
    .stdin(Stdio::null())
    .stdout(std::fs::File::create(&stdout_path).unwrap())
    .stderr(std::fs::File::create(&stderr_path).unwrap());
    #[cfg(unix)]
    std::os::unix::process::CommandExt::process_group(&mut cmd, 0);
    let mut child = cmd
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {}: {e}", exe.display()));
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > BROWSER_TIMEOUT {
            // The browser and its helpers share the process group we made.
            #[cfg(unix)]
            let _ = Command::new("kill")
                .args(["-KILL", "--", &format!("-{}", child.id())])
                .status();
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "{} did not finish within {BROWSER_TIMEOUT:?} on {url}; stderr:\n{}",
                exe.display(),
                tail(&stderr_path)
            );
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    assert!(
        status.success(),
        "{} failed ({status}) on {url}; stderr:\n{}",
        exe.display(),
        tail(&stderr_path)
    );
    std::fs::read_to_string(&stdout_path).unwrap()
}

fn tail(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let lines: Vec<&str> = text.lines().collect();
    lines[lines.len().saturating_sub(30)..].join("\n")
}

fn file_url(path: &Path) -> String {
    format!("file://{}", path.canonicalize().unwrap().display())
}

// --- the DOM check ------------------------------------------------------------

/// The numeric columns the harness sorts by (keys of `th[data-key]`), in
/// turn; the one with empty values first, so its empties keep the study's
/// order.
const SORT_KEYS: &[&str] = &["bake-seconds", "full-rel-mse", "seconds"];

/// A page that loads `index.html` in an iframe, clicks through it and
/// writes what it found as JSON into `<pre id="result">`.
fn harness(truth_image: &str) -> String {
    let config = serde_json::json!({ "sortKeys": SORT_KEYS, "truth": truth_image });
    HARNESS.replace("CONFIG_JSON", &config.to_string())
}

const HARNESS: &str = r#"<!doctype html>
<html><head><meta charset="utf-8"><title>report harness</title></head>
<body>
<pre id="result">pending</pre>
<iframe id="report" width="1280" height="1600"></iframe>
<script>
"use strict";
const CONFIG = CONFIG_JSON;
const found = { errors: [] };
const out = document.getElementById("result");
const publish = () => { out.textContent = JSON.stringify(found); };
window.addEventListener("error", e => { found.errors.push(String(e.message)); publish(); });
const sleep = ms => new Promise(r => setTimeout(r, ms));
async function loaded(images) {
  for (let i = 0; i < 200 && !images().every(im => im.complete); i++) await sleep(50);
}
const frame = document.getElementById("report");
frame.addEventListener("load", async () => {
  try {
    const doc = frame.contentDocument;
    if (!doc) throw new Error("the report's document is not readable (file access)");
    frame.contentWindow.addEventListener("error", e => found.errors.push("report: " + e.message));
    const images = () => Array.from(doc.images);
    await loaded(images);
    const rows = () => Array.from(doc.querySelectorAll("tr[data-row-id]"));
    const order = () => rows().map(tr => tr.getAttribute("data-row-id"));
    found.rows = rows().length;
    found.images = images().length;
    found.broken = images().filter(im => !(im.complete && im.naturalWidth > 0)).map(im => im.getAttribute("src"));
    found.labels = Object.fromEntries(rows().map(tr => [tr.getAttribute("data-row-id"), tr.cells[0].textContent]));
    found.initial = order();
    found.sorts = {};
    for (const key of CONFIG.sortKeys) {
      const th = doc.querySelector('th[data-key="' + key + '"]');
      if (!th) throw new Error("no header " + key);
      th.click();
      const up = order();
      th.click();
      found.sorts[key] = [up, order()];
    }
    const img = doc.querySelector("img.row-image[data-truth-src]");
    const caption = img.parentNode.querySelector("figcaption");
    const flip = { row: img.closest("[data-card-id]").getAttribute("data-card-id"), before: img.getAttribute("src"), captionBefore: caption.textContent };
    img.click();
    flip.after = img.getAttribute("src");
    flip.captionAfter = caption.textContent;
    await loaded(() => [img]);
    flip.afterLoaded = img.complete && img.naturalWidth > 0;
    img.click();
    flip.back = img.getAttribute("src");
    flip.captionBack = caption.textContent;
    found.flip = flip;
    found.done = true;
  } catch (e) {
    found.errors.push(String(e && e.stack || e));
  }
  publish();
});
frame.src = "index.html";
</script>
</body></html>
"#;

/// The JSON the harness left in the dumped DOM.
fn harness_result(dom: &str) -> serde_json::Value {
    let start = dom
        .find("<pre id=\"result\">")
        .unwrap_or_else(|| panic!("no result element in the dumped DOM:\n{dom}"))
        + "<pre id=\"result\">".len();
    let end = start
        + dom[start..]
            .find("</pre>")
            .expect("the result element's end");
    let text = dom[start..end]
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&nbsp;", "\u{a0}")
        .replace("&amp;", "&");
    serde_json::from_str(&text)
        .unwrap_or_else(|e| panic!("the harness did not finish ({e}); it left: {text}"))
}

/// The number a column sorts a row by (`None`: an empty cell).
type SortValue = fn(&Row) -> Option<f64>;

/// Row ids ordered by `value` ascending and descending, rows without a
/// value last in table order (the page's sort is stable).
fn expected_orders(
    study: &Study,
    value: impl Fn(&Row) -> Option<f64>,
) -> (Vec<String>, Vec<String>) {
    let mut with: Vec<(&Row, f64)> = study
        .rows
        .iter()
        .filter_map(|r| value(r).map(|v| (r, v)))
        .collect();
    with.sort_by(|a, b| a.1.total_cmp(&b.1));
    let without = study
        .rows
        .iter()
        .filter(|r| value(r).is_none())
        .map(|r| r.id.clone());
    let up: Vec<String> = with
        .iter()
        .map(|(r, _)| r.id.clone())
        .chain(without.clone())
        .collect();
    let down: Vec<String> = with
        .iter()
        .rev()
        .map(|(r, _)| r.id.clone())
        .chain(without)
        .collect();
    (up, down)
}

fn strings(v: &serde_json::Value) -> Vec<String> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|s| s.as_str().unwrap().to_string())
        .collect()
}

#[test]
fn report_works_in_chromium() {
    let Some(exe) = chromium() else { return };
    let (dir, study) = report();
    let harness_path = dir.path().join("harness.html");
    std::fs::write(&harness_path, harness(&study.truths[0].image)).unwrap();
    let dom = run_chromium(
        &exe,
        dir.path(),
        &["--virtual-time-budget=10000".into(), "--dump-dom".into()],
        &file_url(&harness_path),
    );
    let found = harness_result(&dom);
    assert_eq!(
        found["errors"],
        serde_json::json!([]),
        "script errors: {found:#}"
    );
    assert_eq!(found["done"], true, "{found:#}");

    assert_eq!(
        found["rows"],
        study.rows.len(),
        "tr[data-row-id] count: {found:#}"
    );
    let ids: Vec<String> = study.rows.iter().map(|r| r.id.clone()).collect();
    assert_eq!(strings(&found["initial"]), ids, "initial order");
    for r in &study.rows {
        assert_eq!(
            found["labels"][&r.id],
            r.label.as_str(),
            "label of {} (escaping)",
            r.id
        );
    }

    // Truths, row images, error maps, quantity images and the plot.
    let expected_images = study.truths.len()
        + study.rows.len() * 2
        + study
            .rows
            .iter()
            .filter(|r| r.quantity_image.is_some())
            .count()
        + 1;
    assert_eq!(found["images"], expected_images, "{found:#}");
    assert_eq!(
        found["broken"],
        serde_json::json!([]),
        "images that did not load"
    );

    let by_key: [(&str, SortValue); 3] = [
        ("bake-seconds", |r| r.cost.bake_seconds),
        ("full-rel-mse", |r| Some(r.full.rel_mse)),
        ("seconds", |r| Some(r.cost.seconds)),
    ];
    assert_eq!(by_key.map(|(k, _)| k), SORT_KEYS);
    for (key, value) in by_key {
        let (up, down) = expected_orders(&study, value);
        assert_ne!(
            up, ids,
            "{key}: the study's order must differ from the sorted one"
        );
        let got = &found["sorts"][key];
        assert_eq!(strings(&got[0]), up, "first click on {key} sorts ascending");
        assert_eq!(
            strings(&got[1]),
            down,
            "second click on {key} sorts descending"
        );
    }

    let flip = &found["flip"];
    let row = study
        .rows
        .iter()
        .find(|r| flip["row"] == r.id.as_str())
        .expect("flipped row");
    let truth = &study.truths[0];
    assert_eq!(flip["before"], row.image.as_str(), "{flip:#}");
    assert_eq!(
        flip["after"],
        truth.image.as_str(),
        "click flips to the truth: {flip:#}"
    );
    assert_eq!(flip["afterLoaded"], true, "the truth image loads: {flip:#}");
    assert_eq!(
        flip["back"],
        row.image.as_str(),
        "second click flips back: {flip:#}"
    );
    let caption = |k: &str| flip[k].as_str().unwrap().to_string();
    assert!(caption("captionBefore").contains(&row.label), "{flip:#}");
    assert!(caption("captionAfter").contains(&truth.label), "{flip:#}");
    assert_eq!(caption("captionBack"), caption("captionBefore"), "{flip:#}");
}

#[test]
fn report_screenshot_is_not_blank() {
    let Some(exe) = chromium() else { return };
    let (dir, _) = report();
    let shot = dir.path().join("screenshot.png");
    run_chromium(
        &exe,
        dir.path(),
        &[
            format!("--screenshot={}", shot.display()),
            "--window-size=1280,1600".into(),
        ],
        &file_url(&dir.path().join("index.html")),
    );
    let img = image::open(&shot)
        .unwrap_or_else(|e| panic!("no screenshot at {}: {e}", shot.display()))
        .to_rgb8();
    let mut counts = std::collections::HashMap::<[u8; 3], usize>::new();
    for p in img.pixels() {
        *counts.entry(p.0).or_default() += 1;
    }
    let total = (img.width() * img.height()) as usize;
    let most = counts.values().copied().max().unwrap_or(0);
    assert!(
        counts.len() >= 300,
        "only {} distinct colours in the {}x{} screenshot",
        counts.len(),
        img.width(),
        img.height()
    );
    assert!(
        most * 100 <= total * 99,
        "one colour covers {most} of {total} pixels"
    );
}
