//! The gravity benchmark of the 1D paper §4 (after Wriggers): a bar `[0, L]` with both ends
//! free falls from the height `u⁰` onto the obstacle at `x = 0`, stays in contact while the
//! shock wave runs up and back, takes off, and bounces on. Wave speed and density are 1.
//!
//! # The problem solved
//!
//! `u(x, t)` is the displacement measured from the obstacle:
//!
//! * `u_tt − u_xx = f` on `(0, L)` (eq. 1) with the **gravity load `f = −g`**;
//! * `u(x, 0) = u⁰`, `u_t(x, 0) = 0` (eq. 2 with the data of §4.2);
//! * `0 ≤ u(0, t) ⟂ u_x(0, t) ≤ 0` and `u_x(L, t) = 0` (eq. 4).
//!
//! The contact force acts at `x = 0` only, through the multiplier `λ(t) = u_x(0, t) ≤ 0`. The
//! paper prints the load as `f(x, t) = −(g + u_x(0, t))` (§4.1). Its own solution does not
//! satisfy that reading: the series part of `h₁` (eq. 39) has
//! `(∂_tt − ∂_xx) Σ 2g/(Lν_n³)(cos ν_n t − 1) sin ν_n x = −g Σ 2/(Lν_n) sin ν_n x = −g` on
//! `(0, L)`, and the `min` part is a free wave, so `h₁` solves the equation with `f = −g` while
//! `u_x(0, t) = −√(2u⁰g) − g(t − t₁) ≠ 0` in contact. In flight `u_x(0, t) = 0` and the two
//! readings coincide. The energy conserved is
//! `E = ½∫(u_t² + u_x²) dx + ∫ g u dx = g u⁰ L` (its value at `t = 0`).
//!
//! # The closed form (d'Alembert with gravity)
//!
//! Every solution of `u_tt − u_xx = −g` is
//!
//! ```text
//! u   = g(x²/2 − Lx) + A(t + x) + B(t − x),
//! u_x = g(x − L) + A′(t + x) − B′(t − x),     u_t = A′(t + x) + B′(t − x).
//! ```
//!
//! (`g(x²/2 − Lx)` is the bar at rest on the obstacle; with it `A` and `B` stay bounded.) The
//! Riemann invariant `r = u_t + u_x` that arrives at the obstacle is `R(t) = 2A′(t) − gL`. The
//! data fix `A(τ) = gLτ/2 − gτ²/4` on `[0, L]` and `B(s) = u⁰ − gLs/2 − gs²/4` on `[−L, 0]`, and
//! the boundary conditions continue them:
//!
//! * `x = L`, `u_x = 0`: `A′(τ) = B′(τ − 2L)` for `τ ≥ L` (`A` continuous);
//! * `x = 0` in flight, `u_x(0, t) = 0`: `B′(t) = A′(t) − gL` (`B` continuous);
//! * `x = 0` in contact, `u(0, t) = 0`: `B(t) = −A(t)`, and `λ(t) = u_x(0, t) = R(t)`.
//!
//! The phase follows the height `y(t) = u(0, t) = A(t) + B(t)`: in flight `y′ = R`; contact
//! begins when `y` reaches 0, and lasts while the force it needs is compressive, `R ≤ 0`; the
//! bar takes off as soon as `R > 0` (`R` jumps up when a shock arrives, or crosses 0 with slope
//! `+g`). So `A` and `B` are piecewise quadratic (`A″, B″ = ±g/2`), with finitely many breaks
//! on every bounded interval. They are built once, event by event, in windows of `2L` (the delay
//! of the rule at `x = L`), up to a horizon. Between the characteristics through the breaks,
//! `u` is a quadratic polynomial in `x` and `t`.
//!
//! # The first bounce, and the paper's eqs. 38–40
//!
//! With `t₁ = √(2u⁰/g)` and the impact speed `V = g t₁ = √(2u⁰g)`:
//!
//! * `t ≤ t₁`: free fall `u = u⁰ − gt²/2` (eq. 38, first line).
//! * Contact, `s = t − t₁ ∈ [0, 2L]`: `λ(t) = −V − gs`. At `s = 2L` the returning shock makes
//!   `R` jump by `2V` to `V − 2gL`. When `V > 2gL` (`t₁ > 2L`) the bar therefore takes off at
//!   `t₂ = t₁ + 2L`, with `u(x, t₂) = g(x² − 2Lx)` and `u_t(x, t₂) = V`. Contact lasts `2L`, not
//!   "a time `L`" as the text of §4.1 says. In this phase `u` is eq. (39),
//!   `h₁(x, s) = −V min(x, L − |s − L|) + Σ 2g/(Lν_n³)(cos ν_n s − 1) sin ν_n x`, where the
//!   sine series is `g(x²/2 − Lx)` minus its free vibration. Eq. (39) prints the coefficient of
//!   the `min` term as `√(2u⁰/g) = t₁`. It must be `√(2u⁰g) = V` (for §4.2, 0.332 instead of
//!   3.015), or `u_t` jumps at `t₁` away from the obstacle.
//! * Flight, `s = t − t₂`: `u` is eq. (40),
//!   `h₂(x, s) = u⁰ − g(s − t₁)²/2 − 2gL²/3 + Σ 4g/λ_n² cos λ_n s cos λ_n x`. That is the rigid
//!   motion of the mean plus the free vibration of `g(x² − 2Lx)`. It gives
//!   `y(s) = g[t₁s − s²/2 + σ(σ − 2L)]`, `σ = s mod 2L`, until `y` returns to 0.
//!
//! # Long times
//!
//! * If `t₁/L` is an integer `≥ 3`, the flight is symmetric in time about its middle
//!   (`sin λ_n t₁ = 0`) and lasts `2t₁`. The second contact is the time reverse of the first.
//!   The motion is periodic with period `4(t₁ + L)`: contacts begin at `t₁ + 4k(t₁ + L)` and
//!   `t₁ + 2L + 2t₁ + 4k(t₁ + L)`, and each lasts `2L`. These are the paper's
//!   `t_{4k+1} = 3L + 16kL`, `t_{4k+2} = t_{4k+1} + 2L`, `t_{4k+3} = t_{4k+1} + 8L`,
//!   `t_{4k+4} = t_{4k+1} + 10L` exactly when `t₁ = 3L`, i.e. `g = 2u⁰/(9L²)` (`1/9` for `u⁰ = ½`,
//!   `L = 1`). Eq. (38) then holds for all `k`.
//! * For the data of §4.2 (`L = 1`, `u⁰ = ½`, `g = 0.11`), `t₁ = √(1/0.11) = 3.0151134`.
//!   Contact still lasts `2L`, but the first flight ends at `t₃ = 11.0333379`, not at `11`. The
//!   impacts then come at `19.0394852`, `27.0431593`, …. The flights last `6L + δ_k`, with
//!   `δ_k > 0` shrinking by a factor ≈ 0.205 every two bounces. The motion is not periodic. It
//!   converges geometrically to a `16L`-periodic motion with impacts at `3.0456824789 + 8k`.
//!   Weak fronts (jumps of `u_xx`) accumulate near `x ≈ 0.0457`.
//! * For other parameters the contact splits into many intervals, and their number can grow
//!   exponentially: for `L = 1`, `g = 0.2`, `u⁰ = ½` it doubles about every 20 time units. The
//!   construction stops at [`BouncingBar::MAX_PIECES`] pieces.
//!
//! # Evaluation
//!
//! `eval` locates `t + x` among the pieces of `A` and `t − x` among those of `B` (binary
//! search), then evaluates two quadratics. `eval_many` starts from the previous point's pieces.
//! The kinks of `u(·, t)` are the characteristics through the breaks of `A` and `B`. Between
//! them `u` is quadratic in `x`, so the squared error of a P1 field is a quartic, and three
//! Gauss points per piece integrate it exactly.
//!
//! Rounding: pieces that continue the previous one (slope and curvature equal to 1e-12
//! relative) are merged, and an impact found within rounding (1e-12 (L + t)) before a break of
//! `A` is put at the break. That is the limit `δ_k → 0⁺` of the paper's case, where the impacts
//! follow a front by `δ_k`, below rounding after about 30 bounces.

