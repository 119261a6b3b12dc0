//! Limits and tolerances of one solve.

use std::time::Duration;

use super::shift::SMALLEST_SHIFT;

/// Limits and tolerances of one solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonOptions {
    /// Iterations before a solve is abandoned, unless it is still converging
    /// (then up to three times as many; see `still_converging`).
    pub max_iterations: usize,
    /// Converged when |∇Π| ≤ tolerance · |P ∂V/∂x| (the pressure load's size)
    /// and the last iteration moved no unknown by more than `step_tolerance`.
    pub tolerance: f64,
    /// The largest move (mm) of the last iteration at convergence: a long
    /// tube's soft swing leaves a small residual far from equilibrium, so a
    /// loose `tolerance` alone can stop millimetres short.
    pub step_tolerance: f64,
    /// Wall time of one solve (a simulation may also limit its whole run:
    /// `SimulateOptions::time_limit`).
    pub time_limit: Duration,
    /// Halve a step whose end needs a much larger shift than its start
    /// ([`guard_definiteness`]). On by default; off only to measure what it
    /// saves.
    pub definiteness_guard: bool,
    /// How a step's end is found from the Newton direction.
    pub steps: Steps,
    /// The smallest Levenberg shift (relative to the mean tangent entry)
    /// before a decaying shift becomes zero (`shift.rs`). A lower floor lets
    /// a long tube's slightly concave soft modes be crossed in a few
    /// iterations, where a shift climbing back from zero would creep along
    /// them; on a nearly bare tube's convex soft modes it lets steps run
    /// tens of millimetres. `simulate` takes [`COLD_SHIFT_FLOOR`] for its
    /// cold starts and this for the rest.
    pub shift_floor: f64,
}

/// The shift floor of a cold solve's starts (the kinematic estimate and the
/// coarse model's state): a 1 m balloon with 30 patches converges in 95
/// Newton iterations where the default floor takes 239 and three
/// continuation steps (docs/studies.md, "A 1 m, 30-patch balloon's cold
/// solve").
pub const COLD_SHIFT_FLOOR: f64 = 1e-10;

/// How a Newton step moves the tube's nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Steps {
    /// u + t·Δu.
    #[default]
    Linear,
    /// Ring by ring, the rings' and segments' rotations applied exactly
    /// ([`ring_step`](crate::fe::ring_step)): the same first order, and
    /// no strain from a rigid swing of the tube. At a residual of 1e-9,
    /// cold and warm solves take a tenth fewer iterations and end at the
    /// same equilibrium; at a loose residual alone they can stop far from
    /// it (bound the last move with `step_tolerance`). Not the default:
    /// docs/studies.md, "Newton steps ring by ring".
    Rings,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        NewtonOptions {
            max_iterations: 60,
            tolerance: 1e-9,
            step_tolerance: f64::INFINITY,
            time_limit: Duration::from_secs(60),
            definiteness_guard: true,
            steps: Steps::Linear,
            shift_floor: SMALLEST_SHIFT,
        }
    }
}
