//! The mass-matrix variants beyond the paper (issue 11): lumped, redistributed-conserving and
//! singular-dynamic. Total mass, moments, massless contact dofs, the 1D entries derived in
//! `fem::mass`, the cases that are refused, names, and the consistent start.

use crate::benchmarks;
use signorini::engine::schemes::{initial_state, residual_force, Conventions};

use signorini::engine::exact::{ExactSolution, SignoriniDirichlet};
use signorini::engine::fem::{Bar1d, BoxMesh, EndCondition, MassVariant, SymmetricMatrix};
use signorini::engine::model::Model;

const DENSITY: f64 = 2.5;
const EXTENDED: [MassVariant; 2] = [
    MassVariant::RedistributedConserving,
    MassVariant::SingularDynamic,
];

fn bar(nx: usize, far_end: EndCondition) -> Bar1d {
    Bar1d::new(1.0, nx, DENSITY, 1.0, far_end).unwrap()
}

/// `xᵀ M y`.
fn form(m: &SymmetricMatrix, x: &[f64], y: &[f64]) -> f64 {
    m.bilinear_form(x, y)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-13 * a.abs().max(b.abs()).max(1.0)
}

#[test]
fn lumped_is_the_diagonal_of_row_sums() {
    let b = bar(8, EndCondition::Free);
    let m = b.mass(MassVariant::Standard);
    let l = b.mass(MassVariant::Lumped);
    assert_eq!(l.bandwidth(), 0);
    let ones = vec![1.0; m.dim()];
    let mut sums = vec![0.0; m.dim()];
    m.mul_into(&ones, &mut sums);
    for (i, s) in sums.iter().enumerate() {
        assert!(close(l.get(i, i), *s), "row {i}: {} vs {s}", l.get(i, i));
    }
    let model = Model::bar1d(&b, MassVariant::Lumped, Some(0.0), None);
    assert!(model.massless_dofs().is_empty());
}

/// `1ᵀ M 1` of every variant but the paper's `M^mod` equals the standard one, on the free bar
/// (the whole body) and on the clamped bar (the dofs off the clamped node). The lumped matrix
/// sums each row over every node: on the clamped bar its node next to the clamped end keeps the
/// coupling `ρh/6` that the reduced consistent matrix drops.
#[test]
fn total_mass_is_kept_by_every_variant_but_the_papers() {
    for far_end in [EndCondition::Free, EndCondition::Clamped] {
        let b = bar(10, far_end);
        let standard = b.mass(MassVariant::Standard).sum_of_entries();
        let lumped = b.mass(MassVariant::Lumped).sum_of_entries();
        let coupling = match far_end {
            EndCondition::Free => 0.0,
            EndCondition::Clamped => DENSITY * b.h() / 6.0,
        };
        assert!(
            close(lumped, standard + coupling),
            "lumped {far_end:?}: {lumped} vs {standard}"
        );
        for mass in [
            MassVariant::RedistributedConserving,
            MassVariant::SingularDynamic,
        ] {
            let total = b.mass(mass).sum_of_entries();
            assert!(
                close(total, standard),
                "{mass} {far_end:?}: {total} vs {standard}"
            );
        }
        // The paper's M^mod removes element 0: ρh less.
        let removed = standard - b.mass(MassVariant::Redistributed).sum_of_entries();
        assert!(close(removed, DENSITY * b.h()), "{removed}");
    }
    let free = bar(10, EndCondition::Free);
    assert!(close(
        free.mass(MassVariant::Standard).sum_of_entries(),
        DENSITY
    ));
}

#[test]
fn extended_variants_make_the_contact_dof_massless() {
    for mass in EXTENDED {
        let b = bar(10, EndCondition::Clamped);
        let model = Model::bar1d(&b, mass, Some(0.0), None);
        assert_eq!(model.massless_dofs(), &[b.contact_dof()], "{mass}");
        assert!(model.contact_is_massless());
    }
}

