//! What Newton minimises: a potential of the unknowns with its gradient and
//! the lower triangle of its Hessian as triplets, on a fixed sparsity
//! pattern whose last `n` slots are the diagonal (where a shift goes).

use super::super::model::Model;
use super::super::ring_step::stepped;
use super::super::section::Section;
use super::options::Steps;

/// A smooth potential Π(u) over n unknowns.
pub trait Potential {
    /// The number of unknowns n.
    fn dimension(&self) -> usize;

    /// Π, ∇Π and the Hessian's triplets at `u` (the shift slots, the last n,
    /// zero); `None` outside the potential's domain.
    fn linearise(&self, u: &[f64]) -> Option<Linearisation>;

    /// Π at `u` alone (non-finite outside the domain): what the line search
    /// tries.
    fn energy(&self, u: &[f64]) -> f64;

    /// Where the fraction `t` of `step` from `u` ends: u + t·step unless
    /// the potential knows a better path with the same first order.
    fn advanced(&self, u: &[f64], step: &[f64], t: f64) -> Vec<f64> {
        linear_advance(u, step, t)
    }
}

/// u + t·step.
fn linear_advance(u: &[f64], step: &[f64], t: f64) -> Vec<f64> {
    u.iter().zip(step).map(|(a, s)| a + t * s).collect()
}

/// Π, ∇Π and the triplets of K (shift slots last) at one state.
pub struct Linearisation {
    pub potential: f64,
    pub gradient: Vec<f64>,
    pub values: Vec<f64>,
    /// Mean magnitude of K's entries, unshifted: the scale of shifts.
    pub stiffness: f64,
}

impl Linearisation {
    /// A linearisation from its parts, the stiffness scale taken from the
    /// triplets (whose shift slots must hold zero).
    pub fn new(potential: f64, gradient: Vec<f64>, values: Vec<f64>) -> Linearisation {
        let stiffness = stiffness_scale(&values);
        Linearisation {
            potential,
            gradient,
            values,
            stiffness,
        }
    }

    /// K's triplets with the shift slots zeroed.
    pub fn unshifted(&mut self) -> Vec<f64> {
        let start = self.values.len() - self.gradient.len();
        self.values[start..].fill(0.0);
        self.values.to_vec()
    }
}

/// Mean magnitude of the stored tangent entries: the scale shifts are set
/// against (shift slots hold zero when this is taken).
fn stiffness_scale(values: &[f64]) -> f64 {
    let sum: f64 = values.iter().map(|v| v.abs()).sum();
    (sum / values.len().max(1) as f64).max(1e-12)
}

/// The membrane model's total potential with fixed cross-sections: strain
/// energy minus the pressure's work.
pub struct ModelPotential<'a> {
    pub model: &'a Model,
    pub sections: &'a [Section],
    pub steps: Steps,
}

impl Potential for ModelPotential<'_> {
    fn dimension(&self) -> usize {
        self.model.dof_count
    }

    fn linearise(&self, u: &[f64]) -> Option<Linearisation> {
        let mut gradient = vec![0.0; self.model.dof_count];
        let mut values = Vec::new();
        let x = self.model.positions(u);
        let potential = self
            .model
            .assemble(&x, self.sections, 0.0, &mut gradient, &mut values)?;
        Some(Linearisation::new(potential, gradient, values))
    }

    fn energy(&self, u: &[f64]) -> f64 {
        self.model
            .potential(&self.model.positions(u), self.sections)
    }

    /// With [`Steps::Rings`], the step ring by ring, its rotations applied
    /// exactly ([`ring_step`](super::super::ring_step)).
    fn advanced(&self, u: &[f64], step: &[f64], t: f64) -> Vec<f64> {
        if self.steps == Steps::Linear {
            return linear_advance(u, step, t);
        }
        let (x, dx) = (self.model.positions(u), self.model.moves(step));
        let moved = stepped(&self.model.mesh, &x, &dx, t);
        self.model.unknowns(&moved)
    }
}

/// The Euclidean norm of `v`.
pub fn norm(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}
