//! The damped step within the unit cube, and what the linear model expects
//! of it.
//!
//! Marquardt's step solves (JᵀJ + λ D) δ = −Jᵀr with D = diag(JᵀJ), floored
//! at `floor` so that a variable the residuals do not see stays put. In a
//! box the plain step is not enough: where a variable sits at a bound and
//! the step would push it further, clamping it there leaves the other
//! components as they were solved for — as if that variable had moved — and
//! the clamped step is often no descent at all (a design whose patches are
//! pinned at a fabrication limit spent every other refine solve on such
//! steps). So the step is solved on an active set: a variable at a bound
//! that the gradient's descent pushes outward is held there and the step
//! solved over the others (the normal equations without its row and
//! column); a variable that would only pass a bound on its way is clamped
//! at it.

use nalgebra::{DMatrix, DVector};

use super::super::Iterate;

/// A trial point and the linear model's |r + J δ| there.
pub(super) struct Step {
    pub u: Vec<f64>,
    pub predicted: f64,
}

/// The damped Gauss–Newton step from `at` with Jacobian `jacobian`, floored
/// Marquardt scaling ([`damped_step_from_normal`]), with the error the
/// linear model predicts at the point it reaches.
pub(super) fn damped_step<S>(
    jacobian: &DMatrix<f64>,
    at: &Iterate<S>,
    damping: f64,
) -> Option<Step> {
    let normal = jacobian.transpose() * jacobian;
    let gradient = jacobian.transpose() * &at.residuals;
    let floor = 1e-9 * normal.trace().max(f64::MIN_POSITIVE) / at.u.len() as f64;
    let u = damped_step_from_normal(&normal, &gradient, damping, floor, &at.u)?;
    let delta = DVector::from_iterator(u.len(), u.iter().zip(&at.u).map(|(a, b)| a - b));
    let predicted = (&at.residuals + jacobian * delta).norm();
    Some(Step { u, predicted })
}

/// u + δ with (JᵀJ + λ D) δ = −Jᵀr over the variables not held at a bound
/// (D = diag(JᵀJ) floored at `floor`), clamped into the unit cube; none if
/// the system cannot be solved or the step does not move. A variable is
/// held where it sits at a bound and the gradient's descent −Jᵀr points out
/// of the cube (Bertsekas's projected Newton step, its active set the bounds
/// reached exactly, as clamped steps reach them).
pub(super) fn damped_step_from_normal(
    normal: &DMatrix<f64>,
    gradient: &DVector<f64>,
    damping: f64,
    floor: f64,
    u: &[f64],
) -> Option<Vec<f64>> {
    let outward =
        |i: usize| (u[i] <= 0.0 && gradient[i] > 0.0) || (u[i] >= 1.0 && gradient[i] < 0.0);
    let free: Vec<usize> = (0..u.len()).filter(|&i| !outward(i)).collect();
    if free.is_empty() {
        return None;
    }
    let mut system = normal.select_rows(&free).select_columns(&free);
    for (a, &i) in free.iter().enumerate() {
        system[(a, a)] += damping * normal[(i, i)].max(floor);
    }
    let reduced = system.cholesky()?.solve(&-gradient.select_rows(&free));
    let mut next = u.to_vec();
    for (a, &i) in free.iter().enumerate() {
        next[i] = (u[i] + reduced[a]).clamp(0.0, 1.0);
    }
    let moved = next.iter().zip(u).any(|(a, b)| a != b);
    (moved && next.iter().all(|x| x.is_finite())).then_some(next)
}
