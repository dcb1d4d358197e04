//! `penumbra calibrate` (docs/budget.md): the calibrated estimate's factors fitted on the fitting
//! half of the shipped scenes' `penumbra estimate` pairs, and read on the checking half and the
//! held-out scenes, which the fit never sees.

use crate::methods::calibration::{calibrated_with, Class, Factors};
use crate::methods::estimate::Prediction;
use crate::studies::estimate::EstimateLine;
pub mod charts;
pub mod command;

use self::charts::{calibration_svg, parts_svg};
use crate::report::charts::svg_to_png;
use crate::studies::estimate::charts::EstimatePoint;
use crate::{Error, Result};

/// Which half a scene's pairs fall in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Half {
    Fitting,
    Checking,
    /// A scene not shipped (a class the fit never saw): read as the checking half is.
    HeldOut,
}

impl Half {
    pub fn name(self) -> &'static str {
        match self {
            Half::Fitting => "fitting",
            Half::Checking => "checking",
            Half::HeldOut => "held out",
        }
    }
}

/// The fixed split of the shipped area-light scenes (rectangle, disk and ball lights), the one
/// list docs/budget.md quotes: each class in both halves where it has two scenes (the analytic
/// ones, the meshes, the ball lights), alternating down a list sorted by kind.
pub const SPLIT: [(&str, Half); 15] = [
    ("analytic-square", Half::Fitting),
    ("disk-bar", Half::Checking),
    ("pole-between-corners", Half::Fitting),
    ("grazing-ground", Half::Checking),
    ("overlapping-occluders", Half::Fitting),
    ("slat-roof", Half::Checking),
    ("point-edge", Half::Fitting),
    ("point-room", Half::Checking),
    ("default", Half::Fitting),
    ("teapot", Half::Checking),
    ("cows", Half::Fitting),
    ("dragon", Half::Checking),
    ("bunny", Half::Fitting),
    ("bunny-seed-framing", Half::Checking),
    ("grove", Half::Fitting),
];

pub fn half(scene: &str) -> Half {
    SPLIT
        .iter()
        .find(|(s, _)| *s == scene)
        .map_or(Half::HeldOut, |(_, h)| *h)
}

/// One (scene, setting) pair with what the fit reads.
#[derive(Clone, Debug)]
pub struct Pair {
    pub scene: String,
    pub half: Half,
    pub class: Class,
    pub spec: String,
    pub map_size: u32,
    pub maps: u32,
    pub measured: f64,
    pub predicted_sampling: f64,
    pub predicted_map: f64,
    /// Each part measured (`EstimateLine::measured_sampling`, `measured_map`): which part of a
    /// miss under-reads.
    pub measured_sampling: f64,
    pub measured_map: f64,
}

impl Pair {
    pub fn from_line(l: &EstimateLine, class: Class) -> Pair {
        Pair {
            scene: l.core.scene.clone(),
            half: half(&l.core.scene),
            class,
            spec: l.core.spec.clone(),
            map_size: l.core.map_size,
            maps: l.core.maps,
            measured: l.core.rmse,
            predicted_sampling: l.predicted_sampling,
            predicted_map: l.predicted_map,
            measured_sampling: l.measured_sampling,
            measured_map: l.measured_map,
        }
    }
    pub fn raw(&self) -> f64 {
        self.predicted_sampling.hypot(self.predicted_map)
    }
    pub fn calibrated(&self, f: Factors) -> f64 {
        let p = Prediction {
            predicted_rmse: self.raw(),
            predicted_sampling: self.predicted_sampling,
            predicted_map: self.predicted_map,
            predicted_quantization: 0.0,
            predicted_bias: 0.0,
            predicted_map_averaging: 0.0,
        };
        calibrated_with(&p, f).predicted_rmse
    }
}

/// The share of pairs the promise must cover (predicted ≥ measured), in percent.
pub const COVERAGE_PERCENT: usize = 95;
/// The stretches of the factors the report reads (the cost of more reliability).
const STRETCHES: [f64; 6] = [1.0, 1.25, 1.5, 2.0, 2.5, 3.0];
/// The factors' grid: 0.50 to 4.00 in steps of 0.01.
const GRID: (u32, u32) = (50, 400);

