//! `study.csv`: one line per row, numbers as `{}` prints them (they
//! round-trip), empty fields for missing values.

use crate::row::{Errors, Study};

const HEADER: &[&str] = &[
    "id",
    "label",
    "group",
    "engine",
    "approximates",
    "quantity_rel_mse",
    "quantity_flip_mean",
    "quantity_flip_p99",
    "quantity_mean_ratio_r",
    "quantity_mean_ratio_g",
    "quantity_mean_ratio_b",
    "full_rel_mse",
    "full_flip_mean",
    "full_flip_p99",
    "full_mean_ratio_r",
    "full_mean_ratio_g",
    "full_mean_ratio_b",
    "equal_time_path_spp",
    "equal_time_path_rel_mse",
    "equal_time_path_flip_mean",
    "bake_seconds",
    "seconds",
    "peak_memory_mib",
];

/// The CSV text of `study` (header line, then one line per row).
pub fn study_csv(study: &Study) -> String {
    let mut out = line(HEADER.iter().map(|h| h.to_string()));
    for row in &study.rows {
        let mut fields = vec![
            row.id.clone(),
            row.label.clone(),
            row.group.clone(),
            row.engine.clone(),
            row.approximates.clone(),
        ];
        fields.extend(errors(&row.quantity));
        fields.extend(errors(&row.full));
        let et = row.equal_time_path.as_ref();
        fields.push(opt(et.map(|e| e.spp)));
        fields.push(opt(et.map(|e| e.full.rel_mse)));
        fields.push(opt(et.map(|e| e.full.flip_mean)));
        fields.push(opt(row.cost.bake_seconds));
        fields.push(row.cost.seconds.to_string());
        fields.push(opt(row.cost.peak_memory_mib));
        out += &line(fields.into_iter());
    }
    out
}

fn errors(e: &Errors) -> [String; 6] {
    [
        e.rel_mse.to_string(),
        e.flip_mean.to_string(),
        e.flip_p99.to_string(),
        e.mean_ratio[0].to_string(),
        e.mean_ratio[1].to_string(),
        e.mean_ratio[2].to_string(),
    ]
}

fn opt<T: ToString>(v: Option<T>) -> String {
    v.map_or(String::new(), |v| v.to_string())
}

fn line(fields: impl Iterator<Item = String>) -> String {
    let mut out = fields.map(|f| quote(&f)).collect::<Vec<_>>().join(",");
    out.push('\n');
    out
}

/// RFC 4180 quoting: fields holding a comma, quote or line break are put
/// in double quotes, with inner quotes doubled.
fn quote(field: &str) -> String {
    if field.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", field.replace('"', "\"\""))
    } else {
        field.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoting() {
        assert_eq!(quote("plain"), "plain");
        assert_eq!(quote("a, b"), "\"a, b\"");
        assert_eq!(quote("say \"hi\""), "\"say \"\"hi\"\"\"");
        assert_eq!(quote("two\nlines"), "\"two\nlines\"");
    }

    #[test]
    fn one_line_per_row() {
        let study = crate::report::sample_study();
        let csv = study_csv(&study);
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(lines.len(), study.rows.len() + 1);
        assert_eq!(lines[0].split(',').count(), HEADER.len());
        assert!(lines[1].starts_with("map,\"shadow map, PCF 3\",shadows,raster,path,0.05,"));
        assert!(
            lines[2].starts_with("odd,\"<b>&\"\"\",shadows,"),
            "{}",
            lines[2]
        );
        assert!(lines[3].starts_with("whitted,\"Whitted \"\"classic\"\"\","));
        // Every line has the header's field count once quoted commas are skipped.
        let unquoted_commas = |l: &str| {
            l.chars()
                .fold((0, false), |(n, q), c| match c {
                    '"' => (n, !q),
                    ',' if !q => (n + 1, q),
                    _ => (n, q),
                })
                .0
        };
        for l in &lines {
            assert_eq!(unquoted_commas(l), HEADER.len() - 1, "{l}");
        }
        // Equal-time and memory present, bake empty: `…,4,0.1,0.01,,0.002,512`.
        assert!(lines[1].ends_with(",4,0.1,0.01,,0.002,512"), "{}", lines[1]);
    }
}
