//! The oracle's search (docs/oracle.md): which candidate each tile takes, so that the frame meets
//! its error budget at the least price, and a lower bound on that price.
//!
//! A frame that gives tile t the candidate k(t) pays the fixed stages once, the maps of every
//! candidate it uses once, and each tile's pixel tests:
//!
//! ```text
//! F + Σ_{k ∈ S} M_k + Σ_t c_{t,k(t)},   subject to   Σ_t e_{t,k(t)} ≤ B.
//! ```
//!
//! Without the budget this is uncapacitated facility location (candidates open at M_k, tiles
//! served at c); the budget couples the tiles. The search:
//! - a first frame from local search over sets (add, drop or swap one candidate) from several
//!   starts, each set's tiles assigned as the multiple-choice knapsack's LP orders them;
//! - then branch and bound over which candidates' maps are paid. A node's bound, for any λ ≥ 0,
//!   is F + its open maps + a feasible point of facility location's LP dual at prices c + λe
//!   (Erlenkotter's dual ascent) − λB, the best over λ; a leaf (every candidate decided) is
//!   bounded by its knapsack's LP. Nodes whose bound reaches the best frame are cut.
//!
//! `bound_ms` is the least bound over the nodes not cut: where the search closes (`closed`), the
//! frame found and the bound differ only by the knapsack's last fractional step, and no frame of
//! these candidates is cheaper than the bound. Tiles that are uniformly lit or dark in the
//! reference are taken out before (the caller's gift, free).

/// One frame's choice: per tile (free tiles left out) and candidate, the ms of the tile's pixel
/// tests and its summed squared error of V; per candidate, the ms of its maps.
#[derive(Clone, Debug)]
pub struct Problem {
    /// Paid by every frame whatever it chooses: the G-buffer and the read-back.
    pub fixed_ms: f64,
    /// Per candidate: its maps, paid once per frame when any tile uses it.
    pub maps_ms: Vec<f64>,
    /// Row-major [tile][candidate]: ms of the tile's pixel tests.
    pub cost: Vec<f64>,
    /// Row-major [tile][candidate]: the tile's summed squared error of V.
    pub err: Vec<f64>,
    /// The frame's summed squared error allowed: T² × geometry pixels.
    pub budget: f64,
}

/// What the search found.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// An achievable frame, in ms: fixed + its candidates' maps + its tiles' tests.
    pub frame_ms: f64,
    /// No assignment of these candidates to these tiles within the budget costs less.
    pub bound_ms: f64,
    /// Per tile, its candidate.
    pub choice: Vec<usize>,
    /// The frame's summed squared error (at most the budget).
    pub err: f64,
    /// The branch and bound ended before its node limit: `bound_ms` is the optimum's.
    pub closed: bool,
}

impl Problem {
    pub fn candidates(&self) -> usize {
        self.maps_ms.len()
    }

    pub fn tiles(&self) -> usize {
        self.cost.len().checked_div(self.candidates()).unwrap_or(0)
    }

    fn at(&self, t: usize, k: usize) -> (f64, f64) {
        let i = t * self.candidates() + k;
        (self.cost[i], self.err[i])
    }

    /// The least error any choice reaches: every tile at its own most accurate candidate.
    pub fn least_err(&self) -> f64 {
        (0..self.tiles())
            .map(|t| {
                (0..self.candidates())
                    .map(|k| self.at(t, k).1)
                    .fold(f64::INFINITY, f64::min)
            })
            .sum()
    }

    /// The frame's price with every tile on candidate `k` (the tiles given, not the free ones).
    pub fn single_ms(&self, k: usize) -> f64 {
        self.fixed_ms + self.maps_ms[k] + (0..self.tiles()).map(|t| self.at(t, k).0).sum::<f64>()
    }

    /// A λ of the order where test time trades against error: the mean frame over the budget.
    fn lambda_scale(&self) -> f64 {
        let k = self.candidates().max(1) as f64;
        let mean = self.maps_ms.iter().sum::<f64>() / k + self.cost.iter().sum::<f64>() / k;
        (mean.max(1e-12)) / self.budget.max(1e-12)
    }
}

