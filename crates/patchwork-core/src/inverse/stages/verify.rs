//! Verification: the design so far simulated on the verification model (the
//! polish's simulation when it ran), on which the later stages start.

use super::super::errors::DesignRunError;
use super::super::outcome::Stage;
use super::super::run::{Context, Run};
use super::RunStage;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Verify;

impl RunStage for Verify {
    fn run(&self, run: &mut Run<'_>, ctx: &mut Context<'_>) -> Result<(), DesignRunError> {
        ctx.entering(Stage::Verify, &run.state);
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
