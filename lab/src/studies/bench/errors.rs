//! The error columns of the suite: RMSE of V and FLIP of the shaded image against the continuous
//! reference, taken from the metrics the record layer computes for every row.

use crate::metrics::Metrics;

#[derive(Clone, Debug, serde::Serialize)]
pub struct ErrorColumns {
    pub rmse: f64,
    pub flip: f64,
}

impl ErrorColumns {
    pub fn of(m: &Metrics) -> ErrorColumns {
        ErrorColumns {
            rmse: m.rmse,
            flip: m.flip_mean,
        }
    }
}

/// What the table prints when a column has no value.
pub const PENDING: &str = "no reference";
