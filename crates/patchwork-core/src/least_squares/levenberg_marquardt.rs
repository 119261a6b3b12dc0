//! Levenberg–Marquardt with Broyden updates, in the unit cube.
//!
//! Step: (JᵀJ + λ D) δ = −Jᵀr with D = diag(JᵀJ) (Marquardt's scaling,
//! floored at 1e-9 of the mean diagonal so a variable the residuals do not
//! see stays put), over the variables not held at a bound, then clamped
//! into the cube ([`step`]). A step the linear model predicts no fall of
//! |r| for is not evaluated (λ × 4 and again); one evaluated is accepted
//! only if |r| falls (then λ scaled by the step's gain ratio, Nielsen's
//! rule: between × 1/3 and × 2), else λ × 4 and again.
//!
//! Jacobians: the problem's cheap one (counted as one evaluation) or forward
//! differences (one evaluation per variable). After every trial, accepted or
//! not, J gets Broyden's rank-one secant update ([`super::jacobian`]) and the
//! next step uses it; a fresh Jacobian is taken only when the secant one
//! fails: `stale_rejections` rejected steps in a row, no step left, or an
//! accepted step that gains less than `min_gain` of |r| or lowers it by
//! less than `resolution`. Where the problem's Jacobian is cheap, a secant
//! step whose gain ratio falls below `secant_ratio` (the linear model held
//! for less than that share of the fall it predicted) calls for a fresh one
//! too: the secant has drifted, and a fresh Jacobian costs one evaluation.
//! A fresh Jacobian starts from a damping no higher than the first.
//!
//! Stops: when an iterate meets `target` (|r| at or below it: good
//! enough, whatever the Jacobian), when the budget cannot pay the next
//! evaluation (or the next Jacobian and a step after it), when the problem
//! is out of time (before its next evaluation), or when a *fresh* Jacobian
//! fails — its accepted step gains less than `min_gain` (or `resolution`),
//! its damping passes `max_damping`, or its step does not move (a small
//! gain the linear model promised far more for is an overshoot, not a
//! failure: the raised damping shortens the next step). So every
//! stop but the target's and the budget's is confirmed by a fresh Jacobian
//! at the final point.

use nalgebra::DMatrix;

use super::jacobian::{Jacobian, forward_differences};
use super::{Iterate, Residuals};
use step::damped_step;

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
    /// An iterate whose |r| is at or below this ends the run: the fit is
    /// good enough (0: none).
    pub target: f64,
    /// Rejected steps in a row after which a secant Jacobian is refreshed.
    pub stale_rejections: usize,
    /// A secant step accepted with a gain ratio below this refreshes a
    /// cheap Jacobian (differenced ones keep the secant).
    pub secant_ratio: f64,
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
            target: 0.0,
            stale_rejections: 3,
            secant_ratio: SECANT_RATIO,
            threads: 1,
        }
    }
}

