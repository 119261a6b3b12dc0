//! Newton's loop: linearise, factor (shifted where needed), step, line
//! search, guard — each piece in its own module, this one only the order.

use std::time::Instant;

use super::super::tangent_factor::TangentFactor;
use super::guard::{ceiling, guard_definiteness};
use super::line_search::{line_search, sufficient_decrease};
use super::options::NewtonOptions;
use super::outcome::{SolveError, SolveStats};
use super::potential::{Linearisation, Potential, norm};
use super::shift::{decayed, factor_with_shift};
use super::stopping::{hard_limit, still_converging};
use super::timing::timed;

/// Minimises `potential` from `u` with `factor` (of the potential's
/// pattern); converged when |∇Π| ≤ `options.tolerance` · `scale`. Returns
/// the minimiser and the solve's statistics.
pub fn minimise(
    potential: &impl Potential,
    factor: &mut TangentFactor,
    u: Vec<f64>,
    scale: f64,
    options: &NewtonOptions,
) -> Result<(Vec<f64>, SolveStats), SolveError> {
    let mut newton = Newton {
        potential,
        factor,
        options,
        scale,
        started: Instant::now(),
        stats: SolveStats::default(),
        shift: 0.0,
        factored_with: None,
        guarding: options.definiteness_guard,
        residuals: Vec::new(),
    };
    let here = timed(&mut newton.stats.assembly_time, || potential.linearise(&u));
    let here = here.ok_or(SolveError::InadmissibleStart)?;
    newton.run(u, here)
}

/// The largest |bᵢ − aᵢ|.
fn largest_move(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (y - x).abs())
        .fold(0.0, f64::max)
}

/// A solve's state between iterations.
struct Newton<'a, 'f, P> {
    potential: &'a P,
    factor: &'a mut TangentFactor<'f>,
    options: &'a NewtonOptions,
    /// The load's size, which the residual is relative to.
    scale: f64,
    started: Instant,
    stats: SolveStats,
    /// The shift the next factorisation starts from.
    shift: f64,
    /// The shift with which `factor` already holds K + αI at the current
    /// state (the guard factorised it while accepting the step).
    factored_with: Option<f64>,
    guarding: bool,
    /// Relative residuals of the iterations so far.
    residuals: Vec<f64>,
}

impl<P: Potential> Newton<'_, '_, P> {
    fn run(
        mut self,
        mut u: Vec<f64>,
        mut here: Linearisation,
    ) -> Result<(Vec<f64>, SolveStats), SolveError> {
        let options = self.options;
        let mut residual = f64::INFINITY;
        // The largest move of an unknown in the last iteration (none yet;
        // only measured where `step_tolerance` bounds it).
        let mut last_move = 0.0;
        for iteration in 0..=hard_limit(options.max_iterations) {
            residual = norm(&here.gradient) / self.scale;
            if !residual.is_finite() {
                return Err(SolveError::InadmissibleStart);
            }
            self.residuals.push(residual);
            if residual <= options.tolerance && last_move <= options.step_tolerance {
                let stable = self.factored_with == Some(0.0) || self.stable(&mut here);
                return Ok((u, self.converged(iteration, residual, stable)));
            }
            if iteration >= options.max_iterations && !still_converging(&self.residuals) {
                break;
            }
            if self.started.elapsed() > options.time_limit {
                let limit_s = options.time_limit.as_secs_f64();
                return Err(SolveError::TimeLimit { limit_s, residual });
            }
            let line_search_failed = SolveError::LineSearch {
                iterations: iteration,
                residual,
            };
            let (step, slope, used_shift) = self.newton_step(&mut here, residual)?;
            if slope.is_nan() || slope >= 0.0 {
                return Err(line_search_failed);
            }
            let next = match self.full_step(&u, &step, (here.potential, slope)) {
                Some((end, linearised)) => (end, Some(linearised)),
                None => {
                    let searched = timed(&mut self.stats.line_search_time, || {
                        line_search(self.potential, &u, &step, (here.potential, slope), 0.5)
                    });
                    let Some(next) = searched else {
                        // Converged to round-off: the energy can no longer
                        // resolve the step, and the residual is within 1000×
                        // of the tolerance.
                        if residual <= 1e3 * options.tolerance {
                            let stable = self.stable(&mut here);
                            return Ok((u, self.converged(iteration, residual, stable)));
                        }
                        return Err(line_search_failed);
                    };
                    (next, None)
                }
            };
            let (moved, linearised) = self.guard(&u, &here, next, used_shift, residual)?;
            if options.step_tolerance.is_finite() {
                last_move = largest_move(&u, &moved);
            }
            (u, here) = (moved, linearised);
        }
        Err(SolveError::NotConverged {
            iterations: self.residuals.len().saturating_sub(1),
            residual,
        })
    }

