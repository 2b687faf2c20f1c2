//! `index.html`: the report page, rendered by the `index.html.j2`
//! template (auto-escaped) from a view of the study with its numbers
//! already formatted.

use crate::row::{Errors, Row, Study, Truth};
use minijinja::{AutoEscape, Environment, UndefinedBehavior};
use serde::Serialize;

const TEMPLATE_NAME: &str = "index.html.j2";
const TEMPLATE: &str = include_str!("index.html.j2");

/// The page for `study`; images are referenced by their relative paths.
pub fn index_html(study: &Study) -> Result<String, minijinja::Error> {
    let mut env = Environment::new();
    env.set_auto_escape_callback(|_| AutoEscape::Html);
    env.set_undefined_behavior(UndefinedBehavior::Strict);
    env.set_trim_blocks(true);
    env.set_lstrip_blocks(true);
    env.add_template(TEMPLATE_NAME, TEMPLATE)?;
    env.get_template(TEMPLATE_NAME)?.render(Page::of(study))
}

/// What the template sees.
#[derive(Debug, Serialize)]
struct Page<'a> {
    scene: &'a str,
    resolution: String,
    width: u32,
    height: u32,
    adapter: &'a str,
    version: &'a str,
    total_seconds: String,
    truths: Vec<TruthView<'a>>,
    /// The full-GI truth a row image flips to (URL), if any.
    truth_image: Option<String>,
    truth_label: &'a str,
    columns: &'static [Column],
    rows: Vec<RowView<'a>>,
    skipped: &'a [crate::row::Skipped],
    /// CSS gradient of the FLIP error-map colours on [0, 1].
    flip_gradient: String,
    plot: &'static str,
}

#[derive(Debug, Serialize)]
struct TruthView<'a> {
    id: &'a str,
    label: &'a str,
    source: &'a str,
    image: String,
    image_exr: String,
    noise: String,
    spp: String,
    seconds: String,
}

/// A table column: `key` names it (`th[data-key]`), `numeric` selects the
/// sort.
#[derive(Debug, Serialize)]
struct Column {
    key: &'static str,
    title: &'static str,
    numeric: bool,
    tip: &'static str,
}

const COLUMNS: &[Column] = &[
    Column {
        key: "technique",
        title: "technique",
        numeric: false,
        tip: "the technique (links to its card)",
    },
    Column {
        key: "group",
        title: "group",
        numeric: false,
        tip: "family of techniques",
    },
    Column {
        key: "approximates",
        title: "approximates",
        numeric: false,
        tip: "the truth this technique approximates",
    },
    Column {
        key: "quantity-rel-mse",
        title: "relMSE vs quantity",
        numeric: true,
        tip: "relMSE against the truth of the quantity it approximates",
    },
    Column {
        key: "full-rel-mse",
        title: "relMSE vs full GI",
        numeric: true,
        tip: "relMSE against the full-GI (path) truth",
    },
    Column {
        key: "full-flip-mean",
        title: "FLIP mean",
        numeric: true,
        tip: "mean HDR-FLIP against full GI",
    },
    Column {
        key: "full-flip-p99",
        title: "FLIP p99",
        numeric: true,
        tip: "99th percentile of HDR-FLIP against full GI",
    },
    Column {
        key: "full-mean-ratio",
        title: "mean ratio r/g/b",
        numeric: true,
        tip: "mean(image) / mean(full GI) per channel (1 = same energy); sorts by their average",
    },
    Column {
        key: "equal-time-rel-mse",
        title: "equal-time path relMSE",
        numeric: true,
        tip: "path tracing given this row's time, against full GI (spp in brackets)",
    },
    Column {
        key: "bake-seconds",
        title: "bake s",
        numeric: true,
        tip: "precomputation time",
    },
    Column {
        key: "seconds",
        title: "time s",
        numeric: true,
        tip: "frame time (raster) or render time (ray tracing)",
    },
    Column {
        key: "peak-memory-mib",
        title: "memory MiB",
        numeric: true,
        tip: "how far resident memory rose above its size at the row's start, at its peak",
    },
];

/// One table cell: the text shown and the raw value it sorts by.
#[derive(Debug, Serialize)]
struct Cell {
    text: String,
    value: String,
}

