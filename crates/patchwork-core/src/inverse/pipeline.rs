//! The design pipeline: KSA seed → CMA-ES with the FE model in the loop →
//! verification of the best design on a finer mesh.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use super::evaluation_cache::simulate_cached;
use super::incumbent::{Incumbent, Scorer, score};
use super::limits::{AtLimit, at_limits};
use super::objective::{ObjectiveOptions, SHAPE_SAMPLES, TargetProfiles};
use super::polish::polish;
use super::refine::{RefineProblem, RefineSummary};
use super::report::Profiles;
use super::variables::{DesignSpace, Freedom, VariableBounds, VariableError};
use crate::cmaes::{Bounds, Optimizer, RunOptions, Termination};
use crate::curve::{Curve, dtw, shape_error};
use crate::design::{Design, DesignError, Patch};
use crate::fe::mesh::MeshSpec;
use crate::fe::newton::NewtonOptions;
use crate::fe::tube_theory::inflate_tube;
use crate::fe::{SimulateError, SimulateOptions, Simulation, simulate_from};
use crate::ksa::{KsaError, KsaParams, Stretch, ksa};

/// Objective value given to a candidate whose forward solve failed: worse than
/// any design that solves (a straight tube scores 1 on the profiles; the shape
/// term adds at most its weight times the RMS distance over the length).
pub const FAILED_SOLVE_PENALTY: f64 = 1e6;

/// Default initial CMA-ES step in the unit cube.
pub const INITIAL_STEP: f64 = 0.2;

/// Everything a design run needs besides the target curve.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignRequest {
    /// Balloon, patch material and pressure (its `patches` are ignored).
    pub base: Design,
    /// Keep `base.balloon.length_mm`; otherwise the length is chosen so the
    /// inflated balloon is as long as the target.
    pub fix_length: bool,
    pub freedom: Freedom,
    pub bounds: VariableBounds,
    pub objective: ObjectiveOptions,
    /// Forward evaluations for the search.
    pub budget: usize,
    /// The search ends early once this many evaluations have passed without
    /// improving its best design (0: never). On the Hilbert curve and the
    /// pancake the draft search never beats the KSA seed, and the refine ends
    /// at the same design either way; on the spring it improves three times
    /// in its first 97 evaluations (BENCHMARKS.md).
    pub search_patience: usize,
    pub seed: u64,
    pub threads: usize,
    pub search_mesh: MeshSpec,
    pub verify_mesh: MeshSpec,
    pub rings: usize,
    /// KSA's curvature tolerance, merge distance and default width.
    pub kappa_tol: f64,
    pub merge_mm: f64,
    pub width_mm: f64,
    /// Start each search solve from the best design's inflated state instead
    /// of the candidate's own kinematic estimate. Off by default: for
    /// CMA-ES-sized steps the kinematic start converges in fewer Newton
    /// iterations (BENCHMARKS.md: quick suite 7–16 % faster cold, same
    /// results; Hilbert candidates 26–32 iterations cold against 31–39 warm).
    pub warm_starts: bool,
    /// Evaluations of the coarse-to-fine polish: after the search, a short
    /// CMA-ES run on the verification model from the search's best design
    /// (0: none, the default, and in every preset: the refine does the job
    /// better). The search model is coarser and bends the tube differently;
    /// the polish corrects for that. Not checkpointed: a resumed run repeats it.
    pub polish_budget: usize,
    /// Solves of the refine: after the length correction, Levenberg–Marquardt
    /// on the shape error on the verification model, from the best design,
    /// over its free variables and (unless `fix_length`) the balloon length
    /// (0: none). Each iteration costs one solve per variable for the
    /// Jacobian and one or more for the step. Not checkpointed.
    pub refine_budget: usize,
    /// A finer model that corrects the refine's aim and verifies its result
    /// (see `correction.rs`): the refine's solves stay on the verification
    /// model, and each correction round costs one solve of this one. None:
    /// the refine and the verification are the verification model's.
    pub correction_mesh: Option<MeshSpec>,
    /// A last refine on a finer model still, from the refine's result (and
    /// its Jacobian), on which the design is then verified: standard's and
    /// fine's uniform 0.5 mm stage. It spends what `refine_budget` has left
    /// after the refine on the verification model. None: the refine's
    /// result stands.
    pub final_refine: Option<FinalRefine>,
    /// CMA-ES's initial step σ₀ in the unit cube of the free variables (each
    /// variable's range maps to [0, 1]).
    pub initial_step: f64,
    /// Where CMA-ES starts: from KSA's patches (the method), or unseeded.
    pub start: Start,
}

