//! Levenberg–Marquardt with Broyden updates, in the unit cube.
//!
//! Step: (JᵀJ + λ D) δ = −Jᵀr with D = diag(JᵀJ) (Marquardt's scaling,
//! floored at 1e-9 of the mean diagonal so a variable the residuals do not
//! see stays put), u + δ clamped into the cube; accepted only if |r| falls
//! (then λ × 0.3), else λ × 4 and again.
//!
//! Jacobians: the problem's cheap one (counted as one evaluation) or forward
//! differences (one evaluation per variable). After every trial, accepted or
//! not, J gets Broyden's rank-one secant update ([`super::jacobian`]) and the
//! next step uses it; a fresh Jacobian is taken only when the secant one
//! fails: `stale_rejections` rejected steps in a row, no step left, or an
//! accepted step that gains less than `min_gain` of |r| or lowers it by
//! less than `resolution`. A fresh Jacobian
//! starts from a damping no higher than the first.
//!
//! Stops: when the budget cannot pay the next evaluation (or the next
//! Jacobian and a step after it), when the problem is out of time (before
//! its next evaluation), or when a *fresh* Jacobian fails — its
//! accepted step gains less than `min_gain` (or `resolution`), its damping passes
//! `max_damping`, or its step does not move. So every stop but the
//! budget's is confirmed by a fresh Jacobian at the final point.

use nalgebra::{DMatrix, DVector};

use super::jacobian::{Jacobian, forward_differences};
use super::{Iterate, Residuals};

/// The solver's constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Forward-difference step in the unit cube.
    pub step: f64,
    /// Initial damping λ.
    pub first_damping: f64,
    /// Damping beyond which no step along the gradient lowers |r|.
    pub max_damping: f64,
    /// An accepted step that lowers |r| by less than this fraction ends the
    /// run (from a fresh Jacobian) or refreshes the Jacobian (from a secant one).
    pub min_gain: f64,
    /// An accepted step that lowers |r| by less than this (in |r|'s own
    /// units) counts as one below `min_gain`: where |r| is a measured
    /// quantity, the size of change too small to matter (0: none).
    pub resolution: f64,
    /// Rejected steps in a row after which a secant Jacobian is refreshed.
    pub stale_rejections: usize,
    /// Threads for forward differences.
    pub threads: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            step: 1e-3,
            first_damping: 1e-2,
            max_damping: 1e6,
            min_gain: 1e-3,
            resolution: 0.0,
            stale_rejections: 3,
            threads: 1,
        }
    }
}

/// The caller cancelled the run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cancelled;

/// What a run spent and did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Counts {
    /// Evaluations, a cheap Jacobian counted as one.
    pub evaluations: usize,
    /// Accepted steps.
    pub iterations: usize,
    /// Fresh Jacobians.
    pub jacobians: usize,
    /// Of those, by forward differences.
    pub differenced: usize,
}

/// A run's result: the best point (the start if no step lowered |r|), the
/// start's |r|, the counts, and the last Jacobian (Broyden-updated to the
/// last trial), for a run that goes on from here.
pub struct Solution<S> {
    pub best: Iterate<S>,
    pub start_error: f64,
    pub counts: Counts,
    pub jacobian: Option<DMatrix<f64>>,
}

/// Minimises |r| from `start` with at most `budget` evaluations.
/// `jacobian`, if given and of the right shape, is the first Jacobian (a
/// secant one, from a nearby point) instead of a fresh one.
/// `on_progress(iterations, evaluations, state)` hears every fresh Jacobian
/// and every accepted step.
pub fn minimise<P: Residuals>(
    problem: &P,
    start: Iterate<P::State>,
    budget: usize,
    jacobian: Option<DMatrix<f64>>,
    settings: &Settings,
    on_progress: &mut dyn FnMut(usize, usize, &P::State),
) -> Result<Solution<P::State>, Cancelled> {
    let n = start.u.len();
    let jacobian = jacobian
        .filter(|j| j.ncols() == n && j.nrows() == start.residuals.len())
        .map(|matrix| Jacobian {
            matrix,
            fresh: false,
        });
    let mut run = Minimiser {
        problem,
        settings,
        budget,
        start_error: start.error,
        current: start,
        // Fresh Jacobians are due at the start unless one was handed in.
        refresh: jacobian.is_none(),
        jacobian,
        damping: settings.first_damping,
        counts: Counts::default(),
        on_progress,
    };
    while n > 0 && run.counts.evaluations < budget {
        if run.refresh && !run.take_jacobian()? {
            break;
        }
        if run.try_steps()? == After::Stop {
            break;
        }
    }
    Ok(run.solution())
}

/// What the steps from one Jacobian ended in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum After {
    /// A step was accepted; the Jacobian goes on (or is due afresh).
    Continue,
    Stop,
}

/// A run's state between steps.
struct Minimiser<'r, P: Residuals> {
    problem: &'r P,
    settings: &'r Settings,
    budget: usize,
    start_error: f64,
    current: Iterate<P::State>,
    jacobian: Option<Jacobian>,
    /// A fresh Jacobian is due before the next step.
    refresh: bool,
    damping: f64,
    counts: Counts,
    on_progress: &'r mut dyn FnMut(usize, usize, &P::State),
}

