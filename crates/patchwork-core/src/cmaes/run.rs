//! The loop around the strategy: evaluation (a whole generation in parallel),
//! bounds, termination, progress observers, IPOP restarts and checkpoints.
//! The strategy itself only knows how to take one step.

use serde::{Deserialize, Serialize};

use super::bounds::Bounds;
use super::rng::SeededRng;
use super::strategy::CmaEs;
use crate::parallel::map_in_threads;

/// Why a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Termination {
    /// Best fitness reached `target`.
    TargetReached,
    /// The evaluation budget is spent.
    MaxEvaluations,
    /// The observer asked to stop (cancellation).
    Cancelled,
    /// Fitness stopped changing in the last restart and no restarts remain.
    TolFun,
    /// The distribution shrank below `tol_x` and no restarts remain.
    TolX,
    /// The covariance became ill-conditioned (> 1e14) and no restarts remain.
    ConditionCov,
}

/// Run settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunOptions {
    pub x0: Vec<f64>,
    pub sigma0: f64,
    pub bounds: Option<Bounds>,
    pub max_evaluations: usize,
    pub target: Option<f64>,
    pub tol_fun: f64,
    pub tol_x: f64,
    /// IPOP: restarts with doubled population after a tolerance stop.
    pub max_restarts: usize,
    /// Population of the first run (default 4 + ⌊3 ln n⌋).
    pub lambda: Option<usize>,
    pub seed: u64,
    /// Threads evaluating a generation (1 = the calling thread).
    pub threads: usize,
}

impl RunOptions {
    pub fn new(x0: Vec<f64>, sigma0: f64, seed: u64) -> RunOptions {
        RunOptions {
            x0,
            sigma0,
            bounds: None,
            max_evaluations: 100_000,
            target: None,
            tol_fun: 1e-11,
            tol_x: 1e-11,
            max_restarts: 0,
            lambda: None,
            seed,
            threads: 1,
        }
    }
}

/// What an observer sees after each generation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Progress {
    pub restart: usize,
    pub generation: usize,
    pub evaluations: usize,
    pub best_fitness: f64,
    pub sigma: f64,
}

/// Observers report progress and may stop the run (cancellation).
pub trait Observer {
    /// Return `false` to stop.
    fn observe(&mut self, progress: &Progress) -> bool;
}

impl<F: FnMut(&Progress) -> bool> Observer for F {
    fn observe(&mut self, progress: &Progress) -> bool {
        self(progress)
    }
}

/// The whole state of a run, serialisable: a checkpoint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Optimizer {
    pub options: RunOptions,
    pub strategy: CmaEs,
    pub restart: usize,
    /// Evaluations of finished restarts.
    pub spent: usize,
    pub best_x: Vec<f64>,
    pub best_fitness: f64,
    /// Best fitness of each recent generation (for TolFun).
    recent: Vec<f64>,
    pub termination: Option<Termination>,
}

/// Final answer of a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunResult {
    /// Best point found, inside the bounds.
    pub x: Vec<f64>,
    pub fitness: f64,
    pub evaluations: usize,
    pub restarts: usize,
    pub termination: Termination,
}

impl Optimizer {
    pub fn new(options: RunOptions) -> Optimizer {
        let strategy = CmaEs::new(
            options.x0.clone(),
            options.sigma0,
            options.lambda,
            SeededRng::new(options.seed),
        );
        Optimizer {
            best_x: options.x0.clone(),
            best_fitness: f64::INFINITY,
            strategy,
            restart: 0,
            spent: 0,
            recent: Vec::new(),
            termination: None,
            options,
        }
    }

    pub fn evaluations(&self) -> usize {
        self.spent + self.strategy.evaluations
    }

    /// Maps a search point into the bounds (identity without bounds).
    pub fn phenotype(&self, x: &[f64]) -> Vec<f64> {
        match &self.options.bounds {
            Some(b) => b.transform(x),
            None => x.to_vec(),
        }
    }

    /// One generation: ask, evaluate in parallel, tell, check termination.
    /// Returns the termination once the run has ended.
    pub fn step(&mut self, objective: &(dyn Fn(&[f64]) -> f64 + Sync)) -> Option<Termination> {
        if self.termination.is_some() {
            return self.termination;
        }
        let candidates = self.strategy.ask();
        let points: Vec<Vec<f64>> = candidates.iter().map(|x| self.phenotype(x)).collect();
        let fitness = map_in_threads(&points, self.options.threads, &|x: &Vec<f64>| objective(x));
        for (x, &f) in points.iter().zip(&fitness) {
            if f < self.best_fitness {
                self.best_fitness = f;
                self.best_x = x.clone();
            }
        }
        self.strategy.tell(&candidates, &fitness);
        let generation_best = fitness
            .iter()
            .copied()
            .filter(|f| f.is_finite())
            .fold(f64::INFINITY, f64::min);
        self.recent.push(generation_best);
        self.termination = self.check(&fitness);
        self.termination
    }

    fn check(&mut self, fitness: &[f64]) -> Option<Termination> {
        let o = &self.options;
        if o.target.is_some_and(|t| self.best_fitness <= t) {
            return Some(Termination::TargetReached);
        }
        if self.evaluations() + self.strategy.params.lambda > o.max_evaluations {
            return Some(Termination::MaxEvaluations);
        }
        let s = &self.strategy;
        let n = s.dimension();
        let history = 10 + (30 * n).div_ceil(s.params.lambda);
        let tolerance = if self.recent.len() >= history {
            let window = &self.recent[self.recent.len() - history..];
            let all = window
                .iter()
                .chain(fitness)
                .copied()
                .filter(|f| f.is_finite());
            let (lo, hi) = all.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), f| {
                (a.min(f), b.max(f))
            });
            (hi - lo < o.tol_fun).then_some(Termination::TolFun)
        } else {
            None
        };
        let tolerance = tolerance
            .or_else(|| {
                (s.max_std().max(s.sigma * s.pc.amax()) < o.tol_x).then_some(Termination::TolX)
            })
            .or_else(|| (s.condition() > 1e14).then_some(Termination::ConditionCov));
        let reason = tolerance?;
        if self.restart < o.max_restarts {
            // IPOP: start again from x0 with twice the population, a fresh stream.
            self.restart += 1;
            self.spent += s.evaluations;
            let lambda = s.params.lambda * 2;
            let rng = SeededRng::new(o.seed.wrapping_add(0x9E37_79B9 * self.restart as u64));
            self.strategy = CmaEs::new(o.x0.clone(), o.sigma0, Some(lambda), rng);
            self.recent.clear();
            return None;
        }
        Some(reason)
    }

    /// Runs to termination, reporting each generation to `observer`.
    pub fn run(
        &mut self,
        objective: &(dyn Fn(&[f64]) -> f64 + Sync),
        observer: &mut dyn Observer,
    ) -> RunResult {
        loop {
            let ended = self.step(objective);
            let progress = Progress {
                restart: self.restart,
                generation: self.strategy.generation,
                evaluations: self.evaluations(),
                best_fitness: self.best_fitness,
                sigma: self.strategy.sigma,
            };
            if !observer.observe(&progress) && ended.is_none() {
                self.termination = Some(Termination::Cancelled);
            }
            if let Some(termination) = self.termination {
                return RunResult {
                    x: self.best_x.clone(),
                    fitness: self.best_fitness,
                    evaluations: self.evaluations(),
                    restarts: self.restart,
                    termination,
                };
            }
        }
    }
}