/// The final refine: Levenberg–Marquardt on the shape error on `mesh`, from
/// the result of the refine on the verification model, which may spend at
/// most `staging_solves` of the refine budget (the final one the rest).
/// `newton` limits its model's solves (the presets: the default). If that
/// model cannot solve the refine's result, the run does not fail: the
/// refine's result stands, verified on its own model, and the outcome says
/// why (`DesignOutcome::final_refine_skipped`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FinalRefine {
    pub mesh: MeshSpec,
    pub staging_solves: usize,
    pub newton: NewtonOptions,
}

/// Where the search starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Start {
    /// KSA's patches, with bounds as windows around them.
    #[default]
    Ksa,
    /// Unseeded, to measure what the seed is worth: as many patches as KSA
    /// found, spread evenly along the balloon with mid-range sizes, X = 0 and
    /// Θ = 0, each free over the whole balloon (X around the whole
    /// circumference, Y along the whole length, Θ within its limit). The
    /// balloon is the seeded run's (its length corrected from a simulation
    /// of KSA's seed), so that both starts search the same balloon.
    Even,
}

impl std::str::FromStr for Start {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        match text {
            "ksa" => Ok(Start::Ksa),
            "even" => Ok(Start::Even),
            _ => Err(format!("unknown start {text:?}: choose one of ksa, even")),
        }
    }
}

impl Default for DesignRequest {
    fn default() -> Self {
        DesignRequest {
            base: Design::reference(vec![]),
            fix_length: false,
            freedom: Freedom::default(),
            bounds: VariableBounds::default(),
            objective: ObjectiveOptions::default(),
            budget: 600,
            search_patience: 0,
            seed: 1,
            threads: 1,
            search_mesh: MeshSpec::uniform(2.0),
            verify_mesh: MeshSpec::uniform(1.0),
            rings: 72,
            kappa_tol: 0.01,
            merge_mm: 20.0,
            width_mm: 1.5,
            warm_starts: false,
            polish_budget: 0,
            refine_budget: 0,
            correction_mesh: None,
            final_refine: None,
            initial_step: INITIAL_STEP,
            start: Start::Ksa,
        }
    }
}

impl DesignRequest {
    /// Checks the search's own options (the objective and CMA-ES's step),
    /// naming the field.
    pub fn validate_search(&self) -> Result<(), DesignRunError> {
        self.objective
            .validate()
            .map_err(|(field, reason)| DesignRunError::Options {
                field: format!("objective.{field}"),
                reason,
            })?;
        let step = self.initial_step;
        if !(step.is_finite() && step > 0.0 && step <= 1.0) {
            return Err(DesignRunError::Options {
                field: "initial_step".into(),
                reason: format!(
                    "must be in (0, 1] (a fraction of each variable's range), got {step}"
                ),
            });
        }
        Ok(())
    }
}

/// The pipeline's stages, as reported to observers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    Seed,
    Search,
    /// The coarse-to-fine polish on the verification model.
    Polish,
    Verify,
    /// Levenberg–Marquardt on the shape error on the verification model.
    Refine,
}

/// Progress reported to the observer.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DesignProgress {
    pub stage: Stage,
    pub generation: usize,
    pub evaluations: usize,
    pub best_objective: f64,
    pub sigma: f64,
    pub elapsed_s: f64,
}

/// How well the final design matches the target (on the verification mesh).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    pub objective: f64,
    pub dtw_curvature: f64,
    pub dtw_torsion: f64,
    pub shape_error_mm: f64,
    pub shape_error_percent: f64,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DesignRunError {
    #[error("invalid design options: {0}")]
    Design(DesignError),
    #[error("{0}")]
    Ksa(KsaError),
    #[error("{0}")]
    Variables(VariableError),
    /// A search option out of range: the field (`objective.shape_weight`,
    /// `initial_step`, …) and why.
    #[error("{field}: {reason}")]
    Options { field: String, reason: String },
    #[error("the bare balloon has no stable inflated state at {pressure_kpa} kPa")]
    NoTubeState { pressure_kpa: f64 },
    #[error("the seed design could not be simulated: {0}")]
    Seed(SimulateError),
    #[error("the best design failed verification on the fine mesh: {0}")]
    Verify(SimulateError),
    #[error("cancelled")]
    Cancelled,
}

