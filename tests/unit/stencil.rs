//! The matrix-free storage of the box matrices (issue 19, item 1): on 2D and 3D boxes, every
//! mass variant with a stencil form and the stiffness equal the assembled matrices entry by
//! entry to round-off, with the same non-zero pattern, and every product agrees.

use signorini::engine::fem::{BoxMesh, Elasticity, MassVariant, SymmetricMatrix};

/// The largest `|a_ij − b_ij|` relative to `max |b_ij|` (rows matched by column), and
/// whether the non-zero patterns differ.
fn compare(a: &SymmetricMatrix, b: &SymmetricMatrix) -> (f64, bool) {
    assert_eq!(a.dim(), b.dim());
    let row = |m: &SymmetricMatrix, i: usize| {
        let mut entries = std::collections::BTreeMap::new();
        m.for_each_in_row(i, |j, v| {
            if v != 0.0 {
                entries.insert(j, v);
            }
        });
        entries
    };
    let mut scale = 0.0_f64;
    let mut worst = 0.0_f64;
    let mut pattern_differs = false;
    for i in 0..b.dim() {
        let (row_a, row_b) = (row(a, i), row(b, i));
        pattern_differs |= row_a.keys().ne(row_b.keys());
        for (j, vb) in &row_b {
            scale = scale.max(vb.abs());
            worst = worst.max((row_a.get(j).unwrap_or(&0.0) - vb).abs());
        }
        for (j, va) in &row_a {
            worst = worst.max((va - row_b.get(j).unwrap_or(&0.0)).abs());
        }
    }
    (
        if scale > 0.0 { worst / scale } else { worst },
        pattern_differs,
    )
}

fn meshes() -> Vec<BoxMesh> {
    vec![
        BoxMesh::new(&[0.3, 1.0], &[3, 7]).unwrap(),
        BoxMesh::new(&[0.1, 1.0], &[1, 2]).unwrap(),
        BoxMesh::new(&[0.2, 0.3, 1.0], &[2, 3, 5]).unwrap(),
        BoxMesh::new(&[0.1, 0.1, 1.0], &[1, 1, 1]).unwrap(),
    ]
}

#[test]
fn stencils_equal_the_assembled_matrices() {
    let e = Elasticity::NOTE;
    for mesh in meshes() {
        let variants = [
            MassVariant::Standard,
            MassVariant::Redistributed,
            MassVariant::Lumped,
        ];
        for variant in variants {
            let stencil = mesh.mass_stencil(variant, 2.5).unwrap();
            assert!(stencil.is_stencil());
            let (worst, differs) = compare(&stencil, &mesh.mass(variant, 2.5));
            assert!(!differs, "{variant:?} on {:?}: pattern", mesh.counts());
            assert!(
                worst <= 1e-14,
                "{variant:?} on {:?}: {worst:e}",
                mesh.counts()
            );
        }
        // Some stiffness entries are sums that cancel: zero in one order, round-off in the other.
        let (worst, _) = compare(&mesh.stiffness_stencil(&e), &mesh.stiffness(&e));
        assert!(
            worst <= 1e-14,
            "stiffness on {:?}: {worst:e}",
            mesh.counts()
        );
    }
}

