//! Which settings are on the frontier: not dominated in (frame time, RMSE) by any other setting
//! (charts::pareto_front, the report's Pareto staircase), and for every setting off it, the
//! cheapest frontier setting that beats it.

use crate::report::charts::pareto_front;

/// Per point (frame ms, RMSE): on the frontier or not. No other point is both at most as slow and
/// at most as wrong, one of them strictly; of exact duplicates only the first is on it.
pub fn on_frontier(points: &[(f64, f64)]) -> Vec<bool> {
    let mut on = vec![false; points.len()];
    for i in pareto_front(points) {
        on[i] = true;
    }
    on
}

/// The fastest frontier point at most as slow and at most as wrong as `points[i]` (itself when it
/// is on the frontier).
pub fn beaten_by(points: &[(f64, f64)], on: &[bool], i: usize) -> Option<usize> {
    let (t, e) = points[i];
    (0..points.len())
        .filter(|&j| on[j] && points[j].0 <= t && points[j].1 <= e)
        .min_by(|&a, &b| points[a].0.total_cmp(&points[b].0).then(a.cmp(&b)))
}

/// The frontier in order of cost: for every error level, the cheapest setting reaching it is the
/// last of these whose RMSE is at most that level (time ascending, RMSE descending).
pub fn ladder(points: &[(f64, f64)]) -> Vec<usize> {
    pareto_front(points)
}

/// The cheapest setting whose RMSE is at most `level`, by brute force over all points (what the
/// ladder answers; the tests check the two agree).
pub fn cheapest_reaching(points: &[(f64, f64)], level: f64) -> Option<usize> {
    (0..points.len())
        .filter(|&i| points[i].0.is_finite() && points[i].1.is_finite() && points[i].1 <= level)
        .min_by(|&a, &b| {
            points[a]
                .0
                .total_cmp(&points[b].0)
                .then(points[a].1.total_cmp(&points[b].1))
                .then(a.cmp(&b))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frontier_of_known_points() {
        // (ms, rmse): 0 and 2 and 4 on the front; 1 beaten by 0; 3 beaten by 2; 5 a duplicate of 4.
        let p = [
            (1.0, 0.05),
            (2.0, 0.06),
            (3.0, 0.03),
            (4.0, 0.03),
            (10.0, 0.01),
            (10.0, 0.01),
        ];
        assert_eq!(on_frontier(&p), [true, false, true, false, true, false]);
        assert_eq!(beaten_by(&p, &on_frontier(&p), 1), Some(0));
        assert_eq!(beaten_by(&p, &on_frontier(&p), 3), Some(2));
        assert_eq!(beaten_by(&p, &on_frontier(&p), 5), Some(4));
        assert_eq!(ladder(&p), [0, 2, 4]);
        for level in [0.005, 0.01, 0.02, 0.03, 0.04, 0.05, 0.07] {
            let by_ladder = ladder(&p).into_iter().find(|&i| p[i].1 <= level);
            assert_eq!(by_ladder, cheapest_reaching(&p, level), "level {level}");
        }
    }
}