/// The default [`Settings::secant_ratio`]. On the curve suite under `draft`
/// (18 curves, seed 1, `patchwork bench --suite curves --settings draft
/// --runs 1`), against keeping every secant Jacobian until its steps stall:
/// the refine's time 10 % less in all (217 s against 242 s), the shape
/// error lower on six curves (helix 0.10 → 0.04 %, trefoil 0.26 → 0.19 %),
/// higher on one (spring 0.22 → 0.26 %) and equal on eleven. A fresh
/// Jacobian after every accepted step cut the time 16 % but raised one
/// curve's error by 0.06 points.
pub const SECANT_RATIO: f64 = 0.5;

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
            cheap: false,
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
    while n > 0 && run.counts.evaluations < budget && !run.good_enough() {
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
        let cheap = self.problem.cheap_jacobian(&self.current, step);
        let is_cheap = cheap.is_some();
        let matrix = match cheap {
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
            cheap: is_cheap,
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
            let Some(step) = step else {
                return Ok(self.refresh_unless(fresh));
            };
            // A step the linear model itself expects no gain from (one a
            // bound cut short) is not worth a solve: more damping.
            if step.predicted >= self.current.error {
                self.damping *= 4.0;
                if self.damping > self.settings.max_damping {
                    return Ok(self.refresh_unless(fresh));
                }
                continue;
            }
            self.counts.evaluations += 1;
            let predicted = step.predicted;
            let trial = self.current.evaluate(self.problem, step.u);
            self.check_cancelled()?;
            if let (Some(trial), Some(j)) = (&trial, self.jacobian.as_mut()) {
                j.update(&self.current, trial);
            }
            match trial {
                Some(trial) if trial.error < self.current.error => {
                    return Ok(self.accept(trial, predicted, fresh));
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
    /// A small gain from a fresh Jacobian that the linear model promised
    /// far more for is a step that overshot where the model holds
    /// ([`overshot`]), not a stall: the damping, raised by the gain ratio,
    /// takes a shorter step next.
    fn accept(&mut self, trial: Iterate<P::State>, predicted: f64, fresh: bool) -> After {
        let gain = 1.0 - trial.error / self.current.error;
        let lowered = self.current.error - trial.error;
        let ratio = gain_ratio(self.current.error, trial.error, predicted);
        let overshoot = overshot(self.current.error, predicted, ratio, self.settings);
        let mut cheap = false;
        if let Some(j) = self.jacobian.as_mut() {
            j.fresh = false;
            cheap = j.cheap;
        }
        self.current = trial;
        self.damping = (self.damping * damping_factor(ratio)).max(1e-9);
        self.counts.iterations += 1;
        self.report();
        if self.good_enough() {
            return After::Stop;
        }
        // A fresh Jacobian's overshoot goes on; a secant one's small gain
        // calls for a fresh Jacobian either way.
        let stalled = gain < self.settings.min_gain || lowered < self.settings.resolution;
        if stalled && !(fresh && overshoot) {
            return self.refresh_unless(fresh);
        }
        if cheap && !fresh && ratio < self.settings.secant_ratio {
            self.refresh = true;
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

    /// Whether the current iterate meets `target`.
    fn good_enough(&self) -> bool {
        self.current.error <= self.settings.target
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

/// The gain ratio ρ of a step from |r| = `current` to `actual`: the fall of
/// |r|² it achieved over the fall the linear model predicted (to
/// `predicted`). ρ near 1: the model held over the step; near 0: it barely
/// did.
pub(crate) fn gain_ratio(current: f64, actual: f64, predicted: f64) -> f64 {
    let expected = current * current - predicted * predicted;
    match expected > 0.0 {
        true => (current * current - actual * actual) / expected,
        false => 1.0,
    }
}

/// A step's gain ratio below which a small gain counts as an overshoot
/// rather than a stall (see [`overshot`]).
const OVERSHOT_RATIO: f64 = 0.25;

/// Whether an accepted step from |r| = `current`, predicted to reach
/// `predicted` and achieving the gain ratio `ratio`, overshot: the linear
/// model promised a fall that counts as progress (at least `min_gain` of
/// |r| and `resolution`) and the step achieved less than `OVERSHOT_RATIO`
/// of it (in |r|²). Such a step says the model held over a shorter step
/// than this one, not that no step lowers |r| further; a stall the model
/// itself foresaw (a promised fall below progress) ends a fresh Jacobian's
/// steps as before.
fn overshot(current: f64, predicted: f64, ratio: f64, settings: &Settings) -> bool {
    let promised = current - predicted;
    ratio < OVERSHOT_RATIO
        && promised >= settings.resolution
        && promised >= settings.min_gain * current
}

/// The damping's factor after an accepted step of gain ratio ρ (Nielsen,
/// 1999): max(1/3, 1 − (2ρ − 1)³), so a step the model predicted well
/// lowers the damping threefold, one it predicted half-right keeps it, and
/// one it barely predicted raises it up to twofold — rather than a fixed
/// fall that sends the next step past where the model holds.
pub(crate) fn damping_factor(ratio: f64) -> f64 {
    let r = ratio.clamp(0.0, 1.0);
    (1.0 - (2.0 * r - 1.0).powi(3)).max(1.0 / 3.0)
}

mod step;

#[cfg(test)]
mod tests;
