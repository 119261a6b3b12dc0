//! The robust stage (tuning `robust`): the design refined for the shape
//! error expected under the user's tolerances rather than the nominal one
//! (`refine::robust`), on the verification model, from the spread stage's
//! answer. It weighs the spread's largest sources: those that make up
//! `WEIGHED_SHARE` of its square, at most `MAX_SOURCES` (each costs a solve
//! per evaluation). Its result is verified on the model the design was
//! verified on, with the finer model's gap as the refine's correction, and
//! its spread found again over every source; it replaces the design only if
//! its expected shape error over every source (nominal and spread in
//! quadrature) is lower. The report gives both designs' nominal and
//! expected errors either way. The Monte-Carlo check, when planned, is of
//! the design that stands.

use super::super::errors::DesignRunError;
use super::super::objective::SHAPE_SAMPLES;
use super::super::outcome::{Expected, RobustSummary, StageName};
use super::super::refine::RobustRefined;
use super::super::run::{Context, Run};
use super::refine::refine_problem;
use super::spread::{check_by_sampling, on_verification, on_verify_model, spread_found};
use crate::curve::shape_error;
use crate::fe::{SimulateOptions, Simulation};
use crate::spread::{Source, Spread};

/// The most sources the robust refine weighs.
pub const MAX_SOURCES: usize = 4;
/// The share of the spread's square the weighed sources make up.
pub const WEIGHED_SHARE: f64 = 0.9;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobustStage {
    /// FE solves of the robust refine.
    pub solves: usize,
    /// Designs of the Monte-Carlo check of the design that stands (0: none).
    pub monte_carlo: usize,
}

impl RobustStage {
    pub(in super::super) fn run(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
    ) -> Result<(), DesignRunError> {
        ctx.check_cancelled()?;
        let Some(before) = run.spread.take() else {
            let why = run
                .spread_failed
                .as_deref()
                .unwrap_or("no spread stage ran");
            run.robust_skipped = Some(format!("the design has no spread to weigh: {why}"));
            return Ok(());
        };
        // The spread's own state of the design on the verification model.
        let on_model = match run.spread_state.take() {
            Some(state) => Ok(state),
            None => on_verify_model(run, ctx),
        };
        let verified = run.take_verified("robust")?;
        let outcome = match &on_model {
            Err(why) => Ok(Err(why.clone())),
            Ok(_) if run.space.dimension() == 0 => {
                Ok(Err("the design has no free variables".into()))
            }
            Ok(on_model) => self.refined(run, ctx, &before, (&verified, on_model.clone())),
        };
        let (simulation, mut spread, on_model) = match outcome? {
            Err(why) => {
                run.robust_skipped = Some(why);
                (verified, before, on_model.ok())
            }
            Ok(Candidate { summary, .. }) if !summary.kept => {
                run.robust = Some(summary);
                (verified, before, on_model.ok())
            }
            Ok(c) => {
                run.robust = Some(c.summary);
                run.design = c.design;
                (c.verified, c.spread, Some(c.on_model))
            }
        };
        // The check of the design that stands, on the verification model.
        if let Some(on_model) = on_model {
            let nominal = on_verification(run, ctx, &run.design, &on_model);
            let solves = spread.solves;
            check_by_sampling(&mut spread, &nominal, self.monte_carlo, run, ctx)?;
            run.state.evaluations += spread.solves - solves;
        }
        run.spread = Some(spread);
        run.verified = Some(simulation);
        Ok(())
    }

    /// The robust refine of the run's design from its `verified` state and
    /// its state on the verification model, the result verified and its
    /// spread found; why not, where it cannot be.
    fn refined(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
        before: &Spread,
        (verified, on_model): (&Simulation, Simulation),
    ) -> Result<Result<Candidate, String>, DesignRunError> {
        let sources = weighed(before, &run.setup.settings.tolerances);
        let problem = refine_problem(run, ctx.cancel, ctx.deadline, ctx.caches);
        let offset = match run.verified_on == run.setup.tuning.verify_mesh {
            true => None,
            false => (problem.residuals_of(verified))
                .zip(problem.residuals_of(&on_model))
                .map(|(fine, here)| fine - here),
        };
        let spent = run.state.evaluations;
        let (profiles, objective) = (&run.setup.profiles, &run.setup.tuning.objective);
        let mut on_progress = |iteration, evaluations, simulation: &Simulation| {
            let best = profiles.objective_of(simulation, objective);
            ctx.report(StageName::Robust, iteration, spent + evaluations, best, 0.0)
        };
        let budget = (self.solves, offset.as_ref());
        let design = run.design.clone();
        let refined =
            problem.refine_robust(design, on_model, &sources, budget, &mut on_progress)?;
        let Some(refined) = refined else {
            return Ok(Err(
                "the design's copies at the tolerances could not be solved or aligned".into(),
            ));
        };
        run.state.evaluations += refined.solves;
        Ok(self.verified(run, ctx, before, verified, refined, &sources))
    }

