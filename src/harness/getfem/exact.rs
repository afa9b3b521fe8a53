//! The exact solution as GetFEM's demo evaluates it: the Signorini–Dirichlet solution of the
//! 1D paper §5.1 ([`SignoriniDirichlet`](crate::engine::exact::SignoriniDirichlet)), with the
//! demo's closure of its regions.
//!
//! The solution is piecewise affine, so `u` is continuous but `u_x` and `u_t` jump across the
//! characteristics `x = τ` and `x = 1 − τ`. With `Δx/Δt = 10` a node lies on a characteristic
//! every ten steps, and its nodal value of `u_t` is whatever side the evaluation assigns it to.
//! The engine counts `x = τ` as ahead of the wave (`x ≥ τ`); the demo counts it as behind
//! (`τ < x` is ahead), and decides `x + τ ≤ 1` as `τ ≤ 1 − x` in floating point. The two
//! interpolants of the velocity then differ by `½` at one node at about one step in twenty
//! (33 of the 601 steps of NX = 20), which moves `‖I_h v‖_{L²}` by up to 0.09: the demo's norms
//! can only be reproduced with the demo's closure, hence this evaluation.

use crate::engine::exact::Pointwise;

/// `(u, u_x, u_t)` at `(x, t)` as the demo's `uExact` gives them: with `t_p = t mod 3`, the
/// phase `k = ⌊t_p⌋` and the local time `τ = t_p mod 1`, the point is in region
///
/// - I if `τ < x` and `τ ≤ 1 − x`, II if `x ≤ τ` and `τ ≤ 1 − x`,
/// - III if `τ < x` and `τ > 1 − x`, IV if `x ≤ τ` and `τ > 1 − x`,
///
/// (the comparisons evaluated as written, in floating point), and the value is the one of the
/// table of the 1D paper's eqs. (41)–(42) and their third phase:
///
/// | phase | I | II | III | IV |
/// |---|---|---|---|---|
/// | 0 | `½ − x/2` | `½ − τ/2` | `½ − x/2` | `½ − τ/2` |
/// | 1 | `−τ/2` | `−x/2` | `−½ + x/2` | `−½ + τ/2` |
/// | 2 | `τ/2` | `τ/2` | `½ − x/2` | `½ − x/2` |
///
/// `u_x` and `u_t` are the derivatives of the region's affine expression. At `x = 0` this makes
/// `u_x(0, t)` the contact stress of the demo's `store_s0_ex`: `0` at `t = 0` (region II),
/// `−½` during phase 1.
pub fn demo_exact(x: f64, t: f64) -> Pointwise {
    let tp = t.rem_euclid(3.0);
    let tau = tp.rem_euclid(1.0);
    let phase = tp.floor();
    let ahead = tau < x;
    let before_reflection = tau <= 1.0 - x;
    let (u, ux, ut) = if phase < 1.0 {
        if ahead {
            (0.5 - x / 2.0, -0.5, 0.0)
        } else {
            (0.5 - tau / 2.0, 0.0, -0.5)
        }
    } else if phase < 2.0 {
        match (ahead, before_reflection) {
            (true, true) => (-tau / 2.0, 0.0, -0.5),
            (false, true) => (-x / 2.0, -0.5, 0.0),
            (true, false) => (-0.5 + x / 2.0, 0.5, 0.0),
            (false, false) => (-0.5 + tau / 2.0, 0.0, 0.5),
        }
    } else if before_reflection {
        (tau / 2.0, 0.0, 0.5)
    } else {
        (0.5 - x / 2.0, -0.5, 0.0)
    };
    Pointwise { u, ux, ut }
}
