//! The refine: Levenberg–Marquardt on the shape error, the last stage of a
//! design run, on the verification model.
//!
//! CMA-ES ranks candidates by one number and needs hundreds of them to find
//! a direction that a least-squares method reads off one Jacobian. Near the
//! end of a run the design is close and the model smooth in the patch
//! variables (patch geometry enters through exact overlap areas), so
//! Gauss–Newton steps converge where CMA-ES's samples stall.
//!
//! Residuals: the aligned sample differences rᵢ = R aᵢ + t − bᵢ of the
//! centreline against the target (200 samples, [`AlignedSamples`]), scaled by
//! 100 / (L √n) so that |r| is the shape error in percent of the length L.
//! The alignment R, t is re-fitted at every evaluation; since it minimises |r|,
//! its own change does not enter the first-order change of |r|² (envelope
//! theorem), so forward differences of the re-aligned residuals are the
//! Gauss–Newton Jacobian.
//!
//! Variables: the free patch variables in the unit cube of a design space
//! built around the refine's start (the same windows and fabrication limits
//! as the search's, so patches stay on the balloon), and, unless the length
//! is fixed, the balloon's length as a factor within ±`LENGTH_WINDOW`
//! (patch positions and lengths scale with it, as in the pipeline's length
//! correction): the shape error sees the inflated length, so the refine
//! chooses the length to cut together with the patches. Jacobian column j:
//! Jⱼ = (r(u + h eⱼ) − r(u)) / h, h = `STEP` (backwards at the upper bound),
//! each solve warm-started from the current state, the columns in parallel.
//! Step: (JᵀJ + λ D) δ = −Jᵀr with D = diag(JᵀJ) (Marquardt's scaling, floored
//! so a variable the shape does not see stays put), clamped into the cube;
//! accepted only if |r| falls (λ × 0.3), else λ × 4 and again. It stops when
//! the budget cannot pay another Jacobian, when an accepted step gains less
//! than `MIN_GAIN` of |r|, or when λ passes `MAX_DAMPING`.

use std::sync::atomic::{AtomicBool, Ordering};

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use super::objective::TargetProfiles;
use super::pipeline::{DesignRunError, stretch_balloon};
use super::variables::{DesignSpace, Freedom, VariableBounds};
use crate::curve::{AlignedSamples, Curve};
use crate::design::Design;
use crate::fe::{SimulateOptions, Simulation, simulate_from};
use crate::parallel::map_in_threads;

/// Forward-difference step in the unit cube (about 0.02 mm on a 20 mm
/// window): far above the solves' noise (a warm and a cold solve agree to
/// ~1e-5 mm), small against the curvature of the shape in the variables.
const STEP: f64 = 1e-3;
/// Initial Marquardt damping.
const FIRST_DAMPING: f64 = 1e-2;
/// Damping beyond which no step along the gradient lowers |r|: stop.
const MAX_DAMPING: f64 = 1e6;
/// An accepted step that lowers |r| by less than this fraction ends the refine.
const MIN_GAIN: f64 = 1e-3;
/// The balloon length's range in the refine: ±10 % of its start.
const LENGTH_WINDOW: f64 = 0.1;

/// What the refine needs to evaluate a design.
pub(super) struct RefineProblem<'a> {
    pub model: &'a SimulateOptions,
    pub target: &'a TargetProfiles,
    pub freedom: Freedom,
    pub bounds: &'a VariableBounds,
    /// The balloon length is a variable too (the request does not fix it).
    pub free_length: bool,
    /// Added to the model's residuals: a finer model's correction
    /// ([`super::correction`]); none for the model as it is.
    pub correction: Option<&'a DVector<f64>>,
    pub threads: usize,
    pub cancel: &'a AtomicBool,
}

/// The refine's result: the best design and its simulation on the model (the
/// start itself if no step lowered the shape error), and what it did (none
/// if the start's centreline could not be aligned with the target).
pub(super) struct Refined {
    pub design: Design,
    pub simulation: Simulation,
    pub summary: Option<RefineSummary>,
}

