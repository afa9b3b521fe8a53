//! GetFEM's demo norms: what `demo_dynamic_contact_1D.py` stores at every time point and the
//! seven relative error norms it prints at the end, computed the demo's way from the states of
//! any harness run on the Signorini–Dirichlet bar ([`DemoNorms`]), or from the stored series
//! alone ([`DemoSeries::norms`]).
//!
//! The demo's conventions:
//! - every time point `t_n = n Δt`, `t_0 = 0` included, is a sample;
//! - the exact solution enters through its nodal P1 interpolant `I_h u`, evaluated with the
//!   demo's closure of the regions ([`demo_exact`]), at every node, the clamped one included;
//! - the space norms are exact integrals of P1 fields: on an element of length `h_e` with end
//!   values `a`, `b`, `∫ f² = h_e (a² + ab + b²)/3` (the P1 element mass matrix) and
//!   `∫ f_x² = (b − a)²/h_e`; the H¹ norm is the full one, `(∫ f² + ∫ f_x²)^½`;
//! - the time norms are relative: `L∞` is the largest sample over the largest sample of the
//!   exact quantity, `L²` is a rectangle sum `(Δt Σ_n f_n²)^½` over all samples, divided by the
//!   exact quantity's.

use super::exact::demo_exact;
use crate::engine::error::ParameterError;
use crate::engine::fem::{Bar1d, EndCondition};
use crate::engine::schemes::Integration;
use crate::harness::files::error::Error;
use crate::harness::run::Observer;

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

/// `(∫ f², ∫ f_x²)` of the P1 function with the nodal values `f` on the nodes `x`.
fn p1_squares(x: &[f64], f: &[f64]) -> (f64, f64) {
    let (mut l2, mut semi) = (0.0, 0.0);
    for (xs, fs) in x.windows(2).zip(f.windows(2)) {
        let (h, a, b) = (xs[1] - xs[0], fs[0], fs[1]);
        l2 += h * (a * a + a * b + b * b) / 3.0;
        semi += (b - a) * (b - a) / h;
    }
    (l2, semi)
}

/// The observer that records a run on the demo's bar as the demo does ([`DemoSeries`]), for
/// its seven norms ([`DemoNorms::norms`]).
///
/// At every state `t_n` ([`crate::engine::schemes::SchemeState::time`]) it takes the P1 fields of
/// [`crate::engine::schemes::SchemeState::displacement`] and [`crate::engine::schemes::SchemeState::velocity`] at all `NX + 1` nodes (`0`
/// at the clamped node, which the bar eliminates and the demo keeps), the interpolants
/// `I_h u(t_n)`, `I_h u_t(t_n)` of [`demo_exact`], and the first contact multiplier
/// [`crate::engine::schemes::SchemeState::multiplier`] as the stress `s_h(t_n)`, compared with `u_x(0, t_n)`: the
/// harness's `λ ≤ 0` has the demo's sign (`λ = u_x(0, t)`, `store_s0 = −F_c[0]`). Every quantity
/// is paired with the state's time `t_n`, as the demo pairs its latest stress and its velocity
/// with `t_n` whatever time the scheme gives them (the harness's Paoli–Schatzman carries its
/// velocity at `t_{n−½}`).
#[derive(Debug, Clone)]
pub struct DemoNorms {
    /// The node positions `x_i`, `i = 0..=NX`.
    nodes: Vec<f64>,
    /// The dof of each node (`None` for the clamped node, whose value is 0).
    dofs: Vec<Option<usize>>,
    /// The dof of the contact node `x = 0`.
    contact: usize,
    series: DemoSeries,
    /// Scratch: the nodal errors and interpolants of the current state.
    du: Vec<f64>,
    dv: Vec<f64>,
    iu: Vec<f64>,
    iv: Vec<f64>,
}

impl DemoNorms {
    /// The observer of `bar`, which must be the demo's: `L = 1`, `ρ = c = 1`, clamped at
    /// `x = 1` (a [`ParameterError`] names what differs).
    pub fn new(bar: &Bar1d) -> Result<Self, ParameterError> {
        let demo_value = |name: &'static str, value: f64| {
            if value == 1.0 {
                Ok(())
            } else {
                Err(ParameterError::new(name, value, "1 (GetFEM's demo bar)"))
            }
        };
        demo_value("length", bar.length())?;
        demo_value("density", bar.density())?;
        demo_value("young_modulus", bar.young_modulus())?;
        if bar.far_end() != EndCondition::Clamped {
            return Err(ParameterError::new(
                "far_end",
                "free",
                "clamped (GetFEM's demo bar)",
            ));
        }
        let nodes: Vec<f64> = (0..=bar.nx()).map(|i| bar.node(i)).collect();
        let n = nodes.len();
        Ok(Self {
            nodes,
            dofs: (0..n).map(|i| bar.dof_of_node(i)).collect(),
            contact: bar.contact_dof(),
            series: DemoSeries::default(),
            du: vec![0.0; n],
            dv: vec![0.0; n],
            iu: vec![0.0; n],
            iv: vec![0.0; n],
        })
    }

    /// The series recorded so far, one value per observed state.
    pub fn series(&self) -> &DemoSeries {
        &self.series
    }

    /// The demo's seven norms of the states observed so far ([`DemoSeries::norms`]).
    pub fn norms(&self) -> DemoErrorNorms {
        self.series.norms()
    }
}

impl Observer for DemoNorms {
    fn observe(&mut self, state: &Integration<'_>) -> Result<(), Error> {
        let t = state.time();
        let (u, v) = (state.displacement(), state.velocity());
        for (i, (&x, dof)) in self.nodes.iter().zip(&self.dofs).enumerate() {
            let exact = demo_exact(x, t);
            let (ui, vi) = dof.map_or((0.0, 0.0), |d| (u[d], v[d]));
            self.iu[i] = exact.u;
            self.iv[i] = exact.ut;
            self.du[i] = ui - exact.u;
            self.dv[i] = vi - exact.ut;
        }
        let (eu, eu_x) = p1_squares(&self.nodes, &self.du);
        let (iu, iu_x) = p1_squares(&self.nodes, &self.iu);
        let (ev, _) = p1_squares(&self.nodes, &self.dv);
        let (iv, _) = p1_squares(&self.nodes, &self.iv);
        let contact = demo_exact(0.0, t);
        let s = &mut self.series;
        s.time.push(t);
        s.u0.push(u[self.contact]);
        s.u0_ex.push(contact.u);
        s.v0.push(v[self.contact]);
        s.v0_ex.push(contact.ut);
        s.s0.push(state.multiplier().value.first().copied().unwrap_or(0.0));
        s.s0_ex.push(contact.ux);
        s.u_l2.push(eu.sqrt());
        s.u_l2_ex.push(iu.sqrt());
        s.u_h1.push((eu + eu_x).sqrt());
        s.u_h1_ex.push((iu + iu_x).sqrt());
        s.v_l2.push(ev.sqrt());
        s.v_l2_ex.push(iv.sqrt());
        Ok(())
    }
}
