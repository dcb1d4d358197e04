//! auto's search over the grids it may choose (docs/error-estimate.md §6): the ladder of sides
//! and map sizes the calibration was fitted on, the price of a map of each size, and the
//! prediction of any grid on it from one try. Pure arithmetic: no GPU.

use super::SIZES;
use crate::methods::calibration::{self, Class};
use crate::methods::estimate::Prediction;

/// The grid sides it chooses from, 2 to `max_n`: those the calibration was fitted on
/// (`calibration::fitted_side`: the odd ones, the even ones to 6 with their own sampling factor).
pub(crate) fn sides(max_n: u32) -> Vec<u32> {
    (2..=max_n)
        .filter(|&n| calibration::fitted_side(n))
        .collect()
}

/// The map sizes it chooses from: 512² (`calibration::MIN_FITTED_SIZE`) to `max_size` (256²
/// alone where `max_size` is 256).
pub(crate) fn sizes(max_size: u32) -> Vec<u32> {
    let fitted: Vec<u32> = SIZES
        .iter()
        .copied()
        .filter(|&z| z >= calibration::MIN_FITTED_SIZE && z <= max_size)
        .collect();
    if fitted.is_empty() {
        vec![max_size]
    } else {
        fitted
    }
}

/// Sampling error falls about as n^-1.5 on the scenes measured (docs/error-estimate.md §6).
pub const SAMPLING_ORDER: f64 = 1.5;

/// The price of one map of each size the search may choose (ms under `measured`, relative under
/// `texels`), in SIZES order.
#[derive(Clone, Debug, PartialEq)]
pub struct Costs(pub Vec<(u32, f64)>);

impl Costs {
    /// Double per doubling of the side. From 512² to 1024² maps a map costs 1.1–1.3× more on the
    /// meshes and 1.6–2.9× on the small analytic scenes on lavapipe (docs/error-estimate.md §6).
    pub(crate) fn texels(max_size: u32) -> Costs {
        Costs(
            sizes(max_size)
                .into_iter()
                .map(|z| (z, z as f64 / 512.0))
                .collect(),
        )
    }
    pub(crate) fn of(&self, size: u32) -> f64 {
        self.0
            .iter()
            .find(|(z, _)| *z == size)
            .map_or(f64::INFINITY, |(_, c)| *c)
    }
}

/// The calibrated sampling error of side n2 from side n's, in a scene of `class`: it falls as
/// n^−1.5, and an even side and an odd one take their own factors (`calibration::factors_at`).
fn sampling_at(class: Class, n: u32, sampling: f64, n2: u32) -> f64 {
    let factor =
        calibration::factors_at(class, n2).sampling / calibration::factors_at(class, n).sampling;
    sampling * (n as f64 / n2 as f64).powf(SAMPLING_ORDER) * factor
}

/// A try the search reads from: the centred grid (n, size) it rendered and that grid's
/// calibrated prediction.
#[derive(Clone, Copy, Debug)]
pub struct At {
    pub(crate) n: u32,
    pub(crate) size: u32,
    pub(crate) p: Prediction,
}

impl At {
    pub fn new(n: u32, size: u32, p: Prediction) -> At {
        At { n, size, p }
    }
}

/// The predicted RMSE of the centred grid (n2, size2), from a try `at` (n, size) in a scene of
/// `class`: the sampling error falls as n^−1.5 (`sampling_at`); of the maps' error, the part
/// that averages over samples falls as 1/n (`Prediction::predicted_map_averaging`), and all of it
/// at best as the texel size.
pub fn predicted_at(class: Class, at: &At, (n2, size2): (u32, u32)) -> f64 {
    let (n, size, p) = (at.n, at.size, &at.p);
    let s = sampling_at(class, n, p.predicted_sampling, n2);
    // Fewer samples or smaller maps (a step down) raise both parts by the same laws.
    let kept = 1.0 - (n * n) as f64 / (n2 * n2) as f64;
    let texel = size as f64 / size2 as f64;
    let m2 = (p.predicted_map.powi(2) - p.predicted_map_averaging.powi(2) * kept).max(0.0)
        * texel
        * texel;
    (s * s + m2).sqrt()
}

/// The grids the search chooses among: the centred grid's sides `sides(max_n)` and map sizes
/// `sizes(max_size)`, each map priced at `costs`, predicted for a scene of `class`.
#[derive(Clone, Debug, PartialEq)]
pub struct Ladder {
    pub(crate) class: Class,
    pub(crate) max_n: u32,
    pub(crate) max_size: u32,
    pub(crate) costs: Costs,
}

