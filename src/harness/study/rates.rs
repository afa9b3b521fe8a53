//! Convergence rates: the least-squares slope of `ln e` on `ln h` with a Student-t confidence
//! interval, and the per-level observed order `ln(e_{k−1}/e_k) / ln(h_{k−1}/h_k)` (deal.II's
//! `reduction_rate_log2` generalised to any refinement factor).

use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, StudentsT};

/// A fitted rate over a set of levels.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RateFit {
    /// The slope `p` of `ln e = p ln h + c`.
    pub rate: f64,
    /// The intercept `c`.
    pub intercept: f64,
    /// Lower end of the 95 % confidence interval (`−∞`/`NaN`-free: absent with two levels).
    pub ci_low: Option<f64>,
    /// Upper end of the 95 % confidence interval.
    pub ci_high: Option<f64>,
    /// Number of levels in the fit.
    pub levels: usize,
}

/// Fits `ln e = p ln h + c` by least squares. Levels with a zero or non-finite error are
/// skipped; `None` with fewer than two usable levels. The 95 % interval uses the Student t
/// quantile with `n − 2` degrees of freedom and needs three levels.
pub fn fit_rate(h: &[f64], e: &[f64]) -> Option<RateFit> {
    let pts: Vec<(f64, f64)> = h
        .iter()
        .zip(e)
        .filter(|(hi, ei)| **hi > 0.0 && **ei > 0.0 && ei.is_finite() && hi.is_finite())
        .map(|(hi, ei)| (hi.ln(), ei.ln()))
        .collect();
    let n = pts.len();
    if n < 2 {
        return None;
    }
    let nf = n as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / nf;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / nf;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let rate = sxy / sxx;
    let (ci_low, ci_high) = if n >= 3 {
        let rss: f64 = pts
            .iter()
            .map(|p| (p.1 - my - rate * (p.0 - mx)).powi(2))
            .sum();
        let se = (rss / (nf - 2.0) / sxx).sqrt();
        let t = StudentsT::new(0.0, 1.0, nf - 2.0)
            .expect("n − 2 ≥ 1 degrees of freedom")
            .inverse_cdf(0.975);
        (Some(rate - t * se), Some(rate + t * se))
    } else {
        (None, None)
    };
    Some(RateFit {
        rate,
        intercept: my - rate * mx,
        ci_low,
        ci_high,
        levels: n,
    })
}

/// The slope of the least-squares line through `(x, y)`; `None` when all `x` coincide (or there
/// is no point).
pub fn least_squares_slope(x: &[f64], y: &[f64]) -> Option<f64> {
    let n = x.len() as f64;
    let mx = x.iter().sum::<f64>() / n;
    let my = y.iter().sum::<f64>() / n;
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// The observed order between consecutive levels; `None` on the first level and wherever an
/// error is zero or not finite.
pub fn observed_orders(h: &[f64], e: &[f64]) -> Vec<Option<f64>> {
    (0..h.len())
        .map(|k| {
            if k == 0 {
                return None;
            }
            let ok = |x: f64| x > 0.0 && x.is_finite();
            (ok(e[k - 1]) && ok(e[k]) && h[k - 1] != h[k])
                .then(|| (e[k - 1] / e[k]).ln() / (h[k - 1] / h[k]).ln())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn exact_power_law_has_its_exponent_and_a_zero_width_interval() {
        let h = [0.1, 0.05, 0.025, 0.0125];
        let e: Vec<f64> = h.iter().map(|x: &f64| 3.0 * x.powf(1.5)).collect();
        let fit = fit_rate(&h, &e).unwrap();
        assert_relative_eq!(fit.rate, 1.5, epsilon = 1e-12);
        assert_relative_eq!(fit.intercept, 3.0_f64.ln(), epsilon = 1e-12);
        assert_relative_eq!(fit.ci_low.unwrap(), 1.5, epsilon = 1e-6);
        for o in observed_orders(&h, &e).into_iter().skip(1) {
            assert_relative_eq!(o.unwrap(), 1.5, epsilon = 1e-12);
        }
    }

    #[test]
    fn interval_matches_the_t_quantile_by_hand() {
        // Four levels, dof 2: t_{0.975, 2} = 4.302652729911275 (tables).
        let h = [1.0, 0.5, 0.25, 0.125];
        let e = [1.0, 0.6, 0.2, 0.1];
        let fit = fit_rate(&h, &e).unwrap();
        let x: Vec<f64> = h.iter().map(|v| v.ln()).collect();
        let y: Vec<f64> = e.iter().map(|v| v.ln()).collect();
        let mx = x.iter().sum::<f64>() / 4.0;
        let my = y.iter().sum::<f64>() / 4.0;
        let sxx: f64 = x.iter().map(|v| (v - mx).powi(2)).sum();
        let slope: f64 = x
            .iter()
            .zip(&y)
            .map(|(a, b)| (a - mx) * (b - my))
            .sum::<f64>()
            / sxx;
        let rss: f64 = x
            .iter()
            .zip(&y)
            .map(|(a, b)| (b - my - slope * (a - mx)).powi(2))
            .sum();
        let half = 4.302652729911275 * (rss / 2.0 / sxx).sqrt();
        assert_relative_eq!(fit.rate, slope, epsilon = 1e-12);
        assert_relative_eq!(fit.ci_high.unwrap() - fit.rate, half, epsilon = 1e-9);
    }

    #[test]
    fn zero_errors_are_skipped_and_two_levels_have_no_interval() {
        let fit = fit_rate(&[0.1, 0.05, 0.025], &[0.0, 0.2, 0.1]).unwrap();
        assert_eq!(fit.levels, 2);
        assert!(fit.ci_low.is_none());
        assert!(fit_rate(&[0.1], &[0.3]).is_none());
        assert_eq!(observed_orders(&[0.1, 0.05], &[0.0, 1.0]), vec![None, None]);
    }
}
