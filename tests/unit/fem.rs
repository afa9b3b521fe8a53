//! The P1 assembly of the 1D paper (§3.1–3.2): the consistent mass integrates the density, the
//! stiffness annihilates rigid motions and gives the boundary flux, the redistributed mass drops
//! exactly element 0 (and the model finds the massless dofs), all three are symmetric and
//! tridiagonal, and a bar with bad parameters is refused naming them.
//!
//! Every expected value is computed here independently of the library (by hand formulas, finite
//! differences or our own quadrature), never read back from the code under test.

use approx::assert_abs_diff_eq;
use signorini::engine::fem::{Bar1d, EndCondition, MassVariant, SparseAssembler, SymmetricMatrix};
use signorini::engine::model::Model;

const END_CONDITIONS: [EndCondition; 2] = [EndCondition::Clamped, EndCondition::Free];
const MESHES: [usize; 4] = [1, 2, 7, 64];

/// The matrix as a dense array, read entry by entry through [`SymmetricMatrix::get`].
fn dense(a: &SymmetricMatrix) -> Vec<Vec<f64>> {
    let n = a.dim();
    (0..n)
        .map(|i| (0..n).map(|j| a.get(i, j)).collect())
        .collect()
}

/// `A x` from the dense entries.
fn dense_mul(a: &[Vec<f64>], x: &[f64]) -> Vec<f64> {
    a.iter()
        .map(|row| row.iter().zip(x).map(|(aij, xj)| aij * xj).sum())
        .collect()
}

/// The row sums `(M·1)_i` of the consistent P1 mass matrix by hand: every element `e ∋ i`
/// contributes `ρh/6 · (2 + [the other node of e is a kept dof])` (§3.1, `φ_i` hat functions,
/// `∫ φ_i² = h/3`, `∫ φ_i φ_j = h/6` per element).
fn hand_mass_row_sums(nx: usize, n_dofs: usize, rho: f64, h: f64) -> Vec<f64> {
    (0..n_dofs)
        .map(|i| {
            let mut sum = 0.0;
            // Element i − 1 (nodes i − 1, i) and element i (nodes i, i + 1), when they exist.
            if i >= 1 {
                sum += rho * h / 6.0 * 3.0; // node i − 1 is always a kept dof
            }
            if i < nx {
                let other_kept = i + 1 < n_dofs;
                sum += rho * h / 6.0 * if other_kept { 3.0 } else { 2.0 };
            }
            sum
        })
        .collect()
}

/// §3.1: the consistent mass matrix `M_ij = ∫_0^L ρ φ_i φ_j` integrates the density: its entries
/// sum to `ρL` for the free bar (`V_h^Neu`, `Σ φ_i = 1`), and for the clamped bar (`V_h^Dir`,
/// node `m` eliminated) every row sum matches the hand computation, total `ρ(L − 2h/3)`.
#[test]
fn standard_mass_integrates_the_density() {
    for length in [1.0, 2.5] {
        for rho in [1.0, 3.0] {
            for nx in MESHES {
                for end in END_CONDITIONS {
                    let bar = Bar1d::new(length, nx, rho, 1.0, end).unwrap();
                    let h = length / nx as f64;
                    let m = bar.mass(MassVariant::Standard);
                    let n = bar.n_dofs();
                    assert_eq!(m.dim(), n);
                    assert_eq!(
                        n,
                        match end {
                            EndCondition::Clamped => nx,
                            EndCondition::Free => nx + 1,
                        }
                    );
                    let expected_total = match end {
                        EndCondition::Free => rho * length,
                        EndCondition::Clamped => rho * (length - 2.0 * h / 3.0),
                    };
                    let entries = dense(&m);
                    let total: f64 = entries.iter().flatten().sum();
                    assert_abs_diff_eq!(total, expected_total, epsilon = 1e-12 * length * rho);
                    assert_abs_diff_eq!(
                        m.sum_of_entries(),
                        expected_total,
                        epsilon = 1e-12 * length * rho
                    );

                    let ones = vec![1.0; n];
                    let hand = hand_mass_row_sums(nx, n, rho, h);
                    let from_entries = dense_mul(&entries, &ones);
                    let mut from_product = vec![f64::NAN; n];
                    m.mul_into(&ones, &mut from_product);
                    for i in 0..n {
                        assert_abs_diff_eq!(from_entries[i], hand[i], epsilon = 1e-14);
                        assert_abs_diff_eq!(from_product[i], hand[i], epsilon = 1e-14);
                    }
                    // The element matrix itself: ρh/3 on the diagonal of a boundary node, ρh/6
                    // off the diagonal.
                    assert_abs_diff_eq!(m.get(0, 0), rho * h / 3.0, epsilon = 1e-15);
                    if n > 1 {
                        assert_abs_diff_eq!(m.get(0, 1), rho * h / 6.0, epsilon = 1e-15);
                    }
                }
            }
        }
    }
}

