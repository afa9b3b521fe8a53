//! Engine-level properties, each checked against hand formulas, finite differences or an
//! independent solver rather than read back from the code under test: the P1 and Q1 assembly
//! and the mass variants, the exact solutions of the benchmarks, complementarity and the contact
//! treatments, explicit Newmark, the initial-data perturbation, and the discrete energy
//! balances (all of them in `energy_balance.rs`); the ParaView files of a box run; and the
//! executor of a study's jobs (local, a shard's share, a merge).

#[path = "../common/benchmarks.rs"]
mod benchmarks;
#[path = "../common/mod.rs"]
mod common;
#[path = "../common/external.rs"]
mod external_runs;
#[path = "../common/slabs.rs"]
mod slabs;

mod bouncing_bar;
mod box_budget;
mod box_mesh;
mod cluster_plan;
mod complementarity;
mod contact_cross_check;
mod contact_stabilised_newmark;
mod contact_treatments;
mod distributed;
mod energy_balance;
mod executor;
mod explicit;
mod external;
mod fem;
mod getfem_demo;
mod getfem_roundoff;
mod local_contact;
mod mass_variants;
mod paraview;
mod paraview_fuzz;
mod pcg;
mod perturbation;
mod rival_schemes;
mod run;
mod run_status;
mod schemes_report;
mod settings;
mod signorini_dirichlet;
mod stencil;
mod step_perturbation;
mod stepper;
mod twisted;