/// The result of a design run.
#[derive(Debug, Clone)]
pub struct DesignOutcome {
    pub design: Design,
    pub seed_design: Design,
    /// The verified simulation of `design`.
    pub simulation: Simulation,
    /// Metrics of the verified simulation (fine mesh).
    pub metrics: Metrics,
    /// Target and verified κ, τ on the objective's sampling.
    pub profiles: Profiles,
    /// Objective of the KSA seed and of the best design, both on the search
    /// model (comparable with each other, not with `metrics.objective`).
    pub seed_objective: f64,
    pub search_objective: f64,
    pub target_length_mm: f64,
    pub inflated_length_mm: f64,
    /// The uninflated balloon length to cut (= design.balloon.length_mm).
    pub uninflated_length_to_cut_mm: f64,
    pub evaluations: usize,
    pub termination: Termination,
    /// What the refine did; none when it did not run.
    pub refine: Option<RefineSummary>,
    /// What the final refine on the finest model did (standard, fine); none
    /// when the request has none, or when it could not start.
    pub final_refine: Option<RefineSummary>,
    /// Why a requested final refine did not run: its model could not solve
    /// the refine's result. The design, simulation and metrics are then the
    /// refine's, on `verified_on`.
    pub final_refine_skipped: Option<String>,
    /// The mesh of `simulation`, on which `metrics` were taken: the final
    /// refine's, the correction's (when the refine ran corrected) or the
    /// verification model's.
    pub verified_on: MeshSpec,
    /// Patch sizes and angles on (or beyond) a fabrication limit of the
    /// request's bounds: the target may want what the bounds forbid.
    pub at_limits: Vec<AtLimit>,
    pub elapsed: Duration,
}

/// The state of a design run once its seed is known, and again after every
/// search generation: enough to resume the run where it stopped (a service
/// killed mid-run resumes from its last checkpoint, not from scratch).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DesignCheckpoint {
    /// Balloon, materials and pressure, with the balloon length chosen.
    pub base: Design,
    /// KSA seed on that balloon.
    pub seed_patches: Vec<Patch>,
    pub seed_objective: f64,
    /// The search's state; `None` before its first generation.
    pub optimizer: Option<Optimizer>,
    /// Best design so far on the search model.
    pub best_objective: f64,
    pub best_patches: Vec<Patch>,
    /// Forward evaluations spent, the seed's included.
    pub evaluations: usize,
    /// `evaluations` when the best design last improved (the seed: 1).
    #[serde(default)]
    pub improved_at: usize,
    /// Wall time spent on the run so far, over every process that ran it.
    pub elapsed_s: f64,
}

/// How a caller watches and steers a run.
pub struct DesignHooks<'a> {
    /// Polled before every evaluation and between generations.
    pub cancel: &'a AtomicBool,
    /// Hears every stage and generation.
    pub observer: &'a mut dyn FnMut(&DesignProgress),
    /// Receives a checkpoint after the seed and after every generation.
    pub checkpoint: &'a mut dyn FnMut(&DesignCheckpoint),
}

/// Runs the pipeline from the start, without checkpoints.
pub fn design(
    target: &Curve,
    request: &DesignRequest,
    cancel: &AtomicBool,
    observer: &mut dyn FnMut(&DesignProgress),
) -> Result<DesignOutcome, DesignRunError> {
    let hooks = DesignHooks {
        cancel,
        observer,
        checkpoint: &mut |_| {},
    };
    design_resumable(target, request, None, hooks)
}

