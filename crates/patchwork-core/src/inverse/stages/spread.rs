//! The spread: how far the verified design's centreline moves under the
//! user's fabrication and operating tolerances (`crate::spread`): the
//! sources linearised at once and the large ones solved both ways on the
//! verification model (graded 1 mm in every preset), warm-started from the
//! design's state there. The spread is a difference
//! of states, which the verification model resolves as well as the finer
//! ones that correct and verify a design's shape, at a third of their
//! solve's cost. A spread that cannot be found (a solve fails) leaves the
//! design as it is and says why. With `monte_carlo` designs (fine's
//! preset), the linear estimate is then checked by sampling
//! (`crate::spread::monte_carlo`), on the same model, in parallel.

use super::super::errors::DesignRunError;
use super::super::run::{Context, Run};
use crate::fe::Simulation;
use crate::spread::{Against, Nominal, Spread, monte_carlo, spread_of};

/// Its sources: `SOURCES_PER_PATCH` per patch and three for the balloon,
/// linearised at once, the large ones solved both ways; and the
/// Monte-Carlo check's designs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpreadStage {
    /// Designs of the Monte-Carlo check (0: none).
    pub monte_carlo: usize,
}

impl SpreadStage {
    pub(in super::super) fn run(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
    ) -> Result<(), DesignRunError> {
        ctx.check_cancelled()?;
        let simulation = match on_verify_model(run, ctx) {
            Ok(simulation) => simulation,
            Err(why) => {
                run.spread_failed = Some(why);
                return Ok(());
            }
        };
        let options = &run.setup.verify_model;
        let nominal = Nominal {
            design: &run.design,
            simulation: &simulation,
            options,
            patterns: &ctx.caches.patterns,
        };
        // Measured against the target as given once the run is assessed.
        let against = Against {
            length_mm: run.setup.target.length(),
            nominal_shape_error_percent: None,
        };
        let settings = run.setup.settings;
        let (tolerances, threads) = (&settings.tolerances, settings.threads);
        match spread_of(&nominal, &against, tolerances, threads) {
            Ok(mut spread) => {
                check_by_sampling(&mut spread, &nominal, self.monte_carlo, run, ctx)?;
                run.state.evaluations += spread.solves;
                run.spread = Some(spread);
                run.spread_state = Some(simulation);
            }
            Err(error) => run.spread_failed = Some(error.to_string()),
        }
        Ok(())
    }
}

/// The Monte-Carlo check of `spread` with `samples` designs (none: 0),
/// seeded by the run's seed, its solves added to the spread's.
pub(super) fn check_by_sampling(
    spread: &mut Spread,
    nominal: &Nominal,
    samples: usize,
    run: &Run<'_>,
    ctx: &Context<'_>,
) -> Result<(), DesignRunError> {
    if samples == 0 {
        return Ok(());
    }
    let settings = run.setup.settings;
    let draw = (samples, settings.seed);
    let (tolerances, threads) = (&settings.tolerances, settings.threads);
    let sampled = monte_carlo(nominal, spread, tolerances, draw, threads, ctx.cancel);
    ctx.check_cancelled()?;
    spread.solves += samples;
    spread.monte_carlo = Some(sampled);
    Ok(())
}

/// The run's design on the verification model: its verified state where it
/// was verified there, else solved from it (counted); why not, where that
/// fails.
pub(super) fn on_verify_model(run: &mut Run<'_>, ctx: &Context<'_>) -> Result<Simulation, String> {
    let verified = run
        .verified
        .as_ref()
        .ok_or("the design was not verified before the spread")?;
    if run.verified_on == run.setup.tuning.verify_mesh {
        return Ok(verified.clone());
    }
    let options = &run.setup.verify_model;
    let solved = (ctx.caches).simulate_from(&run.design, options, Some(verified));
    let solved = solved.map_err(|e| format!("the design on the verification model: {e}"))?;
    run.state.evaluations += 1;
    Ok(solved)
}
