//! A rank's share of a one-step implicit run (Newmark β > 0 and the θ-method, 1D paper eq. 32
//! and 34; Crank–Nicolson is the reference's) of a box with the multiplier contact
//! ([`SlabOneStep`]): the steps of [`crate::engine::schemes::OneStepScheme`] with every vector
//! cut into the ranks' slabs.

use std::ops::Range;

use super::slab_balance::{SlabBalanceData, SlabForms};
use super::{DecompositionError, Ranks, SlabCg, SlabOperator, Slabs};
use crate::engine::contact::{ContactStep, ContactTreatment};
use crate::engine::error::SolveError;
use crate::engine::linalg::{PcgWork, SolveCounts, DEFAULT_TOLERANCE};
use crate::engine::model::Model;
use crate::engine::schemes::conventions::PredictorForm;
use crate::engine::schemes::energy_balance::{BalanceForms, Sides, StepVectors};
use crate::engine::schemes::{InitialState, StepCoefficients, StepStatistics};

/// A rank's share of the run: its parts of `U^n`, `V^n`, `A^n`; the slabs of `M`, `S` and the
/// step matrix `K = M/(bΔt²) + S`; and, on rank 0, which holds `Γ_Sig` and the slab of the
/// local contact operator, the contact step and the multipliers `λ^n`.
///
/// A step is [`crate::engine::schemes::OneStepScheme`]'s, `P = U^n + ΔtV^n + aΔt²A^n`,
/// `K U^{n+1} = M P/(bΔt²)` (from `P + bΔt²A^n`), the contact correction on rank 0, then
/// `A^{n+1} = (U^{n+1} − P)/(bΔt²)` and `V^{n+1} = V^n + Δt(cA^n + dA^{n+1})`: every entry
/// of a rank's part is computed as in one process, and only the inner products of the solve
/// and of the energy are summed across ranks (in rank order).
pub struct SlabOneStep<'r, R: Ranks + ?Sized> {
    ranks: &'r R,
    mass: SlabOperator<'r, R>,
    stiffness: SlabOperator<'r, R>,
    system: SlabCg<'r, R>,
    work: PcgWork,
    counts: SolveCounts,
    /// The contact step, on rank 0.
    contact: Option<ContactStep>,
    coef: StepCoefficients,
    predictor_form: PredictorForm,
    dt: f64,
    step: usize,
    u: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    /// `λ^n`, on rank 0 (empty elsewhere).
    lambda: Vec<f64>,
    predictor: Vec<f64>,
    scratch: Vec<f64>,
    guess: Vec<f64>,
    /// `U^n`, `V^n`, `λ^n` of the last step's start, for its balance.
    before: [Vec<f64>; 2],
    lambda_before: Vec<f64>,
    /// `ΔU`, `ΔV`, `U^{n+1} + U^n`, `V^{n+1} + V^n` of the last step's balance.
    pairs: [Vec<f64>; 4],
    balance: SlabBalanceData,
    product: Vec<f64>,
}

