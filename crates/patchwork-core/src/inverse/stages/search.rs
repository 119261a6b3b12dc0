//! The search: CMA-ES over the free patch variables in the unit cube, each
//! candidate simulated on the search model and scored by the objective;
//! checkpointed after every generation.

use super::super::errors::DesignRunError;
use super::super::incumbent::{Incumbent, Scorer, unit_cube_options};
use super::super::outcome::{SearchEnd, StageName};
use super::super::run::{Context, Run};
use crate::cmaes::Optimizer;

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
        let state = &mut run.state;
        let incumbent = Incumbent::new(
            state.best_objective,
            state.best_patches.clone(),
            run.warm_start.take(),
        );
        let base = state.base.clone();
        let scorer = Scorer {
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
                    self.budget,
                    settings.threads,
                ))
            });
            let ended = optimizer.step(&objective);
            let (generation, sigma) = (optimizer.strategy.generation, optimizer.strategy.sigma);
            state.evaluations = 1 + optimizer.evaluations();
            // A generation evaluated while cancelling saw infinities: drop it.
            ctx.check_cancelled()?;
            let previous_best = state.best_objective;
            (state.best_objective, state.best_patches) = incumbent.best();
            if state.best_objective < previous_best {
                state.improved_at = state.evaluations;
            }
            ctx.report(
                StageName::Search,
                generation,
                state.evaluations,
                state.best_objective,
                sigma,
            );
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
