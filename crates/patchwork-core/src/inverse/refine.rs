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
//! where the centreline at u + h eⱼ is the current state's linearised
//! response to the changed design (`fe::sensitivity`: one factorisation of
//! the tangent for all columns, then per column the forces of the elements
//! the change touches and one substitution). On the Hilbert curve's graded
//! 1 mm model the 31 columns take about 0.1 s against about 1.8 s for 31
//! warm-started solves on two threads, and agree with those forward
//! differences within 0.1–19 % per column (the most in Y and Θ, where the
//! forward differences' finite step crosses mesh lines); the length column
//! is linearised on the stretched mesh, where a solve of the longer balloon
//! would remesh it. Where the state's tangent is not positive definite the
//! columns are solved instead (one warm-started solve each, in parallel).
//! Step: (JᵀJ + λ D) δ = −Jᵀr with D = diag(JᵀJ) (Marquardt's scaling, floored
//! so a variable the shape does not see stays put), clamped into the cube;
//! accepted only if |r| falls (λ × 0.3), else λ × 4 and again.
//!
//! A linearised Jacobian is counted as one solve of the budget, a step as
//! one. After every trial, accepted or not, J gets Broyden's rank-one secant
//! update (Madsen, Nielsen & Tingleff, "Methods for non-linear least squares
//! problems", 2004, §3.4) and the next step uses it; a fresh Jacobian is
//! taken only when the secant one fails: `STALE_REJECTIONS` rejected steps
//! in a row, no step left, or an accepted step that gains less than
//! `MIN_GAIN`. (A fresh Jacobian after every accepted step, cheap as it now
//! is, did worse: on the Hilbert curve fine took 54 s instead of 28 s for
//! the same 0.134 %, draft reached 0.141 % instead of 0.138 %; single runs
//! without the search, thirteenth session.) It stops when the budget
//! cannot pay the next solve (or the next Jacobian), or when a *fresh*
//! Jacobian fails: its accepted step gains less than `MIN_GAIN` of |r|, or
//! λ passes `MAX_DAMPING`. So every stop but the budget's is confirmed by a
//! fresh Jacobian at the final point.

use std::sync::atomic::{AtomicBool, Ordering};

use nalgebra::{DMatrix, DVector};

use super::errors::DesignRunError;
use super::objective::TargetProfiles;
use super::outcome::RefineSummary;
use super::variables::{DesignSpace, Freedom, VariableBounds};
use crate::curve::{AlignedSamples, Curve};
use crate::design::Design;
use crate::fe::sensitivity::linearised_centrelines;
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
/// Rejected steps in a row after which a secant (Broyden-updated) Jacobian
/// is replaced by forward differences.
const STALE_REJECTIONS: usize = 3;

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
    /// The last Jacobian (Broyden-updated to the last trial), for a refine
    /// that goes on from here: per unit of each variable (mm, degrees, mm
    /// of balloon length), since the next refine's unit cube is centred on
    /// its own start and may span other ranges.
    pub jacobian: Option<DMatrix<f64>>,
}

/// A design evaluated by the refine: its unit-cube point, simulation,
/// residuals and their norm (the shape error in %).
struct Iterate {
    u: Vec<f64>,
    simulation: Simulation,
    residuals: DVector<f64>,
    error: f64,
}

/// The Jacobian of the residuals in the unit-cube variables: forward
/// differences at the current point (`fresh`), or a secant approximation
/// carried along the steps by Broyden's update.
struct Jacobian {
    matrix: DMatrix<f64>,
    fresh: bool,
}

impl Jacobian {
    /// Broyden's rank-one update from a step `from` → `to` (accepted or
    /// not); see [`broyden_update`].
    fn update(&mut self, from: &Iterate, to: &Iterate) {
        let step =
            DVector::from_iterator(from.u.len(), to.u.iter().zip(&from.u).map(|(b, a)| b - a));
        broyden_update(&mut self.matrix, &step, &(&to.residuals - &from.residuals));
    }
}