use super::{ExactSolution, Pointwise};
use crate::engine::error::{require_positive, ParameterError};

/// Relative tolerance of the event logic (heights, forces and times); far above the rounding of
/// the traces and far below anything physical.
const EVENT_TOL: f64 = 1e-12;

/// A continuous piecewise quadratic `f(s) = c₀ + c₁ d + c₂ d²`, `d = s − start_k`, on
/// `[start_k, start_{k+1})`.
#[derive(Debug, Clone, Default)]
struct Trace {
    start: Vec<f64>,
    coef: Vec<[f64; 3]>,
}

impl Trace {
    /// The piece containing `s`: the last with `start ≤ s` (the first one before the domain).
    #[inline]
    fn locate(&self, s: f64) -> usize {
        self.start.partition_point(|&p| p <= s).saturating_sub(1)
    }

    /// [`Self::locate`], trying the neighbours of `hint` first; same answer.
    #[inline]
    fn locate_near(&self, hint: usize, s: f64) -> usize {
        let n = self.start.len();
        let fits = |i: usize| self.start[i] <= s && (i + 1 == n || s < self.start[i + 1]);
        if hint < n && fits(hint) {
            hint
        } else if hint + 1 < n && fits(hint + 1) {
            hint + 1
        } else if hint > 0 && hint <= n && fits(hint - 1) {
            hint - 1
        } else {
            self.locate(s)
        }
    }

