//! The refine's Jacobians against forward differences, and its bounds.

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
            tolerance: 0.0,
            correction: None,
            threads: 2,
            cancel: &self.cancel,
            deadline: Deadline::default(),
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

/// A start beyond the fabrication limits (a 15 mm patch where the limit
/// is 12 mm, 2.5 mm wide where it is 2 mm) is brought within them before
/// the refine steps: the result's patch is within both limits, the
/// projection counted as one solve of the budget, and the reported
/// simulation is the refined design's own (a fresh solve agrees).
#[test]
fn a_start_beyond_the_limits_is_refined_within_them() {
    let mut scene = OnePatch::new();
    scene.bounds.h_max_mm = 12.0;
    scene.bounds.w_max_mm = 2.0;
    let problem = scene.problem(false);
    let cold = simulate(&scene.design, &scene.model).unwrap();
    let refined = problem
        .refine(scene.design.clone(), cold, 12, None, &mut |_, _, _| {})
        .unwrap();
    let patch = refined.design.patches[0];
    assert!(
        patch.h_mm <= 12.0 + 1e-9 && patch.w_mm <= 2.0 + 1e-9,
        "{patch:?}"
    );
    let summary = refined.summary.unwrap();
    assert!(summary.solves <= 12, "{summary:?}");
    let again = simulate(&refined.design, &scene.model).unwrap();
    let gap = again.centreline.largest_gap(&refined.simulation.centreline);
    assert!(gap < 1e-3, "{gap} mm");
}

/// The refine tolerance: refined to it, the one-patch scene stops at a
/// shape error within it in fewer solves than the refine that runs on
/// until its steps stop paying (which ends far below it); its summary
/// states the tolerance.
#[test]
fn the_refine_stops_within_its_tolerance() {
    let scene = OnePatch::new();
    let refine = |tolerance: f64| {
        let problem = RefineProblem {
            tolerance,
            ..scene.problem(false)
        };
        let cold = simulate(&scene.design, &scene.model).unwrap();
        let refined = problem
            .refine(scene.design.clone(), cold, 40, None, &mut |_, _, _| {})
            .unwrap();
        refined.summary.unwrap()
    };
    let full = refine(0.0);
    let tolerance = 0.2 * full.shape_error_before_percent;
    let within = refine(tolerance);
    assert!(full.shape_error_after_percent < 0.5 * tolerance, "{full:?}");
    assert!(within.shape_error_after_percent <= tolerance, "{within:?}");
    assert!(within.solves < full.solves, "{within:?} {full:?}");
    assert_eq!(within.tolerance_percent, tolerance);
}
