//! Nonlinear least squares in the unit cube, for any vector of residuals:
//! Levenberg–Marquardt with Broyden's secant updates
//! ([`levenberg_marquardt`]), its Jacobians ([`jacobian`]), and output space
//! mapping as a wrapper around a problem ([`SpaceMapped`]). Nothing here knows
//! about balloons: the design refine (`inverse::refine`) is one problem.
//!
//! A problem maps a point u ∈ [0, 1]ⁿ to a *state* (whatever its evaluation
//! produces: for the refine, an inflated simulation) and a state to residuals
//! r; the solvers minimise |r|. A state also warm-starts the evaluation of a
//! nearby point.

pub mod jacobian;
pub mod levenberg_marquardt;

use nalgebra::{DMatrix, DVector};

pub use levenberg_marquardt::{Cancelled, Counts, Settings, Solution, minimise};

/// A least-squares problem over the unit cube.
pub trait Residuals: Sync {
    /// What an evaluation produces; it warm-starts the next ones nearby.
    type State: Send + Sync;

    /// The residuals of an evaluated state; none if it has none (the solver
    /// then treats the point as failed).
    fn residuals(&self, state: &Self::State) -> Option<DVector<f64>>;

    /// Evaluates the point `u`, starting from `near`, the state of a nearby
    /// point; none if the evaluation fails.
    fn solve(&self, u: &[f64], near: &Self::State) -> Option<Self::State>;

    /// The Jacobian at `at` for about the cost of one evaluation (for
    /// example linearised responses), as forward differences at step `step`
    /// would estimate it; none where the problem has no such shortcut, and
    /// the solver then takes forward differences. `at`'s residuals may carry a
    /// constant offset ([`SpaceMapped`]), which a Jacobian does not see.
    fn cheap_jacobian(&self, _at: &Iterate<Self::State>, _step: f64) -> Option<DMatrix<f64>> {
        None
    }

    /// Whether the caller has asked the solver to stop.
    fn cancelled(&self) -> bool {
        false
    }

    /// Whether the caller's time is up: the solver then stops before its
    /// next evaluation and returns its best point so far (a cancelled run
    /// returns nothing).
    fn out_of_time(&self) -> bool {
        false
    }
}

/// An evaluated point: u, its state, residuals and their norm.
pub struct Iterate<S> {
    pub u: Vec<f64>,
    pub state: S,
    pub residuals: DVector<f64>,
    pub error: f64,
}

impl<S> Iterate<S> {
    /// `state` at `u` as an iterate; the state back if it has no residuals.
    pub fn new<P: Residuals<State = S>>(problem: &P, u: Vec<f64>, state: S) -> Result<Self, S> {
        match problem.residuals(&state) {
            Some(residuals) => Ok(Iterate {
                u,
                state,
                error: residuals.norm(),
                residuals,
            }),
            None => Err(state),
        }
    }

    /// Evaluates `u` from this iterate's state; none if cancelled or failed.
    pub fn evaluate<P: Residuals<State = S>>(&self, problem: &P, u: Vec<f64>) -> Option<Self> {
        if problem.cancelled() {
            return None;
        }
        let state = problem.solve(&u, &self.state)?;
        Iterate::new(problem, u, state).ok()
    }
}

/// Output space mapping (defect correction): a problem whose residuals are
/// another's plus a constant, r(u) = r_c(u) + d. With r_c a cheap model's
/// residuals and d = r_f(u₀) − r_c(u₀) the gap to a finer model's at u₀, the
/// mapped residuals equal the finer model's at u₀ and to first order near it
/// as long as the two models respond alike; minimising them moves the cheap
/// model towards the finer model's optimum. Evaluations, warm starts and
/// Jacobians are the inner problem's (d is constant).
pub struct SpaceMapped<'a, P> {
    pub inner: &'a P,
    pub offset: &'a DVector<f64>,
}

impl<P: Residuals> Residuals for SpaceMapped<'_, P> {
    type State = P::State;

    fn residuals(&self, state: &P::State) -> Option<DVector<f64>> {
        let mut residuals = self.inner.residuals(state)?;
        residuals += self.offset;
        Some(residuals)
    }

    fn solve(&self, u: &[f64], near: &P::State) -> Option<P::State> {
        self.inner.solve(u, near)
    }

    fn cheap_jacobian(&self, at: &Iterate<P::State>, step: f64) -> Option<DMatrix<f64>> {
        self.inner.cheap_jacobian(at, step)
    }

    fn cancelled(&self) -> bool {
        self.inner.cancelled()
    }

    fn out_of_time(&self) -> bool {
        self.inner.out_of_time()
    }
}