impl Ladder {
    pub fn new(class: Class, max_n: u32, max_size: u32, costs: Costs) -> Ladder {
        Ladder {
            class,
            max_n,
            max_size,
            costs,
        }
    }

    /// The price of grid (n, size): n² maps at the size's price.
    pub(crate) fn price(&self, (n, size): (u32, u32)) -> f64 {
        (n * n) as f64 * self.costs.of(size)
    }

    /// A step down: the cheapest grid not yet `tried`, cheaper than the try `at`, that
    /// `predicted_at` says meets `target` too; None if none does.
    pub fn cheaper_meeting(
        &self,
        at: &At,
        target: f64,
        tried: &[(u32, u32)],
    ) -> Option<(u32, u32)> {
        let here = self.price((at.n, at.size));
        let mut best: Option<(f64, (u32, u32))> = None;
        for size2 in sizes(self.max_size) {
            for n2 in sides(self.max_n) {
                let cost = self.price((n2, size2));
                if cost >= here {
                    break;
                }
                if !tried.contains(&(n2, size2))
                    && predicted_at(self.class, at, (n2, size2)) <= target
                    && best.is_none_or(|(c, _)| cost < c)
                {
                    best = Some((cost, (n2, size2)));
                }
            }
        }
        best.map(|(_, choice)| choice)
    }

    /// The cheapest grid of sides ≥ the try's n and maps ≥ its size, other than the try's own,
    /// that `predicted_at` says meets `target`; None if none does.
    pub(crate) fn cheapest_meeting(&self, at: &At, target: f64) -> Option<(u32, u32)> {
        let (n, size) = (at.n, at.size);
        let mut best: Option<(f64, (u32, u32))> = None;
        for size2 in sizes(self.max_size).into_iter().filter(|&z| z >= size) {
            // At one size the cost rises with n: the first n that meets it is that size's cheapest.
            let meets = sides(self.max_n)
                .into_iter()
                .filter(|&n2| n2 >= n && (n2, size2) != (n, size))
                .find(|&n2| predicted_at(self.class, at, (n2, size2)) <= target);
            if let Some(n2) = meets {
                let cost = self.price((n2, size2));
                if best.is_none_or(|(c, _)| cost < c) {
                    best = Some((cost, (n2, size2)));
                }
            }
        }
        best.map(|(_, choice)| choice)
    }

