//! The reach stage: before the search, what one patch makes within the
//! bounds (a table from the FE model on the verification mesh, its solves
//! cached with the run's), and where the target asks for more; the report
//! goes to the observer before the search starts.

use super::super::errors::DesignRunError;
use super::super::reach::{ReachTable, WindowLengths, judge};
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
        let table = ReachTable::compute(
            &setup.settings.base,
            bounds,
            &setup.verify_model,
            ctx.caches,
            setup.settings.threads,
            ctx.cancel,
        )
        .map_err(DesignRunError::Reach)?;
        ctx.check_cancelled()?;
        let lengths = WindowLengths {
            bend_mm: bounds.h_min_mm,
            twist_mm: bounds.h_max_mm,
        };
        let report = judge(setup.target, table, lengths, setup.tuning.kappa_tol);
        ctx.report_reach(&report);
        run.reach = Some(report);
        Ok(())
    }
}
