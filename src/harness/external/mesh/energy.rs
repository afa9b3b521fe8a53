//! The discrete energy of a field pair on another code's mesh, the 2D/3D note's eq. (6) on the
//! file's own cells ([`cell_energy`]):
//! ```text
//! E_h(u, v) = ½ ∫_{Ω_M} ρ |v|² + ½ a(u, u),   a(u, u) = ∫_Ω λ (tr ε(u))² + 2μ ε(u):ε(u),
//! ```
//! `Ω_M` every cell for the standard mass, the cells without a vertex on the contact face
//! `x_d = 0` for the redistributed one (the note's `M^mod` on the scene's mesh, applied to the
//! file's cells). Each cell is integrated by a rule exact for its mass term: the three edge
//! midpoints of a triangle, the four-point degree-2 rule of a tetrahedron, 2 Gauss points per
//! axis on a Q1 cell (exact for a parallelogram's or a parallelepiped's mass and stiffness, the
//! scene's own assembly on its elements).

use super::function::{ElementMesh, Evaluation};
use super::pair::PairErrors;
use crate::engine::fem::box_mesh::Elasticity;
use crate::engine::fem::mass::MassVariant;

/// The cells a mass integrates over on another code's mesh: the two masses the note defines
/// on any mesh (the others, lumped or extended from the contact nodes' neighbours, are defined
/// through the scene's structured nodes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MassCells {
    /// Every cell: the standard (consistent) mass.
    All,
    /// The cells without a vertex on the contact face: the redistributed mass `M^mod`.
    OffContactFace,
}

impl MassCells {
    /// The cells of `mass`, `None` for a mass not defined on a foreign mesh.
    pub fn of(mass: MassVariant) -> Option<Self> {
        match mass {
            MassVariant::Standard => Some(Self::All),
            MassVariant::Redistributed => Some(Self::OffContactFace),
            _ => None,
        }
    }
}

/// The points (local coordinates, [`ElementMesh::evaluate_in`]'s) and weights (fractions of the
/// cell's measure) of the rule of a simplex of dimension `d`.
fn simplex_rule(d: usize) -> Vec<([f64; 3], f64)> {
    if d == 2 {
        let third = 1.0 / 3.0;
        return vec![
            ([0.5, 0.0, 0.0], third),
            ([0.5, 0.5, 0.0], third),
            ([0.0, 0.5, 0.0], third),
        ];
    }
    let (a, b) = (0.585_410_196_624_968_5, 0.138_196_601_125_010_5);
    vec![
        ([b, b, b], 0.25),
        ([a, b, b], 0.25),
        ([b, a, b], 0.25),
        ([b, b, a], 0.25),
    ]
}

/// `E_h(u, v)` of the module on `mesh`: `u` and `v` `d` values per point, the mass over the
/// cells `mass`; `tolerance` how far from `x_d = 0` a vertex is on the contact face.
pub fn cell_energy(
    mesh: &ElementMesh,
    (u, v): (&[f64], &[f64]),
    elasticity: &Elasticity,
    mass: MassCells,
    tolerance: f64,
) -> f64 {
    let d = mesh.dim();
    let zero = Evaluation {
        value: [0.0; 3],
        gradient: [[0.0; 3]; 3],
    };
    let simplex = simplex_rule(d);
    // The 2^d Gauss points (±1/√3 per axis) of a Q1 cell, the first axis the fastest.
    let g = 1.0 / 3f64.sqrt();
    let gauss: Vec<[f64; 3]> = (0..1usize << d)
        .map(|s| {
            let mut xi = [0.0; 3];
            for (c, x) in xi.iter_mut().enumerate().take(d) {
                *x = if s >> c & 1 == 1 { g } else { -g };
            }
            xi
        })
        .collect();
    let mut kinetic = PairErrors::default();
    let mut strain = PairErrors::default();
    for (k, cell) in mesh.cells().iter().enumerate() {
        let in_mass = match mass {
            MassCells::All => true,
            MassCells::OffContactFace => cell
                .vertices
                .iter()
                .all(|&p| mesh.points()[p][d - 1].abs() > tolerance),
        };
        let mut add = |xi: [f64; 3], w: f64| {
            strain.add(w, &mesh.evaluate_in(k, xi, u), &zero, d, elasticity);
            if in_mass {
                kinetic.add(w, &mesh.evaluate_in(k, xi, v), &zero, d, elasticity);
            }
        };
        if cell.kind.is_simplex() {
            let measure = mesh.measure(k).abs();
            simplex.iter().for_each(|&(xi, w)| add(xi, w * measure));
        } else {
            gauss
                .iter()
                .for_each(|&xi| add(xi, mesh.volume_element(k, xi)));
        }
    }
    0.5 * kinetic.h_squared + 0.5 * strain.energy_squared
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::fem::box_mesh::BoxMesh;
    use crate::harness::external::mesh::face::tests::split_box;

    /// On a Q1 mesh of the bars and on the same boxes cut into triangles or Kuhn tetrahedra
    /// (5 cells along the axis, so every rule is exact), a uniform velocity and a uniform axial
    /// strain `ε_dd = c` give `½ ρ |v|² |Ω_M| + ½ (λ + 2μ) c² |Ω|`, `Ω_M` without the first layer
    /// of cells for the redistributed mass.
    #[test]
    fn a_uniform_state_has_its_closed_form_energy() {
        let meshes = [vec![0.1, 1.0], vec![0.1, 0.2, 1.0]]
            .into_iter()
            .flat_map(|lengths| {
                let d = lengths.len();
                let counts: Vec<usize> = (0..d).map(|c| if c + 1 == d { 5 } else { 2 }).collect();
                let boxed = BoxMesh::new(&lengths, &counts).unwrap();
                let split = split_box(&lengths, 5);
                [
                    (lengths.clone(), ElementMesh::of_box(&boxed)),
                    (lengths, split),
                ]
            });
        for (lengths, mesh) in meshes {
            let d = lengths.len();
            let n_axis = 5;
            let (speed, c) = (0.5, 0.01);
            let mut u = vec![0.0; mesh.points().len() * d];
            let mut v = vec![0.0; mesh.points().len() * d];
            for (i, p) in mesh.points().iter().enumerate() {
                u[i * d + d - 1] = c * p[d - 1];
                v[i * d + d - 1] = -speed;
            }
            let m = Elasticity::NOTE;
            let volume: f64 = lengths.iter().product();
            let strain = 0.5 * (m.lame_lambda + 2.0 * m.lame_mu) * c * c * volume;
            for (mass, massive) in [
                (MassCells::All, volume),
                (
                    MassCells::OffContactFace,
                    volume * (1.0 - 1.0 / n_axis as f64),
                ),
            ] {
                let e = cell_energy(&mesh, (&u, &v), &m, mass, 1e-12);
                let expected = 0.5 * m.density * speed * speed * massive + strain;
                approx::assert_relative_eq!(e, expected, max_relative = 1e-13);
            }
        }
    }
}
