//! The search on the rod, in rounds: CMA-ES on the rod corrected at the
//! seed; every [`ROUND`] evaluations, and when the search ends, its best
//! design is solved on the verification model and the rod corrected there
//! (iterated output space mapping: the correction holds near where it was
//! made, and the search moves away from the seed). Each such solve is one
//! evaluation of the search's budget, which holds the last one. The
//! search's result is the best design by its corrected score among those
//! solved (the seed's included), so a round in which the rod misled the
//! search does not replace a better design FE has seen. The rounds' state
//! (`RodRounds`) is checkpointed with the optimiser's.
//!
//! The seed is scored on the rod before the first generation, so that the
//! search keeps it only where the rod finds nothing better, and
//! `ROD_EVALUATIONS` rod evaluations count as one of the budget and the
//! patience.

use super::super::errors::DesignRunError;
use super::super::incumbent::FAILED_SOLVE_PENALTY;
use super::super::outcome::SearchEnd;
use super::super::run::{Context, Run};
use super::generations::{Pause, Units};
use super::rod_model::RodModel;
use crate::cmaes::Termination;
use crate::design::Design;
use crate::inverse::{ROD_EVALUATIONS, RodRounds};

/// Evaluations of the search between two corrections of the rod.
const ROUND: usize = 30;

/// The smallest budget a search runs on the rod with: two rounds. With
/// less it runs on FE: one generation on the rod (ten rod evaluations for
/// a budget of 3) finds less than the same budget of FE solves (the noisy
/// helix of `tests/stress.rs`: 1.98 % against 0.05 %).
pub(super) const MIN_BUDGET: usize = 2 * ROUND;

/// The search's CMA-ES generations on a rod, until the search ends or the
/// units' pause.
pub(super) type Generations<'a> = dyn FnMut(&mut Run<'_>, &mut Context<'_>, &RodModel, Units) -> Result<Pause, DesignRunError>
    + 'a;

/// Runs the search (`generations`, `budget` evaluations) on `rod`
/// (corrected where the state's rounds say, else at the state's best) in
/// corrected rounds; leaves the best corrected design in the run's state.
pub(super) fn search_on_rod(
    budget: usize,
    run: &mut Run<'_>,
    ctx: &mut Context<'_>,
    mut rod: RodModel,
    generations: &mut Generations<'_>,
) -> Result<SearchEnd, DesignRunError> {
    if run.state.rod.is_none() {
        let score = rod_score(run, &rod, &run.state.best_design());
        let state = &mut run.state;
        (state.best_objective, state.seed_objective) = (score, score);
        state.rod = Some(RodRounds {
            corrected_at: state.best_patches.clone(),
            next_at: state.evaluations + ROUND,
            kept_objective: score,
            kept_patches: state.best_patches.clone(),
        });
    }
    // The budget holds the last round's correction.
    let last = budget.saturating_sub(1);
    let ended = loop {
        let pause_at = rounds(run).next_at.min(last);
        // A resumed search may be due a correction before its next
        // generation, as the interrupted one was.
        let pause = match run.state.evaluations < pause_at {
            true => {
                let units = Units {
                    scale: ROD_EVALUATIONS,
                    before: run.state.evaluations - spent_by_optimizer(run),
                    pause_at: Some(pause_at),
                };
                generations(run, ctx, &rod, units)?
            }
            false => Pause::Round,
        };
        correct(run, ctx, &mut rod);
        match pause {
            Pause::Ended(end) => break end,
            Pause::Round if pause_at >= last => {
                break SearchEnd::Optimizer(Termination::MaxEvaluations);
            }
            Pause::Round => {}
        }
    };
    let kept = rounds(run);
    let (objective, patches) = (kept.kept_objective, kept.kept_patches.clone());
    (run.state.best_objective, run.state.best_patches) = (objective, patches);
    Ok(ended)
}

/// The state's rounds (set before the first generation).
fn rounds<'a>(run: &'a Run<'_>) -> &'a RodRounds {
    run.state
        .rod
        .as_ref()
        .expect("the rounds begin with the search")
}

/// The state's best design solved on the verification model (one
/// evaluation) and the rod corrected there; its corrected score, which is
/// FE's centreline's (the failed-solve penalty if the solve fails), is the
/// best objective of the next round, and kept if it is the lowest yet.
fn correct(run: &mut Run<'_>, ctx: &Context<'_>, rod: &mut RodModel) {
    let best = run.state.best_design();
    run.state.evaluations += 1;
    let score = match ctx.caches.simulate(&best, &run.setup.verify_model) {
        Ok(fe) => {
            rod.correct_at(&best, &fe);
            rod_score(run, rod, &best)
        }
        Err(_) => FAILED_SOLVE_PENALTY,
    };
    let evaluations = run.state.evaluations;
    run.state.best_objective = score;
    let rounds = run
        .state
        .rod
        .as_mut()
        .expect("the rounds begin with the search");
    rounds.corrected_at = best.patches.clone();
    rounds.next_at = evaluations + ROUND;
    if score < rounds.kept_objective {
        (rounds.kept_objective, rounds.kept_patches) = (score, best.patches);
    }
}

/// `design`'s objective on `rod`.
fn rod_score(run: &Run<'_>, rod: &RodModel, design: &Design) -> f64 {
    let tuning = run.setup.tuning;
    let score = rod.score(design, &run.setup.profiles, &tuning.objective);
    score.unwrap_or(FAILED_SOLVE_PENALTY)
}

/// Evaluations the state's optimiser has spent (none before it starts).
fn spent_by_optimizer(run: &Run<'_>) -> usize {
    let optimizer = run.state.optimizer.as_ref();
    optimizer.map_or(0, |o| o.evaluations().div_ceil(ROD_EVALUATIONS))
}
