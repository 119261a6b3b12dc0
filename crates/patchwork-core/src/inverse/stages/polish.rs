//! Coarse-to-fine: after the search on the coarse model, a short CMA-ES run on
//! the verification model, started from the search's best design with a small
//! step. The coarse model bends the tube differently from the fine one (on a
//! sparse scene the 2 mm and 1 mm meshes' tips differ by several percent of
//! the length), so the coarse optimum is only near the fine one; the polish
//! closes that gap at the fine model's price per evaluation.

use std::sync::atomic::Ordering;

use super::super::errors::DesignRunError;
use super::super::incumbent::{Incumbent, Scorer, unit_cube_options};
use super::super::outcome::StageName;
use super::super::run::{Context, Run};
use crate::cmaes::Optimizer;
use crate::design::{Design, Patch};
use crate::fe::Simulation;

/// The polish stage: CMA-ES on the verification model from the search's best
/// design (off in every preset: the refine does the job better).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Polish {
    /// Evaluations, the start's included.
    pub budget: usize,
}

impl Polish {
    pub(in super::super) fn run(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
    ) -> Result<(), DesignRunError> {
        if run.space.dimension() == 0 || self.budget <= 1 {
            return Ok(());
        }
        let state = &run.state;
        let start = match &state.optimizer {
            Some(o) if o.best_fitness <= state.best_objective => o.best_x.clone(),
            _ => run.space.seed_point(),
        };
        let spent = state.evaluations;
        let scorer = Scorer {
            space: &run.space,
            base: &state.base,
            model: &run.setup.verify_model,
            profiles: &run.setup.profiles,
            objective: &run.setup.tuning.objective,
            warm_starts: run.setup.tuning.warm_starts,
            cancel: ctx.cancel,
            deadline: ctx.deadline,
            caches: ctx.caches,
            rod: None,
        };
        let polished = polish(
            &scorer,
            start,
            self.budget,
            run.setup.settings.seed.wrapping_add(1),
            run.setup.settings.threads,
            &mut |generation, evaluations, best, sigma| {
                ctx.report(
                    StageName::Polish,
                    generation,
                    spent + evaluations,
                    best,
                    sigma,
                )
            },
        )?;
        run.design.patches = polished.patches;
        run.polished = polished.simulation;
        run.state.evaluations += polished.evaluations;
        Ok(())
    }
}

/// Initial step of the polish in the unit cube (the search's default is
/// `INITIAL_STEP`, 0.2): it starts from a good design.
const POLISH_SIGMA: f64 = 0.05;

/// The polish's result: the best design on the fine model (the start itself
/// if nothing beat it), its simulation there (reused as the verification),
/// and the evaluations spent.
struct Polished {
    pub patches: Vec<Patch>,
    pub simulation: Option<Simulation>,
    pub evaluations: usize,
}

/// Runs the polish from unit-cube point `start` with `budget` evaluations
/// (the start's own included); `on_generation(generation, evaluations, best,
/// σ)` hears every generation.
fn polish(
    scorer: &Scorer<'_>,
    start: Vec<f64>,
    budget: usize,
    seed: u64,
    threads: usize,
    on_generation: &mut dyn FnMut(usize, usize, f64, f64),
) -> Result<Polished, DesignRunError> {
    let start_design = Design {
        patches: scorer.space.patches(&start),
        ..scorer.base.clone()
    };
    let (objective, state) = scorer.score(&start_design, None);
    let incumbent = Incumbent::new(objective, start_design.patches, state);
    let mut optimizer = Optimizer::new(unit_cube_options(
        start,
        POLISH_SIGMA,
        seed,
        budget,
        threads,
    ));
    let objective = |u: &[f64]| scorer.evaluate(u, &incumbent);
    loop {
        let ended = optimizer.step(&objective);
        if scorer.cancel.load(Ordering::Relaxed) {
            return Err(DesignRunError::Cancelled);
        }
        on_generation(
            optimizer.strategy.generation,
            1 + optimizer.evaluations(),
            incumbent.best().0,
            optimizer.strategy.sigma,
        );
        if ended.is_some() || scorer.deadline.passed() {
            break;
        }
    }
    let evaluations = 1 + optimizer.evaluations();
    let (patches, simulation) = incumbent.into_best();
    Ok(Polished {
        patches,
        simulation,
        evaluations,
    })
}