/// The cheapest frame found and the bound; None when no choice meets the budget.
pub fn solve(p: &Problem) -> Option<Solution> {
    if p.tiles() == 0 {
        return Some(Solution {
            frame_ms: p.fixed_ms,
            bound_ms: p.fixed_ms,
            choice: Vec::new(),
            err: 0.0,
            closed: true,
        });
    }
    if p.least_err() > p.budget {
        return None;
    }
    let ((_, set), bound_ms, closed) = branch_and_bound(p, search(p));
    let (frame_ms, choice, err) = settle(p, &set);
    Some(Solution {
        frame_ms,
        bound_ms: bound_ms.min(frame_ms),
        choice,
        err,
        closed,
    })
}

/// Erlenkotter's dual ascent for facility location at prices d = c + λe over the candidates `ks`
/// whose maps cost `maps` (0 for a candidate already paid for): a feasible point v of the LP's
/// dual (Σ_t max(0, v_t − d_tk) ≤ maps_k for every k), raised one breakpoint per tile and pass
/// until no tile can rise. Returns Σ v, at most the facility-location optimum, and each
/// candidate's slack (0: the tiles it serves pay for its maps).
fn dual_ascent(p: &Problem, lambda: f64, ks: &[usize], maps: &[f64]) -> (f64, Vec<f64>) {
    let (nt, nk) = (p.tiles(), ks.len());
    let d: Vec<f64> = (0..nt)
        .flat_map(|t| ks.iter().map(move |&k| (t, k)))
        .map(|(t, k)| p.at(t, k).0 + lambda * p.at(t, k).1)
        .collect();
    let orders: Vec<Vec<usize>> = (0..nt)
        .map(|t| {
            let mut o: Vec<usize> = (0..nk).collect();
            o.sort_by(|&a, &b| d[t * nk + a].total_cmp(&d[t * nk + b]));
            o
        })
        .collect();
    let mut v: Vec<f64> = (0..nt).map(|t| d[t * nk + orders[t][0]]).collect();
    // How many of the tile's candidates are at or below v_t: those whose slack its rise uses.
    let mut below: Vec<usize> = (0..nt)
        .map(|t| {
            orders[t]
                .iter()
                .take_while(|&&k| d[t * nk + k] <= v[t])
                .count()
        })
        .collect();
    let mut slack = maps.to_vec();
    loop {
        let mut risen = false;
        for t in 0..nt {
            let o = &orders[t];
            let room = o[..below[t]]
                .iter()
                .map(|&k| slack[k])
                .fold(f64::INFINITY, f64::min);
            let next = o.get(below[t]).map_or(f64::INFINITY, |&k| d[t * nk + k]);
            let rise = (next - v[t]).min(room);
            if !(rise > 0.0) {
                continue;
            }
            for &k in &o[..below[t]] {
                slack[k] = (slack[k] - rise).max(0.0);
            }
            risen = true;
            if rise >= next - v[t] {
                v[t] = next;
                while below[t] < nk && d[t * nk + o[below[t]]] <= v[t] {
                    below[t] += 1;
                }
            } else {
                v[t] += rise;
            }
        }
        if !risen {
            return (v.iter().sum(), slack);
        }
    }
}

/// Which candidates a node of the search has decided.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Status {
    Free,
    /// Its maps are paid for.
    Open,
    /// Not in the frame.
    Closed,
}

