//! The spread: how far the verified design's centreline moves under the
//! user's fabrication and operating tolerances (`crate::spread`): the
//! sources linearised at once and the large ones solved both ways,
//! warm-started from the design's state. The balloon's three sources
//! (pressure, wall, modulus) are found on the verification model (graded
//! 1 mm in every preset), from the design's state there; each patch's on
//! the coarser `patch_mesh` (graded 2 mm in every preset), from the
//! design's state there. The spread is a difference of states, which the
//! verification model resolves as well as the finer ones that correct and
//! verify a design's shape, at a third of their solve's cost; a patch's
//! change is a local bend, which the 2 mm model resolves within 6 % of the
//! verification model at about a fifth of its cost, while the balloon's
//! sources move the whole tube's stretch, which it overstates by up to a
//! quarter (docs/studies.md, "The spread's solves"). A spread that cannot
//! be found (a solve fails) leaves the design as it is and says why; a
//! design that does not solve on the patches' model has every source found
//! on the verification model. With `monte_carlo` designs (fine's preset),
//! the linear estimate is then checked by sampling
//! (`crate::spread::monte_carlo`) on the verification model, in parallel.

use super::super::errors::DesignRunError;
use super::super::run::{Context, Run, Setup};
use crate::design::Design;
use crate::fe::mesh::MeshSpec;
use crate::fe::{SimulateOptions, Simulation};
use crate::inverse::caches::Caches;
use crate::spread::{
    Against, Models, Nominal, Source, Spread, SpreadError, monte_carlo, spread_of,
};

/// Its sources: `SOURCES_PER_PATCH` per patch and three for the balloon,
/// linearised at once, the large ones solved both ways; and the
/// Monte-Carlo check's designs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpreadStage {
    /// Designs of the Monte-Carlo check (0: none).
    pub monte_carlo: usize,
    /// The model each patch's sources are found on (none: the
    /// verification model).
    pub patch_mesh: Option<MeshSpec>,
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
        let nominal = on_verification(run, ctx, &run.design, &simulation);
        match spread_found(&run.setup, ctx.caches, nominal, self.patch_mesh) {
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

/// `design` and `simulation`, its state on the run's verification model,
/// as a spread's nominal (its moved designs sharing the run's patterns).
pub(super) fn on_verification<'a>(
    run: &'a Run<'_>,
    ctx: &'a Context<'_>,
    design: &'a Design,
    simulation: &'a Simulation,
) -> Nominal<'a> {
    Nominal {
        design,
        simulation,
        options: &run.setup.verify_model,
        patterns: &ctx.caches.patterns,
    }
}

/// The spread of `nominal` (a design and its state on the verification
/// model) at the run's tolerances and against its target: each patch's
/// sources on `patch_mesh`'s model where given and the design solves
/// there (that solve counted among the spread's), the balloon's (and,
/// where not, every source) on the verification model.
pub(super) fn spread_found(
    setup: &Setup<'_>,
    caches: &Caches,
    nominal: Nominal<'_>,
    patch_mesh: Option<MeshSpec>,
) -> Result<Spread, SpreadError> {
    let (design, on_model) = (nominal.design, nominal.simulation);
    let settings = setup.settings;
    let patch_mesh = patch_mesh.filter(|_| Source::any_patch(design, &settings.tolerances));
    let patch_model: Option<SimulateOptions> = patch_mesh.map(|mesh| setup.model(mesh));
    let coarse = (patch_model.as_ref()).map(|model| {
        let solved = caches.simulate_from(design, model, Some(on_model));
        (solved.ok(), model)
    });
    let patches = coarse
        .as_ref()
        .and_then(|(s, model)| Some((s.as_ref()?, *model)));
    let models = Models::pair(nominal, patches);
    // Measured against the target as given once the run is assessed.
    let against = Against {
        length_mm: setup.target.length(),
        nominal_shape_error_percent: None,
    };
    let mut spread = spread_of(&models, &against, &settings.tolerances, settings.threads)?;
    spread.solves += usize::from(coarse.is_some());
    Ok(spread)
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
/// was verified there, the refine's state of it there where the refine
/// verified it on a finer model, else solved from its verified state
/// (counted); why not, where that fails.
pub(super) fn on_verify_model(run: &mut Run<'_>, ctx: &Context<'_>) -> Result<Simulation, String> {
    let verified = run
        .verified
        .as_ref()
        .ok_or("the design was not verified before the spread")?;
    if run.verified_on == run.setup.tuning.verify_mesh {
        return Ok(verified.clone());
    }
    if let Some((design, state)) = &run.verify_model_state
        && *design == run.design
    {
        return Ok(state.clone());
    }
    let options = &run.setup.verify_model;
    let solved = (ctx.caches).simulate_from(&run.design, options, Some(verified));
    let solved = solved.map_err(|e| format!("the design on the verification model: {e}"))?;
    run.state.evaluations += 1;
    Ok(solved)
}
