//! How sure a design is: the spread of its inflated centreline under the
//! fabrication and operating tolerances a lab works to — each patch's
//! placement (X, Y), angle (Θ) and size (H, W), the pressure, the wall's
//! thickness and the material's modulus.
//!
//! The linear estimate ([`linear_spread`], [`spread_of`] from a known
//! nominal state), source by source: each source at its tolerance,
//! linearised at the nominal state, and the sources that matter (at least
//! [`SOLVED_FRACTION`] of the largest) solved at +tolerance and −tolerance,
//! warm-started from it, and read to second order; the centreline's change
//! from the nominal (after the best rigid alignment, as the shape error is
//! measured) and the tip's move in the clamp's frame. Tolerances are read
//! as one standard deviation of independent errors, so the spreads add in
//! quadrature and the sources' mean moves as vectors; the worst case adds
//! them in magnitude (an upper bound of every source at its tolerance the
//! worst way).
//!
//! The Monte-Carlo check ([`monte_carlo`]) draws every source at once,
//! solves the samples in full and says whether the linear estimate holds.

mod answer;
mod balloon;
mod change;
mod linear;
mod models;
mod monte_carlo;
mod rounds;
mod sources;
mod tolerances;

pub use answer::{Contributor, Estimate, MonteCarlo, Spread};
pub use change::{Change, Nominal, Offsets, SOURCE_TOLERANCE, offsets_of};
pub use linear::{Against, Check, SpreadError, linear_spread, spread_of};
pub use models::Models;
pub use monte_carlo::{AGREEMENT, monte_carlo};
pub use rounds::SOLVED_FRACTION;
pub use sources::{PatchQuantity, SOURCES_PER_PATCH, Source};
pub use tolerances::Tolerances;

#[cfg(test)]
mod tests;
