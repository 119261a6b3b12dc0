//! What every stage works with: the run's state (the checkpoint, the design
//! so far and its verified simulation, what each stage reported) and the
//! context (cancel flag, clock, observer).

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use nalgebra::DMatrix;

use super::caches::Caches;
use super::checkpoint::DesignCheckpoint;
use super::deadline::Deadline;
use super::errors::DesignRunError;
use super::input::InputReport;
use super::layout::LayoutTrial;
use super::objective::TargetProfiles;
use super::outcome::{
    DesignProgress, RefineSummary, RobustSummary, SearchEnd, StageName, TimeLimited,
};
use super::planar::flattened;
use super::reach::ReachReport;
use super::settings::UserSettings;
use super::tuning::{FinalRefineSettings, Tuning};
use super::variables::{DesignSpace, Freedom, VariableBounds};
use crate::cmaes::Termination;
use crate::curve::Curve;
use crate::design::{Design, Patch};
use crate::fe::mesh::MeshSpec;
use crate::fe::{SimulateOptions, Simulation};
use crate::spread::Spread;

/// How a caller watches a run: progress of every stage and generation, a
/// checkpoint after the seed and after every search generation, and the
/// reach report before the search. Any `FnMut(&DesignProgress)` is an
/// observer that hears only the progress.
pub trait Observer {
    fn progress(&mut self, progress: &DesignProgress);

    /// A stage begins (`progress.stage`), with the run's evaluations and
    /// best objective so far; the executor announces every stage of the
    /// plan, the seed first. By default, a progress report.
    fn stage(&mut self, progress: &DesignProgress) {
        self.progress(progress);
    }

    fn checkpoint(&mut self, checkpoint: &DesignCheckpoint) {
        let _ = checkpoint;
    }

    /// What the balloon can make against the target, as soon as it is known.
    fn reach(&mut self, report: &ReachReport) {
        let _ = report;
    }
}

impl<F: FnMut(&DesignProgress)> Observer for F {
    fn progress(&mut self, progress: &DesignProgress) {
        self(progress)
    }
}

/// What the executor hands every stage besides the run: the cancel flag
/// (polled before every evaluation), the caches, the clock and the time
/// limit, and the observer.
pub struct Context<'a> {
    pub cancel: &'a AtomicBool,
    /// When the run's time limit passes.
    pub deadline: Deadline,
    /// The solves the run may share with others.
    pub caches: &'a Caches,
    observer: &'a mut dyn Observer,
    started: Instant,
    /// Seconds spent by earlier processes on a resumed run.
    earlier_s: f64,
}

impl<'a> Context<'a> {
    pub fn new(
        cancel: &'a AtomicBool,
        caches: &'a Caches,
        observer: &'a mut dyn Observer,
        earlier_s: f64,
        time_limit_s: Option<f64>,
    ) -> Self {
        Context {
            cancel,
            deadline: Deadline::after(time_limit_s, earlier_s),
            caches,
            observer,
            started: Instant::now(),
            earlier_s,
        }
    }

    /// Wall time of the run so far, over every process that ran it.
    pub fn elapsed_s(&self) -> f64 {
        self.earlier_s + self.started.elapsed().as_secs_f64()
    }

    /// Whether the run's time limit has passed.
    pub fn out_of_time(&self) -> bool {
        self.deadline.passed()
    }

    pub fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// `Err(Cancelled)` once the run is cancelled.
    pub fn check_cancelled(&self) -> Result<(), DesignRunError> {
        match self.cancelled() {
            true => Err(DesignRunError::Cancelled),
            false => Ok(()),
        }
    }

    pub fn report(
        &mut self,
        stage: StageName,
        generation: usize,
        evaluations: usize,
        best_objective: f64,
        sigma: f64,
    ) {
        let progress = DesignProgress {
            stage,
            generation,
            evaluations,
            best_objective,
            sigma,
            elapsed_s: self.elapsed_s(),
        };
        self.observer.progress(&progress);
    }

    /// Announces the start of `stage`, after `evaluations` with the best
    /// objective so far (the executor's, before each stage).
    pub(super) fn entering(&mut self, stage: StageName, evaluations: usize, best_objective: f64) {
        let progress = DesignProgress {
            stage,
            generation: 0,
            evaluations,
            best_objective,
            sigma: 0.0,
            elapsed_s: self.elapsed_s(),
        };
        self.observer.stage(&progress);
    }

    /// Hands the reach report to the observer.
    pub fn report_reach(&mut self, report: &ReachReport) {
        self.observer.reach(report);
    }

    /// Stamps the state with the elapsed time and hands it to the observer.
    pub fn checkpoint(&mut self, state: &mut DesignCheckpoint) {
        state.elapsed_s = self.elapsed_s();
        self.observer.checkpoint(state);
    }
}

/// What a run knows before its seed: the target, the settings and the
/// models they define.
pub struct Setup<'a> {
    /// The target as prepared for the design (smoothed).
    pub target: &'a Curve,
    /// What was done to the target as given.
    pub input: InputReport,
    pub settings: &'a UserSettings,
    pub tuning: &'a Tuning,
    pub profiles: TargetProfiles,
    pub search_model: SimulateOptions,
    pub verify_model: SimulateOptions,
}

impl<'a> Setup<'a> {
    /// `patches` as this run's design has them: flattened for a planar
    /// design, as they are otherwise.
    pub fn laid_out(&self, patches: Vec<Patch>, circumference: f64) -> Vec<Patch> {
        match self.input.planar_design {
            true => flattened(&patches, circumference),
            false => patches,
        }
    }

    /// The variables the search and the refines may change: the user's,
    /// less X and Θ while the design is planar.
    pub fn freedom(&self) -> Freedom {
        self.freedom_for(self.input.planar_design)
    }

