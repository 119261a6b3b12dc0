//! The reach stage: before the search, what one patch makes within the
//! bounds (a table from the FE model on the verification mesh, its solves
//! cached with the run's, the table kept for later runs of the scene by
//! `reach::memo`), and where the target asks for more; the report goes to
//! the observer before the search starts. Its solves (the grid's balloons,
//! none when the table was kept) count in its stage time, not in the
//! search's evaluations.

use super::super::errors::DesignRunError;
use super::super::reach::{ReachTable, WindowLengths, judge, memo};
use super::super::run::{Context, Run};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reach;

impl Reach {
    pub(in super::super) fn run(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
    ) -> Result<(), DesignRunError> {
        let setup = &run.setup;
        let bounds = &setup.settings.bounds;
        let base = &setup.settings.base;
        // The grid's balloons, when the table is computed rather than kept.
        let mut solves = 0;
        let compute = || {
            solves = ReachTable::grid(bounds).len();
            ReachTable::compute(
                base,
                bounds,
                &setup.verify_model,
                ctx.caches,
                setup.settings.threads,
                ctx.cancel,
            )
        };
        let key = memo::key(base, bounds, &setup.verify_model);
        let table = memo::table_for(&key, compute, |t| t.is_complete(bounds))
            .map_err(DesignRunError::Reach)?;
        ctx.check_cancelled()?;
        let lengths = WindowLengths {
            bend_mm: bounds.h_min_mm,
            twist_mm: bounds.h_max_mm,
        };
        let report = judge(setup.target, table, lengths, setup.tuning.kappa_tol);
        ctx.report_reach(&report);
        run.reach = Some(report);
        run.uncounted_solves += solves;
        Ok(())
    }
}