/// Runs the pipeline, from `resume` when given (a checkpoint of a run of the
/// same target and request), reporting checkpoints as it goes. A cancelled
/// run's last checkpoint is the generation before the cancellation.
pub fn design_resumable(
    target: &Curve,
    request: &DesignRequest,
    resume: Option<DesignCheckpoint>,
    hooks: DesignHooks<'_>,
) -> Result<DesignOutcome, DesignRunError> {
    let DesignHooks {
        cancel,
        observer,
        checkpoint,
    } = hooks;
    let started = Instant::now();
    let earlier = resume.as_ref().map_or(0.0, |c| c.elapsed_s);
    let elapsed = || earlier + started.elapsed().as_secs_f64();
    let report =
        |stage, generation, evaluations, best, sigma, observer: &mut dyn FnMut(&DesignProgress)| {
            observer(&DesignProgress {
                stage,
                generation,
                evaluations,
                best_objective: best,
                sigma,
                elapsed_s: elapsed(),
            })
        };
    let mut base = Design {
        patches: vec![],
        ..request.base.clone()
    };
    base.validate().map_err(DesignRunError::Design)?;
    request.validate_search()?;
    let search = SimulateOptions {
        mesh: request.search_mesh,
        rings: request.rings,
        ..SimulateOptions::default()
    };
    let verify = SimulateOptions {
        mesh: request.verify_mesh,
        rings: request.rings,
        ..SimulateOptions::default()
    };
    let profiles = TargetProfiles::new(target, request.rings, &request.objective);
    let scorer = |space, base, model| Scorer {
        space,
        base,
        model,
        profiles: &profiles,
        objective: &request.objective,
        warm_starts: request.warm_starts,
        cancel,
    };
    let evaluate = |design: &Design, warm: Option<&Simulation>| {
        score(design, &search, &profiles, &request.objective, warm)
    };

    let (mut state, warm_start) = match resume {
        Some(mut state) => {
            // A checkpoint from before the patience existed does not know
            // when its best last improved: count from the resume, so the
            // search is not stopped at once.
            if state.improved_at == 0 {
                state.improved_at = state.evaluations;
            }
            // The incumbent's state warms the next solves, as it did before
            // (one extra solve, only when warm starts are on).
            let warm = if request.warm_starts {
                let incumbent = Design {
                    patches: state.best_patches.clone(),
                    ..state.base.clone()
                };
                evaluate(&incumbent, None).1
            } else {
                None
            };
            (state, warm)
        }
        None => {
            report(Stage::Seed, 0, 0, f64::NAN, 0.0, observer);
            base = seeded_balloon(target, base, request, &verify)?;
            if request.start == Start::Even {
                base.patches = spread_evenly(&base, base.patches.len(), &request.bounds);
            }
            let seed_patches = base.patches.clone();
            base.patches.clear();
            let seed_design = Design {
                patches: seed_patches.clone(),
                ..base.clone()
            };
            let (seed_objective, seed_sim) = evaluate(&seed_design, None);
            let state = DesignCheckpoint {
                base,
                best_patches: seed_patches.clone(),
                seed_patches,
                seed_objective,
                optimizer: None,
                best_objective: seed_objective,
                evaluations: 1,
                improved_at: 1,
                elapsed_s: elapsed(),
            };
            checkpoint(&state);
            (state, seed_sim)
        }
    };
    let base = state.base.clone();
    let length = base.balloon.length_mm;
    let bounds = match request.start {
        Start::Ksa => request.bounds,
        Start::Even => request.bounds.spanning(length, base.balloon.radius_mm),
    };
    let space = DesignSpace::new(state.seed_patches.clone(), request.freedom, &bounds, length)
        .map_err(DesignRunError::Variables)?;
    let mut termination = Termination::MaxEvaluations;
    if space.dimension() > 0 && request.budget > 1 {
        let incumbent =
            Incumbent::new(state.best_objective, state.best_patches.clone(), warm_start);
        let stage = scorer(&space, &base, &search);
        let objective = |u: &[f64]| stage.evaluate(u, &incumbent);
        // The optimiser lives in the checkpoint state, so what is checkpointed
        // is what runs.
        let ended = loop {
            if cancel.load(Ordering::Relaxed) {
                return Err(DesignRunError::Cancelled);
            }
            let optimizer = state
                .optimizer
                .get_or_insert_with(|| Optimizer::new(search_options(&space, request)));
            let ended = optimizer.step(&objective);
            let (generation, sigma) = (optimizer.strategy.generation, optimizer.strategy.sigma);
            state.evaluations = 1 + optimizer.evaluations();
            // A generation evaluated while cancelling saw infinities: drop it.
            if cancel.load(Ordering::Relaxed) {
                return Err(DesignRunError::Cancelled);
            }
            let previous_best = state.best_objective;
            (state.best_objective, state.best_patches) = incumbent.best();
            if state.best_objective < previous_best {
                state.improved_at = state.evaluations;
            }
            report(
                Stage::Search,
                generation,
                state.evaluations,
                state.best_objective,
                sigma,
                observer,
            );
            state.elapsed_s = elapsed();
            checkpoint(&state);
            if let Some(ended) = ended {
                break ended;
            }
            let patience = request.search_patience;
            if patience > 0 && state.evaluations >= state.improved_at + patience {
                break Termination::Stalled;
            }
        };
        termination = ended;
    }

    let mut best = Design {
        patches: state.best_patches.clone(),
        ..base.clone()
    };
    // The polish's best is already simulated on the verification model.
    let mut verified_best = None;
    if space.dimension() > 0 && request.polish_budget > 1 {
        let start = match &state.optimizer {
            Some(o) if o.best_fitness <= state.best_objective => o.best_x.clone(),
            _ => space.seed_point(),
        };
        let spent = state.evaluations;
        let polished = polish(
            &scorer(&space, &base, &verify),
            start,
            request.polish_budget,
            request.seed.wrapping_add(1),
            request.threads,
            &mut |generation, evaluations, best, sigma| {
                report(
                    Stage::Polish,
                    generation,
                    spent + evaluations,
                    best,
                    sigma,
                    observer,
                )
            },
        )?;
        best.patches = polished.patches;
        verified_best = polished.simulation;
        state.evaluations += polished.evaluations;
    }
    report(
        Stage::Verify,
        0,
        state.evaluations,
        state.best_objective,
        0.0,
        observer,
    );
    let mut simulation = match verified_best {
        Some(simulation) => simulation,
        None => simulate_cached(&best, &verify).map_err(DesignRunError::Verify)?,
    };
    // The length was chosen for the seed; the best design's patches stretch
    // differently. Correct it once more (patch positions and lengths scale
    // with it) and verify the corrected design.
    let ratio = target.length() / simulation.inflated_length_mm;
    if !request.fix_length && (ratio - 1.0).abs() > LENGTH_TOLERANCE {
        stretch_balloon(&mut best, ratio);
        simulation = simulate_cached(&best, &verify).map_err(DesignRunError::Verify)?;
    }
    let problem = RefineProblem {
        model: &verify,
        target: &profiles,
        freedom: request.freedom,
        bounds: &bounds,
        free_length: !request.fix_length,
        correction: None,
        threads: request.threads,
        cancel,
    };
    let spent = state.evaluations;
    let mut on_progress = |iteration, evaluations, simulation: &Simulation| {
        let objective = profiles.objective(&simulation.centreline, &request.objective);
        report(
            Stage::Refine,
            iteration,
            spent + evaluations,
            objective,
            0.0,
            observer,
        )
    };
    // With a final refine, the refine on the verification model spends at
    // most its staging solves, and the final one the rest.
    let first_budget = match request.final_refine {
        Some(last) => request.refine_budget.min(last.staging_solves),
        None => request.refine_budget,
    };
    let mut refine_summary = None;
    let mut jacobian = None;
    let mut verified_on = request.verify_mesh;
    if space.dimension() > 0 && first_budget > 0 {
        let refined = match request.correction_mesh {
            Some(mesh) => {
                let finer = SimulateOptions {
                    mesh,
                    rings: request.rings,
                    ..SimulateOptions::default()
                };
                problem.refine_corrected(
                    &finer,
                    best,
                    simulation,
                    first_budget,
                    &mut on_progress,
                )?
            }
            None => problem.refine(best, simulation, first_budget, None, &mut on_progress)?,
        };
        best = refined.design;
        simulation = refined.simulation;
        jacobian = refined.jacobian;
        refine_summary = refined.summary;
        // A corrected refine verifies on its finer model.
        if let (
            Some(mesh),
            Some(RefineSummary {
                corrected_on_element_mm: Some(_),
                ..
            }),
        ) = (request.correction_mesh, refine_summary)
        {
            verified_on = mesh;
        }
    }
    let mut final_refine_summary = None;
    let mut final_refine_skipped = None;
    // The final refine starts from the refine's result solved on its model;
    // if that solve fails, the refine's result stands (the job is not lost).
    let mut final_start = None;
    if let Some(last) = request.final_refine {
        let finest = SimulateOptions {
            mesh: last.mesh,
            rings: request.rings,
            newton: last.newton,
            ..SimulateOptions::default()
        };
        match simulate_from(&best, &finest, Some(&simulation)) {
            Ok(start) => final_start = Some((last, finest, start)),
            Err(error) => {
                final_refine_skipped = Some(format!(
                    "the {} model could not solve the refine's result ({error}); \
                     the design is the refine's, verified on its {verified_on} model",
                    last.mesh
                ))
            }
        }
    }
    if let Some((last, finest, start)) = final_start {
        simulation = start;
        verified_on = last.mesh;
        let done = refine_summary.map_or(0, |r| r.solves);
        let budget = request.refine_budget - done;
        if space.dimension() > 0 && budget > 0 {
            let problem = RefineProblem {
                model: &finest,
                ..problem
            };
            let refined = problem.refine(best, simulation, budget, jacobian, &mut |i, e, s| {
                on_progress(i, done + e, s)
            })?;
            best = refined.design;
            simulation = refined.simulation;
            final_refine_summary = refined.summary;
        }
    }
    state.evaluations += [refine_summary, final_refine_summary]
        .iter()
        .flatten()
        .map(|r| r.solves)
        .sum::<usize>();
    let (metrics, profiles) = verified(&profiles, &simulation, &request.objective);
    Ok(DesignOutcome {
        at_limits: at_limits(&best.patches, &request.bounds),
        profiles,
        inflated_length_mm: simulation.inflated_length_mm,
        uninflated_length_to_cut_mm: best.balloon.length_mm,
        seed_design: Design {
            patches: state.seed_patches.clone(),
            ..base.clone()
        },
        design: best,
        simulation,
        metrics,
        seed_objective: state.seed_objective,
        search_objective: state.best_objective,
        target_length_mm: target.length(),
        evaluations: state.evaluations,
        termination,
        refine: refine_summary,
        final_refine: final_refine_summary,
        final_refine_skipped,
        verified_on,
        elapsed: Duration::from_secs_f64(elapsed()),
    })
}