#[derive(Debug, Serialize)]
struct RowView<'a> {
    id: &'a str,
    label: &'a str,
    group: &'a str,
    approximates: &'a str,
    command: &'a str,
    notes: &'a [String],
    image: String,
    image_exr: String,
    error_map: String,
    quantity_image: Option<String>,
    cells: Vec<Cell>,
    /// The card's metrics, `(what, value)`.
    metrics: Vec<(String, String)>,
}

impl<'a> Page<'a> {
    fn of(study: &'a Study) -> Self {
        let full = study.truths.first();
        Page {
            scene: &study.scene,
            resolution: format!("{} × {}", study.width, study.height),
            width: study.width,
            height: study.height,
            adapter: study.adapter.as_deref().unwrap_or("none (no raster rows)"),
            version: &study.version,
            total_seconds: seconds(study.total_seconds),
            truths: study.truths.iter().map(TruthView::of).collect(),
            truth_image: full.map(|t| url_path(&t.image)),
            truth_label: full.map_or("full GI", |t| &t.label),
            columns: COLUMNS,
            rows: study.rows.iter().map(RowView::of).collect(),
            skipped: &study.skipped,
            flip_gradient: flip_gradient(),
            plot: super::PLOT_FILE,
        }
    }
}

impl<'a> TruthView<'a> {
    fn of(t: &'a Truth) -> Self {
        TruthView {
            id: &t.id,
            label: &t.label,
            source: &t.source,
            image: url_path(&t.image),
            image_exr: url_path(&t.image_exr),
            noise: t.noise_rel_mse.map_or("— (given reference)".into(), sig),
            spp: t.spp.map_or(String::new(), |s| s.to_string()),
            seconds: seconds(t.seconds),
        }
    }
}

impl<'a> RowView<'a> {
    fn of(r: &'a Row) -> Self {
        let num = |v: f64, text: String| Cell {
            text,
            value: raw(v),
        };
        let none = || Cell {
            text: "—".into(),
            value: String::new(),
        };
        let text = |s: &str| Cell {
            text: s.into(),
            value: s.into(),
        };
        let et = r.equal_time_path.as_ref();
        let cells = vec![
            text(&r.label),
            text(&r.group),
            text(&r.approximates),
            num(r.quantity.rel_mse, sig(r.quantity.rel_mse)),
            num(r.full.rel_mse, sig(r.full.rel_mse)),
            num(r.full.flip_mean, flip(r.full.flip_mean)),
            num(r.full.flip_p99, flip(r.full.flip_p99)),
            num(r.full.mean_ratio.iter().sum::<f64>() / 3.0, ratio(&r.full)),
            et.map_or_else(none, |e| {
                num(
                    e.full.rel_mse,
                    format!("{} ({} spp)", sig(e.full.rel_mse), e.spp),
                )
            }),
            r.cost
                .bake_seconds
                .map_or_else(none, |s| num(s, seconds(s))),
            num(r.cost.seconds, seconds(r.cost.seconds)),
            r.cost
                .peak_memory_mib
                .map_or_else(none, |m| num(m, format!("{m:.0}"))),
        ];
        let errors = |e: &Errors| {
            format!(
                "relMSE {} · FLIP mean {} · p99 {} · mean ratio {}",
                sig(e.rel_mse),
                flip(e.flip_mean),
                flip(e.flip_p99),
                ratio(e)
            )
        };
        let mut metrics = vec![
            (format!("vs {}", r.approximates), errors(&r.quantity)),
            ("vs full GI".to_string(), errors(&r.full)),
        ];
        if let Some(e) = et {
            metrics.push((
                "equal-time path".into(),
                format!(
                    "{} spp in {} s: {}",
                    e.spp,
                    seconds(e.seconds),
                    errors(&e.full)
                ),
            ));
        }
        let mut cost = format!("{} s", seconds(r.cost.seconds));
        if let Some(b) = r.cost.bake_seconds {
            cost += &format!(" + bake {} s", seconds(b));
        }
        if let Some(m) = r.cost.peak_memory_mib {
            cost += &format!(" · memory +{m:.0} MiB at peak");
        }
        metrics.push(("cost".into(), cost));
        metrics.push(("engine".into(), r.engine.clone()));
        RowView {
            id: &r.id,
            label: &r.label,
            group: &r.group,
            approximates: &r.approximates,
            command: &r.command,
            notes: &r.notes,
            image: url_path(&r.image),
            image_exr: url_path(&r.image_exr),
            error_map: url_path(&r.error_map),
            quantity_image: r.quantity_image.as_deref().map(url_path),
            cells,
            metrics,
        }
    }
}

