//! The search: CMA-ES over the free patch variables in the unit cube, each
//! candidate simulated on the search model and scored by the objective;
//! checkpointed after every generation. The search model is the rod
//! (`crate::rod`, with `rod_search`: its table of one-patch FE solves on
//! the verification model found or kept by `rod_model.rs`, the search run
//! in corrected rounds by `rod_search.rs`, where the budget holds two of
//! them), else FE on the search mesh.

use super::super::errors::DesignRunError;
use super::super::incumbent::{Incumbent, Scorer, unit_cube_options};
use super::super::outcome::{SearchEnd, StageName};
use super::super::run::{Context, Run};
use super::generations::{Pause, Units};
use super::rod_model::{RodModel, rod_model};
use super::rod_search::{MIN_BUDGET, search_on_rod};
use crate::cmaes::Optimizer;
use crate::inverse::DesignCheckpoint;

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
        let rod = match run.setup.tuning.rod_search {
            true if self.budget < MIN_BUDGET => {
                run.rod_skipped = Some(format!(
                    "the search's budget of {} evaluations is less than the {MIN_BUDGET} that two of the rod's corrected rounds take",
                    self.budget
                ));
                None
            }
            true => rod_model(run, ctx)?,
            false => None,
        };
        let ended = match rod {
            Some(rod) => {
                let mut generations =
                    |run: &mut Run<'_>, ctx: &mut Context<'_>, rod: &RodModel, units| {
                        self.generations(run, ctx, Some(rod), units)
                    };
                search_on_rod(self.budget, run, ctx, rod, &mut generations)?
            }
            None => {
                // The run solved the seed on the search model.
                let units = Units {
                    scale: 1,
                    before: 1,
                    pause_at: None,
                };
                match self.generations(run, ctx, None, units)? {
                    Pause::Ended(end) => end,
                    Pause::Round => unreachable!("a search on FE has no rounds"),
                }
            }
        };
        run.termination = ended;
        run.design = run.state.best_design();
        Ok(())
    }

    /// CMA-ES generations on `rod` (FE on the search model if none) from
    /// the optimiser the state holds (a new one from the space's seed point
    /// if none), until the search ends or `units.pause_at`.
    pub(super) fn generations(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
        rod: Option<&RodModel>,
        units: Units,
    ) -> Result<Pause, DesignRunError> {
        let (settings, tuning) = (run.setup.settings, run.setup.tuning);
        let state = &mut run.state;
        let base = state.base.clone();
        let scorer = Scorer {
            rod,
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
        let incumbent = Incumbent::new(
            state.best_objective,
            state.best_patches.clone(),
            run.warm_start.take(),
        );
        let objective = |u: &[f64]| scorer.evaluate(u, &incumbent);
        // The optimiser lives in the checkpoint state, so what is
        // checkpointed is what runs.
        loop {
            ctx.check_cancelled()?;
            let optimizer = state.optimizer.get_or_insert_with(|| {
                Optimizer::new(unit_cube_options(
                    run.space.seed_point(),
                    self.initial_step,
                    settings.seed,
                    self.budget * units.scale,
                    settings.threads,
                ))
            });
            let ended = optimizer.step(&objective);
            let (generation, sigma) = (optimizer.strategy.generation, optimizer.strategy.sigma);
            state.evaluations = units.before + optimizer.evaluations().div_ceil(units.scale);
            // A generation evaluated while cancelling saw infinities: drop it.
            ctx.check_cancelled()?;
            take_best(state, &incumbent);
            let (evaluations, best) = (state.evaluations, state.best_objective);
            ctx.report(StageName::Search, generation, evaluations, best, sigma);
            ctx.checkpoint(state);
            if let Some(ended) = ended {
                return Ok(Pause::Ended(SearchEnd::Optimizer(ended)));
            }
            if self.patience > 0 && state.evaluations >= state.improved_at + self.patience {
                return Ok(Pause::Ended(SearchEnd::STALLED));
            }
            if ctx.out_of_time() {
                return Ok(Pause::Ended(SearchEnd::TIME_LIMIT));
            }
            if units.pause_at.is_some_and(|at| state.evaluations >= at) {
                return Ok(Pause::Round);
            }
        }
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
