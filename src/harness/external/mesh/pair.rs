//! The distance between two finite element functions on two meshes of one box, defined once
//! for any pair: an external field `u_h` on its own conforming mesh ([`ElementMesh`]) and a
//! reference `u_ref` on the scene's structured Q1 mesh ([`BoxMesh`], the finer of the two).
//!
//! With `e = u_h − u_ref`, the norms are those of the structured path
//! ([`crate::harness::run::nested_comparison::norm_matrices`]):
//! ```text
//! ‖e‖²_H = ρ ∫_Ω |e|²,   ‖e‖²_V = ‖e‖²_H + a(e, e),   a(e, e) = ∫_Ω λ (tr ε(e))² + 2μ ε(e):ε(e),
//! ```
//! and beside them `‖e‖²_{L²} = ∫ |e|²` and the H¹ seminorm `|e|²_{H¹} = ∫ |∇e|²`.
//!
//! **The quadrature** ([`Quadrature`]): each reference element (an axis-aligned box) is cut into
//! `subcells^d` equal boxes, each integrated by the tensor Gauss–Legendre rule of `gauss` points
//! per axis; at every point `x` the reference is evaluated on its element and `u_h` and its
//! gradient in the external cell that holds `x` ([`ElementMesh::locate`]). Its own error:
//! - **zero** (to round-off) when every external cell is a union of reference elements and Q1
//!   (the scene's structured mesh at a coarser level, nested): the integrand is then a
//!   polynomial of degree at most 2 per axis on each reference element, which 2 Gauss points
//!   per axis integrate exactly; the result is the structured path's `eᵀMe`, `eᵀSe` of the
//!   prolongated error (tested, `tests/cli/verify_mesh.rs`);
//! - otherwise (a simplex mesh, a mesh not nested in the reference's) the integrand is a
//!   polynomial on each piece of a reference element cut by the external cells' faces, with a
//!   kink (a jump of the gradient) across them, and the rule's error is that of Gauss on a
//!   function with a kink: it falls by about 4 each time the subcells are halved, and the
//!   stated bound is **twice the distance to the same rule on halved subcells** (Richardson's
//!   estimate is 4/3 of it). Tested on the bars' level-5 meshes split into triangles (two per
//!   element) and Kuhn tetrahedra (six per element) against the level-20 reference, with a
//!   multilinear field (which the Q1 reference reproduces, P1 does not) whose exact errors are
//!   integrated on the simplices: with 3 points per axis and no subcell the L² error is off by
//!   2.8e-3 (2D) and 3.3e-2 (3D) of itself, the H¹ seminorm by 6.1e-3 and 5.7e-3; on 8 subcells
//!   per axis by at most 5.1e-4, and every rule within its bound.

// Components and axes are indexed as the formulas write them (`J[c][j]`, `∂N_a/∂ξ_j`).
#![allow(clippy::needless_range_loop)]

use crate::engine::fem::box_mesh::{BoxMesh, Elasticity};

use super::face::ContactFace;
use super::function::{ElementMesh, Evaluation};

/// The rule of [`pair_errors`]: `gauss` Gauss–Legendre points per axis (1 to 5) on each of the
/// `subcells^d` equal boxes of a reference element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Quadrature {
    /// Gauss points per axis.
    pub gauss: usize,
    /// Subcells per axis of each reference element.
    pub subcells: usize,
}

impl Quadrature {
    /// The default rule: 3 points per axis, no subcell (exact for the nested Q1 case,
    /// which needs 2).
    pub const DEFAULT: Quadrature = Quadrature {
        gauss: 3,
        subcells: 1,
    };
}