    /// `(f(s), f′(s))` on piece `i`.
    #[inline]
    fn value(&self, i: usize, s: f64) -> (f64, f64) {
        let [c0, c1, c2] = self.coef[i];
        let d = s - self.start[i];
        (c0 + d * (c1 + d * c2), c1 + 2.0 * c2 * d)
    }

    /// The second coefficient (`f″/2`) of piece `i`.
    #[inline]
    fn curvature(&self, i: usize) -> f64 {
        self.coef[i][2]
    }

    fn last(&self) -> usize {
        self.start.len() - 1
    }

    /// Appends the piece `c` from `s` on, unless it continues the last piece (same slope and
    /// curvature at `s` within `tol_slope`, `tol_curv`). A piece starting where the last one
    /// starts replaces it.
    fn push(&mut self, s: f64, c: [f64; 3], tol_slope: f64, tol_curv: f64) {
        if let Some(&p) = self.start.last() {
            let i = self.last();
            if s <= p {
                self.coef[i] = c;
                return;
            }
            let (_, slope) = self.value(i, s);
            if (slope - c[1]).abs() <= tol_slope && (self.coef[i][2] - c[2]).abs() <= tol_curv {
                return;
            }
        }
        self.start.push(s);
        self.coef.push(c);
    }

    /// The end of piece `i` (the next start), or `end` for the last piece.
    fn piece_end(&self, i: usize, end: f64) -> f64 {
        self.start.get(i + 1).copied().unwrap_or(end)
    }
}

/// Smallest root of `y₀ + c₁ d + c₂ d²` in `(0, ∞)` for `y₀ > 0`.
fn first_positive_root(y0: f64, c1: f64, c2: f64) -> Option<f64> {
    if c2 == 0.0 {
        return (c1 < 0.0).then(|| -y0 / c1);
    }
    let disc = c1 * c1 - 4.0 * c2 * y0;
    if disc < 0.0 {
        return None;
    }
    let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
    let roots = [q / c2, if q != 0.0 { y0 / q } else { f64::NAN }];
    roots
        .into_iter()
        .filter(|r| *r > 0.0)
        .min_by(|a, b| a.total_cmp(b))
}

