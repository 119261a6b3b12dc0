//! The refine stage: Levenberg–Marquardt on the shape error on the
//! verification model from the design so far (`refine.rs`), its aim
//! corrected by a finer model when the plan has one (`correction.rs`), which
//! then verifies its result.

use std::sync::atomic::AtomicBool;

use super::super::caches::Caches;
use super::super::correction::refine_corrected;
use super::super::deadline::Deadline;
use super::super::errors::DesignRunError;
use super::super::outcome::{RefineSummary, StageName};
use super::super::refine::{RefineProblem, Refined};
use super::super::run::{Context, Run};
use super::super::variables::Freedom;
use crate::design::Design;
use crate::fe::Simulation;
use crate::fe::mesh::MeshSpec;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Refine {
    /// Solves on the verification model (a linearised Jacobian counts one).
    pub solves: usize,
    /// The finer model that corrects the refine's aim and verifies.
    pub correction: Option<MeshSpec>,
}

impl Refine {
    pub(in super::super) fn run(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
    ) -> Result<(), DesignRunError> {
        if run.space.dimension() == 0 || self.solves == 0 {
            return Ok(());
        }
        let simulation = run.take_verified("refine")?;
        let design = run.design.clone();
        let freedom = run.setup.freedom();
        let start = (design, simulation);
        let (refined, solves) = self.refine_from(run, ctx, start, freedom, StageName::Refine)?;
        let verified_on = self.verified_on(run, &refined);
        run.verified_on = verified_on;
        run.verify_model_state = (refined.verify_model_state).map(|s| (refined.design.clone(), s));
        run.design = refined.design;
        run.verified = Some(refined.simulation);
        run.jacobian = refined.jacobian;
        run.refine = refined.summary;
        run.state.evaluations += solves;
        Ok(())
    }
}

impl Refine {
    /// The refine from `design` (simulated on the verification model as
    /// `simulation`) with `freedom`, and the solves it spent; its progress is
    /// reported as `stage`'s. A design beyond a
    /// fabrication limit (KSA's one long patch, without trains) is brought
    /// within the limits first, so that every design the refine compares,
    /// its start included, is one that can be made.
    pub(super) fn refine_from(
        &self,
        run: &Run<'_>,
        ctx: &mut Context<'_>,
        (mut design, mut simulation): (Design, Simulation),
        freedom: Freedom,
        stage: StageName,
    ) -> Result<(Refined, usize), DesignRunError> {
        let mut spent = 0;
        if let Some(inside) = run.setup.settings.bounds.sizes_within(&design) {
            let model = &run.setup.verify_model;
            if let Ok(solved) = ctx.caches.simulate_from(&inside, model, Some(&simulation)) {
                (design, simulation) = (inside, solved);
                spent += 1;
            }
        }
        let problem = RefineProblem {
            freedom,
            ..refine_problem(run, ctx.cancel, ctx.deadline, ctx.caches)
        };
        let before = run.state.evaluations + spent;
        let (profiles, objective) = (&run.setup.profiles, &run.setup.tuning.objective);
        let mut on_progress = |iteration, evaluations, simulation: &Simulation| {
            let best = profiles.objective_of(simulation, objective);
            ctx.report(stage, iteration, before + evaluations, best, 0.0)
        };
        let refined = match self.correction {
            Some(mesh) => refine_corrected(
                &problem,
                &run.setup.model(mesh),
                design,
                simulation,
                self.solves,
                &mut on_progress,
            )?,
            None => problem.refine(design, simulation, self.solves, None, &mut on_progress)?,
        };
        let solves = spent + refined.summary.map_or(0, |s| s.solves);
        Ok((refined, solves))
    }

    /// The mesh `refined`'s simulation is on: the correction's when the
    /// refine ran corrected (it verifies there), else the verification
    /// model's, which the refine solves on (whatever mesh the run's design
    /// was verified on before).
    pub(super) fn verified_on(&self, run: &Run<'_>, refined: &Refined) -> MeshSpec {
        match (self.correction, refined.summary) {
            (
                Some(mesh),
                Some(RefineSummary {
                    corrected_on_element_mm: Some(_),
                    ..
                }),
            ) => mesh,
            _ => run.setup.tuning.verify_mesh,
        }
    }
}

/// The refine's problem on the run's verification model, its bounds and
/// freedom, with the length free unless the user fixed it.
pub(super) fn refine_problem<'r>(
    run: &'r Run<'_>,
    cancel: &'r AtomicBool,
    deadline: Deadline,
    caches: &'r Caches,
) -> RefineProblem<'r> {
    RefineProblem {
        model: &run.setup.verify_model,
        target: &run.setup.profiles,
        freedom: run.setup.freedom(),
        bounds: &run.bounds,
        free_length: !run.setup.settings.fix_length,
        tolerance: run.setup.tuning.refine_tolerance,
        correction: None,
        threads: run.setup.settings.threads,
        cancel,
        deadline,
        caches,
    }
}