impl<'r, R: Ranks + ?Sized> SlabOneStep<'r, R> {
    /// This rank's share of the run of `model` (the whole box, matrix-free) with the
    /// coefficients `coef`, the step `dt` and the predictor summed in `predictor_form`, from
    /// `start` (the whole initial state, [`crate::engine::schemes::initial_state`], which rank 0
    /// alone holds and sends each rank its part of; the others pass `None`). The box
    /// is cut evenly, rank 0 holding the layers of the local contact operator's slab (its
    /// truncation is chosen on the whole step matrix, as in one process, and told to every
    /// rank). Refused for a penalty or Nitsche contact, a load, or more ranks than the
    /// layers allow.
    pub fn new(
        ranks: &'r R,
        model: &Model,
        coef: StepCoefficients,
        dt: f64,
        start: Option<&InitialState>,
        predictor_form: PredictorForm,
    ) -> Result<Self, SlabRunError> {
        if model.contact_law().treatment() != ContactTreatment::Multiplier {
            return Err(DecompositionError::NotABoxMatrix(
                "a distributed run treats the contact by its multiplier",
            )
            .into());
        }
        if model.load().is_some() {
            return Err(DecompositionError::NotABoxMatrix("a distributed run has no load").into());
        }
        let k = model
            .mass()
            .linear_combination(1.0 / (coef.b * dt * dt), model.stiffness(), 1.0);
        let contact_rows = match (ranks.rank(), model.contact()) {
            (0, Some(c)) => model.contact_law().rows(c),
            _ => Vec::new(),
        };
        let contact = match (ranks.rank(), model.contact()) {
            (0, Some(c)) => {
                ContactStep::local(c, &contact_rows, &k, model.solver_plan().contact.layers())
                    .map(Some)
            }
            _ => Ok(None),
        };
        // Rank 0 tells every rank the layers its contact slab takes (−1: it has none, its
        // operator failed).
        let layers = match &contact {
            Ok(c) => c
                .as_ref()
                .and_then(ContactStep::truncation)
                .map_or(0.0, |t| (t.layers + 1) as f64),
            Err(_) => -1.0,
        };
        let mut slab_layers = vec![0.0; ranks.size()];
        ranks.gather_all(layers, &mut slab_layers);
        let contact = contact?;
        if slab_layers[0] < 0.0 {
            return Err(DecompositionError::RankZeroFailed.into());
        }
        let (Some(k_stencil), Some(m), Some(s)) = (
            k.stencil(),
            model.mass().stencil(),
            model.stiffness().stencil(),
        ) else {
            return Err(DecompositionError::NotABoxMatrix("this model is assembled").into());
        };
        let first_layers = (slab_layers[0] as usize).max(Slabs::FIRST_LAYERS_CONDENSED);
        let slabs = Slabs::even(k_stencil.node_layers(), ranks.size(), first_layers)?;
        let mass = SlabOperator::new(ranks, m, &slabs)?;
        let stiffness = SlabOperator::new(ranks, s, &slabs)?;
        let system = SlabCg::on_slabs(ranks, &k, slabs, DEFAULT_TOLERANCE)?;
        let own = system.own_dofs();
        let layer_dofs = k_stencil.nodes_per_layer() * k_stencil.components();
        let [u, v, a] = scatter(ranks, system.slabs(), layer_dofs, start);
        let lambda = start.map_or_else(Vec::new, |s| s.multiplier.clone());
        let balance = SlabBalanceData::new(&mass, &stiffness, contact_rows);
        let n = own.len();
        Ok(Self {
            ranks,
            balance,
            before: [vec![0.0; n], vec![0.0; n]],
            lambda_before: Vec::new(),
            pairs: std::array::from_fn(|_| vec![0.0; n]),
            product: vec![0.0; n],
            mass,
            stiffness,
            work: PcgWork::new(own.len()),
            counts: SolveCounts::default(),
            system,
            contact,
            coef,
            predictor_form,
            dt,
            step: 0,
            u,
            v,
            a,
            lambda,
            predictor: vec![0.0; own.len()],
            scratch: vec![0.0; own.len()],
            guess: vec![0.0; own.len()],
        })
    }

    /// One step (every rank together): see [`SlabOneStep`]. A failure of rank 0's contact
    /// solve is told to every rank, which all return an error.
    pub fn advance(&mut self) -> Result<(), SolveError> {
        self.before[0].copy_from_slice(&self.u);
        self.before[1].copy_from_slice(&self.v);
        self.lambda_before.clone_from(&self.lambda);
        let dt = self.dt;
        let inv_bdt2 = 1.0 / (self.coef.b * dt * dt);
        self.coef.predict(
            self.predictor_form,
            dt,
            (&self.u, &self.v, &self.a),
            &mut self.predictor,
        );
        self.mass.mul_dot(&self.predictor, &mut self.scratch);
        self.scratch.iter_mut().for_each(|r| *r *= inv_bdt2);
        self.coef
            .warm_start(dt, &self.predictor, &self.a, &mut self.guess);
        let mut x = std::mem::take(&mut self.guess);
        self.counts.iterations += self.system.solve(&self.scratch, &mut x, &mut self.work)?;
        self.counts.solves += 1;
        self.scratch.copy_from_slice(&x);
        self.guess = x;
        let contact = match self.contact.as_mut() {
            Some(contact) => {
                contact.enforce(self.step + 1, &mut self.scratch, |_, g| g, &mut self.lambda)
            }
            None => Ok(()),
        };
        let failed = self.ranks.sum(f64::from(u8::from(contact.is_err())));
        contact?;
        if failed > 0.0 {
            return Err(SolveError::ContactNotConverged {
                step: self.step + 1,
                iterations: 0,
            });
        }
        self.coef.update(
            dt,
            (&self.scratch, &self.predictor),
            &mut self.v,
            &mut self.a,
        );
        std::mem::swap(&mut self.u, &mut self.scratch);
        self.step += 1;
        Ok(())
    }