/// The raw number for `data-value` (round-trips; empty for NaN so it
/// sorts last).
fn raw(v: f64) -> String {
    if v.is_nan() {
        String::new()
    } else {
        v.to_string()
    }
}

/// Three significant digits, scientific outside [0.01, 10⁴).
fn sig(v: f64) -> String {
    sig_from(v, 0.01)
}

/// Seconds: three significant digits, scientific below a millisecond.
fn seconds(v: f64) -> String {
    sig_from(v, 0.001)
}

/// Three significant digits, fixed-point in [lo, 10⁴), scientific outside.
fn sig_from(v: f64, lo: f64) -> String {
    let a = v.abs();
    if !v.is_finite() || v == 0.0 {
        format!("{v}")
    } else if !(lo..1e4).contains(&a) {
        format!("{v:.2e}")
    } else {
        let decimals = (2 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.decimals$}")
    }
}

fn flip(v: f64) -> String {
    format!("{v:.3}")
}

fn ratio(e: &Errors) -> String {
    let [r, g, b] = e.mean_ratio;
    format!("{r:.3} / {g:.3} / {b:.3}")
}

/// `path` as a relative URL: bytes other than unreserved characters and
/// `/` percent-encoded.
fn url_path(path: &str) -> String {
    let mut out = String::with_capacity(path.len());
    for b in path.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~/".contains(&b) {
            out.push(b as char);
        } else {
            out += &format!("%{b:02X}");
        }
    }
    out
}

/// The colours `penumbra_image::flip_heatmap` gives FLIP 0, 0.1, …, 1, as
/// a CSS gradient.
fn flip_gradient() -> String {
    const STOPS: usize = 11;
    let ramp = penumbra_image::Image {
        width: STOPS as u32,
        height: 1,
        pixels: (0..STOPS)
            .map(|i| glam::Vec3::splat(i as f32 / (STOPS - 1) as f32))
            .collect(),
    };
    let heat = penumbra_image::flip_heatmap(&ramp);
    let bytes = penumbra_image::tonemap_to_srgb8(&heat, &penumbra_image::ToneMapping::CLAMP);
    let stops: Vec<String> = bytes
        .chunks_exact(3)
        .enumerate()
        .map(|(i, c)| format!("rgb({},{},{}) {}%", c[0], c[1], c[2], i * 100 / (STOPS - 1)))
        .collect();
    format!("linear-gradient(to right, {})", stops.join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_strings_from_the_data() {
        let study = crate::report::sample_study();
        let html = index_html(&study).unwrap();
        assert!(!html.contains("<b>&\""), "raw label in the page");
        assert!(
            html.contains("&lt;b&gt;&amp;&quot;"),
            "escaped label missing"
        );
        assert!(!html.contains("<adapter>") && html.contains("&lt;adapter&gt;"));
        assert_eq!(html.matches("<tr data-row-id=").count(), study.rows.len());
        assert!(html.contains("data-row-id=\"odd\""));
    }

    #[test]
    fn formats() {
        assert_eq!(sig(0.0512), "0.0512");
        assert_eq!(sig(1.234), "1.23");
        assert_eq!(sig(123.4), "123");
        assert_eq!(sig(0.000123), "1.23e-4");
        assert_eq!(sig(0.0), "0");
        assert_eq!(seconds(0.009), "0.00900");
        assert_eq!(seconds(0.0002), "2.00e-4");
        assert_eq!(url_path("rows/a b#1.png"), "rows/a%20b%231.png");
        assert_eq!(raw(f64::NAN), "");
        assert!(flip_gradient().starts_with("linear-gradient(to right, rgb("));
    }
}
