//! One-sided upper bounds on the mean of the weighted squared errors `w_i = e_i² / (N q_i)` of
//! K independent draws: the frame's MSE is their expectation, so a bound on it at 1 − δ is a
//! bound on the RMSE after a square root (docs/certify.md §3).
//!
//! - [`betting`] holds for any error layout: w is bounded (e² ≤ 1, q ≥ a/N gives w ≤ 1/a), and a
//!   nonnegative betting martingale (Waudby-Smith & Ramdas 2020) cannot exceed 1/δ with
//!   probability over δ (Ville). It pays for the range: with no error seen it still reads about
//!   ln(1/δ)·B/K.
//! - [`student_t`] is sharp where K is large against the tail, and under-covers where the error
//!   lies in few pixels the proxy did not favour (a skewed, heavy-tailed w). [`calibrated`] is it
//!   times a stretch fitted on the fitting half of the shipped scenes and checked on the other.

/// Which bound a record used.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BoundKind {
    /// Distribution-free, per frame: [`betting`].
    PerFrame,
    /// The Student t bound times [`STRETCH`]: promised over scenes (coverage measured on scenes
    /// the stretch was not fitted on).
    Calibrated,
}

impl BoundKind {
    pub fn name(self) -> &'static str {
        match self {
            BoundKind::PerFrame => "per-frame",
            BoundKind::Calibrated => "calibrated",
        }
    }
}

/// The calibrated bound's stretch of the Student t bound on the RMSE. `penumbra certify-study`
/// fits it at K = 2048 on the fitting half's draws (the split-conformal 95% rank of measured /
/// t-bound): 1.02 for both proxies (results/certify-coverage/); the engine keeps 1.05, a margin
/// over the fit, and the checking half measures what it covers.
pub const STRETCH: f64 = 1.05;