/// What the refine did, for the report: the shape error on the verification
/// model (the correction's model when there is one) before and after it, its
/// accepted steps and its solves.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RefineSummary {
    pub shape_error_before_percent: f64,
    pub shape_error_after_percent: f64,
    pub iterations: usize,
    /// Solves on the verification model (the correction's not counted).
    pub solves: usize,
    /// Free variables: a step needs this many solves for its Jacobian, plus
    /// one, so a smaller budget takes none.
    pub variables: usize,
    /// Element size of the finer model that corrected the refine and
    /// verified its result; absent when the refine ran uncorrected.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub corrected_on_element_mm: Option<f64>,
    /// Solves on that finer model.
    #[serde(default)]
    pub correction_solves: usize,
}

/// A design evaluated by the refine: its unit-cube point, simulation,
/// residuals and their norm (the shape error in %).
struct Iterate {
    u: Vec<f64>,
    simulation: Simulation,
    residuals: DVector<f64>,
    error: f64,
}

impl RefineProblem<'_> {
    /// `simulation` at unit-cube point `u` as an iterate with its residuals
    /// (|r| = shape error in %); the simulation back if its centreline cannot
    /// be aligned with the target.
    fn iterate(&self, u: Vec<f64>, simulation: Simulation) -> Result<Iterate, Box<Simulation>> {
        let Some(mut residuals) = self.residuals(&simulation.centreline) else {
            return Err(Box::new(simulation));
        };
        if let Some(correction) = self.correction {
            residuals += correction;
        }
        Ok(Iterate {
            u,
            simulation,
            error: residuals.norm(),
            residuals,
        })
    }

    /// The scaled aligned residuals of `centreline` against the target (|r|
    /// is the shape error in %); none if it cannot be aligned.
    pub fn residuals(&self, centreline: &Curve) -> Option<DVector<f64>> {
        let aligned = AlignedSamples::new(centreline, &self.target.shape_samples).ok()?;
        let n = aligned.residuals.len() as f64;
        let scale = 100.0 / (self.target.curve.length() * n.sqrt());
        let residuals = DVector::from_iterator(
            3 * aligned.residuals.len(),
            aligned
                .residuals
                .iter()
                .flat_map(|p| p.iter().map(|c| c * scale)),
        );
        residuals.norm().is_finite().then_some(residuals)
    }

    /// The design at `u`: the space's patches, then the balloon (and the
    /// patches' axial positions and lengths) scaled by the length factor,
    /// `u`'s last coordinate when the length is free.
    fn design_at(&self, space: &DesignSpace, base: &Design, u: &[f64]) -> Design {
        let mut design = Design {
            patches: space.patches(&u[..space.dimension()]),
            ..base.clone()
        };
        if self.free_length {
            let factor = 1.0 + LENGTH_WINDOW * (2.0 * u[space.dimension()].clamp(0.0, 1.0) - 1.0);
            stretch_balloon(&mut design, factor);
        }
        design
    }

    /// Simulates the design at `u`, warm-started from `from`.
    fn evaluate(
        &self,
        space: &DesignSpace,
        base: &Design,
        u: Vec<f64>,
        from: &Simulation,
    ) -> Option<Iterate> {
        if self.cancel.load(Ordering::Relaxed) {
            return None;
        }
        let design = self.design_at(space, base, &u);
        let simulation = simulate_from(&design, self.model, Some(from)).ok()?;
        self.iterate(u, simulation).ok()
    }

    /// Refines `start` (simulated on this problem's model as `simulation`)
    /// with at most `budget` further solves; `on_progress(iteration,
    /// evaluations, simulation)` hears every Jacobian and every accepted
    /// step.
    pub fn refine(
        &self,
        start: Design,
        simulation: Simulation,
        budget: usize,
        on_progress: &mut dyn FnMut(usize, usize, &Simulation),
    ) -> Result<Refined, DesignRunError> {
        let space = DesignSpace::new(
            start.patches.clone(),
            self.freedom,
            self.bounds,
            start.balloon.length_mm,
        )
        .map_err(DesignRunError::Variables)?;
        let n = space.dimension() + usize::from(self.free_length);
        let mut start_u = space.seed_point();
        if self.free_length {
            start_u.push(0.5);
        }
        let mut current = match self.iterate(start_u, simulation) {
            Ok(current) => current,
            Err(simulation) => {
                return Ok(Refined {
                    design: start,
                    simulation: *simulation,
                    summary: None,
                });
            }
        };
        let before = current.error;
        let mut evaluations = 0;
        let mut damping = FIRST_DAMPING;
        let mut iteration = 0;
        'jacobians: while n > 0 && evaluations + n < budget {
            let jacobian = self.jacobian(&space, &start, &current);
            evaluations += n;
            if self.cancel.load(Ordering::Relaxed) {
                return Err(DesignRunError::Cancelled);
            }
            on_progress(iteration, evaluations, &current.simulation);
            let normal = jacobian.transpose() * &jacobian;
            let gradient = jacobian.transpose() * &current.residuals;
            let floor = 1e-9 * normal.trace().max(f64::MIN_POSITIVE) / n as f64;
            loop {
                let Some(u) = damped_step(&normal, &gradient, damping, floor, &current.u) else {
                    break 'jacobians;
                };
                evaluations += 1;
                let trial = self.evaluate(&space, &start, u, &current.simulation);
                if self.cancel.load(Ordering::Relaxed) {
                    return Err(DesignRunError::Cancelled);
                }
                match trial {
                    Some(trial) if trial.error < current.error => {
                        let gain = 1.0 - trial.error / current.error;
                        current = trial;
                        damping = (damping * 0.3).max(1e-9);
                        iteration += 1;
                        on_progress(iteration, evaluations, &current.simulation);
                        if gain < MIN_GAIN {
                            break 'jacobians;
                        }
                        break;
                    }
                    _ => {
                        damping *= 4.0;
                        if damping > MAX_DAMPING || evaluations >= budget {
                            break 'jacobians;
                        }
                    }
                }
            }
        }
        Ok(Refined {
            design: self.design_at(&space, &start, &current.u),
            summary: Some(RefineSummary {
                shape_error_before_percent: before,
                shape_error_after_percent: current.error,
                iterations: iteration,
                solves: evaluations,
                variables: n,
                corrected_on_element_mm: None,
                correction_solves: 0,
            }),
            simulation: current.simulation,
        })
    }

    /// Forward-difference Jacobian of the residuals at `at`; a column whose
    /// solve failed is left zero (that variable stays put this iteration).
    fn jacobian(&self, space: &DesignSpace, base: &Design, at: &Iterate) -> DMatrix<f64> {
        let n = at.u.len();
        let columns: Vec<usize> = (0..n).collect();
        let differences = map_in_threads(&columns, self.threads, &|&j| {
            let mut u = at.u.clone();
            let h = if u[j] + STEP <= 1.0 { STEP } else { -STEP };
            u[j] += h;
            self.evaluate(space, base, u, &at.simulation)
                .map(|p| (p.residuals - &at.residuals) / h)
        });
        let mut jacobian = DMatrix::zeros(at.residuals.len(), n);
        for (j, column) in differences.into_iter().enumerate() {
            if let Some(column) = column {
                jacobian.set_column(j, &column);
            }
        }
        jacobian
    }
}