/// The exact solution of the gravity benchmark (1D paper §4, eqs. 38–40) for any length `L`,
/// gravity `g` and drop height `u⁰`, in closed form (module documentation).
///
/// `u = g(x²/2 − Lx) + A(t + x) + B(t − x)` with `A`, `B` piecewise quadratic, built up to a
/// horizon (by default `16(t₁ + L)`; see [`BouncingBar::with_horizon`]). Evaluating after the
/// horizon panics.
#[derive(Debug, Clone)]
pub struct BouncingBar {
    length: f64,
    gravity: f64,
    initial_height: f64,
    /// `A` on `[0, b_end + 2L]`.
    a: Trace,
    /// `B` on `[−L, b_end]`.
    b: Trace,
    /// `A` is built up to here.
    a_end: f64,
    /// `B` is built up to here (the horizon).
    b_end: f64,
    /// Whether the bar is in contact at `b_end`.
    in_contact: bool,
    /// Contact intervals `[begin, end)`; the last one ends at `+∞` while open at `b_end`.
    contacts: Vec<(f64, f64)>,
}

impl BouncingBar {
    /// The most pieces `A` or `B` may hold (32 bytes each): the construction stops there.
    pub const MAX_PIECES: usize = 1 << 20;

    /// The most windows of `2L` the construction advances through (each costs a few
    /// operations even when it adds no piece): a horizon is at most `2L` times this, which
    /// bounds the work of a bar much shorter than its flight (`L = 1e-10`), or falling from
    /// very high or under a very weak gravity (`t₁ = √(2u⁰/g)` of `1e15`).
    pub const MAX_WINDOWS: f64 = (1 << 20) as f64;

    /// The benchmark with length `L = length`, gravity `g = gravity` and drop height
    /// `u⁰ = initial_height`, built to the horizon `16(t₁ + L)` (four of the paper's nominal
    /// periods; less if [`Self::MAX_PIECES`] or [`Self::MAX_WINDOWS`] is reached first). Each
    /// must be finite and > 0.
    pub fn new(length: f64, gravity: f64, initial_height: f64) -> Result<Self, ParameterError> {
        let length = require_positive("length", length)?;
        let gravity = require_positive("gravity", gravity)?;
        let initial_height = require_positive("initial_height", initial_height)?;
        let t1 = (2.0 * initial_height / gravity).sqrt();
        let mut bar = Self {
            length,
            gravity,
            initial_height,
            a: Trace::default(),
            b: Trace::default(),
            a_end: length,
            b_end: 0.0,
            in_contact: false,
            contacts: Vec::new(),
        };
        // The data u = u⁰, u_t = 0: A(τ) = gLτ/2 − gτ²/4 on [0, L] and
        // B(s) = u⁰ − gLs/2 − gs²/4 on [−L, 0].
        bar.a.start.push(0.0);
        bar.a
            .coef
            .push([0.0, 0.5 * gravity * length, -0.25 * gravity]);
        bar.b.start.push(-length);
        bar.b.coef.push([
            initial_height + 0.25 * gravity * length * length,
            0.0,
            -0.25 * gravity,
        ]);
        bar.extend_to((16.0 * (t1 + length)).min(bar.reachable()));
        Ok(bar)
    }

    /// The longest horizon within [`Self::MAX_WINDOWS`] windows of `2L`.
    fn reachable(&self) -> f64 {
        2.0 * self.length * Self::MAX_WINDOWS
    }

    /// The parameters of §4.2: `L = 1`, `g = 0.11`, `u⁰ = 0.5`.
    pub fn paper() -> Self {
        Self::new(1.0, 0.11, 0.5).expect("valid parameters")
    }

    /// The same solution built up to at least `horizon` (never shortened). Fails if that
    /// needs more than [`Self::MAX_WINDOWS`] windows or [`Self::MAX_PIECES`] pieces.
    pub fn with_horizon(mut self, horizon: f64) -> Result<Self, ParameterError> {
        let horizon = require_positive("horizon", horizon)?;
        if horizon > self.reachable() {
            return Err(ParameterError::new(
                "horizon",
                format!(
                    "{horizon} (past {:.3e}, the end of 2^20 windows of 2 length = {:.3e})",
                    self.reachable(),
                    2.0 * self.length
                ),
                "a horizon the closed form reaches within BouncingBar::MAX_WINDOWS windows of \
                 2 length (a longer bar, or a shorter horizon)",
            ));
        }
        if self.extend_to(horizon) {
            Ok(self)
        } else {
            Err(ParameterError::new(
                "horizon",
                horizon,
                "a horizon the closed form reaches within BouncingBar::MAX_PIECES pieces (the \
                 number of contact intervals can grow exponentially in time)",
            ))
        }
    }

