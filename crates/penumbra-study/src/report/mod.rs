//! The files of a study's report directory, written from a [`Study`] once
//! the runner has put the images there: `study.json`, `study.csv`,
//! `error-vs-time.svg` and `index.html`.

mod csv;
mod html;
mod plot;

pub use csv::study_csv;
pub use html::index_html;
pub use plot::error_vs_time_svg;

use crate::row::Study;
use std::path::{Path, PathBuf};

/// File names of the report, relative to its directory.
pub const JSON_FILE: &str = "study.json";
pub const CSV_FILE: &str = "study.csv";
pub const PLOT_FILE: &str = "error-vs-time.svg";
pub const HTML_FILE: &str = "index.html";

/// A report file that could not be made or written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error("cannot write {}: {cause}", path.display())]
    Io {
        path: PathBuf,
        cause: std::io::Error,
    },
    #[error("cannot serialise {}: {cause}", path.display())]
    Json {
        path: PathBuf,
        cause: serde_json::Error,
    },
    #[error("cannot render {}: {cause}", path.display())]
    Template {
        path: PathBuf,
        cause: minijinja::Error,
    },
}

/// Writes `study.json`, `study.csv`, `error-vs-time.svg` and `index.html`
/// into `dir` (created if missing). Image paths in `study` are relative to
/// `dir`; the images themselves are not touched.
pub fn write_report(dir: &Path, study: &Study) -> Result<(), ReportError> {
    std::fs::create_dir_all(dir).map_err(|cause| ReportError::Io {
        path: dir.to_path_buf(),
        cause,
    })?;
    let json_path = dir.join(JSON_FILE);
    let json = serde_json::to_string_pretty(study).map_err(|cause| ReportError::Json {
        path: json_path.clone(),
        cause,
    })?;
    write(&json_path, json + "\n")?;
    write(&dir.join(CSV_FILE), study_csv(study))?;
    write(&dir.join(PLOT_FILE), error_vs_time_svg(study))?;
    let html_path = dir.join(HTML_FILE);
    let html = index_html(study).map_err(|cause| ReportError::Template {
        path: html_path.clone(),
        cause,
    })?;
    write(&html_path, html)
}

fn write(path: &Path, contents: String) -> Result<(), ReportError> {
    std::fs::write(path, contents).map_err(|cause| ReportError::Io {
        path: path.to_path_buf(),
        cause,
    })
}

/// A small study for the tests of this module.
#[cfg(test)]
pub(crate) fn sample_study() -> Study {
    use crate::row::{Cost, EqualTime, Errors, Row, Skipped, Truth};
    let errors = |r: f64| Errors {
        rel_mse: r,
        flip_mean: r / 10.0,
        flip_p99: r / 2.0,
        mean_ratio: [1.0, 0.98, 1.02],
    };
    let row = |id: &str, label: &str, group: &str, r: f64, s: f64| Row {
        id: id.into(),
        label: label.into(),
        group: group.into(),
        engine: "raster".into(),
        command: format!("penumbra render --technique {id}"),
        approximates: "path".into(),
        image: format!("rows/{id}.png"),
        image_exr: format!("rows/{id}.exr"),
        error_map: format!("rows/{id}-error.png"),
        quantity_image: None,
        quantity: errors(r),
        full: errors(r),
        equal_time_path: Some(EqualTime {
            spp: 4,
            seconds: s,
            full: errors(r * 2.0),
        }),
        cost: Cost {
            bake_seconds: None,
            seconds: s,
            peak_memory_mib: Some(512.0),
        },
        notes: vec!["a note".into()],
    };
    Study {
        scene: "scenes/cornell.toml".into(),
        width: 64,
        height: 48,
        adapter: Some("llvmpipe".into()),
        version: "0.1.0".into(),
        truths: vec![Truth {
            id: "path".into(),
            label: "full GI".into(),
            source: "path, 1024 spp, seed 7".into(),
            image: "truth.png".into(),
            image_exr: "truth.exr".into(),
            noise_rel_mse: Some(1e-4),
            spp: Some(1024),
            seconds: 10.0,
        }],
        rows: vec![
            row("map", "shadow map, PCF 3", "shadows", 0.05, 0.002),
            row("odd", "<b>&\"", "shadows", 0.0, 0.0),
            row("whitted", "Whitted \"classic\"", "ray tracing", 0.3, 1.5),
        ],
        skipped: vec![Skipped {
            id: "rtx".into(),
            label: "hardware ray tracing".into(),
            reason: "no <adapter> support".into(),
        }],
        total_seconds: 42.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_round_trips() {
        let study = sample_study();
        let dir = tempfile::tempdir().unwrap();
        write_report(dir.path(), &study).unwrap();
        let json = std::fs::read_to_string(dir.path().join(JSON_FILE)).unwrap();
        let back: Study = serde_json::from_str(&json).unwrap();
        assert_eq!(back, study);
        for f in [CSV_FILE, PLOT_FILE, HTML_FILE] {
            assert!(dir.path().join(f).is_file(), "{f}");
        }
    }

    #[test]
    fn error_names_the_file() {
        let dir = tempfile::tempdir().unwrap();
        // A directory where study.csv should go makes that write fail.
        std::fs::create_dir(dir.path().join(CSV_FILE)).unwrap();
        let err = write_report(dir.path(), &sample_study()).unwrap_err();
        assert!(err.to_string().contains(CSV_FILE), "{err}");
    }
}
