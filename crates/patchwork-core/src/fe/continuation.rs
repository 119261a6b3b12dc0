//! The last route of a cold solve: continuation in patch stiffness from
//! the straight, uniformly inflated tube, where Newton from the coarse
//! model's state and from the kinematic estimate both failed.

use super::mesh::TubeMesh;
use super::model::Model;
use super::newton::{NewtonOptions, SolveError, SolveStats, Solver};
use super::tube_theory::TubeState;
use crate::curve::Point;
use crate::design::Design;

/// Continuation in patch stiffness from the straight tube `x` to the
/// design: steps doubled after easy solves, halved after failed ones down to
/// `min_step`. Returns the steps taken (`stats` gathers them), or the patch
/// stiffness (share of the design's) it failed at and why.
pub(super) fn continuation(
    design: &Design,
    min_step: f64,
    model: &Model,
    solver: &Solver,
    x: &mut Vec<Point>,
    left: &impl Fn() -> NewtonOptions,
    stats: &mut SolveStats,
) -> Result<usize, (f64, SolveError)> {
    let (mut done, mut step, mut steps) = (0.0_f64, 1.0_f64, 0);
    while done < 1.0 {
        let target = (done + step).min(1.0);
        let sections = model.sections_at(design, target);
        let mut trial = x.clone();
        match solver.solve(model, &sections, &mut trial, &left()) {
            Ok(s) => {
                steps += 1;
                stats.accumulate(&s);
                *x = trial;
                done = target;
                if s.iterations < 8 {
                    step *= 2.0;
                }
            }
            Err(reason) => {
                step /= 2.0;
                // Retrying a smaller step cannot help once time is up or the
                // start itself is outside the materials' domain.
                let hopeless = matches!(
                    reason,
                    SolveError::TimeLimit { .. } | SolveError::InadmissibleStart
                );
                if step < min_step || hopeless {
                    return Err((target, reason));
                }
            }
        }
    }
    Ok(steps)
}

/// The bare tube's uniform state mapped onto the mesh, shaped so every element
/// starts inside its material's domain:
/// - tube nodes at radius r(Y)·λ-blend and height λ₂Y, where the hoop stretch
///   rises from 1 at the clamped base as 1 + (λ₁ − 1)(1 − e^(−Y/R₀)) — an abrupt
///   step there would stretch the first elements past a Gent locking limit;
/// - cap nodes at polar angle φ (0 at the rim) with hoop stretch falling from λ₁
///   at the rim to 1 at the pole, above the stretched tube — a cap inflated
///   equibiaxially by λ₁ would be far stiffer than the real one.
pub(super) fn initial_state(mesh: &TubeMesh, state: TubeState) -> Vec<Point> {
    let tube_nodes = mesh.ring_y.len() * mesh.around;
    let r0 = mesh.radius;
    let top = mesh.length * state.axial;
    mesh.nodes
        .iter()
        .enumerate()
        .map(|(i, p)| {
            if mesh.fixed[i] {
                *p
            } else if i < tube_nodes {
                let hoop = 1.0 + (state.hoop - 1.0) * (1.0 - (-p.z / r0).exp());
                Point::new(p.x * hoop, p.y * hoop, p.z * state.axial)
            } else {
                let height = p.z - mesh.length;
                let rim_fraction = (1.0 - (height / r0).clamp(0.0, 1.0).powi(2)).sqrt();
                let hoop = 1.0 + (state.hoop - 1.0) * rim_fraction;
                Point::new(p.x * hoop, p.y * hoop, top + height * state.hoop.sqrt())
            }
        })
        .collect()
}