/// Broyden's rank-one update: J ← J + (Δr − J δ) δᵀ / (δᵀδ), the least
/// change of J (in the Frobenius norm) that makes it reproduce the observed
/// change `change` = Δr of the residuals along `step` = δ (the secant
/// condition J δ = Δr); J v is kept for every v orthogonal to δ. A zero or
/// non-finite step leaves J as it is.
fn broyden_update(jacobian: &mut DMatrix<f64>, step: &DVector<f64>, change: &DVector<f64>) {
    let length_squared = step.norm_squared();
    if length_squared == 0.0 || !length_squared.is_finite() {
        return;
    }
    let misfit = change - &*jacobian * step;
    *jacobian += misfit * step.transpose() / length_squared;
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
            design.stretch_length(factor);
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
    /// step. `jacobian`, if given (and of the right size), is used as the
    /// first Jacobian instead of forward differences: a previous refine's
    /// last one ([`Refined::jacobian`], per unit of each variable), from a
    /// nearby design.
    pub fn refine(
        &self,
        start: Design,
        simulation: Simulation,
        budget: usize,
        jacobian: Option<DMatrix<f64>>,
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
                    jacobian: None,
                });
            }
        };
        let before = current.error;
        let mut evaluations = 0;
        let mut damping = FIRST_DAMPING;
        let mut iteration = 0;
        let mut jacobians = 0;
        let mut differenced = 0;
        // Unit-cube coordinate j spans `ranges[j]` units of its variable.
        let mut ranges: Vec<f64> = space.free.iter().map(|&(_, _, lo, hi)| hi - lo).collect();
        if self.free_length {
            ranges.push(2.0 * LENGTH_WINDOW * start.balloon.length_mm);
        }
        let mut jacobian = jacobian
            .filter(|j| j.ncols() == n && j.nrows() == current.residuals.len())
            .map(|mut matrix| {
                for (j, range) in ranges.iter().enumerate() {
                    matrix.column_mut(j).scale_mut(*range);
                }
                Jacobian {
                    matrix,
                    fresh: false,
                }
            });
        // Forward differences are due at the start unless a Jacobian was
        // handed in, and again whenever the secant one fails.
        let mut refresh = jacobian.is_none();
        'steps: while n > 0 && evaluations < budget {
            if refresh {
                // Linearised responses cost about one solve; forward
                // differences, where the state's tangent is not positive
                // definite, one per variable.
                if evaluations + 1 >= budget {
                    break;
                }
                let matrix = match self.linearised_jacobian(&space, &start, &current) {
                    Some(matrix) => {
                        evaluations += 1;
                        matrix
                    }
                    None if evaluations + n < budget => {
                        evaluations += n;
                        differenced += 1;
                        self.forward_differences(&space, &start, &current)
                    }
                    None => break,
                };
                jacobians += 1;
                if self.cancel.load(Ordering::Relaxed) {
                    return Err(DesignRunError::Cancelled);
                }
                on_progress(iteration, evaluations, &current.simulation);
                jacobian = Some(Jacobian {
                    matrix,
                    fresh: true,
                });
                // The secant Jacobian's failures raised the damping; the
                // fresh one starts from no more than the first.
                (refresh, damping) = (false, damping.min(FIRST_DAMPING));
            }
            let Some(j) = jacobian.as_mut() else {
                break;
            };
            let mut rejected = 0;
            loop {
                let normal = j.matrix.transpose() * &j.matrix;
                let gradient = j.matrix.transpose() * &current.residuals;
                let floor = 1e-9 * normal.trace().max(f64::MIN_POSITIVE) / n as f64;
                let step = damped_step(&normal, &gradient, damping, floor, &current.u);
                if evaluations >= budget {
                    break 'steps;
                }
                // No step left: from a fresh Jacobian, done; from a stale
                // one, take forward differences.
                let Some(u) = step else {
                    if j.fresh {
                        break 'steps;
                    }
                    refresh = true;
                    continue 'steps;
                };
                evaluations += 1;
                let trial = self.evaluate(&space, &start, u, &current.simulation);
                if self.cancel.load(Ordering::Relaxed) {
                    return Err(DesignRunError::Cancelled);
                }
                if let Some(trial) = &trial {
                    j.update(&current, trial);
                }
                match trial {
                    Some(trial) if trial.error < current.error => {
                        let gain = 1.0 - trial.error / current.error;
                        let stale = !j.fresh;
                        j.fresh = false;
                        current = trial;
                        // (Nielsen's gain-ratio rule, Madsen et al. eq.
                        // 2.21, rejects fewer trials but bought nothing:
                        // draft 0.159 → 0.151 % on the Hilbert curve, 0.658
                        // → 0.697 % on the pancake, 1.222 → 1.232 % and 20 %
                        // slower on the spring; single runs, twelfth session.)
                        damping = (damping * 0.3).max(1e-9);
                        iteration += 1;
                        on_progress(iteration, evaluations, &current.simulation);
                        if gain < MIN_GAIN {
                            // A small gain from a secant Jacobian may be the
                            // Jacobian's fault: check with a fresh one.
                            if !stale {
                                break 'steps;
                            }
                            refresh = true;
                        }
                        continue 'steps;
                    }
                    _ => {
                        damping *= 4.0;
                        rejected += 1;
                        let gave_up = damping > MAX_DAMPING;
                        if gave_up || (!j.fresh && rejected >= STALE_REJECTIONS) {
                            if j.fresh {
                                break 'steps;
                            }
                            refresh = true;
                            continue 'steps;
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
                jacobians,
                differenced_jacobians: differenced,
                solves: evaluations,
                variables: n,
                corrected_on_element_mm: None,
                correction_solves: 0,
            }),
            simulation: current.simulation,
            jacobian: jacobian.map(|j| {
                let mut matrix = j.matrix;
                for (j, range) in ranges.iter().enumerate() {
                    matrix.column_mut(j).unscale_mut(*range);
                }
                matrix
            }),
        })
    }

    /// Forward-difference Jacobian of the residuals at `at`; a column whose
    /// solve failed is left zero (that variable stays put this iteration).
    fn forward_differences(
        &self,
        space: &DesignSpace,
        base: &Design,
        at: &Iterate,
    ) -> DMatrix<f64> {
        let columns: Vec<usize> = (0..at.u.len()).collect();
        let differences = map_in_threads(&columns, self.threads, &|&j| {
            let (u, h) = Self::stepped(&at.u, j);
            self.evaluate(space, base, u, &at.simulation)
                .map(|p| (p.residuals - &at.residuals) / h)
        });
        let mut jacobian = DMatrix::zeros(at.residuals.len(), at.u.len());
        for (j, column) in differences.into_iter().enumerate() {
            if let Some(column) = column {
                jacobian.set_column(j, &column);
            }
        }
        jacobian
    }

    /// The unit-cube point of column `j`'s difference from `u`, and its step
    /// (backwards at the upper bound).
    fn stepped(u: &[f64], j: usize) -> (Vec<f64>, f64) {
        let mut u = u.to_vec();
        let h = if u[j] + STEP <= 1.0 { STEP } else { -STEP };
        u[j] += h;
        (u, h)
    }

    /// The Jacobian at `at` from linearised responses (`fe::sensitivity`):
    /// one factorisation of the tangent and the changed elements' forces per
    /// column, instead of a solve per column. A column whose response fails
    /// is left zero. `None` when the state's tangent is not positive definite.
    fn linearised_jacobian(
        &self,
        space: &DesignSpace,
        base: &Design,
        at: &Iterate,
    ) -> Option<DMatrix<f64>> {
        let (points, steps): (Vec<Vec<f64>>, Vec<f64>) =
            (0..at.u.len()).map(|j| Self::stepped(&at.u, j)).unzip();
        let designs: Vec<Design> = points
            .iter()
            .map(|u| self.design_at(space, base, u))
            .collect();
        let current = self.design_at(space, base, &at.u);
        let centrelines =
            linearised_centrelines(&current, &at.simulation, self.model, &designs, self.threads)?;
        // The residuals without the correction, which differences cancel.
        let here = self.residuals(&at.simulation.centreline)?;
        let mut jacobian = DMatrix::zeros(at.residuals.len(), at.u.len());
        for (j, (centreline, h)) in centrelines.iter().zip(steps).enumerate() {
            if let Some(r) = centreline.as_ref().and_then(|c| self.residuals(c)) {
                jacobian.set_column(j, &((r - &here) / h));
            }
        }
        Some(jacobian)
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
    use crate::fe::mesh::MeshSpec;
    use crate::fe::simulate;

    /// The one-patch test scene on a uniform 2 mm mesh, with a target drawn
    /// by the same patch turned further (14°) and longer (17 mm).
    struct OnePatch {
        design: Design,
        model: SimulateOptions,
        profiles: TargetProfiles,
        bounds: VariableBounds,
        cancel: AtomicBool,
    }

    impl OnePatch {
        fn new() -> OnePatch {
            let design = Design::one_patch_test_scene();
            let model = SimulateOptions {
                mesh: MeshSpec::uniform(2.0),
                ..SimulateOptions::default()
            };
            let mut other = design.clone();
            other.patches[0].theta_deg = 14.0;
            other.patches[0].h_mm = 17.0;
            let target = simulate(&other, &model).unwrap().centreline;
            OnePatch {
                design,
                model,
                profiles: TargetProfiles::new(&target, 72, &Default::default()),
                bounds: VariableBounds::default(),
                cancel: AtomicBool::new(false),
            }
        }

        fn problem(&self, free_length: bool) -> RefineProblem<'_> {
            RefineProblem {
                model: &self.model,
                target: &self.profiles,
                freedom: Freedom::default(),
                bounds: &self.bounds,
                free_length,
                correction: None,
                threads: 2,
                cancel: &self.cancel,
            }
        }

        fn space(&self) -> DesignSpace {
            DesignSpace::new(
                self.design.patches.clone(),
                Freedom::default(),
                &self.bounds,
                self.design.balloon.length_mm,
            )
            .unwrap()
        }
    }

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
        let scene = OnePatch::new();
        let (design, problem) = (&scene.design, scene.problem(false));
        let space = scene.space();
        let cold = simulate(design, &scene.model).unwrap();
        let start = problem
            .evaluate(&space, design, space.seed_point(), &cold)
            .unwrap();
        let jacobian = problem.forward_differences(&space, design, &start);
        let mut disagreement = Vec::new();
        for j in 0..space.dimension() {
            let mut u = start.u.clone();
            u[j] += 0.5 * STEP;
            let half = problem
                .evaluate(&space, design, u, &start.simulation)
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

    /// The linearised Jacobian (one factorisation of the tangent,
    /// `fe::sensitivity`) against forward differences by solves at `STEP`,
    /// on a one-patch balloon with a free length: every column within 5 %
    /// (measured 0.04–3 %, the most in X and Y where the forward differences
    /// cross mesh lines, as above).
    #[test]
    fn the_linearised_jacobian_agrees_with_forward_differences() {
        let scene = OnePatch::new();
        let (design, problem) = (&scene.design, scene.problem(true));
        let space = scene.space();
        let cold = simulate(design, &scene.model).unwrap();
        let mut u = space.seed_point();
        u.push(0.5);
        let start = problem.evaluate(&space, design, u, &cold).unwrap();
        let differences = problem.forward_differences(&space, design, &start);
        let linearised = problem.linearised_jacobian(&space, design, &start).unwrap();
        let disagreement: Vec<f64> = (0..differences.ncols())
            .map(|j| {
                let d = differences.column(j);
                (d - linearised.column(j)).norm() / d.norm()
            })
            .collect();
        println!("|J_lin − J_fd| / |J_fd| for X, Y, H, W, Θ, L: {disagreement:.4?}");
        assert!(disagreement.iter().all(|d| *d < 0.05), "{disagreement:?}");
    }

    #[test]
    fn broyden_update_meets_the_secant_condition_and_keeps_the_rest() {
        let mut jacobian = DMatrix::from_row_slice(3, 2, &[1.0, 2.0, 0.5, -1.0, 3.0, 0.0]);
        let before = jacobian.clone();
        let step = DVector::from_vec(vec![0.3, -0.1]);
        let change = DVector::from_vec(vec![0.2, 0.4, -0.7]);
        broyden_update(&mut jacobian, &step, &change);
        assert!((&jacobian * &step - &change).norm() < 1e-14);
        let orthogonal = DVector::from_vec(vec![0.1, 0.3]);
        assert!((&jacobian * &orthogonal - &before * &orthogonal).norm() < 1e-14);
        // On a linear map the secant is exact: an exact Jacobian stays put.
        let exact = before.clone();
        let mut same = before.clone();
        broyden_update(&mut same, &step, &(&exact * &step));
        assert!((same - exact).norm() < 1e-14);
        let mut unmoved = before.clone();
        broyden_update(&mut unmoved, &DVector::zeros(2), &change);
        assert_eq!(unmoved, before);
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