    /// The user's freedom, less X and Θ for a `planar` layout.
    pub fn freedom_for(&self, planar: bool) -> Freedom {
        match planar {
            true => Freedom {
                x: false,
                theta: false,
                ..self.settings.freedom
            },
            false => self.settings.freedom,
        }
    }

    pub fn new(
        target: &'a Curve,
        mut input: InputReport,
        settings: &'a UserSettings,
        tuning: &'a Tuning,
    ) -> Setup<'a> {
        input.planar_design = input.planar && tuning.planar_designs;
        input.keep_clear = tuning.keep_clear;
        let mut profiles = TargetProfiles::new(target, tuning.rings, &tuning.objective);
        profiles.keep_clear = tuning.keep_clear;
        Setup {
            target,
            input,
            settings,
            tuning,
            profiles,
            search_model: threaded(tuning.model(tuning.search_mesh), settings),
            verify_model: threaded(tuning.model(tuning.verify_mesh), settings),
        }
    }

    /// The run's model on `mesh`: the tuning's, assembling on the run's
    /// threads where a solve runs alone (`SimulateOptions::threads`).
    pub fn model(&self, mesh: MeshSpec) -> SimulateOptions {
        threaded(self.tuning.model(mesh), self.settings)
    }

    /// The final refine's model (`last`'s Newton limits), on the run's
    /// threads.
    pub fn final_model(&self, last: &FinalRefineSettings) -> SimulateOptions {
        threaded(last.model(self.tuning), self.settings)
    }
}

/// `model` assembling on the run's threads.
fn threaded(model: SimulateOptions, settings: &UserSettings) -> SimulateOptions {
    SimulateOptions {
        threads: settings.threads,
        ..model
    }
}

/// A design run's state between stages. The seed stage creates it; each
/// later stage reads what it needs and leaves its result.
pub struct Run<'a> {
    pub setup: Setup<'a>,
    /// What a checkpoint holds: the balloon, the seed, the search's state
    /// and best design, the evaluations spent.
    pub state: DesignCheckpoint,
    /// The free variables around the seed, and the bounds they were built
    /// from (the whole balloon for an unseeded start).
    pub space: DesignSpace,
    pub bounds: VariableBounds,
    /// The incumbent's inflated state on the search model, to warm the
    /// search's solves (only with warm starts).
    pub warm_start: Option<Simulation>,
    pub termination: SearchEnd,
    /// The design so far: the search's best, then each later stage's.
    pub design: Design,
    /// The polish's best design simulated on the verification model (the
    /// verification reuses it).
    pub polished: Option<Simulation>,
    /// `design` simulated on `verified_on`, once the verify stage ran.
    pub verified: Option<Simulation>,
    pub verified_on: MeshSpec,
    /// A design and its state on the verification model, where a refine
    /// verified it on a finer model: the spread starts from it while the
    /// design is still that one, instead of solving it again.
    pub verify_model_state: Option<(Design, Simulation)>,
    pub refine: Option<RefineSummary>,
    /// The refine's last Jacobian, per unit of each variable, for the final
    /// refine to start from.
    pub jacobian: Option<DMatrix<f64>>,
    pub final_refine: Option<RefineSummary>,
    pub final_refine_skipped: Option<String>,
    /// The reach stage's report, once it ran.
    pub reach: Option<ReachReport>,
    /// Solves of the stage under way that `state.evaluations` (the
    /// search's count, which the search sets) leaves out: the reach
    /// table's. The executor adds them to the stage's time and clears them.
    pub uncounted_solves: usize,
    /// The layouts the layout stage tried (none when it did not run).
    pub layouts: Vec<LayoutTrial>,
    /// The spread stage's answer, or why it has none.
    pub spread: Option<Spread>,
    pub spread_failed: Option<String>,
    /// The design's state on the verification model the spread was found
    /// from, for the robust stage to start from.
    pub spread_state: Option<Simulation>,
    /// The robust stage's summary, or why it did not run.
    pub robust: Option<RobustSummary>,
    pub robust_skipped: Option<String>,
    /// Why a search planned on the rod ran on FE.
    pub rod_skipped: Option<String>,
    /// What the time limit cut short, once it passed.
    pub time_limited: Option<TimeLimited>,
}

impl<'a> Run<'a> {
    /// A run whose seed is known: `state` from the seed stage or a
    /// checkpoint, `space` and `bounds` around its seed.
    pub fn new(
        setup: Setup<'a>,
        state: DesignCheckpoint,
        (space, bounds): (DesignSpace, VariableBounds),
    ) -> Run<'a> {
        Run {
            verified_on: setup.tuning.verify_mesh,
            setup,
            design: state.best_design(),
            state,
            space,
            bounds,
            warm_start: None,
            termination: SearchEnd::Optimizer(Termination::MaxEvaluations),
            polished: None,
            verified: None,
            verify_model_state: None,
            refine: None,
            jacobian: None,
            final_refine: None,
            final_refine_skipped: None,
            reach: None,
            uncounted_solves: 0,
            layouts: Vec::new(),
            spread: None,
            spread_failed: None,
            spread_state: None,
            robust: None,
            robust_skipped: None,
            rod_skipped: None,
            time_limited: None,
        }
    }

    /// The verified simulation of `design`, taken to be replaced; an error
    /// if no verify stage ran before the caller's (a plan the resolver does
    /// not build).
    pub fn take_verified(&mut self, stage: &str) -> Result<Simulation, DesignRunError> {
        self.verified.take().ok_or_else(|| {
            DesignRunError::Plan(format!(
                "the {stage} stage needs the verify stage before it"
            ))
        })
    }
}
