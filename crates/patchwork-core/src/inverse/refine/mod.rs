//! The refine: Levenberg–Marquardt on the shape error, the last stage of a
//! design run, on the verification model.
//!
//! CMA-ES ranks candidates by one number and needs hundreds of them to find
//! a direction that a least-squares method reads off one Jacobian. Near the
//! end of a run the design is close and the model smooth in the patch
//! variables (patch geometry enters through exact overlap areas), so
//! Gauss–Newton steps converge where CMA-ES's samples stall. The solver is
//! the generic one ([`crate::least_squares`]: damped steps, Broyden updates,
//! fresh Jacobians when the secant one fails or predicts a step badly: the
//! refine's linearised Jacobian costs one evaluation); this module is the
//! problem.
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
//! (patch positions and lengths scale with it, as in the length correction):
//! the shape error sees the inflated length, so the refine chooses the length
//! to cut together with the patches. An evaluation is a solve warm-started
//! from the nearest state the refine holds.
//!
//! Jacobian: column j at step h = 10⁻³ (about 0.02 mm on a 20 mm window, far
//! above the solves' noise of ~1e-5 mm and small against the shape's
//! curvature in the variables; backwards at the upper bound) is the current
//! state's linearised response to the changed design (`fe::sensitivity`: one
//! factorisation of the tangent for all columns, then per column the forces
//! of the elements the change touches and one substitution), counted as one
//! solve. On the Hilbert curve's graded 1 mm model the 31 columns take about
//! 0.1 s against about 1.8 s for 31 warm-started solves on two threads, and
//! agree with those forward differences within 0.1–19 % per column (the most
//! in Y and Θ, where the forward differences' finite step crosses mesh
//! lines); the length column is linearised on the stretched mesh, where a
//! solve of the longer balloon would remesh it. Where the state's tangent is
//! not positive definite the solver takes forward differences instead (one
//! warm-started solve per column, in parallel).

use std::sync::atomic::{AtomicBool, Ordering};

use nalgebra::{DMatrix, DVector};

use super::caches::Caches;
use super::deadline::Deadline;
use super::errors::DesignRunError;
use super::objective::TargetProfiles;
use super::outcome::RefineSummary;
use super::variables::{DesignSpace, Freedom, VariableBounds};
use crate::curve::{AlignedSamples, Curve};
use crate::design::Design;
use crate::fe::sensitivity::linearised_centrelines;
use crate::fe::{SimulateOptions, Simulation};
use crate::least_squares::jacobian::stepped;
use crate::least_squares::{self, Iterate, Residuals, SpaceMapped};

/// The balloon length's range in the refine: ±10 % of its start.
const LENGTH_WINDOW: f64 = 0.1;

/// The smallest change of the shape error (% of the target's length) a
/// refine step counts as progress: 0.002 % is 2 µm on 100 mm, far below
/// what a built balloon or the model resolves. A step that gains less
/// ends the refine from a fresh Jacobian (or calls for one), as a step
/// gaining less than `min_gain` of the error does.
pub(super) const RESOLUTION_PERCENT: f64 = 0.002;

/// What the refine needs to evaluate a design.
pub(super) struct RefineProblem<'a> {
    pub model: &'a SimulateOptions,
    pub target: &'a TargetProfiles,
    pub freedom: Freedom,
    pub bounds: &'a VariableBounds,
    /// The balloon length is a variable too (the request does not fix it).
    pub free_length: bool,
    /// The shape error (% of the target's length) at or below which the
    /// refine stops: the design is then as close as needed (0: none;
    /// `Tuning::refine_tolerance`).
    pub tolerance: f64,
    /// Added to the model's residuals: a finer model's correction
    /// ([`super::correction`], as [`SpaceMapped`]); none for the model as it is.
    pub correction: Option<&'a DVector<f64>>,
    pub threads: usize,
    pub cancel: &'a AtomicBool,
    /// When the run's time limit passes: the refine then stops before its
    /// next solve, with its best design so far.
    pub deadline: Deadline,
    pub caches: &'a Caches,
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
    /// `design`'s state on the verification model where `simulation` is
    /// on a finer one (the correction's); none where the refine has none.
    pub verify_model_state: Option<Simulation>,
}