    /// `E_h = ½ VᵀMV + ½ UᵀSU` (note eq. 6, the multiplier's: no contact energy), summed
    /// over the ranks (every rank together).
    pub fn energy(&mut self) -> f64 {
        let kinetic = self
            .ranks
            .sum(self.mass.mul_dot(&self.v, &mut self.scratch));
        let strain = self
            .ranks
            .sum(self.stiffness.mul_dot(&self.u, &mut self.scratch));
        0.5 * kinetic + 0.5 * strain
    }

    /// The two sides of the last step's energy balance, which `law` assembles from the slab's
    /// forms (e.g. [`crate::engine::schemes::energy_balance::newmark_sides`]) and the step's
    /// vectors, every rank together (the module `slab_balance`).
    pub fn balance(
        &mut self,
        law: impl FnOnce(&mut dyn BalanceForms, &StepVectors) -> Sides,
    ) -> Sides {
        let [du, dv, u_sum, v_sum] = &mut self.pairs;
        for (((d, s), now), then) in du
            .iter_mut()
            .zip(u_sum.iter_mut())
            .zip(&self.u)
            .zip(&self.before[0])
        {
            *d = now - then;
            *s = now + then;
        }
        for (((d, s), now), then) in dv
            .iter_mut()
            .zip(v_sum.iter_mut())
            .zip(&self.v)
            .zip(&self.before[1])
        {
            *d = now - then;
            *s = now + then;
        }
        let vectors = StepVectors {
            difference: [du, dv],
            sum: [u_sum, v_sum],
            multipliers: (&self.lambda_before, &self.lambda),
        };
        let mut forms = SlabForms {
            ranks: self.ranks,
            mass: &self.mass,
            stiffness: &self.stiffness,
            data: &self.balance,
            product: &mut self.product,
        };
        law(&mut forms, &vectors)
    }

    /// The steps taken.
    pub fn step(&self) -> usize {
        self.step
    }

    /// `t_n = nΔt`.
    pub fn time(&self) -> f64 {
        self.step as f64 * self.dt
    }

    /// The range of the whole box's unknowns this rank holds.
    pub fn own_dofs(&self) -> Range<usize> {
        self.system.own_dofs()
    }

    /// The decomposition of the box over the ranks.
    pub fn slabs(&self) -> &Slabs {
        self.system.slabs()
    }

    /// This rank's part of `U^n`.
    pub fn displacement(&self) -> &[f64] {
        &self.u
    }

    /// This rank's part of `V^n`.
    pub fn velocity(&self) -> &[f64] {
        &self.v
    }

    /// `λ^n` of every contact constraint on rank 0; empty on the others.
    pub fn multipliers(&self) -> &[f64] {
        &self.lambda
    }

    /// The step solves so far and their CG iterations (the same on every rank), and rank 0's
    /// contact solves, violation and slab (none elsewhere).
    pub fn statistics(&self) -> StepStatistics {
        StepStatistics::of(self.counts, &self.contact)
    }
}

/// Every rank's parts of `U⁰`, `V⁰`, `A⁰`, sent by rank 0 from the whole `start` it alone
/// holds (the other ranks pass `None`): every rank together.
fn scatter<R: Ranks + ?Sized>(
    ranks: &R,
    slabs: &Slabs,
    layer_dofs: usize,
    start: Option<&InitialState>,
) -> [Vec<f64>; 3] {
    let dofs = |r: usize| {
        let layers = slabs.of(r);
        layers.start * layer_dofs..layers.end * layer_dofs
    };
    let own = dofs(ranks.rank());
    if ranks.rank() > 0 {
        return std::array::from_fn(|_| {
            let mut part = vec![0.0; own.len()];
            ranks.receive(0, &mut part);
            part
        });
    }
    let start = start.expect("rank 0 holds the whole initial state");
    let fields = [&start.displacement, &start.velocity, &start.acceleration];
    for r in 1..ranks.size() {
        for field in fields {
            ranks.send(r, &field[dofs(r)]);
        }
    }
    fields.map(|field| field[own.clone()].to_vec())
}

/// Why a distributed run could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum SlabRunError {
    /// The decomposition or the model.
    #[error(transparent)]
    Decomposition(#[from] DecompositionError),
    /// The contact operator.
    #[error(transparent)]
    Solve(#[from] SolveError),
}
