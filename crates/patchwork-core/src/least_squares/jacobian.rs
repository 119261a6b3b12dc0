//! Jacobians of residuals in the unit cube: forward differences, and the
//! secant approximation carried along a solver's steps by Broyden's update.

use nalgebra::{DMatrix, DVector};

use super::{Iterate, Residuals};
use crate::parallel::map_in_threads;

/// A Jacobian of the residuals: forward differences (or the problem's cheap
/// equivalent) at the current point (`fresh`), or a secant approximation
/// carried along the steps by Broyden's update; `cheap` if it started as
/// the problem's cheap one (a fresh one costs one evaluation).
pub struct Jacobian {
    pub matrix: DMatrix<f64>,
    pub fresh: bool,
    pub cheap: bool,
}

impl Jacobian {
    /// Broyden's rank-one update from a step `from` → `to` (accepted or not);
    /// see [`broyden_update`].
    pub fn update<S>(&mut self, from: &Iterate<S>, to: &Iterate<S>) {
        let step =
            DVector::from_iterator(from.u.len(), to.u.iter().zip(&from.u).map(|(b, a)| b - a));
        broyden_update(&mut self.matrix, &step, &(&to.residuals - &from.residuals));
    }
}

/// Broyden's rank-one update: J ← J + (Δr − J δ) δᵀ / (δᵀδ), the least
/// change of J (in the Frobenius norm) that makes it reproduce the observed
/// change `change` = Δr of the residuals along `step` = δ (the secant
/// condition J δ = Δr); J v is kept for every v orthogonal to δ (Madsen,
/// Nielsen & Tingleff, "Methods for non-linear least squares problems",
/// 2004, §3.4). A zero or non-finite step leaves J as it is.
pub fn broyden_update(jacobian: &mut DMatrix<f64>, step: &DVector<f64>, change: &DVector<f64>) {
    let length_squared = step.norm_squared();
    if length_squared == 0.0 || !length_squared.is_finite() {
        return;
    }
    let misfit = change - &*jacobian * step;
    *jacobian += misfit * step.transpose() / length_squared;
}

/// The unit-cube point of column `j`'s forward difference from `u` and its
/// step: +`step`, or −`step` where that would leave the cube.
pub fn stepped(u: &[f64], j: usize, step: f64) -> (Vec<f64>, f64) {
    let mut u = u.to_vec();
    let h = if u[j] + step <= 1.0 { step } else { -step };
    u[j] += h;
    (u, h)
}

/// Forward-difference Jacobian at `at`, Jⱼ = (r(u + h eⱼ) − r(u)) / h, the
/// columns evaluated on up to `threads` threads, each from `at`'s state. A
/// column whose evaluation failed is left zero (that variable stays put
/// until the next Jacobian).
pub fn forward_differences<P: Residuals>(
    problem: &P,
    at: &Iterate<P::State>,
    step: f64,
    threads: usize,
) -> DMatrix<f64> {
    let columns: Vec<usize> = (0..at.u.len()).collect();
    let differences = map_in_threads(&columns, threads, &|&j| {
        let (u, h) = stepped(&at.u, j, step);
        at.evaluate(problem, u)
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

#[cfg(test)]
mod tests {
    use super::*;

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
    fn a_difference_at_the_upper_bound_steps_backwards() {
        assert_eq!(stepped(&[0.2, 0.5], 1, 1e-3), (vec![0.2, 0.5 + 1e-3], 1e-3));
        assert_eq!(
            stepped(&[0.2, 1.0], 1, 1e-3),
            (vec![0.2, 1.0 - 1e-3], -1e-3)
        );
    }
}