/// A node's lower bound on every frame whose set holds its open candidates and no closed one:
/// F + the open maps + the dual ascent over the open (maps paid) and free candidates − λB, the
/// best over λ: 2 points a decade over `span` decades about `around`, then golden-section
/// refinement. Returns (bound, its λ, each candidate's slack, 0 for the closed).
fn node_bound(p: &Problem, status: &[Status], around: f64, span: i32) -> (f64, f64, Vec<f64>) {
    let ks: Vec<usize> = (0..p.candidates())
        .filter(|&k| status[k] != Status::Closed)
        .collect();
    let maps: Vec<f64> = ks
        .iter()
        .map(|&k| {
            if status[k] == Status::Open {
                0.0
            } else {
                p.maps_ms[k]
            }
        })
        .collect();
    let paid: f64 = p.fixed_ms
        + (0..p.candidates())
            .filter(|&k| status[k] == Status::Open)
            .map(|k| p.maps_ms[k])
            .sum::<f64>();
    let value = |lambda: f64| {
        let (v, slack) = dual_ascent(p, lambda, &ks, &maps);
        (paid + v - lambda * p.budget, slack)
    };
    let (v0, s0) = value(0.0);
    let mut best = (v0, 0.0, s0);
    let mut at = None;
    let points: Vec<f64> = (-2 * span..=2 * span)
        .map(|i| around * 10f64.powf(f64::from(i) / 4.0))
        .collect();
    for (i, &l) in points.iter().enumerate() {
        let (v, s) = value(l);
        if v > best.0 {
            (best, at) = ((v, l, s), Some(i));
        }
    }
    if let Some(i) = at {
        let (mut lo, mut hi) = (
            points[i.saturating_sub(1)].ln(),
            points[(i + 1).min(points.len() - 1)].ln(),
        );
        let g = (5f64.sqrt() - 1.0) / 2.0;
        for _ in 0..10 {
            let (a, b) = (hi - g * (hi - lo), lo + g * (hi - lo));
            let ((va, sa), (vb, sb)) = (value(a.exp()), value(b.exp()));
            if va > best.0 {
                best = (va, a.exp(), sa);
            }
            if vb > best.0 {
                best = (vb, b.exp(), sb);
            }
            if va >= vb {
                hi = b;
            } else {
                lo = a;
            }
        }
    }
    let mut slack = vec![0.0; p.candidates()];
    for (i, &k) in ks.iter().enumerate() {
        slack[k] = best.2[i];
    }
    (best.0, best.1, slack)
}

/// The multiple-choice knapsack's LP over the candidates of `set`: its tiles' least test time
/// within the budget with the last hull step taken in part (at most every integral assignment).
fn assign_lp(p: &Problem, set: &[usize]) -> f64 {
    let (mut tests, mut err, steps) = hull_steps(p, set);
    if err <= p.budget {
        return tests;
    }
    for (rate, dc, de) in steps {
        if err - de <= p.budget {
            // The part of this step that meets the budget exactly.
            return tests + (err - p.budget) / rate.max(1e-300);
        }
        (tests, err) = (tests + dc, err - de);
    }
    f64::INFINITY
}

/// Every tile at its cheapest candidate of `set` (test ms and error summed), and every step
/// along each tile's convex hull of (ms, error) as (error saved per ms, ms added, error saved),
/// best first.
fn hull_steps(p: &Problem, set: &[usize]) -> (f64, f64, Vec<(f64, f64, f64)>) {
    let (mut tests, mut err, mut steps) = (0.0, 0.0, Vec::new());
    for t in 0..p.tiles() {
        let hull = hull(p, t, set);
        tests += hull[0].0;
        err += hull[0].1;
        for w in hull.windows(2) {
            steps.push((
                (w[0].1 - w[1].1) / (w[1].0 - w[0].0).max(1e-300),
                w[1].0 - w[0].0,
                w[0].1 - w[1].1,
            ));
        }
    }
    steps.sort_by(|a, b| b.0.total_cmp(&a.0));
    (tests, err, steps)
}

/// Tile t's lower-left convex hull of (test ms, error, candidate) over `set`, cheapest first.
fn hull(p: &Problem, t: usize, set: &[usize]) -> Vec<(f64, f64, usize)> {
    let mut opts: Vec<(f64, f64, usize)> = set
        .iter()
        .map(|&k| (p.at(t, k).0, p.at(t, k).1, k))
        .collect();
    opts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut hull: Vec<(f64, f64, usize)> = vec![opts[0]];
    for &o in &opts[1..] {
        if o.1 >= hull.last().expect("hull starts non-empty").1 {
            continue; // dearer and no more accurate
        }
        // Keep the hull convex: drop a point above the segment from its predecessor to o.
        while hull.len() >= 2 {
            let (a, b) = (hull[hull.len() - 2], hull[hull.len() - 1]);
            if (b.0 - a.0) * (o.1 - a.1) - (b.1 - a.1) * (o.0 - a.0) <= 0.0 {
                hull.pop();
            } else {
                break;
            }
        }
        hull.push(o);
    }
    hull
}

