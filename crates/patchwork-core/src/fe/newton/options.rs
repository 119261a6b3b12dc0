//! Limits and tolerances of one solve.

use std::time::Duration;

/// Limits and tolerances of one solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonOptions {
    /// Iterations before a solve is abandoned, unless it is still converging
    /// (then up to three times as many; see `still_converging`).
    pub max_iterations: usize,
    /// Converged when |∇Π| ≤ tolerance · |P ∂V/∂x| (the pressure load's size).
    pub tolerance: f64,
    /// Wall time of one solve (a simulation may also limit its whole run:
    /// `SimulateOptions::time_limit`).
    pub time_limit: Duration,
    /// Halve a step whose end needs a much larger shift than its start
    /// ([`guard_definiteness`]). On by default; off only to measure what it
    /// saves.
    pub definiteness_guard: bool,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        NewtonOptions {
            max_iterations: 60,
            tolerance: 1e-9,
            time_limit: Duration::from_secs(60),
            definiteness_guard: true,
        }
    }
}
