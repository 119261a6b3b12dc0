//! The executor: runs a plan's stages in order on one run and one context
//! (cancel flag, clock, observer), announcing each to the observer by its
//! name as it begins, then assembles the outcome from the verified
//! simulation.

use std::sync::atomic::AtomicBool;
use std::time::Duration;

use super::assess::{as_given, verified};
use super::caches::Caches;
use super::checkpoint::DesignCheckpoint;
use super::clearing::target_to_aim_at;
use super::errors::DesignRunError;
use super::input::prepare;
use super::limits::at_limits;
use super::outcome::{DesignOutcome, DesignProgress, SearchEnd, StageName, StageTime, TimeLimited};
use super::plan::Plan;
use super::run::{Context, Observer, Run, Setup};
use super::shortfall::{RunFacts, shortfalls};
use crate::cmaes::Termination;
use crate::curve::Curve;

/// Runs the plan from the start, with caches of its own; `observer` hears
/// every stage and generation.
pub fn design(
    target: &Curve,
    plan: &Plan,
    cancel: &AtomicBool,
    mut observer: &mut dyn FnMut(&DesignProgress),
) -> Result<DesignOutcome, DesignRunError> {
    let caches = Caches::default();
    design_resumable(target, plan, None, &caches, cancel, &mut observer)
}

/// Runs the plan, from `resume` when given (a checkpoint of a run of the
/// same target and plan), handing checkpoints to the observer as it goes.
/// A cancelled run's last checkpoint is the generation before the
/// cancellation. `caches` may be shared with other runs (a repeated run
/// finds its solves there); they change no result.
pub fn design_resumable(
    target: &Curve,
    plan: &Plan,
    resume: Option<DesignCheckpoint>,
    caches: &Caches,
    cancel: &AtomicBool,
    observer: &mut dyn Observer,
) -> Result<DesignOutcome, DesignRunError> {
    let earlier_s = resume.as_ref().map_or(0.0, |c| c.elapsed_s);
    let limit_s = plan.settings().time_limit_s;
    let mut ctx = Context::new(cancel, caches, observer, earlier_s, limit_s);
    let given = target;
    let (prepared, mut input) = prepare(given, plan.settings().smoothing, plan.tuning().kappa_tol)
        .map_err(DesignRunError::Input)?;
    let plans = (plan.settings(), plan.tuning());
    let (target, cleared) = target_to_aim_at(prepared, &input, plans, caches);
    input.cleared = cleared;
    let setup = Setup::new(&target, input, plan.settings(), plan.tuning());
    let (evaluations, best) = resume
        .as_ref()
        .map_or((0, f64::NAN), |c| (c.evaluations, c.best_objective));
    ctx.entering(StageName::Seed, evaluations, best);
    let started = ctx.elapsed_s();
    let mut run = plan.seed().run(setup, resume, &mut ctx)?;
    let mut times = vec![StageTime {
        stage: StageName::Seed,
        seconds: ctx.elapsed_s() - started,
        evaluations: run.state.evaluations - evaluations,
    }];
    note_time_limit(&mut run, StageName::Seed, &ctx);
    for stage in plan.stages() {
        ctx.check_cancelled()?;
        if skipped_for_time(&mut run, stage.name()) {
            continue;
        }
        let (started, before) = (ctx.elapsed_s(), run.state.evaluations);
        ctx.entering(stage.name(), before, run.state.best_objective);
        stage.run(&mut run, &mut ctx)?;
        times.push(StageTime {
            stage: stage.name(),
            seconds: ctx.elapsed_s() - started,
            evaluations: run.state.evaluations - before + std::mem::take(&mut run.uncounted_solves),
        });
        note_time_limit(&mut run, stage.name(), &ctx);
    }
    outcome(run, given, times, &ctx)
}