/// §3.1: `S_ij = ∫ E φ_i' φ_j'`. With both ends free, constants are rigid motions: `S·1 = 0`;
/// the energy of `u = x` is `½ ∫ E u_x² = EL/2`, and `S x` is the boundary flux
/// `(−E, 0, …, 0, E)`. With the far end clamped `S` is positive definite: `1ᵀS1 = E/h`
/// (only the last element is strained).
#[test]
fn stiffness_annihilates_constants_on_the_free_bar() {
    for length in [1.0, 2.5] {
        for (rho, c) in [(1.0, 1.0), (2.0, 1.5)] {
            let young = rho * c * c;
            for nx in MESHES {
                let h = length / nx as f64;
                let free = Bar1d::new(length, nx, rho, c, EndCondition::Free).unwrap();
                let s = free.stiffness();
                let n = free.n_dofs();
                let ones = vec![1.0; n];
                let mut s1 = vec![f64::NAN; n];
                s.mul_into(&ones, &mut s1);
                let dense_s1 = dense_mul(&dense(&s), &ones);
                for i in 0..n {
                    assert!(s1[i].abs() <= 1e-12, "nx={nx}: (S·1)_{i} = {}", s1[i]);
                    assert!(dense_s1[i].abs() <= 1e-12, "nx={nx}: dense (S·1)_{i}");
                }
                let x = free.interpolate(|x| x);
                let mut sx = vec![f64::NAN; n];
                s.mul_into(&x, &mut sx);
                for (i, v) in sx.iter().enumerate() {
                    let expected = if i == 0 {
                        -young
                    } else if i == nx {
                        young
                    } else {
                        0.0
                    };
                    assert_abs_diff_eq!(*v, expected, epsilon = 1e-11 * young);
                }
                assert_abs_diff_eq!(
                    s.quadratic_form(&x),
                    young * length,
                    epsilon = 1e-11 * young * length
                );

                let clamped = Bar1d::new(length, nx, rho, c, EndCondition::Clamped).unwrap();
                let sc = clamped.stiffness();
                assert_abs_diff_eq!(
                    sc.quadratic_form(&vec![1.0; nx]),
                    young / h,
                    epsilon = 1e-12 * young / h
                );
            }
        }
    }
}

/// §3.2: `M^mod_ij = ∫_h^L φ_i φ_j`, i.e. `M^mod = [[0, 0], [0, M̄]]` — a zero row and column
/// at the contact dof; `M̄` equals `M` except at `(1, 1)`, which lacks element 0's `ρh/3`.
/// The model detects the massless dofs from the zero rows.
#[test]
fn redistributed_mass_drops_exactly_element_zero() {
    for rho in [1.0, 3.0] {
        for nx in MESHES {
            for end in END_CONDITIONS {
                let bar = Bar1d::new(1.0, nx, rho, 1.0, end).unwrap();
                let h = bar.h();
                let n = bar.n_dofs();
                let standard = bar.mass(MassVariant::Standard);
                let modified = bar.mass(MassVariant::Redistributed);
                assert_eq!(modified.dim(), n);
                // Element 0's diagonal contribution as the element matrix ρh/6·[[2,1],[1,2]]
                // holds it (equal to ρh/3 up to one rounding).
                let element_diagonal = 2.0 * (rho * h / 6.0);
                assert_abs_diff_eq!(element_diagonal, rho * h / 3.0, epsilon = 1e-16);
                for i in 0..n {
                    for j in 0..n {
                        let got = modified.get(i, j);
                        let expected = if i == 0 || j == 0 {
                            0.0
                        } else if i == 1 && j == 1 {
                            standard.get(1, 1) - element_diagonal
                        } else {
                            standard.get(i, j)
                        };
                        assert_eq!(
                            got, expected,
                            "nx={nx} {end:?} ρ={rho}: M^mod({i},{j}) = {got}, expected {expected}"
                        );
                    }
                }
                if n > 1 && nx > 1 {
                    // Node 1 is interior: its remaining mass is element 1's ρh/3.
                    assert_abs_diff_eq!(modified.get(1, 1), rho * h / 3.0, epsilon = 1e-15);
                }
                // Element 0's entries on kept dofs: all four (ρh in total), or only (0, 0) when
                // node 1 is the eliminated clamped end.
                let removed = if n > 1 { rho * h } else { rho * h / 3.0 };
                assert_abs_diff_eq!(
                    modified.sum_of_entries(),
                    standard.sum_of_entries() - removed,
                    epsilon = 1e-12
                );

                let model = Model::bar1d(&bar, MassVariant::Redistributed, Some(0.0), None);
                // Nodes touched only by element 0 carry no mass: node 0 always, node 1 too when
                // the mesh is a single free element.
                let expected_massless: Vec<usize> = if nx == 1 && end == EndCondition::Free {
                    vec![0, 1]
                } else {
                    vec![0]
                };
                assert_eq!(model.massless_dofs(), expected_massless.as_slice());
                if nx > 1 {
                    assert_eq!(model.massless_dofs(), &[0]);
                    assert!(model.contact_is_massless());
                }
                let std_model = Model::bar1d(&bar, MassVariant::Standard, Some(0.0), None);
                assert!(std_model.massless_dofs().is_empty());
                assert!(!std_model.contact_is_massless());
            }
        }
    }
}