/// The mean and the sample standard deviation of `w`.
pub(crate) fn mean_sd(w: &[f64]) -> (f64, f64) {
    let n = w.len() as f64;
    if w.is_empty() {
        return (0.0, 0.0);
    }
    let mean = w.iter().sum::<f64>() / n;
    let var = if w.len() > 1 {
        w.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    (mean, var.sqrt())
}

/// The one-sided Student t upper bound on the mean at confidence 1 − δ.
pub(crate) fn student_t(w: &[f64], delta: f64) -> f64 {
    let (mean, sd) = mean_sd(w);
    if w.len() < 2 {
        return f64::INFINITY;
    }
    let k = w.len() as f64;
    mean + t_quantile(1.0 - delta, k - 1.0) * sd / k.sqrt()
}

/// The calibrated bound on the RMSE: [`STRETCH`] × sqrt of the Student t bound on the MSE.
pub(crate) fn calibrated(w: &[f64], delta: f64) -> f64 {
    STRETCH * student_t(w, delta).max(0.0).sqrt()
}

/// The largest bet a step takes: a fraction of what keeps every factor positive.
const MAX_BET: f64 = 0.75;

/// A distribution-free upper bound on the mean of `w`, each in [0, `range`], at confidence
/// 1 − δ: the least m at which the capital of betting against "the mean is m" reaches 1/δ
/// (Waudby-Smith & Ramdas 2020, the hedged capital process's one side, with their predictable
/// plug-in bets). The draws must be independent and in the order drawn.
pub(crate) fn betting(w: &[f64], range: f64, delta: f64) -> f64 {
    if w.is_empty() || range <= 0.0 {
        return range.max(0.0);
    }
    let x: Vec<f64> = w.iter().map(|v| (v / range).clamp(0.0, 1.0)).collect();
    let n = x.len() as f64;
    let log_target = (1.0 / delta).ln();
    // Bets from the draws before each one (predictable), independent of m.
    let mut bets = Vec::with_capacity(x.len());
    let (mut sum, mut sq) = (0.5, 0.25);
    for (i, &xi) in x.iter().enumerate() {
        let count = i as f64 + 1.0;
        let variance = sq / count;
        bets.push((2.0 * log_target / (n * variance)).sqrt().min(MAX_BET));
        let mean = sum / count;
        sum += xi;
        sq += (xi - mean) * (xi - mean);
    }
    // ln K(m) = Σ ln(1 + λ_i (m − x_i)) grows with m: bisect for where it reaches ln(1/δ).
    let log_capital = |m: f64| {
        x.iter()
            .zip(&bets)
            .map(|(xi, l)| (1.0 + l * (m - xi)).ln())
            .sum::<f64>()
    };
    if log_capital(1.0) < log_target {
        return range;
    }
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if log_capital(mid) >= log_target {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi * range
}

/// The p-quantile of Student's t with `df` degrees of freedom (bisection on its CDF).
pub(crate) fn t_quantile(p: f64, df: f64) -> f64 {
    if p == 0.5 {
        return 0.0;
    }
    if p < 0.5 {
        return -t_quantile(1.0 - p, df);
    }
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    while t_cdf(hi, df) < p && hi < 1e6 {
        hi *= 2.0;
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if t_cdf(mid, df) < p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Student's t CDF.
pub(crate) fn t_cdf(t: f64, df: f64) -> f64 {
    let x = df / (df + t * t);
    let tail = 0.5 * incomplete_beta(x, 0.5 * df, 0.5);
    if t >= 0.0 {
        1.0 - tail
    } else {
        tail
    }
}

/// The regularised incomplete beta function I_x(a, b) (continued fraction, modified Lentz).
pub(crate) fn incomplete_beta(x: f64, a: f64, b: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    if x >= 1.0 {
        return 1.0;
    }
    let front =
        (ln_gamma(a + b) - ln_gamma(a) - ln_gamma(b) + a * x.ln() + b * (1.0 - x).ln()).exp();
    if x < (a + 1.0) / (a + b + 2.0) {
        front * beta_fraction(x, a, b) / a
    } else {
        1.0 - front * beta_fraction(1.0 - x, b, a) / b
    }
}

fn beta_fraction(x: f64, a: f64, b: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let (qab, qap, qam) = (a + b, a + 1.0, a - 1.0);
    let mut c = 1.0;
    let mut d = 1.0 - qab * x / qap;
    if d.abs() < TINY {
        d = TINY;
    }
    d = 1.0 / d;
    let mut h = d;
    for m in 1..400 {
        let m = m as f64;
        let m2 = 2.0 * m;
        let aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 + aa * d;
        d = if d.abs() < TINY { TINY } else { d };
        c = 1.0 + aa / c;
        c = if c.abs() < TINY { TINY } else { c };
        d = 1.0 / d;
        h *= d * c;
        let aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 + aa * d;
        d = if d.abs() < TINY { TINY } else { d };
        c = 1.0 + aa / c;
        c = if c.abs() < TINY { TINY } else { c };
        d = 1.0 / d;
        let step = d * c;
        h *= step;
        if (step - 1.0).abs() < 1e-15 {
            break;
        }
    }
    h
}

/// ln Γ(x) for x > 0 (Lanczos, g = 7).
fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        return (std::f64::consts::PI / (std::f64::consts::PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = G[0];
    let t = x + 7.5;
    for (i, g) in G.iter().enumerate().skip(1) {
        a += g / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn t_quantiles_match_the_tables() {
        // One-sided 95%: 6.314 (1 df), 2.015 (5), 1.812 (10), 1.660 (100); the normal's 1.645 far out.
        for (df, q) in [
            (1.0, 6.3138),
            (5.0, 2.0150),
            (10.0, 1.8125),
            (100.0, 1.6602),
            (2047.0, 1.6456),
        ] {
            assert!(
                (t_quantile(0.95, df) - q).abs() < 2e-4,
                "df {df}: {} against {q}",
                t_quantile(0.95, df)
            );
        }
        assert!((t_quantile(0.975, 30.0) - 2.0423).abs() < 2e-4);
        assert_eq!(t_quantile(0.5, 7.0), 0.0);
        assert!((t_quantile(0.05, 10.0) + 1.8125).abs() < 2e-4);
    }

    /// A reproducible uniform stream for the coverage checks.
    fn stream(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn betting_covers_a_rare_heavy_error_at_its_level_and_t_does_not() {
        // 1% of draws carry the whole error (w = 1), the rest none: mean 0.01. With K = 200 a
        // third of the samples see no error at all, where the t bound reads 0.
        let (k, trials, delta) = (200, 2000, 0.05);
        let mut next = stream(11);
        let (mut betting_misses, mut t_misses) = (0, 0);
        for _ in 0..trials {
            let w: Vec<f64> = (0..k)
                .map(|_| if next() < 0.01 { 1.0 } else { 0.0 })
                .collect();
            betting_misses += (betting(&w, 1.0, delta) < 0.01) as u32;
            t_misses += (student_t(&w, delta) < 0.01) as u32;
        }
        assert!(
            betting_misses as f64 / trials as f64 <= delta,
            "betting missed {betting_misses} of {trials}"
        );
        assert!(
            t_misses as f64 / trials as f64 > 0.10,
            "t missed only {t_misses} of {trials}"
        );
    }

    #[test]
    fn betting_reads_the_floor_when_no_error_is_seen_and_scales_with_the_range() {
        // No error in K draws: about ln(1/δ)/(0.75 K) of the range, whatever the frame.
        let zeros = vec![0.0; 2048];
        let b = betting(&zeros, 1.0, 0.05);
        let floor = (20.0f64).ln() / (MAX_BET * 2048.0);
        assert!(b > 0.9 * floor && b < 1.1 * floor, "{b} against {floor}");
        assert!((betting(&zeros, 4.0, 0.05) - 4.0 * b).abs() < 1e-12);
        // Never under the mean of what it saw, never over the range.
        let half = vec![0.5; 100];
        let u = betting(&half, 1.0, 0.05);
        assert!(u > 0.5 && u <= 1.0, "{u}");
        assert_eq!(betting(&[], 3.0, 0.05), 3.0);
    }

    #[test]
    fn student_t_is_the_textbook_bound() {
        let w = [0.0, 1.0, 2.0, 3.0, 4.0];
        // mean 2, sd sqrt(2.5), t(0.95, 4) = 2.1318.
        let expect = 2.0 + 2.1318 * 2.5f64.sqrt() / 5f64.sqrt();
        assert!((student_t(&w, 0.05) - expect).abs() < 1e-3);
        assert!((calibrated(&w, 0.05) - STRETCH * expect.sqrt()).abs() < 1e-3);
        assert_eq!(student_t(&[1.0], 0.05), f64::INFINITY);
    }
}
