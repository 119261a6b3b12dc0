//! What design runs can share, owned by whoever runs them: the evaluations
//! of cold solves and the tangent patterns of the meshes solved. A run given
//! fresh caches gets the same result as one given warm ones, only slower.

use super::evaluation_cache::EvaluationCache;
use crate::design::Design;
use crate::fe::newton::PatternCache;
use crate::fe::{SimulateError, SimulateOptions, Simulation, simulate_with};

#[derive(Default)]
pub struct Caches {
    pub evaluations: EvaluationCache,
    pub patterns: PatternCache,
}

impl Caches {
    /// `design` on `model` from the cold start, from the evaluation cache
    /// when it holds it.
    pub fn simulate(
        &self,
        design: &Design,
        model: &SimulateOptions,
    ) -> Result<Simulation, SimulateError> {
        self.evaluations.simulate(design, model, &self.patterns)
    }

    /// `design` on `model`, warm-started from `warm` (the cold start, cached,
    /// when none).
    pub fn simulate_from(
        &self,
        design: &Design,
        model: &SimulateOptions,
        warm: Option<&Simulation>,
    ) -> Result<Simulation, SimulateError> {
        match warm {
            Some(_) => simulate_with(design, model, warm, &self.patterns),
            None => self.simulate(design, model),
        }
    }
}
