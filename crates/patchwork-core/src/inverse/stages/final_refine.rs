//! The final refine: the refine once more on a finer model still (standard's
//! and fine's uniform 0.5 mm mesh), from the refine's result and its last
//! Jacobian, with what the refine budget has left; that model then verifies.
//! If it cannot solve the refine's result, the refine's result stands,
//! verified on its own model, and the outcome says why.

use super::super::errors::DesignRunError;
use super::super::outcome::StageName;
use super::super::refine::RefineProblem;
use super::super::run::{Context, Run};
use super::super::tuning::FinalRefineSettings;
use super::refine::refine_problem;
use crate::fe::Simulation;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FinalRefine {
    pub refine: FinalRefineSettings,
    /// Solves of the refine and this stage together.
    pub shared_solves: usize,
}

impl FinalRefine {
    pub(in super::super) fn run(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
    ) -> Result<(), DesignRunError> {
        let mesh = self.refine.mesh;
        let finest = run.setup.final_model(&self.refine);
        let previous = run.take_verified("final refine")?;
        let start = match ctx
            .caches
            .simulate_from(&run.design, &finest, Some(&previous))
        {
            Ok(start) => start,
            Err(error) => {
                run.final_refine_skipped = Some(format!(
                    "the {mesh} model could not solve the refine's result ({error}); \
                     the design is the refine's, verified on its {} model",
                    run.verified_on
                ));
                run.verified = Some(previous);
                return Ok(());
            }
        };
        run.verified_on = mesh;
        let done = run.refine.map_or(0, |r| r.solves);
        let budget = self.shared_solves.saturating_sub(done);
        // The design's own patches: the layout stage may have added some
        // to a seed that had none.
        if run.design.patches.is_empty() || budget == 0 {
            run.verified = Some(start);
            return Ok(());
        }
        let jacobian = run.jacobian.take();
        let problem = RefineProblem {
            model: &finest,
            ..refine_problem(run, ctx.cancel, ctx.deadline, ctx.caches)
        };
        let spent = run.state.evaluations;
        let (profiles, objective) = (&run.setup.profiles, &run.setup.tuning.objective);
        let mut on_progress = |iteration, evaluations, simulation: &Simulation| {
            let best = profiles.objective_of(simulation, objective);
            ctx.report(
                StageName::FinalRefine,
                iteration,
                spent + evaluations,
                best,
                0.0,
            )
        };
        let refined = problem.refine(
            run.design.clone(),
            start,
            budget,
            jacobian,
            &mut on_progress,
        )?;
        run.design = refined.design;
        run.verified = Some(refined.simulation);
        run.final_refine = refined.summary;
        run.state.evaluations += refined.summary.map_or(0, |s| s.solves);
        Ok(())
    }
}
