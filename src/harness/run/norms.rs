//! Error norms: in space by Gauss quadrature on the pieces between the exact solution's kinks,
//! in time by accumulating a discrete series (`L∞` as the maximum, `L²` by the trapezoidal
//! rule on the sample times).

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::engine::error::ParameterError;
use crate::engine::exact::{ExactSolution, Pointwise};
use crate::engine::fem::Bar1d;

/// The independent partial sums of [`SpaceErrorIntegrator::errors`] over the elements.
const LANES: usize = 4;

/// The seven norms of the paper's Tables 1–2.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Norm {
    /// `‖u_h − u‖_{L∞(0,T;H)}`, H = L²(0, L).
    #[serde(rename = "u_Linf_H")]
    DisplacementLinfH,
    /// `‖u_h − u‖_{L²(0,T;H)}`.
    #[serde(rename = "u_L2_H")]
    DisplacementL2H,
    /// `‖u_h − u‖_{L∞(0,T;V)}`, V = H¹(0, L) with the full H¹ norm.
    #[serde(rename = "u_Linf_V")]
    DisplacementLinfV,
    /// `‖u_h − u‖_{L²(0,T;V)}`.
    #[serde(rename = "u_L2_V")]
    DisplacementL2V,
    /// `‖λ_h − λ‖_{L²(0,T)}`.
    #[serde(rename = "lambda_L2")]
    MultiplierL2,
    /// `‖E_h − E‖_{L∞(0,T)}`.
    #[serde(rename = "energy_Linf")]
    EnergyLinf,
    /// `‖E_h − E‖_{L²(0,T)}`.
    #[serde(rename = "energy_L2")]
    EnergyL2,
}

impl Norm {
    /// All norms, in the column order of Tables 1–2.
    pub const ALL: [Norm; 7] = [
        Norm::DisplacementLinfH,
        Norm::DisplacementL2H,
        Norm::DisplacementLinfV,
        Norm::DisplacementL2V,
        Norm::MultiplierL2,
        Norm::EnergyLinf,
        Norm::EnergyL2,
    ];

    /// The stable machine-readable key (`u_Linf_H`, …; the keys of `paper-tables.json`).
    pub fn key(self) -> &'static str {
        match self {
            Norm::DisplacementLinfH => "u_Linf_H",
            Norm::DisplacementL2H => "u_L2_H",
            Norm::DisplacementLinfV => "u_Linf_V",
            Norm::DisplacementL2V => "u_L2_V",
            Norm::MultiplierL2 => "lambda_L2",
            Norm::EnergyLinf => "energy_Linf",
            Norm::EnergyL2 => "energy_L2",
        }
    }

    /// The mathematical label.
    pub fn label(self) -> &'static str {
        match self {
            Norm::DisplacementLinfH => "‖u_h − u‖ L∞(0,T;H)",
            Norm::DisplacementL2H => "‖u_h − u‖ L²(0,T;H)",
            Norm::DisplacementLinfV => "‖u_h − u‖ L∞(0,T;V)",
            Norm::DisplacementL2V => "‖u_h − u‖ L²(0,T;V)",
            Norm::MultiplierL2 => "‖λ_h − λ‖ L²(0,T)",
            Norm::EnergyLinf => "‖E_h − E‖ L∞(0,T)",
            Norm::EnergyL2 => "‖E_h − E‖ L²(0,T)",
        }
    }
}

impl fmt::Display for Norm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.key())
    }
}

impl FromStr for Norm {
    type Err = ParameterError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL.into_iter().find(|n| n.key() == s).ok_or_else(|| {
            ParameterError::new(
                "norm",
                s,
                "one of: u_Linf_H, u_L2_H, u_Linf_V, u_L2_V, lambda_L2, energy_Linf, energy_L2",
            )
        })
    }
}

/// Gauss–Legendre nodes and weights on `[−1, 1]` for 1 to 5 points.
pub fn gauss_legendre(points: usize) -> (&'static [f64], &'static [f64]) {
    const N1: [f64; 1] = [0.0];
    const W1: [f64; 1] = [2.0];
    const N2: [f64; 2] = [-0.577_350_269_189_625_8, 0.577_350_269_189_625_8];
    const W2: [f64; 2] = [1.0, 1.0];
    const N3: [f64; 3] = [-0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4];
    const W3: [f64; 3] = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
    const N4: [f64; 4] = [
        -0.861_136_311_594_052_6,
        -0.339_981_043_584_856_3,
        0.339_981_043_584_856_3,
        0.861_136_311_594_052_6,
    ];
    const W4: [f64; 4] = [
        0.347_854_845_137_453_8,
        0.652_145_154_862_546_1,
        0.652_145_154_862_546_1,
        0.347_854_845_137_453_8,
    ];
    const N5: [f64; 5] = [
        -0.906_179_845_938_664,
        -0.538_469_310_105_683,
        0.0,
        0.538_469_310_105_683,
        0.906_179_845_938_664,
    ];
    const W5: [f64; 5] = [
        0.236_926_885_056_189_1,
        0.478_628_670_499_366_5,
        0.568_888_888_888_888_9,
        0.478_628_670_499_366_5,
        0.236_926_885_056_189_1,
    ];
    match points {
        1 => (&N1, &W1),
        2 => (&N2, &W2),
        3 => (&N3, &W3),
        4 => (&N4, &W4),
        _ => (&N5, &W5),
    }
}