/// §3.1–3.2: `M`, `M^mod` and `S` are Gram matrices of the hat functions, hence symmetric (both
/// triangles are stored; they must agree exactly).
#[test]
fn mass_and_stiffness_are_symmetric() {
    for nx in MESHES {
        for end in END_CONDITIONS {
            let bar = Bar1d::new(1.3, nx, 2.0, 0.7, end).unwrap();
            for (what, a) in [
                ("M", bar.mass(MassVariant::Standard)),
                ("M^mod", bar.mass(MassVariant::Redistributed)),
                ("S", bar.stiffness()),
            ] {
                let n = a.dim();
                let mut nonzero = 0;
                for i in 0..n {
                    for j in 0..n {
                        let (aij, aji) = (a.get(i, j), a.get(j, i));
                        assert_eq!(aij, aji, "{what} nx={nx} {end:?} at ({i},{j})");
                        if aij != 0.0 {
                            nonzero += 1;
                        }
                        if i.abs_diff(j) > 1 {
                            assert_eq!(aij, 0.0, "{what}: P1 matrices are tridiagonal");
                        }
                    }
                }
                if what != "M^mod" || nx > 1 {
                    assert!(nonzero > 0, "{what} nx={nx} {end:?} is empty");
                }
            }
        }
    }
}

/// `weighted_form` (the energy balance's terms and their round-off scale) equals the dense
/// `xᵀAy`, `Σ r_i x_i²` and `Σ r_i y_i²` to round-off, on tridiagonal matrices of every size
/// around its four lanes (1 to 9 rows, and 64) and on a banded one that is not tridiagonal.
#[test]
fn weighted_forms_equal_their_dense_sums() {
    let vector = |n: usize, phase: f64| -> Vec<f64> {
        (0..n)
            .map(|i| (1.7 * i as f64 + phase).sin() + 0.1)
            .collect()
    };
    let mut matrices = Vec::new();
    for nx in (1..=9).chain([64]) {
        let bar = Bar1d::new(1.3, nx, 2.0, 0.7, EndCondition::Free).unwrap();
        matrices.push(bar.mass(MassVariant::Standard));
        matrices.push(bar.stiffness());
    }
    let mut banded = SparseAssembler::new(11);
    for i in 0..11 {
        banded.add(i, i, 4.0 + i as f64);
        for (k, v) in [(1, -1.5), (3, 0.25)] {
            if i + k < 11 {
                banded.add(i, i + k, v);
                banded.add(i + k, i, v);
            }
        }
    }
    matrices.push(banded.finish());
    for a in &matrices {
        let n = a.dim();
        let (x, y) = (vector(n, 0.3), vector(n, -1.1));
        let r: Vec<f64> = (0..n).map(|i| 1.0 + i as f64 / 3.0).collect();
        let d = dense(a);
        let ay = dense_mul(&d, &y);
        let expected: f64 = x.iter().zip(&ay).map(|(a, b)| a * b).sum();
        let squares = |v: &[f64]| -> f64 { v.iter().zip(&r).map(|(v, r)| r * v * v).sum() };
        let scale: f64 = x.iter().zip(&ay).map(|(a, b)| (a * b).abs()).sum::<f64>() + 1.0;
        let form = a.weighted_form(&x, &y, &r);
        assert_abs_diff_eq!(form.value, expected, epsilon = 1e-14 * scale);
        assert_abs_diff_eq!(form.x_squares, squares(&x), epsilon = 1e-14 * squares(&x));
        assert_abs_diff_eq!(form.y_squares, squares(&y), epsilon = 1e-14 * squares(&y));
    }
}

/// §3.1: `h = L/m` needs `m ≥ 1` and `L > 0`; the density must be a positive number. Each
/// rejection names the offending parameter.
#[test]
fn bar_rejects_invalid_parameters_naming_them() {
    let cases: [(&str, f64, usize, f64, f64); 8] = [
        ("nx", 1.0, 0, 1.0, 1.0),
        ("length", 0.0, 4, 1.0, 1.0),
        ("length", -1.0, 4, 1.0, 1.0),
        ("length", f64::NAN, 4, 1.0, 1.0),
        ("density", 1.0, 4, f64::NAN, 1.0),
        ("density", 1.0, 4, -2.0, 1.0),
        ("density", 1.0, 4, 0.0, 1.0),
        ("wave_speed", 1.0, 4, 1.0, f64::INFINITY),
    ];
    for (name, length, nx, density, c) in cases {
        for end in END_CONDITIONS {
            let err = Bar1d::new(length, nx, density, c, end).expect_err(name);
            assert_eq!(err.name, name, "{length} {nx} {density} {c}");
            assert!(err.to_string().contains(name), "{err}");
        }
    }
    assert!(Bar1d::new(1.0, 1, 1.0, 1.0, EndCondition::Free).is_ok());
}