/// CMA-ES settings of the search: the unit cube around the seed.
fn search_options(space: &DesignSpace, request: &DesignRequest) -> RunOptions {
    unit_cube_options(
        space.seed_point(),
        request.initial_step,
        request.seed,
        request.budget,
        request.threads,
    )
}

/// CMA-ES in the unit cube of the free variables from `start` with step
/// `sigma`, `budget` evaluations counting the start's own (evaluated before),
/// shared by the search and the polish.
pub(super) fn unit_cube_options(
    start: Vec<f64>,
    sigma: f64,
    seed: u64,
    budget: usize,
    threads: usize,
) -> RunOptions {
    let n = start.len();
    let mut options = RunOptions::new(start, sigma, seed);
    options.bounds = Bounds::new(vec![0.0; n], vec![1.0; n]).ok();
    options.max_evaluations = budget.saturating_sub(1);
    options.threads = threads.max(1);
    options.tol_fun = 1e-7;
    options.tol_x = 1e-6;
    options
}

/// The balloon with its length chosen and the KSA seed as its patches.
fn seeded_balloon(
    target: &Curve,
    base: Design,
    request: &DesignRequest,
    verify: &SimulateOptions,
) -> Result<Design, DesignRunError> {
    let b = &base.balloon;
    let state = inflate_tube(&b.material, base.pressure_mpa(), b.radius_mm, b.wall_mm).ok_or(
        DesignRunError::NoTubeState {
            pressure_kpa: base.pressure_kpa,
        },
    )?;
    let target_length = target.length();
    // Balloon length from mechanics: the bare tube stretches by λ₂ axially.
    let mut length = if request.fix_length {
        b.length_mm
    } else {
        target_length / state.axial
    };
    let mut seed_patches = seed(target, &base, length, request)?;
    if !request.fix_length {
        // Patches stretch less than bare wall, and the mesh is not the membrane
        // theory: correct the length once from a simulation of the seed (even
        // with no patches), scaling patch positions and lengths with it.
        // The length to cut comes from the most accurate model of the run (the
        // verification mesh): the coarse search mesh's polygonal section
        // understates the axial stretch by several percent.
        let mut trial = Design {
            patches: seed_patches.clone(),
            ..base.clone()
        };
        trial.balloon.length_mm = length;
        let sim = simulate_cached(&trial, verify).map_err(DesignRunError::Seed)?;
        stretch_balloon(&mut trial, target_length / sim.inflated_length_mm);
        length = trial.balloon.length_mm;
        seed_patches = trial.patches;
    }
    let mut seeded = Design {
        patches: seed_patches,
        ..base
    };
    seeded.balloon.length_mm = length;
    Ok(seeded)
}

