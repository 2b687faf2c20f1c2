//! The convergence record as CSV and as an SVG plot (unshot power over
//! iterations, log scale).

use crate::convergence::ConvergenceStep;
use plotters::prelude::*;

/// `iteration,shooter,unshot_power_w,unshot_fraction,seconds`, one row per
/// step.
pub fn convergence_csv(steps: &[ConvergenceStep]) -> String {
    let mut out = String::from("iteration,shooter,unshot_power_w,unshot_fraction,seconds\n");
    for s in steps {
        out += &format!(
            "{},{},{:e},{:e},{:.6}\n",
            s.iteration,
            s.shooter.map_or(String::new(), |p| p.to_string()),
            s.unshot_power,
            s.unshot_fraction,
            s.seconds
        );
    }
    out
}

/// Most points the plot draws; longer records are thinned evenly (the
/// CSV keeps every step).
const MAX_PLOTTED: usize = 2000;

/// The unshot fraction against the iteration, log-scaled, as an SVG
/// document.
pub fn convergence_svg(steps: &[ConvergenceStep]) -> String {
    let mut svg = String::new();
    let ok = (|| -> Result<(), Box<dyn std::error::Error + '_>> {
        let root = SVGBackend::with_string(&mut svg, (720, 420)).into_drawing_area();
        root.fill(&WHITE)?;
        let last = steps.last().map_or(1, |s| s.iteration.max(1));
        let floor = steps
            .iter()
            .map(|s| s.unshot_fraction)
            .filter(|&f| f > 0.0)
            .fold(1.0f64, f64::min)
            .max(1e-12);
        let top = steps
            .iter()
            .map(|s| s.unshot_fraction)
            .fold(floor * 10.0, f64::max);
        let mut chart = ChartBuilder::on(&root)
            .caption(
                "Radiosity: unshot power / emitted power",
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(0u32..last, (floor * 0.5..top * 1.5).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("iteration (shots)")
            .y_desc("unshot fraction")
            .draw()?;
        let stride = steps.len().div_ceil(MAX_PLOTTED).max(1);
        let thinned = steps
            .iter()
            .enumerate()
            .filter(|(i, _)| i % stride == 0 || i + 1 == steps.len())
            .map(|(_, s)| s);
        chart.draw_series(LineSeries::new(
            thinned
                .filter(|s| s.unshot_fraction > 0.0)
                .map(|s| (s.iteration, s.unshot_fraction)),
            &BLUE,
        ))?;
        root.present()?;
        Ok(())
    })()
    .is_ok();
    if !ok {
        // Plotting cannot fail on a string backend; keep the file valid.
        return "<svg xmlns=\"http://www.w3.org/2000/svg\"/>\n".to_string();
    }
    svg
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_and_svg_hold_every_step() {
        let steps: Vec<ConvergenceStep> = (0..5)
            .map(|i| ConvergenceStep {
                iteration: i,
                shooter: (i > 0).then_some(i * 7),
                unshot_power: 10.0 * 0.5f64.powi(i as i32),
                unshot_fraction: 0.5f64.powi(i as i32),
                seconds: i as f64 * 0.1,
            })
            .collect();
        let csv = convergence_csv(&steps);
        assert_eq!(csv.lines().count(), 6);
        assert!(csv.lines().nth(2).unwrap().starts_with("1,7,5e0,5e-1,"));
        let svg = convergence_svg(&steps);
        assert!(svg.starts_with("<svg") && svg.contains("polyline"), "{svg}");
    }
}
