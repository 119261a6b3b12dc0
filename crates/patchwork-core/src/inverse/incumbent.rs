//! The objective a CMA-ES stage minimises, with its incumbent: every candidate
//! is simulated (warm-started from the incumbent's inflated state when warm
//! starts are on), scored against the target's profiles, and becomes the
//! incumbent if it beats it. Shared by the search and the polish stages, which
//! differ only in the model.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use super::caches::Caches;
use super::deadline::Deadline;
use super::objective::{ObjectiveOptions, TargetProfiles};
use super::stages::RodModel;
use super::variables::DesignSpace;
use crate::cmaes::{Bounds, RunOptions};
use crate::design::{Design, Patch};
use crate::fe::{SimulateOptions, Simulation};

/// Objective value given to a candidate whose forward solve failed: worse than
/// any design that solves (a straight tube scores 1 on the profiles; the shape
/// term adds at most its weight times the RMS distance over the length).
pub const FAILED_SOLVE_PENALTY: f64 = 1e6;

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

/// What a stage evaluates candidates with.
pub(super) struct Scorer<'a> {
    pub space: &'a DesignSpace,
    /// Balloon, materials and pressure; its patches are ignored.
    pub base: &'a Design,
    pub model: &'a SimulateOptions,
    pub profiles: &'a TargetProfiles,
    pub objective: &'a ObjectiveOptions,
    pub warm_starts: bool,
    pub cancel: &'a AtomicBool,
    /// When the run's time limit passes: a stage's loop stops at the
    /// generation after.
    pub deadline: Deadline,
    pub caches: &'a Caches,
    /// The rod model that candidates are scored on instead of `model`
    /// (the search's, when it runs on the rod).
    pub rod: Option<&'a RodModel>,
}

/// The best design of a stage so far and its inflated state.
pub(super) struct Incumbent {
    best: Mutex<(f64, Vec<Patch>)>,
    warm: Mutex<Option<Arc<Simulation>>>,
}

impl Scorer<'_> {
    /// Objective of `design` on this stage's model, and its simulation.
    pub fn score(&self, design: &Design, warm: Option<&Simulation>) -> (f64, Option<Simulation>) {
        score(
            self.caches,
            design,
            self.model,
            self.profiles,
            self.objective,
            warm,
        )
    }

    /// The candidate at unit-cube point `u`: simulated (or put on the rod),
    /// scored, and made the incumbent if better. Infinite once cancelled
    /// (the caller drops that generation).
    pub fn evaluate(&self, u: &[f64], incumbent: &Incumbent) -> f64 {
        if self.cancel.load(Ordering::Relaxed) {
            return f64::INFINITY;
        }
        let candidate = Design {
            patches: self.space.patches(u),
            ..self.base.clone()
        };
        if let Some(rod) = self.rod {
            let f = (rod.score(&candidate, self.profiles, self.objective))
                .unwrap_or(FAILED_SOLVE_PENALTY);
            if let Ok(mut best) = incumbent.best.lock()
                && f < best.0
            {
                *best = (f, candidate.patches);
            }
            return f;
        }
        let start = if self.warm_starts {
            incumbent.warm.lock().ok().and_then(|w| w.clone())
        } else {
            None
        };
        let (f, sim) = self.score(&candidate, start.as_deref());
        if let (Some(sim), Ok(mut best)) = (sim, incumbent.best.lock())
            && f < best.0
        {
            *best = (f, candidate.patches);
            if let Ok(mut w) = incumbent.warm.lock() {
                *w = Some(Arc::new(sim));
            }
        }
        f
    }
}

/// Objective of `design` on `model` and its simulation (the failed-solve
/// penalty and none if the solve fails).
pub(super) fn score(
    caches: &Caches,
    design: &Design,
    model: &SimulateOptions,
    profiles: &TargetProfiles,
    objective: &ObjectiveOptions,
    warm: Option<&Simulation>,
) -> (f64, Option<Simulation>) {
    match caches.simulate_from(design, model, warm) {
        Ok(sim) => (profiles.objective_of(&sim, objective), Some(sim)),
        Err(_) => (FAILED_SOLVE_PENALTY, None),
    }
}

impl Incumbent {
    pub fn new(objective: f64, patches: Vec<Patch>, state: Option<Simulation>) -> Incumbent {
        Incumbent {
            best: Mutex::new((objective, patches)),
            warm: Mutex::new(state.map(Arc::new)),
        }
    }

    /// The best design and its simulation on the stage's model (none if no
    /// candidate solved).
    pub fn into_best(self) -> (Vec<Patch>, Option<Simulation>) {
        let patches = self
            .best
            .into_inner()
            .map_or_else(|e| e.into_inner().1, |b| b.1);
        let state = self
            .warm
            .into_inner()
            .unwrap_or_else(|e| e.into_inner())
            .map(Arc::unwrap_or_clone);
        (patches, state)
    }

    /// The best objective and design so far.
    pub fn best(&self) -> (f64, Vec<Patch>) {
        self.best
            .lock()
            .map(|b| b.clone())
            .unwrap_or((f64::INFINITY, Vec::new()))
    }
}
