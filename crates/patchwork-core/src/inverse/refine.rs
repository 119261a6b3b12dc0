//! The refine: Levenberg–Marquardt on the shape error, the last stage of a
//! design run, on the verification model.
//!
//! CMA-ES ranks candidates by one number and needs hundreds of them to find
//! a direction that a least-squares method reads off one Jacobian. Near the
//! end of a run the design is close and the model smooth in the patch
//! variables (patch geometry enters through exact overlap areas), so
//! Gauss–Newton steps converge where CMA-ES's samples stall. The solver is
//! the generic one ([`crate::least_squares`]: damped steps, Broyden updates,
//! fresh Jacobians only when the secant one fails); this module is the
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

/// What the refine needs to evaluate a design.
pub(super) struct RefineProblem<'a> {
    pub model: &'a SimulateOptions,
    pub target: &'a TargetProfiles,
    pub freedom: Freedom,
    pub bounds: &'a VariableBounds,
    /// The balloon length is a variable too (the request does not fix it).
    pub free_length: bool,
    /// Added to the model's residuals: a finer model's correction
    /// ([`super::correction`], as [`SpaceMapped`]); none for the model as it is.
    pub correction: Option<&'a DVector<f64>>,
    pub threads: usize,
    pub cancel: &'a AtomicBool,
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
}

impl RefineProblem<'_> {
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
        let space = DesignSpace::new(
            start.patches.clone(),
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

    /// The design at `u`: the space's patches, then the balloon (and the
    /// patches' axial positions and lengths) scaled by the length factor,
    /// `u`'s last coordinate when the length is free.
    fn design_at(&self, u: &[f64]) -> Design {
        let mut design = Design {
            patches: self.space.patches(&u[..self.space.dimension()]),
            ..self.start.clone()
        };
        if self.problem.free_length {
            let factor =
                1.0 + LENGTH_WINDOW * (2.0 * u[self.space.dimension()].clamp(0.0, 1.0) - 1.0);
            design.stretch_length(factor);
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
        let start = match Iterate::new(residuals, self.start_point(), simulation) {
            Ok(start) => start,
            Err(simulation) => {
                return Ok(Refined {
                    design: self.start.clone(),
                    simulation,
                    summary: None,
                    jacobian: None,
                });
            }
        };
        let settings = least_squares::Settings {
            threads: self.problem.threads,
            ..least_squares::Settings::default()
        };
        let jacobian = jacobian.map(|j| self.per_cube(j, true));
        let solution =
            least_squares::minimise(residuals, start, budget, jacobian, &settings, on_progress)
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
                solves: counts.evaluations,
                variables: self.ranges.len(),
                corrected_on_element_mm: None,
                correction_solves: 0,
            }),
            simulation: solution.best.state,
            jacobian: solution.jacobian.map(|j| self.per_cube(j, false)),
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
        self.problem.residuals(&simulation.centreline)
    }

    fn solve(&self, u: &[f64], near: &Simulation) -> Option<Simulation> {
        let design = self.design_at(u);
        let caches = self.problem.caches;
        caches
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
        let here = self.residuals(&at.state)?;
        let mut jacobian = DMatrix::zeros(at.residuals.len(), at.u.len());
        for (j, (centreline, h)) in centrelines.iter().zip(steps).enumerate() {
            if let Some(r) = centreline.as_ref().and_then(|c| self.problem.residuals(c)) {
                jacobian.set_column(j, &((r - &here) / h));
            }
        }
        Some(jacobian)
    }

    fn cancelled(&self) -> bool {
        self.problem.cancel.load(Ordering::Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::mesh::MeshSpec;
    use crate::fe::simulate;
    use crate::least_squares::jacobian::forward_differences;

    /// The refine's forward-difference step in the unit cube.
    const STEP: f64 = 1e-3;

    /// The one-patch test scene on a uniform 2 mm mesh, with a target drawn
    /// by the same patch turned further (14°) and longer (17 mm).
    struct OnePatch {
        design: Design,
        model: SimulateOptions,
        profiles: TargetProfiles,
        bounds: VariableBounds,
        cancel: AtomicBool,
        caches: Caches,
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
                caches: Caches::default(),
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
                caches: &self.caches,
            }
        }

        /// The refine's problem around the scene's design, and its start
        /// point evaluated from a cold solve.
        fn start<'p>(
            &self,
            problem: &'p RefineProblem<'p>,
        ) -> (ShapeResiduals<'p>, Iterate<Simulation>) {
            let shape = ShapeResiduals::new(problem, self.design.clone()).unwrap();
            let cold = simulate(&self.design, &self.model).unwrap();
            let start = Iterate::new(&shape, shape.start_point(), cold)
                .ok()
                .unwrap();
            (shape, start)
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
        let problem = scene.problem(false);
        let (shape, start) = scene.start(&problem);
        let jacobian = forward_differences(&shape, &start, STEP, 2);
        let mut disagreement = Vec::new();
        for j in 0..start.u.len() {
            let mut u = start.u.clone();
            u[j] += 0.5 * STEP;
            let half = start.evaluate(&shape, u).unwrap();
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
        let problem = scene.problem(true);
        let (shape, start) = scene.start(&problem);
        let differences = forward_differences(&shape, &start, STEP, 2);
        let linearised = shape.cheap_jacobian(&start, STEP).unwrap();
        let disagreement: Vec<f64> = (0..differences.ncols())
            .map(|j| {
                let d = differences.column(j);
                (d - linearised.column(j)).norm() / d.norm()
            })
            .collect();
        println!("|J_lin − J_fd| / |J_fd| for X, Y, H, W, Θ, L: {disagreement:.4?}");
        assert!(disagreement.iter().all(|d| *d < 0.05), "{disagreement:?}");
    }
}