/// `‖u_h − u(·, t)‖` in L² and in H¹ (full norm) for a P1 function on the bar.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpaceErrors {
    /// The L²(0, L) norm of the error.
    pub l2: f64,
    /// The H¹(0, L) norm of the error, `(‖e‖² + ‖e_x‖²)^½`.
    pub h1: f64,
}

/// Integrates the error of a P1 field against an exact solution, splitting every element at
/// the exact solution's kinks so that each piece is smooth (exact for piecewise affine
/// solutions with two Gauss points).
///
/// The Gauss points of the unsplit elements do not move from step to step: they are laid out
/// once per mesh and the exact solution is evaluated on all of them in one call per step; only
/// the few elements that contain a kink at that time are split and integrated piece by piece.
#[derive(Debug, Default)]
pub struct SpaceErrorIntegrator {
    breakpoints: Vec<f64>,
    /// `(nx, Gauss points per element)` of the current layout.
    layout: Option<(usize, usize)>,
    /// The Gauss points of every element, element by element.
    points: Vec<f64>,
    /// Weight × half-length of each point of an element (the same for every element).
    weights: Vec<f64>,
    /// Value of the left hat function at each point of an element.
    left_shape: Vec<f64>,
    exact_values: Vec<Pointwise>,
    kinked: Vec<usize>,
    /// The P1 field's nodal values of the current step (the clamped node included).
    nodal: Vec<f64>,
    /// How many times [`Self::errors`] has run (lets tests prove a run computed no norm).
    evaluations: usize,
}

impl SpaceErrorIntegrator {
    /// A new integrator.
    pub fn new() -> Self {
        Self::default()
    }

    /// The number of space-norm evaluations so far.
    pub fn evaluations(&self) -> usize {
        self.evaluations
    }

    fn lay_out(&mut self, bar: &Bar1d, gauss: usize) {
        if self.layout == Some((bar.nx(), gauss)) {
            return;
        }
        let (nodes, weights) = gauss_legendre(gauss);
        let h = bar.h();
        self.points.clear();
        for e in 0..bar.nx() {
            let (xa, xb) = (bar.node(e), bar.node(e + 1));
            let (mid, half) = (0.5 * (xa + xb), 0.5 * (xb - xa));
            self.points.extend(nodes.iter().map(|xi| mid + half * xi));
        }
        self.weights = weights.iter().map(|w| w * 0.5 * h).collect();
        self.left_shape = nodes.iter().map(|xi| 0.5 * (1.0 - xi)).collect();
        let zero = Pointwise {
            u: 0.0,
            ux: 0.0,
            ut: 0.0,
        };
        self.exact_values.resize(self.points.len(), zero);
        self.layout = Some((bar.nx(), gauss));
    }

    /// The L² and H¹ errors of the dof vector `u` at time `t`.
    pub fn errors(
        &mut self,
        bar: &Bar1d,
        u: &[f64],
        exact: &dyn ExactSolution,
        t: f64,
    ) -> SpaceErrors {
        self.evaluations += 1;
        let gauss = exact.gauss_points();
        self.lay_out(bar, gauss);
        self.breakpoints.clear();
        exact.breakpoints(t, &mut self.breakpoints);
        self.kinked.clear();
        let h = bar.h();
        for &p in &self.breakpoints {
            let e = ((p / h) as usize).min(bar.nx() - 1);
            let inside = p > bar.node(e) && p < bar.node(e + 1);
            if inside {
                self.kinked.push(e);
            }
        }
        self.kinked.sort_unstable();
        self.kinked.dedup();
        exact.eval_many(t, &self.points, &mut self.exact_values);
        bar.nodal_values(u, &mut self.nodal);
        let (mut l2, mut semi) = (0.0, 0.0);
        let mut first = 0;
        for &kinked in self.kinked.iter().chain([&bar.nx()]) {
            let (a, b) = self.smooth_elements(
                &self.nodal[first..=kinked],
                &self.exact_values[first * gauss..kinked * gauss],
                h,
            );
            l2 += a;
            semi += b;
            if kinked < bar.nx() {
                let ends = (self.nodal[kinked], self.nodal[kinked + 1]);
                let (a, b) = self.split_element(bar, kinked, ends, exact, t);
                l2 += a;
                semi += b;
            }
            first = kinked + 1;
        }
        SpaceErrors {
            l2: l2.sqrt(),
            h1: (l2 + semi).sqrt(),
        }
    }

