//! Linearised responses: where a converged state's centreline goes, to first
//! order, when its design changes (direct differentiation of the discrete
//! equilibrium), for the refine's Jacobian.
//!
//! At the converged state x of design p, ∇Π(x; p) = 0. For a changed design
//! p′ on the same mesh (stretched to its balloon length, below),
//!
//!   ∇Π(x + Δx; p′) ≈ ∇Π(x; p′) + K(x; p) Δx = 0
//!   ⇒ Δx = −K⁻¹ [∇Π(x; p′) − ∇Π(x; p)],
//!
//! with K the tangent at the converged state (the difference K(x; p′) −
//! K(x; p) enters only at second order). The base gradient, zero to the
//! solve's tolerance, is subtracted so that its remainder does not enter.
//! One factorisation of K serves every change; a change then costs the
//! elements whose section it alters (those a moved patch outline touches)
//! and one forward/back substitution, instead of a Newton solve of about a
//! dozen factorisations. The centreline of x + Δx is fitted as a solve's is
//! (`centreline.rs`), on the stretched mesh.
//!
//! Each changed design is linearised on the converged state's own mesh,
//! stretched to its balloon length ([`TubeMesh::stretched_to`]), so node k
//! stays the same material point: a forward difference by solves would
//! remesh the changed design (a graded mesh's fine zones follow its patches,
//! a longer balloon may get a ring more), which adds a jump of
//! discretisation error to the response. An unstable base state (K not
//! positive definite) has no linearised response: the caller solves.

use super::centreline::rings;
use super::mesh::TubeMesh;
use super::model::Model;
use super::newton::{PatternCache, Solver};
use super::simulate::{SimulateOptions, Simulation};
use crate::curve::{Curve, Point};
use crate::design::Design;
use crate::parallel::map_in_threads;

/// The centrelines that the designs `changes` take to first order from
/// `simulation`, the converged state of `base` under `options`: one per
/// change (none where the changed model leaves a material's domain at the
/// base state, or its centreline cannot be fitted). `None` for all when the
/// base state's tangent is not positive definite or a change has another
/// balloon radius. The changes' forces are assembled on `threads` threads.
pub fn linearised_centrelines(
    base: &Design,
    simulation: &Simulation,
    options: &SimulateOptions,
    changes: &[Design],
    threads: usize,
    patterns: &PatternCache,
) -> Option<Vec<Option<Curve>>> {
    let states = linearised_states(base, simulation, options, changes, threads, patterns)?;
    Some(states.into_iter().map(|s| Some(s?.centreline)).collect())
}

/// A change's state to first order: its nodes' positions on the base mesh
/// stretched to its balloon length, and their centreline.
pub struct Linearised {
    pub positions: Vec<Point>,
    pub centreline: Curve,
}