/// Nodes the exact search may visit before it stops and reports the bound it has.
const NODE_LIMIT: usize = 4000;

/// Branch and bound over which candidates' maps the frame pays, from the incumbent `best`
/// (frame ms, set): depth first, the free candidate the dual ascent pays for most (least slack
/// per ms of maps) opened first, then closed. A node is cut when its bound reaches the best
/// frame; at a leaf (nothing free) the set's frame is priced, and its knapsack LP bounds it.
/// Returns the best frame and set, and the least bound over every node not cut (the global
/// lower bound: the best frame itself when the search closes), and whether it closed.
fn branch_and_bound(p: &Problem, mut best: (f64, Vec<usize>)) -> ((f64, Vec<usize>), f64, bool) {
    let nk = p.candidates();
    let mut floor = f64::INFINITY;
    let mut stack: Vec<(Vec<Status>, f64)> = vec![(vec![Status::Free; nk], p.lambda_scale())];
    let (mut visited, mut closed) = (0, true);
    while let Some((status, around)) = stack.pop() {
        visited += 1;
        if visited > NODE_LIMIT {
            closed = false;
            // Stopped: every node left may still hold a cheaper frame than the best.
            for (st, l) in std::iter::once((status, around)).chain(stack.drain(..)) {
                floor = floor.min(node_bound(p, &st, l, 2).0);
            }
            break;
        }
        let free: Vec<usize> = (0..nk).filter(|&k| status[k] == Status::Free).collect();
        let open: Vec<usize> = (0..nk).filter(|&k| status[k] == Status::Open).collect();
        if free.is_empty() {
            if open.is_empty() {
                continue;
            }
            let lp =
                p.fixed_ms + open.iter().map(|&k| p.maps_ms[k]).sum::<f64>() + assign_lp(p, &open);
            if lp < best.0 {
                if let Some((f, _, _)) = price(p, &open) {
                    if f < best.0 {
                        best = (f, open.clone());
                    }
                }
                floor = floor.min(lp);
            }
            continue;
        }
        let (bound, lambda, slack) =
            node_bound(p, &status, around, if visited == 1 { 8 } else { 2 });
        if bound >= best.0 * (1.0 - 1e-9) {
            continue;
        }
        // The set the dual ascent pays for, priced: a frame to beat.
        let paid: Vec<usize> = open
            .iter()
            .copied()
            .chain(
                free.iter()
                    .copied()
                    .filter(|&k| slack[k] <= 1e-9 * p.maps_ms[k].max(1e-9)),
            )
            .collect();
        if !paid.is_empty() {
            if let Some((f, _, _)) = price(p, &paid) {
                if f < best.0 {
                    best = (f, paid.clone());
                }
            }
        }
        let k = *free
            .iter()
            .min_by(|&&a, &&b| {
                (slack[a] / p.maps_ms[a].max(1e-12))
                    .total_cmp(&(slack[b] / p.maps_ms[b].max(1e-12)))
                    .then(p.maps_ms[b].total_cmp(&p.maps_ms[a]))
            })
            .expect("a free candidate");
        let mut closed = status.clone();
        closed[k] = Status::Closed;
        let mut opened = status;
        opened[k] = Status::Open;
        // Depth first, the opened child first (popped first).
        stack.push((closed, lambda.max(1e-300)));
        stack.push((opened, lambda.max(1e-300)));
    }
    let bound = floor.min(best.0);
    (best, bound, closed)
}

