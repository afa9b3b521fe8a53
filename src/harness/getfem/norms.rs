//! GetFEM's demo norms: what `demo_dynamic_contact_1D.py` stores at every time point and the
//! seven relative error norms it prints at the end, computed the demo's way from the stored
//! series ([`DemoSeries::norms`]).
//!
//! The demo's time norms are relative: `L∞` is the largest sample over the largest sample of the
//! exact quantity, `L²` is a rectangle sum `(Δt Σ_n f_n²)^½` over all samples `t_n = n Δt`,
//! `t_0 = 0` included, divided by the exact quantity's.

/// The seven relative error norms the demo prints, under its names. A run that blew up has
/// non-finite ones: its printed norms are read as the file writes them (`Infinity`, `NaN`);
/// recomputed from its series they are `NaN` (the files store the series' `inf` and `NaN`
/// alike as `null`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DemoErrorNorms {
    /// `LinfL2u = max_n ‖U_h − I_h u‖_{L²} / max_n ‖I_h u‖_{L²}`.
    pub linf_l2_u: f64,
    /// `LinfH1u = max_n ‖U_h − I_h u‖_{H¹} / max_n ‖I_h u‖_{H¹}`.
    pub linf_h1_u: f64,
    /// `LinfL2v = max_n ‖V_h − I_h v‖_{L²} / max_n ‖I_h v‖_{L²}`.
    pub linf_l2_v: f64,
    /// `L2L2u = (Σ_n ‖U_h − I_h u‖²_{L²})^½ / (Σ_n ‖I_h u‖²_{L²})^½`.
    pub l2_l2_u: f64,
    /// `L2H1u = (Σ_n ‖U_h − I_h u‖²_{H¹})^½ / (Σ_n ‖I_h u‖²_{H¹})^½`.
    pub l2_h1_u: f64,
    /// `L2L2v = (Σ_n ‖V_h − I_h v‖²_{L²})^½ / (Σ_n ‖I_h v‖²_{L²})^½`.
    pub l2_l2_v: f64,
    /// `L2sn = (Σ_n (s_h(t_n) − u_x(0, t_n))²)^½ / (Σ_n u_x(0, t_n)²)^½`, the contact stress.
    pub l2_sn: f64,
}

impl DemoErrorNorms {
    /// The demo's names of the seven norms, in the order it prints them.
    pub const NAMES: [&'static str; 7] = [
        "LinfL2u", "LinfH1u", "LinfL2v", "L2L2u", "L2H1u", "L2L2v", "L2sn",
    ];

    /// The seven values with the demo's names, in the order of [`Self::NAMES`].
    pub fn named(&self) -> [(&'static str, f64); 7] {
        let values = [
            self.linf_l2_u,
            self.linf_h1_u,
            self.linf_l2_v,
            self.l2_l2_u,
            self.l2_h1_u,
            self.l2_l2_v,
            self.l2_sn,
        ];
        let mut named = [("", 0.0); 7];
        for (slot, (name, value)) in named.iter_mut().zip(Self::NAMES.into_iter().zip(values)) {
            *slot = (name, value);
        }
        named
    }
}

/// What the demo stores at every time point (its `TT` and `store_*` arrays, the energy
/// excepted), the exact counterparts (`_ex`) from the nodal interpolant of the exact solution.
/// All series have one value per sample; a non-finite value is `NaN`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DemoSeries {
    /// `TT`: the sample times `t_n`.
    pub time: Vec<f64>,
    /// `store_u0`: `U_h(0, t_n)`.
    pub u0: Vec<f64>,
    /// `store_u0_ex`: `u(0, t_n)`.
    pub u0_ex: Vec<f64>,
    /// `store_v0`: `V_h(0, t_n)`.
    pub v0: Vec<f64>,
    /// `store_v0_ex`: `u_t(0, t_n)`.
    pub v0_ex: Vec<f64>,
    /// `store_s0`: the contact stress `s_h(t_n)` (the multiplier `λ_h ≤ 0`; `0` at `t_0` in
    /// the demo).
    pub s0: Vec<f64>,
    /// `store_s0_ex`: `u_x(0, t_n)`.
    pub s0_ex: Vec<f64>,
    /// `store_UL2`: `‖U_h − I_h u‖_{L²}`.
    pub u_l2: Vec<f64>,
    /// `store_UL2_ex`: `‖I_h u‖_{L²}`.
    pub u_l2_ex: Vec<f64>,
    /// `store_UH1`: `‖U_h − I_h u‖_{H¹}`.
    pub u_h1: Vec<f64>,
    /// `store_UH1_ex`: `‖I_h u‖_{H¹}`.
    pub u_h1_ex: Vec<f64>,
    /// `store_VL2`: `‖V_h − I_h v‖_{L²}`.
    pub v_l2: Vec<f64>,
    /// `store_VL2_ex`: `‖I_h v‖_{L²}`.
    pub v_l2_ex: Vec<f64>,
}

impl DemoSeries {
    /// The demo's seven norms of these series ([`DemoErrorNorms`]): the `L∞` ones as ratios of
    /// maxima, the `L²` ones as ratios of rectangle sums `(Δt Σ_n f_n²)^½`, in which the
    /// uniform `Δt` cancels. As NumPy's `amax`, a maximum over a series holding `NaN` is `NaN`;
    /// empty series give `NaN`.
    pub fn norms(&self) -> DemoErrorNorms {
        let stress_error: Vec<f64> = self
            .s0
            .iter()
            .zip(&self.s0_ex)
            .map(|(a, b)| a - b)
            .collect();
        DemoErrorNorms {
            linf_l2_u: max(&self.u_l2) / max(&self.u_l2_ex),
            linf_h1_u: max(&self.u_h1) / max(&self.u_h1_ex),
            linf_l2_v: max(&self.v_l2) / max(&self.v_l2_ex),
            l2_l2_u: root_sum_of_squares(&self.u_l2) / root_sum_of_squares(&self.u_l2_ex),
            l2_h1_u: root_sum_of_squares(&self.u_h1) / root_sum_of_squares(&self.u_h1_ex),
            l2_l2_v: root_sum_of_squares(&self.v_l2) / root_sum_of_squares(&self.v_l2_ex),
            l2_sn: root_sum_of_squares(&stress_error) / root_sum_of_squares(&self.s0_ex),
        }
    }

    /// The number of samples.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    /// Whether there is no sample.
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }
}

/// NumPy's `amax`: `NaN` if any value is `NaN` (or if there is none).
fn max(values: &[f64]) -> f64 {
    values
        .iter()
        .copied()
        .fold(None, |m: Option<f64>, v| match m {
            Some(m) if m.is_nan() || v.is_nan() => Some(f64::NAN),
            Some(m) => Some(m.max(v)),
            None => Some(v),
        })
        .unwrap_or(f64::NAN)
}

/// `(Σ f²)^½`.
fn root_sum_of_squares(values: &[f64]) -> f64 {
    values.iter().map(|v| v * v).sum::<f64>().sqrt()
}
