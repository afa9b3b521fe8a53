//! Checks of the structured Q1 meshes of the 2D/3D note (§2.1, §3): element matrices (symmetry,
//! rigid modes, exact energy of uniform strains, hand mass entries), assembly (patch test,
//! integrated density), the redistributed mass `M^mod`, the contact set, the von Mises stress of
//! uniform states and bad input. (A short dynamic run of the 1D engine's Crank–Nicolson scheme
//! on the 2D and 3D models, with the discrete energy balance checked at every step, is in
//! `energy_balance.rs`.)
//!
//! Every expected value is computed here from hand formulas (tensor-product 1D integrals, the
//! analytical stresses of uniaxial and shear states), never read back from the code under test.

use std::time::Instant;

use nalgebra::{DMatrix, SMatrix, SymmetricEigen};
use signorini::engine::contact::ContactSet;
use signorini::engine::fem::box_mesh::{
    hex_mass, hex_stiffness, quad_mass, quad_stiffness, HEX_CORNERS, QUAD_CORNERS, VTK_HEXAHEDRON,
    VTK_QUAD,
};
use signorini::engine::fem::{BoxMesh, Elasticity, MassVariant, SymmetricMatrix};
use signorini::engine::model::Model;

/// A material with `λ ≠ μ` and `ρ ≠ 1`, so that a swapped parameter shows.
const STEEL_LIKE: Elasticity = Elasticity {
    density: 2.5,
    lame_lambda: 1.7,
    lame_mu: 0.6,
};

/// Corners `x_a = origin + ((s_a + 1)/2) · sizes` of an axis-aligned box element.
fn box_element<const D: usize, const N: usize>(
    corners: &[[f64; D]; N],
    origin: [f64; D],
    sizes: [f64; D],
) -> [[f64; D]; N] {
    std::array::from_fn(|a| {
        std::array::from_fn(|k| origin[k] + 0.5 * (corners[a][k] + 1.0) * sizes[k])
    })
}

/// A non-square quadrilateral (a trapezoid with no right angle), VTK order, counter-clockwise.
const TRAPEZOID: [[f64; 2]; 4] = [[0.1, -0.2], [2.0, 0.1], [1.7, 0.9], [0.3, 0.6]];

/// The shoelace area of a counter-clockwise polygon.
fn shoelace(p: &[[f64; 2]]) -> f64 {
    (0..p.len())
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            0.5 * (a[0] * b[1] - b[0] * a[1])
        })
        .sum()
}

/// A parallelepiped: the unit cube's corners mapped by `x = x0 + F ξ01` (`ξ01 ∈ [0,1]³`).
fn sheared_hex(f: [[f64; 3]; 3]) -> ([[f64; 3]; 8], f64) {
    let x0 = [0.3, -0.1, 0.2];
    let corners = std::array::from_fn(|a| {
        let s: [f64; 3] = std::array::from_fn(|k| 0.5 * (HEX_CORNERS[a][k] + 1.0));
        std::array::from_fn(|i| x0[i] + (0..3).map(|k| f[i][k] * s[k]).sum::<f64>())
    });
    let det = f[0][0] * (f[1][1] * f[2][2] - f[1][2] * f[2][1])
        - f[0][1] * (f[1][0] * f[2][2] - f[1][2] * f[2][0])
        + f[0][2] * (f[1][0] * f[2][1] - f[1][1] * f[2][0]);
    (corners, det)
}

const SHEAR_MAP: [[f64; 3]; 3] = [[1.2, 0.3, 0.1], [0.0, 0.7, -0.2], [0.15, 0.1, 2.0]];

/// The element dof vector of the nodal field `f(x_a)` (local dof `a·d + c`).
fn element_field<const D: usize, const N: usize, const ND: usize>(
    coords: &[[f64; D]; N],
    f: impl Fn(&[f64; D]) -> [f64; D],
) -> SMatrix<f64, ND, 1> {
    SMatrix::<f64, ND, 1>::from_fn(|i, _| f(&coords[i / D])[i % D])
}

/// A vector field on `R^D`.
type Field<const D: usize> = Box<dyn Fn(&[f64; D]) -> [f64; D]>;