/// The tiles' cheapest assignment to the candidates of `set` within the budget, as the LP of the
/// multiple-choice knapsack solves it: every tile starts at its cheapest candidate, then the
/// steps along each tile's convex hull of (test ms, error) are taken in order of error saved per
/// ms until the frame fits; the budget left is then spent on cheaper choices (`fill`). Returns
/// (test ms, choice, error), or None when the set cannot meet the budget.
fn assign(p: &Problem, set: &[usize]) -> Option<(f64, Vec<usize>, f64)> {
    let nt = p.tiles();
    let mut choice = Vec::with_capacity(nt);
    // (error saved per ms, tile, to): every hull step of every tile.
    let mut steps: Vec<(f64, usize, usize)> = Vec::new();
    let mut err = 0.0;
    for t in 0..nt {
        let hull = hull(p, t, set);
        choice.push(hull[0].2);
        err += hull[0].1;
        for w in hull.windows(2) {
            steps.push(((w[0].1 - w[1].1) / (w[1].0 - w[0].0).max(1e-300), t, w[1].2));
        }
    }
    if err > p.budget {
        steps.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        for (_, t, k) in steps {
            err += p.at(t, k).1 - p.at(t, choice[t]).1;
            choice[t] = k;
            if err <= p.budget {
                break;
            }
        }
        if err > p.budget * (1.0 + 1e-12) {
            return None;
        }
    }
    fill(p, set, &mut choice);
    let tests = choice.iter().enumerate().map(|(t, &k)| p.at(t, k).0).sum();
    let err = choice.iter().enumerate().map(|(t, &k)| p.at(t, k).1).sum();
    Some((tests, choice, err))
}

/// Spends the budget left on cheaper choices: each step takes the move (a tile to a cheaper
/// candidate of the set) that saves the most ms per squared error added, while it fits.
fn fill(p: &Problem, set: &[usize], choice: &mut [usize]) {
    let mut left = p.budget
        - choice
            .iter()
            .enumerate()
            .map(|(t, &k)| p.at(t, k).1)
            .sum::<f64>();
    loop {
        let mut best: Option<(f64, usize, usize)> = None;
        for (t, &now) in choice.iter().enumerate() {
            let (c0, e0) = p.at(t, now);
            for &k in set {
                let (c, e) = p.at(t, k);
                let (saves, adds) = (c0 - c, e - e0);
                if saves <= 0.0 || adds > left {
                    continue;
                }
                let rate = saves / adds.max(1e-300);
                if best.is_none_or(|(r, _, _)| rate > r) {
                    best = Some((rate, t, k));
                }
            }
        }
        let Some((_, t, k)) = best else { break };
        left -= p.at(t, k).1 - p.at(t, choice[t]).1;
        choice[t] = k;
    }
}

/// A set's frame: fixed, its maps, its tiles' tests; None when it cannot meet the budget.
fn price(p: &Problem, set: &[usize]) -> Option<(f64, Vec<usize>, f64)> {
    let maps: f64 = set.iter().map(|&k| p.maps_ms[k]).sum();
    assign(p, set).map(|(tests, c, e)| (p.fixed_ms + maps + tests, c, e))
}

/// Sets of candidates, searched from several starts: the three cheapest single candidates; every
/// candidate, dropping the one whose loss saves most while one does (the classic greedy drop of
/// facility location); and the cheapest single candidate, adding the one that saves most while
/// one does. From each, local search (add, drop or swap one candidate) while the frame gets
/// cheaper. Returns the cheapest frame and its set.
fn search(p: &Problem) -> (f64, Vec<usize>) {
    let nk = p.candidates();
    let mut singles: Vec<(f64, Vec<usize>)> = (0..nk)
        .filter_map(|k| price(p, &[k]).map(|r| (r.0, vec![k])))
        .collect();
    singles.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut starts: Vec<Vec<usize>> = singles.iter().take(3).map(|s| s.1.clone()).collect();
    starts.push(greedy_drop(p));
    if let Some((_, first)) = singles.first() {
        starts.push(greedy_add(p, first.clone()));
    }
    let mut best: Option<(f64, Vec<usize>)> = None;
    for s in starts {
        let (f, s) = local_search(p, s);
        if best.as_ref().is_none_or(|b| f < b.0) {
            best = Some((f, s));
        }
    }
    best.expect("the set of every candidate meets the budget")
}

