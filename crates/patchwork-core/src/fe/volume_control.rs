//! Volume control: the pressure becomes a Lagrange multiplier enforcing
//! V(x) = V*. Latex tubes have a pressure maximum (where a bulge forms); a
//! pressure-controlled solve cannot pass it, a volume-controlled one can.
//!
//! Stationarity of L(u, P) = Π_strain(u) − P (V(u) − V*) gives the bordered
//! Newton system
//!
//!   [ K(P)   −∇V ] [Δu]     [ ∇Π_strain − P∇V ]
//!   [ −∇Vᵀ    0  ] [ΔP] = − [ −(V − V*)       ]
//!
//! with K(P) = K_strain − P ∂²V. Past the limit point K(P) is indefinite (that is
//! the instability pressure control meets), so it is factored by sparse LU, and
//! the border is eliminated: K a = −r, K b = ∇V, ΔP = (−(V − V*) − ∇V·a)/(∇V·b),
//! Δu = a + ΔP b. Steps are damped until the residual norm decreases.

use std::time::Instant;

use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Lu, SymbolicLu};
use faer::sparse::{Argsort, Pair, SparseColMat, SymbolicSparseColMat};

use super::model::Model;
use super::newton::{NewtonOptions, SolveError, norm};
use super::section::Section;
use crate::curve::Point;

/// Sparse structures for volume-controlled solves of one model (full pattern,
/// symbolic LU done once).
pub struct VolumeSolver {
    symbolic: SymbolicSparseColMat<usize>,
    argsort: Argsort<usize>,
    lu: SymbolicLu<usize>,
    /// For each full-pattern entry, the lower-pattern value it copies.
    source: Vec<usize>,
    n: usize,
}

impl VolumeSolver {
    pub fn new(model: &Model) -> Result<VolumeSolver, SolveError> {
        let n = model.dof_count;
        let lower = model.pattern();
        let mut pairs = Vec::with_capacity(2 * lower.len());
        let mut source = Vec::with_capacity(2 * lower.len());
        for (k, p) in lower.iter().enumerate() {
            pairs.push(*p);
            source.push(k);
            if p.row != p.col {
                pairs.push(Pair::new(p.col, p.row));
                source.push(k);
            }
        }
        let setup = |e: String| SolveError::Setup(e);
        let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs)
            .map_err(|e| setup(format!("{e:?}")))?;
        let lu = SymbolicLu::try_new(symbolic.as_ref()).map_err(|e| setup(format!("{e:?}")))?;
        Ok(VolumeSolver {
            symbolic,
            argsort,
            lu,
            source,
            n,
        })
    }

    /// Solves for equilibrium at enclosed volume `target` (mm³), updating the
    /// positions `x` and the pressure `pressure` (MPa, the multiplier).
    pub fn solve(
        &self,
        model: &Model,
        sections: &[Section],
        x: &mut Vec<Point>,
        pressure: &mut f64,
        target: f64,
        options: &NewtonOptions,
    ) -> Result<usize, SolveError> {
        let started = Instant::now();
        // The solve's own sections, as in Newton's solve (Section::remembering).
        let sections: &[Section] = &sections
            .iter()
            .map(Section::remembering)
            .collect::<Vec<_>>();
        let mut u = model.unknowns(x);
        let mut gradient = vec![0.0; self.n];
        let mut values = Vec::new();
        let residual_of = |u: &[f64],
                           p: f64,
                           gradient: &mut [f64],
                           values: &mut Vec<f64>|
         -> Option<(f64, f64)> {
            let positions = model.positions(u);
            model.assemble_at(&positions, sections, p, 0.0, gradient, values)?;
            let scale = p.abs().max(1e-6) * norm(&model.volume_gradient(&positions));
            let dv = (model.volume(&positions) - target) / target;
            Some((norm(gradient) / scale, dv))
        };
        let merit = |(r, dv): (f64, f64)| (r * r + dv * dv).sqrt();
        let mut current = residual_of(&u, *pressure, &mut gradient, &mut values)
            .ok_or(SolveError::InadmissibleStart)?;
        for iteration in 0..options.max_iterations {
            if current.0 <= options.tolerance && current.1.abs() <= options.tolerance {
                *x = model.positions(&u);
                return Ok(iteration);
            }
            if started.elapsed() > options.time_limit {
                return Err(SolveError::TimeLimit {
                    limit_s: options.time_limit.as_secs_f64(),
                    residual: merit(current),
                });
            }
            let positions = model.positions(&u);
            let (step, dp) = self.bordered_step(
                model,
                &positions,
                (&gradient, &values),
                target,
                merit(current),
            )?;
            let mut t = 1.0;
            loop {
                let trial: Vec<f64> = u.iter().zip(&step).map(|(a, s)| a + t * s).collect();
                let p_trial = *pressure + t * dp;
                if let Some(r) = residual_of(&trial, p_trial, &mut gradient, &mut values)
                    && merit(r) < merit(current)
                {
                    u = trial;
                    *pressure = p_trial;
                    current = r;
                    break;
                }
                t *= 0.5;
                if t < 1e-8 {
                    return Err(SolveError::LineSearch {
                        iterations: iteration,
                        residual: merit(current),
                    });
                }
            }
        }
        Err(SolveError::NotConverged {
            iterations: options.max_iterations,
            residual: merit(current),
        })
    }
    /// The Newton step (Δu, ΔP) of the bordered system at `positions`, from
    /// the residual `gradient` and the tangent's lower-pattern `values`: K is
    /// factored by sparse LU and the border eliminated (see the module doc).
    /// A factorisation error (reporting `residual`) when K is singular or
    /// the border's pivot ∇V·b vanishes.
    fn bordered_step(
        &self,
        model: &Model,
        positions: &[Point],
        (gradient, values): (&[f64], &[f64]),
        target: f64,
        residual: f64,
    ) -> Result<(Vec<f64>, f64), SolveError> {
        let singular = || SolveError::Factorisation {
            shift: 0.0,
            residual,
        };
        let full: Vec<f64> = self.source.iter().map(|&k| values[k]).collect();
        let matrix = SparseColMat::new_from_argsort(self.symbolic.clone(), &self.argsort, &full)
            .map_err(|e| SolveError::Setup(format!("{e:?}")))?;
        let lu =
            Lu::try_new_with_symbolic(self.lu.clone(), matrix.as_ref()).map_err(|_| singular())?;
        let dv = model.volume_gradient(positions);
        // ∂∇Π/∂P = −c ∂V/∂u, with c the facets' load factor.
        let c = model.load_factor;
        let mut rhs = faer::Mat::<f64>::from_fn(self.n, 2, |i, j| match j {
            0 => -gradient[i],
            _ => c * dv[i],
        });
        lu.solve_in_place(rhs.as_mut());
        let volume_error = model.volume(positions) - target;
        let dv_a: f64 = (0..self.n).map(|i| dv[i] * rhs[(i, 0)]).sum();
        let dv_b: f64 = (0..self.n).map(|i| dv[i] * rhs[(i, 1)]).sum();
        let dp = (-volume_error - dv_a) / dv_b;
        if !dp.is_finite() {
            return Err(singular());
        }
        let step: Vec<f64> = (0..self.n)
            .map(|i| rhs[(i, 0)] + dp * rhs[(i, 1)])
            .collect();
        Ok((step, dp))
    }
}
