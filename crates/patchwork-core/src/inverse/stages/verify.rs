//! Verification: the design so far simulated on the verification model (the
//! polish's simulation when it ran), on which the later stages start.

use super::super::errors::DesignRunError;
use super::super::run::{Context, Run};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Verify;

impl Verify {
    pub(in super::super) fn run(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
    ) -> Result<(), DesignRunError> {
        let simulation = match run.polished.take() {
            Some(simulation) => simulation,
            None => ctx
                .caches
                .simulate(&run.design, &run.setup.verify_model)
                .map_err(DesignRunError::Verify)?,
        };
        run.verified = Some(simulation);
        run.verified_on = run.setup.tuning.verify_mesh;
        Ok(())
    }
}
