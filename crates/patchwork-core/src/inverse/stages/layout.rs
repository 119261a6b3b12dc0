//! The layout stage: after the refine, the layout with patches added where
//! the target bends more gently than KSA marks (`layout.rs`), refined as
//! the design was; the one with the lower verified shape error, by more
//! than `MARGIN`, is kept. Every layout tried is reported.
//!
//! A design with patches at their smallest and narrowest is then thinned
//! where its error stays above `HIGH_ERROR_PERCENT`, or where two or more
//! of them lie side by side (an overfull train, `layout::overfull`): one of
//! them taken out and its neighbours respaced, refined, kept if the error
//! falls; and again while each round lowers the error, up to
//! `THINNING_ROUNDS` times.
//!
//! A planar design's candidate is tried planar first; when that does not
//! win, again with X and Θ free (inclined patches bend the tube less than
//! axial ones of the same size, which a gentle bend may need). If the free
//! one wins the design is no longer planar, and the report says so.

use super::super::errors::DesignRunError;
use super::super::layout::{LayoutTrial, overfull, thinned, with_gentle_bends};
use super::super::outcome::StageName;
use super::super::planar::flattened;
use super::super::run::{Context, Run};
use super::super::shortfall::HIGH_ERROR_PERCENT;
use super::refine::Refine;
use super::seed::ksa_params;
use crate::curve::shape_error;
use crate::design::Design;
use crate::fe::Simulation;
use crate::inverse::objective::SHAPE_SAMPLES;

/// A layout with more patches must lower the shape error by this fraction
/// to be kept: more patches are more to cut and place. One with fewer is
/// kept when it lowers it at all.
const MARGIN: f64 = 0.05;

/// At most this many patches are taken out of a design with patches at
/// their weakest, one per round while each lowers the error (each a
/// refine of its own).
const THINNING_ROUNDS: usize = 3;

/// The most layouts the stage refines: the gentle-bend layout (planar, then
/// free, for a planar design) and the thinning rounds.
pub const MAX_LAYOUTS: usize = 2 + THINNING_ROUNDS;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layout {
    /// The refine the candidate gets (the run's).
    pub refine: Refine,
}

/// A layout to try: what it is, its patches, whether its refine keeps it
/// planar (X and Θ fixed), and by what fraction it must lower the shape
/// error to be kept.
struct Candidate {
    layout: String,
    design: Design,
    planar: bool,
    margin: f64,
}

/// A candidate refined and verified on the design's mesh.
struct Tried {
    design: Design,
    simulation: Simulation,
    jacobian: Option<nalgebra::DMatrix<f64>>,
    error: f64,
}

impl Layout {
    pub(in super::super) fn run(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
    ) -> Result<(), DesignRunError> {
        let current = run.take_verified("layout")?;
        let mut error = error_of(run, &current);
        run.verified = Some(current);
        run.layouts = vec![LayoutTrial {
            layout: "KSA's (refined)".into(),
            patches: run.design.patches.len(),
            shape_error_percent: error,
            chosen: true,
        }];
        for candidate in candidates(run) {
            if let Some(lower) = self.consider(run, ctx, candidate, error)? {
                error = lower;
                break;
            }
        }
        let full_train = overfull(&run.design, &run.setup.settings.bounds);
        for round in 0..THINNING_ROUNDS {
            // A low error needs no thinning unless a train's patches sit at
            // their weakest side by side; once a patch taken out has
            // lowered the error, the layout was overfull, and the next
            // round is tried whatever the error.
            if round == 0 && error <= HIGH_ERROR_PERCENT && !full_train {
                break;
            }
            let Some(candidate) = thinned_candidate(run) else {
                break;
            };
            match self.consider(run, ctx, candidate, error)? {
                Some(lower) => error = lower,
                None => break,
            }
        }
        Ok(())
    }
}