/// `count` patches spread evenly along the balloon: the unseeded start.
fn spread_evenly(balloon: &Design, count: usize, bounds: &VariableBounds) -> Vec<Patch> {
    let length = balloon.balloon.length_mm;
    (0..count)
        .map(|i| Patch {
            x_mm: 0.0,
            y_mm: (i as f64 + 0.5) * length / count as f64,
            h_mm: 0.5 * (bounds.h_min_mm + bounds.h_max_mm),
            w_mm: 0.5 * (bounds.w_min_mm + bounds.w_max_mm),
            theta_deg: 0.0,
        })
        .collect()
}

/// KSA patches for a balloon of `length`, mapping the whole target onto it.
fn seed(
    target: &Curve,
    base: &Design,
    length: f64,
    request: &DesignRequest,
) -> Result<Vec<Patch>, DesignRunError> {
    let params = KsaParams {
        l0_mm: length,
        r0_mm: base.balloon.radius_mm,
        kappa_tol: request.kappa_tol,
        merge_mm: request.merge_mm,
        width_mm: request.width_mm,
        stretch: Stretch::Fixed(target.length() / length),
        ..KsaParams::default()
    };
    Ok(ksa(target, &params).map_err(DesignRunError::Ksa)?.patches)
}

/// Relative mismatch of inflated and target length left uncorrected.
const LENGTH_TOLERANCE: f64 = 1e-3;