/// The frame of `set`: its tiles assigned, the pair exchanges the greedy misses made, and only
/// the candidates some tile uses paid for. Returns (frame ms, choice, error).
fn settle(p: &Problem, set: &[usize]) -> (f64, Vec<usize>, f64) {
    let (_, mut choice, _) = price(p, set).expect("the set found meets the budget");
    exchange(p, set, &mut choice);
    let used: Vec<usize> = set.iter().copied().filter(|k| choice.contains(k)).collect();
    let tests: f64 = choice.iter().enumerate().map(|(t, &k)| p.at(t, k).0).sum();
    let err = choice.iter().enumerate().map(|(t, &k)| p.at(t, k).1).sum();
    (
        p.fixed_ms + used.iter().map(|&k| p.maps_ms[k]).sum::<f64>() + tests,
        choice,
        err,
    )
}

/// From every candidate, drop the one whose loss makes the frame cheapest while that is cheaper.
fn greedy_drop(p: &Problem) -> Vec<usize> {
    let mut set: Vec<usize> = (0..p.candidates()).collect();
    let mut now = price(p, &set).map_or(f64::INFINITY, |r| r.0);
    while set.len() > 1 {
        let best = (0..set.len())
            .filter_map(|i| price(p, &[&set[..i], &set[i + 1..]].concat()).map(|r| (r.0, i)))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match best {
            Some((f, i)) if f < now => {
                set.remove(i);
                now = f;
            }
            _ => break,
        }
    }
    set
}

/// From `set`, add the candidate that makes the frame cheapest while that is cheaper.
fn greedy_add(p: &Problem, mut set: Vec<usize>) -> Vec<usize> {
    let mut now = price(p, &set).map_or(f64::INFINITY, |r| r.0);
    loop {
        let best = (0..p.candidates())
            .filter(|k| !set.contains(k))
            .filter_map(|k| price(p, &[set.clone(), vec![k]].concat()).map(|r| (r.0, k)))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        match best {
            Some((f, k)) if f < now => {
                set.push(k);
                now = f;
            }
            _ => return set,
        }
    }
}

/// Add, drop or swap one candidate, the move that makes the frame cheapest, while one does.
fn local_search(p: &Problem, mut set: Vec<usize>) -> (f64, Vec<usize>) {
    let nk = p.candidates();
    let mut frame = price(p, &set).map_or(f64::INFINITY, |r| r.0);
    loop {
        let mut moves: Vec<Vec<usize>> = Vec::new();
        for k in (0..nk).filter(|k| !set.contains(k)) {
            moves.push([set.clone(), vec![k]].concat());
            for i in 0..set.len() {
                let mut s = set.clone();
                s[i] = k;
                moves.push(s);
            }
        }
        if set.len() > 1 {
            moves.extend((0..set.len()).map(|i| [&set[..i], &set[i + 1..]].concat()));
        }
        let mut better: Option<(f64, Vec<usize>)> = None;
        for s in moves {
            let bar = better.as_ref().map_or(frame, |b| b.0);
            if p.fixed_ms + s.iter().map(|&k| p.maps_ms[k]).sum::<f64>() >= bar {
                continue;
            }
            if let Some((f, _, _)) = price(p, &s) {
                if f < bar * (1.0 - 1e-12) {
                    better = Some((f, s));
                }
            }
        }
        match better {
            Some((f, s)) => (frame, set) = (f, s),
            None => return (frame, set),
        }
    }
}