/// The states `changes` take to first order from `simulation`, as
/// [`linearised_centrelines`] finds them: a Newton solve of a change that
/// alters the whole tube (its pressure or wall) starts from one in about
/// half the iterations it takes from `simulation`.
pub fn linearised_states(
    base: &Design,
    simulation: &Simulation,
    options: &SimulateOptions,
    changes: &[Design],
    threads: usize,
    patterns: &PatternCache,
) -> Option<Vec<Option<Linearised>>> {
    let mesh = &simulation.mesh;
    if changes.iter().any(|d| d.balloon.radius_mm != mesh.radius) {
        return None;
    }
    let model = Model::new(base, mesh.clone(), options.cut_elements);
    let x = &simulation.positions;
    if x.len() != mesh.nodes.len() {
        return None;
    }
    let changed: Vec<Option<(TubeMesh, Vec<f64>)>> = map_in_threads(changes, threads, &|design| {
        let stretched = mesh.stretched_to(design.balloon.length_mm);
        let changed = Model::new(design, stretched, options.cut_elements);
        let load = changed.gradient_change(&model, x)?;
        Some((changed.mesh, load))
    });
    let (meshes, loads): (Vec<Option<TubeMesh>>, Vec<Option<Vec<f64>>>) = changed
        .into_iter()
        .map(|c| c.map_or((None, None), |(mesh, load)| (Some(mesh), Some(load))))
        .unzip();
    let mut responses = Solver::new(&model, patterns)
        .ok()?
        .linear_responses(&model, x, loads.into_iter().flatten().collect())?
        .into_iter();
    let u = model.unknowns(x);
    let moved: Vec<Option<(TubeMesh, Vec<Point>)>> = meshes
        .into_iter()
        .map(|mesh| {
            let mesh = mesh?;
            let du = responses.next()?;
            let shifted: Vec<f64> = u.iter().zip(&du).map(|(a, d)| a + d).collect();
            Some((mesh, model.positions(&shifted)))
        })
        .collect();
    let centrelines = map_in_threads(&moved, threads, &|m| {
        let (mesh, x) = m.as_ref()?;
        let centres = rings(mesh, x, options.rings)
            .iter()
            .map(|r| r.centre)
            .collect();
        Curve::from_points(centres).ok()
    });
    // The positions moved into their answer, not copied: the refine's
    // Jacobian asks for the centrelines alone, column by column.
    let states = moved.into_iter().zip(centrelines).map(|(m, centreline)| {
        let (_, positions) = m?;
        Some(Linearised {
            positions,
            centreline: centreline?,
        })
    });
    Some(states.collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::mesh::MeshSpec;
    use crate::fe::{simulate, simulate_from};

    fn scene() -> (Design, SimulateOptions, Simulation) {
        let design = Design::one_patch_test_scene();
        let options = SimulateOptions {
            mesh: MeshSpec::uniform(2.0),
            ..SimulateOptions::default()
        };
        let simulation = simulate(&design, &options).unwrap();
        (design, options, simulation)
    }

    /// The design with patch variable `variable` (X, Y, H, W, Θ; 5 is the
    /// balloon length) moved by `by`.
    fn changed(design: &Design, variable: usize, by: f64) -> Design {
        let mut design = design.clone();
        let p = &mut design.patches[0];
        match variable {
            0 => p.x_mm += by,
            1 => p.y_mm += by,
            2 => p.h_mm += by,
            3 => p.w_mm += by,
            4 => p.theta_deg += by,
            _ => design.balloon.length_mm += by,
        }
        design
    }

    /// The linearised centreline of one change.
    fn linearised(
        base: &Design,
        simulation: &Simulation,
        options: &SimulateOptions,
        change: &Design,
    ) -> Curve {
        let mut one = linearised_centrelines(
            base,
            simulation,
            options,
            std::slice::from_ref(change),
            1,
            &PatternCache::default(),
        )
        .expect("a stable state");
        one.pop().flatten().expect("a linearised centreline")
    }

    /// A patch moved along the tube changes the out-of-balance force only
    /// on the nodes of the elements its outline crosses: the mesh stretched
    /// to the same length is the same node for node, so every other element
    /// is shared with the base model and left out.
    #[test]
    fn moving_a_patch_changes_the_force_only_near_its_outline() {
        let (design, options, simulation) = scene();
        let change = changed(&design, 1, 0.02);
        let base = Model::new(&design, simulation.mesh.clone(), options.cut_elements);
        let stretched = simulation.mesh.stretched_to(change.balloon.length_mm);
        assert_eq!(stretched.nodes, simulation.mesh.nodes);
        let moved = Model::new(&change, stretched, options.cut_elements);
        let load = moved.gradient_change(&base, &simulation.positions).unwrap();
        let touched = load.iter().filter(|f| **f != 0.0).count();
        assert!(
            touched > 0 && touched < load.len() / 5,
            "{touched} of {}",
            load.len()
        );
    }

    /// The unchanged design's linearised centreline is its own.
    #[test]
    fn an_unchanged_design_keeps_its_centreline() {
        let (design, options, simulation) = scene();
        let centreline = linearised(&design, &simulation, &options, &design);
        assert!(centreline.largest_gap(&simulation.centreline) < 1e-9);
    }

    /// Against solves of the changed designs (warm-started, tolerance 1e-9):
    /// for small changes of every variable the linearised centreline's
    /// displacement matches the solved one within 2 % (largest point gap
    /// over largest displacement; measured 0.4–1 %), and within 6 % in Y
    /// (5 %: moving along the mesh, the patch's outline crosses mesh lines,
    /// where the response has kinks). Since the linearisation is exact to
    /// first order, its error grows as the square of the change: doubling
    /// the change of H or Θ (where the model is smooth) doubles the gap
    /// relative to the displacement (measured 2.04 and 2.0).
    #[test]
    fn linearised_centrelines_match_solves_to_first_order() {
        let (design, options, simulation) = scene();
        let steps = [0.02, 0.02, 0.02, 0.005, 0.05, 0.02];
        let mut errors = Vec::new();
        for (variable, step) in steps.iter().enumerate() {
            let mut gaps = Vec::new();
            for scale in [1.0, 2.0] {
                let change = changed(&design, variable, scale * step);
                let linear = linearised(&design, &simulation, &options, &change);
                let solved = simulate_from(&change, &options, Some(&simulation)).unwrap();
                let moved = solved.centreline.largest_gap(&simulation.centreline);
                assert!(moved > 1e-3, "variable {variable} moved {moved} mm");
                gaps.push(linear.largest_gap(&solved.centreline) / moved);
            }
            errors.push(gaps);
        }
        println!("relative gap at the step and twice it, X Y H W Θ L: {errors:.4?}");
        assert!(errors[1][0] < 0.06, "{errors:?}");
        for smooth in [0, 2, 3, 4, 5] {
            assert!(errors[smooth][0] < 0.02, "{errors:?}");
        }
        for smooth in [2, 4] {
            // The relative gap is gap / displacement, so it doubles.
            let growth = errors[smooth][1] / errors[smooth][0];
            assert!((1.5..2.5).contains(&growth), "{errors:?}");
        }
    }

    /// Lengthening the balloon by 0.04 mm from 80.90 mm keeps the uniform
    /// 2 mm mesh's 40 segments; from 80.98 mm the fresh mesh of the longer
    /// balloon has 41, and a solve's response jumps by the change of
    /// discretisation (measured: 0.88 mm against 0.11 mm). The linearised
    /// response, on the stretched mesh, is the same from both lengths
    /// (within 3 %) and matches the solve where no ring is added (within
    /// 5 % of the displacement).
    #[test]
    fn a_longer_balloon_is_linearised_on_the_stretched_mesh() {
        let (design, options, _) = scene();
        let mut displacements = Vec::new();
        for length in [80.90, 80.98] {
            let mut base = design.clone();
            base.balloon.length_mm = length;
            let simulation = simulate(&base, &options).unwrap();
            let longer = changed(&base, 5, 0.04);
            let fresh = crate::fe::mesh::TubeMesh::for_design(&longer, options.mesh);
            let added = fresh.ring_y.len() - simulation.mesh.ring_y.len();
            let linear = linearised(&base, &simulation, &options, &longer);
            let solved = simulate_from(&longer, &options, Some(&simulation)).unwrap();
            displacements.push((
                added,
                linear.largest_gap(&simulation.centreline),
                solved.centreline.largest_gap(&simulation.centreline),
                linear.largest_gap(&solved.centreline),
            ));
        }
        println!(
            "(rings added, linearised, solved displacement, their gap) mm: {displacements:.4?}"
        );
        let [(none, lin_a, _, off_a), (one, lin_b, solved_b, _)] = displacements[..] else {
            unreachable!()
        };
        assert_eq!((none, one), (0, 1));
        assert!(off_a < 0.1 * lin_a, "{displacements:?}");
        assert!((lin_b - lin_a).abs() < 0.05 * lin_a, "{displacements:?}");
        assert!(solved_b > 2.0 * lin_b, "{displacements:?}");
    }
}