    /// The Newton step −(K + αI)⁻¹∇Π at `here`, its slope along ∇Π and the
    /// shift α used: the guard's factorisation if it left one, else K
    /// factorised with the smallest shift that works from the current one.
    /// The shift then decays for the next iteration.
    fn newton_step(
        &mut self,
        here: &mut Linearisation,
        residual: f64,
    ) -> Result<(Vec<f64>, f64, f64), SolveError> {
        let used_shift = match self.factored_with.take() {
            Some(used) => used,
            None => {
                let (used, attempts) = timed(&mut self.stats.factor_time, || {
                    let (shift, stiffness) = (self.shift, here.stiffness);
                    factor_with_shift(
                        self.factor,
                        &mut here.values,
                        shift,
                        stiffness,
                        f64::INFINITY,
                    )
                });
                self.stats.factorisations += attempts;
                used.map_err(|shift| SolveError::Factorisation { shift, residual })?
            }
        };
        self.shift = decayed(used_shift, here.stiffness, self.options.shift_floor);
        let mut step: Vec<f64> = here.gradient.iter().map(|g| -g).collect();
        timed(&mut self.stats.substitution_time, || {
            self.factor.solve_in_place(&mut step)
        });
        let slope: f64 = step.iter().zip(&here.gradient).map(|(s, g)| s * g).sum();
        Ok((step, slope, used_shift))
    }

    /// The full step's end and its linearisation, if its energy passes
    /// Armijo's test from `energy` along `slope`: the line search's first
    /// trial and the next iteration's assembly in one. Most steps are taken
    /// whole, and Π alone costs most of an assembly (the material's
    /// thickness solve at every quadrature point dominates both), so
    /// assembling at once instead of trying Π first saves nearly one
    /// evaluation per iteration; a step that fails costs the tangent's
    /// share of one assembly more than before.
    fn full_step(
        &mut self,
        u: &[f64],
        step: &[f64],
        (energy, slope): (f64, f64),
    ) -> Option<(Vec<f64>, Linearisation)> {
        let end = self.potential.advanced(u, step, 1.0);
        let linearised = timed(&mut self.stats.assembly_time, || {
            self.potential.linearise(&end)
        })?;
        sufficient_decrease(energy, slope, 1.0, linearised.potential).then_some((end, linearised))
    }

    /// The guard on the line search's point; the state to go on from. If
    /// every shift up to the guard's ceiling failed there, at every halving,
    /// the next factorisation starts above the ceiling and the guard stands
    /// down for the rest of the solve, which has gone where halving does not
    /// help and each failed check costs factorisations.
    fn guard(
        &mut self,
        u: &[f64],
        here: &Linearisation,
        next: (Vec<f64>, Option<Linearisation>),
        used_shift: f64,
        residual: f64,
    ) -> Result<(Vec<f64>, Linearisation), SolveError> {
        let ceiling = ceiling(self.guarding, used_shift, here.stiffness);
        let guarded = guard_definiteness(
            self.potential,
            self.factor,
            (u, here.potential),
            next,
            (self.shift, ceiling),
            &mut self.stats,
        )
        .ok_or(SolveError::LineSearch {
            iterations: self.residuals.len() - 1,
            residual,
        })?;
        if let Err(tried) = guarded.factored_with {
            if !ceiling.is_finite() {
                // No shift at all made K + αI positive definite.
                return Err(SolveError::Factorisation {
                    shift: tried,
                    residual,
                });
            }
            self.shift = self.shift.max(ceiling);
            self.guarding = false;
        }
        self.factored_with = guarded.factored_with.ok();
        Ok((guarded.u, guarded.here))
    }

    /// Whether K factorises without shift at `here`: a stable equilibrium.
    fn stable(&mut self, here: &mut Linearisation) -> bool {
        let values = here.unshifted();
        timed(&mut self.stats.factor_time, || {
            self.factor.factorise(&values)
        })
    }

    fn converged(self, iterations: usize, residual: f64, stable: bool) -> SolveStats {
        SolveStats {
            iterations,
            residual,
            stable,
            ..self.stats
        }
    }
}
