//! What a solve ends in: its statistics, or why it failed.

use std::time::Duration;

/// Why a solve did not converge. Every variant carries the residual reached.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    #[error(
        "Newton did not converge in {iterations} iterations (relative residual {residual:.3e})"
    )]
    NotConverged { iterations: usize, residual: f64 },
    #[error("line search failed after {iterations} iterations (relative residual {residual:.3e})")]
    LineSearch { iterations: usize, residual: f64 },
    #[error(
        "tangent could not be factorised even with shift {shift:.3e} (relative residual {residual:.3e})"
    )]
    Factorisation { shift: f64, residual: f64 },
    #[error("solve exceeded its time limit of {limit_s:.1} s (relative residual {residual:.3e})")]
    TimeLimit { limit_s: f64, residual: f64 },
    #[error("starting state is outside the materials' domain")]
    InadmissibleStart,
    #[error("sparse matrix setup failed: {0}")]
    Setup(String),
}

/// Statistics of a converged solve.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SolveStats {
    /// Ordering, permuted pattern and symbolic factorisation, once per model.
    pub setup_time: Duration,
    pub iterations: usize,
    pub residual: f64,
    /// Whether K factorised without shift at the solution.
    pub stable: bool,
    pub assembly_time: Duration,
    /// Numeric Cholesky factorisations, failed (shifted) attempts included.
    pub factor_time: Duration,
    pub factorisations: usize,
    /// Forward/back substitution.
    pub substitution_time: Duration,
    pub line_search_time: Duration,
}

impl SolveStats {
    /// Adds another solve's counts and times to these.
    pub fn accumulate(&mut self, other: &SolveStats) {
        self.setup_time += other.setup_time;
        self.iterations += other.iterations;
        self.residual = other.residual;
        self.stable = other.stable;
        self.assembly_time += other.assembly_time;
        self.factor_time += other.factor_time;
        self.factorisations += other.factorisations;
        self.substitution_time += other.substitution_time;
        self.line_search_time += other.line_search_time;
    }
}