impl RefineProblem<'_> {
    /// The scaled aligned residuals of `centreline` against the target (|r|
    /// is the shape error in %), then, if the tube keeps clear of itself,
    /// the clearance's of the tube of `radii_mm` along it
    /// ([`TargetProfiles::clearance_residuals`]); none if it cannot be
    /// aligned.
    pub fn residuals(&self, centreline: &Curve, radii_mm: &[f64]) -> Option<DVector<f64>> {
        let shape = self.shape_residuals(centreline)?;
        let clear = self
            .target
            .clearance_residuals(centreline.points(), radii_mm);
        let count = shape.len() + clear.len();
        let residuals = DVector::from_iterator(count, shape.iter().copied().chain(clear));
        residuals.norm().is_finite().then_some(residuals)
    }

    /// The scaled aligned residuals of `centreline` against the target alone
    /// (the first [`Self::shape_rows`] of [`Self::residuals`]).
    pub fn shape_residuals(&self, centreline: &Curve) -> Option<DVector<f64>> {
        let aligned = AlignedSamples::new(centreline, &self.target.shape_samples).ok()?;
        let n = aligned.residuals.len() as f64;
        let scale = 100.0 / (self.target.curve.length() * n.sqrt());
        let shape = (aligned.residuals.iter()).flat_map(|p| p.iter().map(|c| c * scale));
        let residuals = DVector::from_iterator(3 * aligned.residuals.len(), shape);
        residuals.norm().is_finite().then_some(residuals)
    }

    /// How many of the residuals are the shape's: three per target sample.
    pub fn shape_rows(&self) -> usize {
        3 * self.target.shape_samples.points().len()
    }

    /// [`Self::residuals`] of a simulated design, its rings' radii its own.
    pub fn residuals_of(&self, simulation: &Simulation) -> Option<DVector<f64>> {
        self.residuals(&simulation.centreline, &simulation.radii())
    }

    /// Refines `start` (simulated on this problem's model as `simulation`)
    /// with at most `budget` further solves; `on_progress(iteration,
    /// evaluations, simulation)` hears every Jacobian and every accepted
    /// step. `jacobian`, if given (and of the right size), is used as the
    /// first Jacobian instead of a fresh one: a previous refine's last one
    /// ([`Refined::jacobian`], per unit of each variable), from a nearby
    /// design.
    pub fn refine(
        &self,
        start: Design,
        simulation: Simulation,
        budget: usize,
        jacobian: Option<DMatrix<f64>>,
        on_progress: &mut dyn FnMut(usize, usize, &Simulation),
    ) -> Result<Refined, DesignRunError> {
        let shape = ShapeResiduals::new(self, start)?;
        match self.correction {
            Some(offset) => {
                let mapped = SpaceMapped {
                    inner: &shape,
                    offset,
                };
                shape.minimise(&mapped, simulation, budget, jacobian, on_progress)
            }
            None => shape.minimise(&shape, simulation, budget, jacobian, on_progress),
        }
    }
}

/// The refine's least-squares problem around one start: the unit cube of a
/// design space centred on it (and the length factor), the residuals of the
/// inflated centreline.
struct ShapeResiduals<'p> {
    problem: &'p RefineProblem<'p>,
    space: DesignSpace,
    start: Design,
    /// Unit-cube coordinate j spans `ranges[j]` units of its variable.
    ranges: Vec<f64>,
}

impl<'p> ShapeResiduals<'p> {
    fn new(problem: &'p RefineProblem<'p>, start: Design) -> Result<Self, DesignRunError> {
        let space = DesignSpace::within_limits(
            &start.patches,
            problem.freedom,
            problem.bounds,
            start.balloon.length_mm,
        )
        .map_err(DesignRunError::Variables)?;
        let mut ranges: Vec<f64> = space.free.iter().map(|&(_, _, lo, hi)| hi - lo).collect();
        if problem.free_length {
            ranges.push(2.0 * LENGTH_WINDOW * start.balloon.length_mm);
        }
        Ok(ShapeResiduals {
            problem,
            space,
            start,
            ranges,
        })
    }

    /// The start's point: the space's seed, and the length factor 1.
    fn start_point(&self) -> Vec<f64> {
        let mut u = self.space.seed_point();
        if self.problem.free_length {
            u.push(0.5);
        }
        u
    }

    /// The design at `u`: the space's patches, then the balloon and the
    /// patches' axial positions scaled by the length factor, `u`'s last
    /// coordinate when the length is free (the sizes are variables of their
    /// own, within the fabrication limits).
    fn design_at(&self, u: &[f64]) -> Design {
        let mut design = Design {
            patches: self.space.patches(&u[..self.space.dimension()]),
            ..self.start.clone()
        };
        if self.problem.free_length {
            let factor =
                1.0 + LENGTH_WINDOW * (2.0 * u[self.space.dimension()].clamp(0.0, 1.0) - 1.0);
            design.stretch_positions(factor);
        }
        design
    }

