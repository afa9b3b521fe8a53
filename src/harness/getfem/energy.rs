//! GetFEM's demo energy: what `demo_dynamic_contact_1D.py` stores as the energy of a run,
//! evaluated on the states of any harness run of one of its configurations ([`DemoEnergy`]).

use super::demo_run::{DemoConfig, DemoVersion};
use crate::engine::fem::{Bar1d, SymmetricMatrix};
use crate::engine::linalg::SpdSolver;
use crate::engine::model::Model;
use crate::engine::problem::Discretisation;
use crate::engine::schemes::Integration;
use crate::harness::files::error::Error;

/// The demo's energy evaluated on the harness's state: `½ VᵀMV + ½ UᵀKU` with the scheme's
/// mass and the elastic `K`, plus the penalty's `(γ₀/2h) [u₀]_−²`, or Nitsche's
/// `(θ/2)(h/γ₀)(s² − u_x(0)²)` from the first step on (the demo's `ux` is 0 before it).
/// The demo carries `M·V`: for Paoli–Schatzman, which does not, it is rebuilt from its one-step
/// form, `M V^n = M (U^n − U^{n−1})/Δt − Δt (β K U^{n−1} + (½ − β) K U^n)`.
pub struct DemoEnergy<'a> {
    config: &'a DemoConfig,
    model: &'a Model,
    elastic: SymmetricMatrix,
    with_mass: Vec<usize>,
    mass: SpdSolver,
    previous: Option<Vec<f64>>,
}

impl<'a> DemoEnergy<'a> {
    /// The energy of `config`'s runs on the discretised bar `d` (its model and mesh).
    pub fn new(config: &'a DemoConfig, d: &'a Discretisation<Bar1d>) -> Result<Self, Error> {
        let model = &d.model;
        let with_mass = model.dofs_with_mass();
        let m_rr = model.mass().principal_submatrix(&with_mass);
        Ok(Self {
            config,
            model,
            elastic: d.mesh.stiffness(),
            mass: SpdSolver::factor(&m_rr, "mass (dofs with inertia)").map_err(Error::from)?,
            with_mass,
            previous: None,
        })
    }

    /// The demo's energy of `state`, whose contact stress as the demo stores it is `stress`;
    /// called at every step in order (Paoli–Schatzman's `M·V` needs the previous displacement).
    pub fn energy(&mut self, state: &Integration<'_>, stress: f64) -> f64 {
        let (u, n, dt) = (state.displacement(), self.model.n_dofs(), state.dt());
        let mut mv = vec![0.0; n];
        match (&self.previous, self.config.version) {
            (Some(up), DemoVersion::PaoliSchatzman) => {
                let quotient: Vec<f64> = u.iter().zip(up).map(|(a, b)| (a - b) / dt).collect();
                self.model.mass().mul_into(&quotient, &mut mv);
                let (mut k_prev, mut k_now) = (vec![0.0; n], vec![0.0; n]);
                self.elastic.mul_into(up, &mut k_prev);
                self.elastic.mul_into(u, &mut k_now);
                let beta = self.config.beta;
                for ((m, kp), kn) in mv.iter_mut().zip(&k_prev).zip(&k_now) {
                    *m -= dt * (beta * kp + (0.5 - beta) * kn);
                }
            }
            _ => self.model.mass().mul_into(state.velocity(), &mut mv),
        }
        self.previous = Some(u.to_vec());
        let mv_r: Vec<f64> = self.with_mass.iter().map(|&i| mv[i]).collect();
        let mut v_r = mv_r.clone();
        self.mass.solve_in_place(&mut v_r);
        let kinetic = 0.5 * mv_r.iter().zip(&v_r).map(|(a, b)| a * b).sum::<f64>();
        let mut energy = kinetic + 0.5 * self.elastic.quadratic_form(u);
        let h = 1.0 / self.config.nx as f64;
        match self.config.version {
            DemoVersion::Penalty => {
                energy += 0.5 * self.config.gamma0_p / h * u[0].min(0.0).powi(2);
            }
            DemoVersion::Nitsche if state.step_index() > 0 => {
                let ux = (u[1] - u[0]) / h;
                energy += 0.5
                    * self.config.theta_n
                    * (h / self.config.gamma0_n)
                    * (stress * stress - ux * ux);
            }
            _ => {}
        }
        energy
    }
}