    /// The bar length `L`.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The gravity `g` (the load is `f = −g`).
    pub fn gravity(&self) -> f64 {
        self.gravity
    }

    /// The drop height `u⁰`.
    pub fn initial_height(&self) -> f64 {
        self.initial_height
    }

    /// The time up to which the solution is built: `eval` and friends accept `t ≤ horizon`.
    pub fn horizon(&self) -> f64 {
        self.b_end
    }

    /// The first impact time `t₁ = √(2u⁰/g)` (§4.1).
    pub fn first_impact_time(&self) -> f64 {
        (2.0 * self.initial_height / self.gravity).sqrt()
    }

    /// The impact speed `√(2u⁰g)` (§4.1).
    pub fn impact_speed(&self) -> f64 {
        (2.0 * self.initial_height * self.gravity).sqrt()
    }

    /// The contact intervals `[begin, end)` within `[0, horizon]` (ends clipped to `horizon`).
    /// Their begins are the impact times, their ends the take-off times.
    ///
    /// # Panics
    ///
    /// If `horizon` exceeds [`Self::horizon`].
    pub fn contact_intervals(&self, horizon: f64) -> Vec<(f64, f64)> {
        self.check_time(horizon);
        self.contacts
            .iter()
            .filter(|(begin, _)| *begin < horizon)
            .map(|&(begin, end)| (begin, end.min(horizon)))
            .collect()
    }

    /// The times at which contact begins (impacts), up to [`Self::horizon`].
    pub fn impact_times(&self) -> Vec<f64> {
        self.contacts.iter().map(|c| c.0).collect()
    }

    /// The times at which contact ends (take-offs), up to [`Self::horizon`].
    pub fn takeoff_times(&self) -> Vec<f64> {
        self.contacts
            .iter()
            .map(|c| c.1)
            .filter(|e| e.is_finite())
            .collect()
    }

    /// Whether the bar touches the obstacle at `t` (`t` in a contact interval).
    pub fn in_contact(&self, t: f64) -> bool {
        self.check_time(t);
        let k = self.contacts.partition_point(|c| c.0 <= t);
        k > 0 && t < self.contacts[k - 1].1
    }

    /// `R(t) = 2A′(t) − gL`, the Riemann invariant `u_t + u_x` arriving at `x = 0` (right
    /// limit): the contact force `λ` the obstacle would need to keep `u(0, ·) = 0`.
    pub fn incoming_invariant(&self, t: f64) -> f64 {
        self.check_time(t);
        2.0 * self.a.value(self.a.locate(t), t).1 - self.gravity * self.length
    }

    fn check_time(&self, t: f64) {
        assert!(
            t <= self.b_end,
            "BouncingBar evaluated at t = {t} after its horizon {}; build it with \
             BouncingBar::with_horizon",
            self.b_end
        );
    }

    /// Tolerances: slope (velocity) and curvature for merging pieces.
    fn tolerances(&self) -> (f64, f64) {
        let speed = self.impact_speed() + self.gravity * self.length;
        (EVENT_TOL * speed, EVENT_TOL * self.gravity)
    }

    /// Builds `A` and `B` until `B` covers `[−L, horizon]` and `A` covers `[0, horizon + 2L]`;
    /// `false` if [`Self::MAX_PIECES`] stopped it first.
    fn extend_to(&mut self, horizon: f64) -> bool {
        loop {
            self.extend_a();
            if self.b_end >= horizon {
                return true;
            }
            if self.a.start.len().max(self.b.start.len()) > Self::MAX_PIECES {
                return false;
            }
            self.extend_b();
        }
    }