/// The Gauss–Legendre points and weights on `[−1, 1]` of `n` points (1 to 5).
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    match n {
        1 => (vec![0.0], vec![2.0]),
        2 => {
            let g = 1.0 / 3f64.sqrt();
            (vec![-g, g], vec![1.0, 1.0])
        }
        3 => {
            let g = (3.0f64 / 5.0).sqrt();
            (vec![-g, 0.0, g], vec![5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0])
        }
        4 => {
            let a = (3.0 / 7.0 - 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
            let b = (3.0 / 7.0 + 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
            let wa = (18.0 + 30f64.sqrt()) / 36.0;
            let wb = (18.0 - 30f64.sqrt()) / 36.0;
            (vec![-b, -a, a, b], vec![wb, wa, wa, wb])
        }
        5 => {
            let a = 1.0 / 3.0 * (5.0 - 2.0 * (10.0f64 / 7.0).sqrt()).sqrt();
            let b = 1.0 / 3.0 * (5.0 + 2.0 * (10.0f64 / 7.0).sqrt()).sqrt();
            let wa = (322.0 + 13.0 * 70f64.sqrt()) / 900.0;
            let wb = (322.0 - 13.0 * 70f64.sqrt()) / 900.0;
            (vec![-b, -a, 0.0, a, b], vec![wb, wa, 128.0 / 225.0, wa, wb])
        }
        _ => panic!("Gauss–Legendre rules of 1 to 5 points, not {n}"),
    }
}

/// The integrals of one error `e = u_h − u_ref`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PairErrors {
    /// `∫ |e|²`.
    pub l2_squared: f64,
    /// `∫ |∇e|²`.
    pub h1_seminorm_squared: f64,
    /// `‖e‖²_H = ρ ∫ |e|²`.
    pub h_squared: f64,
    /// `a(e, e)`.
    pub energy_squared: f64,
}

impl PairErrors {
    /// `‖e‖_H`.
    pub fn h(&self) -> f64 {
        self.h_squared.sqrt()
    }

    /// `‖e‖_V = (‖e‖²_H + a(e, e))^½`.
    pub fn v(&self) -> f64 {
        (self.h_squared + self.energy_squared).sqrt()
    }

    /// The integrand at one point of weight `w`: the errors of `external − reference`.
    pub(super) fn add(
        &mut self,
        w: f64,
        external: &Evaluation,
        reference: &Evaluation,
        d: usize,
        m: &Elasticity,
    ) {
        let mut e = [0.0; 3];
        let mut g = [[0.0; 3]; 3];
        for c in 0..d {
            e[c] = external.value[c] - reference.value[c];
            for j in 0..d {
                g[c][j] = external.gradient[c][j] - reference.gradient[c][j];
            }
        }
        let squared: f64 = e[..d].iter().map(|x| x * x).sum();
        let mut gradient = 0.0;
        let mut strain = 0.0;
        let mut trace = 0.0;
        for c in 0..d {
            trace += g[c][c];
            for j in 0..d {
                gradient += g[c][j] * g[c][j];
                let eps = 0.5 * (g[c][j] + g[j][c]);
                strain += eps * eps;
            }
        }
        self.l2_squared += w * squared;
        self.h1_seminorm_squared += w * gradient;
        self.h_squared += w * m.density * squared;
        self.energy_squared += w * (m.lame_lambda * trace * trace + 2.0 * m.lame_mu * strain);
    }
}

/// The errors of `u_h` (`external_values`, `d` per point of `external`) against `u_ref`
/// (`reference_values`, `d` per node of `reference`) by `quadrature` on the reference's elements
/// (the module's rule); `Err` names a quadrature point no external cell holds.
pub fn pair_errors(
    external: &ElementMesh,
    external_values: &[f64],
    reference: &BoxMesh,
    reference_values: &[f64],
    elasticity: &Elasticity,
    quadrature: Quadrature,
) -> Result<PairErrors, String> {
    let [errors] = pair_errors_each(
        external,
        external_values,
        (reference, [reference_values]),
        elasticity,
        quadrature,
    )?;
    Ok(errors)
}