/// The singular dynamic mass keeps the first and second moments; the conserving one moves the
/// contact node's lumped mass `ρh/2` by `h` (first moment `+ρh²/2`).
#[test]
fn moments_of_the_extended_variants() {
    let b = bar(10, EndCondition::Free);
    let h = b.h();
    let x = b.interpolate(|x| x);
    let ones = vec![1.0; x.len()];
    let m = b.mass(MassVariant::Standard);
    let sing = b.mass(MassVariant::SingularDynamic);
    assert!(close(form(&sing, &x, &ones), form(&m, &x, &ones)));
    assert!(close(form(&sing, &x, &x), form(&m, &x, &x)));
    let conserving = b.mass(MassVariant::RedistributedConserving);
    let shift = form(&conserving, &x, &ones) - form(&m, &x, &ones);
    assert!(close(shift, 0.5 * DENSITY * h * h), "{shift}");
}

/// The entries of `fem::mass`'s derivation (ρ = 1 there): only rows 1–2 change.
#[test]
fn singular_dynamic_entries_in_1d() {
    let b = bar(10, EndCondition::Clamped);
    let (h, rho) = (b.h(), DENSITY);
    let m = b.mass(MassVariant::Standard);
    let s = b.mass(MassVariant::SingularDynamic);
    assert!(close(s.get(1, 1), rho * 8.0 * h / 3.0));
    assert!(close(s.get(1, 2), -rho * 2.0 * h / 3.0));
    assert!(close(s.get(2, 2), rho * h));
    assert_eq!(s.get(0, 0), 0.0);
    assert_eq!(s.get(0, 1), 0.0);
    for i in 2..b.n_dofs() {
        for j in 3..b.n_dofs() {
            assert_eq!(s.get(i, j), m.get(i, j), "({i}, {j})");
        }
    }
    let c = b.mass(MassVariant::RedistributedConserving);
    assert!(close(c.get(1, 1), rho * 4.0 * h / 3.0));
    assert!(close(c.get(1, 2), m.get(1, 2)));
}

/// The massed block of every extended variant is positive definite: the consistent start
/// factorises it (it fails on an indefinite matrix).
#[test]
fn consistent_start_equilibrates_the_massless_contact_node() {
    for mass in EXTENDED {
        let b = bar(20, EndCondition::Clamped);
        let model = Model::bar1d(&b, mass, Some(0.0), None);
        let exact = SignoriniDirichlet;
        let u0 = b.interpolate(|x| exact.eval(x, 0.0).u);
        let v0 = b.interpolate(|x| exact.eval(x, 0.0).ut);
        let start = initial_state(&model, &u0, &v0, &Conventions::HARNESS).unwrap();
        let mut r = vec![0.0; u0.len()];
        residual_force(&model, &start.displacement, &mut r);
        // Row 0: S U + Bᵀλ = 0 (the multiplier enters as −λ e_0 on the right-hand side).
        let row0 = r[0] + start.multiplier[0];
        assert!(row0.abs() < 1e-12, "{mass}: static residual {row0:e}");
        let gap = start.displacement[0];
        assert!(gap >= -1e-14 && start.multiplier[0] <= 0.0);
        assert!((gap * start.multiplier[0]).abs() < 1e-14, "{mass}");
    }
}

#[test]
fn too_thin_meshes_are_refused_naming_mass() {
    let problem = benchmarks::dirichlet(3.0);
    for (mass, thinnest_ok) in [
        (MassVariant::RedistributedConserving, 2),
        (MassVariant::SingularDynamic, 3),
    ] {
        let err = problem.model(thinnest_ok - 1, mass).unwrap_err();
        assert_eq!(err.name, "mass", "{mass}");
        assert!(err.allowed.contains("Dirichlet"), "{}", err.allowed);
        assert!(problem.model(thinnest_ok, mass).is_ok(), "{mass}");
    }
    // A free far end has no fixed node to lose mass to, but the extrapolation needs node 2.
    let err = bar(1, EndCondition::Free)
        .check_mass(MassVariant::SingularDynamic)
        .unwrap_err();
    assert!(err.allowed.contains("two nodes above"), "{}", err.allowed);
    for mass in EXTENDED {
        assert!(bar(2, EndCondition::Free).check_mass(mass).is_ok());
        assert!(close(
            bar(2, EndCondition::Free).mass(mass).sum_of_entries(),
            DENSITY
        ));
    }
    assert!(bar(1, EndCondition::Free)
        .check_mass(MassVariant::RedistributedConserving)
        .is_ok());
    let thin = BoxMesh::note_2d(1, 2).unwrap();
    assert_eq!(
        thin.check_mass(MassVariant::SingularDynamic)
            .unwrap_err()
            .name,
        "mass"
    );
    assert!(thin
        .check_mass(MassVariant::RedistributedConserving)
        .is_ok());
}