#[test]
fn stencil_products_agree_with_the_assembled_ones() {
    let e = Elasticity::NOTE;
    let mut rng = fastrand::Rng::with_seed(7);
    for mesh in meshes() {
        let assembled = mesh
            .mass(MassVariant::Redistributed, 1.0)
            .linear_combination(64.0, &mesh.stiffness(&e), 1.0);
        let stencil = mesh
            .mass_stencil(MassVariant::Redistributed, 1.0)
            .unwrap()
            .linear_combination(64.0, &mesh.stiffness_stencil(&e), 1.0);
        assert!(stencil.is_stencil(), "two stencils combine into one");
        // Entries where `64 m_ij` and `s_ij` cancel are round-off in one and zero in the
        // other: the values are compared, not the patterns.
        let (worst, _) = compare(&stencil, &assembled);
        assert!(worst <= 1e-14, "{:?}: {worst:e}", mesh.counts());
        let n = mesh.n_dofs();
        let x: Vec<f64> = (0..n).map(|_| rng.f64() - 0.5).collect();
        let y: Vec<f64> = (0..n).map(|_| rng.f64() - 0.5).collect();
        let (mut ax, mut sx) = (vec![0.0; n], vec![0.0; n]);
        let dot_a = assembled.mul_dot(&x, &mut ax);
        let dot_s = stencil.mul_dot(&x, &mut sx);
        let scale = ax.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (p, q) in sx.iter().zip(&ax) {
            assert!((p - q).abs() <= 1e-13 * scale);
        }
        assert!((dot_a - dot_s).abs() <= 1e-13 * dot_a.abs());
        let (bs, ba) = (
            stencil.bilinear_form(&x, &y),
            assembled.bilinear_form(&x, &y),
        );
        assert!((bs - ba).abs() <= 1e-12 * scale * n as f64, "{bs} vs {ba}");
        assert_eq!(
            stencil.to_faer().compute_nnz(),
            stencil.to_faer().val().len()
        );
        let sub: Vec<usize> = (0..n).step_by(3).collect();
        let (worst, _) = compare(
            &stencil.principal_submatrix(&sub),
            &assembled.principal_submatrix(&sub),
        );
        assert!(worst <= 1e-14, "principal submatrix: {worst:e}");
    }
}

#[test]
fn the_extended_masses_have_no_stencil() {
    let mesh = BoxMesh::new(&[0.1, 1.0], &[2, 4]).unwrap();
    assert!(mesh
        .mass_stencil(MassVariant::RedistributedConserving, 1.0)
        .is_none());
    assert!(mesh
        .mass_stencil(MassVariant::SingularDynamic, 1.0)
        .is_none());
}

/// The interleaved sweeps do the column-by-column solve's operations in its order, so they give
/// its bits: for rows of one entry per system (the first axis, [`solve_interleaved_rows`]'s line
/// path), of two, and of nine (a chunk of twelve and a remainder).
#[test]
fn interleaved_tridiagonal_solves_equal_column_by_column_solves() {
    use signorini::engine::linalg::{solve_interleaved_rows, TridiagonalLdlt};
    let n = 7;
    let factors: Vec<TridiagonalLdlt> = (0..3)
        .map(|c| {
            let diag = vec![4.0 + c as f64; n];
            let off = vec![-1.0 - 0.5 * c as f64; n - 1];
            TridiagonalLdlt::factor(&diag, &off).unwrap()
        })
        .collect();
    let mut rng = fastrand::Rng::with_seed(3);
    for width in [3, 6, 27] {
        let b: Vec<f64> = (0..n * width).map(|_| rng.f64() - 0.5).collect();
        let mut rows = b.clone();
        solve_interleaved_rows(&factors, &mut rows, width);
        for j in 0..width {
            let mut column: Vec<f64> = (0..n).map(|i| b[i * width + j]).collect();
            factors[j % 3].solve_in_place(&mut column);
            for i in 0..n {
                assert_eq!(
                    rows[i * width + j].to_bits(),
                    column[i].to_bits(),
                    "width {width}: ({i}, {j})"
                );
            }
        }
    }
}

/// The product preconditioner of a matrix-free step matrix (the separable part it carries)
/// against Jacobi on the same matrix assembled: the same solution, in fewer iterations.
#[test]
fn the_product_preconditioner_beats_jacobi_on_box_step_matrices() {
    use signorini::engine::linalg::{Pcg, PcgWork, DEFAULT_TOLERANCE};
    let e = Elasticity::NOTE;
    let mut rng = fastrand::Rng::with_seed(11);
    for (lengths, counts) in [
        (vec![0.1, 1.0], vec![4, 40]),
        (vec![0.1, 0.1, 1.0], vec![2, 2, 20]),
    ] {
        let mesh = BoxMesh::new(&lengths, &counts).unwrap();
        let h = 1.0 / counts[counts.len() - 1] as f64;
        for (variant, b) in [
            (MassVariant::Standard, 0.25),
            (MassVariant::Redistributed, 0.5),
        ] {
            let alpha = 1.0 / (b * (h / 2.0) * (h / 2.0));
            let stencil = mesh.mass_stencil(variant, 1.0).unwrap().linear_combination(
                alpha,
                &mesh.stiffness_stencil(&e),
                1.0,
            );
            assert!(stencil.separable_part().is_some());
            let assembled = SymmetricMatrix::from_faer(stencil.to_faer().into_owned());
            let n = mesh.n_dofs();
            let rhs: Vec<f64> = (0..n).map(|_| rng.f64() - 0.5).collect();
            let mut work = PcgWork::new(n);
            let solve = |a: SymmetricMatrix, work: &mut PcgWork| {
                let mut x = vec![0.0; n];
                let pcg = Pcg::new(a, DEFAULT_TOLERANCE, "step").unwrap();
                let iterations = pcg.solve(&rhs, &mut x, work).unwrap();
                (x, iterations)
            };
            let (x_product, product) = solve(stencil, &mut work);
            let (x_jacobi, jacobi) = solve(assembled, &mut work);
            let scale = x_jacobi.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            for (p, q) in x_product.iter().zip(&x_jacobi) {
                assert!((p - q).abs() <= 1e-11 * scale);
            }
            assert!(
                product < jacobi,
                "{variant:?} on {counts:?}: {product} iterations, Jacobi {jacobi}"
            );
        }
    }
}

