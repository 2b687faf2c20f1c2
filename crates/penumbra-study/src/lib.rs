//! penumbra-study: one scene rendered with every technique of the notes,
//! each judged against the path-traced truth and against the quantity it
//! approximates, with its cost, written as an offline HTML report,
//! `study.json` and `study.csv`.
//!
//! * [`technique`]: the techniques, as values (ids, labels, what each
//!   approximates);
//! * [`truth`]: the truths, rendered to a target relMSE or spp;
//! * [`runner`]: one technique through the engines a user calls;
//! * [`measure`]: relMSE, HDR-FLIP (mean, 99th percentile), mean ratio;
//! * [`study`]: the whole study, written all or nothing;
//! * [`report`]: `index.html`, `study.json`, `study.csv`, the plot.

pub mod error;
pub mod measure;
pub mod memory;
pub mod output_dir;
pub mod report;
pub mod row;
pub mod runner;
pub mod study;
pub mod technique;
pub mod truth;

pub use error::StudyError;
pub use report::{ReportError, write_report};
pub use row::{Cost, EqualTime, Errors, Row, Skipped, Study, Truth};
pub use study::{StudyOptions, StudyProgress, run_study};
pub use technique::{Technique, TruthKind, parse_list};
pub use truth::Target;
