//! The fair rows of seed-table2 (issue 23): beside the seed's 289-point lattice, the centred grid
//! (the midpoint rule) with about as many maps as the adaptive run, and a verdict on each pair
//! by the report's dominance rule (`report::charts::verdicts`).

use crate::report::charts::ResultRow;

/// N for the fair grid: N² the square nearest to the adaptive run's map count `maps`, N ≥ 2 (the
/// centred layout needs a 2x2 grid to cover the light). No ties: two neighbouring squares differ by
/// an odd number, so no count sits halfway between them.
pub fn grid_n(maps: u32) -> u32 {
    let m = u64::from(maps);
    let mut n = (m as f64).sqrt() as u64;
    // The float root can be one off for large counts.
    while n * n > m {
        n -= 1;
    }
    while (n + 1) * (n + 1) <= m {
        n += 1;
    }
    let nearer_above = (n + 1) * (n + 1) - m < m - n * n;
    (if nearer_above { n + 1 } else { n }).max(2) as u32
}

/// The method string of the fair grid for `maps`.
pub fn grid_method(maps: u32) -> String {
    format!("regular:n={},layout=centred", grid_n(maps))
}

/// One comparison row's verdict, adaptive against one grid, both measured in the same run, by the
/// report's dominance rule (`report::charts::verdicts`): `adaptive dominates` when its median frame
/// and RMSE are both at most the grid's, `grid dominates` when adaptive is slower and its RMSE at
/// least the grid's (adaptive at 289 maps is the lattice's RMSE exactly: equal error at a higher
/// time is the grid's win), otherwise the trade-off in figures.
pub fn verdict(adaptive: &ResultRow, grid: &ResultRow) -> String {
    verdict_of("adaptive", adaptive, grid)
}

/// `verdict` for any method against a grid, the method named `name` in the words.
pub fn verdict_of(name: &str, method: &ResultRow, grid: &ResultRow) -> String {
    let usable = |r: &ResultRow| r.core.frame_ms.is_finite() && r.metrics.rmse.is_finite();
    if !usable(method) || !usable(grid) {
        return "no verdict (rows without a time or an RMSE)".into();
    }
    let (faster, accurate) = (
        method.core.frame_ms <= grid.core.frame_ms,
        method.metrics.rmse <= grid.metrics.rmse,
    );
    if faster && accurate {
        return format!("{name} dominates");
    }
    if !faster && method.metrics.rmse >= grid.metrics.rmse {
        return "grid dominates".into();
    }
    trade_off(
        name,
        grid.core.frame_ms / method.core.frame_ms,
        method.metrics.rmse / grid.metrics.rmse,
    )
}

/// `trade-off: adaptive 2.31× faster at 1.42× the RMSE`.
pub fn trade_off(name: &str, speedup: f64, rmse_ratio: f64) -> String {
    format!("trade-off: {name} {speedup:.2}× faster at {rmse_ratio:.2}× the RMSE")
}