/// Coverage and sharpness of `f` on `pairs`: (pairs, covered, median calibrated/measured).
pub fn reading(pairs: &[&Pair], f: &dyn Fn(&Pair) -> Factors) -> (usize, usize, f64) {
    let mut ratios: Vec<f64> = pairs
        .iter()
        .map(|p| p.calibrated(f(p)) / p.measured.max(1e-12))
        .collect();
    let covered = ratios.iter().filter(|r| **r >= 1.0).count();
    ratios.sort_by(f64::total_cmp);
    let median = match ratios.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => ratios[n / 2],
        n => 0.5 * (ratios[n / 2 - 1] + ratios[n / 2]),
    };
    (pairs.len(), covered, median)
}

fn covers(pairs: &[&Pair], f: Factors) -> bool {
    let (n, covered, _) = reading(pairs, &|_| f);
    covered * 100 >= COVERAGE_PERCENT * n
}

/// The fit, on the fitting half only: the plane lights' two factors, the pair that covers 95% of
/// their pairs with the least median calibrated/measured (ties: the smaller sampling factor).
/// Then the ball lights': their maps' factor the least that covers 95% of their maps' part on its
/// own measure (`measured_map`), because in their totals the sampling part hides it (`point-edge`:
/// the maps' part is 0.32–0.76 of the measured RMSE, and its estimate reads 0.27–0.75 of it), then
/// their sampling factor the least that covers 95% of their totals with it. None where no factors
/// on the grid cover.
pub fn fit(pairs: &[Pair]) -> Option<(Factors, Factors)> {
    let fitting = |c: Class| -> Vec<&Pair> {
        pairs
            .iter()
            .filter(|p| p.half == Half::Fitting && p.class == c)
            .collect()
    };
    let (plane, cube) = (fitting(Class::Plane), fitting(Class::Cube));
    let step = |k: u32| f64::from(k) / 100.0;
    let mut best: Option<(f64, Factors)> = None;
    for a in GRID.0..=GRID.1 {
        for b in GRID.0..=GRID.1 {
            let f = Factors {
                sampling: step(a),
                map: step(b),
            };
            if !covers(&plane, f) {
                continue;
            }
            let median = reading(&plane, &|_| f).2;
            if best.is_none_or(|(m, _)| median < m - 1e-12) {
                best = Some((median, f));
            }
        }
    }
    let plane_f = best?.1;
    let cube_f = if cube.is_empty() {
        plane_f
    } else {
        let map = (GRID.0..=GRID.1).map(step).find(|&b| {
            cube.iter()
                .filter(|p| b * p.predicted_map >= p.measured_map)
                .count()
                * 100
                >= COVERAGE_PERCENT * cube.len()
        })?;
        (GRID.0..=GRID.1)
            .map(|a| Factors {
                sampling: step(a),
                map,
            })
            .find(|&f| covers(&cube, f))?
    };
    Some((plane_f, cube_f))
}

/// The factors of a pair's class.
pub fn of(fitted: (Factors, Factors)) -> impl Fn(&Pair) -> Factors {
    move |p| match p.class {
        Class::Plane => fitted.0,
        Class::Cube => fitted.1,
    }
}