/// The rigid motions of `R^d`: `d` translations and `d(d−1)/2` infinitesimal rotations
/// `u = ω × (x − c)`.
fn rigid_modes<const D: usize>() -> Vec<Field<D>> {
    let mut modes: Vec<Field<D>> = Vec::new();
    for c in 0..D {
        modes.push(Box::new(move |_| {
            std::array::from_fn(|i| f64::from(u8::from(i == c)))
        }));
    }
    let pairs: &[(usize, usize)] = if D == 2 {
        &[(0, 1)]
    } else {
        &[(0, 1), (1, 2), (0, 2)]
    };
    for &(p, q) in pairs {
        modes.push(Box::new(move |x| {
            let mut u = [0.0; D];
            u[p] = -(x[q] - 0.4);
            u[q] = x[p] - 0.7;
            u
        }));
    }
    modes
}

/// Symmetric, exactly `n_rigid` eigenvalues below `1e-12 · λ_max`, the next one well above, and
/// `K r = 0` for every rigid motion `r`.
fn check_rigid_kernel<const D: usize, const N: usize, const ND: usize>(
    k: &SMatrix<f64, ND, ND>,
    coords: &[[f64; D]; N],
    n_rigid: usize,
) {
    let asym = (k - k.transpose()).abs().max();
    assert!(asym <= 1e-14 * k.abs().max(), "asymmetry {asym}");
    // Through DMatrix: nalgebra's eigen solver has no bound for a generic `Const<ND>`.
    let mut ev: Vec<f64> = SymmetricEigen::new(DMatrix::from_column_slice(ND, ND, k.as_slice()))
        .eigenvalues
        .iter()
        .copied()
        .collect();
    ev.sort_by(f64::total_cmp);
    let largest = ev[ND - 1];
    let zeros = ev.iter().filter(|e| e.abs() <= 1e-12 * largest).count();
    assert_eq!(zeros, n_rigid, "eigenvalues {ev:?}");
    assert!(ev[n_rigid] > 1e-4 * largest, "a spurious soft mode: {ev:?}");
    assert!(ev[0] >= -1e-12 * largest, "negative eigenvalue {}", ev[0]);
    let modes = rigid_modes::<D>();
    assert_eq!(modes.len(), n_rigid);
    for mode in modes {
        let r = element_field::<D, N, ND>(coords, mode);
        let kr = k * r;
        assert!(
            kr.norm() <= 1e-13 * largest * r.norm(),
            "K r = {} for a rigid motion",
            kr.norm()
        );
    }
}

