//! The physics every run is checked for, measured by the one time loop ([`super::drive`]) on
//! every state `t_n` of every run, bar or box: how far the body went into the obstacle, how
//! far its energy rose above the start, and whether a contact force pulled.
//!
//! * **Penetration**: the largest constraint violation `p = max_n max_i (−(B U^n + g)_i)⁺`, in
//!   the scene's length unit, and relative to the contact face's *displacement scale*
//!   `D = max_n max_i (B U^n + g)_i`, the largest distance of a contact node from the obstacle
//!   over the run (`t = 0` included): how far the face travels towards the obstacle. `D` is 0.5
//!   on the 1D benchmarks (the contact node starts 0.5 above the obstacle) and 0.2 on the 2D/3D
//!   bars (their gap). `p / D` is not bounded by 1: Moreau–Jean with the redistributed mass on
//!   the gravity benchmark at NX = 160 sinks 0.733 below the obstacle, 147 % of `D = 0.5`. When
//!   the face never left the obstacle (`D = 0`) there is no relative figure. The judged figure
//!   is `p / max(D, D_min)` with [`FACE_SCALE_FLOOR`] as `D_min`: where the face barely leaves
//!   the obstacle (a grazing contact: `D` and `p` both of round-off size) the ratio of two
//!   round-off numbers decides nothing.
//! * **Energy**: the discrete energy `E^n = E_h = ½VᵀMV + ½UᵀSU − FᵀU` (eq. 31) plus a
//!   penalty's or Nitsche's contact energy, half-step for Paoli–Schatzman, its start `E_0` and
//!   its largest value `E_max`, with the time `t_n` of the state it was taken at. Where the
//!   loop checks the energy balance the energy is the balance monitor's `E^n + ΔE` (no product
//!   computed for it; for explicit Newmark that is `E_h(U^n, V^n)`, not its staggered energy);
//!   elsewhere the scheme's ([`crate::engine::schemes::TimeIntegrator::energy`]). With a load `F` the term `−FᵀU` makes `E^n − E_0` the change of kinetic and
//!   elastic energy minus the work `W^n = Fᵀ(U^n − U^0)` of the external forces: the gain is
//!   judged against energy + work. The largest `|W^n|` is recorded beside it.
//! * **Contact-force sign**: the multipliers are forces `λ_i ≤ 0` (compression, 1D paper
//!   eq. 30); the largest `λ_i > 0` of any step (a pulling force) and the largest `|λ_i|`.
//!
//! A run **penetrates** when `p / max(D, D_min)` exceeds [`PENETRATION_TOLERANCE`],
//! **gains energy** when `(E_max − E_0) / |E_0|` (`E_max − E_0` when `E_0 = 0`) exceeds
//! [`ENERGY_GAIN_TOLERANCE`], and has a **wrong-sign force** when its largest positive
//! multiplier exceeds [`FORCE_SIGN_TOLERANCE`] times its largest `|λ|`. The tolerances are
//! fixed here, before any run was judged by them (see each constant).

use serde::{Deserialize, Serialize};

use crate::engine::contact::{ContactSet, ContactTreatment};
use crate::engine::model::Model;
use crate::engine::schemes::Integration;

/// The largest penetration a run may have relative to its face's displacement scale: 1 %.
/// The multiplier treatments keep `B U + g ≥ 0` at the level of their complementarity solve
/// (10⁻⁷ and below); a scheme that enforces contact on velocities (Moreau–Jean) or on a mean of
/// levels (Paoli–Schatzman) lets a node sink by about `Δt |v|` per impact; a penalty by
/// `|λ| / γ`. On the 1D benchmark (Δx/Δt = 10, T = 3 and 9) that is below 1 % of the travel
/// for every scheme × mass of the tables but Moreau–Jean with the redistributed mass, at every
/// level but Paoli–Schatzman e = 1's at NX = 10 (1.3 %); on the 2D bar (Δx/Δt = 2) Moreau–Jean's is
/// 2.5 % at level 10 and 1.2 % at level 20, and those runs are flagged: their nodes do go that
/// deep. A node that stays inside the obstacle goes far beyond it (97 % for Moreau–Jean with a
/// massless contact node).
pub const PENETRATION_TOLERANCE: f64 = 1e-2;

/// The smallest displacement scale a penetration is judged against, in the scenes' length unit
/// (their bodies are of unit length): 10⁻³. A penetration is then flagged only above 10⁻⁵, a
/// hundred times the multiplier treatments' complementarity round-off (10⁻⁷), whatever `D`.
pub const FACE_SCALE_FLOOR: f64 = 1e-3;