/// In 2D and 3D: `1_cᵀ M 1_c` per component `c` kept, every component of a node of `Γ_Sig`
/// massless, and (singular dynamic) the first moment along the axis kept.
#[test]
fn box_variants_keep_the_mass_per_component() {
    for mesh in [
        BoxMesh::note_2d(2, 6).unwrap(),
        BoxMesh::note_3d(2, 2, 5).unwrap(),
    ] {
        let d = mesh.dim();
        let standard = mesh.mass(MassVariant::Standard, DENSITY);
        let component = |c: usize, f: &dyn Fn(&[f64]) -> f64| {
            mesh.interpolate(|x| {
                let mut v = [0.0; 3];
                v[c] = f(x);
                v
            })
        };
        for mass in [
            MassVariant::RedistributedConserving,
            MassVariant::SingularDynamic,
        ] {
            let m = mesh.mass(mass, DENSITY);
            for c in 0..d {
                let ones = component(c, &|_| 1.0);
                let axis = component(c, &|x| x[d - 1]);
                let (a, b) = (form(&m, &ones, &ones), form(&standard, &ones, &ones));
                assert!(close(a, b), "{d}D {mass} component {c}: {a} vs {b}");
                if mass == MassVariant::SingularDynamic {
                    let (a, b) = (form(&m, &axis, &ones), form(&standard, &axis, &ones));
                    assert!(close(a, b), "{d}D {mass} first moment {c}: {a} vs {b}");
                }
            }
            let model = signorini::engine::model::Model::of_box(
                &mesh,
                &signorini::engine::fem::Elasticity::NOTE,
                mass,
                Some(0.2),
            );
            let contact_dofs: Vec<usize> = mesh
                .contact_nodes()
                .into_iter()
                .flat_map(|n| (0..d).map(move |c| (n, c)))
                .filter_map(|(n, c)| mesh.dof_of(n, c))
                .collect();
            if mass == MassVariant::Lumped {
                assert!(model.massless_dofs().is_empty());
            } else {
                let mut expected = contact_dofs.clone();
                expected.sort_unstable();
                assert_eq!(model.massless_dofs(), expected.as_slice(), "{d}D {mass}");
            }
        }
    }
}

#[test]
fn names_labels_and_serde() {
    let names: Vec<&str> = MassVariant::ALL.iter().map(|m| m.name()).collect();
    assert_eq!(
        names,
        [
            "standard",
            "redistributed",
            "lumped",
            "redistributed-conserving",
            "singular-dynamic",
            "getfem-redistributed",
            "getfem-singular"
        ]
    );
    for m in MassVariant::ALL {
        assert_eq!(m.name().parse::<MassVariant>().unwrap(), m);
        assert_eq!(
            serde_json::to_string(&m).unwrap(),
            format!("\"{}\"", m.name())
        );
    }
    let labels: Vec<&str> = MassVariant::ALL.iter().map(|m| m.paper_label()).collect();
    assert_eq!(labels, ["STD", "MOD", "LUMP", "MODC", "SING", "GF1", "GF2"]);
    let err = "heavy".parse::<MassVariant>().unwrap_err();
    assert_eq!(err.name, "mass");
    for n in names {
        assert!(err.allowed.contains(n), "{n} not in {}", err.allowed);
    }
    assert_eq!(
        MassVariant::PAPER,
        [MassVariant::Standard, MassVariant::Redistributed]
    );
}