/// Scales the balloon's length by `ratio`, and the patches' axial positions
/// and lengths with it.
pub(super) fn stretch_balloon(design: &mut Design, ratio: f64) {
    design.balloon.length_mm *= ratio;
    for p in &mut design.patches {
        p.y_mm *= ratio;
        p.h_mm *= ratio;
    }
}

/// Metrics of `design` against `target` on a model of the caller's choice —
/// to compare designs found at different fidelities on one common model.
pub fn assess(
    target: &Curve,
    design: &Design,
    mesh: MeshSpec,
    request: &DesignRequest,
) -> Result<Metrics, SimulateError> {
    let options = SimulateOptions {
        mesh,
        rings: request.rings,
        ..SimulateOptions::default()
    };
    let simulation = simulate_cached(design, &options)?;
    let profiles = TargetProfiles::new(target, request.rings, &request.objective);
    Ok(verified(&profiles, &simulation, &request.objective).0)
}

/// Metrics and profiles of the verified simulation, each computed once.
fn verified(
    target: &TargetProfiles,
    sim: &Simulation,
    options: &ObjectiveOptions,
) -> (Metrics, Profiles) {
    let shape = shape_error(&sim.centreline, &target.curve, SHAPE_SAMPLES).ok();
    let (curvature, torsion) = target.profiles_of(&sim.centreline, options);
    let metrics = Metrics {
        objective: target.mismatch(&sim.centreline, &curvature, &torsion, options),
        dtw_curvature: dtw(&curvature, &target.curvature, None).unwrap_or(f64::INFINITY),
        dtw_torsion: dtw(&torsion, &target.torsion, None).unwrap_or(f64::INFINITY),
        shape_error_mm: shape.as_ref().map_or(f64::INFINITY, |e| e.rms_mm),
        shape_error_percent: shape
            .as_ref()
            .map_or(f64::INFINITY, |e| e.percent_of_length),
    };
    let profiles = Profiles {
        target_curvature_per_mm: target.curvature.clone(),
        target_torsion_per_mm: target.torsion.clone(),
        curvature_per_mm: curvature,
        torsion_per_mm: torsion,
    };
    (metrics, profiles)
}