/// The largest rise of the energy above its start a run may have, relative to `|E_0|`: 5 %,
/// the stability suite's energy-growth threshold. The exact energy (with the load's potential)
/// is conserved; every scheme's balance (eqs. 33, 35, 37, (GA-E), (MJ-E), (CSN-E)) adds to it
/// only numerical dissipation, which never raises it, and the contact work of its step, which
/// the discrete constraint makes small but not signed: the allowance is that contact work.
pub const ENERGY_GAIN_TOLERANCE: f64 = 5e-2;

/// The largest positive (pulling) contact force a run may have, relative to its largest
/// `|λ|`: 10⁻⁹, the complementarity solves' round-off (the balance tolerance's order).
pub const FORCE_SIGN_TOLERANCE: f64 = 1e-9;

/// What the time loop measured of a run's physics (the module's quantities); the fields of
/// `physics` in every `run.json` and study JSON (docs/src/outputs.md).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Physics {
    /// `p = max_n max_i (−(B U^n + g)_i)⁺`, scene length units (0 without an obstacle).
    pub penetration: f64,
    /// The time `t_n` of the largest penetration (0 when there is none).
    pub penetration_time: f64,
    /// The contact face's displacement scale `D = max_n max_i (B U^n + g)_i`.
    pub face_displacement_scale: f64,
    /// `p / D`; `None` when `D = 0`.
    pub relative_penetration: Option<f64>,
    /// `E_0`, the scheme's energy at `t = 0`.
    pub energy_start: f64,
    /// `E_max`, the largest energy of any step.
    pub energy_max: f64,
    /// The first time the energy came within round-off (10⁻¹² relative) of `E_max`: where a
    /// run that gains energy and then conserves it reached its plateau.
    pub energy_max_time: f64,
    /// `E_max / E_0`; `None` when `E_0 ≤ 0`.
    pub energy_ratio: Option<f64>,
    /// `max_n |Fᵀ(U^n − U^0)|`, the largest work of the external forces; `None` without a load.
    pub external_work: Option<f64>,
    /// The largest positive multiplier of any step (a pulling force), 0 when none.
    pub wrong_sign_force: f64,
    /// The largest `|λ_i|` of any step.
    pub max_force: f64,
}

impl Physics {
    /// `(E_max − E_0) / |E_0|`, or `E_max − E_0` when `E_0 = 0`.
    pub fn energy_gain(&self) -> f64 {
        let gain = self.energy_max - self.energy_start;
        if self.energy_start == 0.0 {
            gain
        } else {
            gain / self.energy_start.abs()
        }
    }

    /// `p / max(D, D_min)` ([`FACE_SCALE_FLOOR`]): the figure judged against
    /// [`PENETRATION_TOLERANCE`].
    pub fn judged_penetration(&self) -> f64 {
        self.penetration / self.face_displacement_scale.max(FACE_SCALE_FLOOR)
    }

    /// Whether the run went into the obstacle beyond [`PENETRATION_TOLERANCE`].
    pub fn penetrates(&self) -> bool {
        exceeds(self.judged_penetration(), PENETRATION_TOLERANCE)
    }

    /// Whether the energy rose above its start beyond [`ENERGY_GAIN_TOLERANCE`].
    pub fn gains_energy(&self) -> bool {
        exceeds(self.energy_gain(), ENERGY_GAIN_TOLERANCE)
    }

    /// Whether a contact force pulled beyond [`FORCE_SIGN_TOLERANCE`].
    pub fn wrong_sign(&self) -> bool {
        exceeds(self.wrong_sign_force, FORCE_SIGN_TOLERANCE * self.max_force)
    }

    /// Whether any of the three checks failed.
    pub fn flagged(&self) -> bool {
        self.penetrates() || self.gains_energy() || self.wrong_sign()
    }

    /// The failed checks with their figures (`penetrates 4.767e-1 (95.647 % of D = 4.984e-1) at
    /// t = 8.3406; gains energy: E_max/E_0 = 50.8397 (…) at t = 4.3897`); `None` when none
    /// failed.
    pub fn flags(&self) -> Option<String> {
        let mut flags = Vec::new();
        if self.penetrates() {
            flags.push(format!(
                "penetrates {} at t = {:.4}",
                self.penetration_text(),
                self.penetration_time
            ));
        }
        if self.gains_energy() {
            flags.push(format!(
                "gains energy: {} at t = {:.4}",
                self.energy_text(),
                self.energy_max_time
            ));
        }
        if self.wrong_sign() {
            flags.push(format!(
                "pulls: contact force +{:.3e} (largest |λ| {:.3e})",
                self.wrong_sign_force, self.max_force
            ));
        }
        (!flags.is_empty()).then(|| flags.join("; "))
    }

