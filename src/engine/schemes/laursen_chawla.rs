//! The energy-conserving scheme of T. A. Laursen and V. Chawla (IJNME 40, 1997, §4): the
//! trapezoidal rule with the contact force at the midpoint, and the persistency condition in
//! place of the Kuhn–Tucker conditions at `t_{n+1}` on the constraints the unconstrained step
//! would close:
//! ```text
//! M (V^{n+1} − V^n) = Δt (F − S U^{n+½}) − Δt Bᵀλ^{n+1}                       (LC-a)
//! U^{n+1} = U^n + Δt V^{n+½}                                                   (LC-b)
//! A^n = { i : (B Ũ^{n+1} + g)_i ≤ 0 },  Ũ^{n+1} the step without contact         (LC-c)
//! i ∈ A^n: 0 ≤ (B U^{n+1} − B U^n)_i ⟂ λ_i^{n+1} ≤ 0;   i ∉ A^n: λ_i^{n+1} = 0      (LC-d)
//! ```
//! with `X^{n+½} = (X^n + X^{n+1})/2`; `λ^{n+1}` is the midpoint force (`Δt λ^{n+1}` the step's
//! impulse), reported at `t_{n+1}`. (LC-d) is the discrete persistency condition `λ ġ = 0`:
//! a pushing constraint keeps its gap over the step. By (LC-b),
//! `(B U^{n+1} − B U^n)_i = ½ Δt (B V^{n+1} + B V^n)_i`, so (LC-d) is Newton's law with e = 1 and
//! the scheme is Moreau–Jean's (θ = ½, e = 1, [`super::moreau_jean`]) with the trial gap of
//! (LC-c) as its activation rule ([`Activation::FreeStep`]).
//!
//! **Why this one.** Its balance is (MJ-E) with θ = ½, `ΔE = −ΔUᵀBᵀλ^{n+1}`, and (LC-d) makes
//! every product `λ_i (BΔU)_i` zero: the energy `E_h(U, V)` (eq. 31) is conserved at every step
//! to round-off, with the exact multiplier, either mass, and one linear complementarity problem
//! per step like the paper's schemes. The other candidate, Hauret and Le Tallec's
//! energy-consistent scheme (CMAME 195, 2006), conserves the penalised energy `E + Φ` by a
//! discrete gradient of the penalty potential: a nonlinear problem at every step, and the
//! penalty's `O(κ⁻¹)` penetration in the solution it conserves. The price of conservation here is
//! the condition itself: a constraint the trial closes stops where it was at `t_n`, so a contact
//! is established up to `O(Δt)` early (a gap of the step's approach remains); a constraint in
//! `A^n` keeps `B U + g ≥ 0` at `t_{n+1}` when it held at `t_n`, and one outside it is checked
//! only on the trial.

use super::moreau_jean::{Activation, MoreauJean};
use crate::engine::error::SolveError;
use crate::engine::model::Model;

/// The Laursen–Chawla integrator on `model` with step `dt`: Moreau–Jean with θ = ½, e = 1 and
/// the trial-gap activation (see the module documentation).
pub fn laursen_chawla(model: &Model, dt: f64) -> Result<MoreauJean<'_>, SolveError> {
    Ok(MoreauJean::new(model, 0.5, 1.0, dt)?.with_activation(Activation::FreeStep))
}
