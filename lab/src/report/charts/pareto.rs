//! Pareto front of (cost, error) points, both minimised.

/// Indices of the non-dominated points (no other point is ≤ in both coordinates and < in one),
/// ordered by x ascending (so y strictly descending). Points with a non-finite coordinate are
/// ignored; of exact duplicates only the lowest index is kept.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].0.is_finite() && points[i].1.is_finite())
        .collect();
    order.sort_by(|&a, &b| {
        let (pa, pb) = (points[a], points[b]);
        pa.0.total_cmp(&pb.0)
            .then(pa.1.total_cmp(&pb.1))
            .then(a.cmp(&b))
    });
    let mut front = Vec::new();
    let mut best_y = f64::INFINITY;
    for i in order {
        // Everything earlier has x ≤ this x, so this point survives only with a strictly lower y.
        if points[i].1 < best_y {
            best_y = points[i].1;
            front.push(i);
        }
    }
    front
}

/// Staircase through the front points (as returned by [`pareto_front`]): the best error
/// reachable within each cost, i.e. horizontal to the next point's x, then down to its y.
pub fn pareto_steps(points: &[(f64, f64)], front: &[usize]) -> Vec<(f64, f64)> {
    let mut path = Vec::with_capacity(front.len() * 2);
    for (k, &i) in front.iter().enumerate() {
        if k > 0 {
            path.push((points[i].0, points[front[k - 1]].1));
        }
        path.push(points[i]);
    }
    path
}