    /// The robust refine's result verified as the design was, its spread
    /// over every source, and both designs' figures.
    fn verified(
        &self,
        run: &mut Run<'_>,
        ctx: &Context<'_>,
        before: &Spread,
        verified: &Simulation,
        refined: RobustRefined,
        sources: &[(Source, f64)],
    ) -> Result<Candidate, String> {
        let RobustRefined {
            design, scenarios, ..
        } = &refined;
        let on_model = scenarios.nominal.clone();
        let candidate = match run.verified_on == run.setup.tuning.verify_mesh {
            true => on_model.clone(),
            false => (ctx.caches)
                .simulate_from(design, &verified_model(run), Some(verified))
                .map_err(|e| format!("its result on the {} model: {e}", run.verified_on))?,
        };
        let nominal = on_verification(run, ctx, design, &on_model);
        let patch_mesh = run.setup.tuning.spread_patch_mesh;
        let spread = spread_found(&run.setup, ctx.caches, nominal, patch_mesh)
            .map_err(|e| format!("its spread: {e}"))?;
        run.state.evaluations += spread.solves + 1;
        let target = &run.setup.profiles.curve;
        let figures = |sim: &Simulation, spread: &Spread| {
            Expected {
                shape_error_percent: shape_error(&sim.centreline, target, SHAPE_SAMPLES)
                    .map_or(f64::INFINITY, |e| e.percent_of_length),
                spread_percent: spread.rms_percent,
                expected_percent: 0.0,
            }
            .with_expected()
        };
        let (nominal_design, robust_design) =
            (figures(verified, before), figures(&candidate, &spread));
        let summary = RobustSummary {
            sources: (sources.iter().step_by(2))
                .map(|(s, _)| s.label())
                .collect(),
            kept: robust_design.expected_percent < nominal_design.expected_percent,
            nominal_design,
            robust_design,
            weighed_before_percent: refined.expected_before_percent,
            weighed_after_percent: refined.expected_after_percent,
            iterations: refined.iterations,
            solves: refined.solves + spread.solves + 1,
        };
        Ok(Candidate {
            design: refined.design,
            verified: candidate,
            on_model,
            spread,
            summary,
        })
    }
}

/// The robust refine's verified result.
struct Candidate {
    design: crate::design::Design,
    verified: Simulation,
    /// Its state on the verification model.
    on_model: Simulation,
    spread: Spread,
    summary: RobustSummary,
}

/// The spread's largest sources, each at its tolerance either way (the
/// robust refine's two copies of each): those that make up `WEIGHED_SHARE`
/// of its square, at most `MAX_SOURCES`.
fn weighed(spread: &Spread, tolerances: &crate::spread::Tolerances) -> Vec<(Source, f64)> {
    let total: f64 = spread.contributors.iter().map(|c| c.rms_mm.powi(2)).sum();
    let mut share = 0.0;
    let mut sources = Vec::new();
    for c in spread.contributors.iter().take(MAX_SOURCES) {
        if share >= WEIGHED_SHARE * total {
            break;
        }
        share += c.rms_mm.powi(2);
        let tolerance = c.source.tolerance(tolerances).0;
        sources.extend([(c.source, tolerance), (c.source, -tolerance)]);
    }
    sources
}

/// The options of the model the run's design is verified on: the final
/// refine's (with its Newton limits) or the run's own.
fn verified_model(run: &Run<'_>) -> SimulateOptions {
    match run.setup.tuning.final_refine {
        Some(last) if last.mesh == run.verified_on => run.setup.final_model(&last),
        _ => run.setup.model(run.verified_on),
    }
}
