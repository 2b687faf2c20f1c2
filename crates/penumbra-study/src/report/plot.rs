//! `error-vs-time.svg`: each row's relMSE against full GI over its frame
//! or render time, both axes logarithmic, one colour per group.

use crate::row::Study;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Distinct colours for the groups, in order of first appearance.
const GROUP_COLOURS: [RGBColor; 8] = [
    RGBColor(0x1f, 0x77, 0xb4),
    RGBColor(0xd6, 0x27, 0x28),
    RGBColor(0x2c, 0xa0, 0x2c),
    RGBColor(0xff, 0x7f, 0x0e),
    RGBColor(0x94, 0x67, 0xbd),
    RGBColor(0x8c, 0x56, 0x4b),
    RGBColor(0xe3, 0x77, 0xc2),
    RGBColor(0x17, 0xbe, 0xcf),
];

/// One point: (seconds, relMSE), both > 0, with the row id.
struct Point<'a> {
    group: &'a str,
    id: &'a str,
    x: f64,
    y: f64,
}

/// The plot as an SVG document. Rows whose time or error is NaN or
/// infinite are left out; zeros are drawn at a floor below the smallest
/// positive value.
pub fn error_vs_time_svg(study: &Study) -> String {
    let finite = |v: f64| v.is_finite();
    let rows: Vec<_> = study
        .rows
        .iter()
        .filter(|r| finite(r.cost.seconds) && finite(r.full.rel_mse))
        .collect();
    // A decade below the smallest positive value (`default` when none).
    let floor_of = |values: &mut dyn Iterator<Item = f64>, default: f64| {
        let min = values.filter(|&v| v > 0.0).fold(f64::INFINITY, f64::min);
        if min.is_finite() { min / 10.0 } else { default }
    };
    let x_floor = floor_of(&mut rows.iter().map(|r| r.cost.seconds), 1e-4);
    let y_floor = floor_of(&mut rows.iter().map(|r| r.full.rel_mse), 1e-6);
    let points: Vec<Point> = rows
        .iter()
        .map(|r| Point {
            group: &r.group,
            id: &r.id,
            x: r.cost.seconds.max(x_floor),
            y: r.full.rel_mse.max(y_floor),
        })
        .collect();
    let mut groups: Vec<&str> = Vec::new();
    for p in &points {
        if !groups.contains(&p.group) {
            groups.push(p.group);
        }
    }

    let mut svg = String::new();
    let drawn = (|| -> Result<(), Box<dyn std::error::Error + '_>> {
        let root = SVGBackend::with_string(&mut svg, (860, 480)).into_drawing_area();
        root.fill(&WHITE)?;
        let (plot_area, legend_area) = root.split_horizontally(700);
        let x_range = log_range(points.iter().map(|p| p.x));
        let mut chart = ChartBuilder::on(&plot_area)
            .caption("Error against full GI vs time", ("sans-serif", 22))
            .margin(14)
            .x_label_area_size(48)
            .y_label_area_size(78)
            .build_cartesian_2d(
                x_range.clone().log_scale(),
                log_range(points.iter().map(|p| p.y)).log_scale(),
            )?;
        chart
            .configure_mesh()
            .x_desc("frame / render time [s] (bakes excluded)")
            .y_desc("relMSE vs full GI")
            .x_label_formatter(&|v| axis_number(*v))
            .y_label_formatter(&|v| axis_number(*v))
            .label_style(("sans-serif", 15))
            .axis_desc_style(("sans-serif", 16))
            .draw()?;
        // Labels sit beside their point, on the side with more room.
        let right_half = |x: f64| x.ln() > (x_range.start.ln() + x_range.end.ln()) / 2.0;
        chart.draw_series(points.iter().map(|p| {
            let colour = colour_of(&groups, p.group);
            let (offset, anchor) = if right_half(p.x) {
                ((-9, 0), HPos::Right)
            } else {
                ((9, 0), HPos::Left)
            };
            let font = ("sans-serif", 15)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(anchor, VPos::Center));
            EmptyElement::at((p.x, p.y))
                + Circle::new((0, 0), 5, colour.filled())
                + Text::new(p.id.to_string(), offset, font)
        }))?;
        // The legend, beside the plot.
        legend_area.draw(&Text::new("group", (8, 40), ("sans-serif", 16).into_font()))?;
        for (i, group) in groups.iter().enumerate() {
            let y = 66 + 22 * i as i32;
            let colour = colour_of(&groups, group);
            legend_area.draw(&Rectangle::new([(8, y), (20, y + 12)], colour.filled()))?;
            legend_area.draw(&Text::new(
                group.to_string(),
                (28, y - 1),
                ("sans-serif", 15),
            ))?;
        }
        root.present()?;
        Ok(())
    })()
    .is_ok();
    if !drawn {
        // Cannot happen on a string backend; keep the file a valid SVG.
        return "<svg xmlns=\"http://www.w3.org/2000/svg\"/>\n".to_string();
    }
    svg
}

fn colour_of(groups: &[&str], group: &str) -> RGBColor {
    let i = groups.iter().position(|g| *g == group).unwrap_or(0);
    GROUP_COLOURS[i % GROUP_COLOURS.len()]
}

/// A log-axis range around `values` (all > 0), half a decade of room on
/// each side; `[1e-3, 1]` when empty.
fn log_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !(lo.is_finite() && hi > 0.0) {
        return 1e-3..1.0;
    }
    let pad = 10f64.sqrt();
    lo / pad..(hi * pad).max(lo * 10.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_marker_per_row() {
        let mut study = crate::report::sample_study();
        let svg = error_vs_time_svg(&study);
        assert!(svg.starts_with("<svg"), "{svg}");
        assert_eq!(svg.matches("<circle").count(), study.rows.len(), "{svg}");
        for row in &study.rows {
            assert!(
                svg.contains(&format!("\n{}\n</text>", row.id)),
                "{}",
                row.id
            );
        }
        for group in ["shadows", "ray tracing"] {
            assert!(
                svg.contains(&format!("\n{group}\n</text>")),
                "legend: {group}"
            );
        }
        // NaN rows are left out; the rest still plots.
        study.rows[0].full.rel_mse = f64::NAN;
        let svg = error_vs_time_svg(&study);
        assert_eq!(svg.matches("<circle").count(), study.rows.len() - 1);
        // No rows at all: still a plot.
        study.rows.clear();
        assert!(error_vs_time_svg(&study).starts_with("<svg"));
    }
}

/// A tick label of a log axis: 3 significant digits, no float noise
/// (0.30000000000000004 is "0.3").
fn axis_number(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = (2 - v.abs().log10().floor() as i32).max(0) as usize;
    if v.abs() >= 1e-3 && v.abs() < 1e5 {
        let s = format!("{v:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.2e}")
    }
}

#[cfg(test)]
mod axis_tests {
    use super::axis_number;

    #[test]
    fn tick_labels_have_no_float_noise() {
        assert_eq!(axis_number(0.1 + 0.2), "0.3");
        assert_eq!(axis_number(0.001), "0.001");
        assert_eq!(axis_number(2.0), "2");
        assert_eq!(axis_number(12.5), "12.5");
        assert_eq!(axis_number(300.0), "300");
        assert_eq!(axis_number(2.5e-5), "2.50e-5");
    }
}
