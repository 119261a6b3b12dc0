//! The layout stage: after the refine, the layout with patches added where
//! the target bends more gently than KSA marks (`layout.rs`), refined as
//! the design was; the one with the lower verified shape error, by more
//! than `MARGIN`, is kept. Both are reported.

use super::super::errors::DesignRunError;
use super::super::layout::{LayoutTrial, with_gentle_bends};
use super::super::run::{Context, Run};
use super::RunStage;
use super::refine::Refine;
use super::seed::ksa_params;
use crate::curve::shape_error;
use crate::fe::Simulation;
use crate::inverse::objective::SHAPE_SAMPLES;

/// The candidate must lower the shape error by this fraction to be kept:
/// more patches are more to cut and place.
const MARGIN: f64 = 0.05;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layout {
    /// The refine the candidate gets (the run's).
    pub refine: Refine,
}

impl RunStage for Layout {
    fn run(&self, run: &mut Run<'_>, ctx: &mut Context<'_>) -> Result<(), DesignRunError> {
        let current = run.take_verified("layout")?;
        let current_error = error_of(run, &current);
        let own = LayoutTrial {
            layout: "KSA's (refined)".into(),
            patches: run.design.patches.len(),
            shape_error_percent: current_error,
            chosen: true,
        };
        let setup = &run.setup;
        let candidate = with_gentle_bends(
            &run.design,
            setup.target,
            setup.tuning.kappa_tol,
            &ksa_params(setup),
        );
        let Some(candidate) = candidate else {
            run.verified = Some(current);
            run.layouts = vec![own];
            return Ok(());
        };
        let added = candidate.patches.len() - run.design.patches.len();
        let mut tried = LayoutTrial {
            layout: format!("{added} more on gentle bends (refined)"),
            patches: candidate.patches.len(),
            shape_error_percent: f64::NAN,
            chosen: false,
        };
        let start = match ctx.caches.simulate(&candidate, &setup.verify_model) {
            Ok(start) => start,
            Err(_) => {
                run.verified = Some(current);
                run.layouts = vec![own, tried];
                return Ok(());
            }
        };
        run.state.evaluations += 1;
        let (refined, solves) = self.refine.refine_from(run, ctx, candidate, start)?;
        run.state.evaluations += solves;
        // Compared on the mesh the design was verified on.
        let simulation = match self.refine.verified_on(run, &refined) == run.verified_on {
            true => Some(refined.simulation),
            false => {
                let model = run.setup.tuning.model(run.verified_on);
                run.state.evaluations += 1;
                ctx.caches.simulate(&refined.design, &model).ok()
            }
        };
        tried.shape_error_percent = simulation.as_ref().map_or(f64::NAN, |s| error_of(run, s));
        let better = tried.shape_error_percent < (1.0 - MARGIN) * current_error;
        match (better, simulation) {
            (true, Some(simulation)) => {
                run.design = refined.design;
                run.verified = Some(simulation);
                run.jacobian = refined.jacobian;
                tried.chosen = true;
                run.layouts = vec![
                    LayoutTrial {
                        chosen: false,
                        ..own
                    },
                    tried,
                ];
            }
            _ => {
                run.verified = Some(current);
                run.layouts = vec![own, tried];
            }
        }
        Ok(())
    }
}

/// The shape error (% of length) of a simulation against the run's target.
fn error_of(run: &Run<'_>, simulation: &Simulation) -> f64 {
    shape_error(&simulation.centreline, run.setup.target, SHAPE_SAMPLES)
        .map_or(f64::INFINITY, |e| e.percent_of_length)
}
