//! The suite's results as report rows (the record layer's rows, one schema with `compare`), so
//! `report.html` shows its tables and charts like `compare` does.

use super::suite::SuiteReport;
use crate::report::charts::ResultRow;

/// One row per scene and method, adaptive first.
pub fn rows(r: &SuiteReport) -> Vec<ResultRow> {
    r.scenes.iter().flat_map(|s| [s.adaptive.row.clone(), s.regular.row.clone()]).collect()
}
