//! The twisted tridiagonal factorisation (`TwistedTridiagonal`, the 1D step solver) against the
//! Thomas algorithm it replaced, and its refusal of a matrix that is not positive definite.

use signorini::engine::fem::SymmetricMatrix;
use signorini::engine::linalg::{TridiagonalLdlt, TwistedTridiagonal};

/// A random symmetric positive definite tridiagonal matrix of size `n` (diagonally dominant)
/// as its diagonal and off-diagonal.
fn random_spd(rng: &mut fastrand::Rng, n: usize) -> (Vec<f64>, Vec<f64>) {
    let off: Vec<f64> = (0..n.saturating_sub(1)).map(|_| rng.f64() - 0.5).collect();
    let diag = (0..n)
        .map(|i| {
            let left = if i > 0 { off[i - 1].abs() } else { 0.0 };
            let right = off.get(i).map_or(0.0, |c| c.abs());
            left + right + 0.01 + rng.f64()
        })
        .collect();
    (diag, off)
}

/// The matrix of `diag` and `off` as the harness stores it, for its product.
fn assembled(diag: &[f64], off: &[f64]) -> SymmetricMatrix {
    let n = diag.len();
    let entries = diag.iter().enumerate().map(|(i, &d)| (i * n + i, d));
    let upper = off.iter().enumerate().map(|(i, &c)| ((i + 1) * n + i, c));
    SymmetricMatrix::from_upper_contributions(n, entries.chain(upper).collect())
}

/// Every size from 0 to 12 (the middle row at each parity, either half empty) and two of the
/// 1D step's: the residual is round-off and the solution is the Thomas algorithm's to round-off.
#[test]
fn twisted_solves_agree_with_the_thomas_algorithm_to_round_off() {
    let mut rng = fastrand::Rng::with_seed(5);
    for n in (0..=12).chain([640, 641]) {
        let (diag, off) = random_spd(&mut rng, n);
        let twisted = TwistedTridiagonal::factor(&diag, &off).unwrap();
        let thomas = TridiagonalLdlt::factor(&diag, &off).unwrap();
        let b: Vec<f64> = (0..n).map(|_| rng.f64() - 0.5).collect();
        let (mut x, mut reference) = (b.clone(), b.clone());
        twisted.solve_in_place(&mut x);
        thomas.solve_in_place(&mut reference);
        let scale = reference.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (i, (a, r)) in x.iter().zip(&reference).enumerate() {
            assert!(
                (a - r).abs() <= 1e-12 * scale,
                "n = {n}, row {i}: {a} against {r}"
            );
        }
        let mut ax = vec![0.0; n];
        assembled(&diag, &off).mul_into(&x, &mut ax);
        for (i, (lhs, rhs)) in ax.iter().zip(&b).enumerate() {
            assert!(
                (lhs - rhs).abs() <= 1e-14 * (1.0 + scale * 4.0),
                "n = {n}, residual at {i}"
            );
        }
    }
}

/// A matrix with a non-positive Schur complement is refused, naming a row, from either end.
#[test]
fn an_indefinite_matrix_is_refused_with_its_row() {
    // Pivots from the top: 1, 1 − 4 < 0 at row 1 (the top half of a size-4 matrix).
    assert_eq!(
        TwistedTridiagonal::factor(&[1.0, 1.0, 1.0, 1.0], &[2.0, 0.0, 0.0]).err(),
        Some(1)
    );
    // Pivots from the bottom: row 3 is 1, row 2 is 1 − 4 < 0.
    assert_eq!(
        TwistedTridiagonal::factor(&[1.0, 1.0, 1.0, 1.0], &[0.0, 0.0, 2.0]).err(),
        Some(2)
    );
    // Both halves positive, the middle row not: 1 − 0.81 − 0.81 < 0 at row 2 of 5.
    assert_eq!(
        TwistedTridiagonal::factor(&[1.0; 5], &[0.0, 0.9, 0.9, 0.0]).err(),
        Some(2)
    );
    assert_eq!(TwistedTridiagonal::factor(&[-1.0], &[]).err(), Some(0));
}
