//! The solver of one mesh: its tangent pattern, Newton's method on the
//! model's potential, and the linear responses of a converged state.

use std::sync::Arc;

use super::super::model::Model;
use super::super::section::Section;
use super::super::tangent_factor::TangentPattern;
use super::minimise::minimise;
use super::options::NewtonOptions;
use super::outcome::{SolveError, SolveStats};
use super::patterns::PatternCache;
use super::potential::{ModelPotential, norm};
use crate::curve::Point;

/// Reusable sparse structures of one model (ordering, pattern, symbolic
/// Cholesky), from a [`PatternCache`].
pub struct Solver {
    pattern: Arc<TangentPattern>,
}

impl Solver {
    pub fn new(model: &Model, patterns: &PatternCache) -> Result<Solver, SolveError> {
        let pattern = patterns
            .get_or_build(model.dof_count, model.pattern())
            .map_err(SolveError::Setup)?;
        Ok(Solver { pattern })
    }

    /// Solves K Δuⱼ = −fⱼ for every load fⱼ (over the free DOFs), with K the
    /// tangent of `model` at `x` factorised once, without shift: the state's
    /// first-order response to out-of-balance forces
    /// ([`super::sensitivity`]). `None` when K is not positive definite (an
    /// unstable state has no unique response) or `x` is outside a
    /// material's domain.
    pub fn linear_responses(
        &self,
        model: &Model,
        x: &[Point],
        loads: Vec<Vec<f64>>,
    ) -> Option<Vec<Vec<f64>>> {
        let mut gradient = vec![0.0; model.dof_count];
        let mut values = Vec::new();
        model.assemble(x, &model.sections, 0.0, &mut gradient, &mut values)?;
        let mut factor = self.pattern.factor();
        if !factor.factorise(&values) {
            return None;
        }
        Some(
            loads
                .into_iter()
                .map(|mut load| {
                    load.iter_mut().for_each(|f| *f = -*f);
                    factor.solve_in_place(&mut load);
                    load
                })
                .collect(),
        )
    }

    /// Minimises Π from `x` (updated in place on success).
    pub fn solve(
        &self,
        model: &Model,
        sections: &[Section],
        x: &mut Vec<Point>,
        options: &NewtonOptions,
    ) -> Result<SolveStats, SolveError> {
        let scale = load_scale(model, x).max(1e-12);
        // The solve's own sections: their laminates start each element's
        // inner minimisation where its previous one ended.
        let sections: &[Section] = &sections
            .iter()
            .map(Section::remembering)
            .collect::<Vec<_>>();
        let potential = ModelPotential {
            model,
            sections,
            steps: options.steps,
        };
        let mut factor = self.pattern.factor();
        let (u, stats) = minimise(&potential, &mut factor, model.unknowns(x), scale, options)?;
        *x = model.positions(&u);
        Ok(stats)
    }
}

/// |P ∂V/∂u|, the size of the pressure load; the wall's stiffness scale when P = 0.
fn load_scale(model: &Model, x: &[Point]) -> f64 {
    let n = model.load().abs() * norm(&model.volume_gradient(x));
    if n > 0.0 {
        n
    } else {
        model.materials[0].shear_modulus() * model.mesh.radius
    }
}
