//! penumbra-study: one scene rendered with every technique of the notes,
//! each judged against the path-traced truth and against the quantity it
//! approximates, with its cost, written as an offline HTML report,
//! `study.json` and `study.csv`.

pub mod report;
pub mod row;

pub use report::{ReportError, write_report};
pub use row::{Cost, EqualTime, Errors, Row, Skipped, Study, Truth};