impl Layout {
    /// Tries `candidate` and records it; adopts it when its shape error is
    /// below `current` by its margin, and then returns that error. Once the
    /// run's time limit has passed, none, untried.
    fn consider(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
        candidate: Candidate,
        current: f64,
    ) -> Result<Option<f64>, DesignRunError> {
        ctx.check_cancelled()?;
        if ctx.out_of_time() {
            return Ok(None);
        }
        let (planar, margin) = (candidate.planar, candidate.margin);
        let mut trial = LayoutTrial {
            layout: candidate.layout.clone(),
            patches: candidate.design.patches.len(),
            shape_error_percent: f64::NAN,
            chosen: false,
        };
        let tried = self.try_layout(run, ctx, candidate)?;
        trial.shape_error_percent = tried.as_ref().map_or(f64::NAN, |t| t.error);
        let better = trial.shape_error_percent < (1.0 - margin) * current;
        let adopted = match (better, tried) {
            (true, Some(tried)) => {
                adopt(run, tried, planar);
                run.layouts.iter_mut().for_each(|l| l.chosen = false);
                trial.chosen = true;
                Some(trial.shape_error_percent)
            }
            _ => None,
        };
        run.layouts.push(trial);
        Ok(adopted)
    }

    /// `candidate` refined like the design and simulated on the mesh the
    /// design was verified on; none when its start does not solve.
    fn try_layout(
        &self,
        run: &mut Run<'_>,
        ctx: &mut Context<'_>,
        candidate: Candidate,
    ) -> Result<Option<Tried>, DesignRunError> {
        let Ok(start) = ctx
            .caches
            .simulate(&candidate.design, &run.setup.verify_model)
        else {
            return Ok(None);
        };
        run.state.evaluations += 1;
        let freedom = run.setup.freedom_for(candidate.planar);
        let start = (candidate.design, start);
        let (refined, solves) =
            self.refine
                .refine_from(run, ctx, start, freedom, StageName::Layout)?;
        run.state.evaluations += solves;
        let simulation = match self.refine.verified_on(run, &refined) == run.verified_on {
            true => Some(refined.simulation),
            false => {
                let model = run.setup.model(run.verified_on);
                run.state.evaluations += 1;
                ctx.caches.simulate(&refined.design, &model).ok()
            }
        };
        Ok(simulation.map(|simulation| Tried {
            error: error_of(run, &simulation),
            design: refined.design,
            simulation,
            jacobian: refined.jacobian,
        }))
    }
}

/// The layouts to try, in order: the design with patches on gentle bends
/// (planar for a planar design, then free).
fn candidates(run: &Run<'_>) -> Vec<Candidate> {
    let setup = &run.setup;
    let Some(gentle) = with_gentle_bends(
        &run.design,
        setup.target,
        setup.tuning.kappa_tol,
        &ksa_params(setup),
        setup.settings.bounds.h_min_mm,
    ) else {
        return vec![];
    };
    let added = gentle.patches.len() - run.design.patches.len();
    let layout = format!("{added} more on gentle bends (refined)");
    let free = Candidate {
        layout: layout.clone(),
        design: gentle.clone(),
        planar: false,
        margin: MARGIN,
    };
    if !setup.input.planar_design {
        return vec![free];
    }
    let circumference = gentle.balloon.circumference();
    let planar = Candidate {
        layout: format!("{added} more on gentle bends, planar (refined)"),
        design: Design {
            patches: flattened(&gentle.patches, circumference),
            ..gentle
        },
        planar: true,
        margin: MARGIN,
    };
    vec![
        planar,
        Candidate {
            layout: format!("{added} more on gentle bends, X and Θ free (refined)"),
            ..free
        },
    ]
}

/// The design less one of its weakest patches (`layout::thinned`), the
/// design's planarity kept.
fn thinned_candidate(run: &Run<'_>) -> Option<Candidate> {
    let (design, removed) = thinned(&run.design, &run.setup.settings.bounds)?;
    Some(Candidate {
        layout: format!(
            "P{removed} (at its smallest) taken out, its neighbours respaced (refined)"
        ),
        design,
        planar: run.setup.input.planar_design,
        margin: 0.0,
    })
}

/// The tried layout as the run's design; a layout refined with X and Θ
/// free ends the design's planarity (if it had any), and the final refine
/// then frees them too.
fn adopt(run: &mut Run<'_>, tried: Tried, planar: bool) {
    run.design = tried.design;
    run.verified = Some(tried.simulation);
    run.jacobian = tried.jacobian;
    run.setup.input.planar_design &= planar;
}

/// The shape error (% of length) of a simulation against the run's target.
fn error_of(run: &Run<'_>, simulation: &Simulation) -> f64 {
    shape_error(&simulation.centreline, run.setup.target, SHAPE_SAMPLES)
        .map_or(f64::INFINITY, |e| e.percent_of_length)
}