/// The step matrix `αM + S` of a box, matrix-free, with `α = 1/(bΔt²)` at `Δx/Δt = 2`.
fn step_stencil(mesh: &BoxMesh, variant: MassVariant, b: f64) -> SymmetricMatrix {
    let h = 1.0 / mesh.counts()[mesh.dim() - 1] as f64;
    let alpha = 1.0 / (b * (h / 2.0) * (h / 2.0));
    mesh.mass_stencil(variant, 1.0).unwrap().linear_combination(
        alpha,
        &mesh.stiffness_stencil(&Elasticity::NOTE),
        1.0,
    )
}

/// The condensed-plane preconditioner `P = L diag(A, Ŝ) Lᵀ` of an `M^mod` step matrix keeps
/// `L` and `A` exact: `P⁻¹ K e = e` for every `e` supported on the massless plane, and `P⁻¹`
/// is symmetric.
#[test]
fn the_condensed_plane_preconditioner_is_exact_on_the_plane_and_symmetric() {
    use signorini::engine::linalg::CondensedPlane;
    let mut rng = fastrand::Rng::with_seed(5);
    for mesh in [
        BoxMesh::new(&[0.1, 1.0], &[4, 12]).unwrap(),
        BoxMesh::new(&[0.1, 0.1, 1.0], &[2, 3, 10]).unwrap(),
    ] {
        let k = step_stencil(&mesh, MassVariant::Redistributed, 0.25);
        let p = CondensedPlane::of(&k, k.separable_part().unwrap()).unwrap();
        let n = mesh.n_dofs();
        let plane = n / mesh.counts()[mesh.dim() - 1];
        let mut e = vec![0.0; n];
        e[..plane].iter_mut().for_each(|v| *v = rng.f64() - 0.5);
        let mut ke = vec![0.0; n];
        k.mul_into(&e, &mut ke);
        let mut back = vec![0.0; n];
        p.solve_into(&ke, &mut back);
        for (got, want) in back.iter().zip(&e) {
            assert!((got - want).abs() <= 1e-12, "{got} against {want}");
        }
        let u: Vec<f64> = (0..n).map(|_| rng.f64() - 0.5).collect();
        let v: Vec<f64> = (0..n).map(|_| rng.f64() - 0.5).collect();
        let (mut pu, mut pv) = (vec![0.0; n], vec![0.0; n]);
        p.solve_into(&u, &mut pu);
        p.solve_into(&v, &mut pv);
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let (vpu, upv) = (dot(&v, &pu), dot(&u, &pv));
        assert!((vpu - upv).abs() <= 1e-12 * vpu.abs().max(upv.abs()));
        assert!(dot(&u, &pu) > 0.0);
    }
}