    /// `A′(τ) = B′(τ − 2L)` (eq. 4 at `x = L`) on `[a_end, b_end + 2L]`.
    fn extend_a(&mut self) {
        let two_l = 2.0 * self.length;
        let target = self.b_end + two_l;
        if self.a_end >= target {
            return;
        }
        let (tol_slope, tol_curv) = self.tolerances();
        let mut ib = self.b.locate(self.a_end - two_l);
        let mut tau = self.a_end;
        while tau < target {
            let s = (tau - two_l).max(self.b.start[ib]);
            let (_, db) = self.b.value(ib, s);
            let curv = self.b.curvature(ib);
            let a_last = self.a.last();
            let (a_val, _) = self.a.value(a_last, tau);
            self.a.push(tau, [a_val, db, curv], tol_slope, tol_curv);
            if ib + 1 >= self.b.start.len() {
                break;
            }
            ib += 1;
            tau = self.b.start[ib] + two_l;
        }
        self.a_end = target;
    }

    /// `B` on `[b_end, a_end]` from the condition at `x = 0`, with the impacts and take-offs.
    fn extend_b(&mut self) {
        let target = self.a_end;
        let (tol_slope, tol_curv) = self.tolerances();
        let tol_y = EVENT_TOL * (self.initial_height + self.gravity * self.length.powi(2));
        // Times carry an absolute rounding error of a few ulp(t): the time tolerance grows
        // with t.
        let length = self.length;
        let tol_t = |t: f64| EVENT_TOL * (length + t.abs());
        let gl = self.gravity * self.length;
        // "The obstacle would have to pull": R > 0 now, or R = 0 and increasing.
        let pushes_off = |r0: f64, slope: f64| r0 > tol_slope || (r0 >= -tol_slope && slope > 0.0);
        let mut t = self.b_end;
        let mut ia = self.a.locate(t);
        // Flight starting at height 0 (take-off, or grazing upwards): y₀ = 0 exactly.
        let mut from_ground = false;
        let mut switches_here = 0;
        while t < target {
            while ia + 1 < self.a.start.len() && self.a.start[ia + 1] <= t {
                ia += 1;
            }
            let q = self.a.piece_end(ia, target).min(target);
            let (av, ad) = self.a.value(ia, t);
            let a2 = self.a.curvature(ia);
            let (r0, r_slope) = (2.0 * ad - gl, 4.0 * a2);
            if self.in_contact {
                if pushes_off(r0, r_slope) && switches_here < 2 {
                    self.take_off(t);
                    from_ground = true;
                    switches_here += 1;
                    continue;
                }
                self.b.push(t, [-av, -ad, -a2], tol_slope, tol_curv);
                // λ = R crosses 0 upwards inside the piece?
                let zero = if r_slope > 0.0 {
                    t - r0 / r_slope
                } else {
                    f64::INFINITY
                };
                if zero > t && zero < q - tol_t(q) {
                    self.take_off(zero);
                    from_ground = true;
                    t = zero;
                } else {
                    t = q;
                }
                switches_here = 0;
            } else {
                let b_last = self.b.last();
                let mut bv = self.b.value(b_last, t).0;
                if from_ground {
                    bv = -av;
                } else if av + bv <= tol_y {
                    if !pushes_off(r0, r_slope) && switches_here < 2 {
                        self.impact(t);
                        switches_here += 1;
                        continue;
                    }
                    bv = -av;
                    from_ground = true;
                }
                let y0 = av + bv;
                self.b.push(t, [bv, ad - gl, a2], tol_slope, tol_curv);
                // y(t + d) = y₀ + R d + 2a₂ d² in this piece.
                let (c1, c2) = (r0, 2.0 * a2);
                let root = if from_ground {
                    (c2 < 0.0 && c1 > 0.0).then(|| -c1 / c2)
                } else {
                    first_positive_root(y0, c1, c2)
                };
                from_ground = false;
                switches_here = 0;
                match root {
                    Some(d) if t + d < q - tol_t(q) => {
                        t += d;
                        self.impact(t);
                    }
                    Some(d) if t + d <= q => {
                        // Within rounding of the next break: the impact follows the front
                        // arriving there.
                        t = q;
                        self.impact(t);
                    }
                    _ => t = q,
                }
            }
        }
        self.b_end = target;
    }