/// `pairs.csv`, `calibration.md` and the chart, for `factors` (the engine's, or a refit).
pub fn files(pairs: &[Pair], factors: (Factors, Factors)) -> Result<Vec<(String, Vec<u8>)>> {
    let f = of(factors);
    let mut csv = String::from("scene,half,class,spec,map_size,maps,measured_rmse,predicted_sampling,predicted_map,predicted_raw,calibrated,calibrated_over_measured,covered,measured_sampling,measured_map\n");
    for p in pairs {
        let c = p.calibrated(f(p));
        csv += &format!(
            "{},{},{},\"{}\",{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.4},{},{:.6},{:.6}\n",
            p.scene,
            p.half.name(),
            p.class.name(),
            p.spec,
            p.map_size,
            p.maps,
            p.measured,
            p.predicted_sampling,
            p.predicted_map,
            p.raw(),
            c,
            c / p.measured.max(1e-12),
            c >= p.measured,
            p.measured_sampling,
            p.measured_map
        );
    }
    let points: Vec<EstimatePoint> = pairs
        .iter()
        .map(|p| EstimatePoint {
            layout: format!("{} half", p.half.name()).replace("held out half", "held out"),
            label: format!(
                "{} {}@{}",
                p.scene,
                p.spec
                    .replace("regular:", "")
                    .replace(",layout=centred", ""),
                p.map_size
            ),
            measured: p.measured,
            predicted: p.calibrated(f(p)),
        })
        .collect();
    let svg = calibration_svg(
        "Calibrated predicted against measured RMSE of V, by half of the split",
        &points,
    )
    .map_err(|e| Error::limit(format!("calibration chart: {e}")))?;
    let parts: Vec<EstimatePoint> = pairs
        .iter()
        .map(|p| {
            let k = f(p);
            EstimatePoint {
                layout: format!("{} half", p.half.name()).replace("held out half", "held out"),
                label: if p.calibrated(k) < p.measured {
                    format!(
                        "{} {}@{}",
                        p.scene,
                        p.spec
                            .replace("regular:", "")
                            .replace(",layout=centred", ""),
                        p.map_size
                    )
                } else {
                    String::new()
                },
                measured: k.sampling * p.predicted_sampling / p.measured_sampling.max(1e-12),
                predicted: k.map * p.predicted_map / p.measured_map.max(1e-12),
            }
        })
        .collect();
    let parts = parts_svg(&parts).map_err(|e| Error::limit(format!("parts chart: {e}")))?;
    let md = markdown(pairs, factors);
    Ok(vec![
        ("charts/parts.png".to_string(), svg_to_png(&parts, 1.0)?),
        ("charts/parts.svg".to_string(), parts.into_bytes()),
        ("pairs.csv".to_string(), csv.into_bytes()),
        ("calibration.md".to_string(), md.into_bytes()),
        ("charts/calibration.png".to_string(), svg_to_png(&svg, 1.0)?),
        ("charts/calibration.svg".to_string(), svg.into_bytes()),
    ])
}