impl<P: Residuals> Minimiser<'_, P> {
    /// Takes a fresh Jacobian at the current point: the problem's cheap one,
    /// or forward differences if it has none and the budget pays them and a
    /// step after them. False if the budget cannot.
    fn take_jacobian(&mut self) -> Result<bool, Cancelled> {
        let (n, evaluations) = (self.current.u.len(), self.counts.evaluations);
        if evaluations + 1 >= self.budget || self.problem.out_of_time() {
            return Ok(false);
        }
        let step = self.settings.step;
        let matrix = match self.problem.cheap_jacobian(&self.current, step) {
            Some(matrix) => {
                self.counts.evaluations += 1;
                matrix
            }
            None if evaluations + n < self.budget => {
                self.counts.evaluations += n;
                self.counts.differenced += 1;
                forward_differences(self.problem, &self.current, step, self.settings.threads)
            }
            None => return Ok(false),
        };
        self.counts.jacobians += 1;
        self.check_cancelled()?;
        self.report();
        self.jacobian = Some(Jacobian {
            matrix,
            fresh: true,
        });
        // The secant Jacobian's failures raised the damping; the fresh one
        // starts from no more than the first.
        self.refresh = false;
        self.damping = self.damping.min(self.settings.first_damping);
        Ok(true)
    }

    /// Damped steps from the current Jacobian until one is accepted, the
    /// Jacobian needs refreshing, or the run ends.
    fn try_steps(&mut self) -> Result<After, Cancelled> {
        let mut rejected = 0;
        loop {
            let Some(j) = self.jacobian.as_ref() else {
                return Ok(After::Stop);
            };
            let fresh = j.fresh;
            let step = damped_step(&j.matrix, &self.current, self.damping);
            if self.counts.evaluations >= self.budget || self.problem.out_of_time() {
                return Ok(After::Stop);
            }
            // No step left: from a fresh Jacobian, done; from a secant one,
            // take a fresh one.
            let Some(u) = step else {
                return Ok(self.refresh_unless(fresh));
            };
            self.counts.evaluations += 1;
            let trial = self.current.evaluate(self.problem, u);
            self.check_cancelled()?;
            if let (Some(trial), Some(j)) = (&trial, self.jacobian.as_mut()) {
                j.update(&self.current, trial);
            }
            match trial {
                Some(trial) if trial.error < self.current.error => {
                    return Ok(self.accept(trial, fresh));
                }
                _ => {
                    self.damping *= 4.0;
                    rejected += 1;
                    let gave_up = self.damping > self.settings.max_damping;
                    if gave_up || (!fresh && rejected >= self.settings.stale_rejections) {
                        return Ok(self.refresh_unless(fresh));
                    }
                }
            }
        }
    }

    /// Moves to `trial`, which lowered |r|. A small gain from a secant
    /// Jacobian may be the Jacobian's fault: it is checked with a fresh one.
    fn accept(&mut self, trial: Iterate<P::State>, fresh: bool) -> After {
        let gain = 1.0 - trial.error / self.current.error;
        let lowered = self.current.error - trial.error;
        if let Some(j) = self.jacobian.as_mut() {
            j.fresh = false;
        }
        self.current = trial;
        self.damping = (self.damping * 0.3).max(1e-9);
        self.counts.iterations += 1;
        self.report();
        if gain < self.settings.min_gain || lowered < self.settings.resolution {
            return self.refresh_unless(fresh);
        }
        After::Continue
    }

    /// The end of a fresh Jacobian's steps ends the run; a secant one's
    /// calls for a fresh Jacobian.
    fn refresh_unless(&mut self, fresh: bool) -> After {
        if fresh {
            return After::Stop;
        }
        self.refresh = true;
        After::Continue
    }

    fn check_cancelled(&self) -> Result<(), Cancelled> {
        if self.problem.cancelled() {
            return Err(Cancelled);
        }
        Ok(())
    }

    fn report(&mut self) {
        let (iterations, evaluations) = (self.counts.iterations, self.counts.evaluations);
        (self.on_progress)(iterations, evaluations, &self.current.state);
    }

    fn solution(self) -> Solution<P::State> {
        Solution {
            best: self.current,
            start_error: self.start_error,
            counts: self.counts,
            jacobian: self.jacobian.map(|j| j.matrix),
        }
    }
}

/// The damped Gauss–Newton step from `at` with Jacobian `jacobian`, floored
/// Marquardt scaling; see [`damped_step_from_normal`].
fn damped_step<S>(jacobian: &DMatrix<f64>, at: &Iterate<S>, damping: f64) -> Option<Vec<f64>> {
    let normal = jacobian.transpose() * jacobian;
    let gradient = jacobian.transpose() * &at.residuals;
    let floor = 1e-9 * normal.trace().max(f64::MIN_POSITIVE) / at.u.len() as f64;
    damped_step_from_normal(&normal, &gradient, damping, floor, &at.u)
}

/// u + δ with (JᵀJ + λ D) δ = −Jᵀr, D = diag(JᵀJ) floored at `floor`,
/// clamped into the unit cube; none if the system cannot be solved or the
/// clamped step does not move.
fn damped_step_from_normal(
    normal: &DMatrix<f64>,
    gradient: &DVector<f64>,
    damping: f64,
    floor: f64,
    u: &[f64],
) -> Option<Vec<f64>> {
    let mut system = normal.clone();
    for i in 0..u.len() {
        system[(i, i)] += damping * normal[(i, i)].max(floor);
    }
    let step = system.cholesky()?.solve(&(-gradient));
    let next: Vec<f64> = u
        .iter()
        .zip(step.iter())
        .map(|(x, d)| (x + d).clamp(0.0, 1.0))
        .collect();
    let moved = next.iter().zip(u).any(|(a, b)| a != b);
    (moved && next.iter().all(|x| x.is_finite())).then_some(next)
}

#[cfg(test)]
mod tests;