    /// `4.767e-1 (95.647 % of D = 4.984e-1)`; `2.776e-17 (p/D = 4.9e-17, D = 5.639e-1)` below
    /// 10⁻⁴ of `D`; the absolute figure alone when `D = 0`.
    pub fn penetration_text(&self) -> String {
        let d = self.face_displacement_scale;
        match self.relative_penetration {
            Some(r) if r >= 1e-4 => {
                format!(
                    "{:.3e} ({:.3} % of D = {d:.3e})",
                    self.penetration,
                    100.0 * r
                )
            }
            Some(r) => format!("{:.3e} (p/D = {r:.1e}, D = {d:.3e})", self.penetration),
            None => format!("{:.3e} (D = 0)", self.penetration),
        }
    }

    /// `E_max/E_0 = 50.84 (E_0 = 1.246e-1, E_max = 6.335e0)`, with the work of the external
    /// forces when there is a load.
    pub fn energy_text(&self) -> String {
        let ratio = match self.energy_ratio {
            Some(r) => format!("E_max/E_0 = {r:.4}"),
            None => format!("E_max − E_0 = {:.3e}", self.energy_max - self.energy_start),
        };
        let work = self.external_work.map_or(String::new(), |w| {
            format!(", largest work of the load {w:.3e}")
        });
        format!(
            "{ratio} (E_0 = {:.4e}, E_max = {:.4e}{work})",
            self.energy_start, self.energy_max
        )
    }
}

/// A rise of the largest energy by less than this fraction of it is round-off: it does not
/// move the time of the maximum.
const ROUND_OFF: f64 = 1e-12;

/// Whether `value` is above `bound` or NaN (a figure that cannot be judged fails its check).
fn exceeds(value: f64, bound: f64) -> bool {
    value > bound || value.is_nan()
}

/// Accumulates [`Physics`] over the states of a run: maxima only, no allocation per step.
#[derive(Debug)]
pub struct PhysicsMonitor<'m> {
    contact: Option<&'m ContactSet>,
    load: Option<&'m [f64]>,
    /// Whether the contact treatment is the multiplier (no contact energy).
    multiplier: bool,
    /// `FᵀU^0`, once the first state was seen.
    initial_load_work: f64,
    started: bool,
    physics: Physics,
}

impl<'m> PhysicsMonitor<'m> {
    /// A monitor of runs of `model`.
    pub fn new(model: &'m Model) -> Self {
        Self {
            contact: model.contact(),
            load: model.load(),
            multiplier: model.contact_law().treatment() == ContactTreatment::Multiplier,
            initial_load_work: 0.0,
            started: false,
            physics: Physics {
                penetration: 0.0,
                penetration_time: 0.0,
                face_displacement_scale: 0.0,
                relative_penetration: None,
                energy_start: 0.0,
                energy_max: f64::NEG_INFINITY,
                energy_max_time: 0.0,
                energy_ratio: None,
                external_work: model.load().map(|_| 0.0),
                wrong_sign_force: 0.0,
                max_force: 0.0,
            },
        }
    }

    /// Takes in the state `t_n` (the first call: `t_0`), with its energy without contact
    /// energy when the balance monitor carries it
    /// ([`crate::engine::schemes::energy_balance::BalanceMonitor::energy_of`]): used for a
    /// multiplier treatment, whose energy it is, instead of evaluating the scheme's.
    pub fn observe(&mut self, state: &Integration<'_>, balanced: Option<f64>) {
        let u = state.displacement();
        let time = state.time();
        let p = &mut self.physics;
        if let Some(set) = self.contact {
            for (&d, &g) in set.dofs.iter().zip(&set.gaps) {
                let gap = u[d] + g;
                if -gap > p.penetration {
                    p.penetration = -gap;
                    p.penetration_time = time;
                }
                p.face_displacement_scale = p.face_displacement_scale.max(gap);
            }
        }
        for &l in state.multiplier().value {
            p.wrong_sign_force = p.wrong_sign_force.max(l);
            p.max_force = p.max_force.max(l.abs());
        }
        let energy = match balanced.filter(|_| self.multiplier) {
            Some(value) => value,
            None => state.energy().value,
        };
        if !self.started {
            p.energy_start = energy;
        }
        if energy > p.energy_max {
            if energy > p.energy_max + ROUND_OFF * p.energy_max.abs() {
                p.energy_max_time = time;
            }
            p.energy_max = energy;
        }
        if let Some(f) = self.load {
            let work: f64 = f.iter().zip(u).map(|(a, b)| a * b).sum();
            if !self.started {
                self.initial_load_work = work;
            }
            let w = (work - self.initial_load_work).abs();
            p.external_work = Some(p.external_work.unwrap_or(0.0).max(w));
        }
        self.started = true;
    }

    /// What was measured over the states seen.
    pub fn physics(&self) -> Physics {
        let mut p = self.physics;
        p.relative_penetration =
            (p.face_displacement_scale > 0.0).then(|| p.penetration / p.face_displacement_scale);
        p.energy_ratio = (p.energy_start > 0.0).then(|| p.energy_max / p.energy_start);
        if !p.energy_max.is_finite() && !self.started {
            p.energy_max = 0.0;
        }
        p
    }
}