    /// `(∫ e², ∫ e_x²)` over consecutive elements with no kink inside: element `k` has the
    /// nodal values `nodal[k]`, `nodal[k + 1]` and the exact values at its Gauss points
    /// `exact[k·g..(k + 1)·g]` ([`Self::lay_out`]). Element `k` adds to partial sum `k mod LANES`,
    /// so that the sums do not wait on one another.
    fn smooth_elements(&self, nodal: &[f64], exact: &[Pointwise], h: f64) -> (f64, f64) {
        let gauss = self.weights.len();
        let rule = || self.weights.iter().zip(&self.left_shape);
        let element = |(ua, ub): (f64, f64), values: &[Pointwise]| {
            let slope = (ub - ua) / h;
            values
                .iter()
                .zip(rule())
                .fold((0.0, 0.0), |(l2, semi), (ex, (&w, &phi))| {
                    let err = ub + (ua - ub) * phi - ex.u;
                    let err_x = slope - ex.ux;
                    (l2 + w * err * err, semi + w * err_x * err_x)
                })
        };
        let mut sums = [(0.0, 0.0); LANES];
        let blocks = nodal.windows(LANES + 1).step_by(LANES);
        let elements = nodal.len().saturating_sub(1);
        let full = elements - elements % LANES;
        for (ends, values) in blocks.zip(exact[..full * gauss].chunks_exact(LANES * gauss)) {
            for (k, sum) in sums.iter_mut().enumerate() {
                let (a, b) = element((ends[k], ends[k + 1]), &values[k * gauss..(k + 1) * gauss]);
                sum.0 += a;
                sum.1 += b;
            }
        }
        for e in full..elements {
            let (a, b) = element((nodal[e], nodal[e + 1]), &exact[e * gauss..(e + 1) * gauss]);
            sums[0].0 += a;
            sums[0].1 += b;
        }
        sums.iter()
            .fold((0.0, 0.0), |(l2, semi), (a, b)| (l2 + a, semi + b))
    }

    /// `(∫ e², ∫ e_x²)` over element `e`, split at the breakpoints inside it.
    fn split_element(
        &self,
        bar: &Bar1d,
        e: usize,
        (ua, ub): (f64, f64),
        exact: &dyn ExactSolution,
        t: f64,
    ) -> (f64, f64) {
        let (nodes, weights) = gauss_legendre(exact.gauss_points());
        let (xa, xb) = (bar.node(e), bar.node(e + 1));
        let slope = (ub - ua) / (xb - xa);
        let mut cuts: Vec<f64> = vec![xa];
        cuts.extend(
            self.breakpoints
                .iter()
                .copied()
                .filter(|&p| p > xa && p < xb),
        );
        cuts.push(xb);
        let (mut l2, mut semi) = (0.0, 0.0);
        for piece in cuts.windows(2) {
            let (mid, half) = (0.5 * (piece[0] + piece[1]), 0.5 * (piece[1] - piece[0]));
            for (&xi, &w) in nodes.iter().zip(weights) {
                let x = mid + half * xi;
                let ex = exact.eval(x, t);
                let err = ua + slope * (x - xa) - ex.u;
                let err_x = slope - ex.ux;
                l2 += w * half * err * err;
                semi += w * half * err_x * err_x;
            }
        }
        (l2, semi)
    }
}

/// `L∞(0, T)` and `L²(0, T)` norms of a sampled time series.
#[derive(Debug, Clone, Default)]
pub struct TimeSeriesNorm {
    max: f64,
    integral_of_square: f64,
    last: Option<(f64, f64)>,
}

impl TimeSeriesNorm {
    /// Adds the sample `value` at `time`; a sample at a time not after the last one is ignored
    /// (schemes may report the same time twice while starting up).
    pub fn push(&mut self, time: f64, value: f64) {
        let value = value.abs();
        match self.last {
            Some((t0, _)) if time <= t0 => return,
            Some((t0, v0)) => {
                self.integral_of_square += 0.5 * (time - t0) * (v0 * v0 + value * value)
            }
            None => {}
        }
        self.max = self.max.max(value);
        self.last = Some((time, value));
    }

    /// The maximum of `|value|`.
    pub fn linf(&self) -> f64 {
        self.max
    }

    /// `(∫ value² dt)^½` by the trapezoidal rule.
    pub fn l2(&self) -> f64 {
        self.integral_of_square.sqrt()
    }
}