/// Pairs of moves the greedy fill cannot see: one tile to a dearer, more accurate candidate, which
/// frees budget for another to a cheaper one, where together they save time and fit the budget.
/// Each step takes the pair that saves the most, until none saves.
fn exchange(p: &Problem, set: &[usize], choice: &mut [usize]) {
    loop {
        let left = p.budget
            - choice
                .iter()
                .enumerate()
                .map(|(t, &k)| p.at(t, k).1)
                .sum::<f64>();
        // (tile, candidate, Δcost, Δerror): up = dearer and more accurate, down = cheaper.
        let (mut up, mut down) = (Vec::new(), Vec::new());
        for (t, &now) in choice.iter().enumerate() {
            let (c0, e0) = p.at(t, now);
            for &k in set.iter().filter(|&&k| k != now) {
                let (c, e) = p.at(t, k);
                if c > c0 && e < e0 {
                    up.push((t, k, c - c0, e - e0));
                } else if c < c0 {
                    down.push((t, k, c - c0, e - e0));
                }
            }
        }
        // (the price change, the tile and candidate that rise, the tile and candidate that fall)
        type Swap = (f64, (usize, usize), (usize, usize));
        let mut best: Option<Swap> = None;
        for &(ta, ka, ca, ea) in &up {
            for &(tb, kb, cb, eb) in &down {
                if ta != tb
                    && ca + cb < 0.0
                    && ea + eb <= left
                    && best.is_none_or(|b| ca + cb < b.0)
                {
                    best = Some((ca + cb, (ta, ka), (tb, kb)));
                }
            }
        }
        let Some((_, (ta, ka), (tb, kb))) = best else {
            break;
        };
        choice[ta] = ka;
        choice[tb] = kb;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cheapest frame by brute force over every assignment (candidates and no free option).
    fn brute(p: &Problem) -> Option<f64> {
        let (nt, nk) = (p.tiles(), p.candidates());
        let mut best: Option<f64> = None;
        let mut a = vec![0usize; nt];
        loop {
            let err: f64 = (0..nt).map(|t| p.at(t, a[t]).1).sum();
            if err <= p.budget {
                let mut used = vec![false; nk];
                a.iter().for_each(|&k| used[k] = true);
                let cost = p.fixed_ms
                    + (0..nk)
                        .filter(|&k| used[k])
                        .map(|k| p.maps_ms[k])
                        .sum::<f64>()
                    + (0..nt).map(|t| p.at(t, a[t]).0).sum::<f64>();
                best = Some(best.map_or(cost, |b| b.min(cost)));
            }
            let mut i = 0;
            while i < nt {
                a[i] += 1;
                if a[i] < nk {
                    break;
                }
                a[i] = 0;
                i += 1;
            }
            if i == nt {
                return best;
            }
        }
    }

    #[test]
    fn a_hand_checked_frame() {
        // Two tiles, two candidates. A: maps 10, tests 1 per tile, tile 1 errs by 4. B: maps 10,
        // tests 5 per tile, exact. Budget 0: tile 1 must take B; B for both (20) beats A and B
        // (10 + 10 + 1 + 5 = 26). Budget 4: A for both, 12.
        let mut p = Problem {
            fixed_ms: 0.0,
            maps_ms: vec![10.0, 10.0],
            cost: vec![1.0, 5.0, 1.0, 5.0],
            err: vec![0.0, 0.0, 4.0, 0.0],
            budget: 0.0,
        };
        let s = solve(&p).unwrap();
        assert_eq!(
            (s.frame_ms, s.choice.clone(), s.err, s.closed),
            (20.0, vec![1, 1], 0.0, true)
        );
        assert!(s.bound_ms <= 20.0 + 1e-9 && s.bound_ms > 15.0, "{s:?}");
        p.budget = 4.0;
        let s = solve(&p).unwrap();
        assert_eq!((s.frame_ms, s.choice.clone()), (12.0, vec![0, 0]));
        assert!((s.bound_ms - 12.0).abs() < 1e-6, "{s:?}");
        // A budget below the least error: no frame.
        p.err[0] = 1.0;
        p.err[1] = 1.0;
        p.budget = 0.5;
        assert!(solve(&p).is_none());
        // No tile left (every tile free): the fixed stages alone.
        let none = Problem {
            fixed_ms: 3.0,
            maps_ms: vec![1.0],
            cost: vec![],
            err: vec![],
            budget: 0.0,
        };
        assert_eq!(solve(&none).unwrap().frame_ms, 3.0);
    }

    #[test]
    fn mixed_needs_split_into_two_candidates() {
        // Four tiles: two need many samples on coarse maps (candidate 1), two few samples on fine
        // maps (candidate 2); candidate 0 (many samples on fine maps) serves all four at a high
        // price. The split pays two cheap sets of maps and beats every single candidate.
        let big = 100.0;
        let p = Problem {
            fixed_ms: 1.0,
            maps_ms: vec![50.0, 8.0, 8.0],
            cost: vec![4.0, 2.0, 1.0, 4.0, 2.0, 1.0, 4.0, 2.0, 1.0, 4.0, 2.0, 1.0],
            err: vec![0.0, 0.0, big, 0.0, 0.0, big, 0.0, big, 0.0, 0.0, big, 0.0],
            budget: 0.5,
        };
        let s = solve(&p).unwrap();
        assert_eq!(s.choice, vec![1, 1, 2, 2]);
        assert_eq!(s.frame_ms, 1.0 + 16.0 + 2.0 * 2.0 + 2.0 * 1.0);
        assert!(
            s.bound_ms <= s.frame_ms + 1e-9 && s.bound_ms >= 0.9 * s.frame_ms,
            "{s:?}"
        );
        assert_eq!(p.single_ms(0), 1.0 + 50.0 + 16.0);
    }

    #[test]
    fn bound_and_frame_bracket_the_brute_force_optimum() {
        // Random problems small enough to enumerate: the bound never above the optimum, the frame
        // never below it (it is achievable), and the search finds the optimum nearly always.
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut exact, mut gap_sum, cases) = (0, 0.0, 300);
        for _ in 0..cases {
            let (nt, nk) = (6, 4);
            let maps_ms: Vec<f64> = (0..nk).map(|_| 1.0 + 20.0 * rnd()).collect();
            let cost: Vec<f64> = (0..nt * nk).map(|_| 0.5 + 5.0 * rnd()).collect();
            let err: Vec<f64> = (0..nt * nk)
                .map(|_| if rnd() < 0.3 { 0.0 } else { 10.0 * rnd() })
                .collect();
            let mut p = Problem {
                fixed_ms: 2.0,
                maps_ms,
                cost,
                err,
                budget: 0.0,
            };
            p.budget = p.least_err() + 15.0 * rnd();
            let opt = brute(&p).unwrap();
            let s = solve(&p).unwrap();
            assert!(
                s.bound_ms <= opt + 1e-9,
                "bound {} over the optimum {opt}",
                s.bound_ms
            );
            assert!(
                s.frame_ms >= opt - 1e-9 && s.err <= p.budget + 1e-9,
                "frame {} below the optimum {opt}",
                s.frame_ms
            );
            let cost: f64 = p.fixed_ms
                + s.choice
                    .iter()
                    .fold(vec![false; nk], |mut u, &k| {
                        u[k] = true;
                        u
                    })
                    .iter()
                    .enumerate()
                    .filter(|(_, &u)| u)
                    .map(|(k, _)| p.maps_ms[k])
                    .sum::<f64>()
                + s.choice
                    .iter()
                    .enumerate()
                    .map(|(t, &k)| p.at(t, k).0)
                    .sum::<f64>();
            assert!(
                (cost - s.frame_ms).abs() < 1e-9,
                "the frame's price is its choice's"
            );
            exact += usize::from(s.frame_ms <= opt + 1e-9);
            gap_sum += (opt - s.bound_ms) / opt;
        }
        // Measured: the optimum on 296 of 300; the bound 1.7% under it on average (on 6 tiles the
        // knapsack's LP at a leaf is loose; on a frame's hundreds of tiles it closes).
        assert!(exact >= 292, "optimum found on {exact} of {cases}");
        assert!(
            gap_sum / cases as f64 <= 0.03,
            "mean gap of the bound {}",
            gap_sum / cases as f64
        );
    }
}
