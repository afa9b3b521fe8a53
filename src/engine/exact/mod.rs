//! Closed-form solutions of the 1D benchmarks, with everything the error norms need: the
//! displacement, its derivatives, the contact multiplier, the energy and the spatial kinks.

mod at_rest;
mod bouncing_bar;
mod clamped_mode;
mod signorini_dirichlet;

pub use at_rest::AtRest;
pub use bouncing_bar::BouncingBar;
pub use clamped_mode::ClampedFreeMode;
pub use signorini_dirichlet::SignoriniDirichlet;

/// `(u, u_x, u_t)` at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pointwise {
    /// Displacement `u`.
    pub u: f64,
    /// Strain `u_x`.
    pub ux: f64,
    /// Velocity `u_t`.
    pub ut: f64,
}

/// An exact solution of `u_tt − u_xx = f` on the bar `[0, L]`.
pub trait ExactSolution: Send + Sync + std::fmt::Debug {
    /// A short name (used in scene files and reports).
    fn name(&self) -> &'static str;
    /// `(u, u_x, u_t)` at `(x, t)`.
    fn eval(&self, x: f64, t: f64) -> Pointwise;
    /// `(u, u_x, u_t)` at the points `xs` of one time `t` (the norms' quadrature points of a
    /// step); implementations hoist the work that depends on `t` only.
    fn eval_many(&self, t: f64, xs: &[f64], out: &mut [Pointwise]) {
        for (o, &x) in out.iter_mut().zip(xs) {
            *o = self.eval(x, t);
        }
    }
    /// The contact multiplier `λ(t) = u_x(0, t)` (1D paper §5.1), zero when there is no contact.
    fn contact_multiplier(&self, t: f64) -> f64;
    /// The exact energy `½ ∫ (u_t² + u_x²) dx` (plus the load's potential).
    fn energy(&self, t: f64) -> f64;
    /// Appends, sorted, the points of `(0, L)` where `u(·, t)` is not smooth.
    fn breakpoints(&self, t: f64, out: &mut Vec<f64>);
    /// Gauss points per smooth piece that make the space error norms accurate: 2 integrates
    /// the square of a piecewise affine error exactly.
    fn gauss_points(&self) -> usize;
}