    /// Runs the solver on `residuals` (this problem, or this problem space
    /// mapped) from the start, `jacobian` given per unit of each variable.
    fn minimise<P: Residuals<State = Simulation>>(
        &self,
        residuals: &P,
        simulation: Simulation,
        budget: usize,
        jacobian: Option<DMatrix<f64>>,
        on_progress: &mut dyn FnMut(usize, usize, &Simulation),
    ) -> Result<Refined, DesignRunError> {
        let u = self.start_point();
        let unrefined = |simulation| Refined {
            design: self.start.clone(),
            simulation,
            summary: None,
            jacobian: None,
            verify_model_state: None,
        };
        // A start beyond a fabrication limit is brought within it first, for
        // one solve of the budget.
        let bounds = self.problem.bounds;
        let beyond = !self.start.patches.iter().all(|p| bounds.holds_size(p));
        let (simulation, spent) = match beyond {
            false => (simulation, 0),
            true if budget == 0 => return Ok(unrefined(simulation)),
            true => match residuals.solve(&u, &simulation) {
                Some(inside) => (inside, 1),
                None => return Ok(unrefined(simulation)),
            },
        };
        let start = match Iterate::new(residuals, u, simulation) {
            Ok(start) => start,
            Err(simulation) => {
                return Ok(Refined {
                    design: self.start.clone(),
                    simulation,
                    summary: None,
                    jacobian: None,
                    verify_model_state: None,
                });
            }
        };
        let settings = least_squares::Settings {
            threads: self.problem.threads,
            resolution: RESOLUTION_PERCENT,
            target: self.problem.tolerance,
            ..least_squares::Settings::default()
        };
        let jacobian = jacobian.map(|j| self.per_cube(j, true));
        let budget = budget - spent;
        let mut on_progress = |i, e, s: &Simulation| on_progress(i, spent + e, s);
        let solution = least_squares::minimise(
            residuals,
            start,
            budget,
            jacobian,
            &settings,
            &mut on_progress,
        )
        .map_err(|least_squares::Cancelled| DesignRunError::Cancelled)?;
        let counts = solution.counts;
        Ok(Refined {
            design: self.design_at(&solution.best.u),
            summary: Some(RefineSummary {
                shape_error_before_percent: solution.start_error,
                shape_error_after_percent: solution.best.error,
                iterations: counts.iterations,
                jacobians: counts.jacobians,
                differenced_jacobians: counts.differenced,
                solves: spent + counts.evaluations,
                variables: self.ranges.len(),
                corrected_on_element_mm: None,
                correction_solves: 0,
                tolerance_percent: self.problem.tolerance,
            }),
            simulation: solution.best.state,
            jacobian: solution.jacobian.map(|j| self.per_cube(j, false)),
            verify_model_state: None,
        })
    }

    /// A Jacobian per unit of each variable rescaled to the unit cube
    /// (`to_cube`), or back. A matrix of another width is left as it is (the
    /// solver then ignores it).
    fn per_cube(&self, mut matrix: DMatrix<f64>, to_cube: bool) -> DMatrix<f64> {
        if matrix.ncols() != self.ranges.len() {
            return matrix;
        }
        for (j, range) in self.ranges.iter().enumerate() {
            if to_cube {
                matrix.column_mut(j).scale_mut(*range);
            } else {
                matrix.column_mut(j).unscale_mut(*range);
            }
        }
        matrix
    }
}

impl Residuals for ShapeResiduals<'_> {
    type State = Simulation;

    fn residuals(&self, simulation: &Simulation) -> Option<DVector<f64>> {
        self.problem.residuals_of(simulation)
    }

    fn solve(&self, u: &[f64], near: &Simulation) -> Option<Simulation> {
        let design = self.design_at(u);
        (self.problem.caches)
            .simulate_from(&design, self.problem.model, Some(near))
            .ok()
    }

    /// The Jacobian from linearised responses (`fe::sensitivity`): one
    /// factorisation of the tangent and the changed elements' forces per
    /// column, instead of a solve per column. A column whose response fails
    /// is left zero. `None` when the state's tangent is not positive definite.
    fn cheap_jacobian(&self, at: &Iterate<Simulation>, step: f64) -> Option<DMatrix<f64>> {
        let (points, steps): (Vec<Vec<f64>>, Vec<f64>) =
            (0..at.u.len()).map(|j| stepped(&at.u, j, step)).unzip();
        let designs: Vec<Design> = points.iter().map(|u| self.design_at(u)).collect();
        let current = self.design_at(&at.u);
        let (model, threads) = (self.problem.model, self.problem.threads);
        let patterns = &self.problem.caches.patterns;
        let centrelines =
            linearised_centrelines(&current, &at.state, model, &designs, threads, patterns)?;
        // The residuals without any correction, which differences cancel.
        // The linearised tube keeps the state's radii.
        let here = self.residuals(&at.state)?;
        let radii = at.state.radii();
        let mut jacobian = DMatrix::zeros(at.residuals.len(), at.u.len());
        for (j, (centreline, h)) in centrelines.iter().zip(steps).enumerate() {
            let residuals = |c: &Curve| self.problem.residuals(c, &radii);
            if let Some(r) = centreline.as_ref().and_then(residuals) {
                jacobian.set_column(j, &((r - &here) / h));
            }
        }
        Some(jacobian)
    }

    fn cancelled(&self) -> bool {
        self.problem.cancel.load(Ordering::Relaxed)
    }

    fn out_of_time(&self) -> bool {
        self.problem.deadline.passed()
    }
}

mod robust;

pub(super) use robust::RobustRefined;

#[cfg(test)]
mod tests;