    fn impact(&mut self, t: f64) {
        self.in_contact = true;
        self.contacts.push((t, f64::INFINITY));
    }

    fn take_off(&mut self, t: f64) {
        self.in_contact = false;
        let last = self.contacts.last_mut().expect("a contact is open");
        if t > last.0 {
            last.1 = t;
        } else {
            self.contacts.pop();
        }
    }

    #[inline]
    fn point(&self, ia: usize, ib: usize, x: f64, t: f64) -> Pointwise {
        let (a, da) = self.a.value(ia, t + x);
        let (b, db) = self.b.value(ib, t - x);
        let g = self.gravity;
        Pointwise {
            u: g * x * (0.5 * x - self.length) + a + b,
            ux: g * (x - self.length) + da - db,
            ut: da + db,
        }
    }
}

impl ExactSolution for BouncingBar {
    fn name(&self) -> &'static str {
        "bouncing-bar"
    }

    /// `u = g(x²/2 − Lx) + A(t + x) + B(t − x)` and its derivatives (module documentation).
    fn eval(&self, x: f64, t: f64) -> Pointwise {
        self.check_time(t);
        self.point(self.a.locate(t + x), self.b.locate(t - x), x, t)
    }

    fn eval_many(&self, t: f64, xs: &[f64], out: &mut [Pointwise]) {
        self.check_time(t);
        let (mut ia, mut ib) = (0, 0);
        for (o, &x) in out.iter_mut().zip(xs) {
            ia = self.a.locate_near(ia, t + x);
            ib = self.b.locate_near(ib, t - x);
            *o = self.point(ia, ib, x, t);
        }
    }

    /// `λ(t) = u_x(0, t) = 2A′(t) − gL ≤ 0` in contact (right limit at an impact), 0 in flight.
    fn contact_multiplier(&self, t: f64) -> f64 {
        if self.in_contact(t) {
            self.incoming_invariant(t).min(0.0)
        } else {
            0.0
        }
    }

    /// `½∫(u_t² + u_x²) dx + ∫ g u dx = g u⁰ L`, conserved.
    fn energy(&self, _t: f64) -> f64 {
        self.gravity * self.initial_height * self.length
    }

    /// The characteristics through the breaks of `A` (`x = τ − t`) and `B` (`x = t − σ`) that
    /// cross `(0, L)` at `t`: the shock fronts (jumps of `u_x`) and the weak fronts (jumps of
    /// `u_xx`).
    fn breakpoints(&self, t: f64, out: &mut Vec<f64>) {
        self.check_time(t);
        let l = self.length;
        let a = &self.a.start;
        let b = &self.b.start;
        let (a_lo, a_hi) = (
            a.partition_point(|&p| p <= t),
            a.partition_point(|&p| p < t + l),
        );
        let (b_lo, b_hi) = (
            b.partition_point(|&p| p <= t - l),
            b.partition_point(|&p| p < t),
        );
        let mut from_a = a[a_lo..a_hi].iter().map(|&p| p - t).peekable();
        let mut from_b = b[b_lo..b_hi].iter().rev().map(|&p| t - p).peekable();
        let min_gap = EVENT_TOL * l;
        let first = out.len();
        loop {
            let x = match (from_a.peek(), from_b.peek()) {
                (Some(&xa), Some(&xb)) if xa <= xb => from_a.next(),
                (Some(_), Some(_)) => from_b.next(),
                (Some(_), None) => from_a.next(),
                (None, Some(_)) => from_b.next(),
                (None, None) => break,
            }
            .expect("peeked");
            if x <= 0.0 || x >= l {
                continue;
            }
            if out.len() > first && x - out[out.len() - 1] <= min_gap {
                continue;
            }
            out.push(x);
        }
    }

    /// 3: between breakpoints `u(·, t)` is quadratic, the error of a P1 field squared is a
    /// quartic, integrated exactly by 3 Gauss points (2 would be exact only to degree 3).
    fn gauss_points(&self) -> usize {
        3
    }
}
