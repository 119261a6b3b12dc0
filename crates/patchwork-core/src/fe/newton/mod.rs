//! Newton's method on the total potential.
//!
//! Each iteration (`minimise.rs`): assemble Π, ∇Π and the Hessian K
//! ([`Potential`]); factor K by sparse Cholesky (faer, AMD ordering, symbolic
//! analysis once per mesh topology, kept in a [`PatternCache`]); step
//! Δ = −K⁻¹∇Π. The full step's end is assembled at once (Π, ∇Π and K: the
//! next iteration's linearisation) and kept if its Π decreases enough
//! (Armijo); otherwise backtrack from half the step on Π alone
//! (`line_search.rs`).
//! Where K is not positive definite — compressed, wrinkling regions, or far
//! from equilibrium — Cholesky fails, which doubles as an inertia test: the
//! step is taken with K + αI (`shift.rs`: α grown until the factorisation
//! succeeds, then decayed), which is still a descent direction. Converged
//! states are tested once more with α = 0: success means a *stable*
//! equilibrium.
//!
//! A step is kept only if the tangent at its end factorises with at most ten
//! times the step's own shift (the definiteness guard, `guard.rs`); otherwise
//! it is halved. Without the guard, a full step from a carried or kinematic
//! start on a 0.5 mm mesh lands where the wall at a patch end wrinkles, and
//! Newton creeps under a huge shift for a dozen iterations. Past its
//! iteration cap a solve goes on only while it still converges
//! (`stopping.rs`); `timing.rs` books where the time went.

mod guard;
mod line_search;
mod minimise;
mod options;
mod outcome;
mod patterns;
mod potential;
mod shift;
mod solver;
mod stopping;
mod timing;

pub use options::{COLD_SHIFT_FLOOR, NewtonOptions, Steps};
pub use outcome::{SolveError, SolveStats};
pub use patterns::PatternCache;
pub use potential::{Linearisation, ModelPotential, Potential, norm};
pub use solver::Solver;

#[cfg(test)]
mod tests;