    /// The next grid after a try `at` that missed `target`, or None when nothing that can grow
    /// would reach it. First the cheapest grid predicted to meet it (`cheapest_meeting`). Where
    /// none is, the target is out of reach by the prediction, and shares decide what grows: the
    /// maps' error gets half the target's square while the map size can double; the sampling
    /// error gets the rest, and n grows to what its order says reaches that (at least one more).
    /// Where n is at its largest the maps take the excess; where the maps are at their largest
    /// and their error alone misses the target, nothing can reach it. Where even the largest maps
    /// would miss it (their error falling at best as the texel size), the sampling error need
    /// only stay under half that floor, which adds at most 12% to it: n does not chase a target
    /// the maps put out of reach.
    pub fn next_choice(&self, at: &At, target: f64) -> Option<(u32, u32)> {
        if let Some(choice) = self.cheapest_meeting(at, target) {
            return Some(choice);
        }
        let (n, size, p, max_size) = (at.n, at.size, &at.p, self.max_size);
        let share = target / std::f64::consts::SQRT_2;
        let ladder = sides(self.max_n);
        let top = *ladder.last().expect("at least one side");
        let (can_n, can_size) = (n < top, size < max_size);
        let mut grow_size = p.predicted_map > share && can_size;
        if !can_size && p.predicted_map >= target {
            return None;
        }
        let floor =
            p.predicted_map * 0.5f64.powi((max_size / size.max(1)).max(1).trailing_zeros() as i32);
        let sampling_share = if grow_size {
            share
        } else {
            (target * target - p.predicted_map * p.predicted_map).sqrt()
        };
        let sampling_share = if floor > target {
            sampling_share.max(0.5 * floor)
        } else {
            sampling_share
        };
        let grow_n = p.predicted_sampling > sampling_share && can_n;
        if p.predicted_sampling > sampling_share && !can_n {
            grow_size = can_size;
        }
        if !grow_n && !grow_size {
            return None;
        }
        let n2 = if grow_n {
            // The first side past n whose sampling error its order (and its factor) puts under the share.
            ladder
                .iter()
                .copied()
                .find(|&n2| {
                    n2 > n && sampling_at(self.class, n, p.predicted_sampling, n2) <= sampling_share
                })
                .unwrap_or(top)
        } else {
            n
        };
        Some((n2, if grow_size { size * 2 } else { size }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ladder(class: Class, max_n: u32, max_size: u32, costs: &Costs) -> Ladder {
        Ladder::new(class, max_n, max_size, costs.clone())
    }

    fn at(n: u32, size: u32, p: &Prediction) -> At {
        At::new(n, size, *p)
    }

    fn tx() -> Costs {
        Costs::texels(2048)
    }

    fn p(sampling: f64, map: f64) -> Prediction {
        pa(sampling, map, 0.0)
    }

    /// With `averaging` of the maps' error falling with n.
    fn pa(sampling: f64, map: f64, averaging: f64) -> Prediction {
        Prediction {
            predicted_rmse: (sampling * sampling + map * map).sqrt(),
            predicted_sampling: sampling,
            predicted_map: map,
            predicted_quantization: map,
            predicted_bias: 0.0,
            predicted_map_averaging: averaging,
        }
    }

    #[test]
    fn the_cheapest_grid_predicted_to_meet_the_target() {
        // Maps well under the target: sampling gets sqrt(0.01² − map²) ≈ 0.00998 and is 1.42× over
        // it, so n grows by 1.42^(1/1.5) ≈ 1.26: 5 → 6.3 → 7, at the same maps.
        let share = 0.01 / std::f64::consts::SQRT_2;
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx())
                .next_choice(&at(5, 512, &p(2.0 * share, 0.1 * share)), 0.01),
            Some((7, 512))
        );
        // The maps alone over the target: doubling them (predicted 0.0053 + 0.0035) meets it.
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx())
                .next_choice(&at(5, 512, &p(0.5 * share, 1.5 * share)), 0.01),
            Some((5, 1024))
        );
        // Both at 0.0078 at 256²: 4×4 there would be predicted to meet 0.01 (16 maps of cost ½),
        // but 256² maps are not a grid the calibration was fitted on: 3×3 at 512² (0.0087, cost 9),
        // before 4×4 there (0.0095 with the even side's factor, cost 16).
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx())
                .next_choice(&at(3, 256, &p(1.1 * share, 1.1 * share)), 0.01),
            Some((3, 512))
        );
        // Maps at their largest, their error under the target: n takes the rest of it.
        // sampling share = sqrt(0.01² − 0.009²) = 0.00436; 0.006 / 0.00436 = 1.38 → 5 · 1.24 = 6.2,
        // and the next odd side is 7.
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx()).next_choice(&at(5, 2048, &p(0.006, 0.009)), 0.01),
            Some((7, 2048))
        );
        // Maps at their largest and their error alone over the target: out of reach.
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx()).next_choice(&at(5, 2048, &p(0.001, 0.011)), 0.01),
            None
        );
        // n at its largest: nothing is predicted to meet it, and the maps take the excess.
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx())
                .next_choice(&at(17, 512, &p(1.5 * share, 0.5 * share)), 0.01),
            Some((17, 1024))
        );
        // Nothing left to grow.
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx())
                .next_choice(&at(17, 2048, &p(1.5 * share, 0.5 * share)), 0.01),
            None
        );
        // Maps whose error would miss the target even at 2048² (grove at 128²: 0.196 at 512²,
        // floor 0.049 against 0.012): nothing meets it, so n grows only to keep sampling under
        // half the floor, 3 · (0.031 / 0.0245)^(2/3) = 3.5 → 5, not to 0.012 / √2 (which asks for 9).
        // 4×4 would be 0.035 with the even side's factor (2.28 against 1.32).
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx()).next_choice(&at(3, 512, &p(0.031, 0.196)), 0.012),
            Some((5, 1024))
        );
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx())
                .next_choice(&at(5, 1024, &p(0.020, 0.150)), 0.012),
            Some((5, 2048))
        );
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx())
                .next_choice(&at(5, 2048, &p(0.016, 0.117)), 0.012),
            None
        );
        // The ladder: odd sides, and even ones to 6 (their own factor), maps from 512² (256² alone
        // under max_size = 256).
        assert_eq!(
            (sides(17), sides(8), sides(2)),
            (
                vec![2, 3, 4, 5, 6, 7, 9, 11, 13, 15, 17],
                vec![2, 3, 4, 5, 6, 7],
                vec![2]
            )
        );
        assert_eq!(
            (sizes(2048), sizes(512), sizes(256)),
            (vec![512, 1024, 2048], vec![512], vec![256])
        );
        assert_eq!(
            ladder(Class::Plane, 2, 256, &Costs::texels(256))
                .next_choice(&at(2, 256, &p(0.02, 0.02)), 0.01),
            None
        );
        // The same maps under a target that 2048² meets (0.049 and 0.031 against 0.06) and 1024²
        // cannot (0.098): straight to 2048².
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx()).next_choice(&at(3, 512, &p(0.031, 0.196)), 0.06),
            Some((3, 2048))
        );
    }

    #[test]
    fn maps_error_that_averages_over_samples_buys_samples_not_texels() {
        // overlapping-occluders-like at 3×3, 512²: sampling 0.02, maps 0.023 of which 0.021
        // averages over samples. Against 0.012: with the averaging part, 7×7 at 1024² (predicted
        // maps 0.0065, sampling 0.0056; cost 98); without it the maps must shrink by texels alone
        // (7×7 at 1024² would read 0.0128), and 5×5 at 2048² (cost 100) is the cheapest.
        let with = pa(0.02, 0.023, 0.021);
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx()).next_choice(&at(3, 512, &with), 0.012),
            Some((7, 1024))
        );
        assert!(
            (predicted_at(Class::Plane, &at(3, 512, &with), (7, 1024)) - 0.00859).abs() < 1e-4,
            "{}",
            predicted_at(Class::Plane, &at(3, 512, &with), (7, 1024))
        );
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx()).next_choice(&at(3, 512, &p(0.02, 0.023)), 0.012),
            Some((5, 2048))
        );
        // Every bit of it averaging: at the same maps, m falls as 1/n: 3 → 9 thirds it.
        let all = pa(0.0, 0.03, 0.03);
        assert!((predicted_at(Class::Plane, &at(3, 512, &all), (9, 512)) - 0.01).abs() < 1e-12);
        assert_eq!(
            ladder(Class::Plane, 17, 512, &tx()).next_choice(&at(3, 512, &all), 0.0101),
            Some((9, 512))
        );
        // With larger maps allowed, 3×3 at 2048² (0.0075, cost 36) is cheaper than 9×9 at 512² (81).
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx()).next_choice(&at(3, 512, &all), 0.0101),
            Some((3, 2048))
        );
    }

    #[test]
    fn measured_prices_move_the_choice_to_larger_maps_where_they_cost_little_more() {
        // bunny at 128² from 3×3 at 512² (predicted 0.0315: sampling 0.0161, maps 0.0270 of which
        // 0.0218 averages), priced as lavapipe's compute raster timed it: 31.0, 36.2 and 51.6 ms per
        // map at 512², 1024² and 2048². Under `texels` a 2048² map costs four 512² ones; measured, 1.7.
        // Against 0.012: 7×7 at 1024² (98 units) under `texels`, 5×5 at 2048² (1290 ms) measured.
        let bunny = pa(0.0161, 0.0270, 0.0218);
        let timed = Costs(vec![(512, 31.0), (1024, 36.2), (2048, 51.6)]);
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx()).next_choice(&at(3, 512, &bunny), 0.012),
            Some((7, 1024))
        );
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &timed).next_choice(&at(3, 512, &bunny), 0.012),
            Some((5, 2048))
        );
        // At 0.03 the maps' part decides, and an even side is on the ladder: 4×4 at 512² (0.0291
        // with the even side's sampling factor, 16 units) under `texels`, before 3×3 at 1024² (18);
        // measured, 3×3 at 1024² (326 ms against 496).
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx()).next_choice(&at(3, 512, &bunny), 0.03),
            Some((4, 512))
        );
        assert!(
            (predicted_at(Class::Plane, &at(3, 512, &bunny), (4, 512)) - 0.0291).abs() < 1e-4,
            "{}",
            predicted_at(Class::Plane, &at(3, 512, &bunny), (4, 512))
        );
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &timed).next_choice(&at(3, 512, &bunny), 0.03),
            Some((3, 1024))
        );
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &timed).next_choice(&at(3, 512, &bunny), 0.02),
            ladder(Class::Plane, 17, 2048, &tx()).next_choice(&at(3, 512, &bunny), 0.02)
        );
        // A size above max_size is never priced, so never chosen: 7×7 at 512² (49) before 5×5 at 1024² (50).
        assert_eq!(
            Costs::texels(1024)
                .0
                .iter()
                .map(|c| c.0)
                .collect::<Vec<_>>(),
            vec![512, 1024]
        );
        assert_eq!(
            ladder(Class::Plane, 17, 1024, &Costs::texels(1024))
                .next_choice(&at(3, 512, &bunny), 0.02),
            Some((7, 512))
        );
    }

    #[test]
    fn cows_takes_2048_maps_where_no_1024_grid_is_predicted_to_meet_the_target_for_less() {
        // cows at 128² from 3×3 at 512² (predicted 0.0556: sampling 0.0165, maps 0.0531 of which
        // 0.0289 averages), at the prices a settled frame gave on lavapipe: 16.4, 21.2 and 39.1 ms
        // per map (results/budget-prices/). Against 0.03, 3×3 at 1024² (the oracle, measured
        // 0.0268) is predicted at 0.031: 3×3 at 2048² (352) beats 5×5 at 1024² (530), and would
        // lose only to a 2048² map priced above 25/9 = 2.78 times a 1024² one.
        let cows = pa(0.0165, 0.0531, 0.0289);
        assert!(
            (predicted_at(Class::Plane, &at(3, 512, &cows), (3, 1024)) - 0.0313).abs() < 1e-4,
            "{}",
            predicted_at(Class::Plane, &at(3, 512, &cows), (3, 1024))
        );
        let frame = Costs(vec![(512, 16.4), (1024, 21.2), (2048, 39.1)]);
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &frame).next_choice(&at(3, 512, &cows), 0.03),
            Some((3, 2048))
        );
        let dear = |ratio: f64| Costs(vec![(512, 16.4), (1024, 21.2), (2048, 21.2 * ratio)]);
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &dear(2.7)).next_choice(&at(3, 512, &cows), 0.03),
            Some((3, 2048))
        );
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &dear(2.8)).next_choice(&at(3, 512, &cows), 0.03),
            Some((5, 1024))
        );
        // Against 0.02 no grid at 1024² is predicted to meet it (the maps' part alone, halved,
        // stays over): 2048² maps at any price.
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &dear(10.0)).next_choice(&at(3, 512, &cows), 0.02),
            Some((5, 2048))
        );
    }

    #[test]
    fn a_first_search_steps_down_to_a_cheaper_grid_predicted_to_meet_the_target() {
        // 5×5 at 512² reads 0.0187 against 0.02 (sampling 0.005, maps 0.018 of which 0.012
        // averages). 3×3 at 1024² is predicted at 0.0162 (sampling 0.005 · (5/3)^1.5, maps
        // sqrt(0.018² + 0.012² · 16/9) / 2) for 18 units against 25; 3×3 at 512² at 0.0241.
        let five = pa(0.005, 0.018, 0.012);
        assert!(
            (predicted_at(Class::Plane, &at(5, 512, &five), (3, 1024)) - 0.01615).abs() < 1e-4,
            "{}",
            predicted_at(Class::Plane, &at(5, 512, &five), (3, 1024))
        );
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx()).cheaper_meeting(
                &at(5, 512, &five),
                0.02,
                &[(5, 512)]
            ),
            Some((3, 1024))
        );
        // Tried already (it missed): nothing else cheaper is predicted to meet it.
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx()).cheaper_meeting(
                &at(5, 512, &five),
                0.02,
                &[(5, 512), (3, 1024)]
            ),
            None
        );
        // A smaller map raises the maps' error as a larger one lowers it: 4× its square per halving.
        assert!(
            (predicted_at(Class::Plane, &at(3, 512, &p(0.0, 0.01)), (3, 256)) - 0.02).abs() < 1e-12
        );
        // At 0.015 no grid of fewer than 25 units is predicted to meet it: 4×4 at 512² (16 units)
        // reads 0.0235 with the even side's factor, and 256² maps are off the ladder.
        assert_eq!(
            ladder(Class::Plane, 17, 2048, &tx()).cheaper_meeting(
                &at(5, 512, &five),
                0.015,
                &[(5, 512)]
            ),
            None
        );
    }
}