/// u + δ with (JᵀJ + λ D) δ = −Jᵀr, clamped into the unit cube; none if the
/// system cannot be solved or the clamped step does not move.
fn damped_step(
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
mod tests {
    use super::*;
    use crate::design::Patch;
    use crate::fe::mesh::MeshSpec;
    use crate::fe::simulate;

    /// Forward differences at `STEP` against differences at half of it: in
    /// the patch's length, width and angle the two agree to a few per mille
    /// (the model is smooth there, and the solves' noise, ~1e-8 in |r| between
    /// a warm and a cold solve, is far below the differences). In X and Y
    /// they differ by 14 and 22 %: moving the patch across the mesh, the
    /// response has kinks where its outline crosses mesh lines (measured along
    /// X: the slope drops threefold within 0.002 of the unit cube). So the
    /// refine's linear model is rougher in position, and a step is accepted
    /// only if the shape error falls.
    #[test]
    fn jacobian_columns_agree_with_a_halved_step_where_the_model_is_smooth() {
        let patch = Patch {
            x_mm: 0.0,
            y_mm: 40.0,
            h_mm: 15.0,
            w_mm: 2.5,
            theta_deg: 10.0,
        };
        let mut design = Design::reference(vec![patch]);
        design.balloon.length_mm = 80.0;
        let model = SimulateOptions {
            mesh: MeshSpec::uniform(2.0),
            ..SimulateOptions::default()
        };
        let mut other = design.clone();
        other.patches[0].theta_deg = 14.0;
        other.patches[0].h_mm = 17.0;
        let target = simulate(&other, &model).unwrap().centreline;
        let profiles = TargetProfiles::new(&target, 72, &Default::default());
        let cancel = AtomicBool::new(false);
        let bounds = VariableBounds::default();
        let problem = RefineProblem {
            model: &model,
            target: &profiles,
            freedom: Freedom::default(),
            bounds: &bounds,
            free_length: false,
            correction: None,
            threads: 2,
            cancel: &cancel,
        };
        let space =
            DesignSpace::new(design.patches.clone(), Freedom::default(), &bounds, 80.0).unwrap();
        let cold = simulate(&design, &model).unwrap();
        let start = problem
            .evaluate(&space, &design, space.seed_point(), &cold)
            .unwrap();
        let jacobian = problem.jacobian(&space, &design, &start);
        let mut disagreement = Vec::new();
        for j in 0..space.dimension() {
            let mut u = start.u.clone();
            u[j] += 0.5 * STEP;
            let half = problem
                .evaluate(&space, &design, u, &start.simulation)
                .unwrap();
            let column = (&half.residuals - &start.residuals) / (0.5 * STEP);
            disagreement.push((&column - jacobian.column(j)).norm() / column.norm());
        }
        println!("|J_j(h) − J_j(h/2)| / |J_j(h/2)| for X, Y, H, W, Θ: {disagreement:.4?}");
        assert!(
            disagreement[2..].iter().all(|d| *d < 0.02),
            "{disagreement:?}"
        );
        assert!(disagreement.iter().all(|d| *d < 0.5), "{disagreement:?}");
    }

    #[test]
    fn damped_step_solves_a_linear_least_squares_problem_when_undamped() {
        // r(u) = J u − b with J = [[2, 0], [0, 1], [1, 1]]: the undamped step
        // from u = 0 lands on the least-squares solution (JᵀJ)⁻¹ Jᵀ b.
        let j = DMatrix::from_row_slice(3, 2, &[2.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
        let b = DVector::from_vec(vec![0.8, 0.3, 0.5]);
        let u = [0.0, 0.0];
        let r = -&b;
        let normal = j.transpose() * &j;
        let next = damped_step(&normal, &(j.transpose() * r), 0.0, 1e-12, &u).unwrap();
        let exact = (j.transpose() * &j).try_inverse().unwrap() * j.transpose() * &b;
        assert!((next[0] - exact[0]).abs() < 1e-12 && (next[1] - exact[1]).abs() < 1e-12);
    }

    #[test]
    fn damped_step_stays_in_the_unit_cube_and_shrinks_with_damping() {
        let normal = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 1.0]);
        let gradient = DVector::from_vec(vec![-5.0, 0.1]);
        let u = [0.5, 0.5];
        let wild = damped_step(&normal, &gradient, 0.0, 1e-12, &u).unwrap();
        assert_eq!(wild[0], 1.0, "clamped at the upper bound");
        let damped = damped_step(&normal, &gradient, 1e3, 1e-12, &u).unwrap();
        assert!((damped[0] - 0.5).abs() < 0.01 && damped[0] > 0.5);
        // A step that only pushes against a bound already reached moves nothing.
        assert!(damped_step(&normal, &gradient, 0.0, 1e-12, &[1.0, 0.5]).is_some());
        let pinned = DVector::from_vec(vec![-5.0, 0.0]);
        assert!(damped_step(&normal, &pinned, 0.0, 1e-12, &[1.0, 0.5]).is_none());
    }
}