/// [`pair_errors`] of one `u_h` against each of `N` fields on the same reference mesh
/// (`references`: the mesh and the fields), each quadrature point located in the external mesh
/// once for all of them.
pub fn pair_errors_each<const N: usize>(
    external: &ElementMesh,
    external_values: &[f64],
    (reference, fields): (&BoxMesh, [&[f64]; N]),
    elasticity: &Elasticity,
    quadrature: Quadrature,
) -> Result<[PairErrors; N], String> {
    let d = reference.dim();
    let fine = ElementMesh::of_box(reference);
    let (points, weights) = gauss_legendre(quadrature.gauss);
    let s = quadrature.subcells.max(1);
    let q = points.len();
    let mut errors = [PairErrors::default(); N];
    for e in 0..reference.n_elements() {
        let nodes = reference.element(e);
        let (lo, hi) = (
            reference.node(nodes[0]),
            reference.node(nodes[nodes.len() - 2]),
        );
        let tensor = |n: usize| (0..d).map(|_| n).product::<usize>();
        for sub in 0..tensor(s) {
            for point in 0..tensor(q) {
                let (mut x, mut xi, mut w) = ([0.0; 3], [0.0; 3], 1.0);
                let (mut sub_at, mut point_at) = (sub, point);
                for c in 0..d {
                    let (k, p) = (sub_at % s, point_at % q);
                    sub_at /= s;
                    point_at /= q;
                    // The subcell's local coordinate on [−1, 1], then the element's.
                    let local = -1.0 + (2.0 * k as f64 + 1.0 + points[p]) / s as f64;
                    xi[c] = local;
                    x[c] = lo[c] + 0.5 * (local + 1.0) * (hi[c] - lo[c]);
                    w *= weights[p] * 0.5 * (hi[c] - lo[c]) / s as f64;
                }
                let at_external = external.evaluate(external_values, x).ok_or_else(|| {
                    format!(
                        "the quadrature point {x:?} of the reference's element {e} is in no cell"
                    )
                })?;
                for (error, field) in errors.iter_mut().zip(fields) {
                    let at_reference = fine.evaluate_in(e, xi, field);
                    error.add(w, &at_external, &at_reference, d, elasticity);
                }
            }
        }
    }
    Ok(errors)
}

/// How far a mesh's bounding box, total measure and contact face may be from the scene's box,
/// relative to the box's largest length (its measure, for the measures).
pub const DOMAIN_TOLERANCE: f64 = 1e-9;

/// Checks that `mesh` covers the box `[0, L₁] × … × [0, L_d]` (`lengths`) to `relative` (at
/// least [`DOMAIN_TOLERANCE`]; a `Float32` file's points need more): its bounding box is the
/// box, no cell is degenerate, the cells' measures add up to the box's (a hole or an overlap
/// changes it), and the cells' facets on the contact face `x_d = 0` cover it. `Err` names what
/// is off and by how much.
pub fn check_domain(mesh: &ElementMesh, lengths: &[f64], relative: f64) -> Result<(), String> {
    let d = mesh.dim();
    let relative = relative.max(DOMAIN_TOLERANCE);
    let scale = lengths.iter().fold(0.0f64, |a, &b| a.max(b));
    let tolerance = relative * scale;
    for c in 0..d {
        let xs = mesh.points().iter().map(|p| p[c]);
        let lo = xs.clone().fold(f64::INFINITY, f64::min);
        let hi = xs.fold(f64::NEG_INFINITY, f64::max);
        if lo.abs() > tolerance || (hi - lengths[c]).abs() > tolerance {
            return Err(format!(
                "the points span [{lo}, {hi}] along x{}, where the box spans [0, {}] (within \
                 {tolerance:e})",
                c + 1,
                lengths[c]
            ));
        }
    }
    let volume: f64 = lengths[..d].iter().product();
    let mut total = 0.0;
    for k in 0..mesh.cells().len() {
        let m = mesh.measure(k).abs();
        if m <= relative * volume / mesh.cells().len() as f64 {
            return Err(format!("cell {k} is degenerate (measure {m:e})"));
        }
        total += m;
    }
    if (total - volume).abs() > relative * volume {
        return Err(format!(
            "the cells' measures add up to {total}, where the box's is {volume} (within a \
             relative {relative:e}): the cells leave a hole or overlap"
        ));
    }
    let face: f64 = lengths[..d - 1].iter().product();
    let on_contact = ContactFace::of(mesh, tolerance).measure();
    if (on_contact - face).abs() > relative * face.max(f64::MIN_POSITIVE) {
        return Err(format!(
            "the cells' facets on the contact face x{d} = 0 measure {on_contact}, where the \
             face's is {face} (within a relative {relative:e})"
        ));
    }
    Ok(())
}
