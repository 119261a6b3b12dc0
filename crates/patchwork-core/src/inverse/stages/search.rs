//! The search: CMA-ES over the free patch variables in the unit cube, each
//! candidate simulated on the search model and scored by the objective;
//! checkpointed after every generation. The search model is the rod
//! (`crate::rod`, with `rod_search`: its table of one-patch FE solves on
//! the verification model found or kept by `rod_model.rs`), else FE on the
//! search mesh. On the rod the seed is scored again on it, so that the
//! search keeps the seed only where the rod finds nothing better, and
//! [`ROD_EVALUATIONS`] rod evaluations count as one of the budget and the
//! patience.

use super::super::errors::DesignRunError;
use super::super::incumbent::{Incumbent, Scorer, unit_cube_options};
use super::super::outcome::{SearchEnd, StageName};
use super::super::run::{Context, Run};
use super::rod_model::{RodModel, rod_model};
use crate::cmaes::Optimizer;
use crate::design::Design;
use crate::inverse::DesignCheckpoint;
use crate::inverse::ROD_EVALUATIONS;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Search {
    /// Forward evaluations, the seed's included.
    pub budget: usize,
    /// Evaluations without a better design after which the search ends
    /// (0: never).
    pub patience: usize,
    /// CMA-ES's initial step in the unit cube.
    pub initial_step: f64,
}

impl Search {
    pub(in super::super) fn run(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
    ) -> Result<(), DesignRunError> {
        if run.space.dimension() == 0 || self.budget <= 1 {
            return Ok(());
        }
        let (settings, tuning) = (run.setup.settings, run.setup.tuning);
        let rod = match tuning.rod_search {
            true => rod_model(run, ctx)?,
            false => None,
        };
        let (scale, before) = units(rod.as_ref());
        let state = &mut run.state;
        let base = state.base.clone();
        let scorer = Scorer {
            rod: rod.as_ref(),
            space: &run.space,
            base: &base,
            model: &run.setup.search_model,
            profiles: &run.setup.profiles,
            objective: &tuning.objective,
            warm_starts: tuning.warm_starts,
            cancel: ctx.cancel,
            deadline: ctx.deadline,
            caches: ctx.caches,
        };
        if state.optimizer.is_none() {
            rod.iter().for_each(|rod| rescore_seed(state, &scorer, rod));
        }
        let incumbent = Incumbent::new(
            state.best_objective,
            state.best_patches.clone(),
            run.warm_start.take(),
        );
        let objective = |u: &[f64]| scorer.evaluate(u, &incumbent);
        // The optimiser lives in the checkpoint state, so what is
        // checkpointed is what runs.
        let ended = loop {
            ctx.check_cancelled()?;
            let optimizer = state.optimizer.get_or_insert_with(|| {
                Optimizer::new(unit_cube_options(
                    run.space.seed_point(),
                    self.initial_step,
                    settings.seed,
                    self.budget * scale,
                    settings.threads,
                ))
            });
            let ended = optimizer.step(&objective);
            let (generation, sigma) = (optimizer.strategy.generation, optimizer.strategy.sigma);
            state.evaluations = before + optimizer.evaluations().div_ceil(scale);
            // A generation evaluated while cancelling saw infinities: drop it.
            ctx.check_cancelled()?;
            take_best(state, &incumbent);
            let (evaluations, best) = (state.evaluations, state.best_objective);
            ctx.report(StageName::Search, generation, evaluations, best, sigma);
            ctx.checkpoint(state);
            if let Some(ended) = ended {
                break SearchEnd::Optimizer(ended);
            }
            if self.patience > 0 && state.evaluations >= state.improved_at + self.patience {
                break SearchEnd::STALLED;
            }
            if ctx.out_of_time() {
                break SearchEnd::TIME_LIMIT;
            }
        };
        run.termination = ended;
        run.design = run.state.best_design();
        Ok(())
    }
}

/// The incumbent's best as the state's, and when it last improved.
fn take_best(state: &mut DesignCheckpoint, incumbent: &Incumbent) {
    let previous_best = state.best_objective;
    (state.best_objective, state.best_patches) = incumbent.best();
    if state.best_objective < previous_best {
        state.improved_at = state.evaluations;
    }
}

/// The units of the search's evaluations, and the evaluations the run
/// spent before it: on the rod, [`ROD_EVALUATIONS`] rod evaluations make
/// one, and the run solved the seed on the search mesh and on the
/// verification model; on FE each is one solve, after the seed's.
fn units(rod: Option<&RodModel>) -> (usize, usize) {
    match rod {
        Some(_) => (ROD_EVALUATIONS, 2),
        None => (1, 1),
    }
}

/// The seed scored on the rod, as the search's start and the seed's
/// objective (both on the search's model).
fn rescore_seed(state: &mut DesignCheckpoint, scorer: &Scorer<'_>, rod: &RodModel) {
    let seed = Design {
        patches: state.best_patches.clone(),
        ..state.base.clone()
    };
    state.best_objective = scorer.rod_score(rod, &seed);
    state.seed_objective = state.best_objective;
}