/// Records `stage` as the one the time limit passed in, if it passed
/// there (the stage stopped at its next step after it).
fn note_time_limit(run: &mut Run<'_>, stage: StageName, ctx: &Context<'_>) {
    if let (None, Some(limit_s), true) = (
        &run.time_limited,
        run.setup.settings.time_limit_s,
        ctx.out_of_time(),
    ) {
        run.time_limited = Some(TimeLimited {
            limit_s,
            reached_in: stage,
            skipped: Vec::new(),
        });
    }
}

/// Whether `stage` is skipped because the time limit has passed: every
/// stage but the verification, which the outcome needs. A skipped stage
/// whose report the outcome carries (the spread, the final and robust
/// refines, a search on the rod) says why it has none.
fn skipped_for_time(run: &mut Run<'_>, stage: StageName) -> bool {
    let Some(limited) = run.time_limited.as_mut() else {
        return false;
    };
    if stage == StageName::Verify {
        return false;
    }
    limited.skipped.push(stage);
    let why = format!(
        "the run's time limit ({} s) passed before the {} stage",
        limited.limit_s,
        stage.as_str()
    );
    match stage {
        StageName::Spread => run.spread_failed = Some(why),
        StageName::FinalRefine => run.final_refine_skipped = Some(why),
        StageName::Robust => run.robust_skipped = Some(why),
        StageName::Search if run.setup.tuning.rod_search => run.rod_skipped = Some(why),
        _ => {}
    }
    true
}

/// The outcome of a run whose stages are done; `given` is the curve as the
/// user gave it.
fn outcome(
    mut run: Run<'_>,
    given: &Curve,
    stage_times: Vec<StageTime>,
    ctx: &Context<'_>,
) -> Result<DesignOutcome, DesignRunError> {
    let simulation = run.take_verified("outcome")?;
    let (metrics, profiles) = verified(
        &run.setup.profiles,
        &simulation,
        &run.setup.tuning.objective,
    );
    let as_given = as_given(&simulation.centreline, given, &run.setup.input, &metrics);
    let at_limits = at_limits(&run.design.patches, &run.setup.settings.bounds);
    let shortfalls = shortfalls(&RunFacts {
        shape_error_percent: metrics.shape_error_percent,
        patches: run.design.patches.len(),
        reach: run.reach.as_ref(),
        at_limits: &at_limits,
        budget_spent: run.termination == SearchEnd::Optimizer(Termination::MaxEvaluations),
        layouts: &run.layouts,
        robust_from_percent: (run.robust.as_ref())
            .filter(|r| r.kept)
            .map(|r| r.nominal_design.shape_error_percent),
        time_limit_s: run.time_limited.as_ref().map(|t| t.limit_s),
    });
    let spread = run
        .spread
        .map(|s| s.against_given(as_given.shape_error_percent));
    let state = run.state;
    Ok(DesignOutcome {
        at_limits,
        profiles,
        inflated_length_mm: simulation.inflated_length_mm,
        uninflated_length_to_cut_mm: run.design.balloon.length_mm,
        seed_design: crate::design::Design {
            patches: state.seed_patches.clone(),
            ..state.base.clone()
        },
        design: run.design,
        simulation,
        metrics,
        seed_objective: state.seed_objective,
        search_objective: state.best_objective,
        target_length_mm: run.setup.target.length(),
        evaluations: state.evaluations,
        termination: run.termination,
        refine: run.refine,
        final_refine: run.final_refine,
        final_refine_skipped: run.final_refine_skipped,
        verified_on: run.verified_on,
        input: run.setup.input,
        as_given,
        given: given.clone(),
        reach: run.reach,
        layouts: run.layouts,
        shortfalls,
        spread,
        spread_failed: run.spread_failed,
        robust: run.robust,
        robust_skipped: run.robust_skipped,
        rod_skipped: run.rod_skipped,
        stage_times,
        elapsed: Duration::from_secs_f64(ctx.elapsed_s()),
        time_limited: run.time_limited,
    })
}

#[cfg(test)]
#[path = "time_limit_tests.rs"]
mod tests;