/// `½ uᵀ K u` for the affine field `u = G x` equals `|K| (μ |ε|² + ½ λ (tr ε)²)`, `ε = sym G`
/// (the strain energy density of eq. 4 times the measure).
fn check_uniform_strain_energy<const D: usize, const N: usize, const ND: usize>(
    k: &SMatrix<f64, ND, ND>,
    coords: &[[f64; D]; N],
    measure: f64,
    e: &Elasticity,
) {
    let gradients: [[[f64; 3]; 3]; 3] = [
        [[0.3, 0.0, 0.0], [0.0, -0.1, 0.0], [0.0, 0.0, 0.2]],
        [[0.0, 0.5, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
        [[0.1, 0.4, -0.3], [0.2, 0.25, 0.7], [-0.6, 0.05, 0.15]],
    ];
    for g in gradients {
        let u = element_field::<D, N, ND>(coords, |x| {
            std::array::from_fn(|i| (0..D).map(|j| g[i][j] * x[j]).sum::<f64>() + 0.01)
        });
        let eps = |i: usize, j: usize| 0.5 * (g[i][j] + g[j][i]);
        let trace: f64 = (0..D).map(|i| eps(i, i)).sum();
        let norm2: f64 = (0..D)
            .flat_map(|i| (0..D).map(move |j| (i, j)))
            .map(|(i, j)| eps(i, j).powi(2))
            .sum();
        let expected = measure * (e.lame_mu * norm2 + 0.5 * e.lame_lambda * trace * trace);
        let got = 0.5 * (u.transpose() * k * u)[(0, 0)];
        assert!(
            (got - expected).abs() <= 1e-12 * expected.abs().max(1e-300),
            "energy {got} vs {expected} for G = {g:?}"
        );
    }
}

/// Element stiffness (2×2 Gauss, plane strain): symmetric, positive semidefinite with exactly
/// the 3 rigid modes as kernel, and the exact energy of uniform strains, on a rectangle and on
/// a trapezoid (the general Jacobian `J = dN·X`).
#[test]
fn quad_stiffness_has_exactly_the_three_rigid_modes() {
    let rectangle = box_element(&QUAD_CORNERS, [0.5, -1.0], [2.0, 0.5]);
    for (coords, area) in [(rectangle, 1.0), (TRAPEZOID, shoelace(&TRAPEZOID))] {
        for e in [STEEL_LIKE, Elasticity::NOTE] {
            let k = quad_stiffness(&coords, &e);
            check_rigid_kernel::<2, 4, 8>(&k, &coords, 3);
            check_uniform_strain_energy::<2, 4, 8>(&k, &coords, area, &e);
        }
    }
}

/// Element stiffness (2×2×2 Gauss): symmetric, exactly the 6 rigid modes as kernel, exact
/// energy of uniform strains, on a non-cubic box and on a sheared parallelepiped.
#[test]
fn hex_stiffness_has_exactly_the_six_rigid_modes() {
    let cuboid = box_element(&HEX_CORNERS, [0.0, 1.0, -0.5], [1.0, 0.5, 2.0]);
    let (sheared, sheared_volume) = sheared_hex(SHEAR_MAP);
    for (coords, volume) in [(cuboid, 1.0), (sheared, sheared_volume)] {
        for e in [STEEL_LIKE, Elasticity::NOTE] {
            let k = hex_stiffness(&coords, &e);
            check_rigid_kernel::<3, 8, 24>(&k, &coords, 6);
            check_uniform_strain_energy::<3, 8, 24>(&k, &coords, volume, &e);
        }
    }
}

/// The consistent Q1 mass of a box element is the tensor product of the 1D P1 masses:
/// `ρ Π_k h_k/6 · (1 + [s_a,k = s_b,k])` on equal components, 0 across components.
fn check_box_mass<const D: usize, const N: usize, const ND: usize>(
    m: &SMatrix<f64, ND, ND>,
    corners: &[[f64; D]; N],
    sizes: [f64; D],
    rho: f64,
) {
    for i in 0..ND {
        for j in 0..ND {
            let (a, c, b, cc) = (i / D, i % D, j / D, j % D);
            let expected = if c == cc {
                (0..D)
                    .map(|k| {
                        sizes[k] / 6.0
                            * if corners[a][k] == corners[b][k] {
                                2.0
                            } else {
                                1.0
                            }
                    })
                    .product::<f64>()
                    * rho
            } else {
                0.0
            };
            assert!(
                (m[(i, j)] - expected).abs() <= 1e-15 * rho,
                "M_e[{i},{j}] = {} vs {expected}",
                m[(i, j)]
            );
        }
    }
}

/// Element mass: hand entries on boxes; on distorted elements every component block sums to
/// `ρ |K|` and the blocks across components vanish.
#[test]
fn element_mass_integrates_the_density() {
    let rho = STEEL_LIKE.density;
    let sizes2 = [0.3, 1.1];
    let quad = quad_mass(&box_element(&QUAD_CORNERS, [1.0, 2.0], sizes2), rho);
    check_box_mass::<2, 4, 8>(&quad, &QUAD_CORNERS, sizes2, rho);
    let sizes3 = [0.3, 1.1, 0.6];
    let hex = hex_mass(&box_element(&HEX_CORNERS, [1.0, 2.0, -3.0], sizes3), rho);
    check_box_mass::<3, 8, 24>(&hex, &HEX_CORNERS, sizes3, rho);

    let block_sums = |m: &DMatrix<f64>, d: usize| -> Vec<Vec<f64>> {
        (0..d)
            .map(|c| {
                (0..d)
                    .map(|cc| {
                        let mut s = 0.0;
                        for i in (c..m.nrows()).step_by(d) {
                            for j in (cc..m.ncols()).step_by(d) {
                                s += m[(i, j)];
                            }
                        }
                        s
                    })
                    .collect()
            })
            .collect()
    };
    let trapezoid = quad_mass(&TRAPEZOID, rho);
    let (sheared, volume) = sheared_hex(SHEAR_MAP);
    let sheared = hex_mass(&sheared, rho);
    let cases = [
        (
            DMatrix::from_column_slice(8, 8, trapezoid.as_slice()),
            2,
            shoelace(&TRAPEZOID),
        ),
        (
            DMatrix::from_column_slice(24, 24, sheared.as_slice()),
            3,
            volume,
        ),
    ];
    for (m, d, measure) in cases {
        let sums = block_sums(&m, d);
        for (c, row) in sums.iter().enumerate() {
            for (cc, &s) in row.iter().enumerate() {
                let expected = if c == cc { rho * measure } else { 0.0 };
                assert!(
                    (s - expected).abs() <= 1e-13,
                    "block ({c},{cc}): {s} vs {expected}"
                );
            }
        }
        assert!((&m - m.transpose()).abs().max() == 0.0);
    }
}

/// The meshes used by the assembly tests: non-square elements in 2D and 3D.
fn meshes() -> Vec<BoxMesh> {
    vec![
        BoxMesh::new(&[0.3, 1.0], &[3, 6]).unwrap(),
        BoxMesh::new(&[0.1, 1.0], &[2, 10]).unwrap(),
        BoxMesh::new(&[0.2, 0.3, 1.0], &[2, 3, 4]).unwrap(),
        BoxMesh::new(&[0.3, 0.3, 0.5], &[3, 3, 5]).unwrap(),
    ]
}

/// Numbering, coordinates and VTK connectivity: the top layer's dofs are the eliminated ones,
/// every element lists its corners in VTK order (corner `a` at `min + (s_a + 1)/2 · h`).
#[test]
fn numbering_and_vtk_connectivity() {
    for mesh in meshes() {
        let d = mesh.dim();
        let h = mesh.element_sizes();
        let per_axis: Vec<usize> = mesh.counts().iter().map(|n| n + 1).collect();
        let n_nodes: usize = per_axis.iter().product();
        let layer: usize = per_axis[..d - 1].iter().product();
        assert_eq!(mesh.n_nodes(), n_nodes);
        assert_eq!(mesh.n_dofs(), d * (n_nodes - layer));
        assert_eq!(mesh.n_elements(), mesh.counts().iter().product::<usize>());
        assert_eq!(
            mesh.vtk_cell_type(),
            if d == 2 { VTK_QUAD } else { VTK_HEXAHEDRON }
        );
        for node in 0..n_nodes {
            let x = mesh.node(node);
            let top = (x[d - 1] - mesh.lengths()[d - 1]).abs() < 1e-12;
            assert_eq!(mesh.on_dirichlet_boundary(node), top);
            assert_eq!(mesh.on_contact_boundary(node), x[d - 1] == 0.0);
            if d == 2 {
                assert_eq!(x[2], 0.0);
            }
            for c in 0..d {
                let expected = (!top).then_some(node * d + c);
                assert_eq!(mesh.dof_of(node, c), expected);
            }
            // Lexicographic, first coordinate fastest.
            let mut rest = node;
            for k in 0..d {
                let i = rest % per_axis[k];
                rest /= per_axis[k];
                assert!(
                    (x[k] - i as f64 * h[k]).abs() < 1e-12,
                    "node {node} axis {k}"
                );
            }
        }
        assert_eq!(mesh.elements().len(), mesh.n_elements());
        for nodes in mesh.elements() {
            assert_eq!(nodes.len(), 1 << d);
            let min: Vec<f64> = (0..d)
                .map(|k| {
                    nodes
                        .iter()
                        .map(|&n| mesh.node(n)[k])
                        .fold(f64::INFINITY, f64::min)
                })
                .collect();
            for (a, &n) in nodes.iter().enumerate() {
                let s: &[f64] = if d == 2 {
                    &QUAD_CORNERS[a]
                } else {
                    &HEX_CORNERS[a]
                };
                for k in 0..d {
                    let expected = min[k] + 0.5 * (s[k] + 1.0) * h[k];
                    assert!((mesh.node(n)[k] - expected).abs() < 1e-12);
                }
            }
        }
    }
}

/// `Σ_ij M_ij` over the kept dofs, by hand: per component `ρ A_⊥ ∫_0^{L_d} w(x_d)² dx_d` with
/// `w = Σ_{kept} φ_i` = 1 except on the top layer, where it falls linearly to 0
/// (`∫ w² = L_d − h_d + h_d/3`); `M^mod` also drops the bottom layer (`− h_d`).
#[test]
fn assembled_mass_integrates_the_density_over_the_kept_dofs() {
    for mesh in meshes() {
        let d = mesh.dim();
        let h = mesh.element_sizes();
        let (l_d, h_d) = (mesh.lengths()[d - 1], h[d - 1]);
        let cross: f64 = mesh.lengths()[..d - 1].iter().product();
        let rho = STEEL_LIKE.density;
        let m = mesh.mass(MassVariant::Standard, rho);
        let expected = d as f64 * rho * cross * (l_d - 2.0 * h_d / 3.0);
        assert!((m.sum_of_entries() - expected).abs() <= 1e-12 * expected);
        let m_mod = mesh.mass(MassVariant::Redistributed, rho);
        let expected_mod = d as f64 * rho * cross * (l_d - 5.0 * h_d / 3.0);
        assert!((m_mod.sum_of_entries() - expected_mod).abs() <= 1e-12 * expected_mod);
        // Row sums of the standard mass per component: M·1_c is the mass of component c.
        for c in 0..d {
            let one_c: Vec<f64> = (0..mesh.n_dofs())
                .map(|i| f64::from(u8::from(i % d == c)))
                .collect();
            let per_component = m.bilinear_form(&one_c, &one_c);
            assert!((per_component - expected / d as f64).abs() <= 1e-12 * expected);
        }
    }
}

/// `A x` through the library's sparse product.
fn sparse_mul(a: &SymmetricMatrix, x: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; a.dim()];
    a.mul_into(x, &mut y);
    y
}

/// Patch test: the interpolant of an affine field `u = A x + b` has `S u = 0` at every dof of
/// a node on no face of the box and not adjacent to the Dirichlet layer (whose eliminated
/// values break the affine field); an affine field vanishing on `Γ_Dir`, `u = a (x_d − L_d)`,
/// has `S u = 0` at every dof of a node on no face. A quadratic field fails the same test.
#[test]
fn patch_test_affine_fields_are_in_equilibrium_inside() {
    for mesh in meshes() {
        let d = mesh.dim();
        let s = mesh.stiffness(&STEEL_LIKE);
        assert!(s.dim() == mesh.n_dofs());
        let l_d = mesh.lengths()[d - 1];
        let a = [[0.3, -0.7, 0.2], [1.1, 0.4, -0.5], [0.6, 0.25, -0.9]];
        let b = [0.05, -0.2, 0.1];
        let affine = mesh.interpolate(|x| {
            std::array::from_fn(|i| (0..x.len()).map(|j| a[i][j] * x[j]).sum::<f64>() + b[i])
        });
        let vanishing =
            mesh.interpolate(|x| std::array::from_fn(|i| b[i] * (x[x.len() - 1] - l_d)));
        let quadratic = mesh.interpolate(|x| std::array::from_fn(|i| a[i][0] * x[0] * x[0]));
        let scale = s.to_faer().val().iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let (r_affine, r_vanishing, r_quadratic) = (
            sparse_mul(&s, &affine),
            sparse_mul(&s, &vanishing),
            sparse_mul(&s, &quadratic),
        );
        let mut checked = 0;
        let mut quadratic_residual = 0.0f64;
        for node in 0..mesh.n_nodes() {
            if mesh.on_boundary(node) {
                continue;
            }
            let below_top = mesh.node_index(node)[d - 1] + 1 < mesh.counts()[d - 1];
            for c in 0..d {
                let dof = mesh.dof_of(node, c).unwrap();
                assert!(
                    r_vanishing[dof].abs() <= 1e-12 * scale,
                    "{}",
                    r_vanishing[dof]
                );
                if below_top {
                    assert!(r_affine[dof].abs() <= 1e-12 * scale, "{}", r_affine[dof]);
                    checked += 1;
                }
                quadratic_residual = quadratic_residual.max(r_quadratic[dof].abs());
            }
        }
        assert!(
            checked > 0,
            "the mesh has interior nodes below the top layer"
        );
        assert!(
            quadratic_residual > 1e-6 * scale,
            "a quadratic field is not in equilibrium"
        );
        // Symmetry of the assembled matrix.
        for j in 0..s.dim() {
            for i in 0..s.dim() {
                assert_eq!(s.get(i, j), s.get(j, i));
            }
        }
    }
}

/// Elements with no node on `Γ_Dir` (there the interpolant of a linear field is exact).
fn elements_off_dirichlet(mesh: &BoxMesh) -> Vec<usize> {
    (0..mesh.n_elements())
        .filter(|&e| {
            mesh.element(e)
                .iter()
                .all(|&n| !mesh.on_dirichlet_boundary(n))
        })
        .collect()
}

/// The von Mises stress of uniform states against the analytical values: 3D uniaxial stress
/// (`u₃ = ε x₃`, lateral `−νε x`): `E|ε|`; 2D plane strain with `σ₁₁ = 0` (`ε₁₁ = −λε/(λ+2μ)`):
/// principal stresses `(0, σ₂₂, σ₃₃)`, `σ_vm² = σ₂₂² − σ₂₂σ₃₃ + σ₃₃²`; simple shear
/// `u₁ = γ x_d`: `√3 μ|γ|`.
#[test]
fn von_mises_of_uniform_states() {
    let e = STEEL_LIKE;
    let (l, m) = (e.lame_lambda, e.lame_mu);
    let eps = 0.01;
    let gamma = -0.02;
    for mesh in meshes() {
        let d = mesh.dim();
        let (stretch, expected_stretch) = if d == 3 {
            let nu = l / (2.0 * (l + m));
            let young = m * (3.0 * l + 2.0 * m) / (l + m);
            (
                mesh.interpolate(|x| [-nu * eps * x[0], -nu * eps * x[1], eps * x[2]]),
                young * eps.abs(),
            )
        } else {
            let lateral = -l / (l + 2.0 * m) * eps;
            let s22 = (l + 2.0 * m) * eps + l * lateral;
            let s33 = l * (eps + lateral);
            (
                mesh.interpolate(|x| [lateral * x[0], eps * x[1], 0.0]),
                (s22 * s22 - s22 * s33 + s33 * s33).sqrt(),
            )
        };
        let shear = mesh.interpolate(|x| [gamma * x[x.len() - 1], 0.0, 0.0]);
        let expected_shear = 3f64.sqrt() * m * gamma.abs();
        let off = elements_off_dirichlet(&mesh);
        assert!(!off.is_empty());
        for (u, expected) in [(stretch, expected_stretch), (shear, expected_shear)] {
            let vm = mesh.von_mises(&u, &e);
            assert_eq!(vm.len(), mesh.n_elements());
            for &el in &off {
                assert!(
                    (vm[el] - expected).abs() <= 1e-12 * expected,
                    "d = {d}, element {el}: {} vs {expected}",
                    vm[el]
                );
            }
            // The nodal average of a field constant off the top layer is that constant at
            // every node belonging only to such elements (here: the contact face).
            let avg = mesh.nodal_average(&vm);
            for node in mesh.contact_nodes() {
                if mesh.counts()[d - 1] > 1 {
                    assert!((avg[node] - expected).abs() <= 1e-12 * expected);
                }
            }
        }
    }
}

/// `nodal_average` is the mean over the elements containing each node (a corner node has one
/// element, a node inside has `2^d`).
#[test]
fn nodal_average_is_the_mean_of_the_adjacent_elements() {
    for mesh in meshes() {
        let values: Vec<f64> = (0..mesh.n_elements())
            .map(|e| (e * e) as f64 + 0.5)
            .collect();
        let avg = mesh.nodal_average(&values);
        for (node, &got) in avg.iter().enumerate() {
            let adjacent: Vec<f64> = mesh
                .elements()
                .zip(&values)
                .filter(|(nodes, _)| nodes.contains(&node))
                .map(|(_, &v)| v)
                .collect();
            let mean = adjacent.iter().sum::<f64>() / adjacent.len() as f64;
            assert!((got - mean).abs() <= 1e-12 * mean);
        }
        assert_eq!(avg[0], values[0], "corner node 0 belongs to element 0 only");
    }
}

/// `nodal_vector(interpolate(f))` is `f` at the nodes off `Γ_Dir`, zero on it, with a zero
/// third component in 2D.
#[test]
fn interpolate_and_nodal_vector_round_trip() {
    for mesh in meshes() {
        let d = mesh.dim();
        let f = |x: &[f64]| {
            [
                x[0] + 1.0,
                2.0 * x[1] - 0.5,
                x.get(2).map_or(7.0, |z| z * z),
            ]
        };
        let u = mesh.interpolate(f);
        assert_eq!(u.len(), mesh.n_dofs());
        let nodal = mesh.nodal_vector(&u);
        for (node, value) in nodal.iter().enumerate() {
            let x = &mesh.node(node)[..d];
            let expected = f(x);
            for c in 0..3 {
                let want = if c >= d || mesh.on_dirichlet_boundary(node) {
                    0.0
                } else {
                    expected[c]
                };
                assert_eq!(value[c], want, "node {node} component {c}");
            }
        }
    }
}

/// `M^mod`: `Model::massless_dofs()` is exactly every component of every node of `Γ_Sig` (not
/// only the normal ones: the note's `ker M^mod = span{ν_i}` is too small); rows of nodes two
/// layers up or more are those of `M`; `M − M^mod` carries the bottom layer's mass
/// `d ρ A_⊥ h_d`.
#[test]
fn redistributed_mass_frees_every_component_of_the_contact_nodes() {
    for mesh in meshes() {
        let d = mesh.dim();
        let e = STEEL_LIKE;
        let standard = Model::of_box(&mesh, &e, MassVariant::Standard, Some(0.1));
        let redistributed = Model::of_box(&mesh, &e, MassVariant::Redistributed, Some(0.1));
        assert!(standard.massless_dofs().is_empty());
        assert!(!standard.contact_is_massless());
        let mut expected: Vec<usize> = mesh
            .contact_nodes()
            .iter()
            .flat_map(|&n| (0..d).map(move |c| (n, c)))
            .map(|(n, c)| mesh.dof_of(n, c).unwrap())
            .collect();
        expected.sort_unstable();
        assert_eq!(redistributed.massless_dofs(), expected.as_slice());
        assert!(redistributed.contact_is_massless());
        let (m, m_mod) = (standard.mass(), redistributed.mass());
        for node in 0..mesh.n_nodes() {
            if mesh.node_index(node)[d - 1] < 2 {
                continue;
            }
            for c in 0..d {
                let Some(i) = mesh.dof_of(node, c) else {
                    continue;
                };
                for j in 0..mesh.n_dofs() {
                    // Equal up to the order in which duplicates are summed.
                    let (a, b) = (m.get(i, j), m_mod.get(i, j));
                    assert!(
                        (a - b).abs() <= 1e-15 * m.get(i, i),
                        "row {i} column {j}: {a} vs {b}"
                    );
                }
            }
        }
        let cross: f64 = mesh.lengths()[..d - 1].iter().product();
        let removed = d as f64 * e.density * cross * mesh.element_sizes()[d - 1];
        let diff = m.sum_of_entries() - m_mod.sum_of_entries();
        assert!(
            (diff - removed).abs() <= 1e-12 * removed,
            "{diff} vs {removed}"
        );
        // The stiffness does not depend on the mass variant.
        assert_eq!(
            standard.stiffness().sum_of_entries(),
            redistributed.stiffness().sum_of_entries()
        );
    }
}

/// One constraint per node of `Γ_Sig`, on component `d − 1` (the normal displacement), with
/// the given gap; none without an obstacle.
#[test]
fn contact_set_constrains_the_normal_displacement_of_the_bottom_nodes() {
    for mesh in meshes() {
        let d = mesh.dim();
        let gap = 0.2;
        let set = ContactSet::on_box_face(&mesh, gap);
        let expected_len: usize = mesh.counts()[..d - 1].iter().map(|n| n + 1).product();
        assert_eq!(set.len(), expected_len);
        assert!(set.gaps.iter().all(|&g| g == gap));
        let mut bottom = 0;
        for node in 0..mesh.n_nodes() {
            if mesh.node(node)[d - 1] != 0.0 {
                continue;
            }
            bottom += 1;
            let dof = mesh.dof_of(node, d - 1).unwrap();
            assert_eq!(set.dofs.iter().filter(|&&x| x == dof).count(), 1);
        }
        assert_eq!(bottom, set.len());
        // u_d = −0.3 everywhere: every constraint value is gap − 0.3.
        let u = mesh.interpolate(|_| {
            let mut v = [0.7, 0.7, 0.7];
            v[d - 1] = -0.3;
            v
        });
        let mut values = vec![0.0; set.len()];
        set.gaps_of(&u, &mut values);
        assert!(values.iter().all(|&v| (v - (gap - 0.3)).abs() < 1e-15));
        let model = Model::of_box(&mesh, &STEEL_LIKE, MassVariant::Standard, None);
        assert_eq!(model.contact(), None);
        assert_eq!(
            Model::of_box(&mesh, &STEEL_LIKE, MassVariant::Standard, Some(gap)).contact(),
            Some(&set)
        );
    }
}

/// Bad input is a typed error naming the field (and the direction for counts and lengths).
#[test]
fn bad_input_is_rejected_with_the_field_named() {
    let cases: [(&[f64], &[usize], &str, &str); 8] = [
        (&[1.0, 1.0], &[2, 0], "elements", "x2"),
        (&[1.0, 1.0, 1.0], &[0, 2, 2], "elements", "x1"),
        (&[1.0, 1.0, 1.0], &[2, 2, 0], "elements", "x3"),
        (&[1.0, 1.0], &[2], "elements", "[2]"),
        (&[1.0], &[2], "lengths", "[1.0]"),
        (&[1.0, 1.0, 1.0, 1.0], &[1, 1, 1, 1], "lengths", ""),
        (&[1.0, -0.5], &[2, 2], "lengths", "x2"),
        (&[f64::NAN, 1.0, 1.0], &[2, 2, 2], "lengths", "x1"),
    ];
    for (lengths, counts, name, value) in cases {
        let err = BoxMesh::new(lengths, counts).unwrap_err();
        assert_eq!(err.name, name, "{lengths:?} {counts:?}");
        assert!(err.value.contains(value), "{err}");
        assert!(err.to_string().contains(name));
    }
    assert!(BoxMesh::new(&[1.0, 0.0], &[1, 1]).is_err());
    assert!(BoxMesh::new(&[1.0, f64::INFINITY], &[1, 1]).is_err());

    let with = |density, lame_lambda, lame_mu| Elasticity {
        density,
        lame_lambda,
        lame_mu,
    };
    let material_cases = [
        (with(1.0, 0.25, 0.0), 2, Some("lame_mu")),
        (with(1.0, 0.25, -0.5), 3, Some("lame_mu")),
        (with(0.0, 0.25, 0.5), 2, Some("density")),
        (with(-1.0, 0.25, 0.5), 3, Some("density")),
        (with(1.0, f64::NAN, 0.5), 2, Some("lame_lambda")),
        // λ + 2μ/d: 2D needs λ > −μ, 3D needs λ > −2μ/3.
        (with(1.0, -0.5, 0.5), 2, Some("lame_lambda")),
        (with(1.0, -0.45, 0.5), 2, None),
        (with(1.0, -0.45, 0.5), 3, Some("lame_lambda")),
        (with(1.0, -1.0 / 3.0, 0.5), 3, Some("lame_lambda")),
        (with(1.0, -0.3, 0.5), 3, None),
        (Elasticity::NOTE, 2, None),
        (Elasticity::NOTE, 3, None),
    ];
    for (e, dim, name) in material_cases {
        match (e.validate(dim), name) {
            (Ok(()), None) => {}
            (Err(err), Some(name)) => assert_eq!(err.name, name, "{e:?} d = {dim}"),
            (got, want) => panic!("{e:?} d = {dim}: got {got:?}, wanted an error on {want:?}"),
        }
    }
}

/// Assembly cost of the 8 × 8 × 80 hexahedral mesh (19 440 dofs): run with
/// `cargo test --release --test unit -- --ignored --nocapture assembly_timing`.
#[test]
#[ignore = "timing measurement, run by hand"]
fn assembly_timing_of_the_8x8x80_hex_mesh() {
    let mesh = BoxMesh::note_3d(8, 8, 80).unwrap();
    assert_eq!(mesh.n_dofs(), 3 * 81 * 80);
    let e = Elasticity::NOTE;
    for _ in 0..3 {
        let t = Instant::now();
        let s = mesh.stiffness(&e);
        let t_s = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let m = mesh.mass(MassVariant::Standard, e.density);
        let t_m = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let model = Model::of_box(&mesh, &e, MassVariant::Redistributed, Some(0.2));
        let t_model = t.elapsed().as_secs_f64();
        println!(
            "8x8x80 hex: {} dofs, {} stiffness nonzeros; stiffness {:.3} s, mass {:.3} s, model (M^mod + S + contact) {:.3} s",
            mesh.n_dofs(),
            s.to_faer().val().len(),
            t_s,
            t_m,
            t_model
        );
        assert_eq!(m.dim(), model.n_dofs());
    }
}