/// With the massless plane condensed, `M^mod`'s step matrices take at most 3 CG iterations
/// more than the standard mass's at two levels (measured from a zero guess: 13 and 14 against
/// 12 and 11 in 2D, 16 and 16 against 14 and 14 in 3D). The product preconditioner alone needed
/// twice as many, and more with each level: 19.5 and 25.8 per Crank–Nicolson step at 3D
/// levels 40 and 80, against 11.4 and 11.3 for the standard mass.
#[test]
fn the_massless_plane_costs_no_extra_cg_iterations() {
    use signorini::engine::linalg::{Pcg, PcgWork, DEFAULT_TOLERANCE};
    let mut rng = fastrand::Rng::with_seed(13);
    for (lengths, coarse, fine) in [
        (vec![0.1, 1.0], vec![4, 40], vec![8, 80]),
        (vec![0.1, 0.1, 1.0], vec![2, 2, 20], vec![4, 4, 40]),
    ] {
        for counts in [coarse, fine] {
            let mesh = BoxMesh::new(&lengths, &counts).unwrap();
            let n = mesh.n_dofs();
            let rhs: Vec<f64> = (0..n).map(|_| rng.f64() - 0.5).collect();
            let mut work = PcgWork::new(n);
            let iterations = |variant: MassVariant, work: &mut PcgWork| {
                let pcg = Pcg::new(
                    step_stencil(&mesh, variant, 0.25),
                    DEFAULT_TOLERANCE,
                    "step",
                );
                let mut x = vec![0.0; n];
                pcg.unwrap().solve(&rhs, &mut x, work).unwrap()
            };
            let standard = iterations(MassVariant::Standard, &mut work);
            let redistributed = iterations(MassVariant::Redistributed, &mut work);
            assert!(
                redistributed <= standard + 3,
                "{counts:?}: M^mod {redistributed} iterations, standard {standard}"
            );
        }
    }
}

/// A stencil cut after its first `m` node layers along the axis is the principal submatrix on
/// those nodes (the contact slab's matrix, solved by CG from the local operator): every entry,
/// both masses, 2D and 3D; the cut keeps a separable part for the preconditioner, and cuts
/// that would change the first two layers' blocks or keep everything are refused.
#[test]
fn a_stencil_cut_after_its_first_layers_is_the_principal_submatrix() {
    for mesh in [
        BoxMesh::new(&[0.3, 1.0], &[3, 7]).unwrap(),
        BoxMesh::new(&[0.2, 0.3, 1.0], &[2, 3, 6]).unwrap(),
    ] {
        let axial = mesh.counts()[mesh.dim() - 1];
        for variant in [MassVariant::Standard, MassVariant::Redistributed] {
            let k = step_stencil(&mesh, variant, 0.25);
            assert!(k.first_layers(2).is_none() && k.first_layers(axial).is_none());
            for m in 3..axial {
                let cut = k.first_layers(m).unwrap();
                assert!(cut.separable_part().is_some());
                let n = cut.dim();
                assert_eq!(n * axial, k.dim() * m, "{:?} m = {m}", mesh.counts());
                for i in 0..n {
                    for j in 0..n {
                        assert_eq!(
                            cut.get(i, j),
                            k.get(i, j),
                            "{:?} {variant:?} m = {m}: entry ({i}, {j})",
                            mesh.counts()
                        );
                    }
                }
            }
        }
    }
}

/// The principal submatrix of a stencil on all its dofs, or on those off the first layer
/// (`M^mod`'s dofs with mass, whose initial acceleration it solves), stays matrix-free and has
/// the stencil's entries; other index sets are assembled.
#[test]
fn a_stencil_off_its_first_layer_is_the_principal_submatrix() {
    for mesh in [
        BoxMesh::new(&[0.3, 1.0], &[3, 7]).unwrap(),
        BoxMesh::new(&[0.2, 0.3, 1.0], &[2, 3, 6]).unwrap(),
    ] {
        for variant in [MassVariant::Standard, MassVariant::Redistributed] {
            let mass = mesh.mass_stencil(variant, 1.0).unwrap();
            for k in [mass, step_stencil(&mesh, variant, 0.25)] {
                let n = k.dim();
                let first = n / mesh.counts()[mesh.dim() - 1];
                let all: Vec<usize> = (0..n).collect();
                assert!(k.principal_submatrix(&all).is_stencil());
                let off = k.principal_submatrix(&all[first..]);
                assert!(off.is_stencil(), "{:?} {variant:?}", mesh.counts());
                assert!(off.separable_part().is_some());
                assert_eq!(off.dim(), n - first);
                for i in 0..off.dim() {
                    for j in 0..off.dim() {
                        assert_eq!(
                            off.get(i, j),
                            k.get(first + i, first + j),
                            "{:?} {variant:?}: entry ({i}, {j})",
                            mesh.counts()
                        );
                    }
                }
                assert!(!k.principal_submatrix(&all[1..]).is_stencil());
            }
        }
    }
}