/// The factors and, per half, the coverage and the median calibrated/measured (and the raw
/// estimate's, for comparison).
pub fn markdown(pairs: &[Pair], factors: (Factors, Factors)) -> String {
    let f = of(factors);
    let raw = |_: &Pair| Factors {
        sampling: 1.0,
        map: 1.0,
    };
    let mut s = format!(
        "# The calibrated estimate\n\nFactors (sampling, maps): plane lights {:.2}, {:.2}; ball lights {:.2}, {:.2}.\n\n\
         | half | pairs | predicted ≥ measured | share | median predicted/measured | raw: share | raw: median |\n|---|---:|---:|---:|---:|---:|---:|\n",
        factors.0.sampling, factors.0.map, factors.1.sampling, factors.1.map
    );
    for h in [Half::Fitting, Half::Checking, Half::HeldOut] {
        let these: Vec<&Pair> = pairs.iter().filter(|p| p.half == h).collect();
        if these.is_empty() {
            continue;
        }
        let (n, covered, median) = reading(&these, &f);
        let (_, raw_covered, raw_median) = reading(&these, &raw);
        s += &format!(
            "| {} | {n} | {covered} | {:.1}% | {median:.2} | {:.1}% | {raw_median:.2} |\n",
            h.name(),
            100.0 * covered as f64 / n as f64,
            100.0 * raw_covered as f64 / n as f64
        );
    }
    s += "\nWhat more reliability costs: the factors all times a stretch, read on each half (the fit stays the fitting half's; the median predicted/measured is the price, as `auto` buys grids to the calibrated prediction):\n\n\
          | stretch | fitting: share | fitting: median | checking and held out: share | checking and held out: median |\n|---:|---:|---:|---:|---:|\n";
    for stretch in STRETCHES {
        let g = |p: &Pair| {
            let k = f(p);
            Factors {
                sampling: k.sampling * stretch,
                map: k.map * stretch,
            }
        };
        let fitting: Vec<&Pair> = pairs.iter().filter(|p| p.half == Half::Fitting).collect();
        let other: Vec<&Pair> = pairs.iter().filter(|p| p.half != Half::Fitting).collect();
        // A half without pairs reads `-`.
        let cells = |(n, c, m): (usize, usize, f64)| {
            if n == 0 {
                "- | -".to_string()
            } else {
                format!("{:.1}% | {m:.2}", 100.0 * c as f64 / n as f64)
            }
        };
        s += &format!(
            "| {stretch:.2} | {} | {} |\n",
            cells(reading(&fitting, &g)),
            cells(reading(&other, &g))
        );
    }
    s += "\nThe pairs under the measured, and which part under-reads (each calibrated part over its measured part: the sampling part against the exact visibility at the grid's points, the maps' part against V there):\n\n\
          | scene | half | setting | calibrated/measured | sampling part | maps' part |\n|---|---|---|---:|---:|---:|\n";
    for p in pairs.iter().filter(|p| p.calibrated(f(p)) < p.measured) {
        let k = f(p);
        s += &format!(
            "| {} | {} | {}@{} | {:.2} | {:.2} | {:.2} |\n",
            p.scene,
            p.half.name(),
            p.spec,
            p.map_size,
            p.calibrated(k) / p.measured,
            k.sampling * p.predicted_sampling / p.measured_sampling.max(1e-12),
            k.map * p.predicted_map / p.measured_map.max(1e-12)
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pair(scene: &str, class: Class, measured: f64, s: f64, m: f64) -> Pair {
        Pair {
            scene: scene.into(),
            half: half(scene),
            class,
            spec: "regular:n=3".into(),
            map_size: 512,
            maps: 9,
            measured,
            predicted_sampling: s,
            predicted_map: m,
            measured_sampling: measured,
            measured_map: 0.0,
        }
    }

    #[test]
    fn the_split_halves_the_shipped_scenes_and_the_rest_is_held_out() {
        let fitting = SPLIT.iter().filter(|(_, h)| *h == Half::Fitting).count();
        assert_eq!((fitting, SPLIT.len() - fitting), (8, 7));
        assert_eq!(half("grove"), Half::Fitting);
        assert_eq!(half("teapot"), Half::Checking);
        assert_eq!(half("lattice-grate"), Half::HeldOut);
    }

    /// The pairs of a CSV the calibration committed (results/budget-calibration/`rel`), its columns
    /// read by name: `pairs.csv` and `even/even.csv` share the leading ones, not the rest.
    fn committed_pairs(rel: &str) -> Vec<Pair> {
        let text = std::fs::read_to_string(format!(
            "{}/../results/budget-calibration/{rel}",
            env!("CARGO_MANIFEST_DIR")
        ))
        .unwrap();
        let names: Vec<&str> = text.lines().next().unwrap().split(',').collect();
        // The quoted spec holds commas: a line is scene,half,class,"spec",… and the fields after
        // the spec are counted from it (the header's fifth name on).
        let after_spec = |name: &str| {
            names
                .iter()
                .position(|n| *n == name)
                .unwrap_or_else(|| panic!("{rel}: no column {name}"))
                - 4
        };
        text.lines()
            .skip(1)
            .map(|line| {
                let mut quoted = line.split('"');
                let head: Vec<&str> = quoted.next().unwrap().split(',').collect();
                let spec = quoted.next().unwrap();
                let tail: Vec<&str> = quoted.next().unwrap().split(',').skip(1).collect();
                let num = |name: &str| tail[after_spec(name)].parse::<f64>().unwrap();
                let class = if head[2] == "cube" {
                    Class::Cube
                } else {
                    Class::Plane
                };
                Pair {
                    spec: spec.into(),
                    map_size: num("map_size") as u32,
                    maps: num("maps") as u32,
                    measured_sampling: num("measured_sampling"),
                    measured_map: num("measured_map"),
                    ..pair(
                        head[0],
                        class,
                        num("measured_rmse"),
                        num("predicted_sampling"),
                        num("predicted_map"),
                    )
                }
            })
            .collect()
    }

    /// The engine's factors are the fit on the committed pairs (results/budget-calibration): a
    /// change to either is a refit, or this fails.
    #[test]
    fn the_engines_factors_are_the_fit_on_the_committed_pairs() {
        let pairs = committed_pairs("pairs.csv");
        assert_eq!(
            pairs.iter().filter(|p| p.half == Half::Fitting).count(),
            48,
            "8 scenes × 6 settings"
        );
        let engine = (
            crate::methods::calibration::PLANE,
            crate::methods::calibration::CUBE,
        );
        assert_eq!(fit(&pairs), Some(engine));
    }

    /// The engine's even sides' sampling factors are the fit on the committed even pairs
    /// (results/budget-calibration/even/even.csv): per class, the least on the grid that covers
    /// 95% of the fitting half's even pairs with the class's maps' factor.
    #[test]
    fn the_even_sides_factors_are_the_fit_on_the_committed_even_pairs() {
        use crate::methods::calibration::{factors, EVEN_CUBE_SAMPLING, EVEN_PLANE_SAMPLING};
        let pairs = committed_pairs("even/even.csv");
        assert_eq!(
            pairs.len(),
            90,
            "15 shipped scenes × n = 2, 4, 6 at 512² and 1024²"
        );
        for (class, even, count) in [
            (Class::Plane, EVEN_PLANE_SAMPLING, 42),
            (Class::Cube, EVEN_CUBE_SAMPLING, 6),
        ] {
            let fitting: Vec<&Pair> = pairs
                .iter()
                .filter(|p| p.half == Half::Fitting && p.class == class)
                .collect();
            assert_eq!(fitting.len(), count, "{class:?}");
            let map = factors(class).map;
            let least = (GRID.0..=GRID.1)
                .map(|k| f64::from(k) / 100.0)
                .find(|&a| covers(&fitting, Factors { sampling: a, map }));
            assert_eq!(least, Some(even), "{class:?}");
        }
    }

    #[test]
    fn the_fit_reads_the_fitting_half_only() {
        // Fitting plane pairs under-read their sampling part by up to 2×; a checking pair that
        // under-reads by 10× must not move the fit.
        let mut pairs: Vec<Pair> = (1..=20)
            .map(|k| {
                pair(
                    "default",
                    Class::Plane,
                    0.01 * (1.0 + f64::from(k) / 20.0) - 1e-7,
                    0.01,
                    0.0,
                )
            })
            .collect();
        let (plane, cube) = fit(&pairs).unwrap();
        pairs.push(pair("teapot", Class::Plane, 0.1, 0.01, 0.0));
        assert_eq!(fit(&pairs).unwrap(), (plane, cube));
        // 19 of 20 covered: the 19th largest measured, 0.01 · 1.95, over its 0.01.
        assert_eq!(plane.sampling, 1.95);
        assert_eq!(
            cube, plane,
            "no ball-light pairs: the plane lights' factors"
        );
        let fitting: Vec<&Pair> = pairs.iter().filter(|p| p.half == Half::Fitting).collect();
        assert_eq!(reading(&fitting, &of((plane, cube))).1, 19);
    }

    #[test]
    fn the_ball_lights_maps_factor_is_sized_on_their_maps_part() {
        // Ball-light pairs whose totals the sampling part covers alone, while their maps' part
        // under-reads its own measure by up to 2×: the maps' factor covers 19 of 20 maps' parts
        // (the 19th largest, 0.001 · 1.95), then the sampling factor the least that covers 95%
        // of the totals with it.
        let pairs: Vec<Pair> = (1..=20)
            .map(|k| Pair {
                measured_map: 0.001 * (1.0 + f64::from(k) / 20.0) - 1e-9,
                ..pair("point-edge", Class::Cube, 0.0101, 0.01, 0.001)
            })
            .collect();
        let (_, cube) = fit(&pairs).unwrap();
        assert_eq!(cube.map, 1.95);
        // sqrt(0.0101² − (1.95 · 0.001)²) / 0.01 = 0.991: the grid's 1.00 (0.50 and up).
        assert_eq!(cube.sampling, 1.0);
        let one_less = Factors {
            sampling: 0.99,
            ..cube
        };
        assert!(reading(&pairs.iter().collect::<Vec<_>>(), &|_| one_less).1 < 19);
    }
}
